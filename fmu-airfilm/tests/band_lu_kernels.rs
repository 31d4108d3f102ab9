//! Kernel tests of the hand-written banded LU (`linsolve::BandLu`, LAPACK dgbtf2/dgbtrs), which
//! stays because it is 3.9x faster than faer's sparse LU on the film's Newton matrix
//! (BENCHMARKS.md): residual tests on seeded random band matrices that need pivoting, faer's dense
//! LU as an independent solution, identity rows, singular matrices; without row interchanges:
//! residual tests, the growth check refusing what needs pivoting, and the film's own Newton
//! matrices, solved like the pivoted factorization solves them.

use faer::linalg::solvers::Solve;
use faer::Mat;
use fmu_airfilm::geometry::{GapField, Geometry};
use fmu_airfilm::linsolve::{BandLu, FactorError, GROWTH_LIMIT};
use fmu_airfilm::mesh::Mesh;
use fmu_airfilm::reynolds::{self, Coeffs};
use fmu_airfilm::{steady_state, BearingParams, Bore, JournalState};

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
    random_band_pivoting(rng, n, kl, ku, diag, true)
}

fn random_band_pivoting(
    rng: &mut Lcg,
    n: usize,
    kl: usize,
    ku: usize,
    diag: f64,
    pivoting: bool,
) -> (BandLu, Vec<f64>) {
    let mut band = BandLu::new(n, kl, ku);
    band.set_pivoting(pivoting);
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
    assert_eq!(s.factor(), Err(FactorError::ZeroPivot { row: 2 }));
}

/// Without row interchanges, on diagonally dominant random band matrices (where elimination
/// without pivoting is stable) of every size 1..80: round-off backward error, and the pivoted
/// factorization of the same matrix as an independent solution.
#[test]
fn without_interchanges_dominant_band_matrices_are_solved_to_round_off() {
    let mut rng = Lcg(5);
    for n in 1..=80 {
        for (kl, ku) in [(0, 0), (1, 1), (2, 5), (5, 2), (9, 9), (28, 28)] {
            let (kl, ku) = (kl.min(n - 1), ku.min(n - 1));
            let diag = (kl + ku + 1) as f64;
            let seed = rng.0;
            let (mut band, dense) = random_band_pivoting(&mut rng, n, kl, ku, diag, false);
            let (mut pivoted, _) = random_band_pivoting(&mut Lcg(seed), n, kl, ku, diag, true);
            assert!(!band.pivoting() && pivoted.pivoting());
            let b: Vec<f64> = (0..n).map(|_| rng.next()).collect();
            band.factor().unwrap();
            pivoted.factor().unwrap();
            let (mut x, mut y) = (b.clone(), b.clone());
            band.solve(&mut x);
            pivoted.solve(&mut y);
            let e = backward_error(n, &dense, &x, &b);
            assert!(
                e < 20.0 * n as f64 * f64::EPSILON,
                "n {n}, kl {kl}, ku {ku}: {e:e}"
            );
            let scale = y.iter().fold(0.0f64, |m, v| m.max(v.abs()));
            for i in 0..n {
                assert!(
                    (x[i] - y[i]).abs() <= 1e-13 * scale,
                    "n {n}, kl {kl}, ku {ku}, x[{i}]: {} vs pivoted {}",
                    x[i],
                    y[i]
                );
            }
        }
    }
}

