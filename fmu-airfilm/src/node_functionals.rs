//! The film's force and the pressure part of its friction torque as weights per node: a few
//! contiguous dot products with the nodal pressures per communication step.
//!
//! `column_integrals` gives, per phi-Gauss point g, Int P and Int dP/dxi over its column as a
//! combination of the column's nodal values. The outputs weigh these with functions of the angle:
//! the force with cos theta and sin theta (fixed for a mesh), the friction's pressure part with the
//! gap H = 1 + step - ex cos theta - ey sin theta (linear in the eccentricity while no point is at
//! the gap floor). Summed over the points, each output is a fixed weight per node, or three of
//! them for the gap. Going through the columns at every call (180 points x 39 gathered nodes per
//! functional) was, with the friction, 7 % of path 1's CPU samples, against 1 599 contiguous
//! multiply-adds per dot product here.

use crate::column_integrals::ColumnIntegrals;

/// Weights per node of all blocks (block k's node i at k * npb + i).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct NodeFunctionals {
    /// Int P cos theta and Int P sin theta over the lobes (applied to P - 1, the gauge pressure:
    /// the weights of a column sum to its Int 1, so ambient pressure gives exactly zero force).
    pub p_cos: Vec<f64>,
    pub p_sin: Vec<f64>,
    /// Int (1 + step) dP/dxi, Int cos theta dP/dxi and Int sin theta dP/dxi over the lobes.
    pub dp_step: Vec<f64>,
    pub dp_cos: Vec<f64>,
    pub dp_sin: Vec<f64>,
}

impl NodeFunctionals {
    /// From the column functionals and the angle data at the `nq` phi-Gauss points of each of
    /// `n_blocks` blocks of `npb` nodes (`Geometry`'s tables).
    pub fn new(
        cols: &ColumnIntegrals,
        n_blocks: usize,
        npb: usize,
        cos_q: &[f64],
        sin_q: &[f64],
        step_q: &[f64],
    ) -> Self {
        let nq = cols.nq();
        let n = n_blocks * npb;
        let mut f = NodeFunctionals {
            p_cos: vec![0.0; n],
            p_sin: vec![0.0; n],
            dp_step: vec![0.0; n],
            dp_cos: vec![0.0; n],
            dp_sin: vec![0.0; n],
        };
        for k in 0..n_blocks {
            for g in 0..nq {
                let gi = k * nq + g;
                let (c, s, st) = (cos_q[gi], sin_q[gi], step_q[gi]);
                for (node, w_p, w_dp) in cols.entries(g) {
                    let i = k * npb + node;
                    f.p_cos[i] += w_p * c;
                    f.p_sin[i] += w_p * s;
                    f.dp_step[i] += w_dp * (1.0 + st);
                    f.dp_cos[i] += w_dp * c;
                    f.dp_sin[i] += w_dp * s;
                }
            }
        }
        f
    }

    /// Whether the weights fit `n` nodal values.
    pub fn fits(&self, n: usize) -> bool {
        [
            &self.p_cos,
            &self.p_sin,
            &self.dp_step,
            &self.dp_cos,
            &self.dp_sin,
        ]
        .iter()
        .all(|v| v.len() == n)
    }
}

/// Sum of w[i] (p[i] - 1) (the gauge part of a scaled pressure), like [`dot`].
#[inline]
pub fn dot_gauge(w: &[f64], p: &[f64]) -> f64 {
    dot_of(w, p, |x| x - 1.0)
}

/// Sum of w[i] p[i], in eight independent chains of additions (they vectorize).
#[inline]
pub fn dot(w: &[f64], p: &[f64]) -> f64 {
    dot_of(w, p, |x| x)
}

/// Sum of w[i] f(p[i]) in eight chains (one chain waits for each addition before the next).
#[inline(always)]
fn dot_of(w: &[f64], p: &[f64], f: impl Fn(f64) -> f64) -> f64 {
    const CHAINS: usize = 8;
    let mut lanes = [0.0; CHAINS];
    let (wc, pc) = (w.chunks_exact(CHAINS), p.chunks_exact(CHAINS));
    let tail: f64 = wc
        .remainder()
        .iter()
        .zip(pc.remainder())
        .map(|(a, &b)| a * f(b))
        .sum();
    for (a, b) in wc.zip(pc) {
        for l in 0..CHAINS {
            lanes[l] += a[l] * f(b[l]);
        }
    }
    lanes.iter().sum::<f64>() + tail
}

