//! Eigenvalues and eigenvectors of a real non-symmetric matrix: balancing (`balance`, written
//! out here), then faer's dense eigendecomposition (Householder reduction to Hessenberg form, the
//! real Schur form by Francis QR, eigenvectors by back-substitution in the Schur form).
//!
//! The balancing matters: a state matrix mixes an identity block with -M^-1 K entries of 1e6 to
//! 1e12, and faer does not balance. The rigid rotor's modal analysis (fmu-rotor) uses the same
//! `balance`.

/// The complex scalar of the eigenproblem (faer's `c64`).
pub type C64 = faer::c64;

/// Balances the row-major n x n matrix `a` in place by a diagonal similarity transform,
/// a <- D^-1 a D, so that each row and its column have about the same 1-norm (off the diagonal);
/// returns the diagonal of D. The EISPACK `balanc` iteration without its permutation step; the
/// scale factors are powers of 2, so the transform is exact (no rounding) and the eigenvalues
/// are those of the input; an eigenvector y of the balanced matrix is D^-1 x, x = D y.
pub fn balance(n: usize, a: &mut [f64]) -> Vec<f64> {
    assert_eq!(a.len(), n * n, "balance: a must be n x n");
    const RADIX: f64 = 2.0;
    const RADIX2: f64 = RADIX * RADIX;
    let mut d = vec![1.0; n];
    let mut done = false;
    while !done {
        done = true;
        for i in 0..n {
            let mut c = 0.0;
            let mut r = 0.0;
            for j in (0..n).filter(|&j| j != i) {
                c += a[j * n + i].abs();
                r += a[i * n + j].abs();
            }
            if c == 0.0 || r == 0.0 || !(c + r).is_finite() {
                continue;
            }
            let s = c + r;
            let mut f = 1.0;
            let g = r / RADIX;
            while c < g {
                f *= RADIX;
                c *= RADIX2;
            }
            let g = r * RADIX;
            while c > g {
                f /= RADIX;
                c /= RADIX2;
            }
            if (c + r) / f < 0.95 * s {
                done = false;
                d[i] *= f;
                let gi = 1.0 / f;
                for j in 0..n {
                    a[i * n + j] *= gi;
                }
                for j in 0..n {
                    a[j * n + i] *= f;
                }
            }
        }
    }
    d
}

/// The component of largest modulus (the first of equal ones); 0 for an empty vector.
pub fn largest(v: &[C64]) -> C64 {
    v.iter().copied().fold(C64::new(0.0, 0.0), |acc, z| {
        if z.norm() > acc.norm() {
            z
        } else {
            acc
        }
    })
}

/// Eigenvalues of the row-major n x n matrix `a` (balanced first); complex ones in exactly
/// conjugate pairs, real ones with an imaginary part of exactly 0. `None` if the QR iteration does
/// not converge or gives a value that is not finite.
pub fn eigenvalues(n: usize, a: &[f64]) -> Option<Vec<C64>> {
    let mut b = a.to_vec();
    balance(n, &mut b);
    let ev = faer::MatRef::from_row_major_slice(&b, n, n)
        .eigenvalues()
        .ok()?;
    ev.iter()
        .all(|l| l.re.is_finite() && l.im.is_finite())
        .then_some(ev)
}

/// Eigenvalues of the row-major n x n matrix `a` (balanced first) with their eigenvectors, each
/// normalized so that its largest component (by modulus) is exactly 1; `None` if the QR
/// iteration does not converge or gives a value that is not finite.
pub fn eigenpairs(n: usize, a: &[f64]) -> Option<Vec<(C64, Vec<C64>)>> {
    let mut b = a.to_vec();
    let d = balance(n, &mut b);
    let evd = faer::MatRef::from_row_major_slice(&b, n, n).eigen().ok()?;
    let (s, u) = (evd.S().column_vector(), evd.U());
    let mut out = Vec::with_capacity(n);
    for j in 0..n {
        let lam = s[j];
        let mut v: Vec<C64> = u.col(j).iter().zip(&d).map(|(y, di)| y * di).collect();
        let big = largest(&v);
        let size = big.norm();
        if !(size > 0.0 && size.is_finite() && lam.re.is_finite() && lam.im.is_finite()) {
            return None;
        }
        for z in v.iter_mut() {
            *z /= big;
        }
        out.push((lam, v));
    }
    Some(out)
}
