//! `airring`: the AirRing co-simulation master (command line). One module per subcommand in
//! `commands/`; this file parses the command line and dispatches.

mod commands;

use clap::{Parser, Subcommand};
use std::process::ExitCode;

#[derive(Parser)]
#[command(
    name = "airring",
    version,
    about = "Rotors in air ring bearings: FMI 2.0 co-simulation master"
)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// A run-up of the paper's rotor in two air ring bearings.
    #[command(allow_negative_numbers = true)]
    Runup(commands::runup::Args),
    /// Any system described by a TOML system file.
    #[command(allow_negative_numbers = true)]
    Run(commands::run::Args),
    /// Continue an interrupted run from its last checkpoint.
    Resume(commands::resume::Args),
    /// A parameter study of run-ups from a study file (TOML), resumable; CSV table and bifurcation maps.
    Sweep(commands::sweep::Args),
    /// Merge the run folders of several sweep outputs (shards) into one table and map.
    SweepMerge(commands::sweep_merge::Args),
    /// How a sweep's classes depend on the classifier's bounds: every completed run classified
    /// again with each bound moved down and up (sensitivity.csv, and a summary).
    #[command(allow_negative_numbers = true)]
    SweepSensitivity(commands::sweep_sensitivity::Args),
    /// Every cell of a study classified from its whirl orbits at constant speed (just past the
    /// linear threshold and at the top speed) instead of a run-up; resumable
    /// (orbit_classes.csv, orbit_classes.json, one folder per cell).
    #[command(allow_negative_numbers = true)]
    SweepOrbits(commands::sweep_orbits::Args),
    /// Modal analysis of the rotor with linear film springs (paper Section 2.3).
    #[command(allow_negative_numbers = true)]
    Modal(commands::modal::Args),
    /// Linear stability: static equilibrium, Campbell table with damping, threshold speed.
    #[command(allow_negative_numbers = true)]
    Stability(commands::stability::Args),
    /// Classify a finished run folder again from its timeseries.csv (prints JSON: class, onset,
    /// first bearing, maximum eccentricities, criteria).
    #[command(allow_negative_numbers = true)]
    Classify(commands::classify::Args),
    /// The air-film library alone along a journal orbit from a CSV file, fed as FMPy's simulate_fmu
    /// feeds airfilm.fmu (cross-check; see docs/fmu-guide.md).
    #[command(allow_negative_numbers = true)]
    Orbit(commands::orbit::Args),
    /// Periodic whirl orbits at constant speeds (shooting on the co-simulation), their Floquet
    /// multipliers, and the branch continued in speed to its Hopf point (orbits.json).
    #[command(allow_negative_numbers = true)]
    Orbits(commands::orbits::Args),
    /// Which design to build: a search over design variables for the design that best meets an
    /// objective while the requirement (film thickness, whirl amplitude, class over a speed
    /// range) holds at every tolerance corner; the recommendation verified on a finer film mesh
    /// (evaluations.csv, optimum.json, recommended.toml, report.html); resumable.
    #[command(allow_negative_numbers = true)]
    Optimize(commands::optimize::Args),
    /// Write a system file as an SSP 1.0 archive (SystemStructure.ssd + the FMUs) for other tools.
    ExportSsp(commands::export_ssp::Args),
}

/// Commands whose product is their standard output end quietly when the reader goes away
/// (`airring classify DIR | head -c1`), as Unix filters do, instead of panicking on EPIPE: the
/// default SIGPIPE action. Run-ups keep Rust's ignored SIGPIPE: they write files, not stdout,
/// and must reach their checkpoint and summary even if the terminal's pipe closes.
fn quiet_on_closed_stdout(command: &Command) {
    let filter = match command {
        Command::Classify(_)
        | Command::Modal(_)
        | Command::Stability(_)
        | Command::SweepSensitivity(_) => true,
        Command::Sweep(a) => a.list,
        _ => false,
    };
    if filter {
        // SAFETY: called once at start-up, before any thread exists; SIG_DFL is a valid action.
        unsafe {
            libc::signal(libc::SIGPIPE, libc::SIG_DFL);
        }
    }
}

