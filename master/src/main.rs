//! `airring`: the AirRing co-simulation master (command line).

use clap::{Parser, Subcommand};
use master::run::{run, RunOptions};
use std::path::{Path, PathBuf};
use std::process::ExitCode;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;

#[derive(Parser)]
#[command(
    name = "airring",
    version,
    about = "Rotors in air ring bearings: FMI 2.0 co-simulation master"
)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// A run-up of the paper's rotor in two air ring bearings.
    #[command(allow_negative_numbers = true)]
    Runup {
        #[command(flatten)]
        args: Box<master::runup_cli::RunupArgs>,
        #[command(flatten)]
        common: Common,
    },
    /// Any system described by a TOML system file.
    #[command(allow_negative_numbers = true)]
    Run {
        /// The system file (TOML; its format: docs/reference/system-file.md; a run folder's
        /// system.toml is one).
        system: PathBuf,
        #[command(flatten)]
        common: Common,
        /// Clearance C [um] for the run-up analysis (eccentricities, plots) of a system whose air
        /// films are not named film_C and film_T (those give their own; the flag is refused there).
        #[arg(long)]
        clearance: Option<f64>,
        /// Step height dH [um] for the orbit plots, with --clearance (default 40).
        #[arg(long, requires = "clearance")]
        dh: Option<f64>,
    },
    /// Continue an interrupted run from its last checkpoint.
    Resume {
        /// The run folder (an interrupted run's, with its checkpoint).
        dir: PathBuf,
        /// Save a checkpoint every this many simulated seconds from here on [s].
        #[arg(long)]
        checkpoint_every: Option<f64>,
        /// Also write timeseries.parquet at the end (automatic if the run wrote one before).
        #[arg(long)]
        parquet: bool,
    },
    /// A parameter study of run-ups from a study file (TOML), resumable; CSV table and bifurcation maps.
    Sweep {
        study: PathBuf,
        /// Output folder (default: `runs/sweep-<study name>`).
        #[arg(long)]
        out: Option<PathBuf>,
        /// Run-ups at a time, 1 or more (default: one per core, each stepping its films one after
        /// the other).
        #[arg(long, value_parser = jobs_at_least_one)]
        jobs: Option<usize>,
        /// Run only every n-th grid point: k/n runs the points with index i where i mod n = k - 1.
        #[arg(long)]
        shard: Option<String>,
        /// No progress lines (each finished run and the closing summary are still printed).
        #[arg(long)]
        quiet: bool,
        /// Run again the completed runs in the output folder that were made with other flags
        /// (an edited study file); without it such a folder is refused, naming them.
        #[arg(long)]
        overwrite: bool,
        /// Print the run-ups (name, index, flags, `airring` arguments) as JSON lines and exit.
        #[arg(long)]
        list: bool,
        /// Predict the map with the linear stability analysis first (study_linear.csv,
        /// bifurcation_map_linear.*; seconds, against the run-ups' minutes), then run the
        /// run-ups, those predicted to take longest (unstable, earliest onset) first.
        #[arg(long)]
        predict_first: bool,
        /// Every run-up writes a checkpoint every this many seconds of simulated time, so a killed
        /// one loses at most that much (interrupted ones checkpoint when they stop in any case,
        /// and the next sweep resumes them).
        #[arg(long)]
        checkpoint_every: Option<f64>,
        /// Predict the map with the linear stability analysis instead of running the run-ups
        /// (threshold speed and visible onset per point; study_linear.csv, bifurcation_map_linear.*).
        #[arg(long)]
        linear: bool,
        /// Speed grid of the linear prediction, from:to:step [Hz].
        #[arg(long, default_value = "100:2000:100")]
        speeds: String,
        /// Film mesh per lobe of the linear prediction when the study sets none (default 8x2).
        #[arg(long)]
        linear_mesh: Option<String>,
    },
    /// Merge the run folders of several sweep outputs (shards) into one table and map.
    SweepMerge {
        /// Sweep output folders (each with its runs/).
        #[arg(required = true)]
        dirs: Vec<PathBuf>,
        /// Output folder (default: the first DIR).
        #[arg(long)]
        out: Option<PathBuf>,
    },
    /// How a sweep's classes depend on the classifier's bounds: every completed run classified
    /// again with each bound moved down and up (sensitivity.csv, and a summary).
    #[command(allow_negative_numbers = true)]
    SweepSensitivity {
        /// A sweep's output folder.
        dir: PathBuf,
        /// Relative move of each bound.
        #[arg(long, default_value_t = 0.2)]
        delta: f64,
    },
    /// Every cell of a study classified from its whirl orbits at constant speed (just past the
    /// linear threshold and at the top speed) instead of a run-up; resumable
    /// (orbit_classes.csv, orbit_classes.json, one folder per cell).
    #[command(allow_negative_numbers = true)]
    SweepOrbits {
        /// Study file (TOML), as for `airring sweep`.
        study: PathBuf,
        /// Output folder.
        #[arg(long)]
        out: PathBuf,
        /// Constant-speed simulation per speed before its whirl counts as settled [s].
        #[arg(long, default_value_t = 1.0)]
        settle: f64,
        /// The first speed lies this fraction above the linear threshold.
        #[arg(long, default_value_t = 0.1)]
        above: f64,
        /// Cells at once, 1 or more (default: one per core; each steps its films serially when > 1).
        #[arg(long, value_parser = jobs_at_least_one)]
        jobs: Option<usize>,
        /// A run-up sweep's study.csv to compare the classes with, cell by cell.
        #[arg(long)]
        compare: Option<PathBuf>,
        /// Folder with rotor.fmu and airfilm.fmu (default: next to the executable, then
        /// target/fmu).
        #[arg(long)]
        fmu_dir: Option<PathBuf>,
    },
    /// Modal analysis of the rotor with linear film springs (paper Section 2.3).
    #[command(allow_negative_numbers = true)]
    Modal {
        /// Rotor speed [Hz] (several: Campbell data).
        #[arg(long, num_args = 1.., default_values_t = vec![1000.0])]
        speed: Vec<f64>,
        /// Ring mount stiffness [N/mm].
        #[arg(long, default_value_t = 500.0)]
        c: f64,
        /// Ring mount damping [N s/m].
        #[arg(long, default_value_t = 0.0)]
        d: f64,
        /// Isotropic air-film stiffness [N/mm].
        #[arg(long, default_value_t = 2000.0)]
        film_stiffness: f64,
        /// Ring mass [g].
        #[arg(long, default_value_t = 50.0)]
        m_r: f64,
        /// Output folder for modal.json and the Campbell diagram (campbell.svg/.png).
        #[arg(long)]
        out: Option<PathBuf>,
    },
    /// Linear stability: static equilibrium, Campbell table with damping, threshold speed.
    #[command(allow_negative_numbers = true)]
    Stability(master::stability::cli::StabilityArgs),
    /// Classify a finished run folder again from its timeseries.csv (prints JSON: class, onset,
    /// first bearing, maximum eccentricities, criteria).
    #[command(allow_negative_numbers = true)]
    Classify {
        /// A run-up's folder (its timeseries.csv and system.toml).
        dir: PathBuf,
        /// Clearance C [um] of both bearings, for run folders whose system.toml names no air
        /// films (a system of one's own); otherwise each film's, from that file, and a
        /// different value is refused.
        #[arg(long)]
        clearance: Option<f64>,
    },
    /// The air-film library alone along a journal orbit from a CSV file, fed as FMPy's simulate_fmu
    /// feeds airfilm.fmu (cross-check; see docs/fmu-guide.md).
    #[command(allow_negative_numbers = true)]
    Orbit(master::orbit::OrbitArgs),
    /// Periodic whirl orbits at constant speeds (shooting on the co-simulation), their Floquet
    /// multipliers, and the branch continued in speed to its Hopf point (orbits.json).
    #[command(allow_negative_numbers = true)]
    Orbits {
        #[command(flatten)]
        args: master::orbits::cli::OrbitsArgs,
        /// Folder with rotor.fmu and airfilm.fmu (default: next to the executable, then
        /// target/fmu).
        #[arg(long)]
        fmu_dir: Option<PathBuf>,
    },
    /// Write a system file as an SSP 1.0 archive (SystemStructure.ssd + the FMUs) for other tools.
    ExportSsp(master::export_ssp::ExportSspArgs),
}

