//! Shooting and continuation on the Hopf normal form, whose orbits, periods, multipliers,
//! fold and Hopf point are known exactly.

use super::continuation::{
    continue_branch, criticality, hopf_estimate, BranchEnd, ContinuationOptions, Criticality,
};
use super::normal_form::HopfNormalForm;
use super::shooting::{shoot, ShootingOptions};

fn rel(a: f64, b: f64) -> f64 {
    (a - b).abs() / b.abs()
}

/// Checks a shot orbit against the exact circle of radius r.
fn check_orbit(nf: &HopfNormalForm, orbit: &super::shooting::PeriodicOrbit, r: f64) {
    let radius = orbit.x0[0].hypot(orbit.x0[1]);
    assert!(rel(radius, r) < 1e-6, "radius {radius} vs exact {r}");
    assert!(orbit.x0[2].abs() < 1e-8, "z {}", orbit.x0[2]);
    let t = nf.exact_period_s(r);
    assert!(
        rel(orbit.period_s, t) < 1e-8,
        "period {} vs {t}",
        orbit.period_s
    );
    let mut got: Vec<f64> = orbit
        .nontrivial_multipliers()
        .iter()
        .map(|m| {
            assert!(m.im.abs() < 1e-6, "real multipliers expected: {m}");
            m.re
        })
        .collect();
    let mut exact = nf.exact_multipliers(r).to_vec();
    got.sort_by(f64::total_cmp);
    exact.sort_by(f64::total_cmp);
    for (g, e) in got.iter().zip(&exact) {
        assert!(
            (g - e).abs() < 2e-5 * e.abs().max(1e-3),
            "multiplier {g} vs exact {e}"
        );
    }
    let trivial = orbit
        .multipliers
        .iter()
        .map(|m| (m - nalgebra::Complex::new(1.0, 0.0)).norm())
        .fold(f64::INFINITY, f64::min);
    assert!(
        trivial < 1e-5,
        "no trivial multiplier 1: {:?}",
        orbit.multipliers
    );
}

#[test]
fn shooting_finds_the_supercritical_orbit_its_period_and_multipliers() {
    let mut nf = HopfNormalForm::supercritical(0.25);
    // Shooting is local: the guess is a point near the orbit (the application's is a settled
    // simulation), here 10 % off in radius, 0.1 off in z and 8 % off in period.
    let orbit = shoot(&mut nf, &[0.4, 0.2, 0.1], 0.9, &ShootingOptions::default()).unwrap();
    check_orbit(&nf, &orbit, 0.5);
    assert!(orbit.stable());
    assert!(
        orbit.iterations <= 8,
        "{} Newton iterations",
        orbit.iterations
    );
}

#[test]
fn shooting_finds_both_subcritical_orbits_the_inner_one_unstable() {
    let mut nf = HopfNormalForm::subcritical(-0.1);
    let radii = nf.exact_radii();
    assert_eq!(radii.len(), 2);
    let opts = ShootingOptions::default();
    let inner = shoot(&mut nf, &[radii[0] * 1.05, 0.0, 0.05], 0.95, &opts).unwrap();
    check_orbit(&nf, &inner, radii[0]);
    assert!(!inner.stable(), "{:?}", inner.multipliers);
    let outer = shoot(&mut nf, &[radii[1] * 0.95, 0.0, 0.05], 0.85, &opts).unwrap();
    check_orbit(&nf, &outer, radii[1]);
    assert!(outer.stable(), "{:?}", outer.multipliers);
}

#[test]
fn shooting_refuses_an_equilibrium_and_reports_non_convergence() {
    let mut nf = HopfNormalForm::supercritical(0.25);
    let e = shoot(&mut nf, &[0.0, 0.0, 0.0], 1.0, &ShootingOptions::default()).unwrap_err();
    assert!(e.contains("equilibrium"), "{e}");
    let e = shoot(&mut nf, &[0.3, 0.0, 0.0], -1.0, &ShootingOptions::default()).unwrap_err();
    assert!(e.contains("period guess"), "{e}");
    let few = ShootingOptions {
        max_iter: 1,
        ..ShootingOptions::default()
    };
    let e = shoot(&mut nf, &[0.4, 0.2, 0.1], 0.9, &few).unwrap_err();
    assert!(e.contains("did not converge in 1 iterations"), "{e}");
}

