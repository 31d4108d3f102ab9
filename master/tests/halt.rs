//! `airring runup --halt-film UM [--halt-speeds LO:HI]`: a run-up that ends where a film's minimum
//! thickness first falls below the limit within the speed range (what a design search needs to
//! know of a failing design), completed and halted, and the same series as the whole run up to
//! there. End to end on the packed FMUs (`cargo xtask fmus` first).

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
    let (ok, err) = airring(
        &[
            &base[..],
            &["--halt-film", &limit_um, "--halt-speeds", "100:400"],
            &["--out", halted.to_str().unwrap()],
        ]
        .concat(),
    );
    assert!(ok, "a halted run-up is a success: {err}");
    let s = RunSummary::read(&halted).unwrap();
    assert_eq!(s.status, RunStatus::Completed);
    let why = s.halted.clone().expect("summary.json says where it halted");
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
        (vec!["--halt-speeds", "1:2"], "--halt-film"),
    ] {
        let (ok, err) = airring(&[&["runup", "--quiet", "--out", o][..], &flags[..]].concat());
        assert!(!ok && err.contains(why), "{flags:?}: {err}");
        assert!(!out.exists(), "{flags:?}: nothing written");
    }
}
