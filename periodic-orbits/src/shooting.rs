//! Periodic orbits of an autonomous system by single shooting on its flow.
//!
//! The system is anything that can advance a state: [`Flow`] (an analytic test problem, or the
//! co-simulated rotor in its films). Unknowns are the start state x0 (n values) and the period
//! T; equations the periodicity phi_T(x0) - x0 = 0 (n) and a phase condition that pins the
//! orbit's start point on the plane through a reference point normal to the vector field there
//! (one). Newton with a finite-difference Jacobian whose n state columns are the monodromy matrix
//! M = d phi_T / d x0: its eigenvalues are the orbit's Floquet multipliers.
//! Everything is solved in scaled variables (state / `Flow::scale`, period / its first guess),
//! because the rotor's states mix metres (~1e-5) and metres per second (~1e-2).

use nalgebra::{Complex, DMatrix, DVector};

/// An autonomous system that can be advanced from any state.
pub trait Flow {
    /// Number of state variables.
    fn dim(&self) -> usize;
    /// A typical magnitude of each state variable (finite-difference steps and tolerances are
    /// relative to it). All positive.
    fn scale(&self) -> Vec<f64>;
    /// The states at the increasing times `at_s` (all > 0, [s]) when starting from `x0` at
    /// time 0.
    fn flow(&mut self, x0: &[f64], at_s: &[f64]) -> Result<Vec<Vec<f64>>, String>;
    /// Named measures of the orbit through `x0` with period `period_s` (e.g. the largest
    /// eccentricity per bearing), written next to each orbit. None by default.
    fn measures(&mut self, _x0: &[f64], _period_s: f64) -> Result<Vec<(String, f64)>, String> {
        Ok(Vec::new())
    }
}

/// How shooting works: a small policy object, as the defaults suit smooth flows.
#[derive(Clone, Copy, Debug)]
pub struct ShootingOptions {
    /// Finite-difference step of a state column, relative to the state's scale.
    pub fd_rel: f64,
    /// Step of the period column and of the vector field at x0, relative to the period.
    pub dt_rel: f64,
    /// Convergence: largest scaled residual (periodicity defect / scale).
    pub tol: f64,
    /// Newton iterations at most.
    pub max_iter: usize,
    /// A defect below this is accepted when no Newton step lowers it any more: the flow's own
    /// noise (adaptive steps inside the FMUs) is reached. Equal to `tol` for exact flows.
    pub noise_floor: f64,
}

impl Default for ShootingOptions {
    fn default() -> Self {
        ShootingOptions {
            fd_rel: 1e-6,
            dt_rel: 1e-6,
            tol: 1e-8,
            max_iter: 20,
            noise_floor: 1e-8,
        }
    }
}

/// A periodic orbit found by [`shoot`].
#[derive(Clone, Debug)]
pub struct PeriodicOrbit {
    pub x0: Vec<f64>,
    pub period_s: f64,
    /// d phi_T / d x0 at the converged orbit.
    pub monodromy: DMatrix<f64>,
    /// Eigenvalues of the monodromy matrix, largest modulus first; one of them is the trivial 1
    /// (a shift along the orbit).
    pub multipliers: Vec<Complex<f64>>,
    /// Newton iterations taken.
    pub iterations: usize,
    /// Largest scaled periodicity defect at the returned orbit.
    pub residual: f64,
}

impl PeriodicOrbit {
    /// The orbit with its multipliers (the monodromy matrix's eigenvalues).
    pub fn new(
        x0: Vec<f64>,
        period_s: f64,
        monodromy: DMatrix<f64>,
        iterations: usize,
        residual: f64,
    ) -> Self {
        let multipliers = multipliers_of(&monodromy);
        PeriodicOrbit {
            x0,
            period_s,
            monodromy,
            multipliers,
            iterations,
            residual,
        }
    }

    /// An orbit whose monodromy matrix was never formed (Newton-Krylov): its multipliers are
    /// given (the leading ones, largest modulus first); `monodromy` is empty.
    pub fn with_multipliers(
        x0: Vec<f64>,
        period_s: f64,
        multipliers: Vec<Complex<f64>>,
        iterations: usize,
        residual: f64,
    ) -> Self {
        PeriodicOrbit {
            x0,
            period_s,
            monodromy: DMatrix::zeros(0, 0),
            multipliers,
            iterations,
            residual,
        }
    }

