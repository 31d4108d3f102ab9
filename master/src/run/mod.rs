//! A run of `airring`: the generic run loop of the `cosim` library with this application's
//! observers attached (the CSV file, the progress line, the in-memory series for Parquet and the
//! run-up analysis), and `summary.json` with the run-up's classification and plots at the end.
//! [`folder`]: who may write into a run folder; [`read_back`]: what a run folder's system file
//! says of its bearings.

pub mod folder;
mod halt;
pub mod read_back;

pub use halt::Halt;
use halt::LimitWatch;

use crate::analysis::{classify, RunSeries};
use crate::plot::plot_runup;
use crate::summary::{ClearancesUm, RunSummary};
use bearing::Bore;
use cosim::algorithm::Event;
use cosim::observer::{Observer, ObserverError, RunStart};
use cosim::timeseries::{self, CsvObserver};
use cosim::{CoSim, Recorded, RunConfig};
use fmi_core::Status;
use fmi_core::{LogHandler, LogRecord};
use std::io::IsTerminal;
use std::path::{Path, PathBuf};
use std::sync::atomic::AtomicBool;
use std::sync::Arc;
use std::time::{Duration, Instant};

pub use cosim::RunReport;

pub struct RunOptions {
    pub out_dir: PathBuf,
    /// Simulated time between checkpoints.
    pub checkpoint_every_s: Option<f64>,
    /// Set by Ctrl-C (or a test) to stop cleanly at the next macro point.
    pub stop: Arc<AtomicBool>,
    /// Stop (as if interrupted) once this simulated time is reached (tests of resume).
    pub halt_at_s: Option<f64>,
    pub quiet: bool,
    /// Extra facts for summary.json (e.g. the run-up settings and the clearance for eps).
    pub extra: serde_json::Value,
    /// The bearings' bores [C, T] for the run-up analysis (C for the eccentricities, lobes for the
    /// orbit plots) when the system's air films are not the instances `film_C` and `film_T`
    /// (`airring run --clearance`). None: read from the run folder's system file; a system
    /// without those films (or without the rotor's outputs) gets no run-up analysis.
    pub bores: Option<[Bore; 2]>,
    /// Also write `timeseries.parquet` when the run ends (the CSV is written in any case).
    pub parquet: bool,
    /// End the run once a film's minimum thickness falls below a limit or a whirl grows beyond
    /// one (`runup --halt-film`, `--halt-whirl`).
    pub halt: Option<Halt>,
    /// Figures of what was run, drawn before it (a flexible rotor to scale): (file stem, chart),
    /// saved and listed with the run-up's figures when the run ends.
    pub figures: Vec<(String, crate::plot::Chart)>,
}

/// Prints FMU messages of status warning or worse (and debug messages when asked) with the
/// instance name.
pub fn stderr_logger() -> LogHandler {
    Arc::new(|r: &LogRecord| {
        if r.status >= Status::Warning || std::env::var_os("AIRRING_LOG_DEBUG").is_some() {
            eprintln!(
                "[{}] {}{} {}: {}",
                r.instance,
                r.standard,
                r.status.name(),
                r.category,
                r.message
            );
        }
    })
}

/// The progress line on stderr (every 250 ms on a terminal, every 5 % otherwise), with the
/// rotor speed when a `*.omega` output is recorded; algorithm events as lines of their own.
struct Progress {
    tty: bool,
    quiet: bool,
    last: Instant,
    last_fraction_printed: f64,
    start: Instant,
    wall_before: f64,
    omega_column: Option<usize>,
    omega_rad_s: Option<f64>,
    stop_time_s: f64,
}

impl Progress {
    fn new(quiet: bool) -> Self {
        Progress {
            tty: std::io::stderr().is_terminal(),
            quiet,
            last: Instant::now(),
            last_fraction_printed: 0.0,
            start: Instant::now(),
            wall_before: 0.0,
            omega_column: None,
            omega_rad_s: None,
            stop_time_s: 0.0,
        }
    }

