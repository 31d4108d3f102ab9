//! Kernel tests of `eigen`: the hand-written balancing (exactness, what it equalizes, that it
//! restores faer's accuracy on badly scaled matrices) and the faer-based eigenpairs (residuals
//! on seeded random matrices, conjugate-pair structure, normalization, known spectra).
use fmu_rotor::eigen::{self, C64};

mod common;
use common::Lcg;

const EPS: f64 = f64::EPSILON;

fn fro(a: &[f64]) -> f64 {
    a.iter().map(|x| x * x).sum::<f64>().sqrt()
}

/// D R D^-1 with D = diag(2^k), k uniform in [-kmax, kmax]: a badly scaled matrix whose
/// eigenvalues are those of the well-scaled R (and the scaling is exact).
fn badly_scaled(rng: &mut Lcg, n: usize, kmax: f64) -> (Vec<f64>, Vec<f64>) {
    let r = rng.vec(n * n);
    let d: Vec<f64> = (0..n)
        .map(|_| 2f64.powi((kmax * rng.next()).round() as i32))
        .collect();
    let mut a = r.clone();
    for i in 0..n {
        for j in 0..n {
            a[i * n + j] *= d[i] / d[j];
        }
    }
    (r, a)
}

fn sorted(mut v: Vec<C64>) -> Vec<C64> {
    v.sort_by(|a, b| a.re.total_cmp(&b.re).then(a.im.total_cmp(&b.im)));
    v
}

#[test]
fn balancing_is_an_exact_power_of_two_similarity() {
    let mut rng = Lcg(0xe16e_0001);
    for n in 1..=24 {
        let (_, a) = badly_scaled(&mut rng, n, 30.0);
        let mut b = a.clone();
        let d = eigen::balance(n, &mut b);
        assert_eq!(d.len(), n);
        for (i, di) in d.iter().enumerate() {
            let (m, _) = frexp(*di);
            assert_eq!(m, 0.5, "d[{i}] = {di} is not a power of 2");
        }
        // b = D^-1 a D, computed here independently: exact, bit for bit.
        for i in 0..n {
            for j in 0..n {
                assert_eq!(
                    b[i * n + j].to_bits(),
                    (a[i * n + j] / d[i] * d[j]).to_bits(),
                    "n = {n}, ({i}, {j})"
                );
            }
        }
    }
}

/// Mantissa and exponent, m in [0.5, 1).
fn frexp(x: f64) -> (f64, i32) {
    let e = x.abs().log2().floor() as i32 + 1;
    (x.abs() / 2f64.powi(e), e)
}

#[test]
fn balancing_equalizes_row_and_column_norms() {
    let mut rng = Lcg(0xe16e_0002);
    for n in 2..=24 {
        let (r, a) = badly_scaled(&mut rng, n, 40.0);
        let mut b = a.clone();
        eigen::balance(n, &mut b);
        for i in 0..n {
            let (c, rr) = (0..n).filter(|&j| j != i).fold((0.0, 0.0), |(c, r), j| {
                (c + b[j * n + i].abs(), r + b[i * n + j].abs())
            });
            if c > 0.0 && rr > 0.0 {
                // The iteration stops when no power of 2 improves c + r by 5 %.
                let ratio = c / rr;
                assert!(
                    (1.0 / 8.0..=8.0).contains(&ratio),
                    "n = {n}, row {i}: column/row norm {ratio}"
                );
            }
        }
        // From a spread of 2^80 back to the size of the well-scaled matrix.
        assert!(
            fro(&b) <= 4.0 * fro(&r),
            "n = {n}: |B| = {:.2e}, |R| = {:.2e}, |A| = {:.2e}",
            fro(&b),
            fro(&r),
            fro(&a)
        );
    }
}

#[test]
fn balancing_leaves_zero_rows_columns_and_small_cases_alone() {
    let mut a = vec![3.0];
    assert_eq!(eigen::balance(1, &mut a), vec![1.0]);
    assert_eq!(a, vec![3.0]);
    // Upper triangular with a zero column: rows or columns without off-diagonal entries are
    // not scaled (their eigenvalue is already isolated).
    let mut a = vec![1.0, 1e6, 0.0, 2.0];
    let d = eigen::balance(2, &mut a);
    assert_eq!(d, vec![1.0, 1.0]);
    assert_eq!(a, vec![1.0, 1e6, 0.0, 2.0]);
    assert!(eigen::balance(0, &mut []).is_empty());
}

