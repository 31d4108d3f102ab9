//! `airfilm.fmu` through the C ABI: the same numbers as the library, input polynomials, two
//! instances, states, and clear refusals of bad parameters and inputs.

use fmi2::importer::Slave;
use fmi_core::Status;
use fmu_airfilm::shell::vr;
use fmu_airfilm::{AirFilm, BearingParams, JournalState};
use integration_tests::{initialized, load, LogBook};
use std::f64::consts::TAU;

const OMEGA: f64 = TAU * 1000.0;
const WHIRL: f64 = TAU * 400.0;
const R: f64 = 0.3 * 20e-6;

/// A circular whirl orbit of radius R about (0, -R/2).
fn orbit(t: f64) -> JournalState {
    JournalState {
        dx_m: R * (WHIRL * t).cos(),
        dy_m: -R / 2.0 + R * (WHIRL * t).sin(),
        vx_m_s: -R * WHIRL * (WHIRL * t).sin(),
        vy_m_s: R * WHIRL * (WHIRL * t).cos(),
        omega_rad_s: OMEGA,
    }
}

fn set_inputs(s: &Slave, t: f64) {
    let j = orbit(t);
    let (c, sn) = ((WHIRL * t).cos(), (WHIRL * t).sin());
    s.set_real(
        &[vr::DX, vr::DY, vr::VX, vr::VY, vr::OMEGA],
        &[j.dx_m, j.dy_m, j.vx_m_s, j.vy_m_s, j.omega_rad_s],
    )
    .unwrap();
    // First and second derivatives of the orbit: the FMU follows the Taylor polynomial inside the step.
    let w = WHIRL;
    s.set_real_input_derivatives(
        &[
            vr::DX,
            vr::DY,
            vr::VX,
            vr::VY,
            vr::DX,
            vr::DY,
            vr::VX,
            vr::VY,
        ],
        &[1, 1, 1, 1, 2, 2, 2, 2],
        &[
            -R * w * sn,
            R * w * c,
            -R * w * w * c,
            -R * w * w * sn,
            -R * w * w * c,
            -R * w * w * sn,
            R * w * w * w * sn,
            -R * w * w * w * c,
        ],
    )
    .unwrap();
}

fn forces(s: &Slave) -> [f64; 2] {
    let mut f = [0.0; 2];
    s.get_real(&[vr::FX, vr::FY], &mut f).unwrap();
    f
}

fn start(fmu: &fmi2::importer::Fmu, book: &LogBook, name: &str) -> Slave {
    initialized(fmu, name, book, |s| set_inputs(s, 0.0))
}

#[test]
fn fmu_matches_the_library_on_a_whirl_orbit() {
    let fmu = load("airfilm");
    let book = LogBook::default();
    let s = start(&fmu, &book, "film");
    let h = 1e-5;
    let n = 40;
    for k in 0..n {
        let t = k as f64 * h;
        set_inputs(&s, t);
        s.do_step(t, h).unwrap();
    }
    // The library driven by the same second-order Taylor polynomials of the orbit.
    let mut film = AirFilm::new(BearingParams::paper()).unwrap();
    film.set_pressures_rel(0.0, orbit(0.0), &vec![1.0; film.pressures_rel().len()])
        .unwrap();
    for k in 0..n {
        let t0 = k as f64 * h;
        let j0 = orbit(t0);
        let taylor = move |t: f64| {
            let s = t - t0;
            let (c, sn, w) = ((WHIRL * t0).cos(), (WHIRL * t0).sin(), WHIRL);
            JournalState {
                dx_m: j0.dx_m + s * (-R * w * sn) + s * s / 2.0 * (-R * w * w * c),
                dy_m: j0.dy_m + s * (R * w * c) + s * s / 2.0 * (-R * w * w * sn),
                vx_m_s: j0.vx_m_s + s * (-R * w * w * c) + s * s / 2.0 * (R * w * w * w * sn),
                vy_m_s: j0.vy_m_s + s * (-R * w * w * sn) + s * s / 2.0 * (-R * w * w * w * c),
                omega_rad_s: OMEGA,
            }
        };
        film.advance(t0, h, &taylor).unwrap();
    }
    let lib = film.outputs();
    let f = forces(&s);
    println!(
        "after {n} steps: FMU F = {f:?} N, library F = [{}, {}] N",
        lib.fx_n, lib.fy_n
    );
    assert!(
        (f[0] - lib.fx_n).abs() <= 1e-9 * lib.fx_n.abs().max(1.0)
            && (f[1] - lib.fy_n).abs() <= 1e-9 * lib.fy_n.abs().max(1.0)
    );
    // The film pushes the journal back towards the centre (negative radial component).
    let j = orbit(n as f64 * h);
    assert!(
        f[0] * j.dx_m + f[1] * j.dy_m < 0.0,
        "the film force must have a restoring radial component"
    );
    let mut d = [0.0; 2];
    s.get_real_output_derivatives(&[vr::FX, vr::FY], &[1, 1], &mut d)
        .unwrap();
    assert!(d[0].is_finite() && d[1].is_finite() && d != [0.0, 0.0]);
}

