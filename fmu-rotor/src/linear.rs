//! Linearization of the lateral motion and modal analysis (paper Section 2.3).
//!
//! The 8 lateral degrees of freedom are the unconstrained coordinates of the multibody model:
//! q = [x, y, alpha, beta (rotor CM and Cardan tilts), x_RC, y_RC, x_RT, y_RT].
//! Linearization is numerical (central differences of the multibody force vector f_e about a
//! state), so it uses exactly the equations that are integrated:
//! M q'' + (D + G) q' + K q = 0 with K = -df/dq, D + G = -df/dq' split into its symmetric part D
//! and skew part G (gyroscopic). Each film is a linear element with general 2x2 K and D.

use crate::eigen::{self, C64};
use crate::params::{RotorError, RotorParams};
use crate::rotor::{build_system, initial_state, FilmCoefficients};
use serde::{Deserialize, Serialize};

/// Indices of the lateral DOFs in the 18 multibody coordinates.
pub const LATERAL_COORDS: [usize; 8] = [0, 1, 3, 4, 6, 7, 12, 13];

pub type Mat8 = [[f64; 8]; 8];

#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct LateralMatrices {
    pub m: Mat8,
    pub g: Mat8,
    pub d: Mat8,
    pub k: Mat8,
    /// Axial offsets of the journals from the rotor CM, z_J - z_cm [m] (C, T).
    pub a_c_m: f64,
    pub a_t_m: f64,
    /// Axial position of the rotor CM [m].
    pub z_cm_m: f64,
    pub omega_rad_s: f64,
}

/// M, G, D, K of the lateral motion at spin speed `omega_rad_s`, rotor centred, with the films
/// replaced by `films` ([C, T]). Gravity does not enter (it adds no stiffness at the centred state).
pub fn lateral_matrices(
    params: &RotorParams,
    omega_rad_s: f64,
    films: &[FilmCoefficients; 2],
) -> LateralMatrices {
    let mut p = params.clone();
    p.g_m_s2 = 0.0;
    let sys = build_system(&p, Some(films));
    let (x0, mut v0) = initial_state(&p);
    v0[5] = omega_rad_s;
    let nq = sys.n_coords();
    let nb = sys.bodies.len();
    let u = [0.0; crate::rotor::N_INPUTS];
    let mut mb = vec![[0.0; 36]; nb];
    let mut f_plus = vec![0.0; nq];
    let mut f_minus = vec![0.0; nq];
    let mut out = LateralMatrices {
        m: [[0.0; 8]; 8],
        g: [[0.0; 8]; 8],
        d: [[0.0; 8]; 8],
        k: [[0.0; 8]; 8],
        a_c_m: p.z_jc_m - p.z_cm_m,
        a_t_m: p.z_jt_m - p.z_cm_m,
        z_cm_m: p.z_cm_m,
        omega_rad_s,
    };
    let mut c = [[0.0; 8]; 8];
    for (jl, &j) in LATERAL_COORDS.iter().enumerate() {
        for (is_vel, step) in [(false, 1e-7), (true, 1e-4)] {
            let mut xp = x0.clone();
            let mut vp = v0.clone();
            let mut xm = x0.clone();
            let mut vm = v0.clone();
            if is_vel {
                vp[j] += step;
                vm[j] -= step;
            } else {
                xp[j] += step;
                xm[j] -= step;
            }
            sys.eval(&xp, &vp, &u, &mut mb, &mut f_plus);
            sys.eval(&xm, &vm, &u, &mut mb, &mut f_minus);
            for (il, &i) in LATERAL_COORDS.iter().enumerate() {
                let dfd = -(f_plus[i] - f_minus[i]) / (2.0 * step);
                if is_vel {
                    c[il][jl] = dfd;
                } else {
                    out.k[il][jl] = dfd;
                }
            }
        }
    }
    sys.eval(&x0, &v0, &u, &mut mb, &mut f_plus);
    for (il, &i) in LATERAL_COORDS.iter().enumerate() {
        for (jl, &j) in LATERAL_COORDS.iter().enumerate() {
            let (bi, bj) = (i / 6, j / 6);
            if bi == bj {
                out.m[il][jl] = mb[bi][(i % 6) * 6 + j % 6];
            }
            out.d[il][jl] = 0.5 * (c[il][jl] + c[jl][il]);
            out.g[il][jl] = 0.5 * (c[il][jl] - c[jl][il]);
        }
    }
    out
}

