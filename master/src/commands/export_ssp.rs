//! `airring export-ssp`: a system file as an SSP 1.0 archive (flags and export in `master::export_ssp`).

use master::error::Error;
use std::process::ExitCode;

pub type Args = master::export_ssp::ExportSspArgs;

pub fn execute(a: Args) -> Result<ExitCode, Error> {
    master::export_ssp::run_cli(&a)?;
    Ok(ExitCode::SUCCESS)
}
