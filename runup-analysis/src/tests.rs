//! Classification tests on synthetic run-ups (see `synth`). Each case is built to carry exactly the signature
//! the paper describes for its path, so a change of a threshold or of the onset logic that breaks the
//! separation fails here.

use super::synth::{add_whirl, base, hopf_amp, speed_hz, C_M};
use super::*;

const DT_S: f64 = 5e-5;
const T_END_S: f64 = 3.0;

fn assert_onset(cl: &Classification, expect_s: f64, rel_tol: f64) {
    let t = cl
        .onset_time_s
        .unwrap_or_else(|| panic!("no onset: {}", cl.criteria));
    assert!(
        (t - expect_s).abs() <= rel_tol * expect_s,
        "onset {t} s, expected {expect_s} s: {}",
        cl.criteria
    );
    let f = cl.onset_speed_hz.unwrap();
    assert!((f - speed_hz(t)).abs() < 1.0, "onset speed {f} Hz at {t} s");
}

#[test]
fn stable_run_has_no_onset() {
    let s = base(DT_S, T_END_S);
    let cl = classify(&s);
    assert_eq!(cl.class, RunClass::Stable, "{}", cl.criteria);
    assert_eq!(cl.onset_time_s, None);
    assert_eq!(cl.first_bearing, None);
    assert!(cl.whirl.is_empty());
    // Start-up (eps ~ 1.3 while settling at standstill) is not in the maxima; the operating sag at 10% of
    // top speed (200 Hz: 1.1 * (0.2 + 0.7 exp(-2/3)) = 0.61) is.
    assert!(
        (cl.max_eps_c - 0.615).abs() < 0.02,
        "max eps C {}",
        cl.max_eps_c
    );
    assert!(cl.criteria.starts_with("stable"));
}

#[test]
fn imbalance_response_is_not_an_onset() {
    // A 1x response of 0.3 C (forced, not self-excited) must not count as a whirl.
    let mut s = base(DT_S, T_END_S);
    let spin = s.spin_angle_rad();
    for i in 0..s.len() {
        s.dx_c_m[i] += 0.3 * C_M * spin[i].cos();
        s.dy_c_m[i] += 0.3 * C_M * spin[i].sin();
    }
    let cl = classify(&s);
    assert_eq!(cl.class, RunClass::Stable, "{}", cl.criteria);
}

/// Paper 3.1: onset 1150 ms (767 Hz), turbine side first at ~0.45x onset speed, compressor side from 1350 ms
/// with its own frequency, synchronisation jump at 2100 ms, large amplitudes, frequencies then roughly locked.
fn path1_run() -> RunSeries {
    let mut s = base(DT_S, T_END_S);
    let f_t = |t: f64| if t < 2.1 { 345.0 } else { 420.0 };
    add_whirl(
        &mut s,
        Bearing::T,
        1.15,
        hopf_amp(1.15, 0.8 * C_M, 0.15),
        f_t,
    );
    // The rigid rotor carries a share of the turbine-side whirl to the compressor journal.
    add_whirl(
        &mut s,
        Bearing::C,
        1.15,
        hopf_amp(1.15, 0.03 * C_M, 0.15),
        f_t,
    );
    add_whirl(
        &mut s,
        Bearing::C,
        1.35,
        hopf_amp(1.35, 0.7 * C_M, 0.15),
        |t| 420.0 + 10.0 * (t - 1.35),
    );
    s
}

#[test]
fn path1_large_turbine_first_two_frequencies() {
    let cl = classify(&path1_run());
    assert_eq!(cl.class, RunClass::Path1, "{}", cl.criteria);
    assert_onset(&cl, 1.15, 0.02);
    assert_eq!(cl.first_bearing.as_deref(), Some("T"));
    // The reported whirl frequencies follow the construction.
    let at = |t: f64| {
        cl.whirl
            .iter()
            .min_by(|a, b| (a.t_s - t).abs().total_cmp(&(b.t_s - t).abs()))
            .unwrap()
    };
    assert!((at(1.6).f_t_hz - 345.0).abs() < 5.0, "{:?}", at(1.6));
    assert!((at(1.6).f_c_hz - 422.5).abs() < 5.0, "{:?}", at(1.6));
    assert!((at(2.5).f_t_hz - 420.0).abs() < 5.0, "{:?}", at(2.5));
    assert!(
        (at(1.6).amp_t_m - 0.8 * C_M).abs() < 0.05 * C_M,
        "{:?}",
        at(1.6)
    );
}

#[test]
fn path1_by_amplitude_alone_with_one_locked_frequency() {
    // Large whirl at a locked 0.45x-of-onset-speed frequency at both bearings: large, not proportional.
    let mut s = base(DT_S, T_END_S);
    for b in Bearing::BOTH {
        add_whirl(&mut s, b, 1.15, hopf_amp(1.15, 0.8 * C_M, 0.1), |_| {
            0.45 * 767.0
        });
    }
    let cl = classify(&s);
    assert_eq!(cl.class, RunClass::Path1, "{}", cl.criteria);
    assert_onset(&cl, 1.15, 0.02);
}

