//! `airring run`: any system described by a TOML system file.

use super::{check_checkpoint_every, default_out, finish, lobes, new_run, stop_flag, Common};
use master::error::{Classify, Error};
use master::run::RunOptions;
use std::path::{Path, PathBuf};
use std::process::ExitCode;

#[derive(clap::Args)]
pub struct Args {
    /// The system file (TOML; its format: docs/reference/system-file.md; a run folder's
    /// system.toml is one).
    pub system: PathBuf,
    #[command(flatten)]
    pub common: Common,
    /// Clearance C [um] for the run-up analysis (eccentricities, plots) of a system whose air
    /// films are not named film_C and film_T (those give their own; the flag is refused there).
    #[arg(long)]
    pub clearance: Option<f64>,
    /// Step height dH [um] for the orbit plots, with --clearance (default 40).
    #[arg(long, requires = "clearance")]
    pub dh: Option<f64>,
}

pub fn execute(a: Args) -> Result<ExitCode, Error> {
    let Args {
        system,
        common,
        clearance,
        dh,
    } = a;
    check_checkpoint_every(common.checkpoint_every)?;
    // The clearance scales the analysis of the whole run: checked before it starts.
    if let Some(c) = clearance {
        master::runup::check_clearance_um(c).flag()?;
    }
    if let Some(dh) = dh {
        master::runup::check_dh_um(dh).flag()?;
    }
    let sys = cosim::System::load(&system).input()?;
    cosim::setup::check_output_interval_whole(&sys).input()?;
    if clearance.is_some() || dh.is_some() {
        check_no_films_named(&system)?;
    }
    let out = common.out.clone().unwrap_or_else(|| {
        default_out(system.file_stem().and_then(|s| s.to_str()).unwrap_or("run"))
    });
    master::run::folder::check_new_run(&out, common.overwrite)?;
    let opts = RunOptions {
        figures: Vec::new(),
        out_dir: out.clone(),
        checkpoint_every_s: common.checkpoint_every,
        stop: stop_flag(),
        halt_at_s: None,
        quiet: common.quiet,
        extra: serde_json::json!({ "system": system }),
        bores: clearance.map(|c| {
            let b = lobes(c, dh.unwrap_or(40.0));
            [b.clone(), b]
        }),
        parquet: common.parquet,
        halt: None,
    };
    let report = new_run(&system, &opts).run()?;
    Ok(finish(report, &out))
}

/// `run --clearance / --dh` describe the bearings of a system without air films `film_C` and
/// `film_T`: where it has them, the analysis takes their own bores (as `classify` does), and a
/// flag that differs would put one clearance in the summary and another in the films.
fn check_no_films_named(system: &Path) -> Result<(), Error> {
    match master::run::read_back::bores_of_system(system).input()? {
        Some([c, t]) => Err(Error::Flag(format!(
            "--clearance / --dh: the system's films film_C and film_T name their own bores \
             (C = {} um and {} um, dH = {} um and {} um), which the run's analysis takes; \
             --clearance and --dh are for systems without those films",
            master::runup::fmt_number(c.c_m * 1e6),
            master::runup::fmt_number(t.c_m * 1e6),
            master::runup::fmt_number(c.dh_m * 1e6),
            master::runup::fmt_number(t.dh_m * 1e6)
        ))),
        None => Ok(()),
    }
}
