//! Calm macro steps (`master::calm_steps`): the window the linear analysis gives ends where the
//! least damped mode falls to a damping ratio of 0.02, before the threshold of instability;
//! a design that is stable throughout is calm to the end; a journal resting on its ring never is.
//! End to end: the run-up writes the plan into its system file and summary, and refuses a calm
//! step that is no multiple of the macro step.

mod common;

use common::airring;
use master::calm_steps::{plan, CALM_DAMPING_RATIO};
use master::runup::RunupSettings;

fn settings(preset: &str, edit: impl Fn(&mut RunupSettings)) -> RunupSettings {
    let mut s = RunupSettings::preset(preset).unwrap();
    edit(&mut s);
    s.validate().unwrap();
    s
}

/// Path 1 (0 -> 2000 Hz in 3 s): 666.7 Hz per second.
fn path1_speed_hz(t: f64) -> f64 {
    2000.0 * t / 3.0
}

#[test]
fn path_1_is_calm_until_its_least_damped_mode_falls_to_two_percent() {
    let s = settings("path1", |_| {});
    let p = plan(&s, None);
    assert!(p.note.is_none(), "{:?}", p.note);
    assert_eq!(p.windows_s.len(), 1, "{p:?}");
    let (a, b) = p.windows_s[0];
    // From the first grid speed (50 Hz, 75 ms) on.
    assert!((path1_speed_hz(a) - 50.0).abs() < 1.0, "{a}");
    // At the end the damping interpolated on the grid is 0.02 (to the window's 1 ms), and the
    // grid speed after it is below 0.02.
    let f_end = path1_speed_hz(b);
    let i = p.least_damping.partition_point(|&(f, _)| f <= f_end);
    let (f0, z0) = p.least_damping[i - 1];
    let (f1, z1) = p.least_damping[i];
    let (z0, z1) = (z0.unwrap(), z1.unwrap());
    let z_end = z0 + (f_end - f0) / (f1 - f0) * (z1 - z0);
    assert!(
        z_end >= CALM_DAMPING_RATIO && z1 < CALM_DAMPING_RATIO,
        "{z_end} {z1}"
    );
    let dz_per_hz = (z1 - z0) / (f1 - f0);
    assert!(z_end - CALM_DAMPING_RATIO <= -dz_per_hz * 0.7, "{z_end}");
    // The linear threshold of instability (full mesh, docs/stability.md: 472.9 Hz) lies more than
    // 40 Hz (60 ms) beyond the window: 49 Hz at the threshold 0.02 (124 Hz at 0.05).
    let stab = master::stability::analyse(&s, &[400.0, 450.0, 500.0]).unwrap();
    let threshold = stab.threshold.expect("path 1 is unstable").speed_hz;
    assert!(
        threshold - f_end > 40.0,
        "window ends at {f_end} Hz, threshold {threshold} Hz"
    );
}

#[test]
fn a_design_stable_throughout_is_calm_to_the_end() {
    let s = settings("path1", |s| {
        (s.clearance_um, s.dh_um, s.d_n_s_per_m) = (10.0, 20.0, 500.0);
    });
    let p = plan(&s, None);
    assert_eq!(p.windows_s.len(), 1, "{p:?}");
    assert_eq!(p.windows_s[0].1, s.stop_time_s);
    assert!(p
        .least_damping
        .iter()
        .all(|(_, z)| z.is_some_and(|z| z >= CALM_DAMPING_RATIO)));
}

#[test]
fn a_journal_riding_on_its_ring_closes_the_calm_window_at_once() {
    // dH = 0: the run-up whirls on its rings from ~7 Hz (docs/results-section4.md), but the linear model
    // finds equilibria damped by 2 % or more up to 120 Hz (the window 0.076-0.160 s at either
    // d); the run closes that window at its first rejected step.
    for (d, plan_end_s) in [("50", 0.160), ("500", 0.161)] {
        let s = settings("path1", |s| {
            (s.clearance_um, s.dh_um, s.d_n_s_per_m) = (15.0, 0.0, d.parse().unwrap());
        });
        let planned = plan(&s, None).windows_s;
        assert!(
            planned.len() == 1 && (planned[0].1 - plan_end_s).abs() < 2e-3,
            "d = {d}: {planned:?}"
        );
        let dir = common::tmp("calm", &format!("ring{d}"));
        let out = dir.to_str().unwrap();
        let (ok, err) = airring(&[
            "runup",
            "--clearance",
            "15",
            "--dh",
            "0",
            "--c",
            "1000",
            "--d",
            d,
            "--stop",
            "0.12",
            "--serial-films",
            "--quiet",
            "--out",
            out,
        ]);
        assert!(ok, "{err}");
        assert!(
            err.contains("calm macro steps of 100 us from 0.076 s"),
            "{err}"
        );
        let summary: serde_json::Value =
            serde_json::from_str(&std::fs::read_to_string(dir.join("summary.json")).unwrap())
                .unwrap();
        let closed = summary["calm_window_closed_at_s"][0]
            .as_f64()
            .expect("closed");
        assert!((0.076..0.09).contains(&closed), "d = {d}: {summary}");
        assert!(
            summary["long_macro_steps"].as_u64().unwrap() < 100,
            "d = {d}: {summary}"
        );
        let _ = std::fs::remove_dir_all(&dir);
    }
}

#[test]
fn the_run_up_writes_its_plan_and_refuses_a_calm_step_that_does_not_fit() {
    let dir = common::tmp("calm", "plan");
    let out = dir.to_str().unwrap();
    let args = [
        "runup",
        "--c",
        "1000",
        "--d",
        "500",
        "--clearance",
        "10",
        "--dh",
        "20",
        "--mesh",
        "8x2",
        "--stop",
        "0.2",
        "--serial-films",
        "--quiet",
        "--out",
        out,
    ];
    let (ok, err) = airring(&args);
    assert!(ok, "{err}");
    assert!(
        err.contains("calm macro steps of 100 us from 0.076 s to 0.200 s"),
        "{err}"
    );
    let system = std::fs::read_to_string(dir.join("system.toml")).unwrap();
    assert!(
        system.contains("[algorithm.long_steps]") && system.contains("factor = 2"),
        "{system}"
    );
    let summary: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(dir.join("summary.json")).unwrap()).unwrap();
    // 0.076 s to 0.2 s: 1240 steps of 100 us; 1520 of 50 us before them.
    assert_eq!(summary["long_macro_steps"], 1240, "{summary}");
    assert_eq!(summary["macro_steps"], 1520 + 1240);
    assert_eq!(summary["settings"]["calm_macro_step_us"], 100.0);
    let rows = std::fs::read_to_string(dir.join("timeseries.csv"))
        .unwrap()
        .lines()
        .count();
    assert_eq!(rows, 1 + 4001, "a row every 50 us, as without calm steps");

    let (ok, err) = airring(&[&args[..], &["--overwrite", "--calm-macro-step", "off"]].concat());
    assert!(ok, "{err}");
    assert!(!std::fs::read_to_string(dir.join("system.toml"))
        .unwrap()
        .contains("long_steps"));

    let (ok, err) = airring(&[&args[..], &["--overwrite", "--calm-macro-step", "75"]].concat());
    assert!(
        !ok && err.contains("--calm-macro-step = 75 us must be a multiple"),
        "{err}"
    );
    let _ = std::fs::remove_dir_all(&dir);
}
