//! The orbit classes of a study cell (`study.rs`): the decision on synthetic settled whirls,
//! the speeds, and the run-up table it is compared with.

use super::driver::SettledRecord;
use super::study::{cell_speeds, orbit_class, read_classes};
use crate::analysis::classify::Bounds;

fn whirl(speed_hz: f64, motion: &str, eps: f64, rms: f64, f_hz: f64) -> SettledRecord {
    SettledRecord {
        speed_hz,
        motion: motion.into(),
        max_eps_c: Some(0.8 * eps),
        max_eps_t: Some(eps),
        whirl_frequency_hz: Some(f_hz),
        bearing_whirl_frequencies_hz: Some([f_hz, f_hz]),
        whirl_rms_c: Some(rms),
        whirl_rms_t: Some(0.5 * rms),
        period_spread: Some(1e-4),
        message: None,
    }
}

fn class(threshold: Option<f64>, settled: &[SettledRecord]) -> String {
    orbit_class(threshold, 2000.0, settled, &[], &Bounds::default()).class
}

#[test]
fn the_threshold_alone_decides_stable_and_low_speed_cells() {
    assert_eq!(class(None, &[]), "stable");
    assert_eq!(class(Some(137.7), &[]), "unstable_low_speed");
    // 10 % of 2000 Hz is the bound: just above it the cell needs its whirls.
    assert_eq!(class(Some(201.0), &[]), "undecided");
}

#[test]
fn a_moderate_whirl_locked_to_a_mode_is_path_2a() {
    // 150 Hz at 550 Hz, 160 Hz at 2000 Hz: elasticity ln(160/150)/ln(2000/550) = 0.050.
    let s = [
        whirl(550.0, "periodic", 0.6, 0.3, 150.0),
        whirl(2000.0, "periodic", 0.7, 0.4, 160.0),
    ];
    let oc = orbit_class(Some(500.0), 2000.0, &s, &[], &Bounds::default());
    assert_eq!(oc.class, "path2a", "{}", oc.why);
    assert!(!oc.borderline, "{oc:?}");
    let e = oc.elasticity.unwrap();
    assert!((e - (160.0_f64 / 150.0).ln() / (2000.0_f64 / 550.0).ln()).abs() < 1e-12);
}

#[test]
fn a_large_whirl_is_path_1_and_path_2b_when_its_frequency_follows_the_speed() {
    let locked = [
        whirl(550.0, "periodic", 1.2, 0.6, 150.0),
        whirl(2000.0, "periodic", 1.3, 0.7, 170.0),
    ];
    assert_eq!(class(Some(500.0), &locked), "path1");
    // The whirl frequency proportional to the speed (elasticity 1): path 2b.
    let proportional = [
        whirl(550.0, "periodic", 0.4, 0.2, 250.0),
        whirl(2000.0, "periodic", 1.1, 0.4, 250.0 * 2000.0 / 550.0),
    ];
    assert_eq!(class(Some(500.0), &proportional), "path2b");
    // Proportional but moderate at both speeds: still path 2a (large decides 2b, as in a run-up).
    let moderate = [
        whirl(550.0, "periodic", 0.4, 0.2, 250.0),
        whirl(2000.0, "periodic", 0.6, 0.3, 250.0 * 2000.0 / 550.0),
    ];
    assert_eq!(class(Some(500.0), &moderate), "path2a");
}

#[test]
fn two_frequencies_make_path_1_and_the_bounds_are_those_of_the_run_up_classifier() {
    // The bearings whirling at 150 and 170 Hz (13 % apart): two frequencies.
    let mut split = [
        whirl(550.0, "quasi-periodic", 0.5, 0.2, 150.0),
        whirl(2000.0, "periodic", 0.6, 0.3, 155.0),
    ];
    split[0].bearing_whirl_frequencies_hz = Some([150.0, 170.0]);
    assert_eq!(class(Some(500.0), &split), "path1");
    // 4 % apart, or a spread of one whirl's periods alone (quasi-periodic), is not.
    split[0].bearing_whirl_frequencies_hz = Some([150.0, 156.0]);
    assert_eq!(class(Some(500.0), &split), "path2a");
    // The whirl amplitude bound 0.5 C is exclusive, like the classifier's.
    let at = |rms: f64| {
        [
            whirl(550.0, "periodic", 0.5, rms, 150.0),
            whirl(2000.0, "periodic", 0.5, 0.1, 150.0),
        ]
    };
    assert_eq!(class(Some(500.0), &at(0.49)), "path2a");
    assert_eq!(class(Some(500.0), &at(0.51)), "path1");
    // Moving the bound up by 20 % moves the cell back (as `airring sweep-sensitivity` does).
    let b = Bounds::default()
        .scaled("large_whirl_amp_rel", 1.2)
        .unwrap();
    assert_eq!(
        orbit_class(Some(500.0), 2000.0, &at(0.51), &[], &b).class,
        "path2a"
    );
    // Both sides of the bound within 10 %: borderline; 0.6 C (20 % over) is not.
    let d = Bounds::default();
    assert!(orbit_class(Some(500.0), 2000.0, &at(0.49), &[], &d).borderline);
    assert!(orbit_class(Some(500.0), 2000.0, &at(0.51), &[], &d).borderline);
    assert!(!orbit_class(Some(500.0), 2000.0, &at(0.6), &[], &d).borderline);
    // Eccentricity above 1 alone is large.
    let grazing = [whirl(550.0, "periodic", 1.01, 0.3, 150.0)];
    assert_eq!(class(Some(500.0), &grazing), "path1");
}

