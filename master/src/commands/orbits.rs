//! `airring orbits`: periodic whirl orbits at constant speeds and their branch.

use super::fmu_dir;
use master::error::Error;
use std::path::PathBuf;
use std::process::ExitCode;

#[derive(clap::Args)]
pub struct Args {
    #[command(flatten)]
    pub args: master::orbits::cli::OrbitsArgs,
    /// Folder with rotor.fmu and airfilm.fmu (default: next to the executable, then
    /// target/fmu).
    #[arg(long)]
    pub fmu_dir: Option<PathBuf>,
}

pub fn execute(a: Args) -> Result<ExitCode, Error> {
    let Args { args, fmu_dir: dir } = a;
    master::orbits::cli::run_cli(&args, fmu_dir(dir)?)?;
    Ok(ExitCode::SUCCESS)
}
