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

    fn factor_in_place(&mut self) -> Result<(), usize> {
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
    pub fn solve(&self, b: &mut [f64]) {
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
