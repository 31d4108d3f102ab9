//! `airring orbits`: periodic whirl orbits at constant speeds and their branch.

use super::fmu_dir;
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

pub fn execute(a: Args) -> Result<ExitCode, String> {
    let Args { args, fmu_dir: dir } = a;
    fmu_dir(dir).and_then(|d| master::orbits::cli::run_cli(&args, d).map(|_| ExitCode::SUCCESS))
}
