//! Running a system to its stop time: the macro-step loop, output sampling, Ctrl-C (a stop
//! flag), checkpoints and resume. What is done with the samples (files, progress, analysis) is up
//! to the [`Observer`]s; the loop prints nothing.

use crate::checkpoint::{self, MasterState, RunIdentity};
use crate::error::RunError;
use crate::observer::{Observer, RunStart};
use crate::report::RunReport;
use crate::setup::{build, Built};
use crate::system::System;
use fmi_core::LogHandler;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;
use std::time::Instant;

/// How a run is executed (the system file says what is simulated).
#[derive(Clone, Debug)]
pub struct RunConfig {
    /// The run folder: the system file used is copied there, checkpoints go to `checkpoint/`.
    pub out_dir: PathBuf,
    /// Simulated time between checkpoints.
    pub checkpoint_every_s: Option<f64>,
    /// Set by Ctrl-C (or a test) to stop cleanly, with a checkpoint, at the next macro point.
    pub stop: Arc<AtomicBool>,
    /// Stop (as if interrupted) once this simulated time is reached (tests of resume).
    pub halt_at_s: Option<f64>,
}

impl RunConfig {
    /// A run into `out_dir` without checkpoints, halts or a stop flag of its own.
    pub fn new(out_dir: impl Into<PathBuf>) -> Self {
        RunConfig {
            out_dir: out_dir.into(),
            checkpoint_every_s: None,
            stop: Arc::new(AtomicBool::new(false)),
            halt_at_s: None,
        }
    }
}

/// Output sample index -> time; computed from the index so that times do not drift.
fn output_time(k: u64, interval: f64) -> f64 {
    k as f64 * interval
}

/// Index of the first output time after the macro point `t` (macro step `h`).
fn first_output_after(t: f64, interval: f64, h: f64) -> u64 {
    let mut next = ((t + 1e-9 * h) / interval).floor().max(0.0) as u64;
    while output_time(next, interval) <= t + 1e-9 * h {
        next += 1;
    }
    next
}

/// Runs `system_path` into `cfg.out_dir` (copying the system file there), or resumes from the
/// checkpoint in `cfg.out_dir` when `resume` is set. Observers see every sample and event; the
/// report comes back also when the run failed or was interrupted (`Err` only when it could not
/// start).
pub fn run(
    system_path: &Path,
    cfg: &RunConfig,
    resume: bool,
    log: LogHandler,
    observers: &mut [&mut dyn Observer],
) -> Result<RunReport, RunError> {
    let io = |path: &Path| {
        let path = path.to_path_buf();
        move |source| RunError::Io { path, source }
    };
    if let Some(dt) = cfg.checkpoint_every_s {
        if !(dt.is_finite() && dt > 0.0) {
            return Err(RunError::Config(format!(
                "checkpoint interval {dt} s: must be a positive, finite simulated time"
            )));
        }
    }
    let used = cfg.out_dir.join("system.toml");
    let source = if resume { used.as_path() } else { system_path };
    let text = std::fs::read(source).map_err(io(source))?;
    let sys = System::load(source)?;
    let built = build(&sys, log)?;
    // A new run's copy of the system file keeps its relative FMU paths findable from the run
    // folder (a resume reads the copy); the run's identity is that of the copy.
    let in_place = system_path.canonicalize().ok() == used.canonicalize().ok();
    let text = if resume || in_place {
        text
    } else {
        sys.text_for_copy_in().into_bytes()
    };
    let (resumed_from, identity) = if resume {
        let (m, states) = resumable_checkpoint(&cfg.out_dir, &built, &text)?;
        let identity = m
            .identity
            .clone()
            .unwrap_or_else(|| RunIdentity::new(&text, built.guids.clone()));
        (Some((m, states)), identity)
    } else {
        (None, RunIdentity::new(&text, built.guids.clone()))
    };
    std::fs::create_dir_all(&cfg.out_dir).map_err(io(&cfg.out_dir))?;
    let exec = Execution::new(built, cfg, identity);
    exec.start(resumed_from.as_ref().map(|(m, _)| m), observers)
        .map_err(RunError::Observer)?;
    if !resume {
        // Only now, with the system built and every observer started, is the folder this run's:
        // an old checkpoint there belongs to another run, and the system file is copied in.
        let cp = cfg.out_dir.join("checkpoint");
        checkpoint::remove(&cfg.out_dir).map_err(io(&cp))?;
        if !in_place {
            crate::files::write_whole(&used, &text).map_err(io(&used))?;
        }
    }
    Ok(exec.run(resumed_from, observers))
}

