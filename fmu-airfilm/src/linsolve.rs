//! Banded LU, written out by hand: with partial pivoting (the LAPACK dgbtf2/dgbtrs algorithm),
//! or without row interchanges where that is stable (the film's Newton matrices).
//!
//! Storage is LAPACK's column-major band layout: entry (r, c) lives at
//! `ab[(ub + r - c) + c * ldab]`. With pivoting `ldab = 2 kl + ku + 1` and `ub = kl + ku`: the
//! extra kl rows hold the fill-in that row interchanges create, U has kl + ku superdiagonals.
//! Without, `ldab = kl + ku + 1` and `ub = ku`: U keeps the matrix's ku superdiagonals, and the
//! factors take (kl + ku + 1) / (2 kl + ku + 1) of the memory (57 / 85 rows for a film lobe),
//! which the triangular solves stream through at every Newton iteration. For those solves the
//! factors can also be kept rounded to f32 (`set_single_precision_solves`, the film's Newton
//! matrices): half of that memory again, with the right-hand side and the arithmetic in f64.
//! Factor and solve allocate nothing (after the first factorization of a matrix).

use serde::{Deserialize, Serialize};

/// Without row interchanges, a factorization whose U has an entry larger than this many times the
/// matrix's largest is refused ([`FactorError::Growth`]): the backward error of LU grows with
/// that ratio (Wilkinson's growth factor). The film's Newton matrices stay at 1.0-1.25 (a lobe of
/// the paper mesh from concentric to eps 0.99, C = 10-30 um, dH = 0-60 um), so the limit leaves
/// a wide margin and still bounds the backward error near 1e-13.
pub const GROWTH_LIMIT: f64 = 1e3;

/// Why a factorization failed.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum FactorError {
    /// An exactly zero (or, without pivoting, a non-finite) pivot in this row.
    ZeroPivot { row: usize },
    /// Without row interchanges, U grew by this factor over the largest entry of the matrix
    /// (above [`GROWTH_LIMIT`], or not finite): factorize with pivoting instead.
    Growth { ratio: f64 },
}

impl FactorError {
    /// The row where the factorization stopped (n for a growth failure, found at the end).
    pub fn row(&self, n: usize) -> usize {
        match *self {
            FactorError::ZeroPivot { row } => row,
            FactorError::Growth { .. } => n,
        }
    }
}

#[derive(Clone, Debug, Serialize, Deserialize)]
#[serde(from = "BandLuData")]
pub struct BandLu {
    pub n: usize,
    pub kl: usize,
    pub ku: usize,
    ldab: usize,
    ab: Vec<f64>,
    ipiv: Vec<u32>,
    /// 1 / U's diagonal, set by `factor`: the back substitution multiplies by it instead of
    /// dividing by the diagonal, which took the division's latency (~13 cycles against ~4 for a
    /// multiplication) into the solve's dependency chain once per row. A state serialized
    /// by an older airring lacks it: the decoder or `fits` refuses it (tested).
    inv_diag: Vec<f64>,
    /// Partial pivoting (LAPACK's layout) or none (the compact layout).
    pivoting: bool,
    /// Solve with the factors rounded to f32 ([`BandLu::set_single_precision_solves`]). A state
    /// serialized by an older airring lacks it and does not read.
    single_precision_solves: bool,
    /// Those rounded factors, set by a factorization without row interchanges (and rebuilt when
    /// a state is read); empty otherwise, or where an entry does not fit in f32.
    #[serde(skip)]
    ab_f32: Vec<f32>,
}

/// The serialized form of [`BandLu`]: its fields but the f32 copy of the factors, which follows
/// from them.
#[derive(Deserialize)]
struct BandLuData {
    n: usize,
    kl: usize,
    ku: usize,
    ldab: usize,
    ab: Vec<f64>,
    ipiv: Vec<u32>,
    inv_diag: Vec<f64>,
    pivoting: bool,
    single_precision_solves: bool,
}

impl From<BandLuData> for BandLu {
    fn from(d: BandLuData) -> BandLu {
        let BandLuData {
            n,
            kl,
            ku,
            ldab,
            ab,
            ipiv,
            inv_diag,
            pivoting,
            single_precision_solves,
        } = d;
        let mut lu = BandLu {
            n,
            kl,
            ku,
            ldab,
            ab,
            ipiv,
            inv_diag,
            pivoting,
            single_precision_solves,
            ab_f32: Vec::new(),
        };
        if single_precision_solves && !pivoting {
            round_to_f32(&lu.ab, &mut lu.ab_f32);
        }
        lu
    }
}

/// `out` = `ab` rounded to f32, or empty if an entry does not fit (overflows to infinity; a NaN
/// or infinity in `ab` too): the solves then take `ab` itself. The check runs in eight lanes of
/// sums of v * 0, which stay 0 for finite v.
fn round_to_f32(ab: &[f64], out: &mut Vec<f32>) {
    out.resize(ab.len(), 0.0);
    if round_into(ab, out) != 0.0 {
        out.clear();
    }
}

