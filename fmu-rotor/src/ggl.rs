//! The Gear-Gupta-Leimkuhler stabilized index-2 equations, eqs. (1)-(4) of the paper,
//! discretized with a BDF formula y_{n+1} = psi + beta h y'_{n+1}:
//!
//! F1 = M(x) (x - psi_x - beta h v) + G^T mu~        (eq. 2 times beta h, mu~ = beta h mu)
//! F2 = M(x) (v - psi_v) - beta h f_e + G^T lambda~  (eq. 1 times beta h, lambda~ = beta h lambda)
//! F3 = g(t, x)                                      (eq. 3)
//! F4 = G v + dg/dt                                   (eq. 4)
//!
//! Unknowns w = [x, v, mu~, lambda~]. Scaling the multipliers with beta h keeps the iteration
//! matrix O(1) for small steps (the usual remedy for the 1/h ill-conditioning of index-2 BDF).

use crate::linalg::Lu;
use crate::params::RotorError;
use crate::system::{ContactMemo, MultibodySystem, RingContacts};

/// Constant constraint Jacobian G (n_c x n_q, row-major). Valid because all constraints of
/// `constraint.rs` are linear in x.
pub fn constraint_jacobian(sys: &MultibodySystem) -> Vec<f64> {
    let nq = sys.n_coords();
    let mut g = vec![0.0; sys.n_constraints() * nq];
    for (i, c) in sys.constraints.iter().enumerate() {
        c.jacobian_row(&mut g[i * nq..(i + 1) * nq]);
    }
    g
}

/// y = M x with M given as 6x6 blocks.
pub fn mass_times(m_blocks: &[[f64; 36]], x: &[f64], y: &mut [f64]) {
    for (b, m6) in m_blocks.iter().enumerate() {
        for i in 0..6 {
            let row = &m6[i * 6..i * 6 + 6];
            y[6 * b + i] = row
                .iter()
                .zip(&x[6 * b..6 * b + 6])
                .map(|(a, z)| a * z)
                .sum();
        }
    }
}

/// Scratch buffers reused by residual evaluations (not part of the state).
#[derive(Debug)]
pub struct Work {
    pub m_blocks: Vec<[f64; 36]>,
    pub f: Vec<f64>,
    pub tmp: Vec<f64>,
    pub tmp2: Vec<f64>,
    /// The ring contacts at the point a force Jacobian is taken.
    pub contacts: ContactMemo,
}

impl Work {
    pub fn new(nb: usize) -> Self {
        Work {
            m_blocks: vec![[0.0; 36]; nb],
            f: vec![0.0; 6 * nb],
            tmp: vec![0.0; 6 * nb],
            tmp2: vec![0.0; 6 * nb],
            contacts: ContactMemo::default(),
        }
    }
}

/// Evaluates F(w) into `out` (length 2 nq + 2 nc).
pub fn residual(
    sys: &MultibodySystem,
    g_mat: &[f64],
    t: f64,
    w: &[f64],
    psi: &[f64],
    beta_h: f64,
    u: &[f64],
    work: &mut Work,
    out: &mut [f64],
) {
    let nq = sys.n_coords();
    let nc = sys.n_constraints();
    let (x, rest) = w.split_at(nq);
    let (v, rest) = rest.split_at(nq);
    let (mu, lam) = rest.split_at(nc);
    sys.eval(x, v, u, &mut work.m_blocks, &mut work.f);
    for i in 0..nq {
        work.tmp[i] = x[i] - psi[i] - beta_h * v[i];
        work.tmp2[i] = v[i] - psi[nq + i];
    }
    let (o1, o) = out.split_at_mut(nq);
    let (o2, o) = o.split_at_mut(nq);
    let (o3, o4) = o.split_at_mut(nc);
    mass_times(&work.m_blocks, &work.tmp, o1);
    mass_times(&work.m_blocks, &work.tmp2, o2);
    for i in 0..nq {
        o2[i] -= beta_h * work.f[i];
    }
    for (ci, c) in sys.constraints.iter().enumerate() {
        let row = &g_mat[ci * nq..(ci + 1) * nq];
        for j in 0..nq {
            if row[j] != 0.0 {
                o1[j] += row[j] * mu[ci];
                o2[j] += row[j] * lam[ci];
            }
        }
        o3[ci] = c.value(t, x);
        o4[ci] = c.rate(t, v);
    }
}

