//! The film's output integrals over the lobes as linear functionals of the nodal pressures, one
//! per phi-Gauss point: the force and the friction torque read the pressure field once per
//! communication step, and these cost a sixth of the element-by-element quadrature.
//!
//! Every output integral over a block has the form Int f(phi) g(P) dphi dzeta with f a function of
//! the angle alone (cos theta, sin theta, the gap, 1 / gap: the same at the three zeta-Gauss
//! points of an element and in every element of a column) and g(P) = P or dP/dphi. So, with the
//! 3 x 3 Gauss rule, the sum over the elements e of a column and their zeta points qb of
//! w_q jac g(P)(q) is, for each phi-Gauss point (column, qa), a fixed linear combination of the
//! column's nodal values: `P_int = sum_m w_p[m] P[node m]` and `dP_int = sum_m w_dp[m] P[node m]`.
//! Weights of one node from several elements are summed, so a column of the paper mesh has 39
//! nodes per functional instead of 6 elements x 9 nodes x 3 points.

use crate::mesh::Mesh;
use serde::{Deserialize, Serialize};

/// Per phi-Gauss point g of a block (g = 3 col + qa, `nq` of them), its nodes and weights.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct ColumnIntegrals {
    /// Entries of point g: `start[g]..start[g + 1]`.
    start: Vec<u32>,
    /// Block-local node of each entry.
    node: Vec<u32>,
    /// Weight of the node's P in Int P over the column at this phi point (w_q jac N_a(q) summed
    /// over the elements and zeta points).
    w_p: Vec<f64>,
    /// The same for dP/dxi (the derivative along phi in the element's reference coordinate) on
    /// a uniform mesh; on a graded one for (dphi_e / 2) dP/dphi, the derivative in a reference
    /// coordinate of the uniform element size, so that the consumers' factor 2 / dphi_e gives
    /// dP/dphi on either (see `new`).
    w_dp: Vec<f64>,
    /// Int 1 over the column at this phi point, per point (sum of w_q jac).
    pub w_one: Vec<f64>,
}

impl ColumnIntegrals {
    pub fn new(mesh: &Mesh) -> Self {
        let b = &mesh.basis;
        let jac = 0.25 * mesh.dphi_e * mesh.dzeta_e;
        let nq = 3 * mesh.ne_phi;
        // (node, w_p, w_dp) per phi point, merged by node.
        let mut rows: Vec<Vec<(u32, f64, f64)>> = vec![Vec::new(); nq];
        let mut w_one = vec![0.0; nq];
        for (e, nodes) in mesh.elem.iter().enumerate() {
            let col = mesh.elem_col[e] as usize;
            // A graded mesh's column has its own Jacobian, and its dP/dxi its own factor to
            // dP/dphi: folded into the dP/dxi weights relative to the uniform factor 2 / dphi_e
            // the consumers apply (friction, node functionals).
            let (jac, to_uniform_xi) = if mesh.graded {
                let d = mesh.col_dphi[col];
                (0.25 * d * mesh.dzeta_e, mesh.dphi_e / d)
            } else {
                (jac, 1.0)
            };
            for q in 0..9 {
                let g = 3 * col + q / 3;
                let w = b.w[q] * jac;
                w_one[g] += w;
                for (a, &node) in nodes.iter().enumerate() {
                    let (wp, wd) = (w * b.n[q][a], w * b.dx[q][a] * to_uniform_xi);
                    match rows[g].iter_mut().find(|r| r.0 == node) {
                        Some(r) => {
                            r.1 += wp;
                            r.2 += wd;
                        }
                        None => rows[g].push((node, wp, wd)),
                    }
                }
            }
        }
        let mut out = ColumnIntegrals {
            start: vec![0],
            node: vec![],
            w_p: vec![],
            w_dp: vec![],
            w_one,
        };
        for mut row in rows {
            row.sort_by_key(|r| r.0);
            for (node, wp, wd) in row {
                out.node.push(node);
                out.w_p.push(wp);
                out.w_dp.push(wd);
            }
            out.start.push(out.node.len() as u32);
        }
        out
    }

    /// Phi-Gauss points per block.
    pub fn nq(&self) -> usize {
        self.w_one.len()
    }