/// A matrix that needs an interchange (a tiny leading pivot) is refused for its growth, a zero
/// pivot and a NaN are refused, and pivoting then solves what elimination without it could not.
#[test]
fn without_interchanges_growth_zero_pivots_and_nan_are_refused() {
    let build = |a00: f64, pivoting: bool| {
        let mut m = BandLu::new(3, 1, 1);
        m.set_pivoting(pivoting);
        for (r, c, v) in [
            (0, 0, a00),
            (0, 1, 1.0),
            (1, 0, 1.0),
            (1, 1, 1.0),
            (1, 2, 1.0),
            (2, 1, 1.0),
            (2, 2, 3.0),
        ] {
            m.add(r, c, v);
        }
        m
    };
    // u11 = 1 - 1/1e-8: growth 1e8.
    match build(1e-8, false).factor() {
        Err(FactorError::Growth { ratio }) => assert!(ratio > GROWTH_LIMIT, "{ratio}"),
        other => panic!("{other:?}"),
    }
    assert_eq!(
        build(0.0, false).factor(),
        Err(FactorError::ZeroPivot { row: 0 })
    );
    let mut with_nan = build(2.0, false);
    with_nan.add(2, 1, f64::NAN);
    assert!(with_nan.factor().is_err());
    // The same tiny-pivot matrix with pivoting: x = (1, 1, 1) from b = A (1, 1, 1).
    let mut m = build(1e-8, true);
    m.factor().unwrap();
    let mut x = vec![1.0 + 1e-8, 3.0, 4.0];
    m.solve(&mut x);
    for v in x {
        assert!((v - 1.0).abs() < 1e-14, "{v}");
    }
    // Switching the layout keeps the matrix square and clears it.
    let mut s = build(2.0, true);
    s.set_pivoting(false);
    assert_eq!(s.get(0, 0), 0.0);
    assert!(s.fits(3, 1, 1));
}

/// The film's own Newton matrices (every lobe of the paper mesh at steady states from concentric
/// to eps 0.99, clearances 10-30 um, steps 5-100 us, C = 15 um / dH = 0 included): elimination
/// without interchanges passes its growth check and solves like partial pivoting, to 1e-12.
#[test]
fn film_newton_matrices_factorize_without_interchanges() {
    let mut worst = 0.0f64;
    for (c_um, dh_um, eps, f_hz, h_s) in [
        (20.0, 40.0, 0.0, 300.0, 5e-5),
        (20.0, 40.0, 0.5, 1000.0, 1e-5),
        (20.0, 40.0, 0.9, 2000.0, 5e-5),
        (15.0, 0.0, 0.95, 2000.0, 5e-5),
        (15.0, 0.0, 0.99, 500.0, 5e-6),
        (30.0, 60.0, 0.9, 2000.0, 1e-4),
        (10.0, 20.0, 0.98, 2000.0, 1e-4),
    ] {
        let mut prm = BearingParams::paper();
        prm.bore = Bore {
            c_m: c_um * 1e-6,
            dh_m: dh_um * 1e-6,
            ..prm.bore
        };
        let mesh = Mesh::new(&prm);
        let geom = Geometry::new(&prm, &mesh);
        let mut gap = GapField::default();
        let j = JournalState {
            dx_m: 2f64.cos() * eps * prm.bore.c_m,
            dy_m: 2f64.sin() * eps * prm.bore.c_m,
            vx_m_s: 0.0,
            vy_m_s: 0.0,
            omega_rad_s: 2.0 * std::f64::consts::PI * f_hz,
        };
        let p = steady_state(&prm, j).unwrap().p_rel;
        geom.update(&j, prm.bore.c_m, &mut gap);
        let co = Coeffs {
            lambda: prm.bearing_number(j.omega_rad_s),
            tau_s: prm.squeeze_time_s(),
            c0_per_s: 1.5 / h_s,
        };
        let n = mesh.npb;
        for k in 0..mesh.n_blocks {
            let mut lus = [true, false].map(|pivoting| {
                let mut lu = BandLu::new(n, mesh.kl, mesh.ku);
                lu.set_pivoting(pivoting);
                reynolds::jacobian(&mesh, &gap, k, co, &p[k * n..(k + 1) * n], &mut lu);
                lu
            });
            let b: Vec<f64> = (0..n)
                .map(|i| ((i * 7919) % 101) as f64 / 101.0 - 0.5)
                .collect();
            let [y, x] = lus.each_mut().map(|lu| {
                lu.factor().unwrap();
                let mut x = b.clone();
                lu.solve(&mut x);
                x
            });
            let scale = y.iter().fold(0.0f64, |m, v| m.max(v.abs()));
            let diff = x
                .iter()
                .zip(&y)
                .fold(0.0f64, |m, (a, b)| m.max((a - b).abs()));
            worst = worst.max(diff / scale);
            assert!(
                diff <= 1e-12 * scale,
                "C {c_um}, dH {dh_um}, eps {eps}, lobe {k}: {diff:e} of {scale:e}"
            );
        }
    }
    println!("largest difference to the pivoted solve {worst:e} (relative)");
}
