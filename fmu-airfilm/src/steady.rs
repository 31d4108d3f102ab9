//! Steady state (dP/dt = 0) at a given journal position and speed, and the static stiffness.
//!
//! Solved per block by pseudo-transient continuation: Newton steps on
//! tau H c0 (P - P_prev) + F_steady(P) = 0 with a fresh analytic Jacobian each step, where the
//! pseudo-time coefficient c0 follows "switched evolution relaxation" (c0 shrinks with the steady
//! residual) and becomes exactly 0 at the end, so the converged answer is the true steady state.
//! Velocities in `journal` enter through dh/dt (a quasi-steady squeeze term); usually they are 0.

use crate::error::FilmError;
use crate::forces::FilmOutputs;
use crate::geometry::{min_gap_m, GapField, Geometry};
use crate::integrator::outputs_for;
use crate::linsolve::BandLu;
use crate::mesh::Mesh;
use crate::params::BearingParams;
use crate::reynolds::{self, Coeffs};
use crate::JournalState;

/// A converged steady pressure field.
#[derive(Clone, Debug)]
pub struct SteadySolution {
    /// Scaled nodal pressures P = p/p_a (block after block, `mesh` numbering).
    pub p_rel: Vec<f64>,
    pub outputs: FilmOutputs,
    /// Newton iterations summed over the blocks.
    pub iterations: usize,
    pub mesh: Mesh,
}

const MAX_ITERS: usize = 200;

/// Steady state of `params` at `journal`.
pub fn steady_state(
    params: &BearingParams,
    journal: JournalState,
) -> Result<SteadySolution, FilmError> {
    params.validate()?;
    let mesh = Mesh::new(params);
    let p0 = vec![1.0; mesh.n_nodes()];
    steady_from(params, mesh, journal, p0, None)
}

/// Largest scaled steady residual of a start that counts as solved (round-off of the element
/// integrals at P ~ 1 is ~1e-14).
const ALREADY_STEADY: f64 = 1e-12;

/// Steady state from the initial guess `p` (Dirichlet nodes keep their values) with an optional
/// source term (manufactured solutions), indexed `(block * n_elem + elem) * 9 + gauss_point`.
pub fn steady_from(
    params: &BearingParams,
    mesh: Mesh,
    journal: JournalState,
    mut p: Vec<f64>,
    source: Option<&[f64]>,
) -> Result<SteadySolution, FilmError> {
    crate::check_finite(&journal, 0.0)?;
    let h_min_m = min_gap_m(&params.bore, &journal);
    if h_min_m <= 0.0 {
        return Err(FilmError::BeyondContactLimit { h_min_m, t_s: 0.0 });
    }
    let geom = Geometry::new(params, &mesh);
    let mut gap = GapField::default();
    geom.update(&journal, params.bore.c_m, &mut gap);
    let npb = mesh.npb;
    let ne = mesh.elem.len();
    let mut lu = BandLu::new(npb, mesh.kl, mesh.ku);
    let mut res = vec![0.0; npb];
    let mut hist = vec![0.0; npb];
    let zero = vec![0.0; npb];
    let tau = params.squeeze_time_s();
    let lambda = params.bearing_number(journal.omega_rad_s);
    let mut iterations = 0;
    for k in 0..mesh.n_blocks {
        let pb = &mut p[k * npb..(k + 1) * npb];
        let src = source.map(|s| &s[k * ne * 9..(k + 1) * ne * 9]);
        let steady = |pb: &[f64], res: &mut [f64]| {
            let co = Coeffs {
                lambda,
                tau_s: tau,
                c0_per_s: 0.0,
            };
            reynolds::residual(&mesh, &gap, k, co, pb, &zero, src, res);
            res.iter().fold(0.0f64, |m, v| m.max(v.abs()))
        };
        let r_start = steady(pb, &mut res);
        // A start that already solves the steady equation to round-off (P = 1 at omega = 0:
        // no wedge, no squeeze) is the solution: the pseudo-time step below shrinks only while
        // the residual falls, so it would wait forever for a residual that cannot fall.
        if r_start <= ALREADY_STEADY {
            continue;
        }
        let r0 = r_start.max(1e-300);
        let mut r = r0;
        let mut c0 = 1.0 / tau;
        let mut done = false;
        for _ in 0..MAX_ITERS {
            iterations += 1;
            let co = Coeffs {
                lambda,
                tau_s: tau,
                c0_per_s: c0,
            };
            for i in 0..npb {
                hist[i] = c0 * pb[i];
            }
            reynolds::jacobian(&mesh, &gap, k, co, pb, &mut lu);
            lu.factor().map_err(|e| FilmError::SingularMatrix {
                lobe: k,
                row: e.row(lu.n),
            })?;
            reynolds::residual(&mesh, &gap, k, co, pb, &hist, src, &mut res);
            lu.solve(&mut res);
            // Damping keeps the pressure positive (P h^3 is the diffusion coefficient).
            let mut scale = 1.0f64;
            let mut dmax = 0.0f64;
            for i in 0..npb {
                dmax = dmax.max(res[i].abs());
                if res[i] > 0.5 * pb[i] {
                    scale = scale.min(0.5 * pb[i] / res[i]);
                }
            }
            for i in 0..npb {
                pb[i] -= scale * res[i];
            }
            let r_new = steady(pb, &mut res);
            if !r_new.is_finite() {
                break;
            }
            if c0 == 0.0 && scale == 1.0 && dmax < 1e-11 {
                done = true;
                break;
            }
            c0 *= (r_new / r).min(1.0);
            if c0 * tau < 1e-6 {
                c0 = 0.0;
            }
            r = r_new;
            if r < 1e-13 * r0.max(1.0) && c0 == 0.0 && scale == 1.0 {
                done = true;
                break;
            }
        }
        if !done {
            return Err(FilmError::SteadyNotConverged {
                iterations,
                residual: r,
            });
        }
    }
    let outputs = outputs_for(params, &mesh, &geom, &journal, &p);
    Ok(SteadySolution {
        p_rel: p,
        outputs,
        iterations,
        mesh,
    })
}

/// Static stiffness K_ij = -dF_i/d(d_j) (N/m) at `journal` by central differences of steady
/// states (step 2e-3 C), each warm-started from the steady state at `journal`.
pub fn static_stiffness(
    params: &BearingParams,
    journal: JournalState,
) -> Result<[[f64; 2]; 2], FilmError> {
    let base = steady_state(params, journal)?;
    let d = 2e-3 * params.bore.c_m;
    let mut k = [[0.0; 2]; 2];
    for jdir in 0..2 {
        let mut f = [[0.0; 2]; 2];
        for (si, sign) in [1.0, -1.0].iter().enumerate() {
            let mut js = journal;
            if jdir == 0 {
                js.dx_m += sign * d;
            } else {
                js.dy_m += sign * d;
            }
            let s = steady_from(params, base.mesh.clone(), js, base.p_rel.clone(), None)?;
            f[si] = [s.outputs.fx_n, s.outputs.fy_n];
        }
        for i in 0..2 {
            k[i][jdir] = -(f[0][i] - f[1][i]) / (2.0 * d);
        }
    }
    Ok(k)
}
