//! `airring sweep`: a parameter study of run-ups (or their linear prediction) from a study file.

use super::{jobs_at_least_one, stop_flag};
use master::error::{Classify, Error};
use std::path::{Path, PathBuf};
use std::process::ExitCode;
use std::sync::atomic::Ordering;

#[derive(clap::Args)]
pub struct Args {
    pub study: PathBuf,
    /// Output folder (default: `runs/sweep-<study name>`).
    #[arg(long)]
    pub out: Option<PathBuf>,
    /// Run-ups at a time, 1 or more (default: one per core, each stepping its films one after
    /// the other).
    #[arg(long, value_parser = jobs_at_least_one)]
    pub jobs: Option<usize>,
    /// Run only every n-th grid point: k/n runs the points with index i where i mod n = k - 1.
    #[arg(long)]
    pub shard: Option<String>,
    /// No progress lines (each finished run and the closing summary are still printed).
    #[arg(long)]
    pub quiet: bool,
    /// Run again the completed runs in the output folder that were made with other flags
    /// (an edited study file); without it such a folder is refused, naming them.
    #[arg(long)]
    pub overwrite: bool,
    /// Print the run-ups (name, index, flags, `airring` arguments) as JSON lines and exit.
    #[arg(long)]
    pub list: bool,
    /// Predict the map with the linear stability analysis first (study_linear.csv,
    /// bifurcation_map_linear.*; seconds, against the run-ups' minutes), then run the
    /// run-ups, those predicted to take longest (unstable, earliest onset) first.
    #[arg(long)]
    pub predict_first: bool,
    /// Every run-up writes a checkpoint every this many seconds of simulated time, so a killed
    /// one loses at most that much (interrupted ones checkpoint when they stop in any case,
    /// and the next sweep resumes them).
    #[arg(long)]
    pub checkpoint_every: Option<f64>,
    /// Predict the map with the linear stability analysis instead of running the run-ups
    /// (threshold speed and visible onset per point; study_linear.csv, bifurcation_map_linear.*).
    #[arg(long)]
    pub linear: bool,
    /// Speed grid of the linear prediction, from:to:step [Hz].
    #[arg(long, default_value = "100:2000:100")]
    pub speeds: String,
    /// Film mesh per lobe of the linear prediction when the study sets none (default 8x2).
    #[arg(long)]
    pub linear_mesh: Option<String>,
}

pub fn execute(a: Args) -> Result<ExitCode, Error> {
    let Args {
        study,
        out,
        jobs,
        shard,
        quiet,
        overwrite,
        list,
        predict_first,
        checkpoint_every,
        linear,
        speeds,
        linear_mesh,
    } = a;
    if checkpoint_every.is_some_and(|dt| !(dt.is_finite() && dt > 0.0)) {
        Err(Error::Flag(
            "--checkpoint-every must be a finite number of seconds > 0".into(),
        ))
    } else if linear
        && (jobs.is_some()
            || shard.is_some()
            || list
            || checkpoint_every.is_some()
            || predict_first)
    {
        Err(Error::Flag("--linear predicts the whole study in one process: it takes no --jobs, --shard, --list, --checkpoint-every or --predict-first".into()))
    } else if linear {
        linear_sweep_command(&study, out, &speeds, linear_mesh.as_deref(), quiet)
    } else {
        let predict = predict_first.then_some((speeds.as_str(), linear_mesh.as_deref()));
        let flags = SweepFlags {
            out,
            jobs,
            shard: shard.as_deref(),
            quiet,
            overwrite,
            list,
            checkpoint_every_s: checkpoint_every,
            predict,
        };
        sweep_command(&study, flags)
    }
}