    fn show(&mut self, t: f64, force: bool) {
        if self.quiet {
            return;
        }
        let stop = self.stop_time_s;
        let frac = (t / stop).clamp(0.0, 1.0);
        let due = if self.tty {
            self.last.elapsed() >= Duration::from_millis(250)
        } else {
            frac - self.last_fraction_printed >= 0.05
        };
        if !(due || force) {
            return;
        }
        self.last = Instant::now();
        self.last_fraction_printed = frac;
        let elapsed = self.start.elapsed().as_secs_f64() + self.wall_before;
        let eta = if frac > 1e-6 {
            elapsed * (1.0 - frac) / frac
        } else {
            f64::NAN
        };
        let speed = self
            .omega_rad_s
            .map(|w| format!(" | {:7.1} Hz", w / std::f64::consts::TAU))
            .unwrap_or_default();
        let line = format!(
            "t = {:.4} s / {:.3} s ({:5.1} %){speed} | wall {:.0} s, ETA {:.0} s",
            t,
            stop,
            100.0 * frac,
            elapsed,
            eta
        );
        if self.tty {
            eprint!("\r{line}   ");
            if force {
                eprintln!();
            }
        } else {
            eprintln!("{line}");
        }
    }
}

impl Observer for Progress {
    fn started(&mut self, run: &RunStart<'_>) -> Result<(), ObserverError> {
        self.stop_time_s = run.stop_time_s;
        self.omega_column = run.columns.iter().position(|r| r.name.ends_with(".omega"));
        if let Some(m) = run.resumed_from {
            self.wall_before = m.wall_before_s;
        }
        self.start = Instant::now();
        Ok(())
    }

    fn sample(&mut self, _t_s: f64, values: &[f64]) -> Result<(), ObserverError> {
        self.omega_rad_s = self.omega_column.map(|k| values[k]);
        Ok(())
    }

    fn macro_point(&mut self, cosim: &CoSim, _stop_time_s: f64) {
        self.show(cosim.time_s(), false);
    }

    fn event(&mut self, event: &Event) {
        // Always shown, also with --quiet: a roll-back is worth knowing about.
        match event {
            Event::RolledBack {
                subsystem,
                reason,
                t_from_s,
                t_to_s,
            } => eprintln!(
                "{subsystem}: {reason} at t = {t_from_s} s (see its log above): rolling back \
                 and retrying [{t_from_s} s, {t_to_s} s] in halves"
            ),
        }
    }

    fn finished(&mut self, cosim: &CoSim, _report: &RunReport) -> Result<(), ObserverError> {
        self.show(cosim.time_s(), true);
        Ok(())
    }
}

/// The samples kept in memory (time first in each row) for Parquet and the run-up analysis; on
/// resume it starts from the rows already in timeseries.csv (after the CSV observer cut it back).
struct Rows {
    csv_path: PathBuf,
    columns: Vec<Recorded>,
    rows: Vec<Vec<f64>>,
}

impl Observer for Rows {
    fn started(&mut self, run: &RunStart<'_>) -> Result<(), ObserverError> {
        self.columns = run.columns.to_vec();
        if run.resumed_from.is_some() {
            let (_, old) = timeseries::read(&self.csv_path)
                .map_err(|e| ObserverError::Other(e.to_string()))?;
            self.rows = old;
        }
        Ok(())
    }

    fn sample(&mut self, t_s: f64, values: &[f64]) -> Result<(), ObserverError> {
        let mut row = Vec::with_capacity(values.len() + 1);
        row.push(t_s);
        row.extend_from_slice(values);
        self.rows.push(row);
        Ok(())
    }
}

/// Set once the run loop has returned (completed, interrupted or failed): a stop signal from
/// then on stops nothing, and no checkpoint is written for it; the command's signal handler
/// says so instead of announcing one.
pub static RUN_LOOP_ENDED: std::sync::atomic::AtomicBool =
    std::sync::atomic::AtomicBool::new(false);

