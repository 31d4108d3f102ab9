//! `airring classify`: a finished run folder classified again from its timeseries.csv.

use master::error::{Classify, Error};
use std::path::{Path, PathBuf};
use std::process::ExitCode;

#[derive(clap::Args)]
pub struct Args {
    /// A run-up's folder (its timeseries.csv and system.toml).
    pub dir: PathBuf,
    /// Clearance C [um] of both bearings, for run folders whose system.toml names no air
    /// films (a system of one's own); otherwise each film's, from that file, and a
    /// different value is refused.
    #[arg(long)]
    pub clearance: Option<f64>,
}

pub fn execute(a: Args) -> Result<ExitCode, Error> {
    let Args { dir, clearance } = a;
    classify(&dir, clearance)
}

fn classify(dir: &Path, clearance_um: Option<f64>) -> Result<ExitCode, Error> {
    if !dir.is_dir() {
        return Err(Error::Input(format!(
            "{}: no such folder (classify takes a run-up's folder, e.g. runs/path1)",
            dir.display()
        )));
    }
    // Each bearing's clearance: the flag, else the run folder's own system file (never a default).
    let c_m = match clearance_um {
        Some(c) => {
            master::runup::check_clearance_um(c).flag()?;
            // Where the run's films name their clearances, the film eccentricities are measured
            // against those: another clearance would classify the amplitudes against one value
            // and the eccentricities against another.
            if let Some(bores) = master::run::read_back::bores_of_run(dir).input()? {
                if bores.iter().any(|b| (b.c_m * 1e6 - c).abs() > 1e-9 * c) {
                    return Err(Error::Flag(format!(
                        "--clearance = {} um: the run's films ran with C = {} um and {} um \
                         (its system.toml); --clearance is for run folders whose system file \
                         names no air films",
                        master::runup::fmt_number(c),
                        master::runup::fmt_number(bores[0].c_m * 1e6),
                        master::runup::fmt_number(bores[1].c_m * 1e6)
                    )));
                }
            }
            [c / 1e6; 2]
        }
        None => match master::run::read_back::bores_of_run(dir).input()? {
            Some([c, t]) => [c.c_m, t.c_m],
            None => {
                return Err(Error::Input(format!(
                    "{}: its system.toml has no air films film_C and film_T to take the \
                     clearance from; give it with --clearance UM",
                    dir.display()
                )))
            }
        },
    };
    let series = master::analysis::load_run(dir, c_m).input()?;
    let cl = master::analysis::classify(&series);
    // A run that did not complete (interrupted, failed, or killed while its summary still said
    // "running") is classified on what it simulated, as its own summary says: said here too.
    let status = master::summary::RunSummary::read(dir).map(|s| s.status);
    let note = match status {
        Some(master::summary::RunStatus::Completed) => None,
        other => Some(format!(
            "classified on the part of the run-up that was simulated (to t = {} s; the run {})",
            series.t_s.last().copied().unwrap_or(0.0),
            match other {
                Some(master::summary::RunStatus::Running) => "was killed before it ended",
                Some(master::summary::RunStatus::Interrupted) => "was interrupted",
                Some(_) => "failed",
                None => "has no summary.json",
            }
        )),
    };
    let out = serde_json::json!({
        "run": dir.display().to_string(),
        "clearance_um": { "C": c_m[0] * 1e6, "T": c_m[1] * 1e6 },
        "classification": cl.class.as_str(),
        "classification_note": note,
        "onset_time_s": cl.onset_time_s,
        "onset_speed_hz": cl.onset_speed_hz,
        "first_bearing": cl.first_bearing,
        "max_eps_C": cl.max_eps_c,
        "max_eps_T": cl.max_eps_t,
        "criteria": cl.criteria,
        "borderline": cl.borderline,
        "margins": cl.margins,
    });
    println!("{}", serde_json::to_string_pretty(&out).output()?);
    Ok(ExitCode::SUCCESS)
}
