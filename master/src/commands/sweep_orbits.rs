//! `airring sweep-orbits`: every cell of a study classified from its whirl orbits at constant speed.

use super::{fmu_dir, jobs_at_least_one};
use master::error::{Classify, Error};
use std::path::PathBuf;
use std::process::ExitCode;

#[derive(clap::Args)]
pub struct Args {
    /// Study file (TOML), as for `airring sweep`.
    pub study: PathBuf,
    /// Output folder.
    #[arg(long)]
    pub out: PathBuf,
    /// Constant-speed simulation per speed before its whirl counts as settled [s].
    #[arg(long, default_value_t = 1.0)]
    pub settle: f64,
    /// The first speed lies this fraction above the linear threshold.
    #[arg(long, default_value_t = 0.1)]
    pub above: f64,
    /// Cells at once, 1 or more (default: one per core; each steps its films serially when > 1).
    #[arg(long, value_parser = jobs_at_least_one)]
    pub jobs: Option<usize>,
    /// A run-up sweep's study.csv to compare the classes with, cell by cell.
    #[arg(long)]
    pub compare: Option<PathBuf>,
    /// Folder with rotor.fmu and airfilm.fmu (default: next to the executable, then
    /// target/fmu).
    #[arg(long)]
    pub fmu_dir: Option<PathBuf>,
}

pub fn execute(a: Args) -> Result<ExitCode, Error> {
    let Args {
        study,
        out,
        settle,
        above,
        jobs,
        compare,
        fmu_dir: dir,
    } = a;
    let study = master::sweep::Study::load(&study).input()?;
    master::run::folder::check_sweep_out(&out)?;
    let opts = master::orbits::study::SweepOrbitsOptions {
        out,
        settle_s: settle,
        above,
        jobs: jobs.unwrap_or_else(master::sweep::default_jobs),
        compare,
        fmu_dir: fmu_dir(dir)?,
    };
    let cells =
        master::orbits::study::sweep_orbits(&study, &opts, &|line| eprintln!("{line}")).run()?;
    let compared: Vec<_> = cells
        .iter()
        .filter_map(|c| c.runup_class.as_ref().map(|r| r == &c.class))
        .collect();
    eprintln!(
        "{} cells -> {}",
        cells.len(),
        opts.out.join("orbit_classes.csv").display()
    );
    if !compared.is_empty() {
        eprintln!(
            "orbit class = run-up class in {} of {} cells",
            compared.iter().filter(|a| **a).count(),
            compared.len()
        );
    }
    Ok(ExitCode::SUCCESS)
}
