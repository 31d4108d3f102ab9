//! Kernel tests of the hand-written banded LU (`linsolve::BandLu`, LAPACK dgbtf2/dgbtrs), which
//! stays because it is 3.9x faster than faer's sparse LU on the film's Newton matrix
//! (BENCHMARKS.md): residual tests on seeded random band matrices that need pivoting, faer's dense
//! LU as an independent solution, identity rows, singular matrices.

use faer::linalg::solvers::Solve;
use faer::Mat;
use fmu_airfilm::linsolve::BandLu;

/// A tiny seeded generator (numbers in [-1, 1)).
struct Lcg(u64);

impl Lcg {
    fn next(&mut self) -> f64 {
        self.0 = self
            .0
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        ((self.0 >> 11) as f64 / (1u64 << 53) as f64) * 2.0 - 1.0
    }
}

/// A random n x n matrix with bandwidths kl, ku, as a BandLu and densely; `diag` is added to the
/// diagonal (0: no dominance, pivoting needed).
fn random_band(rng: &mut Lcg, n: usize, kl: usize, ku: usize, diag: f64) -> (BandLu, Vec<f64>) {
    let mut band = BandLu::new(n, kl, ku);
    let mut dense = vec![0.0; n * n];
    for c in 0..n {
        for r in c.saturating_sub(ku)..(c + kl + 1).min(n) {
            let v = rng.next() + if r == c { diag } else { 0.0 };
            band.add(r, c, v);
            dense[r * n + c] = v;
        }
    }
    (band, dense)
}

/// ||A x - b||_inf / (||A||_inf ||x||_inf + ||b||_inf).
fn backward_error(n: usize, a: &[f64], x: &[f64], b: &[f64]) -> f64 {
    let inf = |v: &[f64]| v.iter().fold(0.0f64, |m, x| m.max(x.abs()));
    let a_norm = (0..n)
        .map(|r| a[r * n..(r + 1) * n].iter().map(|v| v.abs()).sum::<f64>())
        .fold(0.0, f64::max);
    let r: Vec<f64> = (0..n)
        .map(|i| (0..n).map(|j| a[i * n + j] * x[j]).sum::<f64>() - b[i])
        .collect();
    inf(&r) / (a_norm * inf(x) + inf(b))
}

#[test]
fn random_band_matrices_that_need_pivoting_are_solved_to_round_off() {
    let mut rng = Lcg(7);
    let mut worst = 0.0f64;
    for n in 1..=80 {
        for (kl, ku) in [(0, 0), (1, 1), (2, 5), (5, 2), (9, 9), (28, 28)] {
            let (kl, ku) = (kl.min(n - 1), ku.min(n - 1));
            let (mut band, dense) = random_band(&mut rng, n, kl, ku, 0.0);
            let b: Vec<f64> = (0..n).map(|_| rng.next()).collect();
            if band.factor().is_err() {
                continue; // an exactly zero pivot: not expected from random data
            }
            let mut x = b.clone();
            band.solve(&mut x);
            let e = backward_error(n, &dense, &x, &b);
            worst = worst.max(e);
            assert!(
                e < 20.0 * n as f64 * f64::EPSILON,
                "n {n}, kl {kl}, ku {ku}: {e:e}"
            );
        }
    }
    println!("worst backward error {worst:e}");
}

#[test]
fn the_solution_is_faers_dense_lu_solution() {
    let mut rng = Lcg(11);
    for (n, kl, ku) in [(40, 3, 3), (100, 28, 28), (533, 28, 28)] {
        // Diagonally boosted: well conditioned, so the two solutions must agree closely.
        let (mut band, dense) = random_band(&mut rng, n, kl, ku, 4.0);
        let b: Vec<f64> = (0..n).map(|_| rng.next()).collect();
        band.factor().unwrap();
        let mut x = b.clone();
        band.solve(&mut x);
        let a = Mat::<f64>::from_fn(n, n, |i, j| dense[i * n + j]);
        let rhs = Mat::<f64>::from_fn(n, 1, |i, _| b[i]);
        let y = a.partial_piv_lu().solve(&rhs);
        let scale = (0..n).fold(0.0f64, |m, i| m.max(y[(i, 0)].abs()));
        for i in 0..n {
            assert!(
                (x[i] - y[(i, 0)]).abs() <= 1e-12 * scale,
                "n {n}: x[{i}] = {} vs faer {}",
                x[i],
                y[(i, 0)]
            );
        }
    }
}

#[test]
fn identity_rows_pin_their_unknowns_and_singular_matrices_name_the_row() {
    let mut rng = Lcg(3);
    let n = 30;
    let (mut band, _) = random_band(&mut rng, n, 4, 4, 3.0);
    for r in [0, 17, n - 1] {
        band.set_identity_row(r);
    }
    assert_eq!(band.get(17, 17), 1.0);
    assert_eq!(band.get(17, 16), 0.0);
    let b: Vec<f64> = (0..n).map(|i| i as f64).collect();
    band.factor().unwrap();
    let mut x = b.clone();
    band.solve(&mut x);
    for r in [0, 17, n - 1] {
        // Pivoting may mix the row into others: its value holds to round-off, not bit for bit.
        assert!(
            (x[r] - b[r]).abs() <= 4.0 * f64::EPSILON * b[r].abs().max(1.0),
            "row {r}: {} vs {}",
            x[r],
            b[r]
        );
    }
    // A zero column: the pivot search finds nothing at that step.
    let mut s = BandLu::new(5, 1, 1);
    for i in 0..5 {
        if i != 2 {
            s.add(i, i, 1.0);
        }
    }
    assert_eq!(s.factor(), Err(2));
}