#[derive(clap::Args, Clone)]
struct Common {
    /// Output folder (default: `runs/<name>-<timestamp>`).
    #[arg(long)]
    out: Option<PathBuf>,
    /// Save a checkpoint every this many simulated seconds.
    #[arg(long)]
    checkpoint_every: Option<f64>,
    /// No progress display.
    #[arg(long)]
    quiet: bool,
    /// Also write the time series as timeseries.parquet when the run ends (the CSV is written as
    /// the run goes in any case, so a killed run keeps its data).
    #[arg(long)]
    parquet: bool,
    /// Replace the run in the output folder, if it holds one (without it, such a folder is
    /// refused). The old run stays untouched until the new one has started.
    #[arg(long)]
    overwrite: bool,
}

fn default_out(name: &str) -> PathBuf {
    let secs = std::time::SystemTime::now()
        .duration_since(std::time::UNIX_EPOCH)
        .map(|d| d.as_secs())
        .unwrap_or(0);
    PathBuf::from("runs").join(format!("{name}-{secs}"))
}

fn fmu_dir(given: Option<PathBuf>) -> Result<PathBuf, String> {
    let candidates: Vec<PathBuf> = match given {
        Some(d) => vec![d],
        None => {
            let mut c = vec![PathBuf::from("target/fmu")];
            if let Ok(exe) = std::env::current_exe() {
                if let Some(p) = exe.parent().and_then(Path::parent) {
                    c.push(p.join("fmu"));
                }
            }
            c
        }
    };
    for d in &candidates {
        if d.join("rotor.fmu").exists() && d.join("airfilm.fmu").exists() {
            return d.canonicalize().map_err(|e| e.to_string());
        }
    }
    Err(format!("rotor.fmu and airfilm.fmu not found in {candidates:?}: build them with `cargo xtask fmus` or pass --fmu-dir"))
}