/// `dst` = `src` rounded to f32; returns the sum of the rounded values times 0 (0 unless one is
/// infinite or NaN), in eight lanes, which vectorize.
#[inline(always)]
fn round_into(src: &[f64], dst: &mut [f32]) -> f32 {
    let mut zero = [0.0f32; 8];
    let done = src.len() - src.len() % 8;
    for (o, a) in dst[..done]
        .chunks_exact_mut(8)
        .zip(src[..done].chunks_exact(8))
    {
        for i in 0..8 {
            let v = a[i] as f32;
            o[i] = v;
            zero[i] += v * 0.0;
        }
    }
    let mut z: f32 = zero.iter().sum();
    for (o, &a) in dst[done..].iter_mut().zip(&src[done..]) {
        *o = a as f32;
        z += *o * 0.0;
    }
    z
}

/// The largest |v| of `v`; NaN if any element is NaN or infinite. In eight independent lanes,
/// which vectorize: a lane-wise `if a > m { a } else { m }` (the vector max instruction's own
/// rule; a running f64::max cost 17 us over one lobe's 30 000 entries, ~4 us this way, and an
/// integer max on the bit patterns was 1.6-3.5x slower in a micro-benchmark), and a lane-wise
/// sum of v * 0, which stays 0 unless some v is NaN or infinite.
#[inline(always)]
fn abs_max(v: &[f64]) -> f64 {
    let mut max = [0.0f64; 8];
    let mut zero = [0.0f64; 8];
    let chunks = v.chunks_exact(8);
    let tail = chunks.remainder();
    for c in chunks {
        for i in 0..8 {
            let a = c[i].abs();
            max[i] = if a > max[i] { a } else { max[i] };
            zero[i] += c[i] * 0.0;
        }
    }
    let mut m = 0.0f64;
    let mut z = 0.0f64;
    for &x in tail.iter().chain(&max) {
        let a = x.abs();
        m = if a > m { a } else { m };
        z += x * 0.0;
    }
    z += zero.iter().sum::<f64>();
    if z == 0.0 {
        m
    } else {
        f64::NAN
    }
}

/// The elimination step both factorizations share: subtracts u(j, c) times L's column j (its km
/// entries below the diagonal) from each column c = j + 1 ..= c_last. `ub` is U's bandwidth, the
/// diagonal's row in the band storage (kl + ku with pivoting, ku without).
#[inline(always)]
fn update_trailing_columns(
    ab: &mut [f64],
    ldab: usize,
    ub: usize,
    j: usize,
    km: usize,
    c_last: usize,
) {
    match km {
        FILM_KL_20X3 => update_trailing_columns_fixed::<FILM_KL_20X3>(ab, ldab, ub, j, c_last),
        FILM_KL_20X4 => update_trailing_columns_fixed::<FILM_KL_20X4>(ab, ldab, ub, j, c_last),
        FILM_KL => update_trailing_columns_fixed::<FILM_KL>(ab, ldab, ub, j, c_last),
        _ => update_trailing_columns_any(ab, ldab, ub, j, km, c_last),
    }
}

