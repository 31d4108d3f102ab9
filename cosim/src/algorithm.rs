//! The macro step: sequential Gauss-Seidel in a given order (paper Section 2.4) or Jacobi.
//!
//! Gauss-Seidel: a subsystem's inputs from subsystems not yet stepped in this macro step are
//! *extrapolated* through their last macro points (T_N, T_N-1, ...); inputs from subsystems already
//! stepped are *interpolated* through T_N+1, T_N (and T_N-1). Jacobi extrapolates everything.
//! The polynomial reaches an FMU as value + derivatives at T_N (fmi2SetRealInputDerivatives) when it
//! declares canInterpolateInputs; otherwise (fallback) the input is held at the polynomial's value at
//! the step midpoint, which keeps second-order accuracy of the coupling for smooth signals.
//!
//! Consecutive subsystems in the order that do not feed each other form a group and are stepped in
//! parallel (the two air films). A discarded step rolls every FMU back to T_N (FMU states saved at
//! each macro point) and retries the interval in two halves, down to 1/64 of the macro step.
//!
//! Macro-step control (optional, [`StepControl`]): after each step the extrapolated inputs are
//! compared with the outputs the sources then produced at T_N+1. A difference above
//! `atol + rtol |u|` rejects the step like a Discard (roll back, two halves). The refinement level
//! reached is kept for the following macro steps and relaxed one level at a time once the error is
//! well below tolerance. This is what carries a journal through an impact on its ring: the contact
//! force (stiffness ~1e10 N/m against a ring of 50 g) cannot be coupled explicitly at 20 us, but
//! is at ~1 us; steps without contact keep the nominal macro step.

use crate::error::{RestoreError, StepError};
use crate::parallel::StepPool;
use crate::parallel_choice::{ChoiceTuning, Stepping, SteppingChoice, SteppingStats};
use crate::polynomial::{taylor_derivatives, taylor_value};
use crate::slave::Fmu;
use crate::step_control::{
    ControlStats, StepControl, MAX_HALVINGS, RELAX_BELOW, SAVE_BURST_STEPS, SAVE_EVERY,
};
use crate::subsystem::Subsystem;
use fmi_core::CallError;
use fmi_core::Status;
use std::collections::VecDeque;
use std::sync::Arc;
use std::time::{Duration, Instant};

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Scheme {
    GaussSeidel,
    Jacobi,
}

/// How the macro step couples the subsystems: the one configuration of [`CoSim::initialize`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct AlgorithmConfig {
    pub scheme: Scheme,
    /// Order of the polynomial through the last macro points for inputs not yet available at
    /// T_N+1 (0, 1, 2).
    pub extrapolation_order: usize,
    /// Order of the polynomial for inputs whose source already stepped to T_N+1 (0, 1, 2).
    pub interpolation_order: usize,
    /// Save FMU states and roll back on fmi2Discard (required by `control`).
    pub rollback: bool,
    /// Allow stepping the members of a group (subsystems that do not feed each other) in parallel
    /// threads; whether a group step does is measured as the run goes (`parallel_choice`).
    pub parallel: bool,
    /// Macro-step control by the coupling error; None: fixed macro step (Discard still halves).
    pub control: Option<StepControl>,
    /// The tuning of the measured choice between parallel and serial group steps.
    pub parallel_tuning: ChoiceTuning,
}

/// Something the algorithm did that a watcher may want to report (the library prints nothing).
#[derive(Clone, Debug, PartialEq)]
pub enum Event {
    /// A subsystem discarded the step [t_from_s, t_to_s]: the FMUs were rolled back and the
    /// interval is retried in halves.
    RolledBack {
        subsystem: String,
        reason: String,
        t_from_s: f64,
        t_to_s: f64,
    },
}