/// Runs `system_path` into `opts.out_dir` (copying the system file there), or resumes from the
/// checkpoint in `opts.out_dir` when `resume` is set; writes summary.json (and, for a run-up,
/// the classification and plots) however the run ended.
pub fn run(system_path: &Path, opts: &RunOptions, resume: bool) -> Result<RunReport, String> {
    // Held until the summary is written (dropped on return).
    let _lock = crate::run::folder::RunLock::acquire(&opts.out_dir)?;
    let cfg = RunConfig {
        out_dir: opts.out_dir.clone(),
        checkpoint_every_s: opts.checkpoint_every_s,
        stop: opts.stop.clone(),
        halt_at_s: opts.halt_at_s,
    };
    let csv_path = opts.out_dir.join("timeseries.csv");
    let mut guard = crate::run::folder::StartGuard {
        dir: opts.out_dir.clone(),
        settings: opts.extra.clone(),
        memory_limit_bytes: None,
    };
    let mut csv = CsvObserver::new(&csv_path);
    let mut progress = Progress::new(opts.quiet);
    let mut rows = Rows {
        csv_path,
        columns: vec![],
        rows: vec![],
    };
    if resume {
        eprintln!("resuming {}", opts.out_dir.display());
    }
    // The guard comes first: it may refuse the run before anything in the folder changes. The
    // CSV observer comes before `rows`: on resume it cuts the file back to the checkpoint before
    // `rows` reads it.
    let mut watch = opts.halt.map(LimitWatch::new);
    let mut observers: Vec<&mut dyn Observer> =
        vec![&mut guard, &mut csv, &mut rows, &mut progress];
    if let Some(w) = watch.as_mut() {
        observers.push(w);
    }
    let mut report = cosim::run(system_path, &cfg, resume, stderr_logger(), &mut observers)
        .map_err(|e| e.to_string())?;
    RUN_LOOP_ENDED.store(true, std::sync::atomic::Ordering::Relaxed);
    let recorded = &rows.columns;
    // A failed Parquet write is reported like a failed run, but summary.json is still written.
    if opts.parquet {
        let columns: Vec<(String, String)> = recorded
            .iter()
            .map(|r| (r.name.clone(), r.unit.clone()))
            .collect();
        if let Err(e) = crate::output::parquet_file::write(
            &opts.out_dir.join("timeseries.parquet"),
            &columns,
            &rows.rows,
        ) {
            report.error.get_or_insert(e);
        }
    }
    match write_summary(opts, recorded, &rows.rows, &report) {
        Err(e) => {
            // What ended the run comes first (a full disk is first met by the series; the
            // summary then fails on it too).
            return Err(match &report.error {
                Some(first) => format!("{first}; the summary could not be written either: {e}"),
                None => e,
            });
        }
        // A figure or the report page that could not be written is an output missing: the run
        // ends with an error the caller sees (exit status), though summary.json is complete.
        Ok(Some(missing)) => {
            report.error.get_or_insert(missing);
        }
        Ok(None) => {}
    }
    Ok(report)
}

/// Column of a recorded variable in `rows` (0 is time).
fn column(recorded: &[Recorded], name: &str) -> Option<usize> {
    recorded.iter().position(|r| r.name == name).map(|k| k + 1)
}

/// The run-up series, if the standard rotor outputs were recorded.
pub fn runup_series(
    recorded: &[Recorded],
    rows: &[Vec<f64>],
    clearance_m: [f64; 2],
) -> Option<RunSeries> {
    let col = |n: &str| column(recorded, n);
    let cols = [
        col("rotor.omega")?,
        col("rotor.dx_C")?,
        col("rotor.dy_C")?,
        col("rotor.dx_T")?,
        col("rotor.dy_T")?,
        col("rotor.y_JC")?,
        col("rotor.y_JT")?,
    ];
    let get = |k: usize| rows.iter().map(|r| r[k]).collect::<Vec<f64>>();
    Some(RunSeries {
        t_s: get(0),
        omega_rad_s: get(cols[0]),
        dx_c_m: get(cols[1]),
        dy_c_m: get(cols[2]),
        dx_t_m: get(cols[3]),
        dy_t_m: get(cols[4]),
        y_jc_m: get(cols[5]),
        y_jt_m: get(cols[6]),
        clearance_m,
        // The films' own eccentricities, when recorded (every run-up records them).
        eps_films: match (col("film_C.eps"), col("film_T.eps")) {
            (Some(c), Some(t)) => Some([get(c), get(t)]),
            _ => None,
        },
    })
}

