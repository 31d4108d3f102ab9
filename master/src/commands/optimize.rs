//! `airring optimize`: the design that best meets an objective while the requirement holds at
//! every tolerance corner, found by a search over design variables and verified.

use super::{jobs_at_least_one, stop_flag};
use master::error::{Classify, Error};
use std::path::PathBuf;
use std::process::ExitCode;

#[derive(clap::Args)]
pub struct Args {
    /// The optimisation file (TOML; docs/reference/optimization-file.md).
    pub file: PathBuf,
    /// Output folder (default: `runs/optimize-<name>`); an interrupted optimisation resumes
    /// from it.
    #[arg(long)]
    pub out: Option<PathBuf>,
    /// Run-ups at a time, 1 or more (default: one per core).
    #[arg(long, value_parser = jobs_at_least_one)]
    pub jobs: Option<usize>,
    /// Evaluations in all (replaces the file's [search] budget; a larger one continues a
    /// finished optimisation).
    #[arg(long)]
    pub budget: Option<usize>,
    /// Skip the verification of the recommended design (slow run-ups and run-downs on the fine
    /// film mesh at every tolerance corner).
    #[arg(long)]
    pub no_verify: bool,
    /// No progress lines (each round's summary is still printed).
    #[arg(long)]
    pub quiet: bool,
    /// Leave the run-ups to another runner (Dask, Slurm, `airring sweep`): when a round needs
    /// run-ups that are not in the output folder yet, write their study file, print its path on
    /// standard output and exit with status 3; run that study into its own folder, then this
    /// command again (docs/howto/optimize.md).
    #[arg(long)]
    pub external_runs: bool,
}

pub fn execute(a: Args) -> Result<ExitCode, Error> {
    let text = std::fs::read_to_string(&a.file)
        .map_err(|e| Error::Input(format!("{}: {e}", a.file.display())))?;
    let mut problem = master::optimize::Problem::parse(&text, &a.file).input()?;
    if let Some(b) = a.budget {
        if b < 2
            || (problem.method == master::optimize::problem::SearchMethod::Ego
                && b < problem.initial)
        {
            return Err(Error::Flag(format!(
                "--budget {b}: at least 2, and at least the initial design's {} points",
                problem.initial
            )));
        }
        problem.budget = b;
    }
    let out = a
        .out
        .unwrap_or_else(|| PathBuf::from("runs").join(format!("optimize-{}", problem.name)));
    master::run::folder::check_sweep_out(&out)?;
    let opts = master::optimize::OptimizeOptions {
        out: out.clone(),
        jobs: a.jobs.unwrap_or_else(master::sweep::default_jobs),
        exe: std::env::current_exe().run()?,
        quiet: a.quiet,
        stop: stop_flag(),
        no_verify: a.no_verify,
        external_runs: a.external_runs,
    };
    let r = master::optimize::optimize(&problem, &text, &opts).run()?;
    if let Some((study, n)) = &r.pending {
        let folder = study.parent().unwrap_or(std::path::Path::new("."));
        eprintln!(
            "optimize: {} evaluations so far; {n} run-ups wait in {}: run them into {} (airring \
             sweep {} --out {}, scripts/dask_sweep.py, or Slurm shards), then this command again",
            r.candidates.len(),
            study.display(),
            folder.display(),
            study.display(),
            folder.display()
        );
        println!("{}", study.display());
        return Ok(ExitCode::from(3));
    }
    let verdict = match (&r.best, &r.verification) {
        (None, _) => match master::optimize::closest_of(&r.candidates) {
            Some(i) => {
                let c = &r.candidates[i];
                format!(
                    "no design meets the requirement; nearest: #{} ({}): {}",
                    c.index,
                    master::optimize::describe_x(&problem, &c.x),
                    c.reason
                )
            }
            None => "no design meets the requirement".to_string(),
        },
        (Some(b), v) => {
            let c = &r.candidates[*b];
            let checked = match v {
                Some(v) if v.verified && v.resolved => "verified".to_string(),
                Some(v) if v.verified => {
                    "met on the fine mesh, but within its discretization error".to_string()
                }
                Some(_) => "NOT verified: a corner fails on the fine mesh".to_string(),
                None => "not verified".to_string(),
            };
            format!(
                "recommended #{}: {} ({checked})",
                c.index,
                master::optimize::describe_x(&problem, &c.x)
            )
        }
    };
    eprintln!(
        "optimize: {} evaluations ({} feasible) in {:.0} s wall; {verdict} -> {}",
        r.candidates.len(),
        r.candidates.iter().filter(|c| c.feasible).count(),
        r.wall_time_s,
        out.join("report.html").display()
    );
    Ok(if r.interrupted {
        ExitCode::FAILURE
    } else {
        ExitCode::SUCCESS
    })
}
