//! Structured mesh of 9-node biquadratic quadrilaterals on each lobe (half width only),
//! plus the reference-element tables (shape functions at the 3 x 3 Gauss points).
//!
//! Coordinates: ring-fixed angle phi (rad) and zeta = z / r (dimensionless), z = 0 at the mid-plane.
//! Every lobe has the same local mesh; nodes are numbered with the axial direction fastest
//! (`node = line_position * nz + j`), which keeps the half bandwidth at about 2 nz + 2.
//! A plain bore is one periodic block; its phi-lines are numbered in "folded" order
//! (0, 1, N-1, 2, N-2, ...) so the wrap-around coupling stays inside a narrow band too.

use crate::params::BearingParams;
use serde::{Deserialize, Serialize};

/// 3-point Gauss-Legendre abscissae and weights on [-1, 1].
pub use bearing::quadrature::{GAUSS3_W, GAUSS3_X};

/// 1-D quadratic Lagrange shape functions on nodes -1, 0, 1 and their derivatives.
#[inline]
pub fn shape1(x: f64) -> ([f64; 3], [f64; 3]) {
    (
        [0.5 * x * (x - 1.0), 1.0 - x * x, 0.5 * x * (x + 1.0)],
        [x - 0.5, -2.0 * x, x + 0.5],
    )
}

/// Reference tables at the 9 Gauss points: `n[q][a]`, `dx[q][a]` (d/dxi), `dy[q][a]` (d/deta), `w[q]`.
/// Local node `a = 3 * a_phi + a_z`, Gauss point `q = 3 * q_phi + q_z`.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct Basis {
    pub n: [[f64; 9]; 9],
    pub dx: [[f64; 9]; 9],
    pub dy: [[f64; 9]; 9],
    pub w: [f64; 9],
}

impl Basis {
    pub fn new() -> Self {
        let mut b = Basis {
            n: [[0.0; 9]; 9],
            dx: [[0.0; 9]; 9],
            dy: [[0.0; 9]; 9],
            w: [0.0; 9],
        };
        for qa in 0..3 {
            for qb in 0..3 {
                let q = 3 * qa + qb;
                let (nx, dnx) = shape1(GAUSS3_X[qa]);
                let (ny, dny) = shape1(GAUSS3_X[qb]);
                b.w[q] = GAUSS3_W[qa] * GAUSS3_W[qb];
                for a in 0..3 {
                    for c in 0..3 {
                        b.n[q][3 * a + c] = nx[a] * ny[c];
                        b.dx[q][3 * a + c] = dnx[a] * ny[c];
                        b.dy[q][3 * a + c] = nx[a] * dny[c];
                    }
                }
            }
        }
        b
    }
}

impl Default for Basis {
    fn default() -> Self {
        Self::new()
    }
}

/// The mesh of one block (all blocks share it; block k is shifted by `block_phi0_rad[k]`).
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct Mesh {
    pub n_blocks: usize,
    pub ne_phi: usize,
    pub ne_z: usize,
    /// Distinct node lines along phi per block (2 ne_phi + 1, or 2 ne_phi if periodic).
    pub n_lines: usize,
    /// Nodes across the half width (2 ne_z + 1).
    pub nz: usize,
    /// Nodes per block.
    pub npb: usize,
    pub periodic: bool,
    pub block_phi0_rad: Vec<f64>,
    /// Element size in phi (rad) of a uniform mesh (the lobe's span over its elements) and in
    /// zeta = z / r.
    pub dphi_e: f64,
    pub dzeta_e: f64,
    /// Each element column's size in phi (rad) and its start (rad from the block start). On a
    /// uniform mesh every size is `dphi_e`; on a graded one (`BearingParams::mesh_grading` < 1)
    /// the sizes fall geometrically toward the lobe's trailing edge.
    pub col_dphi: Vec<f64>,
    pub col_phi0: Vec<f64>,
    /// The sizes differ (`col_dphi`); false: every formula takes `dphi_e` as before.
    pub graded: bool,
    /// Local node numbers of each element (block-local), order `3 * a_phi + a_z`.
    pub elem: Vec<[u32; 9]>,
    /// Element column (index along phi) of each element.
    pub elem_col: Vec<u32>,
    /// Element row (index along z) of each element.
    pub elem_row: Vec<u32>,
    /// Dirichlet (p = p_a) flag per block-local node.
    pub dirichlet: Vec<bool>,
    /// phi-line index and z index of each block-local node.
    pub node_line: Vec<u32>,
    pub node_j: Vec<u32>,
    /// Lower and upper half bandwidth of the block matrix.
    pub kl: usize,
    pub ku: usize,
    pub basis: Basis,
}

