//! Verification helpers (manufactured solutions): steady solve with a source term and the
//! L2 error against an exact field. Used by the integration tests; cheap and allocation-happy.

use crate::error::FilmError;
use crate::mesh::{shape1, Mesh, GAUSS3_X};
use crate::params::BearingParams;
use crate::steady::steady_from;
use crate::JournalState;

/// 5-point Gauss-Legendre rule for error norms (avoids superconvergent points of the 3-point rule).
const G5_X: [f64; 5] = [
    -0.906_179_845_938_664,
    -0.538_469_310_105_683,
    0.0,
    0.538_469_310_105_683,
    0.906_179_845_938_664,
];
const G5_W: [f64; 5] = [
    0.236_926_885_056_189,
    0.478_628_670_499_366,
    0.568_888_888_888_889,
    0.478_628_670_499_366,
    0.236_926_885_056_189,
];

/// Solves the steady scaled Reynolds equation with source S(phi, zeta) and Dirichlet data from
/// `exact(phi, zeta)` (phi ring-fixed, zeta = z/r), and returns (L2 error of P, L2 norm of exact).
pub fn manufactured_l2_error(
    params: &BearingParams,
    journal: JournalState,
    exact: &dyn Fn(f64, f64) -> f64,
    source: &dyn Fn(f64, f64) -> f64,
) -> Result<(f64, f64), FilmError> {
    params.validate()?;
    let mesh = Mesh::new(params);
    let ne = mesh.elem.len();
    let mut src = vec![0.0; mesh.n_blocks * ne * 9];
    let mut p0 = vec![1.0; mesh.n_nodes()];
    for k in 0..mesh.n_blocks {
        let phi0 = mesh.block_phi0_rad[k];
        for e in 0..ne {
            let (c, r) = (mesh.elem_col[e] as f64, mesh.elem_row[e] as f64);
            for q in 0..9 {
                let phi = phi0 + mesh.gauss_phi(c as usize, q / 3);
                let zeta = (r + 0.5 * (1.0 + GAUSS3_X[q % 3])) * mesh.dzeta_e;
                src[(k * ne + e) * 9 + q] = source(phi, zeta);
            }
        }
        for i in 0..mesh.npb {
            if mesh.dirichlet[i] {
                let (s, z) = mesh.node_coords(i);
                p0[k * mesh.npb + i] = exact(phi0 + s, z);
            }
        }
    }
    let sol = steady_from(params, mesh, journal, p0, Some(&src))?;
    let mesh = &sol.mesh;
    let (mut e2, mut n2) = (0.0, 0.0);
    for k in 0..mesh.n_blocks {
        let pb = &sol.p_rel[k * mesh.npb..(k + 1) * mesh.npb];
        for e in 0..ne {
            let (c, r) = (mesh.elem_col[e] as f64, mesh.elem_row[e] as f64);
            let (col0, dphi) = (mesh.col_phi0[c as usize], mesh.col_dphi[c as usize]);
            let jac = 0.25 * dphi * mesh.dzeta_e;
            for (qa, xa) in G5_X.iter().enumerate() {
                for (qb, xb) in G5_X.iter().enumerate() {
                    let (na, _) = shape1(*xa);
                    let (nb, _) = shape1(*xb);
                    let mut ph = 0.0;
                    for a in 0..3 {
                        for b in 0..3 {
                            ph += na[a] * nb[b] * pb[mesh.elem[e][3 * a + b] as usize];
                        }
                    }
                    let phi = mesh.block_phi0_rad[k] + col0 + 0.5 * (1.0 + xa) * dphi;
                    let zeta = (r + 0.5 * (1.0 + xb)) * mesh.dzeta_e;
                    let ex = exact(phi, zeta);
                    let w = G5_W[qa] * G5_W[qb] * jac;
                    e2 += w * (ph - ex) * (ph - ex);
                    n2 += w * ex * ex;
                }
            }
        }
    }
    Ok((e2.sqrt(), n2.sqrt()))
}