#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub enum Whirl {
    Forward,
    Backward,
}

/// Mode shape: complex amplitudes (x, y) of the four bearing points, normalized so that the
/// largest of the four point amplitudes is 1.
#[derive(Clone, Debug, PartialEq)]
pub struct ModeShape {
    /// Complex DOF vector (order of `LATERAL_COORDS`), same normalization.
    pub dof: [C64; 8],
    pub journal_c: [C64; 2],
    pub journal_t: [C64; 2],
    pub ring_c: [C64; 2],
    pub ring_t: [C64; 2],
    /// Axial position [m, same origin as the params] where the rotor axis' orbit is smallest
    /// (least squares over x and y); the "vibration node" of a conical mode.
    pub rotor_node_z_m: f64,
    /// Orbit size at that point relative to the largest bearing-point orbit (0 = true node).
    pub rotor_node_residual: f64,
}

fn amp(p: &[C64; 2]) -> f64 {
    (p[0].norm_sqr() + p[1].norm_sqr()).sqrt()
}

impl ModeShape {
    /// Orbit sizes |journal C|, |journal T|, |ring C|, |ring T| (largest = 1).
    pub fn amplitudes(&self) -> [f64; 4] {
        [
            amp(&self.journal_c),
            amp(&self.journal_t),
            amp(&self.ring_c),
            amp(&self.ring_t),
        ]
    }
    /// Which bearing's journal moves least ("vibration node" of the paper): 'C' or 'T'.
    pub fn node(&self) -> char {
        if amp(&self.journal_c) < amp(&self.journal_t) {
            'C'
        } else {
            'T'
        }
    }
    /// Short description for reports.
    pub fn describe(&self) -> String {
        let a = self.amplitudes();
        let ring_dominated = a[2].max(a[3]) > a[0].max(a[1]);
        format!(
            "|J_C|={:.3} |J_T|={:.3} |R_C|={:.3} |R_T|={:.3}: {} mode, smaller journal orbit at {}, rotor-axis node at z = {:.0} mm (residual {:.2})",
            a[0],
            a[1],
            a[2],
            a[3],
            if ring_dominated { "ring" } else { "rotor" },
            self.node(),
            1e3 * self.rotor_node_z_m,
            self.rotor_node_residual
        )
    }
}

#[derive(Clone, Debug, PartialEq)]
pub struct Mode {
    pub eigenvalue: C64,
    pub freq_hz: f64,
    pub damping_ratio: f64,
    pub whirl: Whirl,
    pub shape: ModeShape,
}

/// The first-order state matrix A (16 x 16, row-major) of the lateral system, x' = A x with
/// x = (q, q'): A = [[0, I], [-M^-1 K, -M^-1 (D + G)]].
pub fn state_matrix(lm: &LateralMatrices) -> Result<Vec<f64>, RotorError> {
    let n = 16;
    // A = [[0, I], [-M^-1 K, -M^-1 (D + G)]]
    let mut minv_k = vec![0.0; 64];
    let mut minv_c = vec![0.0; 64];
    let mflat: Vec<f64> = lm.m.iter().flatten().copied().collect();
    let lu = crate::linalg::Lu::factor(8, mflat, "lateral mass matrix")?;
    for j in 0..8 {
        let mut colk: Vec<f64> = (0..8).map(|i| lm.k[i][j]).collect();
        let mut colc: Vec<f64> = (0..8).map(|i| lm.d[i][j] + lm.g[i][j]).collect();
        lu.solve(&mut colk);
        lu.solve(&mut colc);
        for i in 0..8 {
            minv_k[i * 8 + j] = colk[i];
            minv_c[i * 8 + j] = colc[i];
        }
    }
    let mut a = vec![0.0; n * n];
    for i in 0..8 {
        a[i * n + 8 + i] = 1.0;
        for j in 0..8 {
            a[(8 + i) * n + j] = -minv_k[i * 8 + j];
            a[(8 + i) * n + 8 + j] = -minv_c[i * 8 + j];
        }
    }
    Ok(a)
}

