//! Running a system to its stop time: macro-step loop, output sampling, progress, Ctrl-C,
//! checkpoints, and the summary at the end (also when interrupted or failed).

use crate::analysis::{classify, RunSeries};
use crate::cosim::gauss_seidel::ControlStats;
use crate::cosim::setup::{build, stderr_logger};
use crate::output::checkpoint::{self, MasterState};
use crate::output::timeseries::{self, TimeSeriesWriter};
use crate::plot::plot_runup;
use crate::system::System;
use bearing::Bore;
use std::io::IsTerminal;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;
use std::time::{Duration, Instant};

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
    /// Bearing geometry (C for the eccentricities, lobes for the orbit plots); None: no run-up
    /// analysis and no plots.
    pub lobes: Option<Bore>,
    /// Also write `timeseries.parquet` when the run ends (the CSV is written in any case).
    pub parquet: bool,
}

#[derive(Debug, Default, serde::Serialize)]
pub struct RunReport {
    pub completed: bool,
    pub interrupted: bool,
    pub error: Option<String>,
    pub t_end_s: f64,
    pub macro_steps: u64,
    pub retries: u64,
    pub wall_time_s: f64,
    /// Wall time in each subsystem's fmi2DoStep, and everything else (the master's own work).
    pub wall_per_subsystem_s: Vec<(String, f64)>,
    pub master_overhead_s: f64,
    /// Parts of the master's own time: state saving, coupling (polynomials, get/set), thread hand-over.
    pub master_parts_s: Vec<(String, f64)>,
    /// What the macro-step control did (None: fixed macro step).
    pub control: Option<ControlStats>,
    /// Integer outputs of each FMU at the end (solver counters such as the air film's
    /// `n_pressure_floored`; counted since the start or the resumed checkpoint).
    pub counters: Vec<(String, Vec<(String, i32)>)>,
}

/// Output sample index -> time; computed from the index so that times do not drift.
fn output_time(k: u64, interval: f64) -> f64 {
    k as f64 * interval
}

struct Progress {
    tty: bool,
    quiet: bool,
    last: Instant,
    last_fraction_printed: f64,
    start: Instant,
    wall_before: f64,
}

