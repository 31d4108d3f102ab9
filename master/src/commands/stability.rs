//! `airring stability`: linear stability (the flags and the analysis live in `master::stability::cli`, shared with the library's tests).

use master::error::Error;
use std::process::ExitCode;

pub type Args = master::stability::cli::StabilityArgs;

pub fn execute(a: Args) -> Result<ExitCode, Error> {
    master::stability::cli::run_cli(&a)?;
    Ok(ExitCode::SUCCESS)
}
