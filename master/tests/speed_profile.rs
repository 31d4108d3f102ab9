//! Speed profiles (issue #14 item 2): `airring runup --profile "T:F,..."` drives the rotor FMU's
//! speed table; bad tables are refused with a message and nothing written; a profile with a
//! run-down gives the hysteresis figure and the whirl's start and stop speeds. End to end on the
//! packed FMUs (`cargo xtask fmus` first).

mod common;

use common::airring;

/// The rotor's omega follows the table exactly (it is a rheonomic constraint, not a controller):
/// up at 250 kHz/s, down, then constant at the last point; the run stops at the profile's end
/// unless --stop says otherwise.
#[test]
fn the_rotor_speed_follows_the_table() {
    let dir = common::tmp("profile", "follows");
    let out = dir.to_str().unwrap();
    let (ok, err) = airring(&[
        "runup",
        "--profile",
        "0:0, 0.002:500, 0.003:200",
        "--stop",
        "0.004",
        "--mesh",
        "8x2",
        "--quiet",
        "--out",
        out,
    ]);
    assert!(ok, "{err}");
    assert!(
        err.contains("speed profile 0 Hz at 0 s, 500 Hz at 0.002 s"),
        "{err}"
    );
    let system = std::fs::read_to_string(dir.join("system.toml")).unwrap();
    assert!(system.contains("speed_table_points = 3"), "{system}");
    let csv = std::fs::read_to_string(dir.join("timeseries.csv")).unwrap();
    let header: Vec<&str> = csv.lines().next().unwrap().split(',').collect();
    let col = |name: &str| {
        header
            .iter()
            .position(|h| h.starts_with(&format!("{name} [")))
            .unwrap()
    };
    let (t_col, w_col) = (col("time"), col("rotor.omega"));
    let expected_hz = |t: f64| {
        if t <= 0.002 {
            500.0 * t / 0.002
        } else if t <= 0.003 {
            500.0 - 300.0 * (t - 0.002) / 0.001
        } else {
            200.0
        }
    };
    let mut n = 0;
    for line in csv.lines().skip(1) {
        let v: Vec<f64> = line.split(',').map(|x| x.parse().unwrap()).collect();
        let f = v[w_col] / std::f64::consts::TAU;
        assert!(
            (f - expected_hz(v[t_col])).abs() < 1e-6,
            "t {}: {f} Hz",
            v[t_col]
        );
        n += 1;
    }
    // One row per output interval from 0 to 4 ms, both ends included.
    let rows = (0.004 / (master::runup::DEFAULT_OUTPUT_INTERVAL_US * 1e-6)).round() as usize + 1;
    assert_eq!(n, rows, "{n} samples");
    let summary: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(dir.join("summary.json")).unwrap()).unwrap();
    assert_eq!(
        summary["settings"]["speed_profile"][1],
        serde_json::json!([0.002, 500.0])
    );
    // 500 -> 200 Hz is a run-down: the hysteresis entry (no whirl in 4 ms) and its figure.
    let h = &summary["hysteresis"];
    let from = h["run_down_from_s"].as_f64().unwrap();
    assert!((0.002..0.00202).contains(&from), "{h}");
    assert!(h["whirl_start_speed_hz"].is_null() && !h["persists_to_end"].as_bool().unwrap());
    let svg = std::fs::read_to_string(dir.join("hysteresis.svg")).unwrap();
    let bad = master::plot::layout::problems(&svg);
    assert!(bad.is_empty(), "{bad:#?}");
    assert_eq!(
        svg.matches(r#"class="series""#).count(),
        4,
        "C and T, up and down"
    );
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn bad_profiles_are_refused_with_a_message_and_nothing_written() {
    let dir = common::tmp("profile", "bad");
    let out = dir.to_str().unwrap();
    for (profile, extra, why) in [
        ("0:0,1.5", &[][..], "TIME_S:SPEED_HZ"),
        ("0:0,1.5:fast", &[][..], "'fast' is not a number"),
        ("0.5:0,1.5:100", &[][..], "t = 0"),
        ("0:0,1:100,0.5:200", &[][..], "increase"),
        ("0:0,1:-100", &[][..], ">= 0"),
        ("0:100", &[][..], "2 to 16"),
        ("0:0,1:100", &["--f-max", "500"][..], "replaces --f-max"),
    ] {
        let mut args = vec!["runup", "--profile", profile, "--quiet", "--out", out];
        args.extend_from_slice(extra);
        let (ok, err) = airring(&args);
        assert!(!ok && err.contains(why), "{profile}: {err}");
        assert!(!dir.exists(), "{profile}: the folder was created");
    }
}
