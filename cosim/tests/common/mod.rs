//! Helpers of the library's integration tests: folders, the packed test FMU, and the two coupled
//! oscillators with their exact solution.

#![allow(dead_code)]

use cosim::timeseries::CsvObserver;
use cosim::{RunConfig, RunReport};
use std::path::{Path, PathBuf};
use std::sync::Arc;

/// `target/fmu`, which must hold `oscillator.fmu`.
pub fn fmu_dir() -> PathBuf {
    let d = Path::new(env!("CARGO_MANIFEST_DIR"))
        .parent()
        .unwrap()
        .join("target/fmu");
    assert!(
        d.join("oscillator.fmu").exists(),
        "run `cargo xtask fmus` first"
    );
    d
}

/// A fresh temporary folder for one test.
pub fn tmp(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("cosim-test-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

/// `cosim::run` writing `timeseries.csv` into the run folder, FMU messages dropped.
pub fn run(system: &Path, cfg: &RunConfig, resume: bool) -> Result<RunReport, cosim::RunError> {
    let mut csv = CsvObserver::new(cfg.out_dir.join("timeseries.csv"));
    cosim::run(
        system,
        cfg,
        resume,
        Arc::new(|_: &fmi_core::LogRecord| {}),
        &mut [&mut csv],
    )
}

/// Two unit-mass oscillators (k = 4 pi^2) coupled through their inputs: F_a = x_b, F_b = x_a.
pub fn coupled(kind: &str, h: f64, order: u8, stop: f64) -> String {
    format!(
        r#"
[[fmu]]
name = "a"
path = "{fmu}/oscillator.fmu"
parameters = {{ x0 = "1 m" }}

[[fmu]]
name = "b"
path = "{fmu}/oscillator.fmu"

[[connection]]
from = "a.x"
to = "b.F"

[[connection]]
from = "b.x"
to = "a.F"

[algorithm]
kind = "{kind}"
macro_step = {h:?}
stop_time = {stop:?}
extrapolation_order = {order}
interpolation_order = {order}

[output]
interval = {stop:?}
variables = ["a.x", "b.x"]
"#,
        fmu = fmu_dir().display()
    )
}

/// x_a(t) for x_a(0) = 1, x_b(0) = 0 at rest: modes x_a +- x_b with w^2 -+ 1.
pub fn exact_xa(t: f64) -> f64 {
    let w2 = 4.0 * std::f64::consts::PI.powi(2);
    let (w1, w2b) = ((w2 - 1.0).sqrt(), (w2 + 1.0).sqrt());
    0.5 * ((w1 * t).cos() + (w2b * t).cos())
}

/// Runs a system text in a fresh folder: its report and rows (the folder removed).
pub fn run_text(name: &str, text: &str) -> (RunReport, Vec<Vec<f64>>) {
    let dir = tmp(name);
    let sys = dir.join("system.toml");
    std::fs::write(&sys, text).unwrap();
    let report = run(&sys, &RunConfig::new(&dir), false).unwrap();
    assert!(report.completed, "{report:?}");
    let (_, rows) = cosim::timeseries::read(&dir.join("timeseries.csv")).unwrap();
    let _ = std::fs::remove_dir_all(&dir);
    (report, rows)
}
