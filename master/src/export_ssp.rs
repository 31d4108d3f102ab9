//! `airring export-ssp`: the command around `cosim::ssp::export`.

use crate::error::{Classify, Error};
use cosim::System;
use std::path::PathBuf;

#[derive(clap::Args, Clone, Debug)]
pub struct ExportSspArgs {
    /// The system file (as for `airring run`).
    pub system: PathBuf,
    /// The SSP archive to write (a new file, unless --overwrite).
    #[arg(long)]
    pub out: PathBuf,
    /// Replace the file --out names, if it exists.
    #[arg(long)]
    pub overwrite: bool,
}

/// AirRing's names in the archives it writes: the parameter set every component's values are
/// under (`init(parameter_set="airring")` in ecos), the generation tool, the annotation type.
pub fn ssp_names() -> cosim::ssp::SspNames {
    cosim::ssp::SspNames {
        tool: format!("airring {}", env!("CARGO_PKG_VERSION")),
        parameter_set: "airring".into(),
        algorithm_annotation: "org.airring.algorithm".into(),
    }
}

/// The command.
pub fn run_cli(a: &ExportSspArgs) -> Result<(), Error> {
    if a.out.is_dir() {
        return Err(Error::Flag(format!(
            "--out {}: a folder; name the archive file",
            a.out.display()
        )));
    }
    // A link counts as existing (also one to nothing); --overwrite replaces the link itself.
    if std::fs::symlink_metadata(&a.out).is_ok() && !a.overwrite {
        return Err(Error::Flag(format!(
            "--out {}: exists; choose another file or pass --overwrite to replace it",
            a.out.display()
        )));
    }
    // What the export refuses is nearly always the system file or its FMUs (writing the
    // archive is its last step).
    let r = cosim::ssp::export(&a.system, &a.out, &ssp_names()).input()?;
    if let Ok(sys) = System::load(&a.system) {
        if sys.file.algorithm.step_control.is_some() {
            eprintln!(
                "note: the system's step_control has no SSP equivalent; other tools run the fixed macro step"
            );
        }
        if sys.file.algorithm.long_steps.is_some() {
            eprintln!(
                "note: the system's long_steps (calm macro steps) have no SSP equivalent; other tools run the base macro step throughout"
            );
        }
    }
    eprintln!(
        "{}: {} components, {} connections, {} parameter values, {}",
        a.out.display(),
        r.components,
        r.connections,
        r.parameters,
        r.resources.join(", ")
    );
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    /// An existing file is not replaced without --overwrite (a run's summary.json was).
    #[test]
    fn an_existing_file_is_kept_unless_overwrite() {
        let dir = std::env::temp_dir().join(format!("airring-ssp-out-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let out = dir.join("summary.json");
        std::fs::write(&out, "{}").unwrap();
        let args = |overwrite| ExportSspArgs {
            system: dir.join("missing.toml"),
            out: out.clone(),
            overwrite,
        };
        let e = run_cli(&args(false)).unwrap_err();
        assert!(
            matches!(&e, Error::Flag(m) if m.contains("exists; choose another file or pass --overwrite")),
            "{e:?}"
        );
        assert_eq!(std::fs::read_to_string(&out).unwrap(), "{}");
        // With --overwrite the export itself runs (and fails here on the missing system file).
        let e = run_cli(&args(true)).unwrap_err();
        assert!(
            matches!(&e, Error::Input(m) if m.contains("missing.toml")),
            "{e:?}"
        );
        let e = run_cli(&ExportSspArgs {
            out: dir.clone(),
            ..args(true)
        })
        .unwrap_err();
        assert!(
            matches!(&e, Error::Flag(m) if m.contains("a folder; name the archive file")),
            "{e:?}"
        );
        let _ = std::fs::remove_dir_all(&dir);
    }
}