/// A co-simulation of FMU instances advancing by macro steps. Its state is private: read it
/// through the accessors, save and restore it with [`CoSim::checkpoint`] and
/// [`CoSim::restore_checkpoint`].
pub struct CoSim {
    subs: Vec<Subsystem>,
    /// Groups of subsystem indices in stepping order; members of a group run in parallel.
    groups: Vec<Vec<usize>>,
    config: AlgorithmConfig,
    t: f64,
    macro_steps: u64,
    retries: u64,
    timing: Timing,
    /// Current refinement: the macro step is covered by 2^level sub-steps.
    level: u32,
    control_stats: ControlStats,
    /// Scratch: extrapolated inputs' predictions at T_N+1 as (source, slot, value).
    predicted: Vec<(usize, usize, f64)>,
    /// Worker threads of the parallel groups. Dropped (joined) before the subsystems: see Drop.
    pool: Option<StepPool>,
    /// Parallel or one after the other, by measurement (only with a pool).
    stepping: SteppingChoice,
    /// Scratch: which subsystems have stepped in the current macro step.
    stepped: Vec<bool>,
    /// Macro steps between saved FMU states when rollback is on.
    save_every: usize,
    /// Macro steps left in which states are saved at every step: set after a rejection or a Discard, because
    /// where the control acted once (a whirl grazing the ring) it acts again within ~100 steps,
    /// and a replay of up to `save_every` steps per rejection costs more than saving each step.
    save_burst: u64,
    saved: Option<Saved>,
    events: Vec<Event>,
    /// The loaded FMUs (their libraries must outlive the instances).
    _fmus: Vec<Arc<Fmu>>,
}

impl CoSim {
    /// Where an observer may offer per-sample work for the threads that wait on the parallel
    /// groups' pool (None without one: then the observer does its work itself).
    pub fn idle_workers(&self) -> Option<crate::parallel::IdleWorkers> {
        self.pool.as_ref().map(StepPool::idle_workers)
    }
}

impl Drop for CoSim {
    /// Joins the worker threads before the FMU instances and libraries are freed (fields drop in
    /// declaration order, and `subs` comes first): a worker may still be inside an instance.
    fn drop(&mut self) {
        self.pool.take();
    }
}

/// The algorithm's own state at a macro point, beyond the FMU states: what a checkpoint keeps.
#[derive(Clone, Debug, PartialEq)]
pub struct AlgorithmState {
    pub t_s: f64,
    /// Per subsystem: coupling outputs at the last macro points, oldest first.
    pub histories: Vec<VecDeque<(f64, Vec<f64>)>>,
    /// Refinement level of the macro-step control.
    pub refine_level: u32,
}

/// Where the master's own time goes (wall time), for the run summary.
#[derive(Clone, Debug, Default)]
pub struct Timing {
    /// Saving FMU states for roll-back.
    pub save_states: Duration,
    /// Setting inputs (polynomials) and reading coupling outputs.
    pub coupling: Duration,
    /// Parallel groups: wall time beyond the slowest member (thread hand-over).
    pub parallel_overhead: Duration,
    /// Sum over macro steps and groups of the slowest member's fmi2DoStep: the time the FMUs
    /// themselves need on as many cores as the largest group; the rest of the wall time is the master's.
    pub critical_path: Duration,
}

/// Accepted sub-steps of one macro step: largest error ratio and deepest level.
#[derive(Clone, Copy, Debug, Default)]
struct Accepted {
    worst: f64,
    deepest: u32,
}

/// The last saved point: time, coupling histories, and the steps taken since (for the replay).
struct Saved {
    t: f64,
    history: Vec<VecDeque<(f64, Vec<f64>)>>,
    replay: Vec<f64>,
}

