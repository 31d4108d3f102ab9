//! `airring runup`: a run-up of the paper's rotor (or a design's) in two air ring bearings.

use super::{check_checkpoint_every, default_out, finish, fmu_dir, new_run, stop_flag, Common};
use master::error::{Classify, Error};
use master::run::RunOptions;
use std::process::ExitCode;

#[derive(clap::Args)]
pub struct Args {
    #[command(flatten)]
    pub args: Box<master::runup::flags::RunupArgs>,
    #[command(flatten)]
    pub common: Common,
}

pub fn execute(a: Args) -> Result<ExitCode, Error> {
    let Args { args, common } = a;
    // The flags and the design file they name: a design file names itself in its messages.
    let mut s = master::runup::flags::settings(&args).flag()?;
    s.validate_runup().flag()?;
    // Every flag and the output folder checked before the calm plan's analysis runs.
    check_checkpoint_every(common.checkpoint_every)?;
    let out = common.out.clone().unwrap_or_else(|| default_out(&s.preset));
    master::run::folder::check_new_run(&out, common.overwrite)?;
    // The FMUs are found before the calm plan's analysis runs (a wrong --fmu-dir was
    // reported only after it).
    let dir = fmu_dir(args.fmu_dir.clone())?;
    if let Some(shaft) = &s.shaft {
        let fmu = master::runup::shaft_fmu::rotor_fmu_with_shaft(&dir, shaft).fmus()?;
        eprintln!(
            "flexible rotor: {} shaft elements, bearings C and T at nodes {} and {}; rotor FMU {}",
            shaft.model.elements.len(),
            shaft.bearing_nodes[0],
            shaft.bearing_nodes[1],
            fmu.display()
        );
        if let Some(r) = s.shaft_reduction().flag()? {
            eprintln!(
                "reduced from {} to {} coordinates: {} fixed-interface modes below {:.0} Hz \
                 ({} left out); natural frequencies up to {:.0} Hz within {:.3} % of the full model",
                r.full_dof,
                r.reduced_dof,
                r.kept_modes_hz.len(),
                r.cutoff_hz,
                r.dropped_modes,
                r.compared_up_to_hz,
                100.0 * r.frequency_error
            );
        }
        s.rotor_fmu = Some(fmu);
        // The calm plan's linear analysis is the rigid rotor's: no longer steps for a shaft.
        if s.calm_macro_step_us.is_some() {
            eprintln!(
                "long calm steps: off (the calm plan analyses the rigid rotor; a flexible one \
                 runs every macro step at {} us)",
                s.macro_step_us
            );
            s.calm_macro_step_us = None;
        }
    }
    if let (Some(calm_us), Some(_)) = (s.calm_macro_step_us, s.calm_factor()) {
        // A cache that cannot be opened only makes the plan slower.
        let cache = args.linear_cache.as_deref().and_then(|d| {
            master::linear_cache::LinearCache::open(d)
                .map_err(|e| eprintln!("warning: --linear-cache not used: {e}"))
                .ok()
        });
        let plan = master::calm_steps::plan(&s, cache.as_ref());
        s.calm_windows_s = plan.windows_s.clone();
        eprintln!("{}", master::calm_steps::describe(&plan, calm_us));
    }
    // TOML is UTF-8: a folder whose name is not cannot be written into a system file.
    let dir_text = dir.to_str().ok_or_else(|| {
        Error::Fmus(format!(
            "--fmu-dir {}: the folder's path is not valid UTF-8, which a system file cannot \
             hold; link or copy the FMUs to a folder with a UTF-8 name",
            dir.display()
        ))
    })?;
    // The system file goes into the run folder only once the run has started.
    let staged = master::run::folder::StagedSystem::new(&s.system_toml(dir_text)).output()?;
    eprintln!(
        "run-up '{}': {}, {}; {}; macro step {} us -> {}",
        s.preset,
        master::runup::describe_bearings(&s).flag()?,
        s.describe_speed(),
        master::runup::describe_film_mesh(&s).flag()?,
        s.macro_step_us,
        out.display()
    );
    let opts = RunOptions {
        out_dir: out.clone(),
        checkpoint_every_s: common.checkpoint_every,
        stop: stop_flag(),
        halt_at_s: None,
        quiet: common.quiet,
        extra: serde_json::to_value(&s).unwrap_or_default(),
        bores: None,
        parquet: common.parquet,
        halt: s.halt(),
        // A flexible rotor to scale (report.html shows it).
        figures: s
            .shaft
            .iter()
            .map(|sh| {
                let chart = master::flexible::drawing_with_bearings(&sh.model, sh.bearing_nodes);
                ("rotor".to_string(), chart)
            })
            .collect(),
    };
    let report = new_run(&staged.path, &opts).map_err(|e| Error::Run(staged.strip_path(e)))?;
    Ok(finish(report, &out))
}
