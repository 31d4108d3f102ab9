//! `airring runup --halt-film UM [--halt-speeds LO:HI]`: a run-up that ends where a film's minimum
//! thickness first falls below the limit within the speed range (what a design search needs to
//! know of a failing design), completed and halted, and the same series as the whole run up to
//! there; `--halt-whirl UM` the same where a whirl first grows beyond its limit. End to end on
//! the packed FMUs (`cargo xtask fmus` first).

mod common;

use common::airring;
use master::summary::{RunStatus, RunSummary};

/// Rows of a run's timeseries.csv: (time, speed [Hz], film_C.h_min, film_T.h_min).
fn rows(dir: &std::path::Path) -> Vec<(f64, f64, f64, f64)> {
    let csv = std::fs::read_to_string(dir.join("timeseries.csv")).unwrap();
    let mut lines = csv.lines();
    let header: Vec<&str> = lines.next().unwrap().split(',').collect();
    let col = |name: &str| {
        header
            .iter()
            .position(|h| h.split_whitespace().next() == Some(name))
            .unwrap()
    };
    let (w, c, t) = (col("rotor.omega"), col("film_C.h_min"), col("film_T.h_min"));
    lines
        .map(|l| {
            let v: Vec<f64> = l.split(',').map(|x| x.parse().unwrap()).collect();
            (v[0], v[w] / std::f64::consts::TAU, v[c], v[t])
        })
        .collect()
}

/// `airring BASE HALT --out OUT`, which must complete and halt: its summary and why it halted.
fn halted_run(base: &[&str], halt: &[&str], out: &std::path::Path) -> (RunSummary, String) {
    let (ok, err) = airring(&[base, halt, &["--out", out.to_str().unwrap()]].concat());
    assert!(ok, "a halted run-up is a success: {err}");
    let s = RunSummary::read(out).unwrap();
    assert_eq!(s.status, RunStatus::Completed);
    let why = s.halted.clone().expect("summary.json says where it halted");
    (s, why)
}

#[test]
fn a_run_up_halts_where_its_film_first_falls_below_the_limit() {
    let whole = common::tmp("halt", "whole");
    let halted = common::tmp("halt", "halted");
    let base = [
        "runup", "--f-max", "400", "--t-ramp", "0.05", "--mesh", "8x2", "--quiet",
    ];
    let (ok, err) = airring(&[&base[..], &["--out", whole.to_str().unwrap()]].concat());
    assert!(ok, "{err}");
    let all = rows(&whole);
    // The limit: a film thickness the whole run crosses part-way up, within 100-400 Hz.
    let in_range: Vec<_> = all.iter().filter(|r| r.1 >= 100.0).collect();
    let (hi, lo) = in_range
        .iter()
        .fold((0.0f64, f64::INFINITY), |(hi, lo), r| {
            (hi.max(r.2.max(r.3)), lo.min(r.2.min(r.3)))
        });
    assert!(lo < hi, "the films change with speed: {lo} .. {hi}");
    let limit_m = 0.5 * (lo + hi);
    let first = all
        .iter()
        .position(|r| r.1 >= 100.0 && r.2.min(r.3) < limit_m)
        .expect("the whole run crosses the limit");
    let limit_um = format!("{}", limit_m * 1e6);
    let (s, why) = halted_run(
        &base,
        &["--halt-film", &limit_um, "--halt-speeds", "100:400"],
        &halted,
    );
    assert!(why.starts_with("film_") && why.contains(" um < "), "{why}");
    // The same series up to the first sample below the limit, and nothing after it.
    let part = rows(&halted);
    assert_eq!(part.len(), first + 1, "{why}");
    for (a, b) in part.iter().zip(&all) {
        assert_eq!(a.0.to_bits(), b.0.to_bits());
        assert_eq!(
            (a.2.to_bits(), a.3.to_bits()),
            (b.2.to_bits(), b.3.to_bits())
        );
    }
    assert_eq!(s.t_end_s.unwrap().to_bits(), all[first].0.to_bits());
    assert!(s.t_end_s.unwrap() < 0.05 - 1e-9, "before the stop time");
    assert!(!halted.join("checkpoint").exists(), "nothing to resume");
    assert!(
        s.classification_note
            .as_deref()
            .unwrap_or("")
            .contains("halted"),
        "{:?}",
        s.classification_note
    );
    // Settings record the halt (a resume or a sweep reads them).
    assert_eq!(s.settings["halt_film_um"].as_f64(), Some(limit_m * 1e6));
    assert_eq!(
        s.settings["halt_speeds_hz"],
        serde_json::json!([100.0, 400.0])
    );
    let _ = std::fs::remove_dir_all(&whole);
    let _ = std::fs::remove_dir_all(&halted);
}