impl CoSim {
    /// Settles the inputs in initialization mode (sources in order, twice), leaves it, and records
    /// the coupling outputs at t = 0 as the first macro point.
    pub fn initialize(
        subs: Vec<Subsystem>,
        order: Vec<usize>,
        config: AlgorithmConfig,
        fmus: Vec<Arc<Fmu>>,
    ) -> Result<CoSim, StepError> {
        let groups = match config.scheme {
            Scheme::Jacobi => vec![order.clone()],
            Scheme::GaussSeidel => {
                let mut groups: Vec<Vec<usize>> = vec![];
                for &i in &order {
                    let feeds_from_last = groups
                        .last()
                        .is_some_and(|g| subs[i].inputs.iter().any(|l| g.contains(&l.from)));
                    match groups.last_mut() {
                        Some(g) if !feeds_from_last => g.push(i),
                        _ => groups.push(vec![i]),
                    }
                }
                groups
            }
        };
        let largest = groups.iter().map(Vec::len).max().unwrap_or(1);
        let pool = (config.parallel && largest > 1).then(|| StepPool::new(largest));
        let mut c = CoSim {
            subs,
            groups,
            config,
            t: 0.0,
            macro_steps: 0,
            retries: 0,
            timing: Timing::default(),
            level: 0,
            control_stats: ControlStats::default(),
            predicted: vec![],
            pool,
            stepping: SteppingChoice::new(config.parallel_tuning),
            stepped: vec![],
            save_every: SAVE_EVERY,
            save_burst: 0,
            saved: None,
            events: vec![],
            _fmus: fmus,
        };
        let fail = |s: &Subsystem, error| StepError {
            subsystem: s.name.clone(),
            error,
            t_s: 0.0,
        };
        for _pass in 0..2 {
            for &i in &order {
                let (vrs, vals): (Vec<u32>, Vec<f64>) = c.subs[i]
                    .inputs
                    .iter()
                    .map(|l| {
                        let src = &c.subs[l.from];
                        let mut v = [0.0];
                        src.slave
                            .get_real(&[src.coupling_vrs[l.from_slot]], &mut v)
                            .map(|_| (l.to_vr, v[0]))
                            .map_err(|e| fail(src, e))
                    })
                    .collect::<Result<Vec<_>, _>>()?
                    .into_iter()
                    .unzip();
                c.subs[i]
                    .slave
                    .set_real(&vrs, &vals)
                    .map_err(|e| fail(&c.subs[i], e))?;
            }
        }
        for s in &mut c.subs {
            s.slave.exit_initialization_mode().map_err(|e| fail(s, e))?;
            let v = s.read_coupling().map_err(|e| fail(s, e))?;
            s.push_history(0.0, v);
        }
        Ok(c)
    }

    /// Sets subsystem `i`'s inputs for the step [t, t+h] from the other subsystems' histories.
    fn set_inputs(&mut self, i: usize, t: f64, h: f64, stepped: &[bool]) -> Result<(), CallError> {
        let (extrap, interp) = (
            self.config.extrapolation_order,
            self.config.interpolation_order,
        );
        let mut scratch = std::mem::take(&mut self.subs[i].vrs);
        let mut values = std::mem::take(&mut self.subs[i].values);
        let mut orders = std::mem::take(&mut self.subs[i].orders);
        let mut der_vrs = std::mem::take(&mut self.subs[i].der_vrs);
        let mut der_values = std::mem::take(&mut self.subs[i].der_values);
        scratch.clear();
        values.clear();
        orders.clear();
        der_vrs.clear();
        der_values.clear();
        let can_interpolate = self.subs[i].can_interpolate;
        for l in &self.subs[i].inputs {
            let hist = &self.subs[l.from].history;
            let n = hist.len();
            // The point at T_N: the newest one, or the one before if the source already stepped.
            let (anchor_idx, order) = if stepped[l.from] {
                (n - 2, interp)
            } else {
                (n - 1, extrap)
            };
            let used = (order + 1).min(n);
            let mut pts = [(0.0, 0.0); 3];
            for (k, p) in hist.iter().skip(n - used).enumerate() {
                pts[k] = (p.0, p.1[l.from_slot]);
            }
            let u0 = hist[anchor_idx].1[l.from_slot];
            debug_assert_eq!(hist[anchor_idx].0, t);
            let d = taylor_derivatives(&pts[..used], t);
            if self.config.control.is_some() && !stepped[l.from] {
                self.predicted
                    .push((l.from, l.from_slot, taylor_value(u0, d, h)));
            }
            scratch.push(l.to_vr);
            if can_interpolate {
                values.push(u0);
                for (k, dk) in d.iter().enumerate().take(used - 1) {
                    der_vrs.push(l.to_vr);
                    orders.push(k as i32 + 1);
                    der_values.push(*dk);
                }
            } else {
                values.push(taylor_value(u0, d, h / 2.0));
            }
        }
        let s = &mut self.subs[i];
        let r = s.slave.set_real(&scratch, &values).and_then(|_| {
            if der_vrs.is_empty() {
                Ok(())
            } else {
                s.slave
                    .set_real_input_derivatives(&der_vrs, &orders, &der_values)
            }
        });
        s.vrs = scratch;
        s.values = values;
        s.orders = orders;
        s.der_vrs = der_vrs;
        s.der_values = der_values;
        r
    }

