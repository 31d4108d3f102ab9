//! The library on its own, as another application would use it: `cosim::run` with observers of
//! its own on the packed test FMU (`oscillator.fmu`; build it first with `cargo xtask fmus`).
//! The coupling-order, roll-back, step-control and checkpoint tests of the run loop are in
//! algorithm.rs.

mod common;

use common::{coupled, fmu_dir, run_text, tmp};
use cosim::algorithm::Event;
use cosim::observer::{Observer, ObserverError, RunStart};
use cosim::timeseries::{self, CsvObserver};
use cosim::{CoSim, RunConfig, RunReport};
use std::path::{Path, PathBuf};
use std::sync::Arc;

/// Two oscillators coupled through their inputs; `a` discards its steps from t = 4 ms on unless
/// they are at most a quarter of the 10 ms macro step (the FMU's fault mode 3).
fn system(dir: &Path) -> PathBuf {
    let text = coupled("gauss-seidel", 0.01, 1, 0.1)
        .replace(
            r#"x0 = "1 m""#,
            r#"x0 = "1 m", fault_mode = 3, fault_time = 0.004"#,
        )
        .replace("interval = 0.1", "interval = 0.01");
    let path = dir.join("coupled.toml");
    std::fs::write(&path, text).unwrap();
    path
}

/// Records what the run loop tells an observer, in order.
#[derive(Default)]
struct Recorder {
    calls: Vec<String>,
    samples: Vec<(f64, Vec<f64>)>,
    macro_points: usize,
    events: Vec<Event>,
}

impl Observer for Recorder {
    fn started(&mut self, run: &RunStart<'_>) -> Result<(), ObserverError> {
        let names: Vec<&str> = run.columns.iter().map(|c| c.name.as_str()).collect();
        self.calls
            .push(format!("started {names:?} to {} s", run.stop_time_s));
        Ok(())
    }
    fn sample(&mut self, t_s: f64, values: &[f64]) -> Result<(), ObserverError> {
        self.samples.push((t_s, values.to_vec()));
        Ok(())
    }
    fn macro_point(&mut self, _cosim: &CoSim, _stop_time_s: f64) {
        self.macro_points += 1;
    }
    fn event(&mut self, event: &Event) {
        self.events.push(event.clone());
    }
    fn finished(&mut self, cosim: &CoSim, report: &RunReport) -> Result<(), ObserverError> {
        self.calls.push(format!(
            "finished at {} s, completed {}",
            cosim.time_s(),
            report.completed
        ));
        Ok(())
    }
}

/// An observer whose sample fails: the run ends as failed, with its message, and the others
/// still hear `finished`.
struct FailsAt(f64);

impl Observer for FailsAt {
    fn sample(&mut self, t_s: f64, _values: &[f64]) -> Result<(), ObserverError> {
        if t_s >= self.0 {
            Err(format!("disk full at {t_s} s").into())
        } else {
            Ok(())
        }
    }
}