impl Mesh {
    pub fn new(p: &BearingParams) -> Self {
        let periodic = p.bore.plain_bore;
        let ne_phi = p.n_elem_phi;
        let ne_z = p.n_elem_z;
        let n_lines = if periodic { 2 * ne_phi } else { 2 * ne_phi + 1 };
        let nz = 2 * ne_z + 1;
        let npb = n_lines * nz;
        // Position of phi-line i in the numbering.
        let pos = |i: usize| -> usize {
            if !periodic {
                i
            } else if i == 0 {
                0
            } else if i <= n_lines / 2 {
                2 * i - 1
            } else {
                2 * (n_lines - i)
            }
        };
        let node = |i: usize, j: usize| -> u32 { (pos(i % n_lines) * nz + j) as u32 };
        let mut elem = Vec::with_capacity(ne_phi * ne_z);
        let mut elem_col = Vec::new();
        let mut elem_row = Vec::new();
        for c in 0..ne_phi {
            for r in 0..ne_z {
                let mut e = [0u32; 9];
                for a in 0..3 {
                    for b in 0..3 {
                        e[3 * a + b] = node(2 * c + a, 2 * r + b);
                    }
                }
                elem.push(e);
                elem_col.push(c as u32);
                elem_row.push(r as u32);
            }
        }
        let mut node_line = vec![0u32; npb];
        let mut node_j = vec![0u32; npb];
        let mut dirichlet = vec![false; npb];
        for i in 0..n_lines {
            for j in 0..nz {
                let k = node(i, j) as usize;
                node_line[k] = i as u32;
                node_j[k] = j as u32;
                dirichlet[k] = j == nz - 1 || (!periodic && (i == 0 || i == n_lines - 1));
            }
        }
        let mut kl = 0usize;
        for e in &elem {
            for &a in e {
                for &b in e {
                    kl = kl.max((a as i64 - b as i64).unsigned_abs() as usize);
                }
            }
        }
        let n_blocks = p.bore.n_blocks();
        let span = p.bore.block_span_rad();
        let dphi_e = span / ne_phi as f64;
        let graded = !periodic && p.mesh_grading != 1.0;
        let (col_dphi, col_phi0) = if graded {
            let raw: Vec<f64> = (0..ne_phi).map(|c| p.mesh_grading.powi(c as i32)).collect();
            let total: f64 = raw.iter().sum();
            let sizes: Vec<f64> = raw.iter().map(|r| span * r / total).collect();
            let starts = sizes
                .iter()
                .scan(0.0, |at, d| {
                    let start = *at;
                    *at += d;
                    Some(start)
                })
                .collect();
            (sizes, starts)
        } else {
            (
                vec![dphi_e; ne_phi],
                (0..ne_phi).map(|c| c as f64 * dphi_e).collect(),
            )
        };
        Mesh {
            n_blocks,
            ne_phi,
            ne_z,
            n_lines,
            nz,
            npb,
            periodic,
            block_phi0_rad: (0..n_blocks).map(|k| p.bore.block_start_rad(k)).collect(),
            dphi_e,
            dzeta_e: 0.5 * p.bore.b_m / p.bore.r_m / ne_z as f64,
            col_dphi,
            col_phi0,
            graded,
            elem,
            elem_col,
            elem_row,
            dirichlet,
            node_line,
            node_j,
            kl,
            ku: kl,
            basis: Basis::new(),
        }
    }

    /// Total number of pressure nodes (all blocks).
    pub fn n_nodes(&self) -> usize {
        self.n_blocks * self.npb
    }

    /// Block-local angle (rad, from the block start) and zeta of a block-local node.
    pub fn node_coords(&self, node: usize) -> (f64, f64) {
        (
            self.line_phi(self.node_line[node] as usize),
            self.node_j[node] as f64 * 0.5 * self.dzeta_e,
        )
    }

    /// Block-local angle of phi-line `i` (2 per element column, the last line at the span).
    pub fn line_phi(&self, i: usize) -> f64 {
        if !self.graded {
            return i as f64 * 0.5 * self.dphi_e;
        }
        let col = (i / 2).min(self.ne_phi - 1);
        self.col_phi0[col] + (i - 2 * col) as f64 * 0.5 * self.col_dphi[col]
    }