    /// One attempt at [t, t+h]; on failure returns the failing subsystem and leaves the FMUs wherever
    /// they got to (the caller rolls back).
    fn try_step(&mut self, h: f64) -> Result<(), StepError> {
        let t = self.t;
        // Per-step scratch lives in `self` (taken and put back): no allocation per macro step.
        let mut stepped = std::mem::take(&mut self.stepped);
        stepped.clear();
        stepped.resize(self.subs.len(), false);
        self.predicted.clear();
        let groups = std::mem::take(&mut self.groups);
        let r = self.try_groups(&groups, t, h, &mut stepped);
        self.groups = groups;
        self.stepped = stepped;
        r?;
        self.t = t + h;
        Ok(())
    }

    fn try_groups(
        &mut self,
        groups: &[Vec<usize>],
        t: f64,
        h: f64,
        stepped: &mut [bool],
    ) -> Result<(), StepError> {
        let fail = |s: &Subsystem, error, t_s| StepError {
            subsystem: s.name.clone(),
            error,
            t_s,
        };
        for group in groups {
            let coupling = Instant::now();
            for &i in group {
                self.set_inputs(i, t, h, stepped)
                    .map_err(|e| fail(&self.subs[i], e, t))?;
            }
            self.timing.coupling += coupling.elapsed();
            let choice = match &self.pool {
                Some(_) if group.len() > 1 => Some(self.stepping.next()),
                _ => None,
            };
            let wall = Instant::now();
            match (&self.pool, choice) {
                (Some(pool), Some(Stepping::Parallel)) => {
                    let mut members: Vec<&mut Subsystem> = self
                        .subs
                        .iter_mut()
                        .enumerate()
                        .filter(|(i, _)| group.contains(i))
                        .map(|(_, s)| s)
                        .collect();
                    let before: Vec<Duration> = members.iter().map(|m| m.step_wall).collect();
                    let results = pool.step(&mut members, t, h);
                    self.stepping.record(wall.elapsed());
                    // Time the group took beyond its slowest member: hand-over to and from the workers.
                    let slowest = members
                        .iter()
                        .zip(&before)
                        .map(|(m, b)| m.step_wall - *b)
                        .max()
                        .unwrap_or_default();
                    self.timing.parallel_overhead += wall.elapsed().saturating_sub(slowest);
                    self.timing.critical_path += slowest;
                    for (&i, r) in group.iter().zip(results) {
                        r.map_err(|e| fail(&self.subs[i], e, t))?;
                    }
                }
                _ => {
                    let mut failed = None;
                    for &i in group {
                        let before = self.subs[i].step_wall;
                        let r = self.subs[i].do_step(t, h);
                        self.timing.critical_path += self.subs[i].step_wall - before;
                        if let Err(e) = r {
                            failed = Some(fail(&self.subs[i], e, t));
                            break;
                        }
                    }
                    if choice.is_some() {
                        self.stepping.record(wall.elapsed());
                    }
                    if let Some(e) = failed {
                        return Err(e);
                    }
                }
            }
            let coupling = Instant::now();
            for &i in group {
                self.subs[i]
                    .read_coupling_into_history(t + h)
                    .map_err(|e| fail(&self.subs[i], e, t + h))?;
                stepped[i] = true;
            }
            self.timing.coupling += coupling.elapsed();
        }
        Ok(())
    }

    fn save_states(&mut self) -> Result<(), StepError> {
        let start = Instant::now();
        for s in &mut self.subs {
            let r = match &mut s.state {
                Some(st) => s.slave.update_state(st),
                None => s.slave.get_state().map(|st| s.state = Some(st)),
            };
            r.map_err(|error| StepError {
                subsystem: s.name.clone(),
                error,
                t_s: self.t,
            })?;
        }
        self.saved = Some(Saved {
            t: self.t,
            history: self.subs.iter().map(|s| s.history.clone()).collect(),
            replay: Vec::with_capacity(self.save_every),
        });
        self.timing.save_states += start.elapsed();
        Ok(())
    }

    fn restore_saved(&mut self) -> Result<Vec<f64>, StepError> {
        let saved = self
            .saved
            .take()
            .expect("a saved point exists when rollback is on");
        for (s, h) in self.subs.iter_mut().zip(&saved.history) {
            let st = s.state.as_ref().expect("saved before the step");
            s.slave.set_state(st).map_err(|error| StepError {
                subsystem: s.name.clone(),
                error,
                t_s: saved.t,
            })?;
            s.history = h.clone();
        }
        self.t = saved.t;
        let replay = saved.replay.clone();
        self.saved = Some(Saved {
            replay: Vec::with_capacity(self.save_every),
            ..saved
        });
        Ok(replay)
    }

