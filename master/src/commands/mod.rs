//! One module per subcommand: its flags (`Args`) and what it does (`execute`); `main.rs` only
//! dispatches. What several commands share is here: the common run flags, the output folder's
//! default, finding the FMUs, the stop signal, a run's start and end.

pub mod classify;
pub mod export_ssp;
pub mod modal;
pub mod optimize;
pub mod orbit;
pub mod orbits;
pub mod resume;
pub mod run;
pub mod runup;
pub mod stability;
pub mod sweep;
pub mod sweep_merge;
pub mod sweep_orbits;
pub mod sweep_sensitivity;

use master::error::Error;
use master::run::{run, RunOptions};
use std::path::{Path, PathBuf};
use std::process::ExitCode;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;

#[derive(clap::Args, Clone)]
pub struct Common {
    /// Output folder (default: `runs/<name>-<timestamp>`).
    #[arg(long)]
    pub out: Option<PathBuf>,
    /// Save a checkpoint every this many simulated seconds.
    #[arg(long)]
    pub checkpoint_every: Option<f64>,
    /// No progress display.
    #[arg(long)]
    pub quiet: bool,
    /// Also write the time series as timeseries.parquet when the run ends (the CSV is written as
    /// the run goes in any case, so a killed run keeps its data).
    #[arg(long)]
    pub parquet: bool,
    /// Replace the run in the output folder, if it holds one (without it, such a folder is
    /// refused). The old run stays untouched until the new one has started.
    #[arg(long)]
    pub overwrite: bool,
}

pub fn default_out(name: &str) -> PathBuf {
    let secs = std::time::SystemTime::now()
        .duration_since(std::time::UNIX_EPOCH)
        .map(|d| d.as_secs())
        .unwrap_or(0);
    PathBuf::from("runs").join(format!("{name}-{secs}"))
}

pub fn fmu_dir(given: Option<PathBuf>) -> Result<PathBuf, Error> {
    let candidates: Vec<PathBuf> = match given {
        Some(d) => vec![d],
        None => {
            let mut c = vec![PathBuf::from("target/fmu")];
            if let Ok(exe) = std::env::current_exe() {
                if let Some(p) = exe.parent().and_then(Path::parent) {
                    c.push(p.join("fmu"));
                }
            }
            c
        }
    };
    for d in &candidates {
        if d.join("rotor.fmu").exists() && d.join("airfilm.fmu").exists() {
            return d.canonicalize().map_err(|e| Error::Fmus(e.to_string()));
        }
    }
    Err(Error::Fmus(format!("rotor.fmu and airfilm.fmu not found in {candidates:?}: build them with `cargo xtask fmus` or pass --fmu-dir")))
}

/// The paper's three-lobe geometry with the given clearance and step height [um].
pub fn lobes(clearance_um: f64, dh_um: f64) -> bearing::Bore {
    bearing::Bore {
        c_m: clearance_um / 1e6,
        dh_m: dh_um / 1e6,
        ..bearing::Bore::paper()
    }
}

pub fn stop_flag() -> Arc<AtomicBool> {
    let flag = Arc::new(AtomicBool::new(false));
    let f = flag.clone();
    let _ = ctrlc::set_handler(move || {
        if f.swap(true, Ordering::Relaxed) {
            eprintln!("\nsecond stop signal: exiting at once");
            std::process::exit(130);
        }
        // Ctrl-C, and (ctrlc's `termination` feature) SIGTERM and SIGHUP: a batch system's time
        // limit stops a run the same way, leaving a checkpoint to resume from. After the last
        // macro step there is nothing left to stop and no checkpoint is written.
        if master::run::RUN_LOOP_ENDED.load(Ordering::Relaxed) {
            eprintln!(
                "\nstop signal after the run's last macro step: the run has ended (no checkpoint \
                 is written); its summary and figures are being written"
            );
        } else {
            eprintln!(
                "\nstop signal: stopping at the next macro step (checkpoint and summary are \
                 written)"
            );
        }
    });
    flag
}

/// A new run into `opts.out_dir`; a folder this call created is removed again if the run could
/// not start (an existing one is left as it was).
pub fn new_run(system: &Path, opts: &RunOptions) -> Result<master::run::RunReport, String> {
    let created = !opts.out_dir.exists();
    let r = run(system, opts, false);
    if r.is_err() && created {
        // Only if empty: remove_dir refuses a folder with content.
        let _ = std::fs::remove_dir(&opts.out_dir);
    }
    r
}

pub fn finish(report: master::run::RunReport, out: &Path) -> ExitCode {
    let s = master::summary::RunSummary::read(out).unwrap_or_default();
    eprintln!(
        "{}: {} macro steps to t = {:.4} s in {:.1} s wall; classification: {}, onset: {} s",
        out.display(),
        report.macro_steps,
        report.t_end_s,
        report.wall_time_s,
        s.classification
            .map_or("null".to_string(), |c| format!("\"{c}\"")),
        s.onset_time_s.map_or("null".to_string(), |t| t.to_string())
    );
    match report.error {
        Some(e) => {
            eprintln!("error: {e}");
            ExitCode::FAILURE
        }
        None if report.interrupted => ExitCode::from(130),
        None => ExitCode::SUCCESS,
    }
}

/// `--jobs`: a whole number of run-ups (cells) at a time, 1 or more (0 used to be taken and run
/// one at a time all the same).
pub fn jobs_at_least_one(text: &str) -> Result<usize, String> {
    match text.trim().parse::<usize>() {
        Ok(0) => Err("0 run-ups at a time would run none: give 1 or more".into()),
        Ok(n) => Ok(n),
        Err(_) => Err(format!(
            "'{text}' is not a whole number of run-ups (1 or more)"
        )),
    }
}

/// `--checkpoint-every`, checked with its name before a run starts.
pub fn check_checkpoint_every(every_s: Option<f64>) -> Result<(), Error> {
    match every_s {
        Some(dt) if !(dt.is_finite() && dt > 0.0) => Err(Error::Flag(format!(
            "--checkpoint-every = {dt} s must be a finite number > 0 (simulated seconds)"
        ))),
        _ => Ok(()),
    }
}
