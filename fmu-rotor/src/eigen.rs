//! Eigenvalues and eigenvectors of a small real non-symmetric matrix (the 16 x 16 state matrix
//! of the lateral motion): balancing, reduction to Hessenberg form by stabilized elimination,
//! the Francis double-shift QR iteration (after EISPACK `balanc`/`elmhes`/`hqr`), and complex
//! inverse iteration for the eigenvectors. Written out here to keep the crate dependency-free.

use crate::params::RotorError;

/// A complex number (only what inverse iteration needs).
/// Method names mirror the arithmetic they do; no operator traits are needed here.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct C64 {
    pub re: f64,
    pub im: f64,
}

#[allow(clippy::should_implement_trait)]
impl C64 {
    pub fn new(re: f64, im: f64) -> Self {
        C64 { re, im }
    }
    pub fn abs(self) -> f64 {
        self.re.hypot(self.im)
    }
    pub fn conj(self) -> Self {
        C64::new(self.re, -self.im)
    }
    pub fn mul(self, o: C64) -> C64 {
        C64::new(
            self.re * o.re - self.im * o.im,
            self.re * o.im + self.im * o.re,
        )
    }
    pub fn sub(self, o: C64) -> C64 {
        C64::new(self.re - o.re, self.im - o.im)
    }
    pub fn add(self, o: C64) -> C64 {
        C64::new(self.re + o.re, self.im + o.im)
    }
    pub fn scale(self, s: f64) -> C64 {
        C64::new(self.re * s, self.im * s)
    }
    pub fn div(self, o: C64) -> C64 {
        let d = o.re * o.re + o.im * o.im;
        C64::new(
            (self.re * o.re + self.im * o.im) / d,
            (self.im * o.re - self.re * o.im) / d,
        )
    }
}

/// Eigenvalues of the row-major n x n matrix `a`.
pub fn eigenvalues(n: usize, a: &[f64]) -> Result<Vec<C64>, RotorError> {
    // 1-based working copy, as in the EISPACK formulation.
    let mut h = vec![vec![0.0; n + 1]; n + 1];
    for i in 0..n {
        for j in 0..n {
            h[i + 1][j + 1] = a[i * n + j];
        }
    }
    balance(n, &mut h);
    hessenberg(n, &mut h);
    hqr(n, &mut h)
}

fn balance(n: usize, a: &mut [Vec<f64>]) {
    const RADIX: f64 = 2.0;
    let sqrdx = RADIX * RADIX;
    let mut done = false;
    while !done {
        done = true;
        for i in 1..=n {
            let mut r = 0.0;
            let mut c = 0.0;
            for j in 1..=n {
                if j != i {
                    c += a[j][i].abs();
                    r += a[i][j].abs();
                }
            }
            if c != 0.0 && r != 0.0 {
                let mut g = r / RADIX;
                let mut f = 1.0;
                let s = c + r;
                while c < g {
                    f *= RADIX;
                    c *= sqrdx;
                }
                g = r * RADIX;
                while c > g {
                    f /= RADIX;
                    c /= sqrdx;
                }
                if (c + r) / f < 0.95 * s {
                    done = false;
                    let gi = 1.0 / f;
                    for j in 1..=n {
                        a[i][j] *= gi;
                    }
                    for j in 1..=n {
                        a[j][i] *= f;
                    }
                }
            }
        }
    }
}

fn hessenberg(n: usize, a: &mut [Vec<f64>]) {
    for m in 2..n {
        let mut x: f64 = 0.0;
        let mut i = m;
        for j in m..=n {
            if a[j][m - 1].abs() > x.abs() {
                x = a[j][m - 1];
                i = j;
            }
        }
        if i != m {
            for j in (m - 1)..=n {
                let t = a[i][j];
                a[i][j] = a[m][j];
                a[m][j] = t;
            }
            for j in 1..=n {
                a[j].swap(i, m);
            }
        }
        if x != 0.0 {
            for i in (m + 1)..=n {
                let mut y = a[i][m - 1];
                if y != 0.0 {
                    y /= x;
                    a[i][m - 1] = y;
                    for j in m..=n {
                        a[i][j] -= y * a[m][j];
                    }
                    for j in 1..=n {
                        a[j][m] += y * a[j][i];
                    }
                }
            }
        }
    }
    // Clear the elimination multipliers below the subdiagonal.
    for i in 1..=n {
        for j in 1..i.saturating_sub(1) {
            a[i][j] = 0.0;
        }
    }
}

