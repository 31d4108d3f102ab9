//! `airring orbits`: flags, the printed progress and orbits.json.

use super::driver::{find_orbits, OrbitsRequest};
use crate::error::{Classify, Error};
use std::path::PathBuf;

#[derive(clap::Args, Clone, Debug)]
pub struct OrbitsArgs {
    /// The rotor and its bearings, as for `airring runup`.
    #[command(flatten)]
    pub bearing: crate::runup::DesignArgs,
    /// Constant speeds from:to:step [Hz], or one speed; each is simulated until its whirl settles and the
    /// orbit is shot from there.
    #[arg(long)]
    pub speeds: String,
    /// Constant-speed simulation before a whirl counts as settled [s].
    #[arg(long, default_value_t = 1.0)]
    pub settle: f64,
    /// Only the orbits at the given speeds: no continuation of the branch.
    #[arg(long)]
    pub no_continuation: bool,
    /// Shoot on the full state (the rotor and both films' pressure fields) by Newton-Krylov,
    /// at the given speeds only (no continuation), instead of the reduced shooting in the
    /// rotor's coordinates with the films relaxed onto the orbit.
    #[arg(long)]
    pub full_state: bool,
    /// A run-up folder whose eccentricity envelope the bifurcation diagram shows beside the
    /// orbits.
    #[arg(long)]
    pub runup: Option<PathBuf>,
    /// Output folder (orbits.json, bifurcation.svg/.png, the system file of each speed).
    #[arg(long)]
    pub out: PathBuf,
    /// Replace the orbits the output folder holds, if any (without it such a folder is refused:
    /// its orbits may have taken hours).
    #[arg(long)]
    pub overwrite: bool,
}

/// Checks that the orbits may be written into `dir`: not a run's or a sweep's folder, and no
/// earlier orbits there unless `overwrite`. Returns the earlier outputs with their times of
/// modification, for [`remove_stale`] once the new orbits are written.
fn check_out(
    dir: &std::path::Path,
    overwrite: bool,
) -> Result<Vec<(PathBuf, std::time::SystemTime)>, String> {
    use crate::run::folder::{holds_run, holds_sweep};
    if dir.exists() && !dir.is_dir() {
        return Err(format!(
            "--out {}: exists and is not a folder",
            dir.display()
        ));
    }
    if holds_run(dir) || holds_sweep(dir) {
        return Err(format!(
            "--out {}: holds a run or a sweep; orbits go into a folder of their own",
            dir.display()
        ));
    }
    if !dir.join("orbits.json").exists() {
        return Ok(vec![]);
    }
    if !overwrite {
        return Err(format!(
            "--out {}: holds orbits already (orbits.json); choose another --out or pass \
             --overwrite to replace them",
            dir.display()
        ));
    }
    let mut earlier = vec![];
    for entry in std::fs::read_dir(dir).map_err(|e| format!("{}: {e}", dir.display()))? {
        let path = entry.map_err(|e| format!("{}: {e}", dir.display()))?.path();
        let name = path.file_name().and_then(|n| n.to_str()).unwrap_or("");
        let ours = name == "orbits.json"
            || name.starts_with("bifurcation.")
            || (name.starts_with("system-") && name.ends_with("Hz.toml"));
        if let (true, Ok(t)) = (ours, path.metadata().and_then(|m| m.modified())) {
            earlier.push((path, t));
        }
    }
    Ok(earlier)
}

/// Removes the earlier outputs the new orbits did not rewrite (a system file of a speed not
/// computed again would otherwise stay beside the new ones). Only after the new orbits are
/// written: a run that fails leaves the earlier ones as they were.
fn remove_stale(earlier: &[(PathBuf, std::time::SystemTime)]) {
    for (path, t) in earlier {
        if path.metadata().and_then(|m| m.modified()).ok() == Some(*t) {
            let _ = std::fs::remove_file(path);
        }
    }
}

