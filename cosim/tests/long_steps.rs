//! Long macro steps in declared windows (`cosim::step_plan`) on the packed test FMU
//! (`oscillator.fmu`; build it first with `cargo xtask fmus`): the run keeps the rows of its base
//! grid, runs unchanged outside the windows, counts its steps, resumes bit for bit, and refuses a
//! bad plan with the file, line and field.

mod common;

use common::{coupled, exact_xa, run, run_text, tmp};
use cosim::{RunConfig, RunReport};

/// The coupled oscillators (`common::coupled`), Gauss-Seidel with second-order polynomials, a
/// row every 10 ms; `long` is an optional `long_steps = ...` line.
fn system(h: f64, stop: f64, long: &str) -> String {
    coupled("gauss-seidel", h, 2, stop)
        .replace(&format!("interval = {stop:?}"), "interval = 0.01")
        .replace(
            "interpolation_order = 2\n",
            &format!("interpolation_order = 2\n{long}\n"),
        )
}

/// Runs `text` whole, and halted at `halt_s` (checkpoints every `every_s`) then resumed; asserts
/// that the two series are the same bytes and returns the two reports (whole, resumed).
fn whole_and_resumed(name: &str, text: &str, every_s: f64, halt_s: f64) -> (RunReport, RunReport) {
    let dir_full = tmp(&format!("{name}-full"));
    let dir_cut = tmp(&format!("{name}-cut"));
    let sys = dir_full.join("input.toml");
    std::fs::write(&sys, text).unwrap();
    let full = run(&sys, &RunConfig::new(&dir_full), false).unwrap();
    assert!(full.completed, "{full:?}");
    let o = RunConfig {
        checkpoint_every_s: Some(every_s),
        halt_at_s: Some(halt_s),
        ..RunConfig::new(&dir_cut)
    };
    let first = run(&sys, &o, false).unwrap();
    assert!(first.interrupted && !first.completed);
    let second = run(
        &dir_cut.join("system.toml"),
        &RunConfig::new(&dir_cut),
        true,
    )
    .unwrap();
    assert!(second.completed);
    let a = std::fs::read(dir_full.join("timeseries.csv")).unwrap();
    let b = std::fs::read(dir_cut.join("timeseries.csv")).unwrap();
    assert!(a == b, "resumed series differs from the uninterrupted one");
    let _ = std::fs::remove_dir_all(&dir_full);
    let _ = std::fs::remove_dir_all(&dir_cut);
    (full, second)
}

const WINDOW: &str = "long_steps = { factor = 2, windows = [[0.2, 0.6]] }";

#[test]
fn long_steps_keep_the_base_grid_rows_and_change_nothing_outside_their_window() {
    let (base, rows_base) = run_text("long-base", &system(0.01, 1.0, ""));
    let (long, rows_long) = run_text("long-plan", &system(0.01, 1.0, WINDOW));
    let (_, rows_coarse) = run_text("long-coarse", &system(0.02, 1.0, ""));
    assert_eq!(base.macro_steps, 100);
    assert_eq!(base.long_macro_steps, None);
    // [0.2, 0.6] s: 20 steps of 20 ms in place of 40 of 10 ms.
    assert_eq!((long.macro_steps, long.long_macro_steps), (80, Some(20)));
    // The same rows at the same times: one every 10 ms.
    assert_eq!(rows_long.len(), 101);
    for (l, b) in rows_long.iter().zip(&rows_base) {
        assert_eq!(l[0].to_bits(), b[0].to_bits());
    }
    // Before the window the runs are the same run, bit for bit.
    for (l, b) in rows_long
        .iter()
        .zip(&rows_base)
        .take_while(|(l, _)| l[0] <= 0.2 + 1e-12)
    {
        assert_eq!(
            (l[1].to_bits(), l[2].to_bits()),
            (b[1].to_bits(), b[2].to_bits()),
            "t {}",
            l[0]
        );
    }
    // Inside it, the rows between the ends of a long step are interpolated between them.
    for i in (21..60).step_by(2) {
        for c in 1..3 {
            let mid = 0.5 * (rows_long[i - 1][c] + rows_long[i + 1][c]);
            assert!((rows_long[i][c] - mid).abs() <= 1e-15, "row {i}");
        }
    }
    // Accuracy between the base step's and the long step's: the largest error against the exact
    // solution at the long steps' own points, and after the window.
    let err = |rows: &[Vec<f64>], keep: &dyn Fn(usize) -> bool| {
        rows.iter()
            .enumerate()
            .filter(|(i, _)| keep(*i))
            .map(|(_, r)| (r[1] - exact_xa(r[0])).abs())
            .fold(0.0, f64::max)
    };
    let macro_points = |i: usize| !(21..60).contains(&i) || i.is_multiple_of(2);
    let (e_base, e_long, e_coarse) = (
        err(&rows_base, &macro_points),
        err(&rows_long, &macro_points),
        err(&rows_coarse, &macro_points),
    );
    println!(
        "max error of x_a: base {e_base:.3e}, long steps {e_long:.3e}, 2x steps {e_coarse:.3e}"
    );
    assert!(
        e_base < e_long && e_long < e_coarse,
        "{e_base} {e_long} {e_coarse}"
    );
}