fn main() -> ExitCode {
    let cli = Cli::parse();
    quiet_on_closed_stdout(&cli.command);
    let result: Result<ExitCode, master::error::Error> = match cli.command {
        Command::Runup(a) => commands::runup::execute(a),
        Command::Run(a) => commands::run::execute(a),
        Command::Resume(a) => commands::resume::execute(a),
        Command::Sweep(a) => commands::sweep::execute(a),
        Command::SweepMerge(a) => commands::sweep_merge::execute(a),
        Command::SweepSensitivity(a) => commands::sweep_sensitivity::execute(a),
        Command::SweepOrbits(a) => commands::sweep_orbits::execute(a),
        Command::Modal(a) => commands::modal::execute(a),
        Command::Stability(a) => commands::stability::execute(a),
        Command::Classify(a) => commands::classify::execute(a),
        Command::Orbit(a) => commands::orbit::execute(a),
        Command::ExportSsp(a) => commands::export_ssp::execute(a),
        Command::Orbits(a) => commands::orbits::execute(a),
        Command::Optimize(a) => commands::optimize::execute(a),
    };
    match result {
        Ok(code) => code,
        Err(e) => {
            eprintln!("airring: {e}");
            ExitCode::FAILURE
        }
    }
}

#[cfg(test)]
mod tests {
    //! Each command's refusals come out as the variant of their kind: a caller tells a refused
    //! flag, input file or folder from a failed run without reading the text.
    use super::*;
    use master::error::Error;
    use master::run::folder::FolderError;

    fn execute(args: &[&str]) -> Result<ExitCode, Error> {
        let cli = Cli::try_parse_from(std::iter::once("airring").chain(args.iter().copied()))
            .expect("the arguments parse");
        match cli.command {
            Command::Runup(a) => commands::runup::execute(a),
            Command::Sweep(a) => commands::sweep::execute(a),
            Command::Resume(a) => commands::resume::execute(a),
            Command::Optimize(a) => commands::optimize::execute(a),
            Command::Classify(a) => commands::classify::execute(a),
            Command::Modal(a) => commands::modal::execute(a),
            _ => unreachable!("not used here"),
        }
    }

    fn scratch(name: &str) -> std::path::PathBuf {
        let d = std::env::temp_dir().join(format!("airring-errors-{name}-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&d);
        std::fs::create_dir_all(&d).unwrap();
        d
    }

    #[test]
    fn refused_flags_are_flag_errors() {
        let e = execute(&["runup", "--clearance", "-3"]).unwrap_err();
        assert!(matches!(&e, Error::Flag(m) if m.contains("-3")), "{e:?}");
        let e = execute(&["runup", "--checkpoint-every", "0"]).unwrap_err();
        assert!(
            matches!(&e, Error::Flag(m) if m.starts_with("--checkpoint-every")),
            "{e:?}"
        );
        let e = execute(&["sweep", "x.toml", "--linear", "--jobs", "2"]).unwrap_err();
        assert!(
            matches!(&e, Error::Flag(m) if m.starts_with("--linear")),
            "{e:?}"
        );
        let e = execute(&["modal", "--rotor", "r.toml", "--c", "500"]).unwrap_err();
        assert!(
            matches!(&e, Error::Flag(m) if m.contains("--bearing-nodes")),
            "{e:?}"
        );
    }

    #[test]
    fn unreadable_input_files_are_input_errors() {
        let d = scratch("input");
        let missing = d.join("missing.toml");
        let missing = missing.to_str().unwrap();
        for args in [
            vec!["sweep", missing],
            vec!["optimize", missing],
            vec!["classify", missing],
            vec!["resume", d.to_str().unwrap()],
        ] {
            let e = execute(&args).unwrap_err();
            assert!(matches!(&e, Error::Input(_)), "{args:?}: {e:?}");
        }
        let _ = std::fs::remove_dir_all(&d);
    }

    /// A folder holding a run is refused, typed, before anything runs (no FMUs are needed).
    #[test]
    fn an_occupied_output_folder_is_a_folder_error() {
        let d = scratch("folder");
        std::fs::write(d.join("system.toml"), "").unwrap();
        std::fs::write(d.join("summary.json"), r#"{"status": "completed"}"#).unwrap();
        let e = execute(&["runup", "--stop", "0.1", "--out", d.to_str().unwrap()]).unwrap_err();
        assert!(
            matches!(&e, Error::Folder(FolderError::RunExists { path, .. }) if *path == d),
            "{e:?}"
        );
        assert!(
            e.to_string().contains("--overwrite"),
            "the message as before: {e}"
        );
        let _ = std::fs::remove_dir_all(&d);
    }
}