/// The real eigenvalues [1/s] of the lateral system: its non-oscillating motions, which `modes`
/// does not list (overdamped modes when < 0; a static divergence when one is > 0).
pub fn real_eigenvalues(lm: &LateralMatrices) -> Result<Vec<f64>, RotorError> {
    let a = state_matrix(lm)?;
    Ok(eigen::eigenvalues(16, &a)?
        .into_iter()
        .filter(|l| l.im == 0.0)
        .map(|l| l.re)
        .collect())
}

/// Damped eigenmodes (one per complex-conjugate pair, Im > 0), sorted by frequency.
/// Whirl direction: a point moving as x = Re(X e^{i nu t}), y = Re(Y e^{i nu t}) turns
/// counter-clockwise (about +z, the spin sense: forward) iff Im(conj(X) Y) < 0 (X = 1, Y = -i
/// is x = cos, y = sin). The sign is summed over the four bearing points.
pub fn modes(lm: &LateralMatrices) -> Result<Vec<Mode>, RotorError> {
    let n = 16;
    let a = state_matrix(lm)?;
    let mut out = Vec::new();
    for (lam, vec) in eigen::eigenpairs(n, &a)?
        .into_iter()
        .filter(|(l, _)| l.im > 0.0)
    {
        let mut dof = [C64::default(); 8];
        dof.copy_from_slice(&vec[..8]);
        let (ac, at) = (lm.a_c_m, lm.a_t_m);
        // small-angle journal kinematics: x_J = x + a beta, y_J = y - a alpha
        let jc = [dof[0] + dof[3] * ac, dof[1] - dof[2] * ac];
        let jt = [dof[0] + dof[3] * at, dof[1] - dof[2] * at];
        let rc = [dof[4], dof[5]];
        let rt = [dof[6], dof[7]];
        let big = amp(&jc).max(amp(&jt)).max(amp(&rc)).max(amp(&rt));
        let s = 1.0 / big;
        let sc = |p: [C64; 2]| [p[0] * s, p[1] * s];
        let whirl_sum: f64 = [jc, jt, rc, rt]
            .iter()
            .map(|p| (p[0].conj() * p[1]).im)
            .sum();
        // rotor orbit at axial offset s from the CM: U0 + s U1, U0 = (x, y), U1 = (beta, -alpha)
        let u0 = [dof[0] * s, dof[1] * s];
        let u1 = [dof[3] * s, dof[2] * -s];
        let n1 = u1[0].norm_sqr() + u1[1].norm_sqr();
        let node_s = if n1 > 0.0 {
            -((u1[0].conj() * u0[0]).re + (u1[1].conj() * u0[1]).re) / n1
        } else {
            f64::INFINITY
        };
        let node_res = if n1 > 0.0 {
            amp(&[u0[0] + u1[0] * node_s, u0[1] + u1[1] * node_s])
        } else {
            amp(&u0)
        };
        let dofn = dof.map(|z| z * s);
        out.push(Mode {
            eigenvalue: lam,
            freq_hz: lam.im / (2.0 * std::f64::consts::PI),
            damping_ratio: -lam.re / lam.norm(),
            whirl: if whirl_sum < 0.0 {
                Whirl::Forward
            } else {
                Whirl::Backward
            },
            shape: ModeShape {
                dof: dofn,
                journal_c: sc(jc),
                journal_t: sc(jt),
                ring_c: sc(rc),
                ring_t: sc(rt),
                rotor_node_z_m: lm.z_cm_m + node_s,
                rotor_node_residual: node_res,
            },
        });
    }
    out.sort_by(|a, b| a.freq_hz.total_cmp(&b.freq_hz));
    Ok(out)
}