/// Down from mu = 0.25 the supercritical branch follows r = sqrt(mu), stays stable and ends at
/// the Hopf point mu = 0, which the extrapolation finds.
#[test]
fn continuation_follows_the_supercritical_branch_into_its_hopf_point() {
    let mut nf = HopfNormalForm::supercritical(0.25);
    let start = shoot(&mut nf, &[0.5, 0.0, 0.0], 0.9, &ShootingOptions::default()).unwrap();
    let opts = ContinuationOptions {
        min_size: 0.05,
        ..ContinuationOptions::default()
    };
    let branch = continue_branch(&mut nf, &start, false, &opts, &mut |_| {}).unwrap();
    assert_eq!(branch.end, BranchEnd::ReachedHopf, "{:?}", branch.end);
    assert!(branch.points.len() >= 4, "{} points", branch.points.len());
    assert!(branch.folds.is_empty());
    for p in &branch.points {
        let r = p.measures[0].1;
        assert!(rel(r, p.param.sqrt()) < 1e-6, "mu {} radius {r}", p.param);
        // A circle's RMS distance from its centre is its radius.
        assert!(rel(p.size, r) < 1e-6, "size {} radius {r}", p.size);
        assert!(p.orbit.stable());
    }
    let hopf = hopf_estimate(&branch).unwrap();
    assert!(hopf.abs() < 1e-6, "Hopf at mu = {hopf}");
    // The equilibrium is unstable for mu > 0.
    assert_eq!(
        criticality(&branch, hopf, true),
        Some(Criticality::Supercritical)
    );
}

/// From the large stable orbit at mu = 0 the subcritical branch runs down to its fold at
/// mu = -1/4, turns, comes back unstable and ends at the Hopf point mu = 0.
#[test]
fn continuation_passes_the_subcritical_fold_and_returns_to_the_hopf_point() {
    let mut nf = HopfNormalForm::subcritical(0.0);
    let r_outer = nf.exact_radii()[0];
    assert!((r_outer - 1.0).abs() < 1e-12);
    let start = shoot(&mut nf, &[1.0, 0.0, 0.0], 0.85, &ShootingOptions::default()).unwrap();
    let opts = ContinuationOptions {
        min_size: 0.05,
        ..ContinuationOptions::default()
    };
    let branch = continue_branch(&mut nf, &start, false, &opts, &mut |_| {}).unwrap();
    assert_eq!(branch.end, BranchEnd::ReachedHopf, "{:?}", branch.end);
    assert_eq!(branch.folds.len(), 1, "folds {:?}", branch.folds);
    let fold = branch.folds[0];
    let fold_mu = branch.points[fold].param.min(branch.points[fold + 1].param);
    assert!(
        fold_mu > -0.25 - 1e-9 && fold_mu < -0.25 + 0.02,
        "fold near mu = {fold_mu}"
    );
    for (i, p) in branch.points.iter().enumerate() {
        let r = p.measures[0].1;
        let g = p.param + r * r - r.powi(4);
        assert!(
            g.abs() < 1e-6,
            "point {i}: mu {} r {r} off the branch",
            p.param
        );
        // Outer (r^2 > 1/2) stable, inner unstable; the fold between them.
        if (r * r - 0.5).abs() > 0.02 {
            assert_eq!(
                p.orbit.stable(),
                r * r > 0.5,
                "point {i}: mu {} r {r}",
                p.param
            );
        }
    }
    let hopf = hopf_estimate(&branch).unwrap();
    assert!(hopf.abs() < 2e-3, "Hopf at mu = {hopf}");
    assert_eq!(
        criticality(&branch, hopf, true),
        Some(Criticality::Subcritical)
    );
}

/// A flow with noise (as the FMUs' adaptive steps give the co-simulated one): Newton stalls at
/// the noise; the defect reached is accepted only below `noise_floor`, else the stall is an
/// error naming the defect.
#[test]
fn shooting_stops_at_a_noisy_flows_noise_floor_only_when_allowed() {
    use super::shooting::Flow;
    struct Noisy(HopfNormalForm);
    impl Flow for Noisy {
        fn dim(&self) -> usize {
            3
        }
        fn scale(&self) -> Vec<f64> {
            vec![1.0; 3]
        }
        fn flow(&mut self, x0: &[f64], at_s: &[f64]) -> Result<Vec<Vec<f64>>, String> {
            // Deterministic noise of 1e-6 from the start state's bits.
            let h = x0.iter().fold(0u64, |h, v| {
                h.rotate_left(7) ^ v.to_bits().wrapping_mul(0x9e37_79b9_7f4a_7c15)
            });
            let noise = ((h >> 11) as f64 / (1u64 << 53) as f64 - 0.5) * 2e-6;
            let mut out = self.0.flow(x0, at_s)?;
            for p in &mut out {
                for v in p.iter_mut() {
                    *v += noise;
                }
            }
            Ok(out)
        }
    }
    let strict = ShootingOptions {
        fd_rel: 1e-3,
        tol: 1e-9,
        noise_floor: 1e-9,
        ..ShootingOptions::default()
    };
    let mut flow = Noisy(HopfNormalForm::supercritical(0.25));
    let e = shoot(&mut flow, &[0.45, 0.1, 0.05], 0.95, &strict).unwrap_err();
    assert!(
        e.contains("stalled") || e.contains("did not converge"),
        "{e}"
    );
    let floor = ShootingOptions {
        noise_floor: 1e-4,
        ..strict
    };
    let orbit = shoot(&mut flow, &[0.45, 0.1, 0.05], 0.95, &floor).unwrap();
    assert!(
        orbit.residual < 1e-4 && orbit.residual > 1e-9,
        "{}",
        orbit.residual
    );
    let r = orbit.x0[0].hypot(orbit.x0[1]);
    assert!((r - 0.5).abs() < 1e-3, "radius {r}");
}
