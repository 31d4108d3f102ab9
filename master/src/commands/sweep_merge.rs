//! `airring sweep-merge`: the run folders of several sweep outputs (shards) in one table and map.

use master::error::{Classify, Error};
use std::path::PathBuf;
use std::process::ExitCode;

#[derive(clap::Args)]
pub struct Args {
    /// Sweep output folders (each with its runs/).
    #[arg(required = true)]
    pub dirs: Vec<PathBuf>,
    /// Output folder (default: the first DIR).
    #[arg(long)]
    pub out: Option<PathBuf>,
}

pub fn execute(a: Args) -> Result<ExitCode, Error> {
    let Args { dirs, out } = a;
    let out = out.unwrap_or_else(|| dirs[0].clone());
    master::run::folder::check_sweep_out(&out)?;
    let (table, maps, n) = master::sweep::merge(&dirs, &out).input()?;
    eprintln!("{n} runs -> {}, {}", table.display(), maps[0].display());
    Ok(ExitCode::SUCCESS)
}
