//! Newton-Krylov shooting and its GMRES on problems with known answers: random dense systems,
//! and the Hopf normal form with a long tail of decaying directions (hundreds of state values,
//! like the films' pressures beside the rotor), whose orbit and multipliers are exact.

use super::krylov::{gmres_dense, shoot_krylov, KrylovOptions};
use super::normal_form::HopfNormalForm;
use super::shooting::{Flow, ShootingOptions};
use nalgebra::{DMatrix, DVector};

/// A reproducible pseudo-random number in [-1, 1).
fn lcg(seed: &mut u64) -> f64 {
    *seed = seed
        .wrapping_mul(6364136223846793005)
        .wrapping_add(1442695040888963407);
    ((*seed >> 11) as f64 / (1u64 << 53) as f64) * 2.0 - 1.0
}

#[test]
fn gmres_solves_random_nonsymmetric_systems_to_its_tolerance() {
    let mut seed = 7;
    for n in [1, 5, 40] {
        // Diagonally shifted: well conditioned but far from symmetric.
        let a = DMatrix::from_fn(n, n, |i, j| lcg(&mut seed) + if i == j { 3.0 } else { 0.0 });
        let b = DVector::from_fn(n, |_, _| lcg(&mut seed));
        for tol in [1e-4, 1e-10] {
            let (z, used) = gmres_dense(&a, &b, tol);
            let r = &b - &a * DVector::from_column_slice(&z);
            assert!(
                r.norm() <= tol * b.norm() * 1.0001,
                "n {n}: |r| {} > {tol} |b|",
                r.norm()
            );
            assert!(used <= n, "{used} products for n = {n}");
        }
    }
    // A system with few distinct eigenvalues converges in that many products.
    let a = DMatrix::from_fn(
        30,
        30,
        |i, j| {
            if i == j {
                [1.0, 2.0, 5.0][i % 3]
            } else {
                0.0
            }
        },
    );
    let b = DVector::from_element(30, 1.0);
    let (_, used) = gmres_dense(&a, &b, 1e-12);
    assert_eq!(used, 3);
}

/// The Hopf normal form plus `m` decoupled directions w_k' = -rate_k w_k, advanced exactly.
struct HopfWithTail {
    nf: HopfNormalForm,
    rates: Vec<f64>,
}

impl Flow for HopfWithTail {
    fn dim(&self) -> usize {
        3 + self.rates.len()
    }
    fn scale(&self) -> Vec<f64> {
        vec![1.0; self.dim()]
    }
    fn flow(&mut self, x0: &[f64], at_s: &[f64]) -> Result<Vec<Vec<f64>>, String> {
        let head = self.nf.flow(&x0[..3], at_s)?;
        Ok(head
            .into_iter()
            .zip(at_s)
            .map(|(mut h, t)| {
                h.extend(
                    self.rates
                        .iter()
                        .zip(&x0[3..])
                        .map(|(r, w)| w * (-r * t).exp()),
                );
                h
            })
            .collect())
    }
}

#[test]
fn newton_krylov_finds_the_orbit_of_a_large_state_and_its_leading_multipliers() {
    // Rates 2..40: the tail's multipliers (below exp(-2 T) = 0.14) cluster under the radial (0.61)
    // and z (0.37) ones.
    let rates: Vec<f64> = (0..300).map(|k| 2.0 + 38.0 * k as f64 / 300.0).collect();
    let mut flow = HopfWithTail {
        nf: HopfNormalForm::supercritical(0.25),
        rates: rates.clone(),
    };
    // 10 % off in radius, every tail direction disturbed, 8 % off in period. (The phase plane is
    // normal to the vector field at the guess: a guess far off a fast-decaying direction would
    // tilt it away from the orbit, as a guess far from a settled whirl would.)
    let mut x0 = vec![0.4, 0.2, 0.1];
    x0.extend((0..rates.len()).map(|k| 1e-3 * (k as f64 * 0.37).sin()));
    let opts = KrylovOptions {
        shooting: ShootingOptions::default(),
        ..KrylovOptions::default()
    };
    let found = shoot_krylov(&mut flow, &x0, 0.9, &opts).unwrap();
    let orbit = &found.orbit;
    let r = orbit.x0[0].hypot(orbit.x0[1]);
    assert!((r - 0.5).abs() < 1e-6, "radius {r}");
    let t_exact = flow.nf.exact_period_s(0.5);
    assert!(
        (orbit.period_s - t_exact).abs() < 1e-8 * t_exact,
        "period {}",
        orbit.period_s
    );
    let tail = orbit.x0[2..].iter().fold(0.0f64, |m, x| m.max(x.abs()));
    assert!(tail < 1e-7, "tail {tail}");
    // Newton converges fast, and each step needs far fewer products than the 303 unknowns.
    assert!(
        orbit.iterations <= 8,
        "{} Newton iterations",
        orbit.iterations
    );
    for k in &found.krylov_iterations {
        assert!(*k <= 40, "{k} GMRES products in one Newton step");
    }
    // The Ritz values hold the trivial multiplier 1, the radial one and the z one.
    let radial = flow.nf.exact_multipliers(0.5)[0];
    let near = |target: f64| {
        orbit
            .multipliers
            .iter()
            .map(|m| (m - nalgebra::Complex::new(target, 0.0)).norm())
            .fold(f64::INFINITY, f64::min)
    };
    assert!(near(1.0) < 1e-4, "{:?}", orbit.multipliers);
    assert!(
        near(radial) < 1e-4 * radial.max(1e-2),
        "radial {radial}: {:?}",
        orbit.multipliers
    );
    let z = flow.nf.exact_multipliers(0.5)[1];
    assert!(near(z) < 1e-3 * z, "z {z}: {:?}", orbit.multipliers);
    assert!(orbit.stable());
}
