//! Variable-step BDF (orders 1-2) for the GGL equations, with local error control, modified
//! Newton with Jacobian and factorization reuse, and constraint-drift monitoring.
//!
//! * Order 1 on the very first step (the only history is the consistent initial state and its
//!   derivative), order 2 afterwards. BDF2 is A-stable, so the stiff ring modes and the fast
//!   gyroscopic terms do not limit the step; accuracy does.
//! * Inputs that jump at the start of a call (a master's new input polynomial starts at another
//!   value than the last one ended on) move the history onto the smooth solution through the
//!   post-jump state (`take_input_jump_into_history`), so BDF2 keeps its order through the kink
//!   instead of stepping through it with a first-order error.
//! * Predictor: order 1 uses y_n + h y'_n; order 2 the quadratic through y_{n-1}, y_n and y'_n.
//!   The local error of the corrector is K (y_{n+1} - y_pred) with K = 1/2 (BDF1) and
//!   K = (1 + w) / (2 + 3 w), w = h_n / h_{n-1} (BDF2; 2/5 at equal steps): the local truncation
//!   error of variable-step BDF2, h_n^2 (h_n + h_{n-1})^2 / (6 (2 h_n + h_{n-1})) y''', over the
//!   sum of it and the Hermite predictor's, h_n^2 (h_n + h_{n-1}) / 6 y''' (the textbook local
//!   error, from exact past values, as the air film's estimate). K = beta = (1 + w) / (1 + 2 w),
//!   2/3 at equal steps, would be 1.67x the local error.
//! * Only x and v enter the error and Newton norms; the multipliers are algebraic (index 2) and
//!   coordinates fixed by a constraint are excluded too (they are exact by construction).
//! * The iteration matrix is refactored only if beta h changes by more than 25 % (from the
//!   current factorization and from the three kept before it) or Newton converges slowly;
//!   force Jacobians are recomputed only after Newton trouble. In a
//!   co-simulation with fixed communication steps every step has the same h, so one
//!   factorization serves thousands of steps.
//! * Every quantity that influences future steps (history, step size, Jacobian, factors, Newton
//!   rate estimate) is in the struct and serializable: a clone or a restored copy continues
//!   bit-identically.

use crate::ggl::{self, Work};
use crate::linalg::Lu;
use crate::params::RotorError;
use crate::system::MultibodySystem;
use serde::{Deserialize, Serialize};
use std::sync::Arc;

/// Most steps the interval length adds to the budget of one call (1 s at h_max = 0.1 ms).
pub const MAX_INTERVAL_STEPS: u64 = 100_000;

/// Default of [`Tolerances::max_steps_per_call`]; defined with the rotor's parameters, whose
/// default it also is.
pub use crate::params::MAX_STEPS_PER_CALL;

#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct Tolerances {
    pub rtol: f64,
    /// For coordinates [m, rad].
    pub atol_pos: f64,
    /// For velocities [m/s, rad/s].
    pub atol_vel: f64,
    pub h_max_s: f64,
    pub h_init_s: f64,
    pub h_min_s: f64,
    /// false: no local error test, every step is h_max (order checks, fixed-step studies).
    pub error_control: bool,
    /// Internal steps (accepted + rejected) allowed in one `advance_to` call beyond ten times the
    /// steps of size h_max the interval needs (that part capped at [`MAX_INTERVAL_STEPS`]); more
    /// end in a StepFailure. Like CVODE's `mxstep`:
    /// a pathological parameter set (a tiny mass under a large force) must fail in milliseconds
    /// instead of integrating for hours; very tight tolerances need a larger budget.
    pub max_steps_per_call: u64,
}

impl Default for Tolerances {
    fn default() -> Self {
        Tolerances {
            rtol: 1e-6,
            atol_pos: 1e-9,
            atol_vel: 1e-6,
            h_max_s: 1e-3,
            h_init_s: 1e-6,
            h_min_s: 1e-14,
            error_control: true,
            max_steps_per_call: MAX_STEPS_PER_CALL,
        }
    }
}

/// What one `advance` did.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct StepStats {
    pub steps: u64,
    pub rejected_steps: u64,
    pub newton_iterations: u64,
    pub newton_failures: u64,
    pub jacobian_evaluations: u64,
    pub factorizations: u64,
    /// Largest |g| (position-level constraint residual) after any step [m or rad].
    pub max_drift_pos: f64,
    /// Largest |g'| (velocity-level residual) after any step.
    pub max_drift_vel: f64,
    /// Last step size taken [s].
    pub h_last_s: f64,
}

impl StepStats {
    pub fn accumulate(&mut self, o: &StepStats) {
        self.steps += o.steps;
        self.rejected_steps += o.rejected_steps;
        self.newton_iterations += o.newton_iterations;
        self.newton_failures += o.newton_failures;
        self.jacobian_evaluations += o.jacobian_evaluations;
        self.factorizations += o.factorizations;
        self.max_drift_pos = self.max_drift_pos.max(o.max_drift_pos);
        self.max_drift_vel = self.max_drift_vel.max(o.max_drift_vel);
        self.h_last_s = o.h_last_s;
    }
}

