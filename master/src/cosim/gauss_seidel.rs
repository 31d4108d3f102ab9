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

use super::parallel::StepPool;
use super::polynomial::{taylor_derivatives, taylor_value};
use fmi2::importer::{CallError, Fmu, FmuState, ModelDescription, Slave};
use fmi2::Status;
use std::collections::VecDeque;
use std::time::{Duration, Instant};

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Scheme {
    GaussSeidel,
    Jacobi,
}

/// An input fed by another subsystem's output.
#[derive(Clone, Debug)]
pub struct Link {
    pub to_vr: u32,
    pub from: usize,
    /// Index into the source's `coupling_vrs`.
    pub from_slot: usize,
}

/// One FMU instance in the co-simulation.
pub struct Subsystem {
    pub name: String,
    pub slave: Slave,
    pub can_interpolate: bool,
    pub inputs: Vec<Link>,
    /// Outputs that other subsystems read, in slot order.
    pub coupling_vrs: Vec<u32>,
    /// Coupling outputs at the last macro points, oldest first (at most 3 kept).
    pub history: VecDeque<(f64, Vec<f64>)>,
    state: Option<FmuState>,
    /// Wall time spent in this FMU's fmi2DoStep.
    pub step_wall: Duration,
    /// Integer outputs (name, value reference): solver counters, reported at the end of a run.
    pub counters: Vec<(String, u32)>,
    // Scratch for setting inputs without allocating each step.
    vrs: Vec<u32>,
    values: Vec<f64>,
    orders: Vec<i32>,
    der_vrs: Vec<u32>,
    der_values: Vec<f64>,
}

impl Subsystem {
    pub fn new(name: String, slave: Slave, md: &ModelDescription) -> Self {
        Subsystem {
            name,
            slave,
            can_interpolate: md.can_interpolate_inputs,
            inputs: vec![],
            coupling_vrs: vec![],
            history: VecDeque::with_capacity(4),
            state: None,
            step_wall: Duration::ZERO,
            counters: md
                .variables
                .iter()
                .filter(|v| {
                    v.var_type == fmi2::variables::VarType::Integer
                        && v.causality == fmi2::variables::Causality::Output
                })
                .map(|v| (v.name.clone(), v.vr))
                .collect(),
            vrs: vec![],
            values: vec![],
            orders: vec![],
            der_vrs: vec![],
            der_values: vec![],
        }
    }

    /// Slot of an output in `coupling_vrs` (added if new).
    pub fn coupling_slot(&mut self, vr: u32) -> usize {
        match self.coupling_vrs.iter().position(|v| *v == vr) {
            Some(i) => i,
            None => {
                self.coupling_vrs.push(vr);
                self.coupling_vrs.len() - 1
            }
        }
    }

    fn read_coupling(&self) -> Result<Vec<f64>, CallError> {
        let mut v = vec![0.0; self.coupling_vrs.len()];
        self.slave.get_real(&self.coupling_vrs, &mut v)?;
        Ok(v)
    }

    /// Reads the coupling outputs at `t` as the newest macro point, reusing the oldest point's
    /// vector once three are kept (no allocation per macro step).
    fn read_coupling_into_history(&mut self, t: f64) -> Result<(), CallError> {
        let mut v = if self.history.len() == 3 {
            self.history.pop_front().map(|p| p.1).unwrap_or_default()
        } else {
            vec![0.0; self.coupling_vrs.len()]
        };
        v.resize(self.coupling_vrs.len(), 0.0);
        self.slave.get_real(&self.coupling_vrs, &mut v)?;
        // A NaN or infinite output would travel silently into the other FMUs' inputs.
        let finite = v.iter().all(|x| x.is_finite());
        self.history.push_back((t, v));
        if !finite {
            return Err(CallError {
                function: "fmi2GetReal (a coupling output is NaN or infinite)",
                status: Status::Error,
            });
        }
        Ok(())
    }