/// The paper's three-lobe geometry with the given clearance and step height [um].
fn lobes(clearance_um: f64, dh_um: f64) -> bearing::Bore {
    bearing::Bore {
        c_m: clearance_um / 1e6,
        dh_m: dh_um / 1e6,
        ..bearing::Bore::paper()
    }
}

fn stop_flag() -> Arc<AtomicBool> {
    let flag = Arc::new(AtomicBool::new(false));
    let f = flag.clone();
    let _ = ctrlc::set_handler(move || {
        if f.swap(true, Ordering::Relaxed) {
            eprintln!("\nsecond stop signal: exiting at once");
            std::process::exit(130);
        }
        // Ctrl-C, and (ctrlc's `termination` feature) SIGTERM and SIGHUP: a batch system's time
        // limit stops a run the same way, leaving a checkpoint to resume from.
        eprintln!(
            "\nstop signal: stopping at the next macro step (a run that has not reached its stop \
             time writes its checkpoint and summary)"
        );
    });
    flag
}

/// A new run into `opts.out_dir`; a folder this call created is removed again if the run could
/// not start (an existing one is left as it was).
fn new_run(system: &Path, opts: &RunOptions) -> Result<master::run::RunReport, String> {
    let created = !opts.out_dir.exists();
    let r = run(system, opts, false);
    if r.is_err() && created {
        // Only if empty: remove_dir refuses a folder with content.
        let _ = std::fs::remove_dir(&opts.out_dir);
    }
    r
}

fn finish(report: master::run::RunReport, out: &Path) -> ExitCode {
    let s = master::summary::RunSummary::read(out).unwrap_or_default();
    eprintln!(
        "{}: {} macro steps to t = {:.4} s in {:.1} s wall; classification: {}, onset: {} s",
        out.display(),
        report.macro_steps,
        report.t_end_s,
        report.wall_time_s,
        s.classification
            .map_or("null".to_string(), |c| format!("\"{c}\"")),
        s.onset_time_s.map_or("null".to_string(), |t| t.to_string())
    );
    match report.error {
        Some(e) => {
            eprintln!("error: {e}");
            ExitCode::FAILURE
        }
        None if report.interrupted => ExitCode::from(130),
        None => ExitCode::SUCCESS,
    }
}