fn sign(a: f64, b: f64) -> f64 {
    if b >= 0.0 {
        a.abs()
    } else {
        -a.abs()
    }
}

#[allow(unused_assignments)]
fn hqr(n: usize, a: &mut [Vec<f64>]) -> Result<Vec<C64>, RotorError> {
    let mut wr = vec![0.0; n + 1];
    let mut wi = vec![0.0; n + 1];
    let mut anorm = 0.0;
    for i in 1..=n {
        for j in (i.max(2) - 1)..=n {
            anorm += a[i][j].abs();
        }
    }
    let mut nn = n;
    let mut t = 0.0;
    // EISPACK keeps p, q, r live across the sweep (k == m uses the values of the shift search).
    let (mut p, mut q, mut r): (f64, f64, f64) = (0.0, 0.0, 0.0);
    let (mut s, mut w, mut x, mut y, mut z): (f64, f64, f64, f64, f64);
    while nn >= 1 {
        let mut its = 0;
        loop {
            let mut l = nn;
            while l >= 2 {
                s = a[l - 1][l - 1].abs() + a[l][l].abs();
                if s == 0.0 {
                    s = anorm;
                }
                if a[l][l - 1].abs() + s == s {
                    a[l][l - 1] = 0.0;
                    break;
                }
                l -= 1;
            }
            x = a[nn][nn];
            if l == nn {
                wr[nn] = x + t;
                wi[nn] = 0.0;
                nn -= 1;
            } else {
                y = a[nn - 1][nn - 1];
                w = a[nn][nn - 1] * a[nn - 1][nn];
                if l == nn - 1 {
                    p = 0.5 * (y - x);
                    q = p * p + w;
                    z = q.abs().sqrt();
                    x += t;
                    if q >= 0.0 {
                        z = p + sign(z, p);
                        wr[nn - 1] = x + z;
                        wr[nn] = x + z;
                        if z != 0.0 {
                            wr[nn] = x - w / z;
                        }
                        wi[nn - 1] = 0.0;
                        wi[nn] = 0.0;
                    } else {
                        wr[nn - 1] = x + p;
                        wr[nn] = x + p;
                        wi[nn - 1] = -z;
                        wi[nn] = z;
                    }
                    nn -= 2;
                } else {
                    if its == 60 {
                        return Err(RotorError::Singular(
                            "QR eigenvalue iteration did not converge",
                        ));
                    }
                    if its == 10 || its == 20 {
                        t += x;
                        for i in 1..=nn {
                            a[i][i] -= x;
                        }
                        s = a[nn][nn - 1].abs() + a[nn - 1][nn - 2].abs();
                        x = 0.75 * s;
                        y = x;
                        w = -0.4375 * s * s;
                    }
                    its += 1;
                    let mut m = nn - 2;
                    loop {
                        z = a[m][m];
                        r = x - z;
                        s = y - z;
                        p = (r * s - w) / a[m + 1][m] + a[m][m + 1];
                        q = a[m + 1][m + 1] - z - r - s;
                        r = a[m + 2][m + 1];
                        s = p.abs() + q.abs() + r.abs();
                        p /= s;
                        q /= s;
                        r /= s;
                        if m == l {
                            break;
                        }
                        let u = a[m][m - 1].abs() * (q.abs() + r.abs());
                        let v = p.abs() * (a[m - 1][m - 1].abs() + z.abs() + a[m + 1][m + 1].abs());
                        if u + v == v {
                            break;
                        }
                        m -= 1;
                    }
                    for i in (m + 2)..=nn {
                        a[i][i - 2] = 0.0;
                        if i != m + 2 {
                            a[i][i - 3] = 0.0;
                        }
                    }
                    let mut k = m;
                    while k < nn {
                        if k != m {
                            p = a[k][k - 1];
                            q = a[k + 1][k - 1];
                            r = 0.0;
                            if k != nn - 1 {
                                r = a[k + 2][k - 1];
                            }
                            x = p.abs() + q.abs() + r.abs();
                            if x != 0.0 {
                                p /= x;
                                q /= x;
                                r /= x;
                            }
                        }
                        s = sign((p * p + q * q + r * r).sqrt(), p);
                        if s != 0.0 {
                            if k == m {
                                if l != m {
                                    a[k][k - 1] = -a[k][k - 1];
                                }
                            } else {
                                a[k][k - 1] = -s * x;
                            }
                            p += s;
                            x = p / s;
                            y = q / s;
                            z = r / s;
                            q /= p;
                            r /= p;
                            for j in k..=nn {
                                p = a[k][j] + q * a[k + 1][j];
                                if k != nn - 1 {
                                    p += r * a[k + 2][j];
                                    a[k + 2][j] -= p * z;
                                }
                                a[k + 1][j] -= p * y;
                                a[k][j] -= p * x;
                            }
                            let mmin = if nn < k + 3 { nn } else { k + 3 };
                            for i in l..=mmin {
                                p = x * a[i][k] + y * a[i][k + 1];
                                if k != nn - 1 {
                                    p += z * a[i][k + 2];
                                    a[i][k + 2] -= p * r;
                                }
                                a[i][k + 1] -= p * q;
                                a[i][k] -= p;
                            }
                        }
                        k += 1;
                    }
                }
            }
            if nn < 2 || l + 1 >= nn {
                break;
            }
        }
    }
    Ok((1..=n).map(|i| C64::new(wr[i], wi[i])).collect())
}