impl Progress {
    fn show(&mut self, t: f64, stop: f64, omega_rad_s: Option<f64>, force: bool) {
        if self.quiet {
            return;
        }
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
        let speed = omega_rad_s
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

/// Runs `system_path` into `opts.out_dir` (copying the system file there), or resumes from the
/// checkpoint in `opts.out_dir` when `resume` is set.
pub fn run(system_path: &Path, opts: &RunOptions, resume: bool) -> Result<RunReport, String> {
    std::fs::create_dir_all(&opts.out_dir)
        .map_err(|e| format!("{}: {e}", opts.out_dir.display()))?;
    let used = opts.out_dir.join("system.toml");
    if !resume {
        let text = std::fs::read_to_string(system_path)
            .map_err(|e| format!("{}: {e}", system_path.display()))?;
        if system_path.canonicalize().ok() != used.canonicalize().ok() {
            std::fs::write(&used, &text).map_err(|e| format!("{}: {e}", used.display()))?;
        }
    }
    let sys = System::load(if resume { &used } else { system_path }).map_err(|e| e.to_string())?;
    let mut built = build(&sys, stderr_logger()).map_err(|e| e.to_string())?;
    let h = built.macro_step_s;
    let stop = built.stop_time_s;
    let n_steps = (stop / h).round() as u64;
    let interval = built.output_interval_s;
    let names: Vec<String> = built.cosim.subs.iter().map(|s| s.name.clone()).collect();
    let columns: Vec<(String, String)> = built
        .recorded
        .iter()
        .map(|(_, _, n, u)| (n.clone(), u.clone()))
        .collect();
    let csv_path = opts.out_dir.join("timeseries.csv");

    let mut rows: Vec<Vec<f64>> = Vec::new();
    let (mut step_index, mut next_output, mut writer, wall_before) = if resume {
        let (m, states) = checkpoint::read(&opts.out_dir, &names)?;
        let t = f64::from_bits(m.t_bits);
        let hist = m
            .histories
            .iter()
            .map(|h| checkpoint::decode_history(h))
            .collect();
        built
            .cosim
            .restore_serialized(t, &states, hist)
            .map_err(|e| e.to_string())?;
        built.cosim.level = m.refine_level;
        let writer = TimeSeriesWriter::resume(&csv_path, m.csv_bytes)
            .map_err(|e| format!("{}: {e}", csv_path.display()))?;
        let (_, old) = timeseries::read(&csv_path).map_err(|e| e.to_string())?;
        rows = old;
        eprintln!("resuming {} at t = {t} s", opts.out_dir.display());
        (m.step_index, m.next_output_index, writer, m.wall_before_s)
    } else {
        let writer = TimeSeriesWriter::create(&csv_path, &columns)
            .map_err(|e| format!("{}: {e}", csv_path.display()))?;
        (0, 0, writer, 0.0)
    };

    let start = Instant::now();
    let mut progress = Progress {
        tty: std::io::stderr().is_terminal(),
        quiet: opts.quiet,
        last: Instant::now(),
        last_fraction_printed: 0.0,
        start,
        wall_before,
    };
    let omega_port = built
        .recorded
        .iter()
        .position(|(_, _, n, _)| n.ends_with(".omega"));
    let mut values = vec![0.0; built.recorded.len()];
    let mut report = RunReport::default();
    let mut next_checkpoint = opts
        .checkpoint_every_s
        .map(|dt| ((built.cosim.t / dt).floor() + 1.0) * dt);

    // One fmi2GetReal per subsystem and sample: (subsystem, its recorded vrs, their columns).
    let mut by_sub: Vec<(usize, Vec<u32>, Vec<usize>)> = vec![];
    for (col, (i, vr, _, _)) in built.recorded.iter().enumerate() {
        match by_sub.iter_mut().find(|g| g.0 == *i) {
            Some(g) => {
                g.1.push(*vr);
                g.2.push(col);
            }
            None => by_sub.push((*i, vec![*vr], vec![col])),
        }
    }
    let mut sub_values = vec![0.0; built.recorded.len()];
    let mut record = |cosim: &crate::cosim::CoSim, values: &mut [f64]| -> Result<(), String> {
        for (i, vrs, cols) in &by_sub {
            let out = &mut sub_values[..vrs.len()];
            cosim
                .get_many(*i, vrs, out)
                .map_err(|e| format!("reading outputs of {}: {e}", cosim.subs[*i].name))?;
            for (c, v) in cols.iter().zip(out.iter()) {
                values[*c] = *v;
            }
        }
        Ok(())
    };

    let result: Result<(), String> = (|| {
        loop {
            let t = built.cosim.t;
            // Output samples due at the current macro point.
            while output_time(next_output, interval) <= t + 1e-9 * h {
                record(&built.cosim, &mut values)?;
                writer.row(t, &values).map_err(|e| e.to_string())?;
                let mut row = vec![t];
                row.extend_from_slice(&values);
                rows.push(row);
                next_output += 1;
            }
            let omega = omega_port.map(|k| values[k]);
            progress.show(t, stop, omega, false);
            if step_index >= n_steps {
                report.completed = true;
                return Ok(());
            }
            let halt = opts.halt_at_s.is_some_and(|th| t >= th - 1e-9 * h);
            let checkpoint_due = next_checkpoint.is_some_and(|tc| t >= tc - 1e-9 * h);
            let stopping = opts.stop.load(Ordering::Relaxed) || halt;
            if checkpoint_due || stopping {
                writer.flush().map_err(|e| e.to_string())?;
                let states = built.cosim.serialize_states().map_err(|e| e.to_string())?;
                let m = MasterState {
                    format: checkpoint::FORMAT,
                    t_bits: t.to_bits(),
                    step_index,
                    next_output_index: next_output,
                    csv_bytes: writer.bytes,
                    histories: built
                        .cosim
                        .subs
                        .iter()
                        .map(|s| checkpoint::encode_history(&s.history))
                        .collect(),
                    wall_before_s: wall_before + start.elapsed().as_secs_f64(),
                    refine_level: built.cosim.level,
                };
                checkpoint::write(&opts.out_dir, &names, &states, &m)
                    .map_err(|e| format!("checkpoint: {e}"))?;
                if let (Some(tc), Some(dt)) = (next_checkpoint.as_mut(), opts.checkpoint_every_s) {
                    *tc += dt;
                }
            }
            if stopping {
                report.interrupted = true;
                return Ok(());
            }
            // Step to the grid point (k+1) h exactly, so the time does not drift over 10^5 steps.
            let target = (step_index + 1) as f64 * h;
            built.cosim.step(target - t).map_err(|e| e.to_string())?;
            step_index += 1;
        }
    })();
    writer.flush().map_err(|e| e.to_string())?;
    progress.show(built.cosim.t, stop, omega_port.map(|k| values[k]), true);
    // A failed Parquet write is reported like a failed run, but summary.json is still written.
    let parquet_error = if opts.parquet {
        crate::output::parquet_file::write(
            &opts.out_dir.join("timeseries.parquet"),
            &columns,
            &rows,
        )
        .err()
    } else {
        None
    };

    report.error = result.err().or(parquet_error);
    report.t_end_s = built.cosim.t;
    report.macro_steps = step_index;
    report.retries = built.cosim.retries;
    report.control = built.cosim.control.map(|_| built.cosim.control_stats);
    report.counters = built.cosim.counters();
    report.wall_time_s = wall_before + start.elapsed().as_secs_f64();
    report.wall_per_subsystem_s = built
        .cosim
        .subs
        .iter()
        .map(|s| (s.name.clone(), s.step_wall.as_secs_f64()))
        .collect();
    // With parallel films the FMU times overlap: the FMUs' share is the critical path (per macro
    // step, the slowest member of each group); everything else is the master's own work.
    let critical = built.cosim.timing.critical_path.as_secs_f64();
    report.master_overhead_s = (start.elapsed().as_secs_f64() - critical).max(0.0);
    let tm = &built.cosim.timing;
    report.master_parts_s = vec![
        ("save_states".into(), tm.save_states.as_secs_f64()),
        ("coupling".into(), tm.coupling.as_secs_f64()),
        (
            "parallel_handover".into(),
            tm.parallel_overhead.as_secs_f64(),
        ),
    ];

    write_summary(opts, &built.recorded, &rows, &report)?;
    Ok(report)
}

/// Column of a recorded variable in `rows` (0 is time).
fn column(recorded: &[(usize, u32, String, String)], name: &str) -> Option<usize> {
    recorded
        .iter()
        .position(|(_, _, n, _)| n == name)
        .map(|k| k + 1)
}

/// The run-up series, if the standard rotor outputs were recorded.
pub fn runup_series(
    recorded: &[(usize, u32, String, String)],
    rows: &[Vec<f64>],
    clearance_m: f64,
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
    })
}