#[test]
fn two_instances_and_state_round_trips_are_bit_identical() {
    let fmu = load("airfilm");
    let book = LogBook::default();
    let a = start(&fmu, &book, "a");
    let b = start(&fmu, &book, "b");
    let h = 1e-5;
    let mut saved = None;
    let mut reference = vec![];
    for k in 0..20 {
        let t = k as f64 * h;
        if k == 10 {
            let st = a.get_state().unwrap();
            saved = Some(a.serialize_state(&st).unwrap());
        }
        for s in [&a, &b] {
            set_inputs(s, t);
            s.do_step(t, h).unwrap();
        }
        assert_eq!(forces(&a).map(f64::to_bits), forces(&b).map(f64::to_bits));
        if k >= 10 {
            reference.push(forces(&a).map(f64::to_bits));
        }
    }
    let st = b.deserialize_state(&saved.unwrap()).unwrap();
    b.set_state(&st).unwrap();
    for k in 10..20 {
        let t = k as f64 * h;
        set_inputs(&b, t);
        b.do_step(t, h).unwrap();
        assert_eq!(forces(&b).map(f64::to_bits), reference[k - 10], "step {k}");
    }
}

fn exit_init_fails(set: impl FnOnce(&Slave), reason: &str) {
    let fmu = load("airfilm");
    let book = LogBook::default();
    let s = fmu.instantiate("bad", false, book.handler()).unwrap();
    s.setup_experiment(None, 0.0, None).unwrap();
    s.enter_initialization_mode().unwrap();
    set(&s);
    assert_eq!(
        s.exit_initialization_mode().unwrap_err().status,
        Status::Error
    );
    assert!(
        book.contains(reason),
        "expected '{reason}' in {:?}",
        book.0.lock().unwrap()
    );
    // No model, no outputs: reading them is an error, not zeros with fmi2OK.
    let e = s.get_real(&[vr::H_MIN], &mut [0.0]).unwrap_err();
    assert_eq!(e.status, Status::Error);
    assert!(book.contains("no values to read: the model could not be initialized"));
}

