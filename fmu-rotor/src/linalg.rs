//! Small dense linear algebra: LU with partial pivoting (row-major), 3x3 helpers.
//! The GGL iteration matrix is 56 x 56; a hand-written LU keeps the crate dependency-free and
//! its factors serializable, so a restored `Rotor` reuses them bit-identically.

use crate::params::RotorError;
use serde::{Deserialize, Serialize};

pub type Vec3 = [f64; 3];
pub type Mat3 = [[f64; 3]; 3];

pub fn mat3_vec(a: &Mat3, v: &Vec3) -> Vec3 {
    [
        a[0][0] * v[0] + a[0][1] * v[1] + a[0][2] * v[2],
        a[1][0] * v[0] + a[1][1] * v[1] + a[1][2] * v[2],
        a[2][0] * v[0] + a[2][1] * v[1] + a[2][2] * v[2],
    ]
}

/// a^T v
pub fn mat3t_vec(a: &Mat3, v: &Vec3) -> Vec3 {
    [
        a[0][0] * v[0] + a[1][0] * v[1] + a[2][0] * v[2],
        a[0][1] * v[0] + a[1][1] * v[1] + a[2][1] * v[2],
        a[0][2] * v[0] + a[1][2] * v[1] + a[2][2] * v[2],
    ]
}

pub fn mat3_mul(a: &Mat3, b: &Mat3) -> Mat3 {
    let mut c = [[0.0; 3]; 3];
    for i in 0..3 {
        for j in 0..3 {
            c[i][j] = a[i][0] * b[0][j] + a[i][1] * b[1][j] + a[i][2] * b[2][j];
        }
    }
    c
}

pub fn transpose3(a: &Mat3) -> Mat3 {
    let mut c = [[0.0; 3]; 3];
    for i in 0..3 {
        for j in 0..3 {
            c[i][j] = a[j][i];
        }
    }
    c
}

pub fn cross(a: &Vec3, b: &Vec3) -> Vec3 {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

pub fn dot(a: &Vec3, b: &Vec3) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

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

    /// Solve A x = b in place.
    pub fn solve(&self, b: &mut [f64]) {
        let n = self.n;
        for k in 0..n {
            let p = self.piv[k];
            if p != k {
                b.swap(k, p);
            }
        }
        for i in 0..n {
            let row = &self.lu[i * n..i * n + i];
            let s: f64 = row.iter().zip(&b[..i]).map(|(a, x)| a * x).sum();
            b[i] -= s;
        }
        for i in (0..n).rev() {
            let row = &self.lu[i * n + i + 1..i * n + n];
            let s: f64 = row.iter().zip(&b[i + 1..n]).map(|(a, x)| a * x).sum();
            b[i] = (b[i] - s) / self.lu[i * n + i];
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