/// Force Jacobians df/dx, df/dv (row-major nq x nq) by forward differences, plus M at (x, v).
/// Differences are cheap here (18 coordinates) and keep every force law Jacobian-free.
pub fn force_jacobians(
    sys: &MultibodySystem,
    x: &[f64],
    v: &[f64],
    u: &[f64],
    work: &mut Work,
) -> (Vec<f64>, Vec<f64>, Vec<[f64; 36]>) {
    let nq = sys.n_coords();
    let record = RingContacts::Record(&mut work.contacts);
    sys.eval_with(x, v, u, &mut work.m_blocks, &mut work.f, record);
    let m0 = work.m_blocks.clone();
    let f0 = work.f.clone();
    let mut fx = vec![0.0; nq * nq];
    let mut fv = vec![0.0; nq * nq];
    let mut xp = x.to_vec();
    let mut vp = v.to_vec();
    // The velocity columns without the forces of the positions alone (the ring contact): they
    // cancel in the difference, and took half of the contact evaluations of a refresh.
    let mut f0_v = vec![0.0; nq];
    sys.eval_with(x, v, u, &mut work.m_blocks, &mut f0_v, RingContacts::Omit);
    for j in 0..nq {
        // Position scale 1e-3 (m or rad) and velocity scale 1 keep the increments far above
        // round-off for the tiny lateral coordinates; forces are nearly linear in them.
        let dx = 1.5e-8 * x[j].abs().max(1e-3);
        xp[j] = x[j] + dx;
        // A coordinate that does not move a journal against its ring reuses that contact's force.
        let reuse = RingContacts::Reuse(&mut work.contacts);
        sys.eval_with(&xp, v, u, &mut work.m_blocks, &mut work.f, reuse);
        for i in 0..nq {
            fx[i * nq + j] = (work.f[i] - f0[i]) / dx;
        }
        xp[j] = x[j];
        let dv = 1.5e-8 * v[j].abs().max(1.0);
        vp[j] = v[j] + dv;
        sys.eval_with(
            x,
            &vp,
            u,
            &mut work.m_blocks,
            &mut work.f,
            RingContacts::Omit,
        );
        for i in 0..nq {
            fv[i * nq + j] = (work.f[i] - f0_v[i]) / dv;
        }
        vp[j] = v[j];
    }
    (fx, fv, m0)
}

/// Factor the iteration matrix dF/dw for the given beta h (dM/dx terms are neglected: they
/// multiply quantities of the size of the Newton correction, so modified Newton still converges).
pub fn iteration_matrix(
    nq: usize,
    nc: usize,
    g_mat: &[f64],
    m_flat: &[f64],
    fx: &[f64],
    fv: &[f64],
    beta_h: f64,
) -> Result<Lu, RotorError> {
    let a = assemble_iteration_matrix(nq, nc, g_mat, m_flat, fx, fv, beta_h);
    Lu::factor(2 * nq + 2 * nc, a, "GGL iteration matrix")
}