#[derive(Clone, Debug, Serialize, Deserialize)]
struct JacCache {
    fx: Vec<f64>,
    fv: Vec<f64>,
    /// Mass-matrix blocks, 36 values per body.
    m_flat: Vec<f64>,
    /// [M G^T; G 0] with these mass blocks, factored when an input jump first needs it. Not
    /// serialized: a restored state factors it again from `m_flat`, to the same bits, and its
    /// saved form stays as small as before (a run-up's checkpoints).
    #[serde(skip)]
    constrained_mass: Option<Arc<Lu>>,
}

/// `advance_to`'s working vectors, kept between its calls: a run-up calls it ~54 000 times, and
/// making them anew each time (ten vectors, and one more per step for the error weights and the
/// accepted state) was ~8 % of the rotor's CPU samples in a path-1 run-up. Not
/// part of the state: a clone (a master's roll-back copy before every macro step) or a restored
/// state starts without them, and `advance_to` resets them to what new vectors held (zeros, an
/// empty contact memo), so the results are the same bits.
#[derive(Debug, Default)]
struct AdvanceScratch(Option<Box<AdvanceBuffers>>);

impl Clone for AdvanceScratch {
    fn clone(&self) -> Self {
        AdvanceScratch(None)
    }
}

#[derive(Debug)]
struct AdvanceBuffers {
    work: Work,
    u: Vec<f64>,
    w: Vec<f64>,
    r: Vec<f64>,
    psi: Vec<f64>,
    yp: Vec<f64>,
    /// The error weights of the current step ([`GglBdf::weights_into`]).
    wt: Vec<f64>,
}

impl AdvanceBuffers {
    fn new(n_bodies: usize, n_inputs: usize, ny: usize, nw: usize) -> AdvanceBuffers {
        AdvanceBuffers {
            work: Work::new(n_bodies),
            u: vec![0.0; n_inputs],
            w: vec![0.0; nw],
            r: vec![0.0; nw],
            psi: vec![0.0; ny],
            yp: vec![0.0; ny],
            wt: vec![0.0; ny],
        }
    }

    /// Back to what [`AdvanceBuffers::new`] gives, without allocating.
    fn reset(&mut self) {
        let AdvanceBuffers {
            work,
            u,
            w,
            r,
            psi,
            yp,
            wt,
        } = self;
        for m in &mut work.m_blocks {
            m.fill(0.0);
        }
        for v in [
            &mut work.f,
            &mut work.tmp,
            &mut work.tmp2,
            u,
            w,
            r,
            psi,
            yp,
            wt,
        ] {
            v.fill(0.0);
        }
        work.contacts.clear();
    }
}

/// The integrator together with the system it integrates.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct GglBdf {
    pub sys: MultibodySystem,
    g_mat: Vec<f64>,
    tol: Tolerances,
    /// Components of y = [x, v] that enter the error and Newton norms.
    mask: Vec<bool>,
    t: f64,
    y: Vec<f64>,
    yd: Vec<f64>,
    lam: Vec<f64>,
    mu: Vec<f64>,
    prev: Option<(f64, Vec<f64>)>,
    h_ctrl: f64,
    jac: Option<JacCache>,
    /// Shared (as the spares and the constrained mass matrix) with the copies a master saves
    /// for its roll-back before every macro step: a factorization is never changed once made,
    /// so a saved state costs a reference, not a copy of four factorizations.
    lu: Option<Arc<Lu>>,
    lu_beta_h: f64,
    /// Newton rate estimate rate / (1 - rate) (DASSL's S).
    newton_s: f64,
    /// The factorizations before the current one (same force Jacobians), most recent first, at
    /// most [`SPARE_FACTORIZATIONS`], each with its beta h and Newton rate estimate. A rejected
    /// step refactorizes for its shorter step, and the next macro step goes back to the former
    /// size: in path 1's large whirl nearly every macro step did so, 47 011 factorizations in
    /// 3 s. Where the master refines its macro steps (journals riding on their rings) the steps
    /// follow the refinement levels, halves of each other, and come back to them.
    lu_prev: Vec<(Arc<Lu>, f64, f64)>,
    u_last: Vec<f64>,
    n_inputs: usize,
    drift_pos: f64,
    drift_vel: f64,
    pub totals: StepStats,
    /// `advance_to`'s working vectors, kept between its calls (not part of the state).
    #[serde(skip)]
    scratch: AdvanceScratch,
    /// The last step's weighted local error estimate (the tests compare it with the true error).
    #[cfg(test)]
    #[serde(skip)]
    last_error_estimate: f64,
}

/// K of the BDF2 error estimate K (y_{n+1} - y_pred) for the step ratio w = h_n / h_{n-1}: the
/// corrector's local truncation error over the sum of it and the predictor's (module header).
fn bdf2_error_factor(w: f64) -> f64 {
    (1.0 + w) / (2.0 + 3.0 * w)
}

