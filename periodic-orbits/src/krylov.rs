//! Matrix-free Newton-Krylov shooting, for flows whose state is too large for a monodromy
//! matrix (the co-simulated rotor with its films' pressure fields: ~3 200 values).
//!
//! The unknowns and equations are those of [`shooting::shoot`](super::shooting::shoot): start
//! state x0, period T, periodicity phi_T(x0) - x0 = 0 and the phase plane. Each Newton step
//! solves the bordered system
//!
//!   [ M - I   f(phi_T) ] [dx]   [ -r     ]
//!   [ n^T     0        ] [dT] = [ -phase ]
//!
//! by GMRES, where every product M v is one flow from x0 + eps v (a directional finite
//! difference): M is never formed. GMRES needs about as many products as M - I has eigenvalues
//! away from its cluster at -1 (strongly damped directions, multipliers near 0), so a state of
//! thousands of values costs tens of flows per Newton step. The Floquet multipliers come from an
//! Arnoldi run on M at the converged orbit (Ritz values: the leading ones, largest modulus first).

use super::shooting::{
    check_guess, defect, max_scaled, Flow, PeriodicOrbit, PhasePlane, ShootingOptions,
};
use nalgebra::{Complex, DMatrix};

/// The Newton-Krylov policy: the shooting's options plus the Krylov solver's.
#[derive(Clone, Copy, Debug)]
pub struct KrylovOptions {
    pub shooting: ShootingOptions,
    /// GMRES stops when its residual is this fraction of the Newton residual.
    pub gmres_rel_tol: f64,
    /// Products (flows) per GMRES solve at most.
    pub max_krylov: usize,
    /// Arnoldi steps for the multipliers (Ritz values of M).
    pub ritz_steps: usize,
}

impl Default for KrylovOptions {
    fn default() -> Self {
        KrylovOptions {
            shooting: ShootingOptions::default(),
            gmres_rel_tol: 1e-3,
            max_krylov: 60,
            ritz_steps: 20,
        }
    }
}

/// A converged orbit and what it cost.
#[derive(Clone, Debug)]
pub struct KrylovOrbit {
    /// Its `monodromy` is empty (never formed); `multipliers` are Ritz values of M.
    pub orbit: PeriodicOrbit,
    /// GMRES products per Newton step.
    pub krylov_iterations: Vec<usize>,
    /// Flows run, the Arnoldi run for the multipliers included.
    pub flows: usize,
}

fn dot(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).map(|(x, y)| x * y).sum()
}

fn norm(a: &[f64]) -> f64 {
    dot(a, a).sqrt()
}

/// M v in scaled coordinates (S^-1 M S v) by one flow: a directional difference whose largest
/// scaled perturbation is `fd_rel`.
struct Monodromy<'a> {
    flow: &'a mut dyn Flow,
    x0: &'a [f64],
    end: &'a [f64],
    period_s: f64,
    scale: &'a [f64],
    fd_rel: f64,
    flows: usize,
}

impl Monodromy<'_> {
    fn apply(&mut self, v: &[f64]) -> Result<Vec<f64>, String> {
        let vmax = v.iter().fold(0.0f64, |m, x| m.max(x.abs()));
        if vmax == 0.0 {
            return Ok(vec![0.0; v.len()]);
        }
        let eps = self.fd_rel / vmax;
        let x: Vec<f64> = (0..v.len())
            .map(|i| self.x0[i] + eps * v[i] * self.scale[i])
            .collect();
        self.flows += 1;
        let e = self.flow.flow(&x, &[self.period_s])?.remove(0);
        Ok((0..v.len())
            .map(|i| (e[i] - self.end[i]) / (eps * self.scale[i]))
            .collect())
    }
}

/// A linear operator given by its product (one flow per call in the shooting).
pub type Product<'a> = dyn FnMut(&[f64]) -> Result<Vec<f64>, String> + 'a;

