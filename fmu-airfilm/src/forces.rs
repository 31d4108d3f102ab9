//! Film force on the journal and diagnostics (peak pressure, gas mass, boundary mass flux).
//!
//! F = -2 Int_lobes (p - p_a) (cos theta, sin theta) r dphi dz + F_contact  (MODEL.md section 3),
//! the factor 2 for the unmeshed half width. With P = p/p_a and zeta = z/r:
//! F = -2 p_a r^2 Int (P - 1) (cos theta, sin theta) dphi dzeta.

use crate::geometry::{gap_m, GapField, Geometry};
use crate::mesh::{at_gauss_points, shape1, Mesh, GAUSS3_W, GAUSS3_X};
use crate::node_functionals::dot_gauge;
use crate::params::BearingParams;
use crate::JournalState;
use serde::{Deserialize, Serialize};

/// Outputs of the film at the current state.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct FilmOutputs {
    /// Force on the journal (pressure + contact), N. The ring feels the opposite.
    pub fx_n: f64,
    pub fy_n: f64,
    /// Contact part of the force, N, and its magnitude.
    pub fx_contact_n: f64,
    pub fy_contact_n: f64,
    pub f_contact_n: f64,
    /// Eccentricity ratio |(dx, dy)| / C.
    pub eps: f64,
    /// Minimum gap over the lobes, m.
    pub h_min_m: f64,
    /// Peak absolute pressure, Pa.
    pub p_max_pa: f64,
    /// Friction torque of the film on the journal, against the rotation [N m] (`friction`).
    #[serde(default)]
    pub friction_torque_nm: f64,
    /// Power the film dissipates [W]: friction torque times speed.
    #[serde(default)]
    pub power_loss_w: f64,
}

impl FilmOutputs {
    /// True if every output is a finite number.
    pub fn all_finite(&self) -> bool {
        [
            self.fx_n,
            self.fy_n,
            self.fx_contact_n,
            self.fy_contact_n,
            self.f_contact_n,
            self.eps,
            self.h_min_m,
            self.p_max_pa,
            self.friction_torque_nm,
            self.power_loss_w,
        ]
        .iter()
        .all(|x| x.is_finite())
    }
}

/// Pressure part of the force (N) from the scaled nodal pressures `p` of all blocks: per node a
/// fixed weight (`node_functionals`), Int (P - 1) cos theta = p_cos . (P - 1). The gauge pressure
/// in the sum, not Int P cos theta - Int cos theta: no cancellation of two ~30 N sums, and
/// ambient pressure gives exactly zero (a master reading the outputs at rest checks that).
pub fn pressure_force_n(prm: &BearingParams, mesh: &Mesh, geom: &Geometry, p: &[f64]) -> [f64; 2] {
    debug_assert_eq!(p.len(), mesh.n_blocks * mesh.npb);
    let f = &geom.nodal;
    let fx = dot_gauge(&f.p_cos, p);
    let fy = dot_gauge(&f.p_sin, p);
    let s = -2.0 * prm.p_a_pa * prm.bore.r_m * prm.bore.r_m;
    [s * fx, s * fy]
}

/// [`pressure_force_n`] through the column functionals point by point, the earlier evaluation
/// (tests compare the two).
#[cfg(test)]
pub(crate) fn pressure_force_by_columns_n(
    prm: &BearingParams,
    mesh: &Mesh,
    geom: &Geometry,
    p: &[f64],
) -> [f64; 2] {
    let cols = &geom.columns;
    let (mut fx, mut fy) = (0.0, 0.0);
    for k in 0..mesh.n_blocks {
        let pb = &p[k * mesh.npb..(k + 1) * mesh.npb];
        cols.each_p(pb, |g, p_int| {
            let gi = k * geom.nq + g;
            let w = p_int - cols.w_one[g];
            fx += w * geom.cos_q[gi];
            fy += w * geom.sin_q[gi];
        });
    }
    let s = -2.0 * prm.p_a_pa * prm.bore.r_m * prm.bore.r_m;
    [s * fx, s * fy]
}