const NEWTON_MAX_IT: usize = 4;
/// Factorizations kept besides the current one (see `GglBdf::lu_prev`).
const SPARE_FACTORIZATIONS: usize = 3;

/// Writes the input vector u(t).
pub type InputFn<'a> = dyn FnMut(f64, &mut [f64]) -> Result<(), RotorError> + 'a;

impl GglBdf {
    /// Start at a consistent state (x0, v0) at t0; the initial derivative comes from the
    /// consistent accelerations with inputs `u0`.
    pub fn new(
        sys: MultibodySystem,
        tol: Tolerances,
        t0: f64,
        x0: Vec<f64>,
        v0: Vec<f64>,
        u0: Vec<f64>,
    ) -> Result<Self, RotorError> {
        let nq = sys.n_coords();
        let g_mat = ggl::constraint_jacobian(&sys);
        let mut mask = vec![true; 2 * nq];
        for c in &sys.constraints {
            mask[c.coord] = false;
            mask[nq + c.coord] = false;
        }
        let mut work = Work::new(sys.bodies.len());
        let (a0, lam) = ggl::consistent_acceleration(&sys, &g_mat, t0, &x0, &v0, &u0, &mut work)?;
        let mut y = x0;
        y.extend_from_slice(&v0);
        let mut yd = y[nq..].to_vec();
        yd.extend_from_slice(&a0);
        let nc = sys.n_constraints();
        let mut s = GglBdf {
            g_mat,
            tol,
            mask,
            t: t0,
            y,
            yd,
            lam,
            mu: vec![0.0; nc],
            prev: None,
            h_ctrl: if tol.error_control {
                tol.h_init_s.min(tol.h_max_s)
            } else {
                tol.h_max_s
            },
            jac: None,
            lu: None,
            lu_beta_h: 0.0,
            newton_s: 100.0,
            lu_prev: Vec::new(),
            n_inputs: u0.len(),
            u_last: u0,
            drift_pos: 0.0,
            drift_vel: 0.0,
            totals: StepStats::default(),
            scratch: AdvanceScratch::default(),
            #[cfg(test)]
            last_error_estimate: 0.0,
            sys,
        };
        s.update_drift();
        Ok(s)
    }

    pub fn t(&self) -> f64 {
        self.t
    }
    /// Coordinates x.
    pub fn x(&self) -> &[f64] {
        &self.y[..self.sys.n_coords()]
    }
    /// Velocities v.
    pub fn v(&self) -> &[f64] {
        &self.y[self.sys.n_coords()..]
    }
    /// Time derivative of [x, v] at the current point (the BDF derivative, or the consistent
    /// one at the start).
    pub fn ydot(&self) -> &[f64] {
        &self.yd
    }
    /// Lagrange multipliers lambda (constraint forces) and mu (GGL stabilization, ~0).
    pub fn multipliers(&self) -> (&[f64], &[f64]) {
        (&self.lam, &self.mu)
    }
    /// Current |g|max, |g'|max.
    pub fn drift(&self) -> (f64, f64) {
        (self.drift_pos, self.drift_vel)
    }
    pub fn inputs_last(&self) -> &[f64] {
        &self.u_last
    }
    pub fn tolerances(&self) -> Tolerances {
        self.tol
    }

    fn update_drift(&mut self) {
        let nq = self.sys.n_coords();
        let (x, v) = self.y.split_at(nq);
        let mut dp: f64 = 0.0;
        let mut dv: f64 = 0.0;
        for c in &self.sys.constraints {
            dp = dp.max(c.value(self.t, x).abs());
            dv = dv.max(c.rate(self.t, v).abs());
        }
        self.drift_pos = dp;
        self.drift_vel = dv;
    }

    /// The error weights 1 / (atol + rtol |y_i|) into `wt`.
    fn weights_into(&self, wt: &mut [f64]) {
        let nq = self.sys.n_coords();
        for (i, (w, yi)) in wt.iter_mut().zip(&self.y).enumerate() {
            let atol = if i < nq {
                self.tol.atol_pos
            } else {
                self.tol.atol_vel
            };
            *w = 1.0 / (atol + self.tol.rtol * yi.abs());
        }
    }

    fn wnorm(&self, d: &[f64], wt: &[f64]) -> f64 {
        let mut s = 0.0;
        let mut n = 0usize;
        for i in 0..self.mask.len() {
            if self.mask[i] {
                let e = d[i] * wt[i];
                s += e * e;
                n += 1;
            }
        }
        if n == 0 {
            0.0
        } else {
            (s / n as f64).sqrt()
        }
    }

    fn refresh_jacobian(&mut self, work: &mut Work, stats: &mut StepStats) {
        let nq = self.sys.n_coords();
        let (x, v) = self.y.split_at(nq);
        let (fx, fv, m_blocks) = ggl::force_jacobians(&self.sys, x, v, &self.u_last, work);
        self.jac = Some(JacCache {
            fx,
            fv,
            m_flat: m_blocks.concat(),
            constrained_mass: None,
        });
        self.lu = None;
        self.lu_prev.clear();
        stats.jacobian_evaluations += 1;
    }

