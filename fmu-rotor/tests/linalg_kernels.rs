//! Kernel tests of the hand-written linear algebra in `linalg` (the LU factorization), in the
//! manner of faer's own tests: residuals on seeded random matrices, checked against an
//! independent solution (faer's partial-pivoting LU). The bodies' 3x3 arithmetic is nalgebra's.
use fmu_rotor::linalg::*;
use fmu_rotor::{RotorError, RotorParams};

mod common;
use common::Lcg;

const EPS: f64 = f64::EPSILON;

fn inf_norm_mat(n: usize, a: &[f64]) -> f64 {
    (0..n)
        .map(|i| a[i * n..(i + 1) * n].iter().map(|x| x.abs()).sum::<f64>())
        .fold(0.0, f64::max)
}

fn inf_norm(v: &[f64]) -> f64 {
    v.iter().fold(0.0, |m, x| m.max(x.abs()))
}

/// ||A x - b||_inf / (||A||_inf ||x||_inf), the normwise backward error of a solve.
fn backward_error(n: usize, a: &[f64], x: &[f64], b: &[f64]) -> f64 {
    let r: Vec<f64> = (0..n)
        .map(|i| {
            let ax: f64 = (0..n).map(|j| a[i * n + j] * x[j]).sum();
            ax - b[i]
        })
        .collect();
    inf_norm(&r) / (inf_norm_mat(n, a) * inf_norm(x))
}

/// faer's partial-pivoting LU solve (an independent implementation) and the 2-norm condition
/// number of `a`.
fn faer_solve_and_cond(n: usize, a: &[f64], b: &[f64]) -> (Vec<f64>, f64) {
    use faer::linalg::solvers::Solve;
    let m = faer::Mat::from_fn(n, n, |i, j| a[i * n + j]);
    let rhs = faer::Mat::from_fn(n, 1, |i, _| b[i]);
    let x = m.partial_piv_lu().solve(&rhs);
    let s = m.singular_values().unwrap();
    let cond = s[0] / s[n - 1];
    ((0..n).map(|i| x[(i, 0)]).collect(), cond)
}

fn check_solve(n: usize, a: &[f64], b: &[f64], label: &str) {
    let lu = Lu::factor(n, a.to_vec(), "kernel test").unwrap();
    assert_eq!(lu.dim(), n);
    let mut x = b.to_vec();
    lu.solve(&mut x);
    let be = backward_error(n, a, &x, b);
    assert!(
        be < 4.0 * n as f64 * EPS,
        "{label}: backward error {be:.2e} (n = {n})"
    );
    let (xf, cond) = faer_solve_and_cond(n, a, b);
    let diff: Vec<f64> = x.iter().zip(&xf).map(|(p, q)| p - q).collect();
    let rel = inf_norm(&diff) / inf_norm(&x);
    // Both solutions are backward stable: they differ by at most ~ cond * n * eps.
    assert!(
        rel <= 8.0 * n as f64 * EPS * cond,
        "{label}: |x - x_faer| / |x| = {rel:.2e}, cond = {cond:.2e} (n = {n})"
    );
    // The convenience wrapper is the same computation.
    let mut y = b.to_vec();
    solve_dense(n, a.to_vec(), &mut y, "kernel test").unwrap();
    assert_eq!(x, y, "{label}: solve_dense differs from Lu (n = {n})");
}

#[test]
fn lu_solves_random_dense_matrices_of_sizes_1_to_60() {
    let mut rng = Lcg(0x5eed_0001);
    for n in 1..=60 {
        for rep in 0..3 {
            let a = rng.vec(n * n);
            let b = rng.vec(n);
            check_solve(n, &a, &b, &format!("dense #{rep}"));
        }
    }
}

