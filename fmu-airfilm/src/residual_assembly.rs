//! The Galerkin residual of the Reynolds equation (`reynolds::residual`), four elements at a time
//! (one per vector lane) and sum-factorized.
//!
//! The 9-node element is a tensor product of 1D quadratics, and so are its 3 x 3 Gauss points:
//! N_a(q) = N1(q_phi, a_phi) N1(q_z, a_z), with local node a = 3 a_phi + a_z and Gauss point
//! q = 3 q_phi + q_z (`mesh::Basis`). Interpolating P, dP/dxi, dP/deta and dP/dt to the Gauss
//! points contracts along z first and then along phi (189 multiply-adds per element instead of
//! 324), and the test-function sums go back the same way (135 instead of 243), rather than the
//! full 9 x 9 tables with the Gauss points as lanes (padded to 12). The sums run in another
//! order, so the residual differs from the scalar formulation by rounding (tested against it to
//! 1e-13 of the element terms' scale).

use crate::geometry::GapField;
use crate::jacobian_assembly::{element_groups, ELEM_LANES};
use crate::mesh::{shape1, Mesh, GAUSS3_X};
use crate::reynolds::Coeffs;

/// The 1D quadratic shape functions (`n1[q][a]`) and their derivatives (`d1[q][a]`) at the three
/// Gauss points.
#[inline(always)]
fn one_d_tables() -> ([[f64; 3]; 3], [[f64; 3]; 3]) {
    let mut n1 = [[0.0; 3]; 3];
    let mut d1 = [[0.0; 3]; 3];
    for q in 0..3 {
        (n1[q], d1[q]) = shape1(GAUSS3_X[q]);
    }
    (n1, d1)
}

