//! Small dense linear algebra: LU with partial pivoting (row-major); the 3x3 array types the
//! serialized parameters use (the bodies compute with nalgebra, body.rs).
//!
//! The LU serves the 56 x 56 GGL iteration matrix (factored now and then, solved at every Newton
//! iteration) and the 8 x 8 lateral mass matrix. The factorization is written out here: the GGL
//! matrix has about 134 nonzeros of 3136 and the elimination skips zero multipliers, which makes
//! it 2.7 times faster than faer's dense `lu_in_place` on that matrix (BENCHMARKS.md, "faer").
//! The elimination follows the nonzero pattern, held as bit masks for n <= 64
//! (`factor_by_masks`): another 2x on the GGL matrix (benches/linalg.rs). The triangular solves
//! run over the factors' nonzeros only, row by row (rather than faer's dense solves, 1.6 times
//! faster than plain dense loops): the GGL factors keep
//! most of the matrix's zeros, and a run-up solves with them at every Newton iteration. The
//! factors are plain data, serialized as the dense factors and the pivots (the nonzero lists are
//! rebuilt on reading), so a restored `Rotor` reuses them bit-identically. Kernel tests:
//! tests/linalg_kernels.rs.

use crate::params::RotorError;
use serde::{Deserialize, Serialize};

pub type Vec3 = [f64; 3];
pub type Mat3 = [[f64; 3]; 3];

/// LU factors of a square matrix, P A = L U, stored row-major in one buffer, with the nonzeros
/// of L and U listed row by row for the solves.
#[derive(Clone, Debug, Default, Serialize, Deserialize)]
#[serde(from = "DenseFactors", into = "DenseFactors")]
pub struct Lu {
    n: usize,
    lu: Vec<f64>,
    piv: Vec<usize>,
    rows: FactorRows,
}

/// The serialized form of [`Lu`]: what the factorization computed (the nonzero lists follow
/// from it). The same fields as `Lu` had before the lists, so saved states still read.
#[derive(Clone, Debug, Default, Serialize, Deserialize)]
struct DenseFactors {
    n: usize,
    lu: Vec<f64>,
    piv: Vec<usize>,
}

impl From<DenseFactors> for Lu {
    fn from(d: DenseFactors) -> Lu {
        let rows = FactorRows::new(d.n, &d.lu);
        Lu {
            n: d.n,
            lu: d.lu,
            piv: d.piv,
            rows,
        }
    }
}

impl From<Lu> for DenseFactors {
    fn from(lu: Lu) -> DenseFactors {
        let Lu {
            n,
            lu,
            piv,
            rows: _,
        } = lu;
        DenseFactors { n, lu, piv }
    }
}

/// The indices of the set bits of `m`, ascending.
fn bits(mut m: u64) -> impl Iterator<Item = usize> {
    std::iter::from_fn(move || {
        (m != 0).then(|| {
            let j = m.trailing_zeros() as usize;
            m &= m - 1;
            j
        })
    })
}

/// The nonzeros of the unit lower factor L (below the diagonal) and of U (above it) by rows, in
/// ascending columns, and U's diagonal. Row i's entries of L are `l_val[l_start[i]..l_start[i +
/// 1]]` at columns `l_col[..]`; likewise for U.
#[derive(Clone, Debug, Default)]
struct FactorRows {
    l_start: Vec<u32>,
    l_col: Vec<u32>,
    l_val: Vec<f64>,
    u_start: Vec<u32>,
    u_col: Vec<u32>,
    u_val: Vec<f64>,
    diag: Vec<f64>,
}

impl FactorRows {
    /// Empty lists for an n x n factorization, sized for dense factors up front: a run-up
    /// refactorizes up to every step where a journal rides on its ring, and growing the lists
    /// entry by entry was costly there.
    fn with_capacity(n: usize) -> FactorRows {
        let half = n * n.saturating_sub(1) / 2;
        let mut r = FactorRows {
            l_start: Vec::with_capacity(n + 1),
            l_col: Vec::with_capacity(half),
            l_val: Vec::with_capacity(half),
            u_start: Vec::with_capacity(n + 1),
            u_col: Vec::with_capacity(half),
            u_val: Vec::with_capacity(half),
            diag: Vec::with_capacity(n),
        };
        r.l_start.push(0);
        r.u_start.push(0);
        r
    }