/// `run --clearance / --dh` describe the bearings of a system without air films `film_C` and
/// `film_T`: where it has them, the analysis takes their own bores (as `classify` does), and a
/// flag that differs would put one clearance in the summary and another in the films.
fn check_no_films_named(system: &Path) -> Result<(), String> {
    match master::run_folder::bores_of_system(system)? {
        Some([c, t]) => Err(format!(
            "--clearance / --dh: the system's films film_C and film_T name their own bores \
             (C = {} um and {} um, dH = {} um and {} um), which the run's analysis takes; \
             --clearance and --dh are for systems without those films",
            master::runup::fmt_number(c.c_m * 1e6),
            master::runup::fmt_number(t.c_m * 1e6),
            master::runup::fmt_number(c.dh_m * 1e6),
            master::runup::fmt_number(t.dh_m * 1e6)
        )),
        None => Ok(()),
    }
}

fn classify_command(dir: &Path, clearance_um: Option<f64>) -> Result<ExitCode, String> {
    if !dir.is_dir() {
        return Err(format!(
            "{}: no such folder (classify takes a run-up's folder, e.g. runs/path1)",
            dir.display()
        ));
    }
    // Each bearing's clearance: the flag, else the run folder's own system file (never a default).
    let c_m = match clearance_um {
        Some(c) => {
            master::runup::check_clearance_um(c)?;
            // Where the run's films name their clearances, the film eccentricities are measured
            // against those: another clearance would classify the amplitudes against one value
            // and the eccentricities against another.
            if let Some(bores) = master::run_folder::bores_of_run(dir)? {
                if bores.iter().any(|b| (b.c_m * 1e6 - c).abs() > 1e-9 * c) {
                    return Err(format!(
                        "--clearance = {} um: the run's films ran with C = {} um and {} um \
                         (its system.toml); --clearance is for run folders whose system file \
                         names no air films",
                        master::runup::fmt_number(c),
                        master::runup::fmt_number(bores[0].c_m * 1e6),
                        master::runup::fmt_number(bores[1].c_m * 1e6)
                    ));
                }
            }
            [c / 1e6; 2]
        }
        None => match master::run_folder::bores_of_run(dir)? {
            Some([c, t]) => [c.c_m, t.c_m],
            None => {
                return Err(format!(
                    "{}: its system.toml has no air films film_C and film_T to take the \
                     clearance from; give it with --clearance UM",
                    dir.display()
                ))
            }
        },
    };
    let series = master::analysis::load_run(dir, c_m)?;
    let cl = master::analysis::classify(&series);
    // A run that did not complete (interrupted, failed, or killed while its summary still said
    // "running") is classified on what it simulated, as its own summary says: said here too.
    let status = master::summary::RunSummary::read(dir).map(|s| s.status);
    let note = match status {
        Some(master::summary::RunStatus::Completed) => None,
        other => Some(format!(
            "classified on the part of the run-up that was simulated (to t = {} s; the run {})",
            series.t_s.last().copied().unwrap_or(0.0),
            match other {
                Some(master::summary::RunStatus::Running) => "was killed before it ended",
                Some(master::summary::RunStatus::Interrupted) => "was interrupted",
                Some(_) => "failed",
                None => "has no summary.json",
            }
        )),
    };
    let out = serde_json::json!({
        "run": dir.display().to_string(),
        "clearance_um": { "C": c_m[0] * 1e6, "T": c_m[1] * 1e6 },
        "classification": cl.class.as_str(),
        "classification_note": note,
        "onset_time_s": cl.onset_time_s,
        "onset_speed_hz": cl.onset_speed_hz,
        "first_bearing": cl.first_bearing,
        "max_eps_C": cl.max_eps_c,
        "max_eps_T": cl.max_eps_t,
        "criteria": cl.criteria,
        "borderline": cl.borderline,
        "margins": cl.margins,
    });
    println!(
        "{}",
        serde_json::to_string_pretty(&out).map_err(|e| e.to_string())?
    );
    Ok(ExitCode::SUCCESS)
}

