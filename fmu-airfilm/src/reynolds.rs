//! Galerkin discretization of the isothermal compressible Reynolds equation (paper eq. (5)).
//!
//! With P = p / p_a, H = h / C, zeta = z / r, Lambda = 6 eta Omega r^2 / (p_a C^2) and
//! tau = 12 eta r^2 / (p_a C^2), eq. (5) divided by p_a^2 C^3 / r^2 reads
//!
//!   d/dphi (P H^3 dP/dphi) + d/dzeta (P H^3 dP/dzeta) = Lambda d(PH)/dphi + tau d(PH)/dt.
//!
//! Weak form per node a (boundary terms vanish: Dirichlet rows are replaced, dp/dzeta = 0 at the
//! mid-plane is natural, periodic seams cancel):
//!
//!   F_a = Int[ P H^3 (P_phi N_a,phi + P_zeta N_a,zeta) + Lambda (P_phi H + P H_phi) N_a
//!              + tau (H P_t + P H_t) N_a - S N_a ] dphi dzeta = 0,
//!
//! with P_t from the BDF formula at the nodes, P_t = c0 P - hist, and S an optional source
//! (manufactured solutions only). 3 x 3 Gauss quadrature; the element Jacobian is analytic.

use crate::geometry::GapField;
use crate::linsolve::BandLu;
use crate::mesh::Mesh;

/// Scalar coefficients of one evaluation.
#[derive(Clone, Copy, Debug)]
pub struct Coeffs {
    /// Bearing number Lambda.
    pub lambda: f64,
    /// Squeeze time constant tau (s).
    pub tau_s: f64,
    /// Leading BDF coefficient c0 (1/s): dP/dt = c0 P - hist. 0 for steady state.
    pub c0_per_s: f64,
}

#[inline(always)]
fn gather(e: &[u32; 9], v: &[f64]) -> [f64; 9] {
    let mut out = [0.0; 9];
    for a in 0..9 {
        out[a] = v[e[a] as usize];
    }
    out
}

/// Residual of block `k`. `p`, `hist`, `out` are block slices; `source` (if any) holds S at the
/// Gauss points, indexed `elem * 9 + q`. Dirichlet rows get 0 (their values are kept fixed).
pub fn residual(
    mesh: &Mesh,
    gap: &GapField,
    k: usize,
    co: Coeffs,
    p: &[f64],
    hist: &[f64],
    source: Option<&[f64]>,
    out: &mut [f64],
) {
    out.iter_mut().for_each(|v| *v = 0.0);
    let b = &mesh.basis;
    let sx = 2.0 / mesh.dphi_e;
    let sy = 2.0 / mesh.dzeta_e;
    let jac = 0.25 * mesh.dphi_e * mesh.dzeta_e;
    let nq = 3 * mesh.ne_phi;
    let (lam, tau, c0) = (co.lambda, co.tau_s, co.c0_per_s);
    for (e, nodes) in mesh.elem.iter().enumerate() {
        let col = mesh.elem_col[e] as usize;
        let pe = gather(nodes, p);
        let he = gather(nodes, hist);
        let mut pd = [0.0; 9];
        for a in 0..9 {
            pd[a] = c0 * pe[a] - he[a];
        }
        let mut re = [0.0; 9];
        for q in 0..9 {
            let gi = k * nq + 3 * col + q / 3;
            let (h, hphi, ht) = (gap.h[gi], gap.h_phi[gi], gap.h_t[gi]);
            let (n, nx, ny) = (&b.n[q], &b.dx[q], &b.dy[q]);
            let (mut pq, mut px, mut py, mut pt) = (0.0, 0.0, 0.0, 0.0);
            for a in 0..9 {
                pq += n[a] * pe[a];
                px += nx[a] * pe[a];
                py += ny[a] * pe[a];
                pt += n[a] * pd[a];
            }
            px *= sx;
            py *= sy;
            let w = b.w[q] * jac;
            let a3 = pq * h * h * h;
            let fx = w * a3 * px * sx;
            let fy = w * a3 * py * sy;
            let mut src = lam * (px * h + pq * hphi) + tau * (h * pt + pq * ht);
            if let Some(s) = source {
                src -= s[e * 9 + q];
            }
            let fs = w * src;
            for a in 0..9 {
                re[a] += fx * nx[a] + fy * ny[a] + fs * n[a];
            }
        }
        for a in 0..9 {
            out[nodes[a] as usize] += re[a];
        }
    }
    for (i, d) in mesh.dirichlet.iter().enumerate() {
        if *d {
            out[i] = 0.0;
        }
    }
}

/// Analytic Jacobian dF/dP of block `k` (including c0 tau M) into `lu` (overwritten).
pub fn jacobian(mesh: &Mesh, gap: &GapField, k: usize, co: Coeffs, p: &[f64], lu: &mut BandLu) {
    lu.zero();
    let b = &mesh.basis;
    let sx = 2.0 / mesh.dphi_e;
    let sy = 2.0 / mesh.dzeta_e;
    let jac = 0.25 * mesh.dphi_e * mesh.dzeta_e;
    let nq = 3 * mesh.ne_phi;
    let (lam, tau, c0) = (co.lambda, co.tau_s, co.c0_per_s);
    for (e, nodes) in mesh.elem.iter().enumerate() {
        let col = mesh.elem_col[e] as usize;
        let pe = gather(nodes, p);
        let mut ke = [[0.0; 9]; 9];
        for q in 0..9 {
            let gi = k * nq + 3 * col + q / 3;
            let (h, hphi, ht) = (gap.h[gi], gap.h_phi[gi], gap.h_t[gi]);
            let (n, nxr, nyr) = (&b.n[q], &b.dx[q], &b.dy[q]);
            let mut nx = [0.0; 9];
            let mut ny = [0.0; 9];
            let (mut pq, mut px, mut py) = (0.0, 0.0, 0.0);
            for a in 0..9 {
                nx[a] = nxr[a] * sx;
                ny[a] = nyr[a] * sy;
                pq += n[a] * pe[a];
                px += nx[a] * pe[a];
                py += ny[a] * pe[a];
            }
            let w = b.w[q] * jac;
            let h3 = h * h * h;
            let a3 = w * pq * h3;
            let lamh = w * lam * h;
            // Coefficient of N_b in row a, and of the gradients of N_b.
            let cb_flux = w * h3;
            let cb_src = w * (lam * hphi + tau * (c0 * h + ht));
            for a in 0..9 {
                let ca = cb_flux * (px * nx[a] + py * ny[a]) + cb_src * n[a];
                let gx = a3 * nx[a] + lamh * n[a];
                let gy = a3 * ny[a];
                let row = &mut ke[a];
                for bb in 0..9 {
                    row[bb] += ca * n[bb] + gx * nx[bb] + gy * ny[bb];
                }
            }
        }
        for a in 0..9 {
            let r = nodes[a] as usize;
            for bb in 0..9 {
                lu.add(r, nodes[bb] as usize, ke[a][bb]);
            }
        }
    }
    for (i, d) in mesh.dirichlet.iter().enumerate() {
        if *d {
            lu.set_identity_row(i);
        }
    }
}