/// `update_trailing_columns` for any km.
#[inline(always)]
fn update_trailing_columns_any(
    ab: &mut [f64],
    ldab: usize,
    ub: usize,
    j: usize,
    km: usize,
    c_last: usize,
) {
    let col = j * ldab + ub;
    for c in (j + 1)..=c_last {
        let base = ub + j - c + c * ldab;
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

/// `subtract_four_columns` for b.len() = N known at compile time (no loop, no remainder test).
#[inline(always)]
fn subtract_four_columns_fixed<const N: usize, T: Entry>(
    b: &mut [f64],
    cols: [&[T]; 4],
    x: [f64; 4],
) {
    let b: &mut [f64; N] = b.try_into().expect("N rows");
    let c: [&[T; N]; 4] = cols.map(|c| c.try_into().expect("N rows per column"));
    let [x0, x1, x2, x3] = x;
    for i in 0..N {
        let mut v = b[i];
        v -= c[0][i].f64() * x0;
        v -= c[1][i].f64() * x1;
        v -= c[2][i].f64() * x2;
        v -= c[3][i].f64() * x3;
        b[i] = v;
    }
}

/// Lower bandwidth of the film's lobes on the paper mesh (quadratic elements, 13 nodes across):
/// the elimination's column length in all but the last 28 columns, and kl - 3 the length of the
/// four-column passes of the solves. Known at compile time, the kernels below have no loop
/// control or remainder around their few vector operations: one lobe's factorization without
/// interchanges 113-119 -> 73-78 us, with pivoting 160-220 -> 93-104 us, its solves (with the
/// reciprocal diagonal) 9.7-10.0 -> 7.9-9.3 us (`cargo bench -p fmu-airfilm --bench kernels`,
/// alternated 3 times). Other bandwidths take the loops.
const FILM_KL: usize = 28;

/// The same for the run-ups' meshes (`film_mesh_for` in the master): 20 x 3 (7 nodes across,
/// kl 16) and 20 x 4 (9 nodes across, kl 20). With only the paper mesh's 28 the run-ups' lobes
/// would take the loops.
const FILM_KL_20X3: usize = 16;
const FILM_KL_20X4: usize = 20;

/// `update_trailing_columns` for km = KM known at compile time: L's column is read once into
/// registers and every trailing column's update is KM / lanes vector operations without a loop
/// or a remainder (the same operations in the same order, so the same bits).
#[inline(always)]
fn update_trailing_columns_fixed<const KM: usize>(
    ab: &mut [f64],
    ldab: usize,
    ub: usize,
    j: usize,
    c_last: usize,
) {
    let col = j * ldab + ub;
    let l: [f64; KM] = ab[col + 1..col + 1 + KM]
        .try_into()
        .expect("KM entries below the diagonal");
    for c in (j + 1)..=c_last {
        let base = ub + j - c + c * ldab;
        let u = ab[base];
        if u != 0.0 {
            let tgt: &mut [f64; KM] = (&mut ab[base + 1..base + 1 + KM])
                .try_into()
                .expect("KM entries below u");
            for (t, &m) in tgt.iter_mut().zip(&l) {
                *t -= m * u;
            }
        }
    }
}

/// An entry of stored factors, read as f64 by the solves: the factorization's own f64, or the f32
/// copy of [`BandLu::set_single_precision_solves`].
trait Entry: Copy {
    fn f64(self) -> f64;
}

impl Entry for f64 {
    #[inline(always)]
    fn f64(self) -> f64 {
        self
    }
}

impl Entry for f32 {
    #[inline(always)]
    fn f64(self) -> f64 {
        self as f64
    }
}

/// t -= cols[0][i] x[0], then cols[1][i] x[1], cols[2][i] x[2], cols[3][i] x[3], for every t = b[i]:
/// four columns of a triangular solve in one pass over b, each element updated in column order
/// (the forward and the back substitution's inner loop).
#[inline(always)]
fn subtract_four_columns<T: Entry>(b: &mut [f64], cols: [&[T]; 4], x: [f64; 4]) {
    if b.len() == FILM_KL - 3 {
        subtract_four_columns_fixed::<{ FILM_KL - 3 }, T>(b, cols, x)
    } else {
        subtract_four_columns_any(b, cols, x)
    }
}

/// `subtract_four_columns` for any length.
#[inline(always)]
fn subtract_four_columns_any<T: Entry>(b: &mut [f64], cols: [&[T]; 4], x: [f64; 4]) {
    let [c0, c1, c2, c3] = cols;
    let [x0, x1, x2, x3] = x;
    for ((((t, &a0), &a1), &a2), &a3) in b.iter_mut().zip(c0).zip(c1).zip(c2).zip(c3) {
        let mut v = *t;
        v -= a0.f64() * x0;
        v -= a1.f64() * x1;
        v -= a2.f64() * x2;
        v -= a3.f64() * x3;
        *t = v;
    }
}

impl BandLu {
    /// An n x n zero matrix of bandwidths kl, ku, to be factorized with partial pivoting.
    pub fn new(n: usize, kl: usize, ku: usize) -> Self {
        let ldab = Self::ldab_for(kl, ku, true);
        BandLu {
            n,
            kl,
            ku,
            ldab,
            ab: vec![0.0; ldab * n],
            ipiv: vec![0; n],
            inv_diag: vec![0.0; n],
            pivoting: true,
            single_precision_solves: false,
            ab_f32: Vec::new(),
        }
    }

    /// Rows of the band storage as allocated (for the memory bound's test).
    #[cfg(test)]
    pub(crate) fn ldab_for_test(&self) -> usize {
        self.ldab
    }

    fn ldab_for(kl: usize, ku: usize, pivoting: bool) -> usize {
        if pivoting {
            2 * kl + ku + 1
        } else {
            kl + ku + 1
        }
    }

    /// U's bandwidth, which is also the diagonal's row in the band storage.
    #[inline(always)]
    fn ub(&self) -> usize {
        self.ldab - self.kl - 1
    }

    /// Whether `factor` pivots.
    pub fn pivoting(&self) -> bool {
        self.pivoting
    }

    /// Chooses partial pivoting or none for the next factorization; a change of layout clears
    /// the matrix (assemble after it).
    pub fn set_pivoting(&mut self, pivoting: bool) {
        if pivoting != self.pivoting {
            self.pivoting = pivoting;
            self.ldab = Self::ldab_for(self.kl, self.ku, pivoting);
            self.ab.clear();
            self.ab.resize(self.ldab * self.n, 0.0);
            self.ab_f32.clear();
        }
    }

    /// Solves with the factors rounded to f32 after each factorization without row interchanges
    /// (from the next one on): half the memory for the solves to stream through, the f64 right-
    /// hand side and arithmetic unchanged. Only where the solve serves an iteration that converges
    /// on an f64 residual (modified Newton: the rounding is a far smaller change of the matrix
    /// than the stale Jacobian and step coefficient it already reuses), never where the solution
    /// is the answer.
    pub fn set_single_precision_solves(&mut self, on: bool) {
        self.single_precision_solves = on;
        if !on {
            self.ab_f32 = Vec::new();
        }
    }

    /// Whether the solves use factors rounded to f32 (asked for, and the last factorization was
    /// one without row interchanges whose entries all fit in f32).
    pub fn solves_in_single_precision(&self) -> bool {
        !self.ab_f32.is_empty()
    }

    /// Whether this is an n x n matrix of bandwidths kl, ku with its storage of that size (a
    /// deserialized matrix is checked with it, so a foreign state is an error, not a panic in the
    /// kernels).
    pub fn fits(&self, n: usize, kl: usize, ku: usize) -> bool {
        let ldab = Self::ldab_for(kl, ku, self.pivoting);
        (self.n, self.kl, self.ku, self.ldab) == (n, kl, ku, ldab)
            && self.ab.len() == ldab * n
            && self.ipiv.len() == n
            && self.inv_diag.len() == n
            && (self.ab_f32.is_empty() || self.ab_f32.len() == self.ab.len())
            && self.ipiv.iter().all(|&l| (l as usize) < n)
    }

    /// Clears the matrix before assembly.
    pub fn zero(&mut self) {
        self.ab.iter_mut().for_each(|v| *v = 0.0);
        self.ab_f32.clear();
    }

    #[inline(always)]
    fn idx(&self, r: usize, c: usize) -> usize {
        self.ub() + r - c + c * self.ldab
    }

    /// Adds `v` to entry (r, c); (r, c) must lie inside the band.
    #[inline(always)]
    pub fn add(&mut self, r: usize, c: usize, v: f64) {
        debug_assert!(r + self.ku >= c && c + self.kl >= r);
        let i = self.idx(r, c);
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

    /// Adds `vals[i]` to entry (r, cols[i]) for every i: one element matrix's row; every (r, c)
    /// must lie inside the band. The same additions as `add` in the same order (so the same
    /// bits), with the band's layout read once per row.
    #[inline(always)]
    pub fn add_row(&mut self, r: usize, cols: &[u32], vals: &[f64]) {
        let (ub, ldab) = (self.ub(), self.ldab);
        for (&c, &v) in cols.iter().zip(vals) {
            let c = c as usize;
            debug_assert!(r + self.ku >= c && c + self.kl >= r);
            self.ab[ub + r - c + c * ldab] += v;
        }
    }

    /// Replaces row r by the identity row (Dirichlet node).
    pub fn set_identity_row(&mut self, r: usize) {
        let c0 = r.saturating_sub(self.kl);
        let c1 = (r + self.ku).min(self.n - 1);
        for c in c0..=c1 {
            let i = self.idx(r, c);
            self.ab[i] = 0.0;
        }
        let i = self.idx(r, r);
        self.ab[i] = 1.0;
    }

    /// In-place LU factorization, with partial pivoting or without (see [`Self::set_pivoting`]).
    /// Without, a factorization that is not stable ([`GROWTH_LIMIT`]) fails: assemble again and
    /// factorize with pivoting. After a failure the contents are undefined.
    pub fn factor(&mut self) -> Result<(), FactorError> {
        self.factor_in_place()
    }

    /// Assembles the matrix with `assemble`, which must write the whole band (clear it first,
    /// [`BandLu::zero`]), and factorizes it without row interchanges; where that is not stable
    /// ([`GROWTH_LIMIT`]), assembles it again and factorizes with partial pivoting. Ok(true) when
    /// pivoting was needed; an error only after both failed.
    pub fn assemble_and_factor(
        &mut self,
        mut assemble: impl FnMut(&mut BandLu),
    ) -> Result<bool, FactorError> {
        self.set_pivoting(false);
        assemble(self);
        if self.factor().is_ok() {
            return Ok(false);
        }
        self.set_pivoting(true);
        assemble(self);
        self.factor().map(|()| true)
    }

    /// Compiled for the widest vector unit the CPU has, like `solve`.
    fn factor_in_place(&mut self) -> Result<(), FactorError> {
        struct Op<'a>(&'a mut BandLu);
        impl pulp::WithSimd for Op<'_> {
            type Output = Result<(), FactorError>;
            #[inline(always)]
            fn with_simd<S: pulp::Simd>(self, _: S) -> Result<(), FactorError> {
                if self.0.pivoting {
                    self.0.factor_lanes()
                } else {
                    self.0.factor_unpivoted_lanes()
                }
            }
        }
        pulp::Arch::new().dispatch(Op(self))
    }

    /// Gaussian elimination without row interchanges in the compact layout, then the growth
    /// check. The same column-by-column update as `factor_lanes` with every interchange absent.
    #[inline(always)]
    fn factor_unpivoted_lanes(&mut self) -> Result<(), FactorError> {
        self.ab_f32.clear();
        let (n, kl, ku, ldab) = (self.n, self.kl, self.ku, self.ldab);
        let ab = &mut self.ab;
        let a_max = abs_max(ab);
        // The largest |U| and, through a sum of v * 0, whether U or L holds a NaN or infinity; each
        // column when it is final (at its own step), while it is in cache.
        let (mut u_max, mut not_finite) = (0.0f64, 0.0f64);
        for j in 0..n {
            self.ipiv[j] = j as u32;
            let km = kl.min(n - 1 - j);
            let col = j * ldab + ku;
            let pivot = ab[col];
            if pivot == 0.0 || !pivot.is_finite() {
                return Err(FactorError::ZeroPivot { row: j });
            }
            for &u in &ab[col - ku.min(j)..=col] {
                let a = u.abs();
                u_max = if a > u_max { a } else { u_max };
                not_finite += u * 0.0;
            }
            let rp = 1.0 / pivot;
            self.inv_diag[j] = rp;
            for l in &mut ab[col + 1..=col + km] {
                *l *= rp;
                not_finite += *l * 0.0;
            }
            update_trailing_columns(ab, ldab, ku, j, km, (j + ku).min(n - 1));
        }
        let ratio = u_max / a_max;
        if !(ratio <= GROWTH_LIMIT && not_finite == 0.0) {
            return Err(FactorError::Growth { ratio });
        }
        // One pass after the elimination: rounding each column as it became final was slower
        // (kernel bench 88 against 83 us), and a lobe solves ~25 times per factorization.
        if self.single_precision_solves {
            round_to_f32(ab, &mut self.ab_f32);
        }
        Ok(())
    }

    #[inline(always)]
    fn factor_lanes(&mut self) -> Result<(), FactorError> {
        self.ab_f32.clear();
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
                return Err(FactorError::ZeroPivot { row: j });
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
            self.inv_diag[j] = rp;
            for i in 1..=km {
                ab[col + i] *= rp;
            }
            update_trailing_columns(ab, ldab, kv, j, km, ju);
        }
        Ok(())
    }

    /// Solves A x = b in place with the factors from `factor`.
    ///
    /// Compiled for the widest vector unit the CPU has (pulp's runtime dispatch); the operations
    /// and their order are the same on every CPU, so the result is too, bit for bit. With partial
    /// pivoting the forward elimination stays column by column: the film's Newton matrices
    /// interchange rows in about a quarter of their columns (132 of 533 in a whirl), so two thirds
    /// of all four-column blocks would hold an interchange, and carrying those through a blocked
    /// pass cost more than it saved (tried: 20 -> 28 us per solve with the interchanges tracked;
    /// two columns per pass with the one interchange carried as scalars: 14.3 -> 14.2 us, not
    /// kept). Without interchanges it runs four columns per pass like the back substitution (one
    /// lobe's solves 9.1-9.6 -> 7.8-8.5 us, kernel bench, alternated 3 times).
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
                let lu = self.0;
                if lu.pivoting {
                    lu.solve_in_place::<true, f64>(&lu.ab, self.1)
                } else if lu.ab_f32.is_empty() {
                    lu.solve_in_place::<false, f64>(&lu.ab, self.1)
                } else {
                    lu.solve_in_place::<false, f32>(&lu.ab_f32, self.1)
                }
            }
        }
        pulp::Arch::new().dispatch(Op(self, b))
    }

    #[inline(always)]
    fn solve_in_place<const PIVOTING: bool, T: Entry>(&self, ab: &[T], b: &mut [f64]) {
        let (n, kl, ldab) = (self.n, self.kl, self.ldab);
        // U's bandwidth and the diagonal's row: kl + ku with pivoting, ku without.
        let kv = self.ub();
        // Without interchanges, four columns per pass while all four reach kl rows down (see
        // `forward_eliminate_four`), then one column at a time near the bottom.
        let mut j0 = 0;
        if !PIVOTING {
            while kl >= 3 && j0 + 3 + kl < n {
                self.forward_eliminate_four(ab, b, j0);
                j0 += 4;
            }
        }
        for j in j0..n.saturating_sub(1) {
            let km = kl.min(n - 1 - j);
            if PIVOTING {
                let l = self.ipiv[j] as usize;
                if l != j {
                    b.swap(l, j);
                }
            }
            let bj = b[j];
            if bj != 0.0 {
                let col = j * ldab + kv;
                // Slices + zip: no bounds checks in the hot loop.
                for (t, &m) in b[j + 1..=j + km].iter_mut().zip(&ab[col + 1..=col + km]) {
                    *t -= m.f64() * bj;
                }
            }
        }
        // Back substitution, four columns per pass over b where all four reach kv rows up (see
        // `back_substitute_four`), one column at a time near the top.
        let mut j = n;
        while kv >= 3 && j >= 4 && j - 4 >= kv {
            self.back_substitute_four(ab, b, j - 1);
            j -= 4;
        }
        for j in (0..j).rev() {
            let col = j * ldab;
            b[j] *= self.inv_diag[j];
            let bj = b[j];
            if bj != 0.0 {
                let i0 = j.saturating_sub(kv);
                let ucol = &ab[col + kv + i0 - j..col + kv];
                for (t, &u) in b[i0..j].iter_mut().zip(ucol) {
                    *t -= u.f64() * bj;
                }
            }
        }
    }

    /// Forward elimination of columns j .. j+3 without interchanges (j + 3 + kl < n, kl >= 3:
    /// all four reach kl rows down) in one pass over b, for the reason `back_substitute_four`
    /// gives. Every element gets the same operations in the same order as in the column loop
    /// (column j first), so the result is bit-identical to it for a b without -0 entries.
    #[inline(always)]
    fn forward_eliminate_four<T: Entry>(&self, ab: &[T], b: &mut [f64], j: usize) {
        let (ldab, kl, kv) = (self.ldab, self.kl, self.ub());
        // Entry (r, col) of L (r > col) lives at kv + r - col + col * ldab.
        let l = |r: usize, col: usize| ab[kv + r - col + col * ldab].f64();
        // The 4 x 4 unit lower triangle, in the column loop's order.
        let mut x = [0.0; 4];
        for m in 0..4 {
            let r = j + m;
            let mut t = b[r];
            for (k, xk) in x.iter().enumerate().take(m) {
                t -= l(r, j + k) * *xk;
            }
            b[r] = t;
            x[m] = t;
        }
        // Rows j + 4 ..= j + kl: all four columns.
        let (r0, r1) = (j + 4, j + kl + 1);
        let len = r1 - r0;
        let col_slice = |k: usize| {
            let col = j + k;
            let start = kv + r0 - col + col * ldab;
            &ab[start..start + len]
        };
        let cols = [col_slice(0), col_slice(1), col_slice(2), col_slice(3)];
        subtract_four_columns(&mut b[r0..r1], cols, x);
        // Rows below j + kl reach back into fewer than four columns: 3 rows.
        for r in r1..r1 + 3 {
            let mut t = b[r];
            for (k, xk) in x.iter().enumerate() {
                let col = j + k;
                if r <= col + kl {
                    t -= l(r, col) * *xk;
                }
            }
            b[r] = t;
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
    /// the only -0 the solve itself makes is an element's own scaling by the reciprocal diagonal,
    /// after its last update.
    #[inline(always)]
    fn back_substitute_four<T: Entry>(&self, ab: &[T], b: &mut [f64], c: usize) {
        let (ldab, kv) = (self.ldab, self.ub());
        // Entry (r, col) of U lives at kv + r - col + col * ldab.
        let u = |r: usize, col: usize| ab[kv + r - col + col * ldab].f64();
        // The 4 x 4 triangle, in the column loop's order.
        let mut x = [0.0; 4];
        for m in 0..4 {
            let r = c - m;
            let mut t = b[r];
            for (k, xk) in x.iter().enumerate().take(m) {
                t -= u(r, c - k) * *xk;
            }
            t *= self.inv_diag[r];
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
        let cols = [col_slice(0), col_slice(1), col_slice(2), col_slice(3)];
        subtract_four_columns(&mut b[r0..r1], cols, x);
    }

    /// The column-by-column solve as it was before `back_substitute_four` (tests only).
    #[cfg(test)]
    pub(crate) fn solve_reference(&self, b: &mut [f64]) {
        if self.ab_f32.is_empty() || self.pivoting {
            self.solve_reference_with(&self.ab, b)
        } else {
            self.solve_reference_with(&self.ab_f32, b)
        }
    }

    #[cfg(test)]
    fn solve_reference_with<T: Entry>(&self, ab: &[T], b: &mut [f64]) {
        let (n, kl, ldab) = (self.n, self.kl, self.ldab);
        let kv = self.ub();
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
                    *t -= m.f64() * bj;
                }
            }
        }
        for j in (0..n).rev() {
            let col = j * ldab;
            b[j] *= self.inv_diag[j];
            let bj = b[j];
            if bj != 0.0 {
                let i0 = j.saturating_sub(kv);
                let ucol = &ab[col + kv + i0 - j..col + kv];
                for (t, &u) in b[i0..j].iter_mut().zip(ucol) {
                    *t -= u.f64() * bj;
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::test_rng::symmetric as next;

    /// The lane-wise maximum: the largest magnitude wherever it sits (lanes, tail), NaN for a NaN
    /// or an infinity anywhere.
    #[test]
    fn abs_max_finds_the_largest_magnitude_and_flags_non_finite_values() {
        for len in [0usize, 1, 7, 8, 9, 30, 57] {
            for at in 0..len {
                let mut v: Vec<f64> = (0..len).map(|i| (i % 5) as f64 - 2.0).collect();
                v[at] = -3.5;
                assert_eq!(abs_max(&v), 3.5, "len {len}, at {at}");
                for bad in [f64::NAN, f64::INFINITY, f64::NEG_INFINITY] {
                    v[at] = bad;
                    assert!(abs_max(&v).is_nan(), "len {len}, {bad} at {at}");
                }
            }
        }
        assert_eq!(abs_max(&[]), 0.0);
    }

    /// Four columns per pass are a re-arrangement only: on random band matrices that need
    /// pivoting, and in the compact layout without interchanges (whose forward elimination runs
    /// four columns per pass too), with identity rows and right-hand sides holding zeros (the
    /// Dirichlet rows), of sizes below, at and above the four-column thresholds (kv + 4 back,
    /// kl + 4 forward) and the film's lobe (533, kl = ku = 28), `solve` equals the
    /// column-by-column solve bit for bit.
    #[test]
    fn solve_equals_the_column_by_column_solve_bit_for_bit() {
        let mut seed = 7u64;
        let mut seed_compact = 8u64;
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
            (6, 3, 2),
            (7, 3, 2),
            (8, 3, 2),
            (11, 3, 1),
            (40, 3, 5),
            (60, 5, 4),
            (533, 28, 28),
        ] {
            // Partial pivoting with and without a dominant diagonal; none with one.
            // (Its own random stream for the latter, so the pivoted cases keep their matrices.)
            for (diag, pivoting) in [(0.0, true), (3.0, true), ((kl + ku + 1) as f64, false)] {
                let seed = if pivoting {
                    &mut seed
                } else {
                    &mut seed_compact
                };
                let mut a = BandLu::new(n, kl, ku);
                a.set_pivoting(pivoting);
                for c in 0..n {
                    for r in c.saturating_sub(ku)..(c + kl + 1).min(n) {
                        a.add(r, c, next(seed) + if r == c { diag } else { 0.0 });
                    }
                }
                for r in (0..n).step_by(7) {
                    a.set_identity_row(r);
                }
                // Without interchanges also with the factors rounded to f32 for the solves.
                let mut single = a.clone();
                single.set_single_precision_solves(true);
                a.factor().unwrap();
                single.factor().unwrap();
                assert_eq!(single.solves_in_single_precision(), !pivoting);
                let pivots = a.ipiv.iter().enumerate().any(|(j, &p)| p as usize != j);
                assert!(
                    pivots || diag > 0.0 || kl == 0,
                    "n {n}: no interchange to test"
                );
                assert!(pivoting || !pivots);
                let b: Vec<f64> = (0..n)
                    .map(|i| {
                        if i % 7 == 0 || i % 11 == 3 {
                            0.0
                        } else {
                            next(seed)
                        }
                    })
                    .collect();
                let mut solutions = Vec::new();
                for lu in [&a, &single] {
                    let (mut x, mut x_ref) = (b.clone(), b.clone());
                    lu.solve(&mut x);
                    lu.solve_reference(&mut x_ref);
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
                    solutions.push(x);
                }
                // Factors rounded to f32 change a diagonally dominant system's solution by a
                // few f32 roundings (~6e-8) relative.
                let scale = solutions[0].iter().fold(0.0f64, |m, v| m.max(v.abs()));
                let diff = solutions[0]
                    .iter()
                    .zip(&solutions[1])
                    .fold(0.0f64, |m, (p, q)| m.max((p - q).abs()));
                if pivoting {
                    assert_eq!(diff, 0.0, "n {n}: pivoted factors are never rounded");
                } else {
                    assert!(diff <= 1e-6 * scale, "n {n}: {diff:e} of {scale:e}");
                    assert!(
                        diff > 0.0 || kl + ku == 0,
                        "n {n}: the f32 factors were not used"
                    );
                }
            }
        }
    }

    /// The fixed-length kernels are the loops with the length known: on random data (with
    /// zeros among the u that the elimination skips) they give the same bits as the loops.
    #[test]
    fn the_fixed_length_kernels_equal_the_loops_bit_for_bit() {
        let mut seed = 11u64;
        for kl in [FILM_KL_20X3, FILM_KL_20X4, FILM_KL] {
            let (n, ku) = (90, kl);
            let ldab = kl + ku + 1;
            for j in [0, 17, 40] {
                let mut ab: Vec<f64> = (0..ldab * n).map(|_| next(&mut seed)).collect();
                for c in (j + 1..j + ku).step_by(5) {
                    ab[ku + j - c + c * ldab] = 0.0;
                }
                let before = ab.clone();
                let mut ab_any = ab.clone();
                let c_last = j + ku;
                // Through the dispatch, which must pick the fixed kernel for these lengths.
                update_trailing_columns(&mut ab, ldab, ku, j, kl, c_last);
                update_trailing_columns_any(&mut ab_any, ldab, ku, j, kl, c_last);
                assert!(ab
                    .iter()
                    .zip(&ab_any)
                    .all(|(a, b)| a.to_bits() == b.to_bits()));
                assert_ne!(ab, before, "the update changed the trailing columns");
            }
        }
        const N: usize = FILM_KL - 3;
        let cols: Vec<Vec<f64>> = (0..4)
            .map(|_| (0..N).map(|_| next(&mut seed)).collect())
            .collect();
        let x = [next(&mut seed), next(&mut seed), 0.0, next(&mut seed)];
        let b: Vec<f64> = (0..N).map(|_| next(&mut seed)).collect();
        let (mut b_fixed, mut b_any) = (b.clone(), b.clone());
        let c = [&cols[0][..], &cols[1][..], &cols[2][..], &cols[3][..]];
        subtract_four_columns_fixed::<N, f64>(&mut b_fixed, c, x);
        subtract_four_columns_any(&mut b_any, c, x);
        assert!(b_fixed
            .iter()
            .zip(&b_any)
            .all(|(a, b)| a.to_bits() == b.to_bits()));
        assert_ne!(b_fixed, b);
    }

    /// Factors rounded to f32 are rebuilt when a state is read (it solves bit-identically); where
    /// an entry does not fit in f32 the solves keep the f64 factors (the same bits as without
    /// rounding asked for), and a factorization with pivoting is never rounded.
    #[test]
    fn single_precision_solves_survive_serialization_and_fall_back_to_f64() {
        let mut seed = 21u64;
        let (n, kl, ku) = (60, 4, 5);
        let assemble = |scale: f64, seed: &mut u64| {
            let mut a = BandLu::new(n, kl, ku);
            a.set_pivoting(false);
            a.set_single_precision_solves(true);
            for c in 0..n {
                for r in c.saturating_sub(ku)..(c + kl + 1).min(n) {
                    let d = if r == c { 12.0 } else { 0.0 };
                    a.add(r, c, scale * (next(seed) + d));
                }
            }
            a
        };
        let b: Vec<f64> = (0..n).map(|_| next(&mut seed)).collect();
        let mut a = assemble(1.0, &mut seed);
        a.factor().unwrap();
        assert!(a.solves_in_single_precision());
        let back: BandLu = bincode::deserialize(&bincode::serialize(&a).unwrap()).unwrap();
        assert!(back.fits(n, kl, ku) && back.solves_in_single_precision());
        let (mut x, mut y) = (b.clone(), b.clone());
        a.solve(&mut x);
        back.solve(&mut y);
        assert!(x.iter().zip(&y).all(|(p, q)| p.to_bits() == q.to_bits()));
        // Entries of 1e39 overflow f32: the f64 factors serve.
        let mut huge = assemble(1e39, &mut seed);
        let mut plain = huge.clone();
        plain.set_single_precision_solves(false);
        huge.factor().unwrap();
        plain.factor().unwrap();
        assert!(!huge.solves_in_single_precision());
        let (mut x, mut y) = (b.clone(), b.clone());
        huge.solve(&mut x);
        plain.solve(&mut y);
        assert!(x.iter().zip(&y).all(|(p, q)| p.to_bits() == q.to_bits()));
        assert!(x.iter().all(|v| v.is_finite() && *v != 0.0));
        // A factorization serialized before the flag existed, followed by the next one (as in a
        // film's state) is refused: the next one's size is not a bool.
        #[derive(Serialize)]
        struct WithoutFlag<'a> {
            n: usize,
            kl: usize,
            ku: usize,
            ldab: usize,
            ab: &'a [f64],
            ipiv: &'a [u32],
            inv_diag: &'a [f64],
            pivoting: bool,
        }
        let old = WithoutFlag {
            n: a.n,
            kl: a.kl,
            ku: a.ku,
            ldab: a.ldab,
            ab: &a.ab,
            ipiv: &a.ipiv,
            inv_diag: &a.inv_diag,
            pivoting: a.pivoting,
        };
        let mut bytes = bincode::serialize(&(&old, &old)).unwrap();
        bytes.extend(bincode::serialize(&[1.0f64; 8]).unwrap());
        assert!(bincode::deserialize::<(BandLu, BandLu)>(&bytes).is_err());
        // With pivoting, never.
        let mut pivoted = assemble(1.0, &mut seed);
        pivoted.set_pivoting(true);
        for c in 0..n {
            pivoted.add(c, c, 1.0);
        }
        pivoted.factor().unwrap();
        assert!(!pivoted.solves_in_single_precision());
    }

    /// A factorization serialized before the reciprocal diagonal existed does not fit: the
    /// solve would read a diagonal it does not have.
    #[test]
    fn a_factorization_without_its_reciprocal_diagonal_does_not_fit() {
        let mut a = BandLu::new(6, 1, 1);
        for i in 0..6 {
            a.add(i, i, 2.0);
        }
        a.factor().unwrap();
        assert!(a.fits(6, 1, 1));
        #[derive(Serialize)]
        struct WithoutReciprocal<'a> {
            n: usize,
            kl: usize,
            ku: usize,
            ldab: usize,
            ab: &'a [f64],
            ipiv: &'a [u32],
            pivoting: bool,
        }
        let old = WithoutReciprocal {
            n: a.n,
            kl: a.kl,
            ku: a.ku,
            ldab: a.ldab,
            ab: &a.ab,
            ipiv: &a.ipiv,
            pivoting: a.pivoting,
        };
        // Followed by more of the state, as inside a film's.
        let mut bytes = bincode::serialize(&old).unwrap();
        bytes.extend(bincode::serialize(&[1.0f64; 8]).unwrap());
        match bincode::deserialize::<BandLu>(&bytes) {
            Err(e) => println!("refused by the decoder: {e}"),
            Ok(b) => assert!(!b.fits(6, 1, 1)),
        }
        let same: BandLu = bincode::deserialize(&bincode::serialize(&a).unwrap()).unwrap();
        assert!(same.fits(6, 1, 1));
    }
}