    /// Largest |predicted - actual| / (atol + rtol |actual|) over the inputs extrapolated in the
    /// attempt just made (0 without control). NaN counts as infinitely large.
    fn coupling_error_ratio(&self) -> f64 {
        let Some(ctl) = self.config.control else {
            return 0.0;
        };
        self.predicted
            .iter()
            .map(|&(from, slot, pred)| {
                let actual = self.subs[from].history.back().expect("stepped").1[slot];
                let r = (pred - actual).abs() / (ctl.atol + ctl.rtol * actual.abs());
                if r.is_nan() {
                    f64::INFINITY
                } else {
                    r
                }
            })
            .fold(0.0, f64::max)
    }

    /// Advances by one macro step `h`. With rollback on, FMU states are saved every `save_every`
    /// macro steps (a save copies the air films' changed Jacobian factors, up to ~3 MB); a discarded
    /// (or, under [`StepControl`], too inaccurate) step restores that point, replays the steps since
    /// (the FMUs are deterministic, so the replay is exact), and retries the failed interval in two
    /// halves, recursively. Under control, a refined level covers the step with 2^level sub-steps.
    pub fn step(&mut self, h: f64) -> Result<(), StepError> {
        if self.config.control.is_some() && self.level > 0 {
            let mut acc = Accepted::default();
            self.cover(h, 0, self.level, &mut acc)?;
            self.finish_refined(acc);
            self.macro_steps += 1;
            return Ok(());
        }
        if self.config.rollback
            && self
                .saved
                .as_ref()
                .is_none_or(|s| s.replay.len() >= self.save_every || self.save_burst > 0)
        {
            self.save_states()?;
        }
        self.save_burst = self.save_burst.saturating_sub(1);
        let attempt = self.try_step(h).map(|()| self.coupling_error_ratio());
        match &attempt {
            Ok(ratio) if *ratio <= 1.0 => {
                let st = &mut self.control_stats;
                st.max_error_ratio = st.max_error_ratio.max(*ratio);
                st.macro_steps_by_level[0] += 1;
                if let Some(s) = self.saved.as_mut() {
                    s.replay.push(h);
                }
            }
            Ok(_)
            | Err(StepError {
                error:
                    CallError {
                        status: Status::Discard,
                        ..
                    },
                ..
            }) if self.config.rollback => {
                let t_fail = self.t - if attempt.is_ok() { h } else { 0.0 };
                match attempt {
                    Err(e) => self.events.push(Event::RolledBack {
                        subsystem: e.subsystem,
                        reason: e.error.to_string(),
                        t_from_s: t_fail,
                        t_to_s: t_fail + h,
                    }),
                    Ok(_) => {
                        self.control_stats.rejected += 1;
                        self.control_stats.rejected_work_macro_steps += 1.0;
                    }
                }
                self.save_burst = SAVE_BURST_STEPS;
                let replay = self.restore_saved()?;
                for dt in replay {
                    self.try_step(dt)?;
                    self.saved.as_mut().expect("saved").replay.push(dt);
                }
                self.retries += 1;
                let mut acc = Accepted::default();
                self.cover(h, 0, 1, &mut acc)?;
                if self.config.control.is_some() {
                    self.finish_refined(acc);
                }
                // The next macro step saves afresh: the replay list of this point would be inconsistent.
                self.saved = None;
            }
            Ok(_) => unreachable!("control requires rollback (checked when the system is built)"),
            Err(_) => return attempt.map(|_| ()),
        }
        self.macro_steps += 1;
        Ok(())
    }

    /// After a refined macro step: keep the deepest level it needed, or relax by one level when
    /// every sub-step was well within tolerance.
    fn finish_refined(&mut self, acc: Accepted) {
        let st = &mut self.control_stats;
        st.refined_macro_steps += 1;
        st.deepest_level = st.deepest_level.max(acc.deepest);
        st.macro_steps_by_level[acc.deepest as usize] += 1;
        st.max_error_ratio = st.max_error_ratio.max(acc.worst);
        self.level = acc.deepest;
        if acc.worst < RELAX_BELOW && self.level > 0 {
            self.level -= 1;
        }
        self.saved = None;
    }