/// The GGL iteration matrix is mostly zeros, with zero diagonal blocks in the constraint rows
/// (a saddle point [[A, G^T], [G, 0]]): pivoting must go off the diagonal, and the elimination
/// skips zero multipliers.
#[test]
fn lu_solves_sparse_saddle_point_matrices() {
    let mut rng = Lcg(0x5eed_0002);
    for (nq, nc) in [(1, 1), (6, 2), (18, 10), (28, 28), (40, 20)] {
        let n = nq + nc;
        let mut a = vec![0.0; n * n];
        for i in 0..nq {
            a[i * n + i] = 2.0 + rng.next();
            for j in 0..nq {
                if rng.next() > 0.8 {
                    a[i * n + j] += rng.next();
                }
            }
        }
        for c in 0..nc {
            // Each constraint row touches a few coordinates, always its own one (full rank).
            let own = c * nq / nc;
            a[(nq + c) * n + own] = 1.0 + rng.next().abs();
            a[own * n + nq + c] = a[(nq + c) * n + own];
            for j in 0..nq {
                if j != own && rng.next() > 0.9 {
                    let g = rng.next();
                    a[(nq + c) * n + j] = g;
                    a[j * n + nq + c] = g;
                }
            }
        }
        let b = rng.vec(n);
        check_solve(n, &a, &b, &format!("saddle point nq = {nq}, nc = {nc}"));
    }
}

/// The solves run over the factors' nonzeros: a diagonally dominant tridiagonal matrix factors
/// without interchanges into bidiagonal L and U (n - 1 entries off each diagonal), and the
/// solve over those lists is the exact solution's backward-stable match.
#[test]
fn lu_solves_run_over_the_nonzeros_of_the_factors() {
    let mut rng = Lcg(0x5eed_0006);
    for n in [1, 2, 5, 56] {
        let mut a = vec![0.0; n * n];
        for i in 0..n {
            a[i * n + i] = 4.0 + rng.next();
            if i > 0 {
                a[i * n + i - 1] = rng.next();
                a[(i - 1) * n + i] = rng.next();
            }
        }
        let lu = Lu::factor(n, a.clone(), "tridiagonal").unwrap();
        assert_eq!(lu.off_diagonal_nonzeros(), (n - 1, n - 1), "n = {n}");
        let b = rng.vec(n);
        check_solve(n, &a, &b, &format!("tridiagonal n = {n}"));
    }
}

/// Badly scaled rows (1e-8 ... 1e8), as in the iteration matrix where masses, beta h and
/// constraint gradients meet.
#[test]
fn lu_solves_badly_scaled_matrices() {
    let mut rng = Lcg(0x5eed_0003);
    for n in [2, 7, 16, 56] {
        let mut a = rng.vec(n * n);
        for i in 0..n {
            let s = 10f64.powf(8.0 * rng.next());
            for j in 0..n {
                a[i * n + j] *= s;
            }
        }
        let b = rng.vec(n);
        // Row scaling does not change the backward error of partial pivoting much, but the
        // normwise bound is looser: compare with faer through the condition number only.
        let lu = Lu::factor(n, a.clone(), "kernel test").unwrap();
        let mut x = b.clone();
        lu.solve(&mut x);
        let (xf, cond) = faer_solve_and_cond(n, &a, &b);
        let diff: Vec<f64> = x.iter().zip(&xf).map(|(p, q)| p - q).collect();
        let rel = inf_norm(&diff) / inf_norm(&x);
        assert!(
            rel <= 8.0 * n as f64 * EPS * cond,
            "n = {n}: {rel:.2e}, cond {cond:.2e}"
        );
        let be = backward_error(n, &a, &x, &b);
        assert!(
            be < 4.0 * n as f64 * EPS,
            "n = {n}: backward error {be:.2e}"
        );
    }
}

#[test]
fn lu_is_exact_on_a_permuted_triangular_system() {
    // P A = L U with small integers: every operation is exact, so is the solution.
    // A = [[0, 2, 1], [1, 1, 1], [2, 0, 4]], x = (1, -2, 3) -> b = (-1, 2, 14).
    let a = vec![0.0, 2.0, 1.0, 1.0, 1.0, 1.0, 2.0, 0.0, 4.0];
    let lu = Lu::factor(3, a, "exact").unwrap();
    let mut b = [-1.0, 2.0, 14.0];
    lu.solve(&mut b);
    assert_eq!(b, [1.0, -2.0, 3.0]);
}

