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

/// The bifurcation diagram draws the stable stretch solid and the unstable one dashed (one
/// series each per bearing), a cross per settled orbit, and no text overlaps.
#[test]
fn bifurcation_diagram_dashes_the_unstable_orbits() {
    use super::driver::{OrbitRecord, OrbitsReport};
    use crate::plot::Figure;
    let orbit = |speed_hz: f64, eps: f64, stable: bool, branch: &str| OrbitRecord {
        speed_hz,
        period_s: 6e-3,
        whirl_frequency_hz: 1.0 / 6e-3,
        max_eps_c: eps,
        max_eps_t: 1.2 * eps,
        whirl_amplitude_c: 0.5 * eps,
        whirl_amplitude_t: 0.6 * eps,
        h_min_c_um: 10.0,
        h_min_t_um: 8.0,
        floquet_multipliers: vec![[1.0, 0.0]],
        leading_multiplier: if stable { 0.9 } else { 1.1 },
        stable,
        stability_decided: true,
        branch: branch.into(),
        newton_iterations: 3,
        residual: 1e-7,
    };
    let report = OrbitsReport {
        preset: "test".into(),
        speeds_hz: vec![470.0, 520.0],
        settle_s: 1.0,
        shooting: "reduced".into(),
        linear_threshold_hz: Some(482.0),
        linear_note: None,
        settled: vec![],
        orbits: vec![
            orbit(520.0, 0.45, true, "settled"),
            orbit(510.0, 0.40, true, "continuation"),
            orbit(500.0, 0.30, true, "continuation"),
            orbit(495.0, 0.20, false, "continuation"),
            orbit(490.0, 0.10, false, "continuation"),
        ],
        hopf_estimate_hz: Some(486.0),
        criticality: Some("subcritical".into()),
        folds_hz: vec![],
        branch_end: None,
        flows: 0,
        macro_steps: 0,
        wall_time_s: 0.0,
    };
    let svg = super::figure::bifurcation_diagram(&report, None)
        .to_svg()
        .unwrap();
    let doc = roxmltree::Document::parse(&svg).unwrap();
    let series = |name: &str| {
        doc.descendants()
            .filter(|n| n.attribute("data-name") == Some(name))
            .collect::<Vec<_>>()
    };
    for b in ["C", "T"] {
        let stable = series(&format!("orbit max eps_{b} (stable)"));
        let unstable = series(&format!("orbit max eps_{b} (unstable)"));
        assert_eq!((stable.len(), unstable.len()), (1, 1), "bearing {b}");
        assert!(stable[0].attribute("stroke-dasharray").is_none());
        assert!(unstable[0].attribute("stroke-dasharray").is_some());
        assert_eq!(
            series(&format!("settled orbit eps_{b}")).len(),
            2,
            "one cross"
        );
    }
    let bad = crate::plot::layout::problems(&svg);
    assert!(bad.is_empty(), "{bad:#?}");
}

/// The settled whirl's period from its crossings of the mean: exact for one frequency, and a
/// second frequency (a quasi-periodic whirl) spreads the intervals beyond the 5 % the command
/// accepts as periodic.
#[test]
fn crossing_period_tells_a_periodic_from_a_quasi_periodic_whirl() {
    use super::driver::crossing_period;
    let ts: Vec<f64> = (0..20_000).map(|k| k as f64 * 20e-6).collect();
    let f = 148.0;
    let w = 2.0 * std::f64::consts::PI;
    let periodic: Vec<f64> = ts.iter().map(|t| 3e-6 + 1e-5 * (w * f * t).sin()).collect();
    let (period, spread) = crossing_period(&ts, &periodic).unwrap();
    assert!((period * f - 1.0).abs() < 1e-4, "period {period}");
    assert!(spread < 0.01, "spread {spread}");
    let quasi: Vec<f64> = ts
        .iter()
        .map(|t| 1e-5 * (w * f * t).sin() + 0.6e-5 * (w * 0.37 * f * t).sin())
        .collect();
    let (_, spread) = crossing_period(&ts, &quasi).unwrap();
    assert!(spread > 0.05, "spread {spread}");
    let flat = vec![1.0; 100];
    assert!(crossing_period(&ts[..100], &flat).is_none());
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

/// The orbit flows' steps towards a target: the summed time of 36 000 steps of 20 us drifts
/// from k H by ~1e-13 s, and that rest was once taken as a step of its own (1.2e-13 s, then
/// 2.0e-14 s: below the rotor's smallest step, which failed). No step is shorter than a
/// millionth of the macro step unless the target asks for it, and every target is reached to
/// rounding.
#[test]
fn flows_never_take_rounding_as_a_step() {
    use super::cosim_flow::grid_step;
    let h = 20e-6;
    let mut t = 0.0_f64;
    let mut smallest = f64::INFINITY;
    for target in [0.72, 0.7364, 0.82, 1.0, 1.0 + 0.5 * h, 1.37] {
        while let Some(step) = grid_step(target - t, h) {
            smallest = smallest.min(step);
            t += step;
        }
        assert!((t - target).abs() <= 1e-6 * h, "{t} vs {target}");
    }
    // The only short step is the half step the target 1.0 + H/2 asks for.
    assert!((smallest - 0.5 * h).abs() < 1e-9 * h, "{smallest}");
    assert_eq!(grid_step(3e-14, h), None);
    assert_eq!(grid_step(h + 1e-13, h), Some(h + 1e-13));
    assert_eq!(grid_step(2.5 * h, h), Some(h));
}

/// `--settle` must leave five periods of the threshold's whirl in its last tenth: at 190 Hz
/// that is 0.263 s, asked for as 0.27 s.
#[test]
fn a_settle_too_short_for_five_whirl_periods_is_refused() {
    use super::driver::check_settle_holds_whirl;
    assert!(check_settle_holds_whirl(1.0, 190.0).is_ok());
    assert!(check_settle_holds_whirl(50.0 / 190.0 * (1.0 + 1e-12), 190.0).is_ok());
    let e = check_settle_holds_whirl(0.1, 190.0).unwrap_err();
    assert!(
        e.contains("--settle 0.1 s is too short")
            && e.contains("(10 ms)")
            && e.contains("190.0 Hz, 5.3 ms each")
            && e.contains("--settle 0.27 s or more"),
        "{e}"
    );
}