/// GMRES (no restart, modified Gram-Schmidt, Givens rotations) for A z = b with `apply` the
/// product. Returns z and the products used.
pub fn gmres(
    apply: &mut Product,
    b: &[f64],
    rel_tol: f64,
    max_iter: usize,
) -> Result<(Vec<f64>, usize), String> {
    let n = b.len();
    let beta = norm(b);
    if beta == 0.0 {
        return Ok((vec![0.0; n], 0));
    }
    let mut basis: Vec<Vec<f64>> = vec![b.iter().map(|x| x / beta).collect()];
    let m = max_iter.min(n).max(1);
    let mut h = DMatrix::<f64>::zeros(m + 1, m);
    let (mut cs, mut sn) = (vec![0.0; m], vec![0.0; m]);
    let mut g = vec![0.0; m + 1];
    g[0] = beta;
    let mut k_used = 0;
    for k in 0..m {
        let mut w = apply(&basis[k])?;
        if w.iter().any(|x| !x.is_finite()) {
            return Err("a Krylov product left the finite numbers".into());
        }
        for (j, v) in basis.iter().enumerate() {
            let hj = dot(&w, v);
            h[(j, k)] = hj;
            w.iter_mut().zip(v).for_each(|(wi, vi)| *wi -= hj * vi);
        }
        let hn = norm(&w);
        h[(k + 1, k)] = hn;
        // Apply the previous rotations to the new column, then make the new one.
        for j in 0..k {
            let t = cs[j] * h[(j, k)] + sn[j] * h[(j + 1, k)];
            h[(j + 1, k)] = -sn[j] * h[(j, k)] + cs[j] * h[(j + 1, k)];
            h[(j, k)] = t;
        }
        let d = h[(k, k)].hypot(h[(k + 1, k)]);
        (cs[k], sn[k]) = if d == 0.0 {
            (1.0, 0.0)
        } else {
            (h[(k, k)] / d, h[(k + 1, k)] / d)
        };
        h[(k, k)] = d;
        h[(k + 1, k)] = 0.0;
        g[k + 1] = -sn[k] * g[k];
        g[k] *= cs[k];
        k_used = k + 1;
        if g[k + 1].abs() <= rel_tol * beta || hn == 0.0 {
            break;
        }
        basis.push(w.iter().map(|x| x / hn).collect());
    }
    // Back substitution in the triangular k x k system.
    let mut y = vec![0.0; k_used];
    for i in (0..k_used).rev() {
        let s: f64 = (i + 1..k_used).map(|j| h[(i, j)] * y[j]).sum();
        if h[(i, i)] == 0.0 {
            return Err("GMRES broke down (singular Hessenberg matrix)".into());
        }
        y[i] = (g[i] - s) / h[(i, i)];
    }
    let mut z = vec![0.0; n];
    for (j, yj) in y.iter().enumerate() {
        z.iter_mut()
            .zip(&basis[j])
            .for_each(|(zi, vi)| *zi += yj * vi);
    }
    Ok((z, k_used))
}

/// The leading eigenvalues of M (Ritz values of an Arnoldi run of `steps` products from a fixed
/// start vector), largest modulus first.
fn ritz_multipliers(m: &mut Monodromy, steps: usize) -> Result<Vec<Complex<f64>>, String> {
    let n = m.x0.len();
    let steps = steps.min(n).max(1);
    // A fixed, non-special start vector: every direction present, reproducible.
    let v0: Vec<f64> = (0..n)
        .map(|i| 1.0 + 0.5 * ((i as f64) * 0.618_033_988_75).fract())
        .collect();
    let b0 = norm(&v0);
    let mut basis = vec![v0.iter().map(|x| x / b0).collect::<Vec<f64>>()];
    let mut h = DMatrix::<f64>::zeros(steps + 1, steps);
    let mut k_used = 0;
    for k in 0..steps {
        let mut w = m.apply(&basis[k])?;
        for (j, v) in basis.iter().enumerate() {
            let hj = dot(&w, v);
            h[(j, k)] = hj;
            w.iter_mut().zip(v).for_each(|(wi, vi)| *wi -= hj * vi);
        }
        let hn = norm(&w);
        h[(k + 1, k)] = hn;
        k_used = k + 1;
        if hn <= 1e-12 {
            break;
        }
        basis.push(w.iter().map(|x| x / hn).collect());
    }
    let square = h.view((0, 0), (k_used, k_used)).into_owned();
    Ok(super::shooting::multipliers_of(&square))
}

/// The orbit at (m.x0, m.period_s) with the Ritz values of its monodromy as multipliers.
fn with_ritz_multipliers(
    m: &mut Monodromy,
    steps: usize,
    iterations: usize,
    residual: f64,
) -> Result<PeriodicOrbit, String> {
    let multipliers = ritz_multipliers(m, steps)?;
    Ok(PeriodicOrbit::with_multipliers(
        m.x0.to_vec(),
        m.period_s,
        multipliers,
        iterations,
        residual,
    ))
}