fn linear_sweep_command(
    study_path: &Path,
    out: Option<PathBuf>,
    speeds: &str,
    mesh: Option<&str>,
    quiet: bool,
) -> Result<ExitCode, Error> {
    let study = master::sweep::Study::load(study_path).input()?;
    let speeds = master::stability::parse_speeds(speeds).flag()?;
    let mesh = match mesh {
        None => master::sweep::linear::DEFAULT_MESH,
        Some(m) => master::runup::parse_mesh(m, "--linear-mesh").flag()?,
    };
    let out = out.unwrap_or_else(|| PathBuf::from("runs").join(format!("sweep-{}", study.name)));
    master::run::folder::check_sweep_out(&out)?;
    let (preds, maps) =
        master::sweep::linear::predict(&study, &speeds, mesh, &out, quiet, None).run()?;
    eprintln!(
        "linear prediction: {} points -> {}, {}",
        preds.len(),
        out.join("study_linear.csv").display(),
        maps.first()
            .map_or(String::new(), |m| m.display().to_string())
    );
    Ok(ExitCode::SUCCESS)
}

/// The flags of `airring sweep` (run-up mode).
struct SweepFlags<'a> {
    out: Option<PathBuf>,
    jobs: Option<usize>,
    shard: Option<&'a str>,
    quiet: bool,
    overwrite: bool,
    list: bool,
    checkpoint_every_s: Option<f64>,
    /// --predict-first: (speed grid, film mesh) of the linear prediction.
    predict: Option<(&'a str, Option<&'a str>)>,
}

fn sweep_command(study_path: &Path, f: SweepFlags) -> Result<ExitCode, Error> {
    use master::sweep;
    let SweepFlags {
        out,
        jobs,
        shard,
        quiet,
        overwrite,
        list,
        checkpoint_every_s,
        predict,
    } = f;
    let text = std::fs::read_to_string(study_path)
        .map_err(|e| Error::Input(format!("{}: {e}", study_path.display())))?;
    let mut study = sweep::Study::parse(&text, study_path).input()?;
    if list {
        let shard = shard.map(sweep::parse_shard).transpose().flag()?;
        print!("{}", sweep::plan_json_lines(&study, shard));
        return Ok(ExitCode::SUCCESS);
    }
    let jobs = jobs.unwrap_or_else(sweep::default_jobs);
    let out = out.unwrap_or_else(|| PathBuf::from("runs").join(format!("sweep-{}", study.name)));
    master::run::folder::check_sweep_out(&out)?;
    if let Some((speeds, mesh)) = predict {
        let speeds = master::stability::parse_speeds(speeds).flag()?;
        let mesh = match mesh {
            None => master::sweep::linear::DEFAULT_MESH,
            Some(m) => master::runup::parse_mesh(m, "--linear-mesh").flag()?,
        };
        let cache = master::linear_cache::LinearCache::open(&sweep::linear_cache_dir(&out))
            .map_err(|e| eprintln!("warning: the prediction's analyses are not kept: {e}"))
            .ok();
        let (preds, _) =
            master::sweep::linear::predict(&study, &speeds, mesh, &out, quiet, cache.as_ref())
                .run()?;
        master::sweep::linear::longest_first(&mut study, &preds);
    }
    let opts = sweep::SweepOptions {
        out,
        jobs,
        // Two film threads per run-up only while there is a core for each.
        serial_films: 2 * jobs > sweep::cores(),
        shard: shard.map(sweep::parse_shard).transpose().flag()?,
        exe: std::env::current_exe().run()?,
        quiet,
        overwrite,
        stop: stop_flag(),
        checkpoint_every_s,
    };
    let r = sweep::sweep(&study, &text, &opts).run()?;
    let interrupted = if r.interrupted.is_empty() {
        String::new()
    } else {
        format!(", {} interrupted", r.interrupted.len())
    };
    eprintln!(
        "sweep: {} runs ({} skipped as completed, {} run, {} failed{interrupted}) in {:.0} s wall \
         -> {}",
        r.total,
        r.skipped,
        r.ran,
        r.failed.len(),
        r.wall_time_s,
        r.table.display()
    );
    Ok(
        if r.failed.is_empty() && r.interrupted.is_empty() && !opts.stop.load(Ordering::Relaxed) {
            ExitCode::SUCCESS
        } else {
            ExitCode::FAILURE
        },
    )
}