    fn push_history(&mut self, t: f64, v: Vec<f64>) {
        if self.history.len() == 3 {
            self.history.pop_front();
        }
        self.history.push_back((t, v));
    }

    pub(crate) fn do_step(&mut self, t: f64, h: f64) -> Result<(), CallError> {
        let start = Instant::now();
        let r = self.slave.do_step(t, h);
        self.step_wall += start.elapsed();
        r
    }
}

/// Why a macro step failed.
#[derive(Debug)]
pub struct StepError {
    pub subsystem: String,
    pub error: CallError,
    pub t_s: f64,
}

impl std::fmt::Display for StepError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "{}: {} at t = {} s (see its log above)",
            self.subsystem, self.error, self.t_s
        )
    }
}

impl std::error::Error for StepError {}

pub struct CoSim {
    pub subs: Vec<Subsystem>,
    /// Groups of subsystem indices in stepping order; members of a group run in parallel.
    pub groups: Vec<Vec<usize>>,
    pub scheme: Scheme,
    pub extrapolation_order: usize,
    pub interpolation_order: usize,
    pub rollback: bool,
    pub parallel: bool,
    pub t: f64,
    pub macro_steps: u64,
    pub retries: u64,
    pub timing: Timing,
    /// Macro-step control by the coupling error; None: fixed macro step (Discard still halves).
    pub control: Option<StepControl>,
    /// Current refinement: the macro step is covered by 2^level sub-steps.
    pub level: u32,
    pub control_stats: ControlStats,
    /// Scratch: extrapolated inputs' predictions at T_N+1 as (source, slot, value).
    predicted: Vec<(usize, usize, f64)>,
    pool: Option<StepPool>,
    /// Scratch: which subsystems have stepped in the current macro step.
    stepped: Vec<bool>,
    /// Macro steps between saved FMU states when rollback is on.
    pub save_every: usize,
    /// Macro steps left in which states are saved at every step: set after a rejection or a Discard, because
    /// where the control acted once (a whirl grazing the ring) it acts again within ~100 steps,
    /// and a replay of up to `save_every` steps per rejection costs more than saving each step.
    save_burst: u64,
    saved: Option<Saved>,
    /// The loaded FMUs (their libraries must outlive the instances).
    _fmus: Vec<Fmu>,
}

/// Deepest refinement: 1/2^MAX_HALVINGS of the macro step (0.31 us at 20 us).
pub const MAX_HALVINGS: u32 = 6;

/// Relax the refinement by one level when the largest error ratio of a macro step is below this
/// (halving the step divides an order-1 extrapolation error by 4: the coarser level then still
/// keeps the error below 1/2 of the tolerance).
const RELAX_BELOW: f64 = 0.125;

/// Macro steps with a state save at every step after a rejection or a Discard (see `save_burst`).
const SAVE_BURST_STEPS: u64 = 1000;

/// Macro steps between state saves otherwise. A save copies the factorized Jacobians that changed
/// since the last one (~3 MB for two films after a few hundred steps, ~0.4 ms); a Discard replays
/// at most this many steps (~0.5 s of wall time), and trouble then switches to a save per step.
const SAVE_EVERY: usize = 1000;

/// Tolerance of the coupling error |extrapolated input - actual output| at T_N+1, in the units of
/// the extrapolated inputs (forces in N for the run-up).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct StepControl {
    pub rtol: f64,
    pub atol: f64,
}

impl StepControl {
    /// The one check of a tolerance pair, for system files and command-line flags alike.
    pub fn new(rtol: f64, atol: f64) -> Result<Self, &'static str> {
        let ok = |x: f64| x.is_finite() && x >= 0.0;
        if ok(rtol) && ok(atol) && rtol + atol > 0.0 {
            Ok(StepControl { rtol, atol })
        } else {
            Err("rtol and atol must be finite, >= 0 and not both 0")
        }
    }
}

