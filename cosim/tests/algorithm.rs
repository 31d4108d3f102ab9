//! The run loop and the macro step on the packed test FMU (`oscillator.fmu`; build it first with
//! `cargo xtask fmus`), through the library alone (`cosim::run` with the CSV observer): coupling
//! order of Gauss-Seidel and Jacobi against the exact solution of two coupled oscillators,
//! roll-back of discarded steps, macro-step control, failing steps, system-file errors, and
//! checkpoint / resume continuing bit for bit. (Moved here from master/tests/cosim.rs with the
//! code they test; the application's own outputs stay tested there.)

mod common;

use common::{coupled, exact_xa, fmu_dir, run, run_text, tmp};
use cosim::system::System;
use cosim::{RunConfig, RunReport};
use std::sync::Arc;

/// Largest error of x_a against the exact solution over 1 s, sampled every 20 ms.
fn max_error(name: &str, kind: &str, h: f64, order: u8) -> f64 {
    let dir = tmp(name);
    let sys = dir.join("system.toml");
    std::fs::write(
        &sys,
        coupled(kind, h, order, 1.0).replace("interval = 1.0", "interval = 0.02"),
    )
    .unwrap();
    let report = run(&sys, &RunConfig::new(&dir), false).unwrap();
    assert!(report.completed, "{report:?}");
    let (_, rows) = cosim::timeseries::read(&dir.join("timeseries.csv")).unwrap();
    assert_eq!(rows.len(), 51);
    assert!((rows.last().unwrap()[0] - 1.0).abs() < 1e-12);
    let _ = std::fs::remove_dir_all(&dir);
    rows.iter()
        .map(|r| (r[1] - exact_xa(r[0])).abs())
        .fold(0.0, f64::max)
}

#[test]
fn coupling_error_converges_with_the_polynomial_order() {
    for kind in ["gauss-seidel", "jacobi"] {
        for order in 0..=2u8 {
            let hs = [0.02, 0.01];
            let errs: Vec<f64> = hs
                .iter()
                .map(|&h| max_error(&format!("conv-{kind}-{order}-{h}"), kind, h, order))
                .collect();
            let observed = (errs[0] / errs[1]).log2();
            println!(
                "{kind} order {order}: errors {errs:?}, observed convergence order {observed:.2}"
            );
            // Extrapolation of order k makes the coupling error O(H^(k+1)).
            assert!(
                observed > order as f64 + 0.7,
                "{kind} order {order}: observed {observed}"
            );
        }
    }
}

#[test]
fn discarded_steps_are_rolled_back_and_retried_in_halves() {
    let dir = tmp("discard");
    let text = coupled("gauss-seidel", 0.01, 1, 0.2).replace(
        "parameters = { x0 = \"1 m\" }",
        "parameters = { x0 = \"1 m\", fault_mode = 3, fault_time = 0.004 }",
    );
    let sys = dir.join("system.toml");
    std::fs::write(&sys, text).unwrap();
    let report = run(&sys, &RunConfig::new(&dir), false).unwrap();
    assert!(report.completed && report.error.is_none(), "{report:?}");
    assert_eq!(
        report.retries, 20,
        "every 10 ms macro step needs quarter steps"
    );
    // The same as a run with 2.5 ms steps throughout? Not exactly (the partner keeps 2.5 ms only in
    // retried steps), but close to the exact solution:
    let (_, rows) = cosim::timeseries::read(&dir.join("timeseries.csv")).unwrap();
    assert!((rows.last().unwrap()[1] - exact_xa(0.2)).abs() < 1e-4);
}

/// Adds macro-step control to a system text from `coupled`.
fn with_control(text: &str, rtol: f64, atol: f64) -> String {
    let at = "interpolation_order = ";
    let i = text.find(at).expect("an interpolation order") + at.len() + 2;
    format!(
        "{}step_control = {{ rtol = {rtol:?}, atol = {atol:?} }}\n{}",
        &text[..i],
        &text[i..]
    )
}