/// The checkpoint in `dir`, checked against the run it would continue: the same system file
/// and FMUs (its identity), an algorithm state that fits the built system, and a time, step
/// index and output index that belong together.
fn resumable_checkpoint(
    dir: &Path,
    built: &Built,
    system_text: &[u8],
) -> Result<(MasterState, Vec<Vec<u8>>), RunError> {
    let names: Vec<String> = built.cosim.names().map(str::to_string).collect();
    let (m, states) = checkpoint::read(dir, &names).map_err(RunError::Checkpoint)?;
    let refuse = |why: String| {
        RunError::Checkpoint(format!(
            "{}: {why}; it cannot be continued (start the run afresh)",
            dir.join("checkpoint").display()
        ))
    };
    if let Some(why) = m
        .identity
        .as_ref()
        .and_then(|id| id.mismatch(system_text, &built.guids))
    {
        return Err(refuse(why));
    }
    let state = m.algorithm_state();
    built
        .cosim
        .check_state(&state, states.len())
        .map_err(|e| refuse(format!("master.json: {e}")))?;
    let h = built.macro_step_s;
    let n_steps = step_count(built.stop_time_s, h);
    // (The time is a sum of the step's sub-steps: on the grid to rounding, not bit for bit.)
    let off_grid = (state.t_s - grid_time(m.step_index, h, built.stop_time_s)).abs() > 1e-6 * h;
    if m.step_index > n_steps || off_grid {
        return Err(refuse(format!(
            "master.json: time {} s is not macro step {} of this system",
            state.t_s, m.step_index
        )));
    }
    let eps = 1e-9 * h;
    let interval = built.output_interval_s;
    let next_ok = output_time(m.next_output_index, interval) > state.t_s + eps
        && (m.next_output_index == 0
            || output_time(m.next_output_index - 1, interval) <= state.t_s + eps);
    if !next_ok {
        return Err(refuse(format!(
            "master.json: output sample {} does not follow time {} s",
            m.next_output_index, state.t_s
        )));
    }
    Ok((m, states))
}

/// Macro steps of a run to `stop` with step `h`: a remainder below 1e-6 of a step is rounding,
/// not a step; a larger one is a last, shorter step.
fn step_count(stop: f64, h: f64) -> u64 {
    (stop / h - 1e-6).ceil().max(1.0) as u64
}

/// The time after `k` macro steps: the grid point k h exactly (no drift over 10^5 steps), or the
/// stop time if the grid would pass it.
fn grid_time(k: u64, h: f64, stop: f64) -> f64 {
    let t = k as f64 * h;
    if t > stop + 1e-9 * h {
        stop
    } else {
        t
    }
}

/// A built co-simulation on its way to the stop time.
struct Execution<'a> {
    built: Built,
    cfg: &'a RunConfig,
    names: Vec<String>,
    /// One fmi2GetReal per subsystem and sample: (subsystem, its recorded vrs, their columns).
    by_sub: Vec<(usize, Vec<u32>, Vec<usize>)>,
    values: Vec<f64>,
    /// The macro point `values` were read at (time bits): read once per point.
    values_at: Option<u64>,
    scratch: Vec<f64>,
    /// The recorded values at the start of a long step, and the rows interpolated inside it.
    values_before: Vec<f64>,
    interpolated: Vec<f64>,
    /// End of the long-step window closed by a rejected or discarded step inside it.
    long_closed_until_s: Option<f64>,
    /// Times at which this process closed a window.
    long_closed_at_s: Vec<f64>,
    /// Macro steps taken and, of them, long ones (the whole run's, across resumes).
    steps_taken: (u64, u64),
    /// Base-step grid intervals covered (a long step of `step_plan` covers several; from the
    /// checkpoint on resume).
    step_index: u64,
    /// Wall time of the run before this process (a resumed run's earlier parts) [s].
    wall_before_s: f64,
    /// Written into every checkpoint.
    identity: RunIdentity,
}

/// How the loop ended without an error.
enum End {
    Completed,
    /// An observer asked to end the run here (its reason).
    Halted(String),
    Interrupted,
}

impl<'a> Execution<'a> {
    fn new(built: Built, cfg: &'a RunConfig, identity: RunIdentity) -> Self {
        let mut by_sub: Vec<(usize, Vec<u32>, Vec<usize>)> = vec![];
        for (col, r) in built.recorded.iter().enumerate() {
            match by_sub.iter_mut().find(|g| g.0 == r.subsystem) {
                Some(g) => {
                    g.1.push(r.vr);
                    g.2.push(col);
                }
                None => by_sub.push((r.subsystem, vec![r.vr], vec![col])),
            }
        }
        let n = built.recorded.len();
        Execution {
            names: built.cosim.names().map(str::to_string).collect(),
            built,
            cfg,
            by_sub,
            values: vec![0.0; n],
            values_at: None,
            scratch: vec![0.0; n],
            values_before: vec![0.0; n],
            interpolated: vec![0.0; n],
            long_closed_until_s: None,
            long_closed_at_s: vec![],
            steps_taken: (0, 0),
            step_index: 0,
            wall_before_s: 0.0,
            identity,
        }
    }