#[cfg(test)]
mod tests {
    use crate::forces::{pressure_force_by_columns_n, pressure_force_n};
    use crate::friction::{friction_torque, poiseuille_by_columns};
    use crate::geometry::Geometry;
    use crate::mesh::Mesh;
    use crate::params::BearingParams;
    use crate::test_rng::uniform;
    use crate::JournalState;

    fn bearings() -> Vec<BearingParams> {
        let mut plain = BearingParams::paper();
        plain.bore.dh_m = 0.0;
        let mut coarse = BearingParams::paper();
        (coarse.n_elem_phi, coarse.n_elem_z) = (7, 3);
        vec![BearingParams::paper(), plain, coarse]
    }

    /// The force and the friction's pressure part through the node weights equal the point-by-
    /// point column sums to rounding, on random pressure fields and eccentricities; where a
    /// point is at the gap floor the friction takes the column path itself.
    #[test]
    fn node_weights_equal_the_column_sums() {
        let mut seed = 0x51f1_5eed_0000_0001u64;
        for prm in bearings() {
            let mesh = Mesh::new(&prm);
            let geom = Geometry::new(&prm, &mesh);
            let n = mesh.n_blocks * mesh.npb;
            assert!(geom.nodal.fits(n));
            // Ambient pressure everywhere: exactly no force.
            assert_eq!(
                pressure_force_n(&prm, &mesh, &geom, &vec![1.0; n]),
                [0.0, 0.0]
            );
            for trial in 0..20 {
                let p: Vec<f64> = (0..n).map(|_| 0.5 + 2.0 * uniform(&mut seed)).collect();
                let f = pressure_force_n(&prm, &mesh, &geom, &p);
                let g = pressure_force_by_columns_n(&prm, &mesh, &geom, &p);
                let scale = f[0].hypot(f[1]);
                for i in 0..2 {
                    assert!(
                        (f[i] - g[i]).abs() <= 1e-12 * scale,
                        "{trial}: {f:?} vs {g:?}"
                    );
                }
                // Eccentricities up to 0.9 C: no point at the floor; 1.5 C: some.
                let r = if trial < 15 { 0.9 } else { 1.5 };
                let a = 2.0 * std::f64::consts::PI * uniform(&mut seed);
                let (ex, ey) = (r * a.cos(), r * a.sin());
                let by_columns = poiseuille_by_columns(&mesh, &geom, ex, ey, &p);
                let j = JournalState {
                    dx_m: ex * prm.bore.c_m,
                    dy_m: ey * prm.bore.c_m,
                    vx_m_s: 0.0,
                    vy_m_s: 0.0,
                    omega_rad_s: 1000.0,
                };
                let t = friction_torque(&prm, &mesh, &geom, &j, &p);
                let r2 = prm.bore.r_m;
                let to_nm = 2.0 * r2 * r2 * r2 * prm.bore.c_m * prm.p_a_pa * (2.0 / mesh.dphi_e)
                    / (2.0 * r2);
                let scale = 1e-12 * (by_columns.abs() + 1.0) * to_nm.abs();
                assert!(
                    (t.poiseuille_lobes_nm - to_nm * by_columns).abs() <= scale,
                    "trial {trial}: {} vs {}",
                    t.poiseuille_lobes_nm,
                    to_nm * by_columns
                );
            }
        }
    }

    /// The weights are not serialized: a geometry read back from its bytes rebuilds them equal.
    #[test]
    fn a_geometry_read_back_rebuilds_its_node_weights() {
        for prm in bearings() {
            let mesh = Mesh::new(&prm);
            let geom = Geometry::new(&prm, &mesh);
            let bytes = bincode::serialize(&geom).unwrap();
            let back: Geometry = bincode::deserialize(&bytes).unwrap();
            assert_eq!(back.nodal, geom.nodal);
            assert!(!geom.nodal.p_cos.is_empty());
        }
    }
}