#[test]
fn macro_step_control_refines_only_where_the_coupling_error_needs_it() {
    let base = coupled("gauss-seidel", 0.02, 1, 1.0).replace("interval = 1.0", "interval = 0.02");
    let err = |rows: &[Vec<f64>]| {
        rows.iter()
            .map(|r| (r[1] - exact_xa(r[0])).abs())
            .fold(0.0, f64::max)
    };
    let (off, rows_off) = run_text("ctl-off", &base);
    assert!(off.control.is_none());
    // A tolerance the order-1 extrapolation always meets: bit-identical to a fixed step.
    let (loose, rows_loose) = run_text("ctl-loose", &with_control(&base, 0.0, 1e3));
    let st = loose.control.unwrap();
    assert_eq!((st.refined_macro_steps, st.rejected), (0, 0), "{st:?}");
    assert!(
        rows_off == rows_loose,
        "a control that never acts changed the series"
    );
    // The order-1 extrapolation error per 20 ms step is up to ~1e-3 m: atol 1e-4 m needs sub-steps.
    let (tight, rows_tight) = run_text("ctl-tight", &with_control(&base, 0.0, 1e-4));
    let st = tight.control.unwrap();
    let (e_off, e_tight) = (err(&rows_off), err(&rows_tight));
    println!("fixed 20 ms: error {e_off:.3e}; controlled (atol 1e-4): error {e_tight:.3e}, {st:?}");
    assert!(st.rejected > 0 && st.refined_macro_steps > 0, "{st:?}");
    assert!((1..6).contains(&st.deepest_level), "{st:?}");
    assert!(
        st.max_error_ratio <= 1.0,
        "accepted above tolerance: {st:?}"
    );
    assert!(
        e_tight < e_off / 10.0,
        "control did not reduce the error: {e_off} -> {e_tight}"
    );
    // The FMUs' integer outputs at the end reach the report (summary.json "fmu_counters"): the
    // oscillators count their accepted steps, 50 at a fixed 20 ms, more when refined (rolled-back
    // attempts are undone with the FMU state).
    let steps = |r: &RunReport| -> Vec<(String, i32)> {
        r.counters
            .iter()
            .map(|(sub, c)| (sub.clone(), c.iter().find(|(n, _)| n == "steps").unwrap().1))
            .collect()
    };
    assert_eq!(steps(&off), [("a".to_string(), 50), ("b".to_string(), 50)]);
    assert!(
        steps(&tight).iter().all(|(_, n)| *n > 50),
        "{:?}",
        steps(&tight)
    );
    // The output grid is kept: 51 samples at 20 ms, the last one at 1 s exactly.
    assert_eq!(rows_tight.len(), 51);
    assert!((rows_tight.last().unwrap()[0] - 1.0).abs() < 1e-12);
}

#[test]
fn a_step_that_always_fails_stops_the_run_with_the_reason() {
    let dir = tmp("fail");
    let text = coupled("gauss-seidel", 0.01, 1, 0.2).replace(
        "parameters = { x0 = \"1 m\" }",
        "parameters = { x0 = \"1 m\", fault_mode = 2, fault_time = 0.1 }",
    );
    let sys = dir.join("system.toml");
    std::fs::write(&sys, text).unwrap();
    let report = run(&sys, &RunConfig::new(&dir), false).unwrap();
    assert!(!report.completed);
    let e = report.error.unwrap();
    assert!(e.contains("a: fmi2DoStep returned fmi2Discard"), "{e}");
    // Nothing lost: the series up to the failure is on disk.
    let (_, rows) = cosim::timeseries::read(&dir.join("timeseries.csv")).unwrap();
    assert!(!rows.is_empty());
}