#[test]
fn non_physical_parameters_are_refused_with_a_reason() {
    exit_init_fails(|s| s.set_real(&[vr::C], &[0.0]).unwrap(), "C");
    // In the FMU's units, as a user of the FMU alone reads them (not bare SI:
    // "C = -0.000001: must be > 0").
    exit_init_fails(
        |s| s.set_real(&[vr::C], &[-1e-6]).unwrap(),
        "parameter C = -1e-6 m (-1 um): must be > 0",
    );
    exit_init_fails(|s| s.set_real(&[vr::PHI_T], &[2.5]).unwrap(), "phi_t");
    // Below the declared minimum (4 per lobe, 2 across): refused already by fmi2SetInteger, so a
    // master that trusts the modelDescription's range never reaches a failing initialization.
    let fmu = load("airfilm");
    let s = fmu
        .instantiate("mesh", false, LogBook::default().handler())
        .unwrap();
    s.setup_experiment(None, 0.0, None).unwrap();
    assert!(s.set_integer(&[vr::N_ELEM_PHI], &[3]).is_err());
    assert!(s.set_integer(&[vr::N_ELEM_Z], &[1]).is_err());
    // Inside the range but too coarse for a plain bore: refused when initialization ends.
    exit_init_fails(
        |s| {
            s.set_boolean(&[vr::PLAIN_BORE], &[true]).unwrap();
            s.set_real(&[vr::DH], &[0.0]).unwrap();
            s.set_integer(&[vr::N_ELEM_PHI], &[4]).unwrap()
        },
        "n_elem_phi",
    );
    // Inside the declared ranges but beyond memory: refused, the host process lives on (before:
    // a 193 GB allocation aborted it). Numbers in messages are short (1e300, not 300 digits).
    exit_init_fails(
        |s| {
            s.set_integer(&[vr::N_ELEM_PHI, vr::N_ELEM_Z], &[2000, 500])
                .unwrap()
        },
        "mesh n_elem_phi x n_elem_z = 2000 x 500 per lobe needs ~",
    );
    exit_init_fails(|s| s.set_real(&[vr::R], &[1e300]).unwrap(), "r = 1e300 m");
    exit_init_fails(
        |s| s.set_real(&[vr::H_MAX], &[-1.0]).unwrap(),
        "h_max = -1 s (-1000 ms): largest sub-step must be >= 1e-12 s",
    );
    // An orientation beyond a turn and a penalty beyond any contact (before: taken).
    exit_init_fails(
        |s| s.set_real(&[vr::ALPHA], &[1e300]).unwrap(),
        "alpha = 1e300 rad",
    );
    exit_init_fails(
        |s| s.set_real(&[vr::C_CON], &[1e300]).unwrap(),
        "c_con = 1e300 N/m3 (1e291 N/mm3): must be at most 1e20 N/m3",
    );
    // Absurd magnitudes (before: accepted; r = 1e300 m made a discarded step's forces inf).
    exit_init_fails(|s| s.set_real(&[vr::C], &[1e300]).unwrap(), "C");
    exit_init_fails(|s| s.set_real(&[vr::P_A], &[1e300]).unwrap(), "p_a");
    exit_init_fails(|s| s.set_real(&[vr::R], &[1e300]).unwrap(), "r");
    exit_init_fails(|s| s.set_real(&[vr::ETA], &[1e300]).unwrap(), "eta");
    // A clearance that is no thin film any more: C above a tenth of the radius.
    exit_init_fails(
        |s| s.set_real(&[vr::C], &[5e-3]).unwrap(),
        "tenth of the radius",
    );
    // A journal already beyond the contact limit (gap closed) at the start.
    exit_init_fails(
        |s| s.set_real(&[vr::DY], &[-100e-6]).unwrap(),
        "contact limit",
    );
}

#[test]
fn bad_inputs_are_refused() {
    let fmu = load("airfilm");
    let book = LogBook::default();
    let s = start(&fmu, &book, "film");
    assert!(s.set_real(&[vr::DX], &[f64::NAN]).is_err());
    assert!(s.set_real(&[vr::OMEGA], &[f64::INFINITY]).is_err());
    // Driving the journal into the ring within a step is an error with the reason, not a NaN.
    s.set_real(&[vr::DY], &[-10e-6]).unwrap();
    s.set_real_input_derivatives(&[vr::DY], &[1], &[-100.0])
        .unwrap();
    let e = s.do_step(0.0, 1e-5).unwrap_err();
    assert!(matches!(e.status, Status::Error | Status::Discard));
    assert!(
        book.contains("contact limit") || book.contains("Newton"),
        "{:?}",
        book.0.lock().unwrap()
    );
    let f = forces(&s);
    assert!(f[0].is_finite() && f[1].is_finite());
}

/// libcosim's order of calls: parameters, fmi2EnterInitializationMode, then every output read
/// before any input is set (the journal centred, omega = 0). With `start_steady` the film starts
/// from its steady state, which at omega = 0 is ambient pressure: no force, and the run goes on.
/// (Before the fix the steady solve waited for a residual below round-off: "did not converge in
/// 200 iterations (residual 1.37e-14)", and libcosim aborted the process.)
#[test]
fn start_steady_at_rest_reads_no_force_before_any_input() {
    let fmu = load("airfilm");
    let book = LogBook::default();
    let s = fmu
        .instantiate("film", false, book.handler())
        .expect("instantiate");
    s.setup_experiment(None, 0.0, None).unwrap();
    s.set_boolean(&[vr::START_STEADY], &[true]).unwrap();
    s.enter_initialization_mode().unwrap();
    let mut f = [f64::NAN; 2];
    s.get_real(&[vr::FX, vr::FY], &mut f).unwrap();
    assert!(f[0].abs() < 1e-9 && f[1].abs() < 1e-9, "{f:?}");
    s.exit_initialization_mode().unwrap();
    s.do_step(0.0, 1e-4).unwrap();
    s.get_real(&[vr::FX, vr::FY], &mut f).unwrap();
    assert!(f[0].abs() < 1e-9 && f[1].abs() < 1e-9, "{f:?}");
}