    /// Appends row `i` of U from the factor's row: the nonzeros among `cols` (ascending, right of
    /// the diagonal; all of them or those the nonzero pattern holds), then the diagonal.
    /// A NaN entry is kept (it must reach the solution, never be skipped).
    fn push_u_row(&mut self, i: usize, row: &[f64], cols: impl Iterator<Item = usize>) {
        for j in cols {
            if row[j] != 0.0 {
                self.u_col.push(j as u32);
                self.u_val.push(row[j]);
            }
        }
        self.u_start.push(self.u_col.len() as u32);
        self.diag.push(row[i]);
    }

    /// Appends a row of L from the factor's row: the nonzeros among `cols` (ascending, left of
    /// the diagonal).
    fn push_l_row(&mut self, row: &[f64], cols: impl Iterator<Item = usize>) {
        for j in cols {
            if row[j] != 0.0 {
                self.l_col.push(j as u32);
                self.l_val.push(row[j]);
            }
        }
        self.l_start.push(self.l_col.len() as u32);
    }

    /// The lists of finished dense factors (a state read back).
    fn new(n: usize, lu: &[f64]) -> FactorRows {
        let mut r = FactorRows::with_capacity(n);
        for i in 0..n {
            r.push_u_row(i, &lu[i * n..(i + 1) * n], i + 1..n);
        }
        for i in 0..n {
            r.push_l_row(&lu[i * n..(i + 1) * n], 0..i);
        }
        r
    }
}

/// The pivot row of column k: the first largest |a(i, k)| over i = k and the rows `below`
/// (ascending; all of them, or those the nonzero pattern holds). An exactly zero or non-finite
/// largest entry is a singular matrix.
fn pivot_row(
    a: &[f64],
    n: usize,
    k: usize,
    below: impl Iterator<Item = usize>,
    what: &'static str,
) -> Result<usize, RotorError> {
    let mut p = k;
    let mut best = a[k * n + k].abs();
    for i in below {
        let v = a[i * n + k].abs();
        if v > best {
            best = v;
            p = i;
        }
    }
    if best == 0.0 || !best.is_finite() {
        return Err(RotorError::Singular(what));
    }
    Ok(p)
}

/// Eliminates column k from `row` with row k of U (`inv` = 1 / its diagonal, its nonzeros right
/// of the diagonal at `u_cols`): stores the multiplier in `row[k]` and subtracts it times U's
/// nonzeros. False (and `row[k]` = 0) if the multiplier is zero.
fn eliminate(row: &mut [f64], k: usize, inv: f64, u_cols: &[u32], u_vals: &[f64]) -> bool {
    let l = row[k] * inv;
    if l == 0.0 {
        row[k] = 0.0;
        return false;
    }
    row[k] = l;
    for (&j, &u) in u_cols.iter().zip(u_vals) {
        row[j as usize] -= l * u;
    }
    true
}

impl Lu {
    /// Factor the row-major n x n matrix `a` (consumed), with partial pivoting.
    ///
    /// Row k of U is final once its pivot is in place (later steps swap and update only rows
    /// below it), so its nonzeros are listed then, and the elimination updates the rows below
    /// in those columns only: the entries a dense row update would leave unchanged (x - l 0) are
    /// skipped, the others computed as before. The GGL matrix's rows of U hold a few nonzeros of
    /// up to 55 columns.
    pub fn factor(n: usize, a: Vec<f64>, what: &'static str) -> Result<Lu, RotorError> {
        debug_assert_eq!(a.len(), n * n);
        if n <= 64 {
            Self::factor_by_masks(n, a, what)
        } else {
            Self::factor_dense(n, a, what)
        }
    }

