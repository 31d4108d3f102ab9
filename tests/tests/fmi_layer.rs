//! The FMI layer through the real C ABI of the packed test FMU (`oscillator.fmu`): lifecycle, call
//! checks, input derivatives, FMU states, panics, and several instances per process.

use fmi_core::Status;
use fmu_oscillator::vr;
use integration_tests::{initialized, load, LogBook};
use std::f64::consts::PI;

const W: f64 = 2.0 * PI; // default k = 4 pi^2, m = 1

fn x_of(s: &fmi2::importer::Slave) -> f64 {
    let mut x = [0.0];
    s.get_real(&[vr::X], &mut x).unwrap();
    x[0]
}

#[test]
fn constant_force_matches_closed_form() {
    let fmu = load("oscillator");
    let book = LogBook::default();
    let s = initialized(&fmu, "osc", &book, |s| {
        s.set_real(&[vr::F], &[2.0]).unwrap()
    });
    let h = 0.01;
    for n in 0..37 {
        s.do_step(n as f64 * h, h).unwrap();
    }
    let t = 0.37;
    let exact = 2.0 / (W * W) * (1.0 - (W * t).cos());
    assert!(
        (x_of(&s) - exact).abs() < 1e-14,
        "x = {} vs {exact}",
        x_of(&s)
    );
    s.terminate().unwrap();
}

#[test]
fn inputs_follow_the_taylor_polynomial_of_input_derivatives() {
    // F(t) = a t set as value + first derivative at each communication point: exact for a ramp.
    let fmu = load("oscillator");
    let book = LogBook::default();
    let s = initialized(&fmu, "osc", &book, |_| {});
    let (a, h) = (3.0, 0.05);
    for n in 0..20 {
        let t = n as f64 * h;
        s.set_real(&[vr::F], &[a * t]).unwrap();
        s.set_real_input_derivatives(&[vr::F], &[1], &[a]).unwrap();
        s.do_step(t, h).unwrap();
    }
    let t = 1.0;
    let exact = a / (W * W) * (t - (W * t).sin() / W);
    assert!(
        (x_of(&s) - exact).abs() < 1e-13,
        "ramp: x = {} vs {exact}",
        x_of(&s)
    );

    // Without derivatives the same inputs are held constant over each step: a visibly different answer.
    // (Compared at t = 0.75: at whole periods of the oscillator the two happen to coincide.)
    let s0 = initialized(&fmu, "osc0", &book, |_| {});
    for n in 0..15 {
        let t = n as f64 * h;
        s0.set_real(&[vr::F], &[a * t]).unwrap();
        s0.do_step(t, h).unwrap();
    }
    let t0 = 0.75;
    let exact0 = a / (W * W) * (t0 - (W * t0).sin() / W);
    assert!(
        (x_of(&s0) - exact0).abs() > 1e-4,
        "zero-order hold should differ from the ramp"
    );

    // A quadratic F = c t^2 / 2 through the second derivative.
    let s2 = initialized(&fmu, "osc2", &book, |_| {});
    let c = 5.0;
    for n in 0..20 {
        let t = n as f64 * h;
        s2.set_real(&[vr::F], &[c * t * t / 2.0]).unwrap();
        s2.set_real_input_derivatives(&[vr::F, vr::F], &[1, 2], &[c * t, c])
            .unwrap();
        s2.do_step(t, h).unwrap();
    }
    // x'' + w^2 x = c t^2/2: x = c/(2 w^2) (t^2 - 2/w^2 (1 - cos w t)).
    let exact2 = c / (2.0 * W * W) * (t * t - 2.0 / (W * W) * (1.0 - (W * t).cos()));
    assert!(
        (x_of(&s2) - exact2).abs() < 1e-13,
        "quadratic: {} vs {exact2}",
        x_of(&s2)
    );
}

#[test]
fn output_derivatives() {
    let fmu = load("oscillator");
    let book = LogBook::default();
    let s = initialized(&fmu, "osc", &book, |s| {
        s.set_real(&[vr::X0], &[0.5]).unwrap()
    });
    s.do_step(0.0, 0.1).unwrap();
    let mut xv = [0.0; 2];
    s.get_real(&[vr::X, vr::V], &mut xv).unwrap();
    let mut d = [0.0; 2];
    s.get_real_output_derivatives(&[vr::X, vr::V], &[1, 1], &mut d)
        .unwrap();
    assert_eq!(d[0], xv[1]);
    assert!((d[1] + W * W * xv[0]).abs() < 1e-12);
    let before = book.len();
    assert_eq!(
        s.get_real_output_derivatives(&[vr::X], &[2], &mut d[..1])
            .unwrap_err()
            .status,
        Status::Error
    );
    assert!(book.len() > before && book.contains("not provided"));
}

