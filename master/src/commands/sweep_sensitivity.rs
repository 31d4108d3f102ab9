//! `airring sweep-sensitivity`: how a sweep's classes depend on the classifier's bounds.

use master::error::{Classify, Error};
use std::path::PathBuf;
use std::process::ExitCode;

#[derive(clap::Args)]
pub struct Args {
    /// A sweep's output folder.
    pub dir: PathBuf,
    /// Relative move of each bound.
    #[arg(long, default_value_t = 0.2)]
    pub delta: f64,
}

pub fn execute(a: Args) -> Result<ExitCode, Error> {
    let Args { dir, delta } = a;
    let (runs, left_out) = master::sweep::sensitivity::sensitivity(&dir, delta).input()?;
    let (path, text) = master::sweep::sensitivity::write(&dir, delta, &runs, &left_out).output()?;
    print!("{text}");
    eprintln!("-> {}", path.display());
    Ok(ExitCode::SUCCESS)
}
