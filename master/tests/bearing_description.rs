//! One description of each bearing (issue: "one bearing, one description"): every way of setting
//! a bearing quantity edits the same thing, the rotor's contact geometry is derived from the air
//! films, and the analysis takes each bearing's clearance from the run folder. End to end on the
//! packed FMUs (`cargo xtask fmus` first).

use std::path::{Path, PathBuf};
use std::process::Command;

fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .parent()
        .unwrap()
        .to_path_buf()
}

fn tmp(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("airring-bearing-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

fn airring(args: &[&str]) -> (bool, String, String) {
    let out = Command::new(env!("CARGO_BIN_EXE_airring"))
        .args(args)
        .current_dir(root())
        .output()
        .expect("airring runs");
    (
        out.status.success(),
        String::from_utf8_lossy(&out.stdout).into_owned(),
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
}

/// A short run-up on a coarse mesh into `dir` with `extra` flags.
fn runup(dir: &Path, extra: &[&str]) -> String {
    let mut args = vec![
        "runup",
        "--stop",
        "0.004",
        "--mesh",
        "8x2",
        "--quiet",
        "--out",
        dir.to_str().unwrap(),
    ];
    args.extend_from_slice(extra);
    let (ok, _, err) = airring(&args);
    assert!(ok, "{err}");
    std::fs::read_to_string(dir.join("timeseries.csv")).unwrap()
}

fn summary(dir: &Path) -> serde_json::Value {
    serde_json::from_str(&std::fs::read_to_string(dir.join("summary.json")).unwrap()).unwrap()
}

/// The rotor's `bearing_C` in a generated system file, in m.
fn rotor_bearing_c(dir: &Path) -> f64 {
    let text = std::fs::read_to_string(dir.join("system.toml")).unwrap();
    let sys: toml::Table = text.parse().unwrap();
    let rotor = sys["fmu"]
        .as_array()
        .unwrap()
        .iter()
        .find(|f| f["name"].as_str() == Some("rotor"))
        .unwrap();
    rotor["parameters"]["bearing_C"].as_float().unwrap()
}

#[test]
fn clearance_flag_and_set_film_c_give_the_same_run() {
    let a = tmp("flag");
    let b = tmp("set");
    let series_a = runup(&a, &["--clearance", "25", "--dh", "50"]);
    let series_b = runup(&b, &["--set", "film.C=25 um", "--dh", "50"]);
    assert!(series_a.lines().count() > 5);
    assert_eq!(series_a, series_b, "the two spellings must give one run");
    // The rotor's contact uses the films' clearance, not the preset's 20 um ...
    for d in [&a, &b] {
        let film_c = match master::fmu_params::FmuParameter::parse("film.C", "25 um")
            .unwrap()
            .value
        {
            master::fmu_params::Value::Real(v) => v,
            other => panic!("{other:?}"),
        };
        assert_eq!(rotor_bearing_c(d), film_c, "{}", d.display());
        // ... and so does the analysis.
        let s = summary(d);
        assert_eq!(s["clearance_um"]["C"].as_f64(), Some(25.0), "{s}");
        assert_eq!(s["clearance_um"]["T"].as_f64(), Some(25.0), "{s}");
    }
    // Before the fix, the rotor's contact kept 20 um: a run with that geometry differs.
    let c = tmp("stale");
    let stale = runup(
        &c,
        &["--set", "film.C=25 um", "--dh", "50", "--contact", "film"],
    );
    assert_ne!(
        series_a, stale,
        "the contact side must matter for this check"
    );
    for d in [a, b, c] {
        let _ = std::fs::remove_dir_all(d);
    }
}

#[test]
fn a_per_bearing_clearance_reaches_the_analysis_or_is_refused_with_the_flag_to_use() {
    // With the contact in the rotor (one geometry for both bearings) it is refused, naming the
    // way out; nothing is written.
    let dir = tmp("per-bearing");
    let out = dir.join("refused");
    let (ok, _, err) = airring(&[
        "runup",
        "--stop",
        "0.004",
        "--set",
        "film_T.C=25 um",
        "--quiet",
        "--out",
        out.to_str().unwrap(),
    ]);
    assert!(!ok);
    assert!(
        err.contains("film_C and film_T differ") && err.contains("--contact film"),
        "{err}"
    );
    assert!(!out.exists(), "a refused run-up leaves no folder");
    // With the contact in the films each bearing has its own: the summary, and `classify` on the
    // folder, normalise each bearing with its own clearance.
    let ok_dir = dir.join("films");
    runup(&ok_dir, &["--set", "film_T.C=25 um", "--contact", "film"]);
    let s = summary(&ok_dir);
    assert_eq!(s["clearance_um"]["C"].as_f64(), Some(20.0), "{s}");
    assert_eq!(s["clearance_um"]["T"].as_f64(), Some(25.0), "{s}");
    let (ok, stdout, err) = airring(&["classify", ok_dir.to_str().unwrap()]);
    assert!(ok, "{err}");
    let c: serde_json::Value = serde_json::from_str(&stdout).unwrap();
    assert_eq!(c["clearance_um"]["T"].as_f64(), Some(25.0), "{c}");
    assert_eq!(
        c["max_eps_T"], s["max_eps_T"],
        "classify agrees with the run"
    );
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn the_rotors_contact_geometry_is_not_a_runup_flag() {
    let dir = tmp("bearing-c");
    let (ok, _, err) = airring(&[
        "runup",
        "--set",
        "rotor.bearing_C=25 um",
        "--out",
        dir.join("x").to_str().unwrap(),
    ]);
    assert!(!ok);
    assert!(
        err.contains("film.C") && err.contains("--clearance"),
        "{err}"
    );
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn a_design_file_is_the_same_description_as_the_flags() {
    let dir = tmp("design");
    let design = dir.join("d.toml");
    std::fs::write(
        &design,
        "[bearing]\nC = \"25 um\"\ndH = \"50 um\"\nmount_c = \"800 N/mm\"\nring_mass = \"60 g\"\n",
    )
    .unwrap();
    let a = dir.join("design");
    let b = dir.join("flags");
    let series_a = runup(&a, &["--design", design.to_str().unwrap()]);
    let series_b = runup(
        &b,
        &[
            "--clearance",
            "25",
            "--dh",
            "50",
            "--c",
            "800",
            "--m-r",
            "60",
        ],
    );
    assert_eq!(series_a, series_b);
    // A flag overrides the file: --clearance 30 over the design is the flags' run with C = 30.
    let c = dir.join("override");
    let d = dir.join("flags30");
    let series_c = runup(
        &c,
        &["--design", design.to_str().unwrap(), "--clearance", "30"],
    );
    let series_d = runup(
        &d,
        &[
            "--clearance",
            "30",
            "--dh",
            "50",
            "--c",
            "800",
            "--m-r",
            "60",
        ],
    );
    assert_eq!(series_c, series_d);
    assert_ne!(series_a, series_c);
    // The example design runs as it is (default contact side) ...
    runup(
        &dir.join("example"),
        &["--design", "studies/design_example.toml"],
    );
    // ... and in the linear analysis (one speed).
    let (ok, stdout, err) = airring(&[
        "stability",
        "--design",
        "studies/design_example.toml",
        "--speeds",
        "1000:1000:100",
        "--out",
        dir.join("stab").to_str().unwrap(),
    ]);
    assert!(ok, "{err}");
    assert!(stdout.contains("1000"), "{stdout}");
    // A bad design stops before anything runs, naming the file and the key.
    std::fs::write(&design, "[bearing]\nC = \"25 furlongs\"\n").unwrap();
    let (ok, _, err) = airring(&[
        "runup",
        "--design",
        design.to_str().unwrap(),
        "--out",
        dir.join("bad").to_str().unwrap(),
    ]);
    assert!(!ok);
    assert!(
        err.contains("d.toml") && err.contains("[bearing] C"),
        "{err}"
    );
    assert!(!dir.join("bad").exists());
    let _ = std::fs::remove_dir_all(&dir);
}

/// The generated system file is valid TOML whatever the FMU folder is called: quotes and
/// backslashes in --fmu-dir are escaped (before: the run-up failed although the folder held both
/// FMUs; issue #17 item 8).
#[test]
fn an_fmu_folder_with_quotes_and_backslashes_runs() {
    let dir = tmp("quotes");
    let odd = dir.join("fmus \"x\" \\y");
    std::fs::create_dir_all(&odd).unwrap();
    for f in ["rotor.fmu", "airfilm.fmu"] {
        std::fs::copy(root().join("target/fmu").join(f), odd.join(f)).unwrap();
    }
    let out = dir.join("run");
    runup(&out, &["--fmu-dir", odd.to_str().unwrap()]);
    let sys: toml::Table = std::fs::read_to_string(out.join("system.toml"))
        .unwrap()
        .parse()
        .unwrap();
    let path = sys["fmu"][0]["path"].as_str().unwrap();
    assert!(path.ends_with("fmus \"x\" \\y/rotor.fmu"), "{path}");
    let _ = std::fs::remove_dir_all(&dir);
}
