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
#[cfg(test)]
use crate::mesh::gather;
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

/// Residual of block `k`. `p`, `hist`, `out` are block slices; `source` (if any) holds S at the
/// Gauss points, indexed `elem * 9 + q`. Dirichlet rows get 0 (their values are kept fixed).
///
/// Runs the same code compiled for the widest vector unit the CPU has (pulp's runtime dispatch),
/// four elements at a time and sum-factorized (`residual_assembly`). Rust neither reorders nor
/// fuses floating-point operations, so the result is bit-identical on every CPU; it equals the
/// scalar formulation in the tests to rounding (the sums run in another order).
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
    struct Op<'a> {
        mesh: &'a Mesh,
        gap: &'a GapField,
        k: usize,
        co: Coeffs,
        p: &'a [f64],
        hist: &'a [f64],
        source: Option<&'a [f64]>,
        out: &'a mut [f64],
    }
    impl pulp::WithSimd for Op<'_> {
        type Output = ();
        #[inline(always)]
        fn with_simd<S: pulp::Simd>(self, _: S) {
            let Op {
                mesh,
                gap,
                k,
                co,
                p,
                hist,
                source,
                out,
            } = self;
            crate::residual_assembly::residual_element_lanes(mesh, gap, k, co, p, hist, source, out)
        }
    }
    pulp::Arch::new().dispatch(Op {
        mesh,
        gap,
        k,
        co,
        p,
        hist,
        source,
        out,
    })
}

/// Analytic Jacobian dF/dP of block `k` (including c0 tau M) into `lu` (overwritten). Compiled
/// for the widest vector unit the CPU has, like `residual`; the same operations in the same order
/// on every CPU. Four elements at a time, one per vector lane (`jacobian_assembly`).
pub fn jacobian(mesh: &Mesh, gap: &GapField, k: usize, co: Coeffs, p: &[f64], lu: &mut BandLu) {
    struct Op<'a> {
        mesh: &'a Mesh,
        gap: &'a GapField,
        k: usize,
        co: Coeffs,
        p: &'a [f64],
        lu: &'a mut BandLu,
    }
    impl pulp::WithSimd for Op<'_> {
        type Output = ();
        #[inline(always)]
        fn with_simd<S: pulp::Simd>(self, _: S) {
            crate::jacobian_assembly::jacobian_element_lanes(
                self.mesh, self.gap, self.k, self.co, self.p, self.lu,
            )
        }
    }
    pulp::Arch::new().dispatch(Op {
        mesh,
        gap,
        k,
        co,
        p,
        lu,
    })
}

/// The residual written one Gauss point at a time over the full 9 x 9 tables, as it was before
/// the lane layouts: the reference `residual` must equal to rounding (tests only).
#[cfg(test)]
pub(crate) fn residual_scalar_reference(
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
    let sy = 2.0 / mesh.dzeta_e;
    let nq = 3 * mesh.ne_phi;
    let (lam, tau, c0) = (co.lambda, co.tau_s, co.c0_per_s);
    for (e, nodes) in mesh.elem.iter().enumerate() {
        let col = mesh.elem_col[e] as usize;
        // Each column's own size (on a uniform mesh `dphi_e` itself: the same bits).
        let (sx, jac) = (
            2.0 / mesh.col_dphi[col],
            0.25 * mesh.col_dphi[col] * mesh.dzeta_e,
        );
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::lane_test_cases::{lane_cases, LaneCase};
    use crate::test_rng::uniform;

    /// The sum-factorized element lanes compute what the scalar formulation does: on random
    /// pressures, histories, sources and journal states (plain and lobed bores, every block, a
    /// mesh whose element count leaves a partly used last group of lanes), `residual` equals it to
    /// 1e-13 of the largest element term, the scale of rounding in either sum.
    #[test]
    fn residual_equals_the_scalar_formulation() {
        let mut seed = 0x9e37_79b9_7f4a_7c15u64;
        for LaneCase {
            case,
            mesh,
            gap,
            co,
        } in lane_cases(&mut seed)
        {
            let npb = mesh.npb;
            let src: Vec<f64> = (0..mesh.elem.len() * 9)
                .map(|_| uniform(&mut seed) - 0.5)
                .collect();
            for k in 0..mesh.n_blocks {
                let p: Vec<f64> = (0..npb).map(|_| 0.5 + 2.0 * uniform(&mut seed)).collect();
                let hist: Vec<f64> = (0..npb).map(|_| 1e5 * uniform(&mut seed)).collect();
                for source in [None, Some(&src[..])] {
                    let (mut new, mut old) = (vec![f64::NAN; npb], vec![f64::NAN; npb]);
                    residual(&mesh, &gap, k, co, &p, &hist, source, &mut new);
                    residual_scalar_reference(&mesh, &gap, k, co, &p, &hist, source, &mut old);
                    // The terms' scale: the residual of the absolute values is not at hand, but
                    // random fields are far from equilibrium, so the largest |F_a| is of it.
                    let scale = old.iter().fold(0.0f64, |m, v| m.max(v.abs()));
                    assert!(scale > 0.0);
                    for i in 0..npb {
                        assert!(
                            (new[i] - old[i]).abs() <= 1e-13 * scale,
                            "case {case}, block {k}, node {i}: {} vs {} (scale {scale:e})",
                            new[i],
                            old[i]
                        );
                        assert_eq!(new[i] == 0.0, mesh.dirichlet[i], "node {i}");
                    }
                }
            }
        }
    }
}