    /// [`Self::factor`] for n <= 64, driven by the nonzero pattern held as bit masks (one u64
    /// per row and per column, kept through interchanges and fill-in): the pivot search, the
    /// interchanges, the eliminated rows and the lists visit nonzeros only, where the dense loops
    /// scanned all n entries of a column or row at each step (the GGL matrix has ~134 nonzeros
    /// of 3136 and fills in to ~300). The same operations on the same entries in the same order:
    /// bit-identical to [`Self::factor_dense`] (kernel test).
    fn factor_by_masks(n: usize, mut a: Vec<f64>, what: &'static str) -> Result<Lu, RotorError> {
        // Bits j of row i and i of column j: entry (i, j) is not zero (or NaN).
        let mut row_nz = [0u64; 64];
        let mut col_nz = [0u64; 64];
        for i in 0..n {
            let mut m = 0u64;
            for (j, &v) in a[i * n..(i + 1) * n].iter().enumerate() {
                m |= u64::from(v != 0.0) << j;
            }
            row_nz[i] = m;
            for j in bits(m) {
                col_nz[j] |= 1 << i;
            }
        }
        // Rows (or columns) above index k.
        let above = |k: usize| (!0u64).checked_shl(k as u32 + 1).unwrap_or(0);
        let mut piv = vec![0usize; n];
        let mut rows = FactorRows::with_capacity(n);
        for k in 0..n {
            let p = pivot_row(&a, n, k, bits(col_nz[k] & above(k)), what)?;
            piv[k] = p;
            if p != k {
                for j in bits(row_nz[k] | row_nz[p]) {
                    a.swap(k * n + j, p * n + j);
                }
                for j in bits(row_nz[k] ^ row_nz[p]) {
                    col_nz[j] ^= (1 << k) | (1 << p);
                }
                row_nz.swap(k, p);
            }
            // Row k of U is final: its nonzeros right of the diagonal, listed for the solves.
            let first = rows.u_col.len();
            rows.push_u_row(k, &a[k * n..(k + 1) * n], bits(row_nz[k] & above(k)));
            let u_cols = &rows.u_col[first..];
            let u_vals = &rows.u_val[first..];
            let u_nz = u_cols.iter().fold(0u64, |m, &j| m | 1 << j);
            let inv = 1.0 / a[k * n + k];
            for i in bits(col_nz[k] & above(k)) {
                if eliminate(&mut a[i * n..(i + 1) * n], k, inv, u_cols, u_vals) {
                    for j in bits(u_nz & !row_nz[i]) {
                        col_nz[j] |= 1 << i;
                    }
                    row_nz[i] |= u_nz;
                }
            }
        }
        // L by rows, ascending columns (the strict lower triangle's nonzeros).
        for (i, &m) in row_nz.iter().enumerate().take(n) {
            rows.push_l_row(&a[i * n..(i + 1) * n], bits(m & ((1u64 << i) - 1)));
        }
        Ok(Lu {
            n,
            lu: a,
            piv,
            rows,
        })
    }

    /// [`Self::factor`] with dense row and column scans (any n).
    fn factor_dense(n: usize, mut a: Vec<f64>, what: &'static str) -> Result<Lu, RotorError> {
        let mut piv = vec![0usize; n];
        let mut rows = FactorRows::with_capacity(n);
        for k in 0..n {
            let p = pivot_row(&a, n, k, k + 1..n, what)?;
            piv[k] = p;
            if p != k {
                for j in 0..n {
                    a.swap(k * n + j, p * n + j);
                }
            }
            let first = rows.u_col.len();
            rows.push_u_row(k, &a[k * n..(k + 1) * n], k + 1..n);
            let u_cols = &rows.u_col[first..];
            let u_vals = &rows.u_val[first..];
            let inv = 1.0 / a[k * n + k];
            for i in k + 1..n {
                eliminate(&mut a[i * n..(i + 1) * n], k, inv, u_cols, u_vals);
            }
        }
        for i in 0..n {
            rows.push_l_row(&a[i * n..(i + 1) * n], 0..i);
        }
        Ok(Lu {
            n,
            lu: a,
            piv,
            rows,
        })
    }

    /// Nonzeros of L below and of U above the diagonal (the solves' work).
    pub fn off_diagonal_nonzeros(&self) -> (usize, usize) {
        (self.rows.l_val.len(), self.rows.u_val.len())
    }

    pub fn dim(&self) -> usize {
        self.n
    }

    /// Solve A x = b in place: the row interchanges, then forward and back substitution over
    /// the factors' nonzeros, row by row.
    pub fn solve(&self, b: &mut [f64]) {
        let n = self.n;
        assert_eq!(b.len(), n, "Lu::solve: right-hand side of the wrong length");
        for k in 0..n {
            let p = self.piv[k];
            if p != k {
                b.swap(k, p);
            }
        }
        let r = &self.rows;
        for i in 0..n {
            let span = r.l_start[i] as usize..r.l_start[i + 1] as usize;
            let mut s = b[i];
            for (&j, &l) in r.l_col[span.clone()].iter().zip(&r.l_val[span]) {
                s -= l * b[j as usize];
            }
            b[i] = s;
        }
        for i in (0..n).rev() {
            let span = r.u_start[i] as usize..r.u_start[i + 1] as usize;
            let mut s = b[i];
            for (&j, &u) in r.u_col[span.clone()].iter().zip(&r.u_val[span]) {
                s -= u * b[j as usize];
            }
            b[i] = s / r.diag[i];
        }
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