/// What the macro-step control did over a run.
#[derive(Clone, Copy, Debug, Default, PartialEq, serde::Serialize)]
pub struct ControlStats {
    /// Attempts rejected for their coupling error.
    pub rejected: u64,
    /// Macro steps covered by more than one sub-step.
    pub refined_macro_steps: u64,
    /// Deepest refinement level used (sub-step = macro step / 2^level).
    pub deepest_level: u32,
    /// Largest error ratio of an accepted attempt.
    pub max_error_ratio: f64,
    /// Accepted sub-steps of the refined macro steps.
    pub sub_steps: u64,
    /// Length of the rejected attempts, in macro steps: the work the control threw away.
    pub rejected_work_macro_steps: f64,
    /// Macro steps by the deepest level they used (index 0: one sub-step, the nominal step).
    pub macro_steps_by_level: [u64; MAX_HALVINGS as usize + 1],
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
    #[allow(clippy::too_many_arguments)]
    pub fn initialize(
        subs: Vec<Subsystem>,
        order: Vec<usize>,
        scheme: Scheme,
        extrapolation_order: usize,
        interpolation_order: usize,
        rollback: bool,
        parallel: bool,
        fmus: Vec<Fmu>,
    ) -> Result<CoSim, StepError> {
        let groups = match scheme {
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
        let pool = (parallel && largest > 1).then(|| StepPool::new(largest));
        let mut c = CoSim {
            subs,
            groups,
            scheme,
            extrapolation_order,
            interpolation_order,
            rollback,
            parallel,
            t: 0.0,
            macro_steps: 0,
            retries: 0,
            timing: Timing::default(),
            control: None,
            level: 0,
            control_stats: ControlStats::default(),
            predicted: vec![],
            pool,
            stepped: vec![],
            save_every: SAVE_EVERY,
            save_burst: 0,
            saved: None,
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
        let (extrap, interp) = (self.extrapolation_order, self.interpolation_order);
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
            if self.control.is_some() && !stepped[l.from] {
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
            match &self.pool {
                Some(pool) if group.len() > 1 => {
                    let wall = Instant::now();
                    let mut members: Vec<&mut Subsystem> = self
                        .subs
                        .iter_mut()
                        .enumerate()
                        .filter(|(i, _)| group.contains(i))
                        .map(|(_, s)| s)
                        .collect();
                    let before: Vec<Duration> = members.iter().map(|m| m.step_wall).collect();
                    let results = pool.step(&mut members, t, h);
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
                    for &i in group {
                        let before = self.subs[i].step_wall;
                        let r = self.subs[i].do_step(t, h);
                        self.timing.critical_path += self.subs[i].step_wall - before;
                        r.map_err(|e| fail(&self.subs[i], e, t))?;
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
        let Some(ctl) = self.control else {
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
        if self.control.is_some() && self.level > 0 {
            let mut acc = Accepted::default();
            self.cover(h, 0, self.level, &mut acc)?;
            self.finish_refined(acc);
            self.macro_steps += 1;
            return Ok(());
        }
        if self.rollback
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
            }) if self.rollback => {
                let t_fail = self.t - if attempt.is_ok() { h } else { 0.0 };
                match attempt {
                    Err(e) => eprintln!(
                        "{e}: rolling back and retrying [{t_fail} s, {} s] in halves",
                        t_fail + h
                    ),
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
                if self.control.is_some() {
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

    /// Serialized FMU states of all subsystems at the current time (for checkpoints).
    pub fn serialize_states(&self) -> Result<Vec<Vec<u8>>, StepError> {
        self.subs
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
            .collect()
    }

    /// Restores serialized FMU states (from `serialize_states`) and the master's histories.
    pub fn restore_serialized(
        &mut self,
        t: f64,
        states: &[Vec<u8>],
        history: Vec<VecDeque<(f64, Vec<f64>)>>,
    ) -> Result<(), StepError> {
        for ((s, bytes), h) in self.subs.iter_mut().zip(states).zip(history) {
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
        Ok(())
    }
}