/// The iteration matrix dF/dw (row-major, (2 nq + 2 nc) squared) that [`iteration_matrix`]
/// factors.
pub fn assemble_iteration_matrix(
    nq: usize,
    nc: usize,
    g_mat: &[f64],
    m_flat: &[f64],
    fx: &[f64],
    fv: &[f64],
    beta_h: f64,
) -> Vec<f64> {
    let n = 2 * nq + 2 * nc;
    let mut a = vec![0.0; n * n];
    for (b, m6) in m_flat.chunks(36).enumerate() {
        for i in 0..6 {
            for j in 0..6 {
                let (r, c) = (6 * b + i, 6 * b + j);
                a[r * n + c] = m6[i * 6 + j];
                a[r * n + nq + c] = -beta_h * m6[i * 6 + j];
                a[(nq + r) * n + nq + c] = m6[i * 6 + j];
            }
        }
    }
    for i in 0..nq {
        for j in 0..nq {
            a[(nq + i) * n + j] -= beta_h * fx[i * nq + j];
            a[(nq + i) * n + nq + j] -= beta_h * fv[i * nq + j];
        }
    }
    for ci in 0..nc {
        for j in 0..nq {
            let gij = g_mat[ci * nq + j];
            if gij != 0.0 {
                a[j * n + 2 * nq + ci] = gij; // G^T mu~ in F1
                a[(nq + j) * n + 2 * nq + nc + ci] = gij; // G^T lambda~ in F2
                a[(2 * nq + ci) * n + j] = gij; // F3
                a[(2 * nq + nc + ci) * n + nq + j] = gij; // F4
            }
        }
    }
    a
}

/// The constrained mass matrix [M G^T; G 0] for the mass blocks `m_blocks` (6x6 each,
/// row-major), factored.
pub fn constrained_mass_matrix<'a>(
    sys: &MultibodySystem,
    g_mat: &[f64],
    m_blocks: impl Iterator<Item = &'a [f64]>,
    what: &'static str,
) -> Result<Lu, RotorError> {
    let nq = sys.n_coords();
    let nc = sys.n_constraints();
    let n = nq + nc;
    let mut a = vec![0.0; n * n];
    for (b, m6) in m_blocks.enumerate() {
        for i in 0..6 {
            for j in 0..6 {
                a[(6 * b + i) * n + 6 * b + j] = m6[i * 6 + j];
            }
        }
    }
    for ci in 0..nc {
        for j in 0..nq {
            let gij = g_mat[ci * nq + j];
            a[j * n + nq + ci] = gij;
            a[(nq + ci) * n + j] = gij;
        }
    }
    Lu::factor(n, a, what)
}

/// Consistent accelerations a and multipliers lambda at (t, x, v): solves
/// [M G^T; G 0] [a; lambda] = [f; c] with G a = c the acceleration-level constraints.
pub fn consistent_acceleration(
    sys: &MultibodySystem,
    g_mat: &[f64],
    t: f64,
    x: &[f64],
    v: &[f64],
    u: &[f64],
    work: &mut Work,
) -> Result<(Vec<f64>, Vec<f64>), RotorError> {
    let nq = sys.n_coords();
    let nc = sys.n_constraints();
    let n = nq + nc;
    sys.eval(x, v, u, &mut work.m_blocks, &mut work.f);
    let mut rhs = vec![0.0; n];
    rhs[..nq].copy_from_slice(&work.f);
    for (ci, c) in sys.constraints.iter().enumerate() {
        rhs[nq + ci] = c.accel_rhs(t);
    }
    let lu = constrained_mass_matrix(
        sys,
        g_mat,
        work.m_blocks.iter().map(|m| m.as_slice()),
        "consistent acceleration",
    )?;
    lu.solve(&mut rhs);
    let lam = rhs[nq..].to_vec();
    rhs.truncate(nq);
    Ok((rhs, lam))
}

/// How much the consistent accelerations and multipliers at (x, v) change when the inputs change
/// by `du`: the solution of [M G^T; G 0] [da; dlambda] = [f_u(du); 0], with `mass` the factored
/// constrained mass matrix ([`constrained_mass_matrix`]) and f_u the forces the inputs apply
/// (linear in them).
pub fn acceleration_jump(
    sys: &MultibodySystem,
    mass: &Lu,
    x: &[f64],
    v: &[f64],
    du: &[f64],
) -> (Vec<f64>, Vec<f64>) {
    let nq = sys.n_coords();
    let mut rhs = vec![0.0; nq + sys.n_constraints()];
    sys.input_forces(x, v, du, &mut rhs[..nq]);
    mass.solve(&mut rhs);
    let dlam = rhs.split_off(nq);
    (rhs, dlam)
}
