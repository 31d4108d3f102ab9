//! Classes, margins and the borderline flag on recorded run-ups (issue #14 item 1): the three
//! Section 3 presets as the co-simulation computed them (full 3 s run-ups at the defaults, every
//! 10th output sample: 500 us, 6 significant digits; tests/data/recorded/*/timeseries.csv.gz). The
//! synthetic series of `analysis::tests` check each rule; these check that the rules, applied to
//! what the physics really produces, give the paper's paths, and which of them is close to a bound.

use master::analysis::classify::{classify_with, Bounds};
use master::analysis::{classify, series_from_csv, RunClass, RunSeries};
use std::io::Read;
use std::path::{Path, PathBuf};
use std::process::Command;

fn data(preset: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join(format!("tests/data/recorded/{preset}"))
}

fn csv(preset: &str) -> String {
    let gz = std::fs::File::open(data(preset).join("timeseries.csv.gz")).unwrap();
    let mut text = String::new();
    flate2::read::GzDecoder::new(gz)
        .read_to_string(&mut text)
        .unwrap();
    text
}

fn series(preset: &str) -> RunSeries {
    series_from_csv(&csv(preset), [20e-6; 2]).unwrap()
}

/// (preset, class, borderline, onset speed [Hz] of the full-resolution run, its max eps C, T).
/// The recorded (decimated) series must reproduce the full run's onset to 0.1 % and its maximum
/// eccentricities to 1 %.
const EXPECTED: [(&str, RunClass, bool, f64, f64, f64); 3] = [
    ("path1", RunClass::Path1, false, 743.95, 1.3994, 1.2813),
    ("path2a", RunClass::Path2a, true, 1219.16, 0.6362, 0.5072),
    ("path2b", RunClass::Path2b, false, 1378.69, 1.1009, 1.0210),
];

#[test]
fn the_presets_fall_into_their_paths_with_the_borderline_flag_where_a_bound_is_close() {
    for (preset, class, borderline, onset_hz, eps_c, eps_t) in EXPECTED {
        let c = classify(&series(preset));
        assert_eq!(c.class, class, "{preset}: {}", c.criteria);
        assert_eq!(c.borderline, borderline, "{preset}: {:?}", c.margins);
        let f = c.onset_speed_hz.unwrap();
        assert!((f / onset_hz - 1.0).abs() < 1e-3, "{preset}: onset {f} Hz");
        assert!(
            (c.max_eps_c / eps_c - 1.0).abs() < 0.01,
            "{preset}: {}",
            c.max_eps_c
        );
        assert!(
            (c.max_eps_t / eps_t - 1.0).abs() < 0.01,
            "{preset}: {}",
            c.max_eps_t
        );
        // Every criterion states its value, bound and margin; a borderline class has a deciding
        // criterion within 10 % of its bound, and only then.
        assert_eq!(c.margins.len(), 5, "{preset}");
        let close = c
            .margins
            .iter()
            .any(|m| m.deciding && m.margin.is_some_and(|x| x.abs() < 0.1));
        assert_eq!(close, borderline, "{preset}: {:?}", c.margins);
    }
}

/// Path 2a's whirl amplitude is 4 % below the path-1 bound (0.48 C against 0.5 C): moving that bound
/// down by 20 % makes it path 1, up by 20 % leaves it path 2a; the other presets keep their paths
/// under either move of that bound (their amplitudes are far above it).
#[test]
fn the_borderline_preset_changes_class_when_its_bound_moves_and_the_others_do_not() {
    let b = Bounds::default();
    let down = b.scaled("large_whirl_amp_rel", 0.8).unwrap();
    let up = b.scaled("large_whirl_amp_rel", 1.2).unwrap();
    let s2a = series("path2a");
    assert_eq!(classify_with(&s2a, &down).class, RunClass::Path1);
    assert_eq!(classify_with(&s2a, &up).class, RunClass::Path2a);
    for (preset, class) in [("path1", RunClass::Path1), ("path2b", RunClass::Path2b)] {
        let s = series(preset);
        assert_eq!(classify_with(&s, &down).class, class, "{preset}");
        assert_eq!(classify_with(&s, &up).class, class, "{preset}");
    }
}

/// What `airring classify DIR` prints (it must succeed).
fn classify_folder(dir: &Path) -> serde_json::Value {
    let out = Command::new(env!("CARGO_BIN_EXE_airring"))
        .args(["classify", dir.to_str().unwrap()])
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    serde_json::from_slice(&out.stdout).unwrap()
}

/// `airring classify DIR` on a run folder of an earlier version (no films' eps columns): the same
/// class as on the recorded series, from |dr| / C.
#[test]
fn classify_reads_a_folder_of_an_earlier_version() {
    let dir = std::env::temp_dir().join(format!("airring-recorded-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    std::fs::copy(data("path2b").join("system.toml"), dir.join("system.toml")).unwrap();
    let text = csv("path2b");
    let mut lines = text.lines();
    let header: Vec<&str> = lines.next().unwrap().split(',').collect();
    let keep: Vec<usize> = (0..header.len())
        .filter(|k| !header[*k].starts_with("film_"))
        .collect();
    assert!(
        keep.len() < header.len(),
        "the recorded series has the films' eps"
    );
    let mut old = String::new();
    for line in std::iter::once(header.join(",")).chain(lines.map(String::from)) {
        let v: Vec<&str> = line.split(',').collect();
        old += &keep.iter().map(|k| v[*k]).collect::<Vec<_>>().join(",");
        old.push('\n');
    }
    std::fs::write(dir.join("timeseries.csv"), old).unwrap();
    let v = classify_folder(&dir);
    assert_eq!(v["classification"], "path2b", "{v}");
    let _ = std::fs::remove_dir_all(&dir);
}

/// `airring classify DIR` on a run that did not complete says so, as the run's own summary does:
/// a killed run (its summary still "running") was classified "stable" without a word.
#[test]
fn classify_says_when_the_run_did_not_complete() {
    let dir = std::env::temp_dir().join(format!("airring-partial-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    std::fs::copy(data("path1").join("system.toml"), dir.join("system.toml")).unwrap();
    // The first 0.5 s of path 1, as a run killed there leaves it.
    let text: String = csv("path1")
        .lines()
        .take_while(|l| {
            l.split(',')
                .next()
                .and_then(|t| t.parse::<f64>().ok())
                .is_none_or(|t| t <= 0.5)
        })
        .map(|l| format!("{l}\n"))
        .collect();
    std::fs::write(dir.join("timeseries.csv"), text).unwrap();
    let classify = |status: master::summary::RunStatus| -> serde_json::Value {
        let s = master::summary::RunSummary {
            status,
            ..Default::default()
        };
        s.write(&dir).unwrap();
        classify_folder(&dir)
    };
    let v = classify(master::summary::RunStatus::Running);
    let note = v["classification_note"].as_str().unwrap_or_default();
    assert!(
        note.starts_with("classified on the part of the run-up that was simulated (to t = 0.5 s")
            && note.ends_with("the run was killed before it ended)"),
        "{v}"
    );
    let v = classify(master::summary::RunStatus::Interrupted);
    assert!(
        v["classification_note"]
            .as_str()
            .unwrap_or_default()
            .ends_with("the run was interrupted)"),
        "{v}"
    );
    let v = classify(master::summary::RunStatus::Completed);
    assert!(v["classification_note"].is_null(), "{v}");
    let _ = std::fs::remove_dir_all(&dir);
}
