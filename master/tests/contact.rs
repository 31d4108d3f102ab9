//! The journal-ring contact evaluated in the rotor (`--contact rotor`) against the contact in
//! the films: the fall and impact of the C = 30 um rotor in its first 10 ms (the start-up that
//! needs the macro-step control when the contact force is extrapolated).
//! Build the FMUs first: `cargo xtask fmus`.

use master::run::{run, RunOptions, RunReport};
use master::runup::{ContactSide, RunupSettings};
use std::path::{Path, PathBuf};
use std::sync::atomic::AtomicBool;
use std::sync::Arc;

fn fmu_dir() -> PathBuf {
    let d = Path::new(env!("CARGO_MANIFEST_DIR"))
        .parent()
        .unwrap()
        .join("target/fmu");
    assert!(d.join("rotor.fmu").exists(), "run `cargo xtask fmus` first");
    d
}

/// Columns of the run-up series used here.
struct Series {
    header: Vec<String>,
    rows: Vec<Vec<f64>>,
}

impl Series {
    fn col(&self, name: &str) -> Vec<f64> {
        let i = self
            .header
            .iter()
            .position(|h| h.starts_with(&format!("{name} ")))
            .unwrap_or_else(|| panic!("no column {name}"));
        self.rows.iter().map(|r| r[i]).collect()
    }
}

fn drop_c30(
    name: &str,
    contact: ContactSide,
    macro_step_us: f64,
    step_control: Option<[f64; 2]>,
) -> (RunReport, Series) {
    let mut s = RunupSettings::preset("path1").unwrap();
    s.clearance_um = 30.0;
    s.dh_um = 60.0;
    s.c_n_per_mm = 1500.0;
    s.stop_time_s = 0.01;
    s.output_interval_us = 100.0;
    s.macro_step_us = macro_step_us;
    // A coarse film mesh: all runs share it, and the contact law does not depend on it.
    (s.n_elem_phi, s.n_elem_z) = (10, 3);
    s.contact = contact;
    s.step_control = step_control;
    let dir = std::env::temp_dir().join(format!("airring-contact-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    let sys = dir.join("system.toml");
    std::fs::write(&sys, s.system_toml(&fmu_dir().to_string_lossy())).unwrap();
    let opts = RunOptions {
        figures: Vec::new(),
        out_dir: dir.clone(),
        checkpoint_every_s: None,
        stop: Arc::new(AtomicBool::new(false)),
        halt_at_s: None,
        quiet: true,
        extra: serde_json::Value::Null,
        bores: None,
        parquet: false,
        halt: None,
    };
    let report = run(&sys, &opts, false).unwrap();
    assert!(report.completed, "{name}: {report:?}");
    let (header, rows) = cosim::timeseries::read(&dir.join("timeseries.csv")).unwrap();
    let _ = std::fs::remove_dir_all(&dir);
    (report, Series { header, rows })
}

/// Largest difference of the journal displacements relative to the rings [m].
fn journal_difference_m(a: &Series, b: &Series) -> f64 {
    let mut worst = 0.0f64;
    for c in ["rotor.dx_C", "rotor.dy_C", "rotor.dx_T", "rotor.dy_T"] {
        for (x, y) in a.col(c).iter().zip(b.col(c)) {
            worst = worst.max((x - y).abs());
        }
    }
    worst
}

#[test]
fn contact_in_the_rotor_converges_to_the_film_side_contact_and_needs_no_refinement() {
    // Reference: contact in the films at a fixed 0.3125 us macro step (the deepest level of
    // the step control at 20 us).
    let (_, reference) = drop_c30("film-ref", ContactSide::Film, 0.3125, None);
    // The window holds a real impact: the contact force peaks far above the rotor weight.
    let f_peak = reference
        .col("film_C.F_contact")
        .into_iter()
        .chain(reference.col("film_T.F_contact"))
        .fold(0.0, f64::max);
    assert!(f_peak > 20.0, "peak contact force {f_peak} N");
    // Contact in the rotor, fine fixed macro step: the same solution (an independent check of
    // the rotor's contact element: a wrong sign, reaction or geometry shows as micrometres).
    let (_, fine) = drop_c30("rotor-fine", ContactSide::Rotor, 1.25, None);
    let e_fine = journal_difference_m(&fine, &reference);
    // Contact in the rotor at the run-up's 20 us with the run-up's step control: the control
    // never needs to refine (the film force alone is smooth enough to extrapolate).
    let (coarse, series) = drop_c30("rotor-20", ContactSide::Rotor, 20.0, Some([0.1, 1.0]));
    let ctl = coarse.control.unwrap();
    let e_coarse = journal_difference_m(&series, &reference);
    println!(
        "C30 drop, 10 ms, peak contact {f_peak:.1} N: rotor-side contact vs film-side at 0.3125 us: \
         {:.3} um at 1.25 us, {:.3} um at 20 us ({} refined macro steps)",
        e_fine * 1e6,
        e_coarse * 1e6,
        ctl.refined_macro_steps
    );
    assert!(
        e_fine < 0.1e-6,
        "1.25 us: journal paths differ by {e_fine} m"
    );
    assert_eq!((ctl.refined_macro_steps, ctl.rejected), (0, 0), "{ctl:?}");
    // The remaining error at 20 us is the extrapolated squeeze-film force during the impact:
    // ~1.6 % of C here, in a transient that decides nothing (docs/convergence.md).
    assert!(
        e_coarse < 0.025 * 30e-6,
        "20 us: journal paths differ by {e_coarse} m"
    );
    // The run-up's defaults (50 us, second-order extrapolation, the default control): the fall
    // and the impact as close to the reference.
    let defaults = RunupSettings::preset("path1").unwrap();
    let (run, series) = drop_c30(
        "rotor-default",
        ContactSide::Rotor,
        defaults.macro_step_us,
        defaults.step_control,
    );
    let e_default = journal_difference_m(&series, &reference);
    println!(
        "at the defaults ({} us, control {:?}): {:.3} um, {:?}",
        defaults.macro_step_us,
        defaults.step_control,
        e_default * 1e6,
        run.control
    );
    assert!(
        e_default < 0.025 * 30e-6,
        "defaults: journal paths differ by {e_default} m"
    );
}
