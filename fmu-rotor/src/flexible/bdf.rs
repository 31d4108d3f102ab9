//! Variable-step BDF (orders 1-2) for an ODE y' = f(t, y) with a dense Jacobian: the flexible
//! rotor's integrator. The same method as the rigid rotor's (integrator.rs) without the
//! constraints: order 1 on the first step, then BDF2 (A-stable: the stiff shaft and ring modes
//! do not limit the step), the local error K (y_{n+1} - y_pred) against the Hermite predictor
//! through y_{n-1}, y_n and y'_n, K = (1 + w) / (2 + 3 w), w = h_n / h_{n-1}; modified Newton
//! with the iteration matrix I - beta h J factored anew when none of the four kept factorizations
//! lies within 25 % of beta h and 1 % of the speed (the gyroscopic terms), or when Newton
//! converges slowly.
//!
//! An input that jumps at the start of a call (a master's new force polynomial) moves the
//! history onto the smooth solution through the post-jump derivative (y_{n-1} -= h_{n-1} dy'),
//! as the rigid rotor does, so BDF2 keeps its order through the kink.

use crate::integrator::StepStats;
use crate::linalg::Lu;
use crate::params::RotorError;
use serde::{Deserialize, Serialize};

/// The equations: f and its Jacobian (row-major), at the inputs of the current call.
pub trait Ode {
    fn dim(&self) -> usize;
    fn rhs(&mut self, t: f64, y: &[f64], ydot: &mut [f64]) -> Result<(), RotorError>;
    fn jacobian(&mut self, t: f64, y: &[f64], jac: &mut [f64]) -> Result<(), RotorError>;
    /// A number the Jacobian depends on besides y (the speed): a change of more than 1 % (or
    /// of 1 unit) refactors the iteration matrix.
    fn jacobian_parameter(&self, _t: f64) -> f64 {
        0.0
    }
}

#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct BdfTolerances {
    pub rtol: f64,
    pub h_max_s: f64,
    pub h_min_s: f64,
    pub max_steps_per_call: u64,
}

#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct Bdf {
    pub tol: BdfTolerances,
    /// Absolute tolerance of each component.
    pub atol: Vec<f64>,
    t: f64,
    y: Vec<f64>,
    ydot: Vec<f64>,
    /// y_{n-1} and h_{n-1} (none before the first step).
    prev: Option<(Vec<f64>, f64)>,
    h: f64,
    /// The factorizations kept, newest first (beta h, the Jacobian parameter, the factors): the
    /// last step of a communication interval is cut to its end, so two or three step sizes take
    /// turns, and each keeps its factors instead of refactoring at every turn.
    factors: Vec<(f64, f64, Lu)>,
    pub totals: StepStats,
}

/// Factorizations kept (the rigid rotor's integrator keeps as many).
const KEPT_FACTORS: usize = 4;

fn wrms(e: &[f64], y: &[f64], y2: &[f64], atol: &[f64], rtol: f64) -> f64 {
    let n = e.len();
    let s: f64 = (0..n)
        .map(|i| {
            let w = atol[i] + rtol * y[i].abs().max(y2[i].abs());
            (e[i] / w).powi(2)
        })
        .sum();
    (s / n as f64).sqrt()
}

impl Bdf {
    pub fn new(tol: BdfTolerances, atol: Vec<f64>, t0: f64, y0: Vec<f64>, h_init: f64) -> Bdf {
        let n = y0.len();
        Bdf {
            tol,
            atol,
            t: t0,
            y: y0,
            ydot: vec![0.0; n],
            prev: None,
            h: h_init,
            factors: Vec::new(),
            totals: StepStats::default(),
        }
    }
    pub fn t(&self) -> f64 {
        self.t
    }
    pub fn y(&self) -> &[f64] {
        &self.y
    }
    pub fn ydot(&self) -> &[f64] {
        &self.ydot
    }

    /// Starts again from `y` at the current time (order 1, no history).
    pub fn restart(&mut self, y: Vec<f64>) {
        self.y = y;
        self.prev = None;
        self.factors.clear();
    }

    fn factor(&mut self, ode: &mut dyn Ode, t: f64, y: &[f64], bh: f64) -> Result<(), RotorError> {
        let n = self.y.len();
        let mut j = vec![0.0; n * n];
        ode.jacobian(t, y, &mut j)?;
        for v in j.iter_mut() {
            *v *= -bh;
        }
        for i in 0..n {
            j[i * n + i] += 1.0;
        }
        let lu = Lu::factor(n, j, "the flexible rotor's iteration matrix")?;
        self.factors.insert(0, (bh, ode.jacobian_parameter(t), lu));
        self.factors.truncate(KEPT_FACTORS);
        self.totals.jacobian_evaluations += 1;
        self.totals.factorizations += 1;
        Ok(())
    }