fn linear_sweep_command(
    study_path: &Path,
    out: Option<PathBuf>,
    speeds: &str,
    mesh: Option<&str>,
    quiet: bool,
) -> Result<ExitCode, String> {
    let study = master::sweep::Study::load(study_path)?;
    let speeds = master::stability::parse_speeds(speeds)?;
    let mesh = match mesh {
        None => master::sweep_linear::DEFAULT_MESH,
        Some(m) => master::runup::parse_mesh(m, "--linear-mesh")?,
    };
    let out = out.unwrap_or_else(|| PathBuf::from("runs").join(format!("sweep-{}", study.name)));
    master::out_folder::check_sweep_out(&out)?;
    let (preds, maps) = master::sweep_linear::predict(&study, &speeds, mesh, &out, quiet, None)?;
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

fn sweep_command(study_path: &Path, f: SweepFlags) -> Result<ExitCode, String> {
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
        .map_err(|e| format!("{}: {e}", study_path.display()))?;
    let mut study = sweep::Study::parse(&text, study_path)?;
    if list {
        let shard = shard.map(sweep::parse_shard).transpose()?;
        print!("{}", sweep::plan_json_lines(&study, shard));
        return Ok(ExitCode::SUCCESS);
    }
    let jobs = jobs.unwrap_or_else(sweep::default_jobs);
    let out = out.unwrap_or_else(|| PathBuf::from("runs").join(format!("sweep-{}", study.name)));
    master::out_folder::check_sweep_out(&out)?;
    if let Some((speeds, mesh)) = predict {
        let speeds = master::stability::parse_speeds(speeds)?;
        let mesh = match mesh {
            None => master::sweep_linear::DEFAULT_MESH,
            Some(m) => master::runup::parse_mesh(m, "--linear-mesh")?,
        };
        let cache = master::linear_cache::LinearCache::open(&sweep::linear_cache_dir(&out))
            .map_err(|e| eprintln!("warning: the prediction's analyses are not kept: {e}"))
            .ok();
        let (preds, _) =
            master::sweep_linear::predict(&study, &speeds, mesh, &out, quiet, cache.as_ref())?;
        master::sweep_linear::longest_first(&mut study, &preds);
    }
    let opts = sweep::SweepOptions {
        out,
        jobs,
        // Two film threads per run-up only while there is a core for each.
        serial_films: 2 * jobs > sweep::cores(),
        shard: shard.map(sweep::parse_shard).transpose()?,
        exe: std::env::current_exe().map_err(|e| e.to_string())?,
        quiet,
        overwrite,
        stop: stop_flag(),
        checkpoint_every_s,
    };
    let r = sweep::sweep(&study, &text, &opts)?;
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

/// Commands whose product is their standard output end quietly when the reader goes away
/// (`airring classify DIR | head -c1`), as Unix filters do, instead of panicking on EPIPE: the
/// default SIGPIPE action. Run-ups keep Rust's ignored SIGPIPE: they write files, not stdout,
/// and must reach their checkpoint and summary even if the terminal's pipe closes.
fn quiet_on_closed_stdout(command: &Command) {
    let filter = match command {
        Command::Classify { .. }
        | Command::Modal { .. }
        | Command::Stability(_)
        | Command::SweepSensitivity { .. } => true,
        Command::Sweep { list, .. } => *list,
        _ => false,
    };
    if filter {
        // SAFETY: called once at start-up, before any thread exists; SIG_DFL is a valid action.
        unsafe {
            libc::signal(libc::SIGPIPE, libc::SIG_DFL);
        }
    }
}

/// `--jobs`: a whole number of run-ups (cells) at a time, 1 or more (0 used to be taken and run
/// one at a time all the same).
fn jobs_at_least_one(text: &str) -> Result<usize, String> {
    match text.trim().parse::<usize>() {
        Ok(0) => Err("0 run-ups at a time would run none: give 1 or more".into()),
        Ok(n) => Ok(n),
        Err(_) => Err(format!(
            "'{text}' is not a whole number of run-ups (1 or more)"
        )),
    }
}

/// `--checkpoint-every`, checked with its name before a run starts.
fn check_checkpoint_every(every_s: Option<f64>) -> Result<(), String> {
    match every_s {
        Some(dt) if !(dt.is_finite() && dt > 0.0) => Err(format!(
            "--checkpoint-every = {dt} s must be a finite number > 0 (simulated seconds)"
        )),
        _ => Ok(()),
    }
}

fn main() -> ExitCode {
    let cli = Cli::parse();
    quiet_on_closed_stdout(&cli.command);
    let result: Result<ExitCode, String> = (|| match cli.command {
        Command::Runup { args, common } => {
            let mut s = master::runup_cli::settings(&args)?;
            s.validate_runup()?;
            // Every flag and the output folder checked before the calm plan's analysis runs.
            check_checkpoint_every(common.checkpoint_every)?;
            let out = common.out.clone().unwrap_or_else(|| default_out(&s.preset));
            master::out_folder::check_new_run(&out, common.overwrite)?;
            // The FMUs are found before the calm plan's analysis runs (a wrong --fmu-dir was
            // reported only after it).
            let dir = fmu_dir(args.fmu_dir.clone())?;
            if let (Some(calm_us), Some(_)) = (s.calm_macro_step_us, s.calm_factor()) {
                // A cache that cannot be opened only makes the plan slower.
                let cache = args.linear_cache.as_deref().and_then(|d| {
                    master::linear_cache::LinearCache::open(d)
                        .map_err(|e| eprintln!("warning: --linear-cache not used: {e}"))
                        .ok()
                });
                let plan = master::calm_steps::plan(&s, cache.as_ref());
                s.calm_windows_s = plan.windows_s.clone();
                eprintln!("{}", master::calm_steps::describe(&plan, calm_us));
            }
            // TOML is UTF-8: a folder whose name is not cannot be written into a system file.
            let dir_text = dir.to_str().ok_or_else(|| {
                format!(
                    "--fmu-dir {}: the folder's path is not valid UTF-8, which a system file cannot \
                     hold; link or copy the FMUs to a folder with a UTF-8 name",
                    dir.display()
                )
            })?;
            // The system file goes into the run folder only once the run has started.
            let staged = master::out_folder::StagedSystem::new(&s.system_toml(dir_text))?;
            eprintln!(
                "run-up '{}': {}, {}; {}; macro step {} us -> {}",
                s.preset,
                master::runup::describe_bearings(&s)?,
                s.describe_speed(),
                master::runup::describe_film_mesh(&s)?,
                s.macro_step_us,
                out.display()
            );
            let opts = RunOptions {
                out_dir: out.clone(),
                checkpoint_every_s: common.checkpoint_every,
                stop: stop_flag(),
                halt_at_s: None,
                quiet: common.quiet,
                extra: serde_json::to_value(&s).unwrap_or_default(),
                bores: None,
                parquet: common.parquet,
            };
            let report = new_run(&staged.path, &opts).map_err(|e| staged.strip_path(e))?;
            Ok(finish(report, &out))
        }
        Command::Run {
            system,
            common,
            clearance,
            dh,
        } => {
            check_checkpoint_every(common.checkpoint_every)?;
            // The clearance scales the analysis of the whole run: checked before it starts.
            if let Some(c) = clearance {
                master::runup::check_clearance_um(c)?;
            }
            if let Some(dh) = dh {
                master::runup::check_dh_um(dh)?;
            }
            let sys = cosim::System::load(&system).map_err(|e| e.to_string())?;
            cosim::setup::check_output_interval_whole(&sys).map_err(|e| e.to_string())?;
            if clearance.is_some() || dh.is_some() {
                check_no_films_named(&system)?;
            }
            let out = common.out.clone().unwrap_or_else(|| {
                default_out(system.file_stem().and_then(|s| s.to_str()).unwrap_or("run"))
            });
            master::out_folder::check_new_run(&out, common.overwrite)?;
            let opts = RunOptions {
                out_dir: out.clone(),
                checkpoint_every_s: common.checkpoint_every,
                stop: stop_flag(),
                halt_at_s: None,
                quiet: common.quiet,
                extra: serde_json::json!({ "system": system }),
                bores: clearance.map(|c| {
                    let b = lobes(c, dh.unwrap_or(40.0));
                    [b.clone(), b]
                }),
                parquet: common.parquet,
            };
            let report = new_run(&system, &opts)?;
            Ok(finish(report, &out))
        }
        Command::Resume {
            dir,
            checkpoint_every,
            parquet,
        } => {
            check_checkpoint_every(checkpoint_every)?;
            if !dir.join("system.toml").is_file() {
                return Err(format!(
                    "{}: no run to resume (no system.toml): the run never started here, or this \
                     is not a run folder",
                    dir.display()
                ));
            }
            master::out_folder::check_not_in_progress(&dir)?;
            let old = master::summary::RunSummary::read(&dir).unwrap_or_default();
            if old.status == master::summary::RunStatus::Completed {
                return Err(format!(
                    "{}: the run completed (summary.json): nothing to resume",
                    dir.display()
                ));
            }
            if !dir.join("checkpoint").is_dir() {
                let why = old
                    .error
                    .as_deref()
                    .map_or(String::new(), |e| format!(": {e}"));
                let what = match old.status {
                    // Its summary still says "running": killed before it could say how it ended.
                    master::summary::RunStatus::Running => "was killed before it ended, and \
                        --checkpoint-every was not given"
                        .to_string(),
                    master::summary::RunStatus::Interrupted => format!("was interrupted{why}"),
                    other => format!("{}{why}", other.as_str()),
                };
                return Err(format!(
                    "{}: no checkpoint to resume from (the run {what}); run it again with \
                     --overwrite",
                    dir.display(),
                ));
            }
            let opts = RunOptions {
                out_dir: dir.clone(),
                checkpoint_every_s: checkpoint_every,
                stop: stop_flag(),
                halt_at_s: None,
                quiet: false,
                extra: old.settings,
                // The bores come from the run folder's own system file.
                bores: None,
                // A run that wrote Parquet goes on writing it.
                parquet: parquet || dir.join("timeseries.parquet").exists(),
            };
            let report = run(&dir.join("system.toml"), &opts, true)?;
            Ok(finish(report, &dir))
        }
        Command::Sweep {
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
        } => {
            if checkpoint_every.is_some_and(|dt| !(dt.is_finite() && dt > 0.0)) {
                Err("--checkpoint-every must be a finite number of seconds > 0".into())
            } else if linear
                && (jobs.is_some()
                    || shard.is_some()
                    || list
                    || checkpoint_every.is_some()
                    || predict_first)
            {
                Err("--linear predicts the whole study in one process: it takes no --jobs, --shard, --list, --checkpoint-every or --predict-first".into())
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
        Command::SweepMerge { dirs, out } => {
            let out = out.unwrap_or_else(|| dirs[0].clone());
            master::out_folder::check_sweep_out(&out)?;
            let (table, maps, n) = master::sweep::merge(&dirs, &out)?;
            eprintln!("{n} runs -> {}, {}", table.display(), maps[0].display());
            Ok(ExitCode::SUCCESS)
        }
        Command::SweepSensitivity { dir, delta } => {
            let (runs, left_out) = master::sweep::sensitivity::sensitivity(&dir, delta)?;
            let (path, text) = master::sweep::sensitivity::write(&dir, delta, &runs, &left_out)?;
            print!("{text}");
            eprintln!("-> {}", path.display());
            Ok(ExitCode::SUCCESS)
        }
        Command::SweepOrbits {
            study,
            out,
            settle,
            above,
            jobs,
            compare,
            fmu_dir: dir,
        } => {
            let study = master::sweep::Study::load(&study)?;
            master::out_folder::check_sweep_out(&out)?;
            let opts = master::orbits::study::SweepOrbitsOptions {
                out,
                settle_s: settle,
                above,
                jobs: jobs.unwrap_or_else(master::sweep::default_jobs),
                compare,
                fmu_dir: fmu_dir(dir)?,
            };
            let cells =
                master::orbits::study::sweep_orbits(&study, &opts, &|line| eprintln!("{line}"))?;
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
        Command::Modal {
            speed,
            c,
            d,
            film_stiffness,
            m_r,
            out,
        } => master::modal::modal(&speed, c, d, film_stiffness, m_r, out.as_deref())
            .map(|_| ExitCode::SUCCESS),
        Command::Stability(args) => {
            master::stability::cli::run_cli(&args).map(|_| ExitCode::SUCCESS)
        }
        Command::Classify { dir, clearance } => classify_command(&dir, clearance),
        Command::Orbit(args) => master::orbit::run_cli(&args).map(|_| ExitCode::SUCCESS),
        Command::ExportSsp(args) => master::export_ssp::run_cli(&args).map(|_| ExitCode::SUCCESS),
        Command::Orbits { args, fmu_dir: dir } => fmu_dir(dir)
            .and_then(|d| master::orbits::cli::run_cli(&args, d).map(|_| ExitCode::SUCCESS)),
    })();
    match result {
        Ok(code) => code,
        Err(e) => {
            eprintln!("airring: {e}");
            ExitCode::FAILURE
        }
    }
}