/// Eigenvector of `a` (row-major n x n) for the eigenvalue `lam`, by inverse iteration with a
/// slightly shifted, complex LU. Normalized to unit largest component.
pub fn eigenvector(n: usize, a: &[f64], lam: C64) -> Result<Vec<C64>, RotorError> {
    let shift = lam.add(C64::new(
        1e-10 * lam.abs().max(1.0),
        1e-10 * lam.abs().max(1.0),
    ));
    let mut m: Vec<C64> = (0..n * n).map(|k| C64::new(a[k], 0.0)).collect();
    for i in 0..n {
        m[i * n + i] = m[i * n + i].sub(shift);
    }
    // complex LU with partial pivoting
    let mut piv = vec![0usize; n];
    for k in 0..n {
        let mut pk = k;
        for i in k + 1..n {
            if m[i * n + k].abs() > m[pk * n + k].abs() {
                pk = i;
            }
        }
        piv[k] = pk;
        if pk != k {
            for j in 0..n {
                m.swap(k * n + j, pk * n + j);
            }
        }
        let d = m[k * n + k];
        if d.abs() == 0.0 {
            m[k * n + k] = C64::new(1e-300, 0.0);
        }
        let d = m[k * n + k];
        for i in k + 1..n {
            let l = m[i * n + k].div(d);
            m[i * n + k] = l;
            for j in k + 1..n {
                let v = m[i * n + j].sub(l.mul(m[k * n + j]));
                m[i * n + j] = v;
            }
        }
    }
    let mut b: Vec<C64> = (0..n).map(|i| C64::new(1.0, 0.1 * i as f64)).collect();
    for _ in 0..3 {
        for k in 0..n {
            if piv[k] != k {
                b.swap(k, piv[k]);
            }
        }
        for i in 0..n {
            let mut s = b[i];
            for j in 0..i {
                s = s.sub(m[i * n + j].mul(b[j]));
            }
            b[i] = s;
        }
        for i in (0..n).rev() {
            let mut s = b[i];
            for j in i + 1..n {
                s = s.sub(m[i * n + j].mul(b[j]));
            }
            b[i] = s.div(m[i * n + i]);
        }
        let big = b.iter().copied().fold(
            C64::default(),
            |acc, z| if z.abs() > acc.abs() { z } else { acc },
        );
        if big.abs().is_nan() || big.abs() <= 0.0 || !big.abs().is_finite() {
            return Err(RotorError::Singular("inverse iteration"));
        }
        for z in b.iter_mut() {
            *z = z.div(big);
        }
    }
    Ok(b)
}