#[test]
fn a_singular_matrix_is_an_error_naming_the_system() {
    let mut rng = Lcg(0x5eed_0004);
    let check = |n: usize, a: Vec<f64>, label: &str| match Lu::factor(n, a, "test matrix") {
        Err(e @ RotorError::Singular(what)) => {
            assert_eq!(what, "test matrix", "{label}");
            assert!(e.to_string().contains("test matrix"), "{label}: {e}");
        }
        other => panic!("{label}: expected Singular, got {other:?}"),
    };
    // Only exact zero pivots are detected (a numerically singular matrix with round-off in its
    // last pivot is not): matrices whose elimination is exact, or with a zero row or column.
    check(1, vec![0.0], "1 x 1 zero");
    // Row 2 = 2 x row 1 (pivot 2, multiplier 0.5: exact), row 3 independent.
    check(
        3,
        vec![1.0, 2.0, 3.0, 2.0, 4.0, 6.0, 1.0, 1.0, 1.0],
        "dependent rows, exact elimination",
    );
    check(4, vec![0.0; 16], "zero matrix");
    for n in [2, 5, 17, 56] {
        // A zero column.
        let mut a = rng.vec(n * n);
        let j0 = n / 2;
        for i in 0..n {
            a[i * n + j0] = 0.0;
        }
        check(n, a, &format!("zero column, n = {n}"));
        // A zero row: never chosen as pivot, it is the last row left, with a zero pivot.
        let mut a = rng.vec(n * n);
        for j in 0..n {
            a[(n / 3) * n + j] = 0.0;
        }
        check(n, a, &format!("zero row, n = {n}"));
        // A pivot column without a finite nonzero entry (here NaN over zeros) is reported too.
        let mut a = rng.vec(n * n);
        a[0] = f64::NAN;
        a[n * n - 1] = f64::INFINITY;
        for i in 0..n {
            a[i * n] = if i == 0 { f64::NAN } else { 0.0 };
        }
        check(n, a, &format!("NaN column, n = {n}"));
    }
    let mut b = [1.0, 2.0];
    match solve_dense(2, vec![1.0, 2.0, 2.0, 4.0], &mut b, "wrapper") {
        Err(RotorError::Singular(what)) => assert_eq!(what, "wrapper"),
        other => panic!("expected Singular, got {other:?}"),
    }
}

/// The factors are state of the integrator: a serialized and restored LU must solve
/// bit-identically.
#[test]
fn lu_factors_survive_serialization_bit_identically() {
    let mut rng = Lcg(0x5eed_0005);
    let n = 56;
    let a = rng.vec(n * n);
    let lu = Lu::factor(n, a, "serde").unwrap();
    let bytes = bincode::serialize(&lu).unwrap();
    let back: Lu = bincode::deserialize(&bytes).unwrap();
    let b = rng.vec(n);
    let (mut x, mut y) = (b.clone(), b.clone());
    lu.solve(&mut x);
    back.solve(&mut y);
    assert!(x.iter().zip(&y).all(|(p, q)| p.to_bits() == q.to_bits()));
}

/// Real GGL iteration matrices of the paper's rotor (56 x 56): journals free, and pressed into
/// their rings (the contact's stiff entries), each at a short and a long step.
fn ggl_matrices() -> Vec<(String, Vec<f64>)> {
    use bearing::{Bore, BoreContact};
    use fmu_rotor::ggl::{assemble_iteration_matrix, constraint_jacobian, force_jacobians, Work};
    use fmu_rotor::rotor::{build_system, initial_state, N_INPUTS};
    let mut out = Vec::new();
    for pressed in [false, true] {
        let p = RotorParams {
            contact: Some([BoreContact::paper(), BoreContact::paper()]),
            ..RotorParams::paper()
        };
        let sys = build_system(&p, None);
        let (nq, nc) = (sys.n_coords(), sys.n_constraints());
        let (mut x, mut v) = initial_state(&p);
        if pressed {
            x[1] -= 3.0 * Bore::paper().c_m;
        }
        for (i, vi) in v.iter_mut().enumerate() {
            *vi += 1e-3 * (i as f64 + 1.0).sin();
        }
        let u = [0.0; N_INPUTS];
        let mut work = Work::new(sys.bodies.len());
        let (fx, fv, m) = force_jacobians(&sys, &x, &v, &u, &mut work);
        let m_flat: Vec<f64> = m.iter().flatten().copied().collect();
        let g = constraint_jacobian(&sys);
        for beta_h in [2e-7, 2e-5] {
            let a = assemble_iteration_matrix(nq, nc, &g, &m_flat, &fx, &fv, beta_h);
            out.push((format!("pressed {pressed}, beta h {beta_h:e}"), a));
        }
    }
    out
}