#[test]
fn wrong_call_order_is_refused_with_a_reason() {
    let fmu = load("oscillator");
    let book = LogBook::default();
    let s = fmu.instantiate("osc", false, book.handler()).unwrap();
    assert_eq!(s.do_step(0.0, 0.1).unwrap_err().status, Status::Error);
    assert!(book.contains("fmi2DoStep: not allowed in state 'instantiated'"));
    assert_eq!(
        s.exit_initialization_mode().unwrap_err().status,
        Status::Error
    );
    assert_eq!(s.terminate().unwrap_err().status, Status::Error);
    // A relative tolerance of 1 or more is refused where it is given, naming it.
    for tol in [1.0, 2.0, 0.0, f64::NAN] {
        assert_eq!(
            s.setup_experiment(Some(tol), 0.0, Some(1.0))
                .unwrap_err()
                .status,
            Status::Error
        );
    }
    assert!(book.contains("tolerance 2 must lie in (0, 1)"));
    // The instance is still usable after refused calls.
    s.setup_experiment(None, 0.0, Some(1.0)).unwrap();
    s.enter_initialization_mode().unwrap();
    assert_eq!(
        s.setup_experiment(None, 0.0, None).unwrap_err().status,
        Status::Error
    );
    s.exit_initialization_mode().unwrap();
    // Parameters are fixed after initialization.
    assert_eq!(
        s.set_real(&[vr::K], &[1.0]).unwrap_err().status,
        Status::Error
    );
    assert!(book.contains("cannot be set in state 'step complete'"));
    // Outputs are never settable.
    assert_eq!(
        s.set_real(&[vr::X], &[1.0]).unwrap_err().status,
        Status::Error
    );
    s.do_step(0.0, 0.5).unwrap();
    // Past the stop time.
    assert_eq!(s.do_step(0.5, 0.6).unwrap_err().status, Status::Error);
    assert!(book.contains("stopTime"));
    s.terminate().unwrap();
    assert_eq!(s.do_step(0.5, 0.1).unwrap_err().status, Status::Error);
    s.reset().unwrap();
    s.setup_experiment(None, 0.0, None).unwrap();
}

#[test]
fn bad_values_and_references_are_refused_and_change_nothing() {
    let fmu = load("oscillator");
    let book = LogBook::default();
    let s = initialized(&fmu, "osc", &book, |_| {});
    for bad in [f64::NAN, f64::INFINITY, f64::NEG_INFINITY] {
        let n = book.len();
        assert_eq!(
            s.set_real(&[vr::F], &[bad]).unwrap_err().status,
            Status::Error
        );
        assert!(book.len() > n, "refusal of {bad} must be logged");
    }
    assert!(book.contains("is not finite"));
    // A batch with one bad value changes none of them.
    s.set_real(&[vr::F], &[1.0]).unwrap();
    assert!(s.set_real(&[vr::F, 99], &[7.0, 1.0]).is_err());
    assert!(book.contains("unknown Real value reference 99"));
    let mut f = [0.0];
    s.get_real(&[vr::F], &mut f).unwrap();
    assert_eq!(f[0], 1.0);
    assert!(s.get_real(&[1000], &mut f).is_err());
    assert!(s.get_integer(&[77], &mut [0]).is_err());
    // Out-of-range parameter before initialization.
    let p = fmu.instantiate("p", false, book.handler()).unwrap();
    assert!(p.set_real(&[vr::M], &[-1.0]).is_err());
    assert!(book.contains("below its minimum"));
    // Step size and communication point.
    assert!(s.do_step(0.0, 0.0).is_err());
    assert!(s.do_step(0.0, -0.1).is_err());
    assert!(s.do_step(0.0, f64::NAN).is_err());
    assert!(book.contains("communicationStepSize"));
    assert!(s.do_step(0.3, 0.1).is_err());
    assert!(book.contains("does not match the FMU time"));
    s.do_step(0.0, 0.1).unwrap();
}

#[test]
fn wrong_guid_is_refused() {
    let fmu = load("oscillator");
    let book = LogBook::default();
    let r = fmi2::importer::Slave::instantiate(
        fmu.api.clone(),
        "{not-the-guid}",
        "",
        "x",
        false,
        book.handler(),
    );
    assert!(r.is_err());
    assert!(book.contains("does not match"));
}

#[test]
fn two_instances_are_independent_and_identical() {
    let fmu = load("oscillator");
    let book = LogBook::default();
    let a = initialized(&fmu, "a", &book, |s| s.set_real(&[vr::X0], &[0.1]).unwrap());
    let b = initialized(&fmu, "b", &book, |s| s.set_real(&[vr::X0], &[0.1]).unwrap());
    let c = initialized(&fmu, "c", &book, |s| {
        s.set_real(&[vr::X0], &[-3.0]).unwrap()
    });
    let h = 0.013;
    for n in 0..50 {
        let t = n as f64 * h;
        for s in [&a, &c, &b] {
            s.set_real(&[vr::F], &[(t * 7.0).sin()]).unwrap();
            s.do_step(t, h).unwrap();
        }
    }
    assert_eq!(x_of(&a).to_bits(), x_of(&b).to_bits());
    assert_ne!(x_of(&a), x_of(&c));
    // A second load of the same FMU in the process works too.
    let fmu2 = load("oscillator");
    let d = initialized(&fmu2, "d", &book, |_| {});
    d.do_step(0.0, 0.1).unwrap();
}