/// fmi2SetupExperiment's tolerance sets the film's rtol (and atol in proportion) unless the
/// master sets rtol / atol itself (before: 1e-2, 1e-8 and no tolerance gave bit-identical
/// forces). Checked against runs given the rtol / atol the rule says.
#[test]
fn the_experiment_tolerance_sets_rtol_unless_the_master_sets_it() {
    let fmu = load("airfilm");
    let run = |tolerance: Option<f64>, explicit: Option<[f64; 2]>| -> Vec<[f64; 2]> {
        let book = LogBook::default();
        let s = fmu.instantiate("tol", false, book.handler()).unwrap();
        s.setup_experiment(tolerance, 0.0, None).unwrap();
        s.enter_initialization_mode().unwrap();
        if let Some([rtol, atol]) = explicit {
            s.set_real(&[vr::RTOL, vr::ATOL], &[rtol, atol]).unwrap();
        }
        set_inputs(&s, 0.0);
        s.exit_initialization_mode().unwrap();
        let h = 2e-5;
        (0..20)
            .map(|k| {
                let t = k as f64 * h;
                set_inputs(&s, t);
                s.do_step(t, h).unwrap();
                forces(&s)
            })
            .collect()
    };
    let d = BearingParams::default();
    let none = run(None, None);
    let loose = run(Some(1e-2), None);
    let tight = run(Some(1e-8), None);
    assert!(
        loose != tight && tight != none,
        "the tolerance changes the result"
    );
    // The rule: rtol = tolerance, atol scaled with it from its default.
    assert_eq!(none, run(None, Some([d.rtol, d.atol_pa])));
    assert_eq!(tight, run(None, Some([1e-8, d.atol_pa * 1e-8 / d.rtol])));
    // The master's own rtol / atol win over the tolerance.
    assert_eq!(
        run(Some(1e-8), Some([1e-3, 50.0])),
        run(None, Some([1e-3, 50.0]))
    );
}

/// What `dependencies=""` on the outputs declares: an input set in step mode changes no output
/// before the next doStep (modelDescription's Outputs; model_descriptions.rs).
#[test]
fn an_input_set_in_step_mode_changes_no_output_before_the_next_step() {
    let fmu = load("airfilm");
    let book = LogBook::default();
    let s = start(&fmu, &book, "film");
    set_inputs(&s, 0.0);
    s.do_step(0.0, 1e-5).unwrap();
    let outputs = [vr::FX, vr::FY, vr::EPS, vr::H_MIN, vr::P_MAX, vr::F_CONTACT];
    let mut before = [0.0; 6];
    s.get_real(&outputs, &mut before).unwrap();
    s.set_real(&[vr::DX, vr::DY, vr::OMEGA], &[3e-6, -4e-6, 100.0])
        .unwrap();
    let mut after = [0.0; 6];
    s.get_real(&outputs, &mut after).unwrap();
    assert_eq!(before.map(f64::to_bits), after.map(f64::to_bits));
    // The next step does take the new inputs.
    s.do_step(1e-5, 1e-5).unwrap();
    s.get_real(&outputs, &mut after).unwrap();
    assert_ne!(before[2], after[2], "eps follows the new journal position");
}

/// A tolerance below what the film's Newton iteration reaches in double precision (1e-10) is
/// refused by fmi2SetupExperiment, naming the tolerance; at 1e-11 the film failed its first step
/// with a Newton failure at t = 0 (FMPy's `relative_tolerance`). 1e-10 runs.
#[test]
fn a_tolerance_the_film_cannot_reach_is_refused_where_it_is_given() {
    let fmu = load("airfilm");
    let book = LogBook::default();
    let s = fmu.instantiate("tol", false, book.handler()).unwrap();
    let e = s.setup_experiment(Some(1e-11), 0.0, None).unwrap_err();
    assert_eq!(e.status, Status::Error);
    assert!(
        book.contains("tolerance 1e-11 is below 1e-10"),
        "{:?}",
        book.0.lock().unwrap()
    );
    // The instance is still usable: the smallest tolerance runs an eccentric whirl.
    s.setup_experiment(Some(1e-10), 0.0, None).unwrap();
    s.enter_initialization_mode().unwrap();
    set_inputs(&s, 0.0);
    s.exit_initialization_mode().unwrap();
    let h = 1e-5;
    for k in 0..10 {
        let t = k as f64 * h;
        set_inputs(&s, t);
        s.do_step(t, h).unwrap();
    }
    assert!(forces(&s).iter().all(|f| f.is_finite() && *f != 0.0));
}
