//! Small dense linear algebra: LU with partial pivoting (row-major); the 3x3 array types the
//! serialized parameters use (the bodies compute with nalgebra, body.rs).
//!
//! The LU serves the 56 x 56 GGL iteration matrix (factored now and then, solved at every Newton
//! iteration) and the 8 x 8 lateral mass matrix. The factorization is written out here: the GGL
//! matrix has about 134 nonzeros of 3136 and the elimination skips zero multipliers, which makes
//! it 2.7 times faster than faer's dense `lu_in_place` on that matrix (BENCHMARKS.md, "faer
//! (session 7)"). The two triangular solves are faer's, 1.6 times faster than the former plain
//! loops. The factors are plain data, serializable, so a restored `Rotor` reuses them
//! bit-identically. Kernel tests: tests/linalg_kernels.rs.

use crate::params::RotorError;
use serde::{Deserialize, Serialize};

pub type Vec3 = [f64; 3];
pub type Mat3 = [[f64; 3]; 3];

/// LU factors of a square matrix, P A = L U, stored row-major in one buffer.
#[derive(Clone, Debug, Default, Serialize, Deserialize)]
pub struct Lu {
    n: usize,
    lu: Vec<f64>,
    piv: Vec<usize>,
}

impl Lu {
    /// Factor the row-major n x n matrix `a` (consumed).
    pub fn factor(n: usize, mut a: Vec<f64>, what: &'static str) -> Result<Lu, RotorError> {
        debug_assert_eq!(a.len(), n * n);
        let mut piv = vec![0usize; n];
        for k in 0..n {
            let mut p = k;
            let mut best = a[k * n + k].abs();
            for i in k + 1..n {
                let v = a[i * n + k].abs();
                if v > best {
                    best = v;
                    p = i;
                }
            }
            if best == 0.0 || !best.is_finite() {
                return Err(RotorError::Singular(what));
            }
            piv[k] = p;
            if p != k {
                for j in 0..n {
                    a.swap(k * n + j, p * n + j);
                }
            }
            let inv = 1.0 / a[k * n + k];
            for i in k + 1..n {
                let l = a[i * n + k] * inv;
                if l != 0.0 {
                    a[i * n + k] = l;
                    let (top, bottom) = a.split_at_mut(i * n);
                    let rk = &top[k * n + k + 1..k * n + n];
                    let ri = &mut bottom[k + 1..n];
                    for (x, y) in ri.iter_mut().zip(rk) {
                        *x -= l * y;
                    }
                } else {
                    a[i * n + k] = 0.0;
                }
            }
        }
        Ok(Lu { n, lu: a, piv })
    }

    pub fn dim(&self) -> usize {
        self.n
    }

    /// Solve A x = b in place: the row interchanges, then faer's unit-lower and upper
    /// triangular solves on the (row-major) factors.
    pub fn solve(&self, b: &mut [f64]) {
        use faer::linalg::triangular_solve as ts;
        let n = self.n;
        assert_eq!(b.len(), n, "Lu::solve: right-hand side of the wrong length");
        for k in 0..n {
            let p = self.piv[k];
            if p != k {
                b.swap(k, p);
            }
        }
        let lu = faer::MatRef::from_row_major_slice(&self.lu, n, n);
        let mut x = faer::MatMut::from_column_major_slice_mut(b, n, 1);
        ts::solve_unit_lower_triangular_in_place(lu, x.as_mut(), faer::Par::Seq);
        ts::solve_upper_triangular_in_place(lu, x.as_mut(), faer::Par::Seq);
    }
}

/// Solve a small dense system (row-major), convenience wrapper.
pub fn solve_dense(
    n: usize,
    a: Vec<f64>,
    b: &mut [f64],
    what: &'static str,
) -> Result<(), RotorError> {
    let lu = Lu::factor(n, a, what)?;
    lu.solve(b);
    Ok(())
}