    /// Covers [t, t+h] with sub-steps at depth `min_depth` or deeper (a sub-step at depth k is
    /// h_macro / 2^k), each saved before it is tried; a Discard or a coupling error above
    /// tolerance splits a sub-step in two, down to depth MAX_HALVINGS. At that depth a step with
    /// too large a coupling error is accepted (counted in the error ratio of the summary).
    fn cover(
        &mut self,
        h: f64,
        depth: u32,
        min_depth: u32,
        acc: &mut Accepted,
    ) -> Result<(), StepError> {
        if depth < min_depth {
            for _ in 0..2 {
                self.cover(h / 2.0, depth + 1, min_depth, acc)?;
            }
            return Ok(());
        }
        self.save_states()?;
        let split = match self.try_step(h) {
            Ok(()) => {
                let ratio = self.coupling_error_ratio();
                if ratio > 1.0 && depth < MAX_HALVINGS {
                    self.control_stats.rejected += 1;
                    self.control_stats.rejected_work_macro_steps += 0.5f64.powi(depth as i32);
                    true
                } else {
                    self.control_stats.sub_steps += 1;
                    acc.worst = acc.worst.max(ratio);
                    acc.deepest = acc.deepest.max(depth);
                    false
                }
            }
            Err(e) if e.error.status == Status::Discard && depth < MAX_HALVINGS => true,
            Err(e) => return Err(e),
        };
        if split {
            self.restore_saved()?;
            self.cover(h, depth, depth + 1, acc)?;
        }
        Ok(())
    }

    /// The integer outputs (solver counters) of every subsystem, by subsystem name; a subsystem
    /// whose FMU refuses the read (after an error) is left out.
    pub fn counters(&self) -> Vec<(String, Vec<(String, i32)>)> {
        self.subs
            .iter()
            .filter(|s| !s.counters.is_empty())
            .filter_map(|s| {
                let vrs: Vec<u32> = s.counters.iter().map(|c| c.1).collect();
                let mut v = vec![0; vrs.len()];
                s.slave.get_integer(&vrs, &mut v).ok()?;
                let named = s.counters.iter().map(|c| c.0.clone()).zip(v).collect();
                Some((s.name.clone(), named))
            })
            .collect()
    }

    /// Current value of a Real variable of subsystem `i`.
    pub fn get(&self, i: usize, vr: u32, out: &mut f64) -> Result<(), CallError> {
        let mut v = [0.0];
        self.subs[i].slave.get_real(&[vr], &mut v)?;
        *out = v[0];
        Ok(())
    }

    /// Current values of several Real variables of subsystem `i` (one fmi2GetReal call).
    pub fn get_many(&self, i: usize, vrs: &[u32], out: &mut [f64]) -> Result<(), CallError> {
        self.subs[i].slave.get_real(vrs, out)
    }

    /// Index of a subsystem by name.
    pub fn index(&self, name: &str) -> Option<usize> {
        self.subs.iter().position(|s| s.name == name)
    }

    /// The algorithm's state and every subsystem's serialized FMU state at the current macro
    /// point: what a checkpoint must keep to continue the run bit for bit.
    pub fn checkpoint(&self) -> Result<(AlgorithmState, Vec<Vec<u8>>), StepError> {
        let states = self
            .subs
            .iter()
            .map(|s| {
                let err = |error| StepError {
                    subsystem: s.name.clone(),
                    error,
                    t_s: self.t,
                };
                let st = s.slave.get_state().map_err(err)?;
                s.slave.serialize_state(&st).map_err(err)
            })
            .collect::<Result<Vec<_>, _>>()?;
        let state = AlgorithmState {
            t_s: self.t,
            histories: self.subs.iter().map(|s| s.history.clone()).collect(),
            refine_level: self.level,
        };
        Ok((state, states))
    }