#[test]
fn bad_halt_flags_are_refused_before_anything_runs() {
    let out = common::tmp("halt", "refused");
    let o = out.to_str().unwrap();
    for (flags, why) in [
        (
            vec!["--halt-film", "-1"],
            "--halt-film = -1 um must be a finite number > 0",
        ),
        (vec!["--halt-film", "nan"], "--halt-film = NaN um"),
        (
            vec!["--halt-film", "5", "--halt-speeds", "900:100"],
            "--halt-speeds '900:100': expected LO:HI",
        ),
        (
            vec!["--halt-film", "5", "--halt-speeds", "x"],
            "--halt-speeds 'x'",
        ),
        (
            vec!["--halt-speeds", "1:2"],
            "needs --halt-film or --halt-whirl",
        ),
        (
            vec!["--halt-whirl", "0"],
            "--halt-whirl = 0 um must be a finite number > 0",
        ),
    ] {
        let (ok, err) = airring(&[&["runup", "--quiet", "--out", o][..], &flags[..]].concat());
        assert!(!ok && err.contains(why), "{flags:?}: {err}");
        assert!(!out.exists(), "{flags:?}: nothing written");
    }
}

/// `--halt-whirl UM`: the run-up ends with the first whirl window (40 ms every 20 ms, the
/// analysis' own) whose amplitude exceeds the limit within the speed range, at the sample that
/// completes that window; up to there it is the whole run, sample for sample, and the analysis
/// of what it recorded finds the amplitude that halted it.
#[test]
fn a_run_up_halts_where_its_whirl_first_exceeds_the_limit() {
    use master::analysis::classify::{WHIRL_HOP_S, WHIRL_WINDOW_S};
    use master::analysis::onset::{oscillation_track, window_samples};
    use master::analysis::{load_run, Bearing};
    let whole = common::tmp("halt", "whirl-whole");
    let halted = common::tmp("halt", "whirl-halted");
    // Path 1 whirls from about 740 Hz on; a quick ramp to 1000 Hz on a coarse mesh.
    let base = [
        "runup", "--preset", "path1", "--f-max", "1000", "--t-ramp", "1", "--mesh", "8x2",
        "--quiet",
    ];
    let (ok, err) = airring(&[&base[..], &["--out", whole.to_str().unwrap()]].concat());
    assert!(ok, "{err}");
    let cl = RunSummary::read(&whole).unwrap().clearance_um.unwrap();
    let series = load_run(&whole, [cl.c * 1e-6, cl.t * 1e-6]).unwrap();
    let spin = series.spin();
    let range = (600.0, 1000.0);
    let tracks: Vec<_> = [Bearing::C, Bearing::T]
        .into_iter()
        .map(|b| oscillation_track(&series, b, &spin, WHIRL_WINDOW_S, WHIRL_HOP_S))
        .collect();
    let in_range = |t: f64| (range.0..=range.1).contains(&series.speed_hz_at(t));
    let largest = tracks
        .iter()
        .flat_map(|k| k.t_s.iter().zip(&k.amp_m))
        .filter(|(t, _)| in_range(**t))
        .map(|(_, a)| *a)
        .fold(0.0, f64::max);
    assert!(largest > 2e-6, "the whole run whirls: {largest} m");
    let limit_m = 0.5 * largest;
    // The first window over the limit, by either bearing, and the sample that completes it.
    let (n_win, hop) = window_samples(&series, WHIRL_WINDOW_S, WHIRL_HOP_S);
    let k = (0..tracks[0].t_s.len())
        .find(|&k| in_range(tracks[0].t_s[k]) && tracks.iter().any(|tr| tr.amp_m[k] > limit_m))
        .expect("a window over the limit");
    let last = k * hop + n_win - 1;
    let limit_um = format!("{}", limit_m * 1e6);
    let (s, why) = halted_run(
        &base,
        &["--halt-whirl", &limit_um, "--halt-speeds", "600:1000"],
        &halted,
    );
    assert!(why.starts_with("whirl_") && why.contains(" um > "), "{why}");
    let part = rows(&halted);
    let all = rows(&whole);
    assert_eq!(part.len(), last + 1, "{why}");
    for (a, b) in part.iter().zip(&all) {
        assert_eq!(
            (a.0.to_bits(), a.1.to_bits()),
            (b.0.to_bits(), b.1.to_bits())
        );
    }
    assert_eq!(s.settings["halt_whirl_um"].as_f64(), Some(limit_m * 1e6));
    // What the halted run recorded shows the amplitude that halted it, and none before it.
    let series = load_run(&halted, [cl.c * 1e-6, cl.t * 1e-6]).unwrap();
    let spin = series.spin();
    let amps: Vec<f64> = [Bearing::C, Bearing::T]
        .into_iter()
        .map(|b| {
            let tr = oscillation_track(&series, b, &spin, WHIRL_WINDOW_S, WHIRL_HOP_S);
            assert_eq!(tr.amp_m.len(), k + 1);
            for j in 0..k {
                assert!(!in_range(tr.t_s[j]) || tr.amp_m[j] <= limit_m);
            }
            tr.amp_m[k]
        })
        .collect();
    assert!(
        amps.iter().any(|a| *a > limit_m),
        "{amps:?} against {limit_m}"
    );
    let _ = std::fs::remove_dir_all(&whole);
    let _ = std::fs::remove_dir_all(&halted);
}