    /// An iteration matrix for `beta_h`: the current one if within 25 %, else the most recent
    /// earlier factorization that is (it becomes the current one), else a new factorization.
    fn ensure_matrix(&mut self, beta_h: f64, stats: &mut StepStats) -> Result<(), RotorError> {
        let fits = |b: f64| (beta_h / b - 1.0).abs() <= 0.25;
        if self.lu.is_some() && fits(self.lu_beta_h) {
            return Ok(());
        }
        if let Some(i) = self.lu_prev.iter().position(|(_, b, _)| fits(*b)) {
            let (lu, b, s) = self.lu_prev.remove(i);
            self.retire_current();
            self.lu = Some(lu);
            self.lu_beta_h = b;
            self.newton_s = s;
            return Ok(());
        }
        self.factor(beta_h, stats)
    }

    /// The current factorization to the front of the spares (the oldest spare beyond
    /// [`SPARE_FACTORIZATIONS`] is dropped).
    fn retire_current(&mut self) {
        if let Some(cur) = self.lu.take() {
            self.lu_prev.insert(0, (cur, self.lu_beta_h, self.newton_s));
            self.lu_prev.truncate(SPARE_FACTORIZATIONS);
        }
    }

    fn factor(&mut self, beta_h: f64, stats: &mut StepStats) -> Result<(), RotorError> {
        self.retire_current();
        let nq = self.sys.n_coords();
        let nc = self.sys.n_constraints();
        let j = self.jac.as_ref().expect("jacobian present");
        self.lu = Some(Arc::new(ggl::iteration_matrix(
            nq,
            nc,
            &self.g_mat,
            &j.m_flat,
            &j.fx,
            &j.fv,
            beta_h,
        )?));
        self.lu_beta_h = beta_h;
        self.newton_s = 100.0;
        stats.factorizations += 1;
        Ok(())
    }

    /// A call's inputs `u_new` start where the last step's inputs `u_last` ended, but not at
    /// their value: the master's new input polynomial jumps by the coupling error. The solution
    /// then has a kink (the accelerations jump by da), through which BDF2 commits a local error of
    /// h da / 3, first order in h, that its error test rejects again and again. Moved instead: the
    /// history to the smooth solution that continues the post-jump one backwards, v - (t_n - t) da
    /// and x + (t_n - t)^2 da / 2; BDF2 then steps on it at its full order. Restarting at order 1
    /// removes the kink's error too but damps weakly growing whirls (docs/convergence.md).
    ///
    /// da comes from the mass matrix of the force Jacobians (factored once per Jacobian): it
    /// moves by micro-radians of tilt between refreshes, and an error of da of that relative size
    /// leaves a kink error of the same relative size.
    fn take_input_jump_into_history(
        &mut self,
        u_new: &[f64],
        work: &mut Work,
    ) -> Result<(), RotorError> {
        if u_new == self.u_last.as_slice() {
            return Ok(());
        }
        let nq = self.sys.n_coords();
        let (x, v) = self.y.split_at(nq);
        let du: Vec<f64> = u_new.iter().zip(&self.u_last).map(|(a, b)| a - b).collect();
        let fresh;
        let mass: &Lu = match &mut self.jac {
            Some(j) => {
                if j.constrained_mass.is_none() {
                    let blocks = j.m_flat.chunks(36);
                    j.constrained_mass = Some(Arc::new(ggl::constrained_mass_matrix(
                        &self.sys,
                        &self.g_mat,
                        blocks,
                        "acceleration jump",
                    )?));
                }
                j.constrained_mass.as_ref().expect("factored above")
            }
            None => {
                self.sys
                    .eval(x, v, &self.u_last, &mut work.m_blocks, &mut work.f);
                let blocks = work.m_blocks.iter().map(|m| m.as_slice());
                fresh = ggl::constrained_mass_matrix(
                    &self.sys,
                    &self.g_mat,
                    blocks,
                    "acceleration jump",
                )?;
                &fresh
            }
        };
        let (da, dlam) = ggl::acceleration_jump(&self.sys, mass, x, v, &du);
        let Some((tp, yprev)) = &mut self.prev else {
            return Ok(());
        };
        let hp = self.t - *tp;
        for (i, da) in da.iter().enumerate() {
            self.yd[nq + i] += da;
            yprev[i] += 0.5 * hp * hp * da;
            yprev[nq + i] -= hp * da;
        }
        for (lam, dlam) in self.lam.iter_mut().zip(&dlam) {
            *lam += dlam;
        }
        Ok(())
    }

