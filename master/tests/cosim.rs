//! The application's run outputs on the packed test FMU (`oscillator.fmu`; `cargo xtask fmus`
//! first): summary.json and the Parquet copy of the series, also after a resume and a failure.
//! The run loop and the macro step themselves are tested in cosim/tests/algorithm.rs.

use master::run::{run, RunOptions};
use std::path::{Path, PathBuf};
use std::sync::atomic::AtomicBool;
use std::sync::Arc;

fn fmu_dir() -> PathBuf {
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

fn tmp(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("airring-test-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

fn opts(out: &Path) -> RunOptions {
    RunOptions {
        figures: Vec::new(),
        out_dir: out.to_path_buf(),
        checkpoint_every_s: None,
        stop: Arc::new(AtomicBool::new(false)),
        halt_at_s: None,
        quiet: true,
        extra: serde_json::Value::Null,
        bores: None,
        parquet: false,
        halt: None,
    }
}

/// Two unit-mass oscillators (k = 4 pi^2) coupled through their inputs: F_a = x_b, F_b = x_a.
fn coupled(kind: &str, h: f64, order: u8, stop: f64) -> String {
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

/// `--parquet`: the same rows as the CSV, bit for bit, after an interrupted and resumed run
/// (the resumed run rewrites the file whole).
#[test]
fn parquet_holds_the_same_rows_as_the_csv_after_a_resume() {
    use parquet::file::reader::{FileReader, SerializedFileReader};
    use parquet::record::RowAccessor;
    let dir = tmp("parquet");
    let sys = dir.join("input.toml");
    std::fs::write(&sys, coupled("gauss-seidel", 0.01, 1, 0.3)).unwrap();
    let mut o = opts(&dir);
    o.parquet = true;
    o.checkpoint_every_s = Some(0.05);
    o.halt_at_s = Some(0.1234);
    assert!(run(&sys, &o, false).unwrap().interrupted);
    assert!(dir.join("timeseries.parquet").exists());
    o.halt_at_s = None;
    assert!(run(&dir.join("system.toml"), &o, true).unwrap().completed);
    let (header, rows) = cosim::timeseries::read(&dir.join("timeseries.csv")).unwrap();
    let reader =
        SerializedFileReader::new(std::fs::File::open(dir.join("timeseries.parquet")).unwrap())
            .unwrap();
    let schema = reader.metadata().file_metadata().schema_descr();
    assert_eq!(schema.num_columns(), header.len());
    for (k, h) in header.iter().enumerate().skip(1) {
        assert!(h.starts_with(schema.column(k).name()), "{h}");
    }
    let pq: Vec<Vec<f64>> = reader
        .get_row_iter(None)
        .unwrap()
        .map(|r| {
            let r = r.unwrap();
            (0..header.len())
                .map(|k| r.get_double(k).unwrap())
                .collect()
        })
        .collect();
    assert_eq!(pq.len(), rows.len());
    assert!(pq == rows, "Parquet and CSV rows differ");
}

/// A Parquet file that cannot be written fails the run with the reason; nothing else is lost.
#[test]
fn a_failed_parquet_write_is_reported_and_the_summary_still_written() {
    let dir = tmp("parquet-fail");
    std::fs::create_dir_all(dir.join("timeseries.parquet")).unwrap();
    let sys = dir.join("input.toml");
    std::fs::write(&sys, coupled("gauss-seidel", 0.01, 1, 0.05)).unwrap();
    let mut o = opts(&dir);
    o.parquet = true;
    let report = run(&sys, &o, false).unwrap();
    let e = report.error.unwrap();
    assert!(e.contains("timeseries.parquet"), "{e}");
    let summary: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(dir.join("summary.json")).unwrap()).unwrap();
    assert!(summary["error"]
        .as_str()
        .unwrap()
        .contains("timeseries.parquet"));
    let (_, rows) = cosim::timeseries::read(&dir.join("timeseries.csv")).unwrap();
    assert!(
        (rows.last().unwrap()[0] - 0.05).abs() < 1e-12,
        "CSV kept to the end"
    );
}

/// A failing run still writes its summary (status failed, the reason) and keeps its series.
#[test]
fn a_failed_run_writes_its_summary() {
    let dir = tmp("fail");
    let text = coupled("gauss-seidel", 0.01, 1, 0.2).replace(
        "parameters = { x0 = \"1 m\" }",
        "parameters = { x0 = \"1 m\", fault_mode = 2, fault_time = 0.1 }",
    );
    let sys = dir.join("system.toml");
    std::fs::write(&sys, text).unwrap();
    let report = run(&sys, &opts(&dir), false).unwrap();
    assert!(!report.completed);
    let summary: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(dir.join("summary.json")).unwrap()).unwrap();
    assert_eq!(summary["status"], "failed");
    assert!(
        summary["error"].as_str().unwrap().contains("fmi2Discard"),
        "{summary}"
    );
    let (_, rows) = cosim::timeseries::read(&dir.join("timeseries.csv")).unwrap();
    assert!(!rows.is_empty());
}