/// ||A x - lambda x|| / (||A|| ||x||) for every pair, the conjugate-pair structure, the
/// normalization, and sum(lambda) = trace(A).
fn check_pairs(n: usize, a: &[f64], label: &str) {
    let pairs = eigen::eigenpairs(n, a).unwrap();
    assert_eq!(pairs.len(), n, "{label}");
    let values = eigen::eigenvalues(n, a).unwrap();
    let an = fro(a);
    // `eigenvalues` (no Schur vectors) and `eigenpairs` find the same spectrum.
    let from_pairs = sorted(pairs.iter().map(|(l, _)| *l).collect());
    for (x, y) in from_pairs.iter().zip(&sorted(values.clone())) {
        assert!(
            (x - y).norm() <= 16.0 * n as f64 * EPS * an,
            "{label}: {x} vs {y}"
        );
    }
    for (k, (lam, v)) in pairs.iter().enumerate() {
        let vn = v.iter().map(|z| z.norm_sqr()).sum::<f64>().sqrt();
        let mut res = 0.0;
        for i in 0..n {
            let mut s = C64::new(0.0, 0.0);
            for j in 0..n {
                s += v[j] * a[i * n + j];
            }
            res += (s - lam * v[i]).norm_sqr();
        }
        let res = res.sqrt() / (an * vn);
        assert!(
            res < 16.0 * n as f64 * EPS,
            "{label}: residual {res:.2e} of pair {k}"
        );
        // Largest component exactly 1.
        let big = v.iter().map(|z| z.norm()).fold(0.0, f64::max);
        assert_eq!(big, 1.0, "{label}");
        assert!(v.contains(&C64::new(1.0, 0.0)), "{label}");
    }
    // Real eigenvalues have im == 0 exactly; complex ones come as exact conjugates.
    let mut pos: Vec<C64> = values.iter().copied().filter(|l| l.im > 0.0).collect();
    let mut neg: Vec<C64> = values
        .iter()
        .filter(|l| l.im < 0.0)
        .map(|l| l.conj())
        .collect();
    pos = sorted(pos);
    neg = sorted(neg);
    assert_eq!(pos, neg, "{label}: conjugate pairs");
    let trace: f64 = (0..n).map(|i| a[i * n + i]).sum();
    let sum: f64 = values.iter().map(|l| l.re).sum();
    let scale = values.iter().map(|l| l.norm()).sum::<f64>().max(an);
    assert!(
        (sum - trace).abs() <= 16.0 * n as f64 * EPS * scale,
        "{label}: sum {sum} vs trace {trace}"
    );
}

#[test]
fn eigenpairs_of_random_matrices_have_small_residuals() {
    let mut rng = Lcg(0xe16e_0003);
    for n in 1..=24 {
        for rep in 0..3 {
            let a = rng.vec(n * n);
            check_pairs(n, &a, &format!("random n = {n} #{rep}"));
        }
    }
}

#[test]
fn balancing_restores_accuracy_on_badly_scaled_matrices() {
    // The eigenvalues of D R D^-1 are those of R. Computed from R (well scaled), they are the
    // reference; from the badly scaled matrix they must agree to round-off of |R|.
    let mut rng = Lcg(0xe16e_0004);
    for n in [2, 5, 8, 16, 20] {
        for _ in 0..3 {
            let (r, a) = badly_scaled(&mut rng, n, 25.0);
            let reference = sorted(eigen::eigenvalues(n, &r).unwrap());
            let got = sorted(eigen::eigenvalues(n, &a).unwrap());
            let rn = fro(&r);
            for (x, y) in reference.iter().zip(&got) {
                assert!(
                    (x - y).norm() <= 1e-10 * rn,
                    "n = {n}: {x} vs {y} (|R| = {rn:.2e})"
                );
            }
            check_pairs(n, &a, &format!("badly scaled n = {n}"));
        }
    }
}

#[test]
fn known_spectra() {
    // Damped oscillator x'' + 2 zeta w x' + w^2 x = 0 in first-order form, w = 2 pi 1000 Hz.
    let (w, zeta) = (2.0 * std::f64::consts::PI * 1000.0, 0.05);
    let a = [0.0, 1.0, -w * w, -2.0 * zeta * w];
    let ev = eigen::eigenvalues(2, &a).unwrap();
    let exact = C64::new(-zeta * w, w * (1.0 - zeta * zeta).sqrt());
    let upper = ev.iter().find(|l| l.im > 0.0).unwrap();
    assert!((upper - exact).norm() <= 1e-13 * w, "{upper} vs {exact}");
    assert!(ev.contains(&upper.conj()));
    // Undamped: purely imaginary (to round-off of w).
    let ev = eigen::eigenvalues(2, &[0.0, 1.0, -w * w, 0.0]).unwrap();
    for l in &ev {
        assert!(l.re.abs() <= 4.0 * EPS * w && (l.im.abs() - w).abs() <= 4.0 * EPS * w);
    }
    // Companion matrix of (x - 1)(x - 2)(x - 3)(x^2 + 1) = x^5 - 6x^4 + 12x^3 - 12x^2 + 11x - 6.
    let c = [6.0, -12.0, 12.0, -11.0, 6.0]; // x^5 = 6x^4 - 12x^3 + 12x^2 - 11x + 6
    let mut m = vec![0.0; 25];
    m[..5].copy_from_slice(&c);
    for i in 1..5 {
        m[i * 5 + i - 1] = 1.0;
    }
    let ev = sorted(eigen::eigenvalues(5, &m).unwrap());
    let exact = sorted(vec![
        C64::new(1.0, 0.0),
        C64::new(2.0, 0.0),
        C64::new(3.0, 0.0),
        C64::new(0.0, 1.0),
        C64::new(0.0, -1.0),
    ]);
    for (x, y) in ev.iter().zip(&exact) {
        assert!((x - y).norm() < 1e-12, "{x} vs {y}");
    }
    assert_eq!(ev.iter().filter(|l| l.im == 0.0).count(), 3);
    // A triangular matrix: its diagonal, real, exactly separated.
    let t = [1.0, 5.0, -3.0, 0.0, -2.0, 7.0, 0.0, 0.0, 0.5];
    let ev = sorted(eigen::eigenvalues(3, &t).unwrap());
    let exact = [-2.0, 0.5, 1.0];
    for (x, y) in ev.iter().zip(exact) {
        assert!(x.im == 0.0 && (x.re - y).abs() < 1e-15, "{x} vs {y}");
    }
    check_pairs(3, &t, "triangular");
    check_pairs(5, &m, "companion");
}

#[test]
fn non_finite_input_is_an_error() {
    for bad in [f64::NAN, f64::INFINITY] {
        let mut a = vec![1.0, 2.0, 3.0, 4.0];
        a[1] = bad;
        assert!(eigen::eigenvalues(2, &a).is_err());
        assert!(eigen::eigenpairs(2, &a).is_err());
    }
}