#[test]
fn system_file_errors_name_file_line_and_field() {
    let dir = tmp("errors");
    let good = coupled("gauss-seidel", 0.01, 1, 0.2);
    let cases = [
        (
            good.replace("x0 = \"1 m\"", "x0 = \"1 N\""),
            ":5: fmu 'a' parameters.x0: unit 'N' does not fit 'x0' (accepted: m, um, mm)",
        ),
        (
            good.replace("x0 = \"1 m\"", "x1 = 2.0"),
            ":5: fmu 'a' parameters.x1: 'oscillator' has no variable 'x1'",
        ),
        (
            good.replace("to = \"b.F\"", "to = \"b.x\""),
            ":13: connection.to: 'b.x' is not a Real input",
        ),
        (
            good.replace("from = \"b.x\"", "from = \"c.x\""),
            ":16: connection.from: no FMU instance 'c'",
        ),
        (
            good.replace("kind = \"gauss-seidel\"", "kind = \"newton\""),
            ":20: algorithm.kind: 'newton' is neither",
        ),
        (
            good.replace("extrapolation_order = 1", "extrapolation_order = 5"),
            ":23: algorithm.extrapolation_order: polynomial order must be 0, 1 or 2",
        ),
        (
            good.replace("oscillator.fmu\"\nparameters", "missing.fmu\"\nparameters"),
            ":4: fmu.path:",
        ),
        (
            with_control(&good, 0.1, 1.0).replace("[algorithm]", "[algorithm]\nrollback = false"),
            "algorithm.step_control: needs rollback = true",
        ),
        (
            with_control(&good, -0.1, 1.0),
            "algorithm.step_control: rtol and atol must be finite",
        ),
        (
            good.replace("x0 = \"1 m\"", "x0 = \"1e999 m\""),
            "is not finite",
        ),
        // A value of the wrong type: the parser names the type, the key comes from the text.
        (
            good.replace("extrapolation_order = 1", "extrapolation_order = -1"),
            ":23: extrapolation_order: invalid value: integer `-1`, expected u8",
        ),
    ];
    for (k, (text, want)) in cases.iter().enumerate() {
        let path = dir.join(format!("case{k}.toml"));
        std::fs::write(&path, text).unwrap();
        let err = match System::load(&path) {
            Err(e) => e.to_string(),
            Ok(sys) => match cosim::build(&sys, Arc::new(|_: &fmi_core::LogRecord| {})) {
                Err(e) => e.to_string(),
                Ok(_) => String::from("(no error)"),
            },
        };
        assert!(err.contains(want), "case {k}: got '{err}', want '{want}'");
        assert!(
            err.starts_with(&path.display().to_string()),
            "case {k}: '{err}' must name the file"
        );
    }
    // The output interval's check reports the macro step's own error first: a bare number is
    // seconds, and 50 s was reported as an interval that is not a whole number of it.
    let path = dir.join("bare_step.toml");
    std::fs::write(&path, good.replace("macro_step = 0.01", "macro_step = 50")).unwrap();
    let sys = System::load(&path).unwrap();
    let err = cosim::setup::check_output_interval_whole(&sys)
        .unwrap_err()
        .to_string();
    assert!(
        err.contains(":21: algorithm.macro_step: 50 s is longer than the stop time 0.2 s"),
        "{err}"
    );
}

/// `sys` run into `dir` with checkpoints every 0.05 s, halted at 0.1234 s.
fn halt(sys: &std::path::Path, dir: &std::path::Path) -> RunReport {
    let o = RunConfig {
        checkpoint_every_s: Some(0.05),
        halt_at_s: Some(0.1234),
        ..RunConfig::new(dir)
    };
    run(sys, &o, false).unwrap()
}

/// The run in `dir` resumed from its checkpoint (still checkpointing every 0.05 s).
fn resume(dir: &std::path::Path) -> RunReport {
    let o = RunConfig {
        checkpoint_every_s: Some(0.05),
        ..RunConfig::new(dir)
    };
    run(&dir.join("system.toml"), &o, true).unwrap()
}

#[test]
fn checkpoint_resume_gives_the_uninterrupted_series() {
    let dir_full = tmp("full");
    let dir_cut = tmp("cut");
    let text = coupled("gauss-seidel", 0.001, 2, 0.3).replace("interval = 0.3", "interval = 0.002");
    let sys = dir_full.join("input.toml");
    std::fs::write(&sys, &text).unwrap();
    run(&sys, &RunConfig::new(&dir_full), false).unwrap();

    let first = halt(&sys, &dir_cut);
    assert!(first.interrupted && !first.completed);
    let second = resume(&dir_cut);
    assert!(second.completed);
    let full = std::fs::read(dir_full.join("timeseries.csv")).unwrap();
    let resumed = std::fs::read(dir_cut.join("timeseries.csv")).unwrap();
    assert!(
        full == resumed,
        "resumed series differs from the uninterrupted one"
    );
}

/// A system file whose FMU paths are relative to its own folder: the run's copy names that
/// folder (`base_dir`), and the run resumes from its folder to the uninterrupted series.
#[test]
fn a_run_of_a_system_file_with_relative_fmu_paths_resumes_from_its_folder() {
    let src = tmp("relative-src");
    let dir_full = tmp("relative-full");
    let dir_cut = tmp("relative-cut");
    std::fs::copy(fmu_dir().join("oscillator.fmu"), src.join("oscillator.fmu")).unwrap();
    let text = coupled("gauss-seidel", 0.001, 1, 0.3)
        .replace("interval = 0.3", "interval = 0.002")
        .replace(
            &format!("{}/oscillator.fmu", fmu_dir().display()),
            "oscillator.fmu",
        );
    assert!(text.contains("path = \"oscillator.fmu\""));
    let sys = src.join("input.toml");
    std::fs::write(&sys, &text).unwrap();
    run(&sys, &RunConfig::new(&dir_full), false).unwrap();
    assert!(halt(&sys, &dir_cut).interrupted);
    let copy = std::fs::read_to_string(dir_cut.join("system.toml")).unwrap();
    assert!(
        copy.ends_with(&text),
        "the user's file follows the added lines unchanged"
    );
    assert!(resume(&dir_cut).completed);
    assert_eq!(
        std::fs::read(dir_full.join("timeseries.csv")).unwrap(),
        std::fs::read(dir_cut.join("timeseries.csv")).unwrap()
    );
}

