//! `rotor.fmu` through the C ABI: run-up outputs, output derivatives, states, bad input.

use fmi2::importer::Slave;
use fmi_core::Status;
use fmu_rotor::shell::vr;
use integration_tests::{initialized, load, LogBook};

fn get(s: &Slave, vrs: &[u32]) -> Vec<f64> {
    let mut v = vec![0.0; vrs.len()];
    s.get_real(vrs, &mut v).unwrap();
    v
}

#[test]
fn run_up_speed_gravity_sag_and_output_derivatives() {
    let fmu = load("rotor");
    let book = LogBook::default();
    let s = initialized(&fmu, "rotor", &book, |_| {});
    let h = 1e-5;
    for k in 0..300 {
        s.do_step(k as f64 * h, h).unwrap();
    }
    let t = 300.0 * h;
    let omega = get(&s, &[vr::OMEGA])[0];
    let expected = std::f64::consts::TAU * 2000.0 * t / 3.0;
    assert!(
        (omega - expected).abs() < 1e-9 * expected,
        "omega {omega} vs {expected}"
    );
    // No film forces: journals and rings fall under gravity, the journal relative to the ring too.
    let y = get(&s, &[vr::Y_JC, vr::Y_JT, vr::DY_C, vr::DY_T]);
    assert!(y.iter().all(|v| *v < 0.0), "{y:?}");
    // dy_C(t) from its output derivative matches a finite difference over one step.
    let v0 = get(&s, &[vr::DY_C])[0];
    let mut d = [0.0; 2];
    s.get_real_output_derivatives(&[vr::DY_C, vr::OMEGA], &[1, 1], &mut d)
        .unwrap();
    s.do_step(t, h).unwrap();
    let v1 = get(&s, &[vr::DY_C])[0];
    let fd = (v1 - v0) / h;
    assert!(
        (d[0] - fd).abs() < 0.01 * fd.abs(),
        "derivative {} vs finite difference {fd}",
        d[0]
    );
    assert!((d[1] - std::f64::consts::TAU * 2000.0 / 3.0).abs() < 1e-6);
}

#[test]
fn states_round_trip_bit_identically() {
    let fmu = load("rotor");
    let book = LogBook::default();
    let s = initialized(&fmu, "rotor", &book, |_| {});
    let h = 1e-5;
    let force = |t: f64| [(3e3 * t).sin(), 2.0 + t, -1.0, 0.5];
    let step = |s: &Slave, k: usize| {
        let t = k as f64 * h;
        s.set_real(&[vr::F_C_X, vr::F_C_Y, vr::F_T_X, vr::F_T_Y], &force(t))
            .unwrap();
        s.do_step(t, h).unwrap();
        get(s, &[vr::DX_C, vr::DY_C, vr::DX_T, vr::DY_T])
            .iter()
            .map(|v| v.to_bits())
            .collect::<Vec<_>>()
    };
    for k in 0..10 {
        step(&s, k);
    }
    let st = s.get_state().unwrap();
    let bytes = s.serialize_state(&st).unwrap();
    let reference: Vec<_> = (10..30).map(|k| step(&s, k)).collect();
    s.set_state(&st).unwrap();
    assert_eq!((10..30).map(|k| step(&s, k)).collect::<Vec<_>>(), reference);
    let other = initialized(&fmu, "other", &book, |_| {});
    other
        .set_state(&other.deserialize_state(&bytes).unwrap())
        .unwrap();
    assert_eq!(
        (10..30).map(|k| step(&other, k)).collect::<Vec<_>>(),
        reference
    );
}

#[test]
fn bad_parameters_and_inputs_are_refused_with_a_reason() {
    let fmu = load("rotor");
    for (vr, value, reason) in [
        (vr::M, -0.1, "m"),
        (vr::J_P, 0.0, "J"),
        (vr::C_C, -5.0, "c"),
        // In the FMU's units, not bare SI ("c_C = -5000: must be >= 0").
        (vr::C_C, -5000.0, "c_C = -5000 N/m (-5 N/mm): must be >= 0"),
        (vr::T_RAMP, 0.0, "t_ramp"),
    ] {
        let book = LogBook::default();
        let s = fmu.instantiate("bad", false, book.handler()).unwrap();
        s.setup_experiment(None, 0.0, None).unwrap();
        s.enter_initialization_mode().unwrap();
        s.set_real(&[vr], &[value]).unwrap();
        assert_eq!(
            s.exit_initialization_mode().unwrap_err().status,
            Status::Error,
            "{reason} = {value}"
        );
        assert!(
            book.contains(reason),
            "{reason}: {:?}",
            book.0.lock().unwrap()
        );
    }
    let book = LogBook::default();
    let s = initialized(&fmu, "rotor", &book, |_| {});
    assert!(s.set_real(&[vr::F_C_X], &[f64::NAN]).is_err());
    assert!(book.contains("not finite"));
}

/// The rotor starts at t = 0 only. Another start time is refused at the call that gives it,
/// fmi2SetupExperiment (not only when initialization ends), naming it; the
/// instance then still takes a start at 0 and runs.
#[test]
fn a_start_time_other_than_zero_is_refused_where_it_is_given() {
    let fmu = load("rotor");
    let book = LogBook::default();
    let s = fmu.instantiate("late", false, book.handler()).unwrap();
    for start in [1.0, -0.5] {
        assert_eq!(
            s.setup_experiment(None, start, None).unwrap_err().status,
            Status::Error,
            "startTime {start}"
        );
    }
    assert!(
        book.contains("fmi2SetupExperiment")
            && book.contains("startTime 1 s is not supported")
            && book.contains("starts at t = 0"),
        "{:?}",
        book.0.lock().unwrap()
    );
    s.setup_experiment(None, 0.0, None).unwrap();
    s.enter_initialization_mode().unwrap();
    s.exit_initialization_mode().unwrap();
    s.do_step(0.0, 1e-5).unwrap();
}

/// A tolerance below what the rotor's BDF2 reaches in double precision (1e-12) is refused by
/// fmi2SetupExperiment, naming the tolerance (at 1e-14 the rotor failed its first steps).
#[test]
fn a_tolerance_the_rotor_cannot_reach_is_refused_where_it_is_given() {
    let fmu = load("rotor");
    let book = LogBook::default();
    let s = fmu.instantiate("tol", false, book.handler()).unwrap();
    let e = s.setup_experiment(Some(1e-13), 0.0, None).unwrap_err();
    assert_eq!(e.status, Status::Error);
    assert!(
        book.contains("tolerance 1e-13 is below 1e-12"),
        "{:?}",
        book.0.lock().unwrap()
    );
    s.setup_experiment(Some(1e-12), 0.0, None).unwrap();
    s.enter_initialization_mode().unwrap();
    s.exit_initialization_mode().unwrap();
    s.do_step(0.0, 1e-5).unwrap();
}