    /// Integrates to `t_end`.
    pub fn advance_to(&mut self, ode: &mut dyn Ode, t_end: f64) -> Result<StepStats, RotorError> {
        let n = self.y.len();
        let mut stats = StepStats::default();
        // The derivative with this call's inputs; a jump moves the history (see the module doc).
        let mut f0 = vec![0.0; n];
        ode.rhs(self.t, &self.y, &mut f0)?;
        if let Some((yp, hp)) = &mut self.prev {
            for i in 0..n {
                yp[i] -= *hp * (f0[i] - self.ydot[i]);
            }
        }
        self.ydot = f0;
        let span = t_end - self.t;
        let budget = self.tol.max_steps_per_call
            + 10 * ((span / self.tol.h_max_s).ceil() as u64)
                .min(crate::integrator::MAX_INTERVAL_STEPS);
        let mut y_new = vec![0.0; n];
        let mut psi = vec![0.0; n];
        let mut g = vec![0.0; n];
        let mut fy = vec![0.0; n];
        let mut pred = vec![0.0; n];
        let mut err = vec![0.0; n];
        while self.t < t_end {
            if stats.steps + stats.rejected_steps >= budget {
                return Err(RotorError::StepFailure {
                    t_s: self.t,
                    h_s: self.h,
                    reason: format!("more than {budget} steps in one call"),
                });
            }
            let h_wanted = self.h.min(self.tol.h_max_s);
            let mut h = h_wanted.min(t_end - self.t);
            // No sliver of a step at the end.
            if t_end - (self.t + h) < 1e-3 * h {
                h = t_end - self.t;
            }
            let t1 = if h == t_end - self.t {
                t_end
            } else {
                self.t + h
            };
            // Coefficients: y_{n+1} - psi = beta h f(y_{n+1}).
            let (beta, k_err) = match &self.prev {
                None => {
                    psi.copy_from_slice(&self.y);
                    for i in 0..n {
                        pred[i] = self.y[i] + h * self.ydot[i];
                    }
                    (1.0, 0.5)
                }
                Some((yp, hp)) => {
                    let w = h / hp;
                    let d = 1.0 + 2.0 * w;
                    let a1 = (1.0 + w).powi(2) / d;
                    let a2 = -w * w / d;
                    for i in 0..n {
                        psi[i] = a1 * self.y[i] + a2 * yp[i];
                        let c = (yp[i] - self.y[i] + hp * self.ydot[i]) / (hp * hp);
                        pred[i] = self.y[i] + h * self.ydot[i] + c * h * h;
                    }
                    ((1.0 + w) / d, (1.0 + w) / (2.0 + 3.0 * w))
                }
            };
            let bh = beta * h;
            let param = ode.jacobian_parameter(t1);
            let fits = |f: &(f64, f64, Lu)| {
                (0.8..=1.25).contains(&(bh / f.0))
                    && (param - f.1).abs() <= 0.01 * f.1.abs().max(100.0)
            };
            match self.factors.iter().position(fits) {
                Some(0) => {}
                Some(k) => {
                    let f = self.factors.remove(k);
                    self.factors.insert(0, f);
                }
                None => self.factor(ode, t1, &pred, bh)?,
            }
            // Modified Newton from the predictor.
            y_new.copy_from_slice(&pred);
            let mut converged = false;
            let mut fresh = self.totals.jacobian_evaluations;
            let mut tries = 0;
            loop {
                let mut prev_norm = f64::INFINITY;
                let mut ok = false;
                for _ in 0..6 {
                    ode.rhs(t1, &y_new, &mut fy)?;
                    for i in 0..n {
                        g[i] = -(y_new[i] - psi[i] - bh * fy[i]);
                    }
                    self.factors[0].2.solve(&mut g);
                    for i in 0..n {
                        y_new[i] += g[i];
                    }
                    stats.newton_iterations += 1;
                    let norm = wrms(&g, &y_new, &self.y, &self.atol, self.tol.rtol);
                    if !norm.is_finite() {
                        break;
                    }
                    if norm < 1e-3 || (norm < 0.1 && norm < 0.2 * prev_norm) {
                        ok = true;
                        break;
                    }
                    if norm > 2.0 * prev_norm {
                        break;
                    }
                    prev_norm = norm;
                }
                if ok {
                    converged = true;
                    break;
                }
                tries += 1;
                stats.newton_failures += 1;
                if tries > 1 || fresh != self.totals.jacobian_evaluations {
                    break;
                }
                // A fresh Jacobian at the predictor, then once more.
                y_new.copy_from_slice(&pred);
                self.factor(ode, t1, &pred, bh)?;
                fresh = self.totals.jacobian_evaluations;
            }
            if !converged {
                stats.rejected_steps += 1;
                self.h = 0.25 * h;
                if self.h < self.tol.h_min_s {
                    return Err(RotorError::StepFailure {
                        t_s: self.t,
                        h_s: h,
                        reason: "Newton did not converge".into(),
                    });
                }
                continue;
            }
            for i in 0..n {
                err[i] = k_err * (y_new[i] - pred[i]);
            }
            let e = wrms(&err, &y_new, &self.y, &self.atol, self.tol.rtol);
            let order = if self.prev.is_none() { 1.0 } else { 2.0 };
            let factor = if e > 0.0 {
                (0.9 * e.powf(-1.0 / (order + 1.0))).clamp(0.2, 2.0)
            } else {
                2.0
            };
            if e > 1.0 || !e.is_finite() {
                stats.rejected_steps += 1;
                self.h = h * factor.min(0.9);
                if self.h < self.tol.h_min_s {
                    return Err(RotorError::StepFailure {
                        t_s: self.t,
                        h_s: h,
                        reason: "the local error test failed at the smallest step".into(),
                    });
                }
                continue;
            }
            // Accept.
            stats.steps += 1;
            let y_old = std::mem::replace(&mut self.y, y_new.clone());
            self.prev = Some((y_old, h));
            self.t = t1;
            ode.rhs(t1, &self.y, &mut self.ydot)?;
            // A step cut short by the end of the call does not shrink the next one.
            self.h = (h * factor).max(if h < h_wanted { h_wanted } else { 0.0 });
            stats.h_last_s = h;
        }
        self.totals.accumulate(&stats);
        Ok(stats)
    }
}