    /// The entries of phi point `g`: (block-local node, weight in Int P, weight in Int dP/dxi).
    pub fn entries(&self, g: usize) -> impl Iterator<Item = (usize, f64, f64)> + '_ {
        let r = self.start[g] as usize..self.start[g + 1] as usize;
        self.node[r.clone()]
            .iter()
            .zip(&self.w_p[r.clone()])
            .zip(&self.w_dp[r])
            .map(|((&n, &wp), &wd)| (n as usize, wp, wd))
    }

    /// Nodes per block the tables refer to (the largest node + 1).
    pub fn nodes_per_block(&self) -> usize {
        self.node.iter().max().map_or(0, |&n| n as usize + 1)
    }

    /// Int dP/dxi over the column of phi point `g`, for the block's nodal values `pb`.
    #[inline]
    pub fn dp(&self, g: usize, pb: &[f64]) -> f64 {
        self.functional(&self.w_dp, g, pb)
    }

    /// Int P over the column of phi point `g`, for the block's nodal values `pb`.
    #[inline]
    pub fn p(&self, g: usize, pb: &[f64]) -> f64 {
        self.functional(&self.w_p, g, pb)
    }

    /// `f(g, Int P over the column of g)` for every phi point g in order (see `each`).
    #[inline]
    pub fn each_p(&self, pb: &[f64], f: impl FnMut(usize, f64)) {
        self.each(&self.w_p, pb, f)
    }

    /// `f(g, Int dP/dxi over the column of g)` for every phi point g in order (see `each`).
    #[inline]
    pub fn each_dp(&self, pb: &[f64], f: impl FnMut(usize, f64)) {
        self.each(&self.w_dp, pb, f)
    }

    /// `f(g, functional(weights, g, pb))` for g = 0 .. nq in order, four points per pass where
    /// they have as many entries: each sum is one chain of dependent additions (39 of them on the
    /// paper mesh, ~4 cycles each), and four chains side by side run in the time of one. Every
    /// sum still adds its terms in the same order, so the values are `functional`'s to the bit.
    #[inline(always)]
    fn each(&self, weights: &[f64], pb: &[f64], mut f: impl FnMut(usize, f64)) {
        let (nq, start) = (self.nq(), &self.start);
        let mut g = 0;
        while g + 4 <= nq {
            let r0: [usize; 4] = std::array::from_fn(|l| start[g + l] as usize);
            let len = start[g + 1] as usize - r0[0];
            if (0..4).all(|l| start[g + l + 1] as usize - r0[l] == len) {
                let w: [&[f64]; 4] = std::array::from_fn(|l| &weights[r0[l]..r0[l] + len]);
                let nd: [&[u32]; 4] = std::array::from_fn(|l| &self.node[r0[l]..r0[l] + len]);
                let mut acc = [0.0f64; 4];
                for m in 0..len {
                    for l in 0..4 {
                        acc[l] += w[l][m] * pb[nd[l][m] as usize];
                    }
                }
                for (l, v) in acc.into_iter().enumerate() {
                    f(g + l, v);
                }
            } else {
                for l in 0..4 {
                    f(g + l, self.functional(weights, g + l, pb));
                }
            }
            g += 4;
        }
        for g in g..nq {
            f(g, self.functional(weights, g, pb));
        }
    }

    /// sum over the entries m of point `g` of weights[m] pb[node m].
    #[inline(always)]
    fn functional(&self, weights: &[f64], g: usize, pb: &[f64]) -> f64 {
        let r = self.start[g] as usize..self.start[g + 1] as usize;
        self.node[r.clone()]
            .iter()
            .zip(&weights[r])
            .fold(0.0, |s, (&node, &w)| s + w * pb[node as usize])
    }

    /// Whether the tables fit a mesh with `nq` phi points per block and `npb` nodes per block (a
    /// deserialized state is checked with it).
    pub fn fits(&self, nq: usize, npb: usize) -> bool {
        self.start.len() == nq + 1
            && self.w_one.len() == nq
            && self.start.windows(2).all(|w| w[0] <= w[1])
            && *self.start.last().unwrap_or(&0) as usize == self.node.len()
            && self.w_p.len() == self.node.len()
            && self.w_dp.len() == self.node.len()
            && self.node.iter().all(|&n| (n as usize) < npb)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::at_gauss_points;
    use crate::params::BearingParams;
    use crate::test_rng::symmetric;

    /// The functionals against the element-by-element quadrature they replace, on the paper mesh,
    /// a plain bore's periodic mesh and two graded meshes (each column its own size; the dP/dxi
    /// weights then in the uniform element's reference coordinate, (dphi_e / 2) dP/dphi), with
    /// random nodal values: equal to round-off.
    #[test]
    fn column_functionals_equal_the_element_quadrature() {
        let mut seed = 0x5eed_u64;
        let graded = |n_elem_phi, mesh_grading| BearingParams {
            n_elem_phi,
            n_elem_z: 3,
            mesh_grading,
            ..BearingParams::paper()
        };
        for prm in [
            BearingParams::paper(),
            BearingParams {
                bore: crate::Bore::plain(),
                n_elem_phi: 12,
                n_elem_z: 3,
                ..BearingParams::default()
            },
            graded(10, 0.8),
            graded(7, 0.5),
        ] {
            let mesh = Mesh::new(&prm);
            assert_eq!(mesh.graded, prm.mesh_grading < 1.0);
            let cols = ColumnIntegrals::new(&mesh);
            assert!(cols.fits(3 * mesh.ne_phi, mesh.npb));
            let pb: Vec<f64> = (0..mesh.npb).map(|_| 1.0 + symmetric(&mut seed)).collect();
            let b = &mesh.basis;
            let nq = cols.nq();
            let (mut p_ref, mut dp_ref, mut one_ref) =
                (vec![0.0; nq], vec![0.0; nq], vec![0.0; nq]);
            for (e, nodes) in mesh.elem.iter().enumerate() {
                let col = mesh.elem_col[e] as usize;
                let dphi = if mesh.graded {
                    mesh.col_dphi[col]
                } else {
                    mesh.dphi_e
                };
                let jac = 0.25 * dphi * mesh.dzeta_e;
                let pq = at_gauss_points(&b.n, nodes, &pb);
                let dq = at_gauss_points(&b.dx, nodes, &pb);
                for q in 0..9 {
                    let g = 3 * col + q / 3;
                    p_ref[g] += b.w[q] * jac * pq[q];
                    // dq is dP/dxi of this element: dP/dphi = dq 2 / dphi.
                    dp_ref[g] += b.w[q] * jac * dq[q] * mesh.dphi_e / dphi;
                    one_ref[g] += b.w[q] * jac;
                }
            }
            for g in 0..nq {
                let (p, dp) = (cols.p(g, &pb), cols.dp(g, &pb));
                assert!(
                    (p - p_ref[g]).abs() <= 1e-14 * p_ref[g].abs(),
                    "g {g}: {p} vs {}",
                    p_ref[g]
                );
                let scale = dp_ref.iter().fold(0.0f64, |m, v| m.max(v.abs()));
                assert!(
                    (dp - dp_ref[g]).abs() <= 1e-13 * scale,
                    "g {g}: {dp} vs {}",
                    dp_ref[g]
                );
                assert!((cols.w_one[g] - one_ref[g]).abs() <= 1e-15 * one_ref[g]);
            }
            // A column of the paper mesh: 3 node lines x 13 nodes.
            if !mesh.periodic {
                assert_eq!(cols.start[1] - cols.start[0], 3 * mesh.nz as u32);
            }
        }
    }

    /// Four points per pass are a re-arrangement only: `each_p` and `each_dp` visit every point
    /// once, in order, with `p` and `dp`'s values bit for bit, on the paper mesh (60 points, 39
    /// entries each), on meshes whose point count is not a multiple of four, on a periodic mesh,
    /// and on tables whose points hold different numbers of entries (no mesh makes them, but a
    /// restored state's tables are only checked for consistency).
    #[test]
    fn four_points_per_pass_give_each_points_value_bit_for_bit() {
        let mut seed = 0x4_u64;
        for (bore, ne_phi, ne_z) in [
            (crate::Bore::paper(), 20, 6),
            (crate::Bore::paper(), 7, 3),
            (crate::Bore::paper(), 5, 2),
            (crate::Bore::plain(), 12, 3),
            (crate::Bore::plain(), 5, 2),
        ] {
            let prm = BearingParams {
                bore,
                n_elem_phi: ne_phi,
                n_elem_z: ne_z,
                ..BearingParams::default()
            };
            let mesh = Mesh::new(&prm);
            let cols = ColumnIntegrals::new(&mesh);
            let pb: Vec<f64> = (0..mesh.npb)
                .map(|i| symmetric(&mut seed) * 10f64.powi((i % 5) as i32 - 2))
                .collect();
            let label = format!("{ne_phi}x{ne_z}");
            check_each(
                &cols,
                &pb,
                &label,
                &|c, pb, f| c.each_p(pb, f),
                ColumnIntegrals::p,
            );
            check_each(
                &cols,
                &pb,
                &label,
                &|c, pb, f| c.each_dp(pb, f),
                ColumnIntegrals::dp,
            );
        }
        let pb: Vec<f64> = (0..40).map(|_| symmetric(&mut seed)).collect();
        let start = vec![0u32, 3, 6, 9, 12, 14, 19, 20, 23, 26, 30, 34, 38, 38, 41];
        let n = *start.last().unwrap() as usize;
        let node: Vec<u32> = (0..n).map(|i| (i * 7 % 40) as u32).collect();
        let w: Vec<f64> = (0..n).map(|_| symmetric(&mut seed)).collect();
        let cols = ColumnIntegrals {
            start,
            node,
            w_p: w.clone(),
            w_dp: w,
            w_one: vec![1.0; 14],
        };
        assert!(cols.fits(14, 40));
        check_each(
            &cols,
            &pb,
            "uneven tables",
            &|c, pb, f| c.each_p(pb, f),
            ColumnIntegrals::p,
        );
    }

    /// `ColumnIntegrals::each_p` or `each_dp`, as a value.
    type Each = dyn Fn(&ColumnIntegrals, &[f64], &mut dyn FnMut(usize, f64));

    /// `each` visits every point once, in order, with `one`'s value bit for bit.
    fn check_each(
        cols: &ColumnIntegrals,
        pb: &[f64],
        label: &str,
        each: &Each,
        one: fn(&ColumnIntegrals, usize, &[f64]) -> f64,
    ) {
        let mut seen = Vec::new();
        each(cols, pb, &mut |g, v| {
            assert_eq!(
                v.to_bits(),
                one(cols, g, pb).to_bits(),
                "{label}: point {g}"
            );
            seen.push(g);
        });
        assert_eq!(seen, (0..cols.nq()).collect::<Vec<_>>(), "{label}");
    }
}
