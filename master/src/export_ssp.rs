//! `airring export-ssp`: the command around `cosim::ssp::export`.

use cosim::System;
use std::path::PathBuf;

#[derive(clap::Args, Clone, Debug)]
pub struct ExportSspArgs {
    /// The system file (as for `airring run`).
    pub system: PathBuf,
    /// The SSP archive to write.
    #[arg(long)]
    pub out: PathBuf,
}

/// The command.
pub fn run_cli(a: &ExportSspArgs) -> Result<(), String> {
    let r = cosim::ssp::export(&a.system, &a.out)?;
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