    /// Tells every observer the run starts (before anything in the run folder is replaced).
    fn start(
        &self,
        resumed_from: Option<&MasterState>,
        observers: &mut [&mut dyn Observer],
    ) -> Result<(), crate::error::ObserverError> {
        let run_start = RunStart {
            columns: &self.built.recorded,
            resumed_from,
            stop_time_s: self.built.stop_time_s,
            output_interval_s: self.built.output_interval_s,
            idle_workers: self.built.cosim.idle_workers(),
        };
        for o in observers.iter_mut() {
            o.started(&run_start)?;
        }
        for o in observers.iter_mut() {
            o.begun(&run_start)?;
        }
        Ok(())
    }

    /// Rolled-back or rejected attempts so far (they close a long-step window).
    fn trouble_count(&self) -> u64 {
        let c = &self.built.cosim;
        c.macro_steps().1 + c.control_stats().map_or(0, |s| s.rejected)
    }

    /// Reads the recorded variables into `values`, unless they were read at this macro point.
    fn record(&mut self) -> Result<(), String> {
        let t = self.built.cosim.time_s().to_bits();
        if self.values_at == Some(t) {
            return Ok(());
        }
        for (i, vrs, cols) in &self.by_sub {
            let out = &mut self.scratch[..vrs.len()];
            self.built
                .cosim
                .get_many(*i, vrs, out)
                .map_err(|e| format!("reading outputs of {}: {e}", self.names[*i]))?;
            for (c, v) in cols.iter().zip(out.iter()) {
                self.values[*c] = *v;
            }
        }
        self.values_at = Some(t);
        Ok(())
    }

    fn run(
        mut self,
        resumed_from: Option<(MasterState, Vec<Vec<u8>>)>,
        observers: &mut [&mut dyn Observer],
    ) -> RunReport {
        let start = Instant::now();
        let mut report = RunReport::default();
        match self.run_loop(resumed_from, observers, start) {
            Ok(End::Completed) => report.completed = true,
            Ok(End::Halted(reason)) => {
                report.completed = true;
                report.halted = Some(reason);
            }
            Ok(End::Interrupted) => report.interrupted = true,
            Err(e) => report.error = Some(e),
        }
        let cosim = &self.built.cosim;
        report.t_end_s = cosim.time_s();
        report.macro_steps = self.steps_taken.0;
        if self.built.long_steps.is_some() {
            report.long_macro_steps = Some(self.steps_taken.1);
            report.long_steps_closed_at_s = self.long_closed_at_s.clone();
        }
        report.retries = cosim.macro_steps().1;
        report.control = cosim.control_stats();
        report.group_stepping = cosim.stepping_stats();
        report.counters = cosim.counters();
        report.wall_time_s = self.wall_before_s + start.elapsed().as_secs_f64();
        report.wall_per_subsystem_s = cosim
            .wall_in_fmus()
            .into_iter()
            .map(|(n, d)| (n, d.as_secs_f64()))
            .collect();
        // With parallel groups the FMU times overlap: the FMUs' share is the critical path (per
        // macro step, the slowest member of each group); everything else is the master's own work.
        let tm = cosim.timing();
        report.master_overhead_s =
            (start.elapsed().as_secs_f64() - tm.critical_path.as_secs_f64()).max(0.0);
        report.master_parts_s = vec![
            ("save_states".into(), tm.save_states.as_secs_f64()),
            ("coupling".into(), tm.coupling.as_secs_f64()),
            (
                "parallel_handover".into(),
                tm.parallel_overhead.as_secs_f64(),
            ),
        ];
        for o in observers.iter_mut() {
            if let Err(e) = o.finished(cosim, &report) {
                report.error.get_or_insert(e.to_string());
            }
        }
        report
    }

