//! `airring` on the FMI 3.0 twins (`target/fmu/fmi3`; `cargo xtask fmus` first): a run-up with
//! them equals the FMI 2.0 run-up byte for byte. The input polynomials that FMI 2.0 FMUs take as
//! input derivatives reach the twins through intermediate update (tests/tests/fmi3_importer.rs
//! shows that they matter there).

mod common;

use common::{airring, root, tmp};

#[test]
fn a_run_up_with_the_fmi3_twins_equals_the_fmi2_run_up() {
    let fmi2 = tmp("fmi3-twins", "fmi2");
    let fmi3 = tmp("fmi3-twins", "fmi3");
    for (dir, out) in [("target/fmu", &fmi2), ("target/fmu/fmi3", &fmi3)] {
        assert!(
            root().join(dir).join("airfilm.fmu").exists(),
            "run `cargo xtask fmus` first"
        );
        let (ok, err) = airring(&[
            "runup",
            "--preset",
            "path1",
            "--stop",
            "0.1",
            "--fmu-dir",
            dir,
            "--out",
            out.to_str().unwrap(),
        ]);
        assert!(ok, "{dir}: {err}");
    }
    let series = |d: &std::path::Path| std::fs::read(d.join("timeseries.csv")).unwrap();
    let (a, b) = (series(&fmi2), series(&fmi3));
    assert!(a.len() > 10_000, "{} bytes", a.len());
    assert!(a == b, "the time series differ");
    // The system files name the FMUs of each version.
    let system = std::fs::read_to_string(fmi3.join("system.toml")).unwrap();
    assert!(system.contains("fmi3/airfilm.fmu"), "{system}");
    for d in [fmi2, fmi3] {
        let _ = std::fs::remove_dir_all(d);
    }
}