    /// Block-local angle of the Gauss point `qa` of element column `col`.
    pub fn gauss_phi(&self, col: usize, qa: usize) -> f64 {
        if !self.graded {
            return (col as f64 + 0.5 * (1.0 + GAUSS3_X[qa])) * self.dphi_e;
        }
        self.col_phi0[col] + 0.5 * (1.0 + GAUSS3_X[qa]) * self.col_dphi[col]
    }
}

/// The values of the nodal field `v` at an element's nine nodes.
#[inline(always)]
pub(crate) fn gather(nodes: &[u32; 9], v: &[f64]) -> [f64; 9] {
    let mut out = [0.0; 9];
    for a in 0..9 {
        out[a] = v[nodes[a] as usize];
    }
    out
}

/// The values at the element's nine Gauss points of the field whose nodal values are `pb`, with
/// the shape-function table `shape` (`Basis::n`, or a derivative's `Basis::dx`): sum over the
/// nodes a = 0..9 of shape[q][a] pb[node a]. The element's nodal values are gathered once and the
/// nine sums advance together, node by node (lanes over q): each sum still adds its terms in node
/// order, as the loop per Gauss point did, so the values are the same to the bit.
#[inline(always)]
pub(crate) fn at_gauss_points(shape: &[[f64; 9]; 9], nodes: &[u32; 9], pb: &[f64]) -> [f64; 9] {
    let pe = gather(nodes, pb);
    let mut v = [0.0; 9];
    for (a, &pa) in pe.iter().enumerate() {
        for q in 0..9 {
            v[q] += shape[q][a] * pa;
        }
    }
    v
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::test_rng::symmetric;

    /// A graded mesh's columns shrink by the grading from one to the next and fill the lobe;
    /// node lines and Gauss points run in order inside their columns; a uniform mesh and a plain
    /// bore keep `dphi_e` everywhere.
    #[test]
    fn graded_columns_shrink_by_the_grading_and_fill_the_lobe() {
        let mut p = BearingParams::paper();
        p.n_elem_phi = 10;
        p.mesh_grading = 0.8;
        let m = Mesh::new(&p);
        let span = p.bore.block_span_rad();
        assert!(m.graded);
        let total: f64 = m.col_dphi.iter().sum();
        assert!((total - span).abs() < 1e-14 * span);
        for c in 1..10 {
            assert!((m.col_dphi[c] / m.col_dphi[c - 1] - 0.8).abs() < 1e-12);
            assert!((m.col_phi0[c] - m.col_phi0[c - 1] - m.col_dphi[c - 1]).abs() < 1e-15);
        }
        assert!((m.line_phi(2 * 10) - span).abs() < 1e-14 * span);
        for i in 1..=20 {
            assert!(m.line_phi(i) > m.line_phi(i - 1), "line {i}");
        }
        for c in 0..10 {
            for q in 0..3 {
                let g = m.gauss_phi(c, q);
                assert!(g > m.line_phi(2 * c) && g < m.line_phi(2 * c + 2));
            }
        }
        p.mesh_grading = 1.0;
        let u = Mesh::new(&p);
        assert!(!u.graded && u.col_dphi.iter().all(|d| *d == u.dphi_e));
        let mut plain = BearingParams::plain_bore();
        plain.mesh_grading = 0.8;
        assert!(
            !Mesh::new(&plain).graded,
            "a plain bore is periodic: never graded"
        );
    }

    /// The lanes over Gauss points give the loop per Gauss point's values to the bit, for the
    /// shape functions and their derivative, on every element of the paper mesh with random
    /// nodal values of mixed magnitude.
    #[test]
    fn gauss_point_values_in_lanes_equal_the_loop_per_point_bit_for_bit() {
        let mesh = Mesh::new(&BearingParams::paper());
        let mut seed = 0x9e37_79b9_7f4a_7c15;
        let pb: Vec<f64> = (0..mesh.npb)
            .map(|i| symmetric(&mut seed) * 10f64.powi((i % 7) as i32 - 3))
            .collect();
        for shape in [&mesh.basis.n, &mesh.basis.dx] {
            for nodes in &mesh.elem {
                let lanes = at_gauss_points(shape, nodes, &pb);
                for (q, &v) in lanes.iter().enumerate() {
                    let mut per_point = 0.0;
                    for a in 0..9 {
                        per_point += shape[q][a] * pb[nodes[a] as usize];
                    }
                    assert_eq!(v.to_bits(), per_point.to_bits(), "Gauss point {q}");
                }
            }
        }
    }
}