/// `reynolds::residual`'s body, inlined into its runtime dispatch.
#[allow(clippy::too_many_arguments)]
#[inline(always)]
pub(crate) fn residual_element_lanes(
    mesh: &Mesh,
    gap: &GapField,
    k: usize,
    co: Coeffs,
    p: &[f64],
    hist: &[f64],
    source: Option<&[f64]>,
    out: &mut [f64],
) {
    const L: usize = ELEM_LANES;
    out.iter_mut().for_each(|v| *v = 0.0);
    let (n1, d1) = one_d_tables();
    let sy = 2.0 / mesh.dzeta_e;
    let nq = 3 * mesh.ne_phi;
    let (lam, tau, c0) = (co.lambda, co.tau_s, co.c0_per_s);
    // Per lane: d xi / d phi and the Gauss weights times the element's Jacobian (on a uniform
    // mesh the same in every lane, computed as the uniform formulas did: the same bits).
    let lane_scales = |lane_elem: &[usize; L]| -> ([f64; L], [[f64; L]; 9]) {
        let dphi: [f64; L] = if mesh.graded {
            std::array::from_fn(|l| mesh.col_dphi[mesh.elem_col[lane_elem[l]] as usize])
        } else {
            [mesh.dphi_e; L]
        };
        let sx = std::array::from_fn(|l| 2.0 / dphi[l]);
        let wj = std::array::from_fn(|q| {
            std::array::from_fn(|l| mesh.basis.w[q] * (0.25 * dphi[l] * mesh.dzeta_e))
        });
        (sx, wj)
    };
    for (e0, used, lane_elem) in element_groups(mesh.elem.len()) {
        let (sx, wj) = lane_scales(&lane_elem);
        let mut pe = [[0.0; L]; 9];
        let mut pd = [[0.0; L]; 9];
        for (l, &e) in lane_elem.iter().enumerate() {
            for (a, &node) in mesh.elem[e].iter().enumerate() {
                let v = p[node as usize];
                pe[a][l] = v;
                pd[a][l] = c0 * v - hist[node as usize];
            }
        }
        // Along z: per phi-node row a_phi, P and dP/deta and dP/dt at the z-Gauss points.
        let mut u = [[[0.0; L]; 3]; 3];
        let mut u_z = [[[0.0; L]; 3]; 3];
        let mut u_t = [[[0.0; L]; 3]; 3];
        for ap in 0..3 {
            for qz in 0..3 {
                for az in 0..3 {
                    let (nv, dv) = (n1[qz][az], d1[qz][az]);
                    let (pa, da) = (&pe[3 * ap + az], &pd[3 * ap + az]);
                    for l in 0..L {
                        u[ap][qz][l] += nv * pa[l];
                        u_z[ap][qz][l] += dv * pa[l];
                        u_t[ap][qz][l] += nv * da[l];
                    }
                }
            }
        }
        // Along phi, and the flux terms at each Gauss point (the gap varies along phi only).
        let (mut fx, mut fy, mut fs) = ([[0.0; L]; 9], [[0.0; L]; 9], [[0.0; L]; 9]);
        for qp in 0..3 {
            let (mut h, mut hphi, mut ht) = ([0.0; L], [0.0; L], [0.0; L]);
            for l in 0..L {
                let gi = k * nq + 3 * mesh.elem_col[lane_elem[l]] as usize + qp;
                (h[l], hphi[l], ht[l]) = (gap.h[gi], gap.h_phi[gi], gap.h_t[gi]);
            }
            for qz in 0..3 {
                let q = 3 * qp + qz;
                let (mut pq, mut px, mut py, mut pt) = ([0.0; L], [0.0; L], [0.0; L], [0.0; L]);
                for ap in 0..3 {
                    let (nv, dv) = (n1[qp][ap], d1[qp][ap]);
                    for l in 0..L {
                        pq[l] += nv * u[ap][qz][l];
                        px[l] += dv * u[ap][qz][l];
                        py[l] += nv * u_z[ap][qz][l];
                        pt[l] += nv * u_t[ap][qz][l];
                    }
                }
                let w = &wj[q];
                for l in 0..L {
                    let (pxq, pyq) = (px[l] * sx[l], py[l] * sy);
                    let a3 = pq[l] * h[l] * h[l] * h[l];
                    fx[q][l] = w[l] * a3 * pxq * sx[l];
                    fy[q][l] = w[l] * a3 * pyq * sy;
                    let src =
                        lam * (pxq * h[l] + pq[l] * hphi[l]) + tau * (h[l] * pt[l] + pq[l] * ht[l]);
                    fs[q][l] = w[l] * src;
                }
                if let Some(s) = source {
                    for l in 0..L {
                        fs[q][l] -= w[l] * s[lane_elem[l] * 9 + q];
                    }
                }
            }
        }
        // The test functions back along z (Gauss points q_z to nodes a_z) ...
        let (mut tx, mut ty) = ([[[0.0; L]; 3]; 3], [[[0.0; L]; 3]; 3]);
        for qp in 0..3 {
            for az in 0..3 {
                for qz in 0..3 {
                    let (nv, dv) = (n1[qz][az], d1[qz][az]);
                    let q = 3 * qp + qz;
                    for l in 0..L {
                        tx[qp][az][l] += nv * fx[q][l];
                        ty[qp][az][l] += dv * fy[q][l] + nv * fs[q][l];
                    }
                }
            }
        }
        // ... and along phi (q_phi to a_phi).
        let mut re = [[0.0; L]; 9];
        for ap in 0..3 {
            for az in 0..3 {
                for qp in 0..3 {
                    let (nv, dv) = (n1[qp][ap], d1[qp][ap]);
                    for l in 0..L {
                        re[3 * ap + az][l] += dv * tx[qp][az][l] + nv * ty[qp][az][l];
                    }
                }
            }
        }
        for l in 0..used {
            for (a, &node) in mesh.elem[e0 + l].iter().enumerate() {
                out[node as usize] += re[a][l];
            }
        }
    }
    for (i, d) in mesh.dirichlet.iter().enumerate() {
        if *d {
            out[i] = 0.0;
        }
    }
}