/// Paper 3.2: onset ~2000 ms, moderate amplitude, one common frequency.
fn path2a_run(amp_rel: f64) -> RunSeries {
    let mut s = base(DT_S, T_END_S);
    // A mode-locked whirl whose frequency stiffens a little with speed (elasticity ~ 0.2).
    let f = |t: f64| 430.0 * (speed_hz(t) / 1333.0).powf(0.2);
    add_whirl(
        &mut s,
        Bearing::C,
        2.0,
        hopf_amp(2.0, amp_rel * C_M, 0.1),
        f,
    );
    add_whirl(
        &mut s,
        Bearing::T,
        2.0,
        hopf_amp(2.0, 0.8 * amp_rel * C_M, 0.1),
        f,
    );
    s
}

#[test]
fn path2a_moderate_common_frequency() {
    let cl = classify(&path2a_run(0.2));
    assert_eq!(cl.class, RunClass::Path2a, "{}", cl.criteria);
    assert_onset(&cl, 2.0, 0.02);
    assert_eq!(cl.first_bearing.as_deref(), Some("C"));
    let last = cl.whirl.last().unwrap();
    assert!((last.f_c_hz - last.f_t_hz).abs() < 3.0, "{last:?}");
}

#[test]
fn threshold_is_sharp_between_path2a_and_path1() {
    // The same whirl at 0.35 C is harmless (2a); at 0.65 C it is "very large" (path 1).
    assert_eq!(classify(&path2a_run(0.35)).class, RunClass::Path2a);
    assert_eq!(classify(&path2a_run(0.65)).class, RunClass::Path1);
}

#[test]
fn path2b_growing_eccentricity_speed_proportional_whirl() {
    // Paper 3.3: onset 2050 ms, whirl at ~0.4x speed (rising linearly with speed), nearly equal at both
    // bearings, eccentricities rising to critical levels as the speed rises.
    let mut s = base(DT_S, T_END_S);
    let amp = |t: f64| {
        C_M * (0.1 + 0.9 * ((t - 2.05) / 0.9).clamp(0.0, 1.0))
            * ((t - 2.05) / 0.05).clamp(0.0, 1.0).sqrt()
    };
    add_whirl(&mut s, Bearing::T, 2.05, amp, |t| 0.40 * speed_hz(t));
    add_whirl(&mut s, Bearing::C, 2.05, amp, |t| 0.41 * speed_hz(t));
    let cl = classify(&s);
    assert_eq!(cl.class, RunClass::Path2b, "{}", cl.criteria);
    assert_onset(&cl, 2.05, 0.02);
    assert!(cl.max_eps_c > 1.0 && cl.max_eps_t > 1.0);
}

#[test]
fn onset_at_low_speed() {
    // Whirl from 0.15 s (100 Hz, 5% of top speed): the bearings never stabilise the rotor.
    let mut s = base(DT_S, T_END_S);
    add_whirl(
        &mut s,
        Bearing::C,
        0.15,
        hopf_amp(0.15, 0.3 * C_M, 0.05),
        |_| 60.0,
    );
    let cl = classify(&s);
    assert_eq!(cl.class, RunClass::UnstableLowSpeed, "{}", cl.criteria);
    assert_onset(&cl, 0.15, 0.05);
}

#[test]
fn start_up_oscillation_that_never_decays_is_low_speed_instability() {
    let mut s = base(DT_S, 1.0);
    add_whirl(&mut s, Bearing::T, 0.0, |_| 0.2 * C_M, |_| 80.0);
    let cl = classify(&s);
    assert_eq!(cl.class, RunClass::UnstableLowSpeed, "{}", cl.criteria);
    assert!(cl.onset_time_s.unwrap() < 0.02);
}

#[test]
fn class_names_serialize_as_in_summary_json() {
    let names: Vec<String> = [
        RunClass::Stable,
        RunClass::Path1,
        RunClass::Path2a,
        RunClass::Path2b,
        RunClass::UnstableLowSpeed,
    ]
    .iter()
    .map(|c| {
        let j = serde_json::to_string(c).unwrap();
        assert_eq!(j, format!("\"{}\"", c.as_str()));
        j
    })
    .collect();
    assert_eq!(
        names.join(","),
        r#""stable","path1","path2a","path2b","unstable_low_speed""#
    );
    let back: RunClass = serde_json::from_str("\"path2b\"").unwrap();
    assert_eq!(back, RunClass::Path2b);
}

#[test]
fn onset_detector_reads_a_clean_sqrt_growth() {
    // Unit check of the onset module on its own: a whirl growing as sqrt(t - 0.5) to 0.5 C in 0.1 s crosses
    // 0.02 C at 0.5 + 0.1 * 0.04^2 = 0.50016 s.
    let mut s = base(DT_S, 1.0);
    add_whirl(
        &mut s,
        Bearing::C,
        0.5,
        hopf_amp(0.5, 0.5 * C_M, 0.1),
        |_| 300.0,
    );
    let spin = s.spin();
    let tr = onset::oscillation_track(&s, Bearing::C, &spin, onset::AMP_WINDOW_S, onset::AMP_HOP_S);
    let t = onset::sustained_onset(
        &tr,
        onset::ONSET_AMP_REL * C_M,
        onset::MIN_PERSIST_S,
        onset::GAP_BRIDGE_S,
    )
    .unwrap();
    // The window is 20 ms long: its RMS sees the growth up to 10 ms early.
    assert!((t - 0.5).abs() < 0.012, "onset {t}");
}