    /// Why `state` (read back from a checkpoint) cannot be this co-simulation's state: the
    /// subsystem count, each coupling history's length (1 to 3 points), its vectors' length, its
    /// times (finite, increasing, the newest at `t_s`), its values (finite) and the refinement
    /// level must all be what a checkpoint of this system holds.
    pub fn check_state(&self, state: &AlgorithmState, n_fmu_states: usize) -> Result<(), String> {
        let t = state.t_s;
        if !(t.is_finite() && t >= 0.0) {
            return Err(format!("time {t} s is not a time of a run"));
        }
        if state.histories.len() != self.subs.len() || n_fmu_states != self.subs.len() {
            return Err(format!(
                "{} coupling histories and {n_fmu_states} FMU states for {} subsystems",
                state.histories.len(),
                self.subs.len()
            ));
        }
        if state.refine_level > MAX_HALVINGS {
            return Err(format!(
                "refinement level {} (at most {MAX_HALVINGS})",
                state.refine_level
            ));
        }
        for (s, h) in self.subs.iter().zip(&state.histories) {
            let bad = |what: String| Err(format!("coupling history of {}: {what}", s.name));
            if h.is_empty() || h.len() > 3 {
                return bad(format!("{} points (1 to 3 expected)", h.len()));
            }
            if let Some((_, v)) = h.iter().find(|p| p.1.len() != s.coupling_vrs.len()) {
                return bad(format!(
                    "{} values per point ({} expected)",
                    v.len(),
                    s.coupling_vrs.len()
                ));
            }
            if h.iter()
                .any(|p| !p.0.is_finite() || p.1.iter().any(|x| !x.is_finite()))
            {
                return bad("a time or value is not finite".into());
            }
            if h.iter().zip(h.iter().skip(1)).any(|(a, b)| a.0 >= b.0) {
                return bad("its times do not increase".into());
            }
            if h.back().map(|p| p.0.to_bits()) != Some(t.to_bits()) {
                return bad(format!("its newest point is not at t = {t} s"));
            }
        }
        Ok(())
    }

    /// Continues from a [`CoSim::checkpoint`]: restores the FMU states and the algorithm's state
    /// (after [`CoSim::check_state`]; a state that does not fit changes nothing).
    pub fn restore_checkpoint(
        &mut self,
        state: AlgorithmState,
        fmu_states: &[Vec<u8>],
    ) -> Result<(), RestoreError> {
        self.check_state(&state, fmu_states.len())
            .map_err(RestoreError::Mismatch)?;
        let t = state.t_s;
        for ((s, bytes), h) in self.subs.iter_mut().zip(fmu_states).zip(state.histories) {
            let err = |error| StepError {
                subsystem: s.name.clone(),
                error,
                t_s: t,
            };
            let st = s.slave.deserialize_state(bytes).map_err(err)?;
            s.slave.set_state(&st).map_err(err)?;
            s.history = h;
        }
        self.t = t;
        self.level = state.refine_level;
        // A roll-back point saved before belongs to another course of the run.
        self.saved = None;
        Ok(())
    }

    /// Keeps of each subsystem's coupling history only the current point, read afresh from the
    /// FMUs. For a state set from outside the run (a shooting method's start state, put in with
    /// [`CoSim::restore_checkpoint`]): the input polynomials then start again as at t = 0
    /// instead of spanning the jump.
    pub fn restart_coupling_histories(&mut self) -> Result<(), StepError> {
        let t = self.t;
        for s in &mut self.subs {
            let v = s.read_coupling().map_err(|error| StepError {
                subsystem: s.name.clone(),
                error,
                t_s: t,
            })?;
            s.history.clear();
            s.push_history(t, v);
        }
        self.saved = None;
        Ok(())
    }

    /// Current simulated time [s].
    pub fn time_s(&self) -> f64 {
        self.t
    }

    /// Instance names, in subsystem order.
    pub fn names(&self) -> impl Iterator<Item = &str> {
        self.subs.iter().map(|s| s.name.as_str())
    }

    /// Macro steps taken, and how many of them were retried after a Discard.
    pub fn macro_steps(&self) -> (u64, u64) {
        (self.macro_steps, self.retries)
    }

    /// Where the master's own time went.
    /// How parallel groups were stepped (None: no parallel group, or parallel off).
    pub fn stepping_stats(&self) -> Option<SteppingStats> {
        self.pool.as_ref().map(|_| self.stepping.stats())
    }

    pub fn timing(&self) -> &Timing {
        &self.timing
    }

    /// What the macro-step control did (None: fixed macro step).
    pub fn control_stats(&self) -> Option<ControlStats> {
        self.config.control.map(|_| self.control_stats)
    }

    /// Wall time spent in each subsystem's fmi2DoStep, by instance name.
    pub fn wall_in_fmus(&self) -> Vec<(String, Duration)> {
        self.subs
            .iter()
            .map(|s| (s.name.clone(), s.step_wall))
            .collect()
    }

    /// The events since the last call, oldest first.
    pub fn drain_events(&mut self) -> std::vec::Drain<'_, Event> {
        self.events.drain(..)
    }
}
