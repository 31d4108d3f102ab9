//! The orbit driver's and figure's own checks (the numerics' tests are in the periodic-orbits
//! crate).

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