fn run_from(s: &fmi2::importer::Slave, t0: f64, n: usize) -> Vec<u64> {
    let h = 0.01;
    (0..n)
        .map(|k| {
            let t = t0 + k as f64 * h;
            s.set_real(&[vr::F], &[(3.0 * t).cos()]).unwrap();
            s.set_real_input_derivatives(&[vr::F], &[1], &[-3.0 * (3.0 * t).sin()])
                .unwrap();
            s.do_step(t, h).unwrap();
            x_of(s).to_bits()
        })
        .collect()
}

#[test]
fn states_round_trip_bit_identically() {
    let fmu = load("oscillator");
    let book = LogBook::default();
    let s = initialized(&fmu, "s", &book, |_| {});
    run_from(&s, 0.0, 10);
    let state = s.get_state().unwrap();
    let bytes = s.serialize_state(&state).unwrap();
    let reference = run_from(&s, 0.1, 20);

    s.set_state(&state).unwrap();
    assert_eq!(run_from(&s, 0.1, 20), reference, "get/set state");

    // Deserialized into a fresh instance.
    let other = initialized(&fmu, "other", &book, |_| {});
    let restored = other.deserialize_state(&bytes).unwrap();
    other.set_state(&restored).unwrap();
    assert_eq!(
        run_from(&other, 0.1, 20),
        reference,
        "serialize/deserialize"
    );
    // Serializing the restored state gives the same bytes.
    assert_eq!(other.serialize_state(&restored).unwrap(), bytes);
}

#[test]
fn bad_state_bytes_are_refused() {
    let fmu = load("oscillator");
    let book = LogBook::default();
    let s = initialized(&fmu, "s", &book, |_| {});
    let bytes = s.serialize_state(&s.get_state().unwrap()).unwrap();
    for cut in [0, 5, 16, bytes.len() / 2, bytes.len() - 1] {
        assert!(
            s.deserialize_state(&bytes[..cut]).is_err(),
            "truncated at {cut}"
        );
    }
    let mut flipped = bytes.clone();
    let mid = flipped.len() / 2;
    flipped[mid] ^= 0x40;
    assert!(s.deserialize_state(&flipped).is_err());
    assert!(s
        .deserialize_state(b"definitely not an FMU state, just some bytes")
        .is_err());
    assert!(book.contains("truncated") && book.contains("not an AirRing FMU state"));
}

#[test]
fn a_panic_in_the_model_is_contained() {
    let fmu = load("oscillator");
    let book = LogBook::default();
    let bystander = initialized(&fmu, "bystander", &book, |_| {});
    let s = initialized(&fmu, "faulty", &book, |s| {
        s.set_integer(&[vr::FAULT_MODE], &[1]).unwrap();
        s.set_real(&[vr::FAULT_TIME], &[0.05]).unwrap();
    });
    s.do_step(0.0, 0.05).unwrap();
    assert_eq!(s.do_step(0.05, 0.05).unwrap_err().status, Status::Error);
    assert!(book.contains("panic caught") && book.contains("injected fault"));
    // Error state: only reset/free (and reads) are allowed.
    assert!(s.do_step(0.05, 0.05).is_err());
    x_of(&s);
    bystander.do_step(0.0, 0.1).unwrap();
    s.reset().unwrap();
}

#[test]
fn discard_reports_last_successful_time_and_rolls_back() {
    let fmu = load("oscillator");
    let book = LogBook::default();
    let s = initialized(&fmu, "d", &book, |s| {
        s.set_integer(&[vr::FAULT_MODE], &[2]).unwrap();
        s.set_real(&[vr::FAULT_TIME], &[0.25]).unwrap();
    });
    s.do_step(0.0, 0.2).unwrap();
    let before = s.get_state().unwrap();
    let e = s.do_step(0.2, 0.1).unwrap_err();
    assert_eq!(e.status, Status::Discard);
    assert_eq!(s.last_successful_time().unwrap(), 0.2);
    assert_eq!(book.last().unwrap().status, Status::Discard);
    s.set_state(&before).unwrap();
    s.do_step(0.2, 0.04).unwrap();
}

#[test]
fn debug_logging_categories() {
    let fmu = load("oscillator");
    let book = LogBook::default();
    let s = initialized(&fmu, "log", &book, |_| {});
    s.do_step(0.0, 0.1).unwrap();
    assert!(
        !book.contains("step 0 ->"),
        "debug logging is off by default"
    );
    s.set_debug_logging(true, &["logSteps"]).unwrap();
    s.do_step(0.1, 0.1).unwrap();
    assert!(book.contains("step 0.1 ->"));
    // An unknown category is a warning, not an error.
    s.set_debug_logging(true, &["noSuchCategory"]).unwrap();
    assert!(book.contains("unknown log categories"));
}
