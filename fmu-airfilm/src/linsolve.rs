//! Banded LU with partial pivoting (the LAPACK dgbtf2/dgbtrs algorithm), written out by hand.
//!
//! Storage is LAPACK's column-major band layout: entry (r, c) lives at
//! `ab[(kl + ku + r - c) + c * ldab]`, `ldab = 2 kl + ku + 1`; the extra kl rows hold the fill-in
//! that row interchanges create. Factor and solve allocate nothing.

use serde::{Deserialize, Serialize};
use std::sync::atomic::{AtomicU64, Ordering};

#[derive(Debug, Serialize, Deserialize)]
pub struct BandLu {
    pub n: usize,
    pub kl: usize,
    pub ku: usize,
    ldab: usize,
    ab: Vec<f64>,
    ipiv: Vec<u32>,
    /// Names the current contents: a successful `factor` draws a process-wide unique stamp, every
    /// other change sets 0 ("unknown"). Equal non-zero stamps mean equal contents, which lets
    /// `clone_from` skip the copy (an FMU state saved at every macro step holds factors that
    /// change only every few dozen steps). Not serialized: a deserialized matrix is "unknown".
    #[serde(skip)]
    stamp: u64,
}

/// Source of factorization stamps (0 is never drawn).
static NEXT_STAMP: AtomicU64 = AtomicU64::new(1);

impl Clone for BandLu {
    fn clone(&self) -> Self {
        BandLu {
            n: self.n,
            kl: self.kl,
            ku: self.ku,
            ldab: self.ldab,
            ab: self.ab.clone(),
            ipiv: self.ipiv.clone(),
            stamp: self.stamp,
        }
    }

    fn clone_from(&mut self, src: &Self) {
        if self.stamp != 0 && self.stamp == src.stamp {
            return;
        }
        let BandLu {
            n,
            kl,
            ku,
            ldab,
            ab,
            ipiv,
            stamp,
        } = src;
        (self.n, self.kl, self.ku, self.ldab) = (*n, *kl, *ku, *ldab);
        self.ab.clone_from(ab);
        self.ipiv.clone_from(ipiv);
        self.stamp = *stamp;
    }
}

impl BandLu {
    pub fn new(n: usize, kl: usize, ku: usize) -> Self {
        let ldab = 2 * kl + ku + 1;
        BandLu {
            n,
            kl,
            ku,
            ldab,
            ab: vec![0.0; ldab * n],
            ipiv: vec![0; n],
            stamp: 0,
        }
    }

    /// Whether this is an n x n matrix of bandwidths kl, ku with its storage of that size (a
    /// deserialized matrix is checked with it, so a foreign state is an error, not a panic in the
    /// kernels).
    pub fn fits(&self, n: usize, kl: usize, ku: usize) -> bool {
        let ldab = 2 * kl + ku + 1;
        (self.n, self.kl, self.ku, self.ldab) == (n, kl, ku, ldab)
            && self.ab.len() == ldab * n
            && self.ipiv.len() == n
            && self.ipiv.iter().all(|&l| (l as usize) < n)
    }

    /// Clears the matrix before assembly.
    pub fn zero(&mut self) {
        self.stamp = 0;
        self.ab.iter_mut().for_each(|v| *v = 0.0);
    }

    #[inline(always)]
    fn idx(&self, r: usize, c: usize) -> usize {
        self.kl + self.ku + r - c + c * self.ldab
    }

    /// Adds `v` to entry (r, c); (r, c) must lie inside the band.
    #[inline(always)]
    pub fn add(&mut self, r: usize, c: usize, v: f64) {
        debug_assert!(r + self.ku >= c && c + self.kl >= r);
        let i = self.idx(r, c);
        self.stamp = 0;
        self.ab[i] += v;
    }

    /// Entry (r, c) of the (unfactored) matrix; zero outside the band.
    pub fn get(&self, r: usize, c: usize) -> f64 {
        if r + self.ku >= c && c + self.kl >= r {
            self.ab[self.idx(r, c)]
        } else {
            0.0
        }
    }