    /// Integrate to `t_end`; `inputs(t, u)` writes the input vector at time t.
    pub fn advance_to(
        &mut self,
        t_end: f64,
        inputs: &mut InputFn,
    ) -> Result<StepStats, RotorError> {
        let ny = 2 * self.sys.n_coords();
        let nw = ny + 2 * self.sys.n_constraints();
        let mut buffers = match self.scratch.0.take() {
            Some(mut b) => {
                b.reset();
                b
            }
            None => Box::new(AdvanceBuffers::new(
                self.sys.bodies.len(),
                self.n_inputs,
                ny,
                nw,
            )),
        };
        let result = self.advance_with(t_end, inputs, &mut buffers);
        self.scratch.0 = Some(buffers);
        result
    }

    /// [`GglBdf::advance_to`] with its working vectors.
    fn advance_with(
        &mut self,
        t_end: f64,
        inputs: &mut InputFn,
        buffers: &mut AdvanceBuffers,
    ) -> Result<StepStats, RotorError> {
        let mut stats = StepStats::default();
        let nq = self.sys.n_coords();
        let nc = self.sys.n_constraints();
        let ny = 2 * nq;
        let nw = ny + 2 * nc;
        let AdvanceBuffers {
            work,
            u,
            w,
            r,
            psi,
            yp,
            wt,
        } = buffers;
        if self.prev.is_none() && self.t < t_end {
            // First step ever: the inputs at t0 are only known now; start from the consistent
            // accelerations they imply, so the order-1 predictor is consistent.
            inputs(self.t, u)?;
            let (x, v) = self.y.split_at(nq);
            let (a0, lam) =
                ggl::consistent_acceleration(&self.sys, &self.g_mat, self.t, x, v, u, work)?;
            self.yd[nq..].copy_from_slice(&a0);
            self.lam = lam;
        } else if self.prev.is_some() && self.t < t_end {
            inputs(self.t, u)?;
            self.take_input_jump_into_history(u, work)?;
        }
        // A budget of internal steps per call: a pathological parameter set (a tiny mass under a
        // large force) must end in a StepFailure (fmi2Discard) instead of running for hours. Long
        // intervals get 10 steps per h_max on top, but at most MAX_INTERVAL_STEPS: a 1e300 s
        // doStep would otherwise be a budget of billions of steps.
        let interval_steps = 10.0 * ((t_end - self.t) / self.tol.h_max_s);
        let budget = self.tol.max_steps_per_call
            + interval_steps.clamp(0.0, MAX_INTERVAL_STEPS as f64) as u64;
        while self.t < t_end {
            if stats.steps + stats.rejected_steps >= budget {
                return Err(RotorError::StepFailure {
                    t_s: self.t,
                    h_s: self.h_ctrl,
                    reason: format!("more than {budget} internal steps in one call"),
                });
            }
            let remaining = t_end - self.t;
            let mut h = self.h_ctrl.min(self.tol.h_max_s);
            if let Some((tp, _)) = &self.prev {
                // BDF2 is zero-stable for step ratios below 1 + sqrt(2).
                h = h.min(2.0 * (self.t - tp));
            }
            let mut clamped = false;
            if remaining <= h * (1.0 + 1e-9) {
                h = remaining;
                clamped = true;
            } else if remaining < 8.0 * h {
                // Split the rest of the interval into equal steps: successive communication
                // intervals then repeat the same step size and reuse the factorization.
                let n = (remaining / h * (1.0 - 1e-9)).ceil();
                h = remaining / n;
                clamped = true;
            }
            let mut jac_fresh = false;
            loop {
                if h.is_nan() || h < self.tol.h_min_s {
                    let e = RotorError::StepFailure {
                        t_s: self.t,
                        h_s: h,
                        reason: "step size below minimum".into(),
                    };
                    self.totals.accumulate(&stats);
                    return Err(e);
                }
                let t1 = if h == remaining || self.t + h > t_end {
                    t_end
                } else {
                    self.t + h
                };
                let order2 = self.prev.is_some();
                let beta;
                let k_err;
                if let Some((tp, yprev)) = &self.prev {
                    let hp = self.t - tp;
                    let om = h / hp;
                    let den = 1.0 + 2.0 * om;
                    beta = (1.0 + om) / den;
                    k_err = bdf2_error_factor(om);
                    let a = (1.0 + om) * (1.0 + om) / den;
                    let b = om * om / den;
                    for i in 0..ny {
                        psi[i] = a * self.y[i] - b * yprev[i];
                        let c = (yprev[i] - self.y[i] + hp * self.yd[i]) / (hp * hp);
                        yp[i] = self.y[i] + h * self.yd[i] + c * h * h;
                    }
                } else {
                    beta = 1.0;
                    k_err = 0.5;
                    for i in 0..ny {
                        psi[i] = self.y[i];
                        yp[i] = self.y[i] + h * self.yd[i];
                    }
                }
                let beta_h = beta * h;
                inputs(t1, u)?;
                if self.jac.is_none() {
                    self.refresh_jacobian(work, &mut stats);
                    jac_fresh = true;
                }
                self.ensure_matrix(beta_h, &mut stats)?;
                // Newton from the predictor.
                w[..ny].copy_from_slice(yp);
                for i in 0..nc {
                    w[ny + i] = beta_h * self.mu[i];
                    w[ny + nc + i] = beta_h * self.lam[i];
                }
                self.weights_into(wt);
                let mut converged = false;
                let mut nrm0 = 0.0;
                let mut iters_this = 0;
                for m in 0..NEWTON_MAX_IT {
                    ggl::residual(&self.sys, &self.g_mat, t1, w, psi, beta_h, u, work, r);
                    self.lu.as_ref().expect("factored").solve(r);
                    for i in 0..nw {
                        w[i] -= r[i];
                    }
                    iters_this += 1;
                    let nrm = self.wnorm(&r[..ny], wt);
                    if !nrm.is_finite() {
                        break;
                    }
                    if m == 0 {
                        nrm0 = nrm;
                        if nrm <= 1e-10 || self.newton_s * nrm <= 0.33 {
                            converged = true;
                            break;
                        }
                    } else {
                        let rate = (nrm / nrm0).powf(1.0 / m as f64);
                        if rate > 0.9 {
                            break;
                        }
                        self.newton_s = rate / (1.0 - rate);
                        if self.newton_s * nrm <= 0.33 {
                            converged = true;
                            break;
                        }
                    }
                }
                stats.newton_iterations += iters_this as u64;
                if !converged {
                    stats.newton_failures += 1;
                    if !jac_fresh {
                        self.jac = None; // re-linearize at the current point, same h
                        continue;
                    }
                    h *= 0.25;
                    clamped = false;
                    continue;
                }
                if iters_this >= 3 {
                    // Slow convergence: re-linearize before the next step.
                    self.jac = None;
                }
                // Local error estimate.
                for i in 0..ny {
                    r[i] = k_err * (w[i] - yp[i]);
                }
                let err = if self.tol.error_control {
                    self.wnorm(&r[..ny], wt)
                } else {
                    0.0
                };
                #[cfg(test)]
                {
                    self.last_error_estimate = err;
                }
                let p = if order2 { 3.0 } else { 2.0 };
                if err.is_nan() || err > 1.0 {
                    stats.rejected_steps += 1;
                    let fac = if err.is_finite() {
                        (0.9 * err.powf(-1.0 / p)).clamp(0.2, 0.9)
                    } else {
                        0.25
                    };
                    h *= fac;
                    clamped = false;
                    continue;
                }
                // Accept.
                // The new state goes into the buffer of the state two steps back.
                let mut y_new = match self.prev.take() {
                    Some((_, v)) => v,
                    None => vec![0.0; ny],
                };
                y_new.copy_from_slice(&w[..ny]);
                let yold = std::mem::replace(&mut self.y, y_new);
                for i in 0..ny {
                    self.yd[i] = (self.y[i] - psi[i]) / beta_h;
                }
                for i in 0..nc {
                    self.mu[i] = w[ny + i] / beta_h;
                    self.lam[i] = w[ny + nc + i] / beta_h;
                }
                self.prev = Some((self.t, yold));
                self.t = t1;
                self.u_last.copy_from_slice(u);
                self.update_drift();
                stats.steps += 1;
                stats.h_last_s = h;
                stats.max_drift_pos = stats.max_drift_pos.max(self.drift_pos);
                stats.max_drift_vel = stats.max_drift_vel.max(self.drift_vel);
                let mut fac = (0.9 * err.max(1e-10).powf(-1.0 / p)).clamp(0.2, 2.0);
                if (1.0..1.2).contains(&fac) {
                    fac = 1.0; // hysteresis: keep h (and the factorization)
                }
                let proposal = h * fac;
                self.h_ctrl = if clamped && fac >= 1.0 {
                    self.h_ctrl.max(proposal)
                } else {
                    proposal
                }
                .min(self.tol.h_max_s);
                break;
            }
        }
        self.totals.accumulate(&stats);
        Ok(stats)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::body::RigidBody;
    use crate::constraint::Constraint;
    use crate::system::ForceElement;

    /// Mass [kg], mount stiffness [N/m] and damping [N s/m] of the ring of `ring_on_mount`.
    const RING: (f64, f64, f64) = (0.05, 1e6, 20.0);

    /// A ring on its mount (x and y free, z and the rotations constrained): a damped linear
    /// oscillator with an exact flow.
    fn ring_on_mount() -> (MultibodySystem, impl Fn(f64, f64, f64) -> (f64, f64)) {
        let (m, c, d) = RING;
        let sys = MultibodySystem {
            bodies: vec![RigidBody {
                mass_kg: m,
                inertia_kg_m2: [[1e-5, 0.0, 0.0], [0.0, 1e-5, 0.0], [0.0, 0.0, 2e-5]],
                point_masses: vec![],
            }],
            constraints: (2..6).map(|i| Constraint::fixed(i, 0.0)).collect(),
            forces: vec![ForceElement::Mount {
                body: 0,
                anchor_m: [0.0, 0.0],
                c_n_m: c,
                d_n_s_m: d,
            }],
            gravity_m_s2: [0.0; 3],
        };
        let w = (c / m).sqrt();
        let zeta = d / (2.0 * (c * m).sqrt());
        let wd = w * (1.0 - zeta * zeta).sqrt();
        // (x, v) after t from (x0, v0).
        let flow = move |x0: f64, v0: f64, t: f64| {
            let b = (v0 + zeta * w * x0) / wd;
            let e = (-zeta * w * t).exp();
            let (s, co) = (wd * t).sin_cos();
            let x = e * (x0 * co + b * s);
            (x, -zeta * w * x + e * wd * (b * co - x0 * s))
        };
        (sys, flow)
    }

    /// [`ring_on_mount`] with the input pair (inputs 0 and 1) as a force on the ring's centre.
    fn ring_on_mount_with_input_force() -> (MultibodySystem, impl Fn(f64, f64, f64) -> (f64, f64)) {
        let (mut sys, flow) = ring_on_mount();
        sys.forces.push(ForceElement::InputForce {
            body: 0,
            s_m: [0.0; 3],
            input: 0,
            reaction_body: None,
        });
        (sys, flow)
    }

    /// One BDF2 step from exact past values (y_{n-1}, y_n and y'_n on the exact solution), w
    /// times as long as the step before: its error estimate must be its true local error. Before
    /// the fix (K = beta) the ratio was 1.67 at w = 1 (1.60-1.75 for w = 0.5-2).
    #[test]
    fn bdf2_error_estimate_matches_the_true_local_error() {
        let (sys, flow) = ring_on_mount();
        let h = 1e-6;
        let (m, c, d) = RING;
        // Position and velocity errors weigh alike for the ring's own frequency.
        let (atol_pos, atol_vel) = (1e-3, 1e-3 * (c / m).sqrt());
        let x0 = [1e-5, 0.0, 0.0, 0.0, 0.0, 0.0];
        // y = [x, v] (12 values) and y' = [v, a] on the exact solution at t.
        let exact = |t: f64| {
            let (x, v) = flow(x0[0], 0.0, t);
            let mut y = vec![0.0; 12];
            let mut yd = vec![0.0; 12];
            (y[0], y[6]) = (x, v);
            (yd[0], yd[6]) = (v, -(c * x + d * v) / m);
            (y, yd)
        };
        for w in [1.0, 2.0, 0.5, 1.5, 0.7] {
            // Tolerances so loose that the step is accepted as asked.
            let tol = Tolerances {
                rtol: 0.0,
                atol_pos,
                atol_vel,
                h_max_s: 2.0 * h,
                h_init_s: h,
                ..Default::default()
            };
            let mut ig =
                GglBdf::new(sys.clone(), tol, 0.0, x0.to_vec(), vec![0.0; 6], vec![]).unwrap();
            let t_n = 30.0 * h;
            (ig.y, ig.yd) = exact(t_n);
            ig.prev = Some((t_n - h, exact(t_n - h).0));
            (ig.t, ig.h_ctrl) = (t_n, 2.0 * h);
            let st = ig.advance_to(t_n + w * h, &mut |_, _| Ok(())).unwrap();
            assert_eq!((st.steps, st.rejected_steps), (1, 0));
            let (y_exact, _) = exact(t_n + w * h);
            // The norm's four components: x, y, vx, vy (y stays 0).
            let ex = (ig.x()[0] - y_exact[0]) / atol_pos;
            let ev = (ig.v()[0] - y_exact[6]) / atol_vel;
            let actual = ((ex * ex + ev * ev) / 4.0).sqrt();
            let ratio = ig.last_error_estimate / actual;
            println!(
                "w = {w}: estimate {:.4e}, actual {actual:.4e}, ratio {ratio:.4}",
                ig.last_error_estimate
            );
            assert!(
                actual > 1e-12,
                "the local error must dwarf round-off ({actual})"
            );
            assert!(
                (ratio - 1.0).abs() < 0.02,
                "w = {w}: estimate / actual = {ratio}"
            );
        }
    }

    /// The ring on its mount under an input force that is constant over each call and jumps
    /// from one call to the next, as the master's input polynomials jump by their coupling error,
    /// every step h_max long: the error at the end must fall at second order in h. Before the
    /// jump went into BDF2's history each jump left an error of h da / 3 in the velocity, and the
    /// error fell at first order (orders 1.11 and 1.06 here, errors 7x larger at 2 steps per call).
    #[test]
    fn input_jumps_between_calls_keep_second_order() {
        let (sys, flow) = ring_on_mount_with_input_force();
        let (_, c, _) = RING;
        let (call_s, n_calls) = (40e-6, 50);
        let force_n = |k: usize| [20.0 * (1.3 * k as f64).cos(), 0.0];
        let x0 = [1e-5, 0.0, 0.0, 0.0, 0.0, 0.0];
        // The exact solution: the free flow about each call's static equilibrium F / c.
        let (mut x, mut v) = (x0[0], 0.0);
        for k in 0..n_calls {
            let x_eq = force_n(k)[0] / c;
            let (xr, vr) = flow(x - x_eq, v, call_s);
            (x, v) = (xr + x_eq, vr);
        }
        let mut errors = vec![];
        for steps_per_call in [2, 4, 8] {
            let h = call_s / steps_per_call as f64;
            let tol = Tolerances {
                h_max_s: h,
                h_init_s: h,
                error_control: false,
                ..Default::default()
            };
            let u0 = force_n(0).to_vec();
            let mut ig = GglBdf::new(sys.clone(), tol, 0.0, x0.to_vec(), vec![0.0; 6], u0).unwrap();
            for k in 0..n_calls {
                let f = force_n(k);
                let t_end = (k + 1) as f64 * call_s;
                let st = ig
                    .advance_to(t_end, &mut |_, u| {
                        u.copy_from_slice(&f);
                        Ok(())
                    })
                    .unwrap();
                assert_eq!(st.steps, steps_per_call);
            }
            let ex = (ig.x()[0] - x) / x0[0];
            let ev = (ig.v()[0] - v) / (x0[0] * (c / RING.0).sqrt());
            errors.push(ex.hypot(ev));
        }
        for pair in errors.windows(2) {
            let order = (pair[0] / pair[1]).log2();
            println!(
                "errors {:.3e} -> {:.3e}: order {order:.2}",
                pair[0], pair[1]
            );
            assert!(order > 1.8, "order {order:.2} (errors {errors:?})");
        }
    }

    /// The working vectors kept between calls give the same bits as new ones: one integrator
    /// keeps them, its twin is a clone before every call (a clone starts without them, as a
    /// master's roll-back copy does), under input jumps and the error control's own steps.
    #[test]
    fn kept_working_vectors_give_the_bits_of_new_ones() {
        let (sys, _) = ring_on_mount_with_input_force();
        let force_n = |k: usize| [20.0 * (1.3 * k as f64).cos(), 5.0 * (0.7 * k as f64).sin()];
        let x0 = [1e-5, -2e-6, 0.0, 0.0, 0.0, 0.0];
        let tol = Tolerances::default();
        let u0 = force_n(0).to_vec();
        let mut kept = GglBdf::new(sys, tol, 0.0, x0.to_vec(), vec![0.0; 6], u0).unwrap();
        let mut fresh = kept.clone();
        let mut steps = 0;
        for k in 0..60 {
            let f = force_n(k);
            let t_end = (k + 1) as f64 * 50e-6;
            let mut input = |_: f64, u: &mut [f64]| {
                u.copy_from_slice(&f);
                Ok(())
            };
            steps += kept.advance_to(t_end, &mut input).unwrap().steps;
            fresh = fresh.clone();
            assert!(fresh.scratch.0.is_none());
            fresh.advance_to(t_end, &mut input).unwrap();
            let bits = |ig: &GglBdf| -> Vec<u64> {
                ig.x().iter().chain(ig.v()).map(|v| v.to_bits()).collect()
            };
            assert_eq!(bits(&kept), bits(&fresh), "call {k}");
        }
        assert!(steps > 60, "{steps} steps: some calls take more than one");
    }

    /// Communication intervals of 10 us and 5 us in turn, every step as long as its interval:
    /// beta h alternates between two values 60 % apart. The previous factorization serves the
    /// way back, so two factorizations serve the whole run (instead of one per call),
    /// and the ring still follows its exact flow.
    #[test]
    fn alternating_step_sizes_reuse_the_previous_factorization() {
        let (sys, flow) = ring_on_mount();
        let tol = Tolerances {
            h_max_s: 10e-6,
            h_init_s: 5e-6,
            error_control: false,
            ..Default::default()
        };
        let x0 = [1e-5, 0.0, 0.0, 0.0, 0.0, 0.0];
        let mut ig = GglBdf::new(sys, tol, 0.0, x0.to_vec(), vec![0.0; 6], vec![]).unwrap();
        let mut t = 0.0;
        let mut total = StepStats::default();
        for call in 0..200 {
            t += if call % 2 == 0 { 5e-6 } else { 10e-6 };
            let st = ig.advance_to(t, &mut |_, _| Ok(())).unwrap();
            total.accumulate(&st);
        }
        assert_eq!(total.steps, 200, "one step per interval");
        // Order 1 on the first step, then the two BDF2 step ratios (0.5 and 2).
        assert!(
            total.factorizations <= 3,
            "{} factorizations for 200 steps",
            total.factorizations
        );
        let (x, _) = flow(x0[0], 0.0, t);
        // BDF2 at 5-10 us on a 712 Hz oscillator over 1.5 ms: a few per cent of the amplitude.
        assert!(
            (ig.x()[0] - x).abs() < 0.05 * x0[0],
            "x {:.4e} against the exact {x:.4e}",
            ig.x()[0]
        );
    }
}