fn write_summary(
    opts: &RunOptions,
    recorded: &[(usize, u32, String, String)],
    rows: &[Vec<f64>],
    report: &RunReport,
) -> Result<(), String> {
    let mut summary = serde_json::json!({
        "status": if report.completed { "completed" } else if report.interrupted { "interrupted" } else { "failed" },
        "interrupted": report.interrupted,
        "error": report.error,
        "t_end_s": report.t_end_s,
        "macro_steps": report.macro_steps,
        "retried_macro_steps": report.retries,
        "macro_step_control": report.control,
        "wall_time_s": report.wall_time_s,
        "wall_in_fmus_s": report.wall_per_subsystem_s.iter().map(|(n, s)| (n.clone(), serde_json::json!(s))).collect::<serde_json::Map<_, _>>(),
        "master_overhead_s": report.master_overhead_s,
        "master_overhead_parts_s": report.master_parts_s.iter().map(|(n, s)| (n.clone(), serde_json::json!(s))).collect::<serde_json::Map<_, _>>(),
        "fmu_counters": report.counters.iter().map(|(sub, c)| (sub.clone(), c.iter().map(|(n, v)| (n.clone(), serde_json::json!(v))).collect::<serde_json::Map<_, _>>().into())).collect::<serde_json::Map<_, serde_json::Value>>(),
        "master_overhead_percent": 100.0 * report.master_overhead_s / report.wall_time_s.max(1e-12),
        "settings": opts.extra,
        "classification": serde_json::Value::Null,
        "onset_time_s": serde_json::Value::Null,
        "max_eps_C": serde_json::Value::Null,
        "max_eps_T": serde_json::Value::Null,
    });
    if let (Some(lobes), true) = (&opts.lobes, rows.len() > 16) {
        if let Some(series) = runup_series(recorded, rows, lobes.c_m) {
            let cl = classify(&series);
            summary["classification"] = serde_json::json!(cl.class.as_str());
            summary["onset_time_s"] = serde_json::json!(cl.onset_time_s);
            summary["onset_speed_hz"] = serde_json::json!(cl.onset_speed_hz);
            summary["max_eps_C"] = serde_json::json!(cl.max_eps_c);
            summary["max_eps_T"] = serde_json::json!(cl.max_eps_t);
            summary["first_bearing"] = serde_json::json!(cl.first_bearing);
            summary["criteria"] = serde_json::json!(cl.criteria);
            summary["whirl"] = serde_json::to_value(&cl.whirl).unwrap_or_default();
            if !report.completed {
                summary["classification_note"] =
                    serde_json::json!("classified on the part of the run-up that was simulated");
            }
            match plot_runup(&series, &cl, lobes, &opts.out_dir) {
                Ok(files) => {
                    summary["plots"] = serde_json::json!(files
                        .iter()
                        .filter_map(|f| f.file_name())
                        .map(|f| f.to_string_lossy())
                        .collect::<Vec<_>>())
                }
                Err(e) => summary["plot_error"] = serde_json::json!(e.to_string()),
            }
        }
    }
    let path = opts.out_dir.join("summary.json");
    std::fs::write(&path, serde_json::to_string_pretty(&summary).expect("json"))
        .map_err(|e| format!("{}: {e}", path.display()))
}