/// The elimination as it was written before it updated only the columns of U's nonzeros
/// (every column right of the pivot, x - l 0 included), with the solve over every nonzero entry.
fn dense_reference_solve(n: usize, mut a: Vec<f64>, b: &mut [f64]) {
    let mut piv = vec![0usize; n];
    for k in 0..n {
        let mut p = k;
        let mut best = a[k * n + k].abs();
        for i in k + 1..n {
            if a[i * n + k].abs() > best {
                best = a[i * n + k].abs();
                p = i;
            }
        }
        assert!(best > 0.0 && best.is_finite());
        piv[k] = p;
        for j in 0..n {
            a.swap(k * n + j, p * n + j);
        }
        let inv = 1.0 / a[k * n + k];
        for i in k + 1..n {
            let l = a[i * n + k] * inv;
            if l != 0.0 {
                a[i * n + k] = l;
                for j in k + 1..n {
                    a[i * n + j] -= l * a[k * n + j];
                }
            } else {
                a[i * n + k] = 0.0;
            }
        }
    }
    for k in 0..n {
        b.swap(k, piv[k]);
    }
    for i in 0..n {
        for j in 0..i {
            if a[i * n + j] != 0.0 {
                b[i] -= a[i * n + j] * b[j];
            }
        }
    }
    for i in (0..n).rev() {
        for j in i + 1..n {
            if a[i * n + j] != 0.0 {
                b[i] -= a[i * n + j] * b[j];
            }
        }
        b[i] /= a[i * n + i];
    }
}

/// Updating only U's nonzero columns, and (n <= 64) visiting only the nonzeros the masks hold,
/// skips exactly the operations that change nothing: the solutions equal the dense elimination's
/// bit for bit, on the rotor's GGL matrices (free and in ring contact), sparse and dense
/// matrices on both sides of n = 64. And a factorization read back from its
/// serialized form solves bit-identically (its nonzero lists are rebuilt from the dense factors).
#[test]
fn lu_equals_the_dense_elimination_bit_for_bit() {
    let mut rng = Lcg(0x5eed_0007);
    let mut cases = ggl_matrices();
    assert_eq!(cases.len(), 4);
    // n <= 64 is factorized by the nonzero masks, larger n by the dense scans: both are checked.
    for (nq, nc) in [(6, 2), (18, 10), (40, 20), (44, 20), (50, 30)] {
        let n = nq + nc;
        let mut a = vec![0.0; n * n];
        for i in 0..n {
            for j in 0..n {
                if rng.next() > 0.85 || i == j {
                    a[i * n + j] = rng.next();
                } else if (i + j) % 7 == 0 {
                    a[i * n + j] = -0.0; // a negative zero is a zero too
                }
            }
        }
        cases.push((format!("sparse n = {n}"), a));
    }
    for n in [1, 3, 20, 56, 64, 65] {
        cases.push((format!("dense n = {n}"), rng.vec(n * n)));
    }
    for (label, a) in cases {
        let n = (a.len() as f64).sqrt() as usize;
        let lu = Lu::factor(n, a.clone(), "kernel test").unwrap();
        let back: Lu = bincode::deserialize(&bincode::serialize(&lu).unwrap()).unwrap();
        let (nl, nu) = lu.off_diagonal_nonzeros();
        assert_eq!((nl, nu), back.off_diagonal_nonzeros(), "{label}");
        for _ in 0..3 {
            let b = rng.vec(n);
            let (mut x, mut y, mut z) = (b.clone(), b.clone(), b.clone());
            lu.solve(&mut x);
            back.solve(&mut y);
            dense_reference_solve(n, a.clone(), &mut z);
            let bits = |v: &[f64]| v.iter().map(|q| q.to_bits()).collect::<Vec<_>>();
            assert_eq!(
                bits(&x),
                bits(&z),
                "{label}: differs from the dense elimination"
            );
            assert_eq!(bits(&x), bits(&y), "{label}: differs after serialization");
        }
        if label.starts_with("pressed") {
            // The GGL factors keep most of the matrix's zeros (the point of the sparse lists).
            assert!(nl + nu < n * (n - 1) / 2, "{label}: {nl} + {nu} nonzeros");
        }
    }
}

// ----- 3x3 helpers against nalgebra -----