    /// Replaces row r by the identity row (Dirichlet node).
    pub fn set_identity_row(&mut self, r: usize) {
        self.stamp = 0;
        let c0 = r.saturating_sub(self.kl);
        let c1 = (r + self.ku).min(self.n - 1);
        for c in c0..=c1 {
            let i = self.idx(r, c);
            self.ab[i] = 0.0;
        }
        let i = self.idx(r, r);
        self.ab[i] = 1.0;
    }

    /// In-place LU factorization with partial pivoting. Err(row) on an exactly zero pivot.
    pub fn factor(&mut self) -> Result<(), usize> {
        self.stamp = 0;
        self.factor_in_place()?;
        self.stamp = NEXT_STAMP.fetch_add(1, Ordering::Relaxed);
        Ok(())
    }

    /// Compiled for the widest vector unit the CPU has, like `solve`.
    fn factor_in_place(&mut self) -> Result<(), usize> {
        struct Op<'a>(&'a mut BandLu);
        impl pulp::WithSimd for Op<'_> {
            type Output = Result<(), usize>;
            #[inline(always)]
            fn with_simd<S: pulp::Simd>(self, _: S) -> Result<(), usize> {
                self.0.factor_lanes()
            }
        }
        pulp::Arch::new().dispatch(Op(self))
    }

    #[inline(always)]
    fn factor_lanes(&mut self) -> Result<(), usize> {
        let (n, kl, ku, ldab) = (self.n, self.kl, self.ku, self.ldab);
        let kv = kl + ku;
        // Fill-in rows of the first columns must start at zero.
        for c in (ku + 1)..kv.min(n) {
            for i in (kv - c)..kl {
                self.ab[i + c * ldab] = 0.0;
            }
        }
        let ab = &mut self.ab;
        let mut ju = 0usize;
        for j in 0..n {
            if j + kv < n {
                for i in 0..kl {
                    ab[i + (j + kv) * ldab] = 0.0;
                }
            }
            let km = kl.min(n - 1 - j);
            let col = j * ldab + kv;
            let mut jp = 0;
            let mut amax = ab[col].abs();
            for i in 1..=km {
                let a = ab[col + i].abs();
                if a > amax {
                    amax = a;
                    jp = i;
                }
            }
            self.ipiv[j] = (j + jp) as u32;
            if amax == 0.0 {
                return Err(j);
            }
            ju = ju.max((j + ku + jp).min(n - 1));
            if jp != 0 {
                for c in j..=ju {
                    let a = kv + j + jp - c + c * ldab;
                    let b = kv + j - c + c * ldab;
                    ab.swap(a, b);
                }
            }
            let rp = 1.0 / ab[col];
            for i in 1..=km {
                ab[col + i] *= rp;
            }
            for c in (j + 1)..=ju {
                let base = kv + j - c + c * ldab;
                let u = ab[base];
                if u != 0.0 {
                    let (l, rest) = ab.split_at_mut(base + 1);
                    let lcol = &l[col + 1..col + 1 + km];
                    let tgt = &mut rest[..km];
                    for (t, &m) in tgt.iter_mut().zip(lcol) {
                        *t -= m * u;
                    }
                }
            }
        }
        Ok(())
    }

    /// Solves A x = b in place with the factors from `factor`.
    ///
    /// Compiled for the widest vector unit the CPU has (pulp's runtime dispatch); the operations
    /// and their order are the same on every CPU, so the result is too, bit for bit. The forward
    /// elimination stays column by column: the film's Newton matrices interchange rows in about a
    /// quarter of their columns (132 of 533 in a whirl), so two thirds of all four-column blocks
    /// would hold an interchange, and carrying those through a blocked pass cost more than it saved
    /// (tried: 20 -> 28 us per solve with the interchanges tracked, no gain without them; two
    /// columns per pass with the one interchange carried as scalars: 14.3 -> 14.2 us, not kept).
    /// The back substitution's passes subtract 0 * u where the column loop skips a column whose
    /// value is 0: bit-identical for a b without -0 entries (the film's residuals never hold one:
    /// sums that start at +0 and differences are never -0); with them, x can differ in the sign of
    /// a zero.
    pub fn solve(&self, b: &mut [f64]) {
        struct Op<'a>(&'a BandLu, &'a mut [f64]);
        impl pulp::WithSimd for Op<'_> {
            type Output = ();
            #[inline(always)]
            fn with_simd<S: pulp::Simd>(self, _: S) {
                self.0.solve_in_place(self.1)
            }
        }
        pulp::Arch::new().dispatch(Op(self, b))
    }

    #[inline(always)]
    fn solve_in_place(&self, b: &mut [f64]) {
        let (n, kl, ku, ldab) = (self.n, self.kl, self.ku, self.ldab);
        let kv = kl + ku;
        let ab = &self.ab;
        for j in 0..n.saturating_sub(1) {
            let km = kl.min(n - 1 - j);
            let l = self.ipiv[j] as usize;
            if l != j {
                b.swap(l, j);
            }
            let bj = b[j];
            if bj != 0.0 {
                let col = j * ldab + kv;
                // Slices + zip: no bounds checks in the hot loop.
                for (t, &m) in b[j + 1..=j + km].iter_mut().zip(&ab[col + 1..=col + km]) {
                    *t -= m * bj;
                }
            }
        }
        // Back substitution, four columns per pass over b where all four reach kv rows up (see
        // `back_substitute_four`), one column at a time near the top.
        let mut j = n;
        while kv >= 3 && j >= 4 && j - 4 >= kv {
            self.back_substitute_four(b, j - 1);
            j -= 4;
        }
        for j in (0..j).rev() {
            let col = j * ldab;
            b[j] /= ab[col + kv];
            let bj = b[j];
            if bj != 0.0 {
                let i0 = j.saturating_sub(kv);
                let ucol = &ab[col + kv + i0 - j..col + kv];
                for (t, &u) in b[i0..j].iter_mut().zip(ucol) {
                    *t -= u * bj;
                }
            }
        }
    }

    /// Back substitution of columns c, c-1, c-2, c-3 (c - 3 >= kv >= 3: the 4 x 4 triangle lies
    /// inside the band) in one pass over b.
    ///
    /// Column by column, every pass reads the b[i] the previous pass has just stored, at an offset
    /// one element lower: vector loads that straddle two earlier vector stores cannot be forwarded
    /// and wait for the stores to retire, so the passes run one after the other. Four columns per
    /// pass load and store each b[i] once for four updates. Every element still gets the same
    /// operations in the same order (column c first), so x is bit-identical to the column-by-column
    /// loop for a b without -0 entries (see `solve`): b[i] - (+-0) == b[i] unless b[i] = -0, and
    /// the only -0 the solve itself makes is an element's own division, after its last update.
    #[inline(always)]
    fn back_substitute_four(&self, b: &mut [f64], c: usize) {
        let (ldab, kv) = (self.ldab, self.kl + self.ku);
        let ab = &self.ab;
        // Entry (r, col) of U lives at kv + r - col + col * ldab.
        let u = |r: usize, col: usize| ab[kv + r - col + col * ldab];
        // The 4 x 4 triangle, in the column loop's order.
        let mut x = [0.0; 4];
        for m in 0..4 {
            let r = c - m;
            let mut t = b[r];
            for (k, xk) in x.iter().enumerate().take(m) {
                t -= u(r, c - k) * *xk;
            }
            t /= u(r, r);
            b[r] = t;
            x[m] = t;
        }
        // Rows kv above the lowest column reach into fewer than four columns: 3 rows.
        let lo = c - 3 - kv;
        for r in lo..lo + 3 {
            let mut t = b[r];
            for (k, xk) in x.iter().enumerate() {
                let col = c - k;
                if r + kv >= col {
                    t -= u(r, col) * *xk;
                }
            }
            b[r] = t;
        }
        // The rest: all four columns, rows lo + 3 .. c - 3.
        let (r0, r1) = (lo + 3, c - 3);
        let len = r1 - r0;
        let col_slice = |k: usize| {
            let col = c - k;
            let start = kv + r0 - col + col * ldab;
            &ab[start..start + len]
        };
        let (u0, u1, u2, u3) = (col_slice(0), col_slice(1), col_slice(2), col_slice(3));
        let [x0, x1, x2, x3] = x;
        for ((((t, &a0), &a1), &a2), &a3) in b[r0..r1].iter_mut().zip(u0).zip(u1).zip(u2).zip(u3) {
            let mut v = *t;
            v -= a0 * x0;
            v -= a1 * x1;
            v -= a2 * x2;
            v -= a3 * x3;
            *t = v;
        }
    }

    /// The column-by-column solve as it was before `back_substitute_four` (tests only).
    #[cfg(test)]
    pub(crate) fn solve_reference(&self, b: &mut [f64]) {
        let (n, kl, ku, ldab) = (self.n, self.kl, self.ku, self.ldab);
        let kv = kl + ku;
        let ab = &self.ab;
        for j in 0..n.saturating_sub(1) {
            let km = kl.min(n - 1 - j);
            let l = self.ipiv[j] as usize;
            if l != j {
                b.swap(l, j);
            }
            let bj = b[j];
            if bj != 0.0 {
                let col = j * ldab + kv;
                for (t, &m) in b[j + 1..=j + km].iter_mut().zip(&ab[col + 1..=col + km]) {
                    *t -= m * bj;
                }
            }
        }
        for j in (0..n).rev() {
            let col = j * ldab;
            b[j] /= ab[col + kv];
            let bj = b[j];
            if bj != 0.0 {
                let i0 = j.saturating_sub(kv);
                let ucol = &ab[col + kv + i0 - j..col + kv];
                for (t, &u) in b[i0..j].iter_mut().zip(ucol) {
                    *t -= u * bj;
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::test_rng::symmetric as next;

    /// Four columns per pass are a re-arrangement only: on random band matrices that need
    /// pivoting, with identity rows and right-hand sides holding zeros (the Dirichlet rows), of
    /// sizes below, at and above the four-column threshold (kv + 4) and the film's lobe (533, kl =
    /// ku = 28), `solve` equals the column-by-column solve bit for bit.
    #[test]
    fn solve_equals_the_column_by_column_solve_bit_for_bit() {
        let mut seed = 7u64;
        for (n, kl, ku) in [
            (12, 0, 0),
            (12, 1, 1),
            (12, 0, 2),
            (12, 2, 0),
            (12, 1, 2),
            (5, 2, 2),
            (9, 2, 3),
            (10, 2, 3),
            (11, 2, 3),
            (40, 3, 5),
            (60, 5, 4),
            (533, 28, 28),
        ] {
            for diag in [0.0, 3.0] {
                let mut a = BandLu::new(n, kl, ku);
                for c in 0..n {
                    for r in c.saturating_sub(ku)..(c + kl + 1).min(n) {
                        a.add(r, c, next(&mut seed) + if r == c { diag } else { 0.0 });
                    }
                }
                for r in (0..n).step_by(7) {
                    a.set_identity_row(r);
                }
                a.factor().unwrap();
                let pivots = a.ipiv.iter().enumerate().any(|(j, &p)| p as usize != j);
                assert!(
                    pivots || diag > 0.0 || kl == 0,
                    "n {n}: no interchange to test"
                );
                let b: Vec<f64> = (0..n)
                    .map(|i| {
                        if i % 7 == 0 || i % 11 == 3 {
                            0.0
                        } else {
                            next(&mut seed)
                        }
                    })
                    .collect();
                let (mut x, mut x_ref) = (b.clone(), b.clone());
                a.solve(&mut x);
                a.solve_reference(&mut x_ref);
                for i in 0..n {
                    assert_eq!(
                        x[i].to_bits(),
                        x_ref[i].to_bits(),
                        "n {n}, row {i}: {} vs {}",
                        x[i],
                        x_ref[i]
                    );
                }
                assert!(x.iter().any(|v| *v != 0.0));
            }
        }
    }
}