#[test]
fn checkpoint_resume_keeps_the_refinement_of_the_step_control() {
    let dir_full = tmp("ctl-full");
    let dir_cut = tmp("ctl-cut");
    let text = with_control(
        &coupled("gauss-seidel", 0.01, 1, 0.3).replace("interval = 0.3", "interval = 0.01"),
        0.0,
        1e-5,
    );
    let sys = dir_full.join("input.toml");
    std::fs::write(&sys, &text).unwrap();
    let full_report = run(&sys, &RunConfig::new(&dir_full), false).unwrap();
    assert!(full_report.control.unwrap().refined_macro_steps > 0);
    let o = RunConfig {
        checkpoint_every_s: Some(0.05),
        halt_at_s: Some(0.1234),
        ..RunConfig::new(&dir_cut)
    };
    assert!(run(&sys, &o, false).unwrap().interrupted);
    let cp: serde_json::Value = serde_json::from_str(
        &std::fs::read_to_string(dir_cut.join("checkpoint").join("master.json")).unwrap(),
    )
    .unwrap();
    assert!(
        cp["refine_level"].as_u64().unwrap() > 0,
        "checkpointed at the nominal step: {cp}"
    );
    let o = RunConfig {
        checkpoint_every_s: Some(0.05),
        ..RunConfig::new(&dir_cut)
    };
    assert!(
        run(&dir_cut.join("system.toml"), &o, true)
            .unwrap()
            .completed
    );
    let full = std::fs::read(dir_full.join("timeseries.csv")).unwrap();
    let resumed = std::fs::read(dir_cut.join("timeseries.csv")).unwrap();
    assert!(
        full == resumed,
        "resumed series differs from the uninterrupted one"
    );
}

/// `restart_coupling_histories` (for a state set from outside the run): at t = 0 it changes
/// nothing; mid-run it keeps one point per subsystem, read from the FMUs, and the polynomials
/// build up again from there (first steps of order 0, then the configured order), so the
/// run goes on within the coupling error of a restart and not bit for bit.
#[test]
fn coupling_histories_restart_from_the_fmus_outputs() {
    let dir = tmp("restart-histories");
    std::fs::create_dir_all(&dir).unwrap();
    let sys_path = dir.join("system.toml");
    std::fs::write(&sys_path, coupled("gauss-seidel", 1e-3, 2, 1.0)).unwrap();
    let build = || {
        let sys = System::load(&sys_path).unwrap();
        cosim::setup::build(&sys, Arc::new(|_: &fmi_core::LogRecord| {})).unwrap()
    };
    let xa = |c: &cosim::algorithm::CoSim| {
        let mut v = 0.0;
        c.get(c.index("a").unwrap(), 4, &mut v).unwrap(); // x
        v
    };
    let steps = |c: &mut cosim::algorithm::CoSim, n: usize| {
        for _ in 0..n {
            c.step(1e-3).unwrap();
        }
    };
    let mut plain = build().cosim;
    let mut restarted = build().cosim;
    restarted.restart_coupling_histories().unwrap();
    steps(&mut plain, 300);
    steps(&mut restarted, 300);
    assert_eq!(
        xa(&plain).to_bits(),
        xa(&restarted).to_bits(),
        "a no-op at t = 0"
    );

    restarted.restart_coupling_histories().unwrap();
    let (state, _) = restarted.checkpoint().unwrap();
    assert!(
        state.histories.iter().all(|h| h.len() == 1),
        "{:?}",
        state.histories
    );
    let (plain_state, _) = plain.checkpoint().unwrap();
    assert_eq!(plain_state.histories[0].len(), 3);
    assert_eq!(
        state.histories[0].back(),
        plain_state.histories[0].back(),
        "the kept point is the FMUs' current output"
    );
    steps(&mut plain, 300);
    steps(&mut restarted, 300);
    let (a, b) = (xa(&plain), xa(&restarted));
    assert!(a != b, "a restart is not a no-op mid-run");
    // Orders 0 and 1 for one step each: a local error of ~(h w)^2 x on an O(1) oscillation.
    assert!((a - b).abs() < 1e-4, "{a} vs {b}");
    let _ = std::fs::remove_dir_all(&dir);
}