/// Newton-Krylov shooting from (x0_guess, period_guess_s).
pub fn shoot_krylov(
    flow: &mut dyn Flow,
    x0_guess: &[f64],
    period_guess_s: f64,
    opts: &KrylovOptions,
) -> Result<KrylovOrbit, String> {
    let n = flow.dim();
    check_guess(n, x0_guess, period_guess_s)?;
    let so = &opts.shooting;
    let scale = flow.scale();
    let t_ref = period_guess_s;
    let (mut x0, mut period) = (x0_guess.to_vec(), period_guess_s);
    let mut plane: Option<PhasePlane> = None;
    let mut krylov_iterations = vec![];
    let mut flows = 0usize;
    let mut residual = f64::INFINITY;
    for iter in 0..so.max_iter {
        let dt = period * so.dt_rel;
        flows += 1;
        let base = flow.flow(&x0, &[dt, period, period + dt])?;
        let field_start: Vec<f64> = (0..n).map(|i| (base[0][i] - x0[i]) / dt).collect();
        let field_end: Vec<f64> = (0..n).map(|i| (base[2][i] - base[1][i]) / dt).collect();
        let end = base[1].clone();
        let plane = match &plane {
            Some(p) => p.clone(),
            None => {
                let p = PhasePlane::new(&x0, &field_start, &scale)?;
                plane = Some(p.clone());
                p
            }
        };
        let r: Vec<f64> = end.iter().zip(&x0).map(|(e, x)| e - x).collect();
        residual = max_scaled(&r, &scale);
        if !residual.is_finite() {
            return Err(format!(
                "the flow left the finite numbers at iteration {iter}"
            ));
        }
        let phase = plane.defect(&x0, &scale);
        let mut m = Monodromy {
            flow: &mut *flow,
            x0: &x0,
            end: &end,
            period_s: period,
            scale: &scale,
            fd_rel: so.fd_rel,
            flows: 0,
        };
        if residual < so.tol && phase.abs() < so.tol {
            let orbit = with_ritz_multipliers(&mut m, opts.ritz_steps, iter, residual)?;
            return Ok(KrylovOrbit {
                orbit,
                krylov_iterations,
                flows: flows + m.flows,
            });
        }
        // The bordered system in scaled unknowns (u = dx / s, tau = dT / t_ref).
        let fe: Vec<f64> = (0..n).map(|i| field_end[i] * t_ref / scale[i]).collect();
        let mut b: Vec<f64> = (0..n).map(|i| -r[i] / scale[i]).collect();
        b.push(-phase);
        let normal = plane.normal.clone();
        let mut apply = |z: &[f64]| -> Result<Vec<f64>, String> {
            let (u, tau) = (&z[..n], z[n]);
            let mu = m.apply(u)?;
            let mut out: Vec<f64> = (0..n).map(|i| mu[i] - u[i] + fe[i] * tau).collect();
            out.push(dot(&normal, u));
            Ok(out)
        };
        let (step, used) = gmres(&mut apply, &b, opts.gmres_rel_tol, opts.max_krylov)?;
        flows += m.flows;
        krylov_iterations.push(used);
        // Damped: halve the step while the defect grows (as in `shoot`).
        let mut lambda = 1.0;
        loop {
            let trial: Vec<f64> = (0..n)
                .map(|i| x0[i] + lambda * step[i] * scale[i])
                .collect();
            let trial_period = period + lambda * step[n] * t_ref;
            if trial_period > 0.0 {
                flows += 1;
                // A flow the FMUs refuse counts as a step too far (as in `shoot`).
                let m = defect(flow, &trial, trial_period, &scale).map_or(f64::INFINITY, |d| d.1);
                if m.is_finite() && m < residual {
                    x0 = trial;
                    period = trial_period;
                    break;
                }
            }
            lambda *= 0.5;
            if lambda < 1.0 / 16.0 {
                if residual < so.noise_floor && phase.abs() < so.noise_floor {
                    // As periodic as the flow can tell (see `ShootingOptions::noise_floor`).
                    let mut m = Monodromy {
                        flow: &mut *flow,
                        x0: &x0,
                        end: &end,
                        period_s: period,
                        scale: &scale,
                        fd_rel: so.fd_rel,
                        flows: 0,
                    };
                    let orbit = with_ritz_multipliers(&mut m, opts.ritz_steps, iter, residual)?;
                    return Ok(KrylovOrbit {
                        orbit,
                        krylov_iterations,
                        flows: flows + m.flows,
                    });
                }
                return Err(format!(
                    "Newton-Krylov shooting stalled at iteration {iter}: no step along Newton's direction lowers the periodicity defect {residual:.3e}"
                ));
            }
        }
    }
    Err(format!(
        "Newton-Krylov shooting did not converge in {} iterations (scaled periodicity defect {residual:.3e}, tolerance {:.1e})",
        so.max_iter, so.tol
    ))
}

/// The GMRES solution of a small dense system, for the tests: A z = b with A given.
#[cfg(test)]
pub fn gmres_dense(
    a: &DMatrix<f64>,
    b: &nalgebra::DVector<f64>,
    rel_tol: f64,
) -> (Vec<f64>, usize) {
    use nalgebra::DVector;
    let mut apply = |z: &[f64]| -> Result<Vec<f64>, String> {
        Ok((a * DVector::from_column_slice(z))
            .iter()
            .copied()
            .collect())
    };
    gmres(&mut apply, b.as_slice(), rel_tol, b.len()).expect("no breakdown")
}