pub fn run_cli(args: &OrbitsArgs, fmu_dir: PathBuf) -> Result<(), Error> {
    // Every flag is checked before any work, as `runup` does (a NaN clearance was found only
    // after a second of settling, naming a generated system file left in --out).
    let settings = args.bearing.settings().flag()?;
    settings.validate().flag()?;
    settings.check_shaft().flag()?;
    if !(args.settle.is_finite() && args.settle > 0.0) {
        return Err(Error::Flag(format!(
            "--settle {} s: must be a positive, finite time",
            crate::runup::fmt_number(args.settle)
        )));
    }
    let speeds_hz = crate::stability::parse_speeds(&args.speeds).flag()?;
    // The folder's refusals name --out and --overwrite (orbits keep their own files).
    let earlier = check_out(&args.out, args.overwrite).flag()?;
    // Read before hours of shooting, so that a wrong folder is refused at once.
    let runup = match &args.runup {
        Some(dir) => {
            let bores = crate::run::read_back::bores_of_run(dir)
                .input()?
                .ok_or_else(|| {
                    Error::Input(format!(
                        "--runup {}: no run-up's system.toml there",
                        dir.display()
                    ))
                })?;
            Some(crate::analysis::load_run(dir, [bores[0].c_m, bores[1].c_m]).input()?)
        }
        None => None,
    };
    let req = OrbitsRequest {
        settings,
        speeds_hz,
        settle_s: args.settle,
        continuation: !args.no_continuation && !args.full_state,
        full_state: args.full_state,
        fmu_dir,
        out_dir: args.out.clone(),
    };
    let report = find_orbits(&req, &mut |line| eprintln!("{line}")).run()?;
    super::figure::write_bifurcation_diagram(&report, runup.as_ref(), &args.out)
        .map_err(|e| Error::Output(format!("{}: {e}", args.out.display())))?;
    remove_stale(&earlier);
    if let Some(t) = report.linear_threshold_hz {
        println!("linear threshold: {t:.1} Hz");
    }
    if let Some(h) = report.hopf_estimate_hz {
        println!(
            "branch meets the equilibrium at {h:.1} Hz ({})",
            report
                .criticality
                .as_deref()
                .unwrap_or("criticality not decided")
        );
    }
    println!(
        "{} orbits, {} flows, {} macro steps, {:.1} s; written to {}",
        report.orbits.len(),
        report.flows,
        report.macro_steps,
        report.wall_time_s,
        args.out.join("orbits.json").display()
    );
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Earlier orbits are kept unless --overwrite; with it, what the new orbits did not rewrite
    /// is removed once they are written, and only then.
    #[test]
    fn earlier_orbits_are_refused_or_replaced_whole() {
        let dir = std::env::temp_dir().join(format!("airring-orbits-out-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        assert!(check_out(&dir, false).unwrap().is_empty(), "a new folder");
        std::fs::create_dir_all(&dir).unwrap();
        for f in [
            "orbits.json",
            "system-1300Hz.toml",
            "system-900Hz.toml",
            "notes.txt",
        ] {
            std::fs::write(dir.join(f), "old").unwrap();
        }
        let e = check_out(&dir, false).unwrap_err();
        assert!(e.contains("holds orbits already (orbits.json)"), "{e}");
        let earlier = check_out(&dir, true).unwrap();
        assert_eq!(earlier.len(), 3, "{earlier:?}");
        std::thread::sleep(std::time::Duration::from_millis(20));
        // The new run writes its orbits and the system file of its one speed.
        for f in ["orbits.json", "system-900Hz.toml"] {
            std::fs::write(dir.join(f), "new").unwrap();
        }
        remove_stale(&earlier);
        let mut left: Vec<String> = std::fs::read_dir(&dir)
            .unwrap()
            .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
            .collect();
        left.sort();
        assert_eq!(left, ["notes.txt", "orbits.json", "system-900Hz.toml"]);
        std::fs::write(dir.join("summary.json"), "{}").unwrap();
        let e = check_out(&dir, true).unwrap_err();
        assert!(e.contains("holds a run or a sweep"), "{e}");
        let _ = std::fs::remove_dir_all(&dir);
    }
}