#[test]
fn a_speed_without_a_settled_whirl_leaves_the_cell_undecided_and_names_it() {
    let mut s = [
        whirl(550.0, "periodic", 0.5, 0.2, 150.0),
        whirl(2000.0, "decaying", 0.5, 0.2, 150.0),
    ];
    s[1].message = Some("the whirl shrinks by 9 %".into());
    let oc = orbit_class(Some(500.0), 2000.0, &s, &[], &Bounds::default());
    let (c, why) = (oc.class, oc.why);
    assert_eq!(c, "undecided");
    assert!(
        why.contains("2000.0 Hz") && why.contains("decaying") && why.contains("9 %"),
        "{why}"
    );
    s[1].motion = "failed".into();
    assert_eq!(class(Some(500.0), &s), "undecided");
    // At rest where the linear analysis finds the equilibrium stable again (a closed unstable
    // band): no whirl there, and the moderate whirl below decides. Still growing there
    // (linearly unstable) leaves the cell open.
    s[1].motion = "equilibrium".into();
    let d = Bounds::default();
    let oc = orbit_class(Some(500.0), 2000.0, &s, &[25.0, -3.0], &d);
    assert_eq!(oc.class, "path2a", "{}", oc.why);
    assert!(
        oc.why.contains("stable again at 2000 Hz") && oc.elasticity.is_none(),
        "{oc:?}"
    );
    assert_eq!(
        orbit_class(Some(500.0), 2000.0, &s, &[25.0, 3.0], &d).class,
        "undecided"
    );
    s[0].motion = "decaying".into();
    let oc = orbit_class(Some(500.0), 2000.0, &s, &[-1.0, -3.0], &d);
    assert_eq!(oc.class, "stable", "{}", oc.why);
}

#[test]
fn the_speeds_lie_past_the_threshold_and_at_the_top() {
    assert_eq!(cell_speeds(500.0, 2000.0, 0.1), vec![550.0, 2000.0]);
    assert_eq!(cell_speeds(774.4, 2000.0, 0.1), vec![851.8, 2000.0]);
    // Within 5 % of the top: the top speed alone.
    assert_eq!(cell_speeds(1800.0, 2000.0, 0.1), vec![1980.0]);
    assert_eq!(cell_speeds(1950.0, 2000.0, 0.1), vec![2000.0]);
}

#[test]
fn the_run_up_table_is_read_by_its_header_and_a_wrong_file_is_named() {
    let dir = std::env::temp_dir().join(format!("airring-orbit-classes-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let ok = dir.join("study.csv");
    std::fs::write(
        &ok,
        "run,note [1],status,classification,onset_time [s]\n\
         C10_dH20,\"a, b\",completed,stable,\n\
         C30_dH60,x,completed,path2a,1.81\n",
    )
    .unwrap();
    let m = read_classes(&ok).unwrap();
    assert_eq!(m.len(), 2);
    assert_eq!(m["C10_dH20"], "stable");
    assert_eq!(m["C30_dH60"], "path2a");
    let bad = dir.join("other.csv");
    std::fs::write(&bad, "name,class\nA,stable\n").unwrap();
    let e = read_classes(&bad).unwrap_err();
    assert!(e.contains("other.csv") && e.contains("'run'"), "{e}");
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn settled_records_of_earlier_versions_still_read() {
    let old = r#"{"speed_hz": 520.0, "motion": "periodic", "max_eps_C": 0.44, "max_eps_T": 0.73,
        "whirl_frequency_hz": 148.0, "period_spread": 1e-5, "message": null}"#;
    let r: SettledRecord = serde_json::from_str(old).unwrap();
    assert_eq!(r.whirl_rms_c, None);
    assert_eq!(r.whirl_rms_t, None);
    assert_eq!(r.bearing_whirl_frequencies_hz, None);
}
