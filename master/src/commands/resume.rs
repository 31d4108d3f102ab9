//! `airring resume`: continue an interrupted run from its last checkpoint.

use super::{check_checkpoint_every, finish, stop_flag};
use master::error::{Classify, Error};
use master::run::{run, RunOptions};
use std::path::PathBuf;
use std::process::ExitCode;

#[derive(clap::Args)]
pub struct Args {
    /// The run folder (an interrupted run's, with its checkpoint).
    pub dir: PathBuf,
    /// Save a checkpoint every this many simulated seconds from here on [s].
    #[arg(long)]
    pub checkpoint_every: Option<f64>,
    /// Also write timeseries.parquet at the end (automatic if the run wrote one before).
    #[arg(long)]
    pub parquet: bool,
}

/// The halt of a run-up's settings (`halt_film_um`, `halt_whirl_um`, `halt_speeds_hz` in
/// summary.json).
fn halt_of(settings: &serde_json::Value) -> Option<master::run::Halt> {
    let um = |key: &str| settings.get(key).and_then(|v| v.as_f64());
    let (film, whirl) = (um("halt_film_um"), um("halt_whirl_um"));
    if film.is_none() && whirl.is_none() {
        return None;
    }
    let speeds = settings
        .get("halt_speeds_hz")
        .and_then(|v| Some((v.get(0)?.as_f64()?, v.get(1)?.as_f64()?)))
        .unwrap_or((0.0, f64::INFINITY));
    Some(master::run::Halt {
        min_film_m: film.map(|um| um * 1e-6),
        max_whirl_m: whirl.map(|um| um * 1e-6),
        speeds_hz: speeds,
    })
}

pub fn execute(a: Args) -> Result<ExitCode, Error> {
    let Args {
        dir,
        checkpoint_every,
        parquet,
    } = a;
    check_checkpoint_every(checkpoint_every)?;
    if !dir.join("system.toml").is_file() {
        return Err(Error::Input(format!(
            "{}: no run to resume (no system.toml): the run never started here, or this \
             is not a run folder",
            dir.display()
        )));
    }
    master::run::folder::check_not_in_progress(&dir)?;
    let old = master::summary::RunSummary::read(&dir).unwrap_or_default();
    if old.status == master::summary::RunStatus::Completed {
        return Err(Error::Input(format!(
            "{}: the run completed (summary.json): nothing to resume",
            dir.display()
        )));
    }
    if !dir.join("checkpoint").is_dir() {
        let why = old
            .error
            .as_deref()
            .map_or(String::new(), |e| format!(": {e}"));
        let what = match old.status {
            // Its summary still says "running": killed before it could say how it ended.
            master::summary::RunStatus::Running => "was killed before it ended, and \
                --checkpoint-every was not given"
                .to_string(),
            master::summary::RunStatus::Interrupted => format!("was interrupted{why}"),
            other => format!("{}{why}", other.as_str()),
        };
        return Err(Error::Input(format!(
            "{}: no checkpoint to resume from (the run {what}); run it again with \
             --overwrite",
            dir.display(),
        )));
    }
    // A run-up that was to halt on its film limit still is.
    let halt = halt_of(&old.settings);
    // A flexible rotor's drawing, from the shaft in the rotor FMU the run-up ran.
    let figures = old
        .settings
        .get("rotor_fmu")
        .and_then(|p| p.as_str())
        .and_then(|p| master::runup::shaft_fmu::shaft_in(std::path::Path::new(p)).ok()?)
        .map(|spec| {
            let chart = master::flexible::drawing_with_bearings(&spec.shaft, spec.bearing_nodes);
            ("rotor".to_string(), chart)
        })
        .into_iter()
        .collect();
    let opts = RunOptions {
        figures,
        out_dir: dir.clone(),
        checkpoint_every_s: checkpoint_every,
        stop: stop_flag(),
        halt_at_s: None,
        quiet: false,
        extra: old.settings,
        // The bores come from the run folder's own system file.
        bores: None,
        // A run that wrote Parquet goes on writing it.
        parquet: parquet || dir.join("timeseries.parquet").exists(),
        halt,
    };
    let report = run(&dir.join("system.toml"), &opts, true).run()?;
    Ok(finish(report, &dir))
}