    /// The multipliers without the trivial one (the one nearest to 1 + 0i).
    pub fn nontrivial_multipliers(&self) -> Vec<Complex<f64>> {
        let one = Complex::new(1.0, 0.0);
        let trivial = (0..self.multipliers.len()).min_by(|&a, &b| {
            (self.multipliers[a] - one)
                .norm()
                .total_cmp(&(self.multipliers[b] - one).norm())
        });
        self.multipliers
            .iter()
            .enumerate()
            .filter(|(i, _)| Some(*i) != trivial)
            .map(|(_, m)| *m)
            .collect()
    }

    /// Largest modulus of the nontrivial multipliers: below 1 for a stable orbit.
    pub fn leading_multiplier(&self) -> f64 {
        self.nontrivial_multipliers()
            .iter()
            .map(|m| m.norm())
            .fold(0.0, f64::max)
    }

    pub fn stable(&self) -> bool {
        self.leading_multiplier() < 1.0
    }
}

/// The flow's linearisation around (x0, T): the end state, the vector field at x0 and at the end
/// state, and the monodromy matrix (forward differences).
pub struct Linearization {
    pub end: Vec<f64>,
    pub field_start: Vec<f64>,
    pub field_end: Vec<f64>,
    pub monodromy: DMatrix<f64>,
}

pub fn linearize(
    flow: &mut dyn Flow,
    x0: &[f64],
    period_s: f64,
    scale: &[f64],
    opts: &ShootingOptions,
) -> Result<Linearization, String> {
    let n = x0.len();
    let dt = period_s * opts.dt_rel;
    let base = flow.flow(x0, &[dt, period_s, period_s + dt])?;
    let field_start: Vec<f64> = (0..n).map(|i| (base[0][i] - x0[i]) / dt).collect();
    let field_end: Vec<f64> = (0..n).map(|i| (base[2][i] - base[1][i]) / dt).collect();
    let end = base[1].clone();
    let mut monodromy = DMatrix::zeros(n, n);
    let mut xk = x0.to_vec();
    for k in 0..n {
        let h = opts.fd_rel * scale[k];
        xk[k] = x0[k] + h;
        let e = flow.flow(&xk, &[period_s])?.remove(0);
        xk[k] = x0[k];
        for i in 0..n {
            monodromy[(i, k)] = (e[i] - end[i]) / h;
        }
    }
    Ok(Linearization {
        end,
        field_start,
        field_end,
        monodromy,
    })
}

/// The phase condition's plane: through `x_ref`, normal to the (scaled) vector field there.
#[derive(Clone, Debug)]
pub struct PhasePlane {
    pub x_ref: Vec<f64>,
    /// Unit normal in scaled coordinates.
    pub normal: Vec<f64>,
}

impl PhasePlane {
    pub fn new(x_ref: &[f64], field: &[f64], scale: &[f64]) -> Result<Self, String> {
        let v: Vec<f64> = field.iter().zip(scale).map(|(f, s)| f / s).collect();
        let norm = v.iter().map(|x| x * x).sum::<f64>().sqrt();
        if !(norm > 0.0 && norm.is_finite()) {
            return Err(
                "the vector field vanishes at the start point: it is an equilibrium, not a point on an orbit"
                    .into(),
            );
        }
        Ok(PhasePlane {
            x_ref: x_ref.to_vec(),
            normal: v.iter().map(|x| x / norm).collect(),
        })
    }

    /// Signed scaled distance of `x` from the plane.
    pub fn defect(&self, x: &[f64], scale: &[f64]) -> f64 {
        (0..x.len())
            .map(|i| self.normal[i] * (x[i] - self.x_ref[i]) / scale[i])
            .sum()
    }
}

/// Largest |v_i| / scale_i.
pub(super) fn max_scaled(v: &[f64], scale: &[f64]) -> f64 {
    v.iter()
        .zip(scale)
        .map(|(a, s)| (a / s).abs())
        .fold(0.0, f64::max)
}

/// Refuses a first guess that does not fit the system or whose period is not a positive time.
pub(super) fn check_guess(n: usize, x0_guess: &[f64], period_guess_s: f64) -> Result<(), String> {
    if x0_guess.len() != n {
        return Err(format!(
            "start state has {} values, the system {n}",
            x0_guess.len()
        ));
    }
    if !(period_guess_s > 0.0 && period_guess_s.is_finite()) {
        return Err(format!(
            "period guess {period_guess_s} s is not a positive time"
        ));
    }
    Ok(())
}

/// The scaled periodicity defect of (x0, T): one flow.
pub(super) fn defect(
    flow: &mut dyn Flow,
    x0: &[f64],
    period_s: f64,
    scale: &[f64],
) -> Result<(Vec<f64>, f64), String> {
    let end = flow.flow(x0, &[period_s])?.remove(0);
    let r: Vec<f64> = end.iter().zip(x0).map(|(e, x)| e - x).collect();
    let m = max_scaled(&r, scale);
    Ok((r, m))
}