/// Film gas mass times R T (J): Int p h dA over the full width.
pub fn mass_times_rt_j(prm: &BearingParams, mesh: &Mesh, gap: &GapField, p: &[f64]) -> f64 {
    let b = &mesh.basis;
    let nq = 3 * mesh.ne_phi;
    let mut m = 0.0;
    for k in 0..mesh.n_blocks {
        let pb = &p[k * mesh.npb..(k + 1) * mesh.npb];
        for (e, nodes) in mesh.elem.iter().enumerate() {
            let col = mesh.elem_col[e] as usize;
            let jac = 0.25 * mesh.col_dphi[col] * mesh.dzeta_e;
            let pq = at_gauss_points(&b.n, nodes, pb);
            for q in 0..9 {
                m += b.w[q] * jac * pq[q] * gap.h[k * nq + 3 * col + q / 3];
            }
        }
    }
    2.0 * prm.bore.r_m * prm.bore.r_m * prm.p_a_pa * prm.bore.c_m * m
}

/// P and its reference derivatives at (xi, eta) of element `e` of a block slice `pb`.
fn eval(mesh: &Mesh, e: usize, pb: &[f64], xi: f64, eta: f64) -> (f64, f64, f64) {
    let (nx, dnx) = shape1(xi);
    let (ny, dny) = shape1(eta);
    let nodes = &mesh.elem[e];
    let (mut p, mut px, mut py) = (0.0, 0.0, 0.0);
    for a in 0..3 {
        for c in 0..3 {
            let v = pb[nodes[3 * a + c] as usize];
            p += nx[a] * ny[c] * v;
            px += dnx[a] * ny[c] * v;
            py += nx[a] * dny[c] * v;
        }
    }
    let dphi = mesh.col_dphi[mesh.elem_col[e] as usize];
    (p, px * 2.0 / dphi, py * 2.0 / mesh.dzeta_e)
}

/// Gas mass outflow times R T (W) through the film boundary (lobe edges and bearing edges, both
/// halves), from the FE pressure gradient: mass flux * R T = p (-h^3/(12 eta) grad p + Omega r h/2 e_phi).
/// Used to check gas mass conservation: d/dt mass_times_rt_j = -outflow.
pub fn mass_outflow_times_rt_w(
    prm: &BearingParams,
    mesh: &Mesh,
    j: &JournalState,
    p: &[f64],
) -> f64 {
    let lam = prm.bearing_number(j.omega_rad_s);
    let c = prm.bore.c_m;
    let mut flow = 0.0;
    for k in 0..mesh.n_blocks {
        let pb = &p[k * mesh.npb..(k + 1) * mesh.npb];
        for (e, _) in mesh.elem.iter().enumerate() {
            let col = mesh.elem_col[e] as usize;
            let row = mesh.elem_row[e] as usize;
            for q in 0..3 {
                if row == mesh.ne_z - 1 {
                    // Bearing edge z = b/2, outward normal +zeta.
                    let s = mesh.gauss_phi(col, q);
                    let hh = gap_m(&prm.bore, k, s, j) / c;
                    let (pq, _, pz) = eval(mesh, e, pb, GAUSS3_X[q], 1.0);
                    let dphi = mesh.col_dphi[col];
                    flow += 0.5 * dphi * GAUSS3_W[q] * (-pq * hh.powi(3) * pz);
                }
                if !mesh.periodic && (col == 0 || col == mesh.ne_phi - 1) {
                    let (xi, s, sign) = if col == 0 {
                        (-1.0, 0.0, -1.0)
                    } else {
                        (1.0, prm.bore.block_span_rad(), 1.0)
                    };
                    let hh = gap_m(&prm.bore, k, s, j) / c;
                    let (pq, pp, _) = eval(mesh, e, pb, xi, GAUSS3_X[q]);
                    let fphi = -pq * hh.powi(3) * pp + lam * pq * hh;
                    flow += 0.5 * mesh.dzeta_e * GAUSS3_W[q] * sign * fphi;
                }
            }
        }
    }
    2.0 * prm.p_a_pa * prm.p_a_pa * c.powi(3) / (12.0 * prm.eta_pa_s) * flow
}