#[test]
fn a_run_with_long_steps_resumes_bit_for_bit() {
    // Halted inside the window, where the macro points are every 20 ms.
    let (full, resumed) = whole_and_resumed("long", &system(0.01, 1.0, WINDOW), 0.05, 0.333);
    assert_eq!(
        (resumed.macro_steps, resumed.long_macro_steps),
        (full.macro_steps, full.long_macro_steps)
    );
}

#[test]
fn a_bad_plan_is_refused_with_file_line_and_field() {
    for (plan, says) in [
        (
            "long_steps = { factor = 0, windows = [[0.2, 0.6]] }",
            "factor 0",
        ),
        (
            "long_steps = { factor = 2, windows = [[0.2, 0.6], [0.5, 0.7]] }",
            "overlap",
        ),
        (
            "long_steps = { factor = 2, windows = [[0.6, 0.2]] }",
            "start < end",
        ),
    ] {
        let dir = tmp("long-bad");
        let sys = dir.join("system.toml");
        std::fs::write(&sys, system(0.01, 1.0, plan)).unwrap();
        let e = run(&sys, &RunConfig::new(&dir), false)
            .expect_err("refused")
            .to_string();
        assert!(
            e.contains("system.toml:") && e.contains("algorithm.long_steps") && e.contains(says),
            "{e}"
        );
        let _ = std::fs::remove_dir_all(&dir);
    }
}

/// `system` with a macro-step control of absolute tolerance `atol` (in metres of x).
fn with_control(text: &str, atol: f64) -> String {
    text.replace(
        "interpolation_order = 2\n",
        &format!("interpolation_order = 2\nstep_control = {{ rtol = 0.0, atol = {atol:?} }}\n"),
    )
}

#[test]
fn a_rejected_step_closes_the_rest_of_its_window_also_across_a_resume() {
    // The coupling error of these oscillators' second-order extrapolation is ~1e-5 m over a
    // 20 ms step: a tolerance of 3e-5 m rejects the first long step (at 0.2 s) and no 10 ms one.
    // Halted after the window closed: the resumed run must not open it again.
    let text = with_control(&system(0.01, 1.0, WINDOW), 3e-5);
    let (full, resumed) = whole_and_resumed("long-close", &text, 0.1, 0.35);
    assert_eq!(full.long_steps_closed_at_s.len(), 1, "{full:?}");
    assert!((full.long_steps_closed_at_s[0] - 0.2).abs() < 1e-9);
    // The one long step tried (rolled back and covered in halves), then 10 ms steps only.
    assert_eq!(full.long_macro_steps, Some(1));
    assert_eq!(full.macro_steps, 99);
    assert_eq!(
        (resumed.macro_steps, resumed.long_macro_steps),
        (full.macro_steps, full.long_macro_steps)
    );
    let (open, _) = run_text("long-open", &system(0.01, 1.0, WINDOW));
    assert_eq!(open.long_macro_steps, Some(20));
}