/// Newton's shooting from the guess (x0, T). Fails with a message naming the last residual when
/// it does not converge in `opts.max_iter` iterations.
pub fn shoot(
    flow: &mut dyn Flow,
    x0_guess: &[f64],
    period_guess_s: f64,
    opts: &ShootingOptions,
) -> Result<PeriodicOrbit, String> {
    let n = flow.dim();
    check_guess(n, x0_guess, period_guess_s)?;
    let scale = flow.scale();
    let t_ref = period_guess_s;
    let mut x0 = x0_guess.to_vec();
    let mut period = period_guess_s;
    let mut plane: Option<PhasePlane> = None;
    let mut residual = f64::INFINITY;
    for iter in 0..opts.max_iter {
        let lin = linearize(flow, &x0, period, &scale, opts)?;
        let plane = match &plane {
            Some(p) => p.clone(),
            None => {
                let p = PhasePlane::new(&x0, &lin.field_start, &scale)?;
                plane = Some(p.clone());
                p
            }
        };
        let r: Vec<f64> = lin.end.iter().zip(&x0).map(|(e, x)| e - x).collect();
        residual = max_scaled(&r, &scale);
        if !residual.is_finite() {
            return Err(format!(
                "the flow left the finite numbers at iteration {iter}"
            ));
        }
        let phase = plane.defect(&x0, &scale);
        if residual < opts.tol && phase.abs() < opts.tol {
            return Ok(PeriodicOrbit::new(
                x0,
                period,
                lin.monodromy,
                iter,
                residual,
            ));
        }
        // Scaled Newton system in (u = x0 / s, tau = T / t_ref):
        //   [ S^-1 (M - I) S   S^-1 f_end t_ref ] [du  ]   [ -S^-1 r ]
        //   [ normal^T          0               ] [dtau] = [ -phase  ]
        let mut a = DMatrix::zeros(n + 1, n + 1);
        let mut b = DVector::zeros(n + 1);
        for i in 0..n {
            for k in 0..n {
                let id = if i == k { 1.0 } else { 0.0 };
                a[(i, k)] = (lin.monodromy[(i, k)] - id) * scale[k] / scale[i];
            }
            a[(i, n)] = lin.field_end[i] * t_ref / scale[i];
            b[i] = -r[i] / scale[i];
        }
        for k in 0..n {
            a[(n, k)] = plane.normal[k];
        }
        b[n] = -phase;
        let step = a
            .lu()
            .solve(&b)
            .ok_or_else(|| format!("singular shooting Jacobian at iteration {iter} (residual {residual:.3e}): at a Hopf point, or the orbit is not isolated"))?;
        // Damped: halve the step while the defect grows.
        let mut lambda = 1.0;
        loop {
            let trial: Vec<f64> = (0..n)
                .map(|i| x0[i] + lambda * step[i] * scale[i])
                .collect();
            let trial_period = period + lambda * step[n] * t_ref;
            if trial_period > 0.0 {
                // A flow that fails from the trial point (an FMU refusing the state: a journal
                // pushed into its ring) counts as a step too far.
                let m = defect(flow, &trial, trial_period, &scale).map_or(f64::INFINITY, |d| d.1);
                if m.is_finite() && m < residual {
                    x0 = trial;
                    period = trial_period;
                    break;
                }
            }
            lambda *= 0.5;
            if lambda < 1.0 / 16.0 && residual < opts.noise_floor && phase.abs() < opts.noise_floor
            {
                // No step lowers the defect any more, and it is below the map's noise floor:
                // this is as periodic as the flow can tell.
                return Ok(PeriodicOrbit::new(
                    x0,
                    period,
                    lin.monodromy,
                    iter,
                    residual,
                ));
            }
            if lambda < 1.0 / 16.0 {
                return Err(format!(
                    "shooting stalled at iteration {iter}: no step along Newton's direction lowers the periodicity defect {residual:.3e}"
                ));
            }
        }
    }
    Err(format!(
        "shooting did not converge in {} iterations (scaled periodicity defect {residual:.3e}, tolerance {:.1e})",
        opts.max_iter, opts.tol
    ))
}

/// Eigenvalues of a real square matrix, largest modulus first.
pub fn multipliers_of(m: &DMatrix<f64>) -> Vec<Complex<f64>> {
    let mut ev: Vec<Complex<f64>> = m.clone().complex_eigenvalues().iter().copied().collect();
    ev.sort_by(|a, b| b.norm().total_cmp(&a.norm()));
    ev
}