#[test]
fn observers_see_every_sample_and_the_roll_backs_and_the_csv_matches_them() {
    let dir = tmp("observers");
    let sys = system(&dir);
    let mut csv = CsvObserver::new(dir.join("series.csv"));
    let mut rec = Recorder::default();
    let log = Arc::new(|_: &fmi_core::LogRecord| {});
    let report = cosim::run(
        &sys,
        &RunConfig::new(&dir),
        false,
        log,
        &mut [&mut csv, &mut rec],
    )
    .unwrap();
    assert!(report.completed && report.error.is_none(), "{report:?}");
    assert_eq!(rec.calls.len(), 2, "{:?}", rec.calls);
    assert_eq!(rec.calls[0], "started [\"a.x\", \"b.x\"] to 0.1 s");
    assert!(rec.calls[1].starts_with("finished at 0.1") && rec.calls[1].ends_with("true"));
    // 11 samples (t = 0, 0.01, ..., 0.1), one per macro point.
    assert_eq!(rec.samples.len(), 11);
    assert_eq!(rec.macro_points, 11);
    // Each macro step from 4 ms on was discarded once and rolled back: one event each, in order,
    // naming the subsystem and the interval.
    assert_eq!(report.retries, 10);
    assert_eq!(rec.events.len(), 10, "{:?}", rec.events);
    for (k, e) in rec.events.iter().enumerate() {
        let Event::RolledBack {
            subsystem,
            t_from_s,
            t_to_s,
            ..
        } = e;
        assert_eq!(subsystem, "a");
        assert!((t_from_s - 0.01 * k as f64).abs() < 1e-12, "{e:?}");
        assert!((t_to_s - t_from_s - 0.01).abs() < 1e-12, "{e:?}");
    }
    // The file holds exactly what the observers saw, bit for bit.
    let (header, rows) = timeseries::read(&dir.join("series.csv")).unwrap();
    assert_eq!(header, ["time [s]", "a.x [m]", "b.x [m]"]);
    assert_eq!(rows.len(), rec.samples.len());
    for (row, (t, v)) in rows.iter().zip(&rec.samples) {
        assert_eq!(row[0].to_bits(), t.to_bits());
        assert_eq!(row[1].to_bits(), v[0].to_bits());
        assert_eq!(row[2].to_bits(), v[1].to_bits());
    }
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn a_failing_observer_fails_the_run_with_its_message() {
    let dir = tmp("failing");
    let sys = system(&dir);
    let mut rec = Recorder::default();
    let log = Arc::new(|_: &fmi_core::LogRecord| {});
    let report = cosim::run(
        &sys,
        &RunConfig::new(&dir),
        false,
        log,
        &mut [&mut FailsAt(0.05), &mut rec],
    )
    .unwrap();
    assert!(!report.completed, "{report:?}");
    assert!(
        report
            .error
            .as_deref()
            .unwrap_or("")
            .contains("disk full at 0.05"),
        "{report:?}"
    );
    assert!((report.t_end_s - 0.05).abs() < 1e-12);
    assert!(rec.calls.last().unwrap().starts_with("finished at 0.05"));
    let _ = std::fs::remove_dir_all(&dir);
}

/// An observer that has seen enough once `a.x` falls below a level.
struct HaltsBelow(f64, Option<String>);

impl Observer for HaltsBelow {
    fn sample(&mut self, t_s: f64, values: &[f64]) -> Result<(), ObserverError> {
        if self.1.is_none() && values[0] < self.0 {
            self.1 = Some(format!("a.x = {} below {} at {t_s} s", values[0], self.0));
        }
        Ok(())
    }
    fn halt(&self) -> Option<String> {
        self.1.clone()
    }
}

/// An observer's halt ends the run at the macro point of the sample that crossed its limit: the
/// run is completed and halted with the reason, the others hear `finished` there, the series
/// ends with that sample, and no checkpoint is written (a halted run is not resumed).
#[test]
fn an_observer_halts_the_run_where_it_has_seen_enough() {
    let dir = tmp("halting");
    let sys = system(&dir);
    let mut full = Recorder::default();
    let log = Arc::new(|_: &fmi_core::LogRecord| {});
    let whole = cosim::run(
        &sys,
        &RunConfig::new(&dir),
        false,
        log.clone(),
        &mut [&mut full],
    );
    assert!(whole.unwrap().halted.is_none());
    // The first sample below 0.95 m in the run without a halt.
    let (t_cross, _) = full
        .samples
        .iter()
        .find(|(_, v)| v[0] < 0.95)
        .cloned()
        .expect("a.x falls below 0.95 m");
    let dir2 = tmp("halting2");
    let sys = system(&dir2);
    let mut rec = Recorder::default();
    let mut csv = CsvObserver::new(dir2.join("series.csv"));
    let mut cfg = RunConfig::new(&dir2);
    cfg.checkpoint_every_s = Some(1.0);
    let report = cosim::run(
        &sys,
        &cfg,
        false,
        log,
        &mut [&mut HaltsBelow(0.95, None), &mut csv, &mut rec],
    )
    .unwrap();
    assert!(
        report.completed && !report.interrupted && report.error.is_none(),
        "{report:?}"
    );
    let why = report.halted.as_deref().unwrap_or("");
    assert!(
        why.starts_with("a.x = ") && why.ends_with(&format!("at {t_cross} s")),
        "{why}"
    );
    assert_eq!(report.t_end_s.to_bits(), t_cross.to_bits());
    assert!(t_cross < 0.1, "before the stop time");
    assert_eq!(rec.samples.last().unwrap().0.to_bits(), t_cross.to_bits());
    assert_eq!(rec.samples, full.samples[..rec.samples.len()]);
    assert!(rec.calls.last().unwrap().ends_with("completed true"));
    let (_, rows) = timeseries::read(&dir2.join("series.csv")).unwrap();
    assert_eq!(rows.len(), rec.samples.len());
    assert!(
        !dir2.join("checkpoint").exists(),
        "a halted run leaves no checkpoint"
    );
    let _ = std::fs::remove_dir_all(&dir);
    let _ = std::fs::remove_dir_all(&dir2);
}

#[test]
fn a_run_that_cannot_start_is_a_typed_error() {
    let dir = tmp("nostart");
    let log = Arc::new(|_: &fmi_core::LogRecord| {});
    let e = cosim::run(
        &dir.join("missing.toml"),
        &RunConfig::new(&dir),
        false,
        log.clone(),
        &mut [],
    )
    .unwrap_err();
    assert!(matches!(e, cosim::RunError::Io { .. }), "{e}");
    // A run folder without a checkpoint (a completed run) cannot be resumed.
    let sys = system(&dir);
    // A checkpoint interval that never checkpoints (before: accepted silently).
    for dt in [0.0, -1.0, f64::NAN, f64::INFINITY] {
        let cfg = RunConfig {
            checkpoint_every_s: Some(dt),
            ..RunConfig::new(dir.join("never"))
        };
        let e = cosim::run(&sys, &cfg, false, log.clone(), &mut []).unwrap_err();
        assert!(matches!(e, cosim::RunError::Config(_)), "{dt}: {e}");
        assert!(!dir.join("never").exists(), "nothing written");
    }
    let done = cosim::run(&sys, &RunConfig::new(&dir), false, log.clone(), &mut []).unwrap();
    assert!(done.completed);
    let e = cosim::run(&sys, &RunConfig::new(&dir), true, log, &mut []).unwrap_err();
    assert!(matches!(e, cosim::RunError::Checkpoint(_)), "{e}");
    assert!(e.to_string().contains("no checkpoint"), "{e}");
    let _ = std::fs::remove_dir_all(&dir);
}

/// One free oscillator with the given algorithm lines.
fn single(dir: &Path, algorithm: &str, output: &str) -> PathBuf {
    let text = format!(
        "[[fmu]]\nname = \"a\"\npath = \"{}/oscillator.fmu\"\nparameters = {{ x0 = \"1 m\" }}\n\n\
         [algorithm]\n{algorithm}\n\n[output]\n{output}\nvariables = [\"a.x\"]\n",
        fmu_dir().display()
    );
    let path = dir.join("single.toml");
    std::fs::write(&path, text).unwrap();
    path
}

#[test]
fn a_macro_step_that_does_not_divide_the_stop_time_ends_with_a_shorter_step() {
    let dir = tmp("remainder");
    let sys = single(
        &dir,
        "macro_step = 0.03\nstop_time = 0.1",
        "interval = 0.01",
    );
    let log = Arc::new(|_: &fmi_core::LogRecord| {});
    let mut rec = Recorder::default();
    let report = cosim::run(&sys, &RunConfig::new(&dir), false, log, &mut [&mut rec]).unwrap();
    assert!(report.completed && report.error.is_none(), "{report:?}");
    assert_eq!(report.macro_steps, 4, "0.03, 0.06, 0.09, then 0.1");
    assert_eq!(report.t_end_s, 0.1);
    // Output times (0, 0.01, ..., 0.1) are due at every macro point: one row each (outputs
    // exist only at macro points; before, a point repeated its row for each due output time),
    // the last one at the stop time itself.
    let times: Vec<f64> = rec.samples.iter().map(|s| s.0).collect();
    assert_eq!(times, [0.0, 0.03, 0.06, 0.09, 0.1], "{times:?}");
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn time_grids_no_run_can_cover_are_refused_before_anything_runs() {
    let dir = tmp("grids");
    let log = Arc::new(|_: &fmi_core::LogRecord| {});
    for (algorithm, output, expect) in [
        (
            "macro_step = 1e300\nstop_time = 0.1",
            "interval = 0.01",
            "longer than the stop time",
        ),
        (
            "macro_step = \"1e-300 s\"\nstop_time = 1.0",
            "interval = 0.1",
            "macro steps",
        ),
        (
            "macro_step = 0.01\nstop_time = 1.0",
            "interval = 1e-300",
            "output rows",
        ),
    ] {
        let sys = single(&dir, algorithm, output);
        let e = cosim::run(&sys, &RunConfig::new(&dir), false, log.clone(), &mut [])
            .unwrap_err()
            .to_string();
        assert!(
            e.contains(expect) && e.contains("single.toml"),
            "{algorithm}: {e}"
        );
    }
    let _ = std::fs::remove_dir_all(&dir);
}

fn copy_dir(from: &Path, to: &Path) {
    let _ = std::fs::remove_dir_all(to);
    std::fs::create_dir_all(to).unwrap();
    for e in std::fs::read_dir(from).unwrap().flatten() {
        let target = to.join(e.file_name());
        if e.file_type().unwrap().is_dir() {
            copy_dir(&e.path(), &target);
        } else {
            std::fs::copy(e.path(), target).unwrap();
        }
    }
}

/// Every file of a folder, by relative name, with its bytes.
fn snapshot(dir: &Path) -> Vec<(String, Vec<u8>)> {
    let mut out = vec![];
    for e in std::fs::read_dir(dir).unwrap().flatten() {
        let name = e.file_name().to_string_lossy().into_owned();
        if e.file_type().unwrap().is_dir() {
            for (n, b) in snapshot(&e.path()) {
                out.push((format!("{name}/{n}"), b));
            }
        } else {
            out.push((name, std::fs::read(e.path()).unwrap()));
        }
    }
    out.sort();
    out
}

#[test]
fn a_checkpoint_is_continued_only_by_its_own_run_and_every_field_is_checked() {
    let root = tmp("identity");
    let log = Arc::new(|_: &fmi_core::LogRecord| {});
    let sys = system(&root);
    let run = |dir: &Path, resume: bool, halt: Option<f64>| {
        let cfg = RunConfig {
            halt_at_s: halt,
            ..RunConfig::new(dir)
        };
        let mut csv = CsvObserver::new(dir.join("series.csv"));
        cosim::run(&sys, &cfg, resume, log.clone(), &mut [&mut csv])
    };
    // The reference: straight through.
    let straight = root.join("straight");
    assert!(run(&straight, false, None).unwrap().completed);
    let reference = std::fs::read(straight.join("series.csv")).unwrap();
    // Stopped at 0.05 s with a checkpoint, then resumed: the same series, bit for bit.
    let halted = root.join("halted");
    assert!(run(&halted, false, Some(0.05)).unwrap().interrupted);
    let good = root.join("good");
    copy_dir(&halted, &good);
    assert!(run(&good, true, None).unwrap().completed);
    assert_eq!(std::fs::read(good.join("series.csv")).unwrap(), reference);

    // Each damaged copy is refused with a message naming what does not match, and left as it was.
    type Edit = fn(&mut serde_json::Value);
    let edits: [(&str, Edit, &str); 8] = [
        (
            "emptied histories",
            |m| m["histories"] = serde_json::json!([[], []]),
            "coupling history of a: 0 points",
        ),
        (
            "a history vector too short",
            |m| {
                m["histories"][1][0][1] = serde_json::json!([]);
            },
            "values per point",
        ),
        (
            "one history missing",
            |m| {
                m["histories"].as_array_mut().unwrap().pop();
            },
            "1 coupling histories",
        ),
        (
            "time moved off its step",
            |m| {
                let t = f64::from_bits(m["t_bits"].as_u64().unwrap()) + 0.003;
                m["t_bits"] = t.to_bits().into();
                let h = &mut m["histories"];
                for s in h.as_array_mut().unwrap() {
                    let last = s.as_array_mut().unwrap().last_mut().unwrap();
                    last[0] = t.to_bits().into();
                }
            },
            "is not macro step",
        ),
        (
            "step index edited",
            |m| m["step_index"] = 2.into(),
            "is not macro step",
        ),
        (
            "output index edited",
            |m| m["next_output_index"] = 9.into(),
            "output sample 9",
        ),
        (
            "refinement level",
            |m| m["refine_level"] = 60.into(),
            "refinement level 60",
        ),
        (
            "other FMUs",
            |m| m["identity"]["guids"][0][1] = "{not-this-one}".into(),
            "not the ones",
        ),
    ];
    for (what, edit, expect) in edits {
        let dir = root.join("bad");
        copy_dir(&halted, &dir);
        let mp = dir.join("checkpoint/master.json");
        let mut m: serde_json::Value =
            serde_json::from_str(&std::fs::read_to_string(&mp).unwrap()).unwrap();
        edit(&mut m);
        std::fs::write(&mp, m.to_string()).unwrap();
        let before = snapshot(&dir);
        let e = run(&dir, true, None).unwrap_err().to_string();
        assert!(e.contains(expect), "{what}: {e}");
        assert!(snapshot(&dir) == before, "{what}: the folder was changed");
    }
    // The run folder's system file edited after the checkpoint: another run.
    let dir = root.join("edited-system");
    copy_dir(&halted, &dir);
    let used = dir.join("system.toml");
    let text = std::fs::read_to_string(&used).unwrap();
    std::fs::write(&used, text.replace("stop_time = 0.1", "stop_time = 0.2")).unwrap();
    let e = run(&dir, true, None).unwrap_err().to_string();
    assert!(e.contains("system.toml was changed"), "{e}");
    // The series edited before the checkpoint's length (same length, one digit): refused by the
    // CSV observer before anything is cut.
    let dir = root.join("edited-series");
    copy_dir(&halted, &dir);
    let csv = dir.join("series.csv");
    let mut bytes = std::fs::read(&csv).unwrap();
    let k = bytes.len() - 10
        + bytes[bytes.len() - 10..]
            .iter()
            .position(|c| c.is_ascii_digit())
            .unwrap();
    bytes[k] = if bytes[k] == b'1' { b'2' } else { b'1' };
    std::fs::write(&csv, &bytes).unwrap();
    let e = run(&dir, true, None).unwrap_err().to_string();
    assert!(e.contains("checksum differs"), "{e}");
    assert_eq!(std::fs::read(&csv).unwrap(), bytes, "not cut");
    let _ = std::fs::remove_dir_all(&root);
}

/// A stop time between output times still gets its row: the run's final state is in the series
/// (a stop at 1.5 ms with rows every 1 ms used to end the series at 1 ms), and it is the state
/// the run ended in.
#[test]
fn the_stop_time_has_its_row_between_output_times() {
    let text =
        coupled("gauss-seidel", 0.001, 1, 0.0015).replace("interval = 0.0015", "interval = 0.001");
    let (report, rows) = run_text("stop_row", &text);
    assert_eq!(report.t_end_s, 0.0015);
    let times: Vec<f64> = rows.iter().map(|r| r[0]).collect();
    assert_eq!(times, vec![0.0, 0.001, 0.0015]);
    // The last row is the state at the stop time: within the coupling error of the exact
    // solution there (x_a moves by ~1e-5 between 1 and 1.5 ms; the error at 1 ms steps is ~1e-7).
    let xa = rows[2][1];
    assert!((xa - common::exact_xa(0.0015)).abs() < 1e-6, "{xa}");
    assert!((xa - rows[1][1]).abs() > 1e-6, "the row moved on from 1 ms");
    // On the grid nothing changes: no second row at the stop time.
    let on_grid =
        coupled("gauss-seidel", 0.001, 1, 0.002).replace("interval = 0.002", "interval = 0.001");
    let (_, rows) = run_text("stop_row_on_grid", &on_grid);
    let times: Vec<f64> = rows.iter().map(|r| r[0]).collect();
    assert_eq!(times, vec![0.0, 0.001, 0.002]);
}