/// Writes summary.json (an error if it cannot be written), then the figures and report.html it
/// lists; returns what of those could not be written.
fn write_summary(
    opts: &RunOptions,
    recorded: &[Recorded],
    rows: &[Vec<f64>],
    report: &RunReport,
) -> Result<Option<String>, String> {
    let mut summary = RunSummary::of_report(report, opts.extra.clone());
    let bores = match &opts.bores {
        Some(b) => Some(b.clone()),
        None => crate::run::read_back::bores_of_run(&opts.out_dir)?,
    };
    if let (Some(bores), true) = (&bores, !rows.is_empty()) {
        if let Some(series) = runup_series(recorded, rows, [bores[0].c_m, bores[1].c_m]) {
            let cl = classify(&series);
            summary.classification = Some(cl.class.as_str().to_string());
            summary.onset_time_s = cl.onset_time_s;
            summary.onset_speed_hz = cl.onset_speed_hz;
            summary.max_eps_c = Some(cl.max_eps_c);
            summary.max_eps_t = Some(cl.max_eps_t);
            summary.first_bearing = cl.first_bearing.clone();
            summary.criteria = Some(cl.criteria.clone());
            summary.margins = Some(cl.margins.clone());
            summary.borderline = Some(cl.borderline);
            summary.whirl = serde_json::to_value(&cl.whirl).ok();
            if !report.completed {
                summary.classification_note =
                    Some("classified on the part of the run-up that was simulated".into());
            } else if let Some(why) = &report.halted {
                summary.classification_note = Some(format!(
                    "classified on the part of the run-up before it halted ({why})"
                ));
            }
            summary.clearance_um = Some(ClearancesUm {
                c: bores[0].c_m * 1e6,
                t: bores[1].c_m * 1e6,
            });
            summary.hysteresis = crate::analysis::hysteresis(&series, &cl);
            // The results first, then the figures: figures that fill the disk must not leave
            // the folder with only the "running" summary (the list of figures follows below).
            summary.write(&opts.out_dir)?;
            let mut figures = plot_runup(&series, &cl, bores, &opts.out_dir);
            if let (Ok(files), Some(h)) = (&mut figures, &summary.hysteresis) {
                match crate::plot::plot_hysteresis(&series, h, &opts.out_dir) {
                    Ok(more) => files.extend(more),
                    Err(e) => figures = Err(e),
                }
            }
            match figures {
                Ok(files) => {
                    summary.plots = Some(
                        files
                            .iter()
                            .filter_map(|f| f.file_name())
                            .map(|f| f.to_string_lossy().into_owned())
                            .collect(),
                    )
                }
                Err(e) => summary.plot_error = Some(e.to_string()),
            }
        }
    }
    if let Some(files) = power_loss(&mut summary, recorded, rows, &opts.out_dir) {
        summary.plots.get_or_insert_with(Vec::new).extend(files);
    }
    for (stem, chart) in &opts.figures {
        match crate::plot::Figure::save(chart, &opts.out_dir, stem) {
            Ok(files) => summary.plots.get_or_insert_with(Vec::new).extend(
                files
                    .iter()
                    .filter_map(|f| f.file_name())
                    .map(|f| f.to_string_lossy().into_owned()),
            ),
            Err(e) => {
                summary.plot_error.get_or_insert_with(|| e.to_string());
            }
        }
    }
    if let Err(e) = summary.write(&opts.out_dir) {
        // The figures take the space first: say so beside the summary's own error.
        return Err(match &summary.plot_error {
            Some(p) => format!("figures not written: {p}; {e}"),
            None => e,
        });
    }
    let mut missing = summary
        .plot_error
        .as_ref()
        .map(|e| format!("figures not written: {e} (summary.json and the series are complete)"));
    if let Err(e) = crate::report::write_run_report(&opts.out_dir, &summary) {
        let e = format!("report.html not written: {e}");
        missing = Some(match missing {
            Some(m) => format!("{m}; {e}"),
            None => e,
        });
    }
    Ok(missing)
}

/// The films' friction power loss into the summary (and its figure), if the run recorded the
/// rotor speed and both films' `power_loss`; returns the figure files written.
fn power_loss(
    summary: &mut RunSummary,
    recorded: &[Recorded],
    rows: &[Vec<f64>],
    out_dir: &Path,
) -> Option<Vec<String>> {
    let cols = [
        column(recorded, "rotor.omega")?,
        column(recorded, "film_C.power_loss")?,
        column(recorded, "film_T.power_loss")?,
    ];
    let get = |k: usize| rows.iter().map(|r| r[k]).collect::<Vec<f64>>();
    let t = get(0);
    let speed: Vec<f64> = get(cols[0])
        .iter()
        .map(|w| w / std::f64::consts::TAU)
        .collect();
    let (pc, pt) = (get(cols[1]), get(cols[2]));
    summary.power_loss_w = crate::analysis::power_loss_summary(&t, &speed, &pc, &pt);
    summary.power_loss_w.as_ref()?;
    match crate::plot::plot_power_loss(&speed, &pc, &pt, out_dir) {
        Ok(files) => Some(
            files
                .iter()
                .filter_map(|f| f.file_name())
                .map(|f| f.to_string_lossy().into_owned())
                .collect(),
        ),
        Err(e) => {
            summary.plot_error.get_or_insert(e.to_string());
            None
        }
    }
}