fn criterion<'a>(cl: &'a Classification, name_start: &str) -> &'a classify::Criterion {
    cl.margins
        .iter()
        .find(|c| c.name.starts_with(name_start))
        .unwrap_or_else(|| panic!("no criterion '{name_start}' in {:?}", cl.margins))
}

/// Margins: every criterion reports value, bound and relative margin; those whose crossing alone
/// would change the class are marked deciding; a deciding margin under 10 % makes the class
/// borderline. The path-2a whirl at 0.48 C (the path2a preset's amplitude, 4 % under the path-1
/// bound) is borderline; at 0.2 C it is not.
#[test]
fn margins_mark_a_class_close_to_its_neighbour_as_borderline() {
    let near = classify(&path2a_run(0.48));
    assert_eq!(near.class, RunClass::Path2a, "{}", near.criteria);
    let amp = criterion(&near, "whirl amplitude");
    assert!(
        amp.deciding && amp.bound == classify::LARGE_WHIRL_AMP_REL,
        "{amp:?}"
    );
    let m = amp.margin.unwrap();
    assert!((-0.10..0.0).contains(&m), "{amp:?}");
    assert!(near.borderline);

    let far = classify(&path2a_run(0.2));
    assert_eq!(far.class, RunClass::Path2a);
    assert!(!far.borderline, "{:?}", far.margins);
    // For path 2a: a larger amplitude, eccentricity or a second frequency would make it path 1
    // (deciding); a speed-proportional frequency alone would not (still moderate: 2a).
    assert!(criterion(&far, "whirl amplitude").deciding);
    assert!(criterion(&far, "eccentricity after onset").deciding);
    assert!(criterion(&far, "share of whirl windows").deciding);
    assert!(!criterion(&far, "whirl-frequency elasticity").deciding);
    assert!(criterion(&far, "onset speed").deciding);
    for c in &far.margins {
        if let (Some(v), Some(m)) = (c.value, c.margin) {
            assert!((m - (v - c.bound) / c.bound).abs() < 1e-12, "{c:?}");
        }
    }
}

/// A stable run reports its largest oscillation against the onset threshold; the class serializes
/// with its margins (summary.json, `airring classify`).
#[test]
fn a_stable_run_has_its_amplitude_margin() {
    let cl = classify(&base(DT_S, T_END_S));
    assert_eq!(cl.class, RunClass::Stable);
    let c = criterion(&cl, "oscillation amplitude after start-up");
    assert!(
        c.deciding && c.bound == onset::ONSET_AMP_REL && c.margin.unwrap() < -0.1,
        "{c:?}"
    );
    assert!(!cl.borderline);
    let json = serde_json::to_value(&cl).unwrap();
    assert_eq!(json["borderline"], false);
    assert!(json["margins"][0]["bound"].as_f64().is_some());
}

/// The bounds reach the decision: the 0.48 C path-2a whirl turns path 1 when the amplitude bound
/// moves down by 20 % (0.4 C), and stays 2a when it moves up; the default bounds give `classify`.
#[test]
fn moved_bounds_move_the_class() {
    let s = path2a_run(0.48);
    let b = classify::Bounds::default();
    assert_eq!(classify_with_default_is_classify(&s), RunClass::Path2a);
    let down = b.scaled("large_whirl_amp_rel", 0.8).unwrap();
    let up = b.scaled("large_whirl_amp_rel", 1.2).unwrap();
    assert_eq!(classify::classify_with(&s, &down).class, RunClass::Path1);
    assert_eq!(classify::classify_with(&s, &up).class, RunClass::Path2a);
    // A lower onset threshold finds the same whirl no later.
    let early = classify::classify_with(&s, &b.scaled("onset_amp_rel", 0.8).unwrap());
    assert!(early.onset_time_s.unwrap() <= classify(&s).onset_time_s.unwrap());
}

fn classify_with_default_is_classify(s: &RunSeries) -> RunClass {
    let a = classify::classify_with(s, &classify::Bounds::default());
    assert_eq!(a, classify(s));
    a.class
}

/// A run of a handful of rows (a run-up stopped after a few output intervals) is `too_short`,
/// never unclassified and never a panic: `run.rs` once classified only runs of more than 16
/// rows and left shorter ones with `classification: null`.
#[test]
fn a_run_of_a_few_rows_is_too_short() {
    for rows in 1..=20 {
        let s = base(50e-6, (rows - 1) as f64 * 50e-6);
        assert_eq!(s.len(), rows);
        let cl = classify(&s);
        assert_eq!(cl.class, RunClass::TooShort, "{rows} rows: {}", cl.criteria);
        assert!(
            cl.max_eps_c.is_finite() && cl.max_eps_t.is_finite(),
            "{rows} rows"
        );
    }
}
