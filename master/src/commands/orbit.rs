//! `airring orbit`: the air-film library along a CSV orbit (flags and run in `master::film_orbit`).

use master::error::Error;
use std::process::ExitCode;

pub type Args = master::film_orbit::OrbitArgs;

pub fn execute(a: Args) -> Result<ExitCode, Error> {
    master::film_orbit::run_cli(&a)?;
    Ok(ExitCode::SUCCESS)
}