    fn run_loop(
        &mut self,
        resumed_from: Option<(MasterState, Vec<Vec<u8>>)>,
        observers: &mut [&mut dyn Observer],
        start: Instant,
    ) -> Result<End, String> {
        let h = self.built.macro_step_s;
        let stop = self.built.stop_time_s;
        let n_steps = step_count(stop, h);
        let interval = self.built.output_interval_s;
        let mut next_output = 0;
        if let Some((m, states)) = &resumed_from {
            self.built
                .cosim
                .restore_checkpoint(m.algorithm_state(), states)
                .map_err(|e| e.to_string())?;
            self.step_index = m.step_index;
            next_output = m.next_output_index;
            self.long_closed_until_s = m.long_steps_closed_until_s;
            self.steps_taken = m.macro_steps_taken.unwrap_or((m.step_index, 0));
            self.wall_before_s = m.wall_before_s;
        }
        let cfg = self.cfg;
        let mut next_checkpoint = cfg
            .checkpoint_every_s
            .map(|dt| ((self.built.cosim.time_s() / dt).floor() + 1.0) * dt);
        loop {
            let t = self.built.cosim.time_s();
            // One sample at a macro point where output times are due. Outputs exist only at macro
            // points: an output interval shorter than the macro step gives one row per macro
            // point, never repeated rows of the same time. The stop time gets its row also where
            // it falls between output times: the run's final state belongs in its series (a stop
            // at 1.5 ms with rows every 1 ms ended the series at 1 ms).
            let at_stop = self.step_index >= n_steps;
            if at_stop || output_time(next_output, interval) <= t + 1e-9 * h {
                self.record()?;
                for o in observers.iter_mut() {
                    o.sample(t, &self.values)?;
                }
                next_output = first_output_after(t, interval, h);
            }
            for o in observers.iter_mut() {
                o.macro_point(&self.built.cosim, stop);
            }
            if self.step_index >= n_steps {
                return Ok(End::Completed);
            }
            if let Some(reason) = observers.iter().find_map(|o| o.halt()) {
                return Ok(End::Halted(reason));
            }
            let halt = cfg.halt_at_s.is_some_and(|th| t >= th - 1e-9 * h);
            let checkpoint_due = next_checkpoint.is_some_and(|tc| t >= tc - 1e-9 * h);
            let stopping = cfg.stop.load(Ordering::Relaxed) || halt;
            if checkpoint_due || stopping {
                let (state, states) = self.built.cosim.checkpoint().map_err(|e| e.to_string())?;
                let mut m = MasterState::new(
                    &state,
                    self.step_index,
                    next_output,
                    self.wall_before_s + start.elapsed().as_secs_f64(),
                );
                m.identity = Some(self.identity.clone());
                m.long_steps_closed_until_s = self.long_closed_until_s;
                m.macro_steps_taken = Some(self.steps_taken);
                for o in observers.iter_mut() {
                    o.checkpoint(&mut m)?;
                }
                checkpoint::write(&cfg.out_dir, &self.names, &states, &m)
                    .map_err(|e| format!("checkpoint: {e}"))?;
                if let (Some(tc), Some(dt)) = (next_checkpoint.as_mut(), cfg.checkpoint_every_s) {
                    *tc += dt;
                }
            }
            if stopping {
                return Ok(End::Interrupted);
            }
            // A long step (`step_plan`) covers several grid intervals; the rows a run of base
            // steps would have written at the grid points it passes are interpolated linearly
            // between its ends (the plan's windows are where the system is calm).
            // A window is closed for good at its first rejected or discarded step.
            let open = self
                .long_closed_until_s
                .is_none_or(|end| t >= end - 1e-9 * h);
            let m = match &self.built.long_steps {
                Some(p) if open => p.base_steps_from(self.step_index, h, n_steps),
                _ => 1,
            };
            let trouble_before = self.trouble_count();
            if m > 1 {
                self.record()?;
                self.values_before.clone_from(&self.values);
            }
            let target = grid_time(self.step_index + m, h, stop);
            let r = self.built.cosim.step(target - t);
            // Events first: a roll-back the step made is reported also when the step then failed.
            for e in self.built.cosim.drain_events() {
                for o in observers.iter_mut() {
                    o.event(&e);
                }
            }
            r.map_err(|e| e.to_string())?;
            if self.trouble_count() > trouble_before {
                if let Some((_, end)) = self
                    .built
                    .long_steps
                    .as_ref()
                    .and_then(|p| p.window_at(t, h))
                    .filter(|&(_, end)| self.long_closed_until_s.is_none_or(|c| c < end))
                {
                    self.long_closed_until_s = Some(end);
                    self.long_closed_at_s.push(t);
                }
            }
            if m > 1 {
                self.record()?;
                for i in 1..m {
                    let g = grid_time(self.step_index + i, h, stop);
                    if output_time(next_output, interval) <= g + 1e-9 * h {
                        let w = (g - t) / (target - t);
                        for ((v, &a), &b) in self
                            .interpolated
                            .iter_mut()
                            .zip(&self.values_before)
                            .zip(&self.values)
                        {
                            *v = a + w * (b - a);
                        }
                        for o in observers.iter_mut() {
                            o.sample(g, &self.interpolated)?;
                        }
                        next_output = first_output_after(g, interval, h);
                    }
                }
            }
            self.step_index += m;
            self.steps_taken.0 += 1;
            self.steps_taken.1 += u64::from(m > 1);
        }
    }
}
