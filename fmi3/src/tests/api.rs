//! Instantiation, values, stepping, call-state rules, panics and logging through the C functions.

use super::fmi3_exports::*;
use super::fmu::{token, Fmu};
use super::lag::{vr, Lag};
use crate::types::*;
use crate::value_refs::{BOOLEAN_VR_OFFSET, INT32_VR_OFFSET, TIME_VR};
use std::ffi::{CStr, CString};

const STEPS: u32 = INT32_VR_OFFSET + vr::STEPS;
const FAULT_MODE: u32 = INT32_VR_OFFSET + vr::FAULT_MODE;
const FROZEN: u32 = BOOLEAN_VR_OFFSET + vr::FROZEN;

#[test]
fn version_is_3_0() {
    // SAFETY: a static NUL-terminated string.
    assert_eq!(
        unsafe { CStr::from_ptr(fmi3GetVersion()) }
            .to_str()
            .unwrap(),
        "3.0"
    );
}

#[test]
fn two_instances_step_side_by_side() {
    let a = Fmu::started("a", &[(vr::TAU, 0.5), (vr::Y0, 1.0)]);
    let b = Fmu::started("b", &[(vr::TAU, 0.2)]);
    let (h, mut ya, mut yb) = (0.01, 1.0, 0.0);
    for n in 0..50 {
        let t = n as f64 * h;
        assert_eq!(b.set_f64(&[vr::U], &[2.0]), FMI3_OK);
        assert_eq!(a.step(t, h).0, FMI3_OK);
        assert_eq!(b.step(t, h), (FMI3_OK, t + h, false));
        ya = Lag::exact(ya, 0.0, 0.5, h);
        yb = Lag::exact(yb, 2.0, 0.2, h);
    }
    let (s, y) = a.get_f64(&[vr::Y, TIME_VR]);
    assert_eq!(s, FMI3_OK);
    assert_eq!(y[0].to_bits(), ya.to_bits());
    assert!((y[1] - 0.5).abs() < 1e-12, "time {}", y[1]);
    assert_eq!(b.get_f64(&[vr::Y]).1[0].to_bits(), yb.to_bits());
    assert_eq!(a.get_i32(&[STEPS]), (FMI3_OK, vec![50]));
    assert_eq!(fmi3Terminate(a.instance), FMI3_OK);
    // b is unaffected by a's termination.
    assert_eq!(b.step(0.5, h).0, FMI3_OK);
}

#[test]
fn int32_and_boolean_use_their_own_value_references() {
    let f = Fmu::new("types");
    assert_eq!(f.set_i32(&[FAULT_MODE], &[0]), FMI3_OK);
    let on = [true];
    // SAFETY: arrays of length 1.
    assert_eq!(
        unsafe { fmi3SetBoolean(f.instance, &FROZEN, 1, on.as_ptr(), 1) },
        FMI3_OK
    );
    assert_eq!(
        fmi3EnterInitializationMode(f.instance, false, 0.0, 0.0, false, 0.0),
        FMI3_OK
    );
    let mut back = [false];
    // SAFETY: arrays of length 1.
    assert_eq!(
        unsafe { fmi3GetBoolean(f.instance, &FROZEN, 1, back.as_mut_ptr(), 1) },
        FMI3_OK
    );
    assert!(back[0]);
    assert_eq!(f.get_i32(&[FAULT_MODE, STEPS]), (FMI3_OK, vec![0, 0]));
    // An Int32 reference is not a Float64 one, and the fmi2 numbers are not FMI 3.0 ones.
    assert_eq!(f.get_f64(&[FAULT_MODE]).0, FMI3_ERROR);
    assert!(
        f.last_message().contains("is of type Int32, not Float64"),
        "{}",
        f.last_message()
    );
    assert_eq!(f.get_i32(&[vr::STEPS]).0, FMI3_ERROR);
    // No String variables: an empty request is fine, any reference is unknown.
    let mut s: [fmi3String; 1] = [std::ptr::null()];
    // SAFETY: arrays of the given lengths.
    assert_eq!(
        unsafe { fmi3GetString(f.instance, [].as_ptr(), 0, s.as_mut_ptr(), 0) },
        FMI3_OK
    );
    // SAFETY: as above.
    assert_eq!(
        unsafe { fmi3GetString(f.instance, &0, 1, s.as_mut_ptr(), 1) },
        FMI3_ERROR
    );
    // Frozen output: y stays at y0.
    assert_eq!(fmi3ExitInitializationMode(f.instance), FMI3_OK);
    assert_eq!(f.set_f64(&[vr::U], &[3.0]), FMI3_OK);
    assert_eq!(f.step(0.0, 0.1).0, FMI3_OK);
    assert_eq!(f.get_f64(&[vr::Y]).1, vec![0.0]);
}

#[test]
fn output_derivatives_come_from_the_model() {
    let f = Fmu::started("der", &[(vr::TAU, 0.5), (vr::U, 1.0)]);
    assert_eq!(f.step(0.0, 0.1).0, FMI3_OK);
    let y = f.get_f64(&[vr::Y]).1[0];
    let mut d = [f64::NAN];
    // SAFETY: arrays of length 1.
    let s = unsafe { fmi3GetOutputDerivatives(f.instance, &vr::Y, 1, &1, d.as_mut_ptr(), 1) };
    assert_eq!(s, FMI3_OK);
    assert_eq!(d[0], (1.0 - y) / 0.5);
    // SAFETY: as above.
    let s = unsafe { fmi3GetOutputDerivatives(f.instance, &vr::Y, 1, &2, d.as_mut_ptr(), 1) };
    assert_eq!(s, FMI3_ERROR);
}

#[test]
fn wrong_state_calls_are_errors_and_change_nothing() {
    let f = Fmu::new("states");
    assert_eq!(f.step(0.0, 0.1).0, FMI3_ERROR);
    assert!(
        f.last_message()
            .contains("fmi3DoStep: illegal call sequence"),
        "{}",
        f.last_message()
    );
    assert_eq!(f.get_f64(&[vr::Y]).0, FMI3_ERROR, "no get in Instantiated");
    assert_eq!(fmi3ExitInitializationMode(f.instance), FMI3_ERROR);
    assert_eq!(fmi3Terminate(f.instance), FMI3_ERROR);
    assert_eq!(
        fmi3EnterInitializationMode(f.instance, false, 0.0, 0.0, false, 0.0),
        FMI3_OK
    );
    assert_eq!(
        fmi3EnterInitializationMode(f.instance, false, 0.0, 0.0, false, 0.0),
        FMI3_ERROR
    );
    assert_eq!(
        f.set_f64(&[vr::Y], &[1.0]),
        FMI3_ERROR,
        "outputs are not settable"
    );
    assert_eq!(
        f.set_f64(&[TIME_VR], &[1.0]),
        FMI3_ERROR,
        "time is not settable"
    );
    // SAFETY: nValues (2) exceeds the one value reference; both arrays are long enough.
    let s = unsafe { fmi3SetFloat64(f.instance, &vr::U, 1, [1.0, 2.0].as_ptr(), 2) };
    assert_eq!(s, FMI3_ERROR);
    assert_eq!(fmi3ExitInitializationMode(f.instance), FMI3_OK);
    assert_eq!(
        f.set_i32(&[FAULT_MODE], &[1]),
        FMI3_ERROR,
        "fixed parameter in Step Mode"
    );
    assert_eq!(f.step(0.1, 0.1).0, FMI3_ERROR, "wrong communication point");
    assert_eq!(f.step(0.0, 0.1).0, FMI3_OK, "still usable");
    assert_eq!(fmi3Terminate(f.instance), FMI3_OK);
    assert_eq!(f.step(0.1, 0.1).0, FMI3_ERROR);
    assert_eq!(f.get_f64(&[vr::Y]).0, FMI3_OK, "final values readable");
    // Functions this FMU does not provide.
    assert_eq!(fmi3EnterEventMode(f.instance), FMI3_ERROR);
    assert!(f.last_message().contains("no Event Mode"));
    assert_eq!(fmi3GetFloat32(f.instance, &0, 1, &mut 0.0, 1), FMI3_ERROR);
    assert_eq!(
        fmi3GetNumberOfVariableDependencies(f.instance, vr::Y, &mut 0),
        FMI3_ERROR
    );
    assert_eq!(fmi3Reset(f.instance), FMI3_OK);
    assert_eq!(f.set_f64(&[vr::TAU], &[1.0]), FMI3_OK, "Instantiated again");
    // A null instance is refused without a crash.
    assert_eq!(fmi3Reset(std::ptr::null_mut()), FMI3_ERROR);
    // SAFETY: null is allowed.
    unsafe { fmi3FreeInstance(std::ptr::null_mut()) };
}

#[test]
fn a_panicking_step_is_an_error_not_an_unwind() {
    let f = Fmu::new("panics");
    assert_eq!(f.set_f64(&[vr::FAULT_TIME], &[0.045]), FMI3_OK);
    assert_eq!(f.set_i32(&[FAULT_MODE], &[1]), FMI3_OK);
    assert_eq!(
        fmi3EnterInitializationMode(f.instance, false, 0.0, 0.0, false, 0.0),
        FMI3_OK
    );
    assert_eq!(fmi3ExitInitializationMode(f.instance), FMI3_OK);
    for n in 0..4 {
        assert_eq!(f.step(n as f64 * 0.01, 0.01).0, FMI3_OK);
    }
    let mut saved: fmi3FMUState = std::ptr::null_mut();
    // SAFETY: a writable handle.
    assert_eq!(unsafe { fmi3GetFMUState(f.instance, &mut saved) }, FMI3_OK);
    let (s, _, terminate) = f.step(0.04, 0.01);
    assert_eq!(s, FMI3_ERROR);
    assert!(terminate);
    assert!(
        f.last_message().contains("panic caught"),
        "{}",
        f.last_message()
    );
    assert_eq!(f.step(0.04, 0.01).0, FMI3_ERROR, "no step after an error");
    assert_eq!(
        f.get_f64(&[vr::Y]).0,
        FMI3_OK,
        "values readable for debugging"
    );
    // SAFETY: a handle from fmi3GetFMUState.
    unsafe {
        assert_eq!(
            fmi3GetFMUState(f.instance, &mut saved),
            FMI3_ERROR,
            "no state of a failed model"
        );
        assert_eq!(
            fmi3SetFMUState(f.instance, saved),
            FMI3_OK,
            "restoring recovers"
        );
        assert_eq!(f.get_i32(&[STEPS]), (FMI3_OK, vec![4]));
        assert_eq!(fmi3FreeFMUState(f.instance, &mut saved), FMI3_OK);
    }
    assert!(saved.is_null());
}

#[test]
fn a_discarded_step_needs_a_restore_or_terminate() {
    let f = Fmu::new("discards");
    assert_eq!(f.set_i32(&[FAULT_MODE], &[2]), FMI3_OK);
    assert_eq!(
        fmi3EnterInitializationMode(f.instance, false, 0.0, 0.0, false, 0.0),
        FMI3_OK
    );
    assert_eq!(fmi3ExitInitializationMode(f.instance), FMI3_OK);
    let (s, last, terminate) = f.step(0.0, 0.1);
    assert_eq!((s, last, terminate), (FMI3_DISCARD, 0.0, false));
    assert_eq!(f.step(0.0, 0.1).0, FMI3_ERROR);
    assert_eq!(fmi3Terminate(f.instance), FMI3_OK);
}

/// Whether the model, asking its fmi2 logger before formatting a debug message, hears that
/// `category` is on.
fn model_hears_on(f: &Fmu, category: &str) -> bool {
    // SAFETY: a live instance of this test's model, not inside a call.
    let shell = unsafe { crate::ffi::shell::<Lag>(f.instance) }.expect("live instance");
    // SAFETY: no FMI call is running on the instance, so nothing borrows it mutably.
    let instance = unsafe { &*shell.instance.get() };
    instance.inner.logger.enabled(category)
}

#[test]
fn logging_follows_fmi3_rules() {
    let f = Fmu::try_new("quiet", &token(), false, false).expect("instantiated");
    assert_eq!(f.step(0.0, 0.1).0, FMI3_ERROR);
    assert!(
        f.messages().is_empty(),
        "loggingOn = false: the callback is never called"
    );
    // The model's own question follows the FMI 3.0 filter: nothing is on yet.
    assert!(!model_hears_on(&f, "logSteps") && !model_hears_on(&f, "logAll"));
    let cats = [c"logStatusError".as_ptr()];
    // SAFETY: one category string.
    assert_eq!(
        unsafe { fmi3SetDebugLogging(f.instance, true, 1, cats.as_ptr()) },
        FMI3_OK
    );
    assert_eq!(f.step(0.0, 0.1).0, FMI3_ERROR);
    let m = f.messages();
    assert_eq!(m.len(), 1);
    assert_eq!((m[0].0, m[0].1.as_str()), (FMI3_ERROR, "logStatusError"));
    let cats = [c"noSuchCategory".as_ptr()];
    // SAFETY: as above.
    assert_eq!(
        unsafe { fmi3SetDebugLogging(f.instance, true, 1, cats.as_ptr()) },
        FMI3_WARNING
    );
    assert!(!model_hears_on(&f, "logSteps"));
    // Model debug messages go out in their own category once it is on.
    let cats = [c"logSteps".as_ptr()];
    // SAFETY: as above.
    assert_eq!(
        unsafe { fmi3SetDebugLogging(f.instance, true, 1, cats.as_ptr()) },
        FMI3_OK
    );
    assert!(model_hears_on(&f, "logSteps"));
    assert!(!model_hears_on(&f, "logEvents"), "only the listed category");
    assert_eq!(
        fmi3EnterInitializationMode(f.instance, false, 0.0, 0.0, false, 0.0),
        FMI3_OK
    );
    assert_eq!(fmi3ExitInitializationMode(f.instance), FMI3_OK);
    assert_eq!(f.step(0.0, 0.1).0, FMI3_OK);
    let m = f.messages();
    let last = m.last().unwrap();
    assert_eq!((last.0, last.1.as_str()), (FMI3_OK, "logSteps"));
    assert!(last.2.contains("step 0 -> 0.1"), "{}", last.2);
    // Off again for that category only; logAll switches on every one.
    // SAFETY: as above.
    assert_eq!(
        unsafe { fmi3SetDebugLogging(f.instance, false, 1, cats.as_ptr()) },
        FMI3_OK
    );
    assert!(!model_hears_on(&f, "logSteps") && model_hears_on(&f, "logStatusError"));
    let all = [c"logAll".as_ptr()];
    // SAFETY: as above.
    assert_eq!(
        unsafe { fmi3SetDebugLogging(f.instance, true, 1, all.as_ptr()) },
        FMI3_OK
    );
    assert!(model_hears_on(&f, "logSteps") && model_hears_on(&f, "logEvents"));
    // loggingOn = true at instantiation: every category is on, for the model too.
    let loud = Fmu::try_new("loud", &token(), true, false).expect("instantiated");
    assert!(model_hears_on(&loud, "logSteps"));
}

#[test]
fn instantiation_refusals() {
    let bad = CString::new("{00000000-0000-0000-0000-000000000000}").unwrap();
    let log = Fmu::try_new("bad token", &bad, true, false)
        .err()
        .expect("refused");
    assert!(log.lock().unwrap()[0].2.contains("does not match"));
    let log = Fmu::try_new("events", &token(), true, true)
        .err()
        .expect("refused");
    assert!(log.lock().unwrap()[0].2.contains("eventModeUsed"));
    let name = CString::new("me").unwrap();
    // SAFETY: valid strings, no callback.
    let me = unsafe {
        fmi3InstantiateModelExchange(
            name.as_ptr(),
            token().as_ptr(),
            std::ptr::null(),
            false,
            false,
            std::ptr::null_mut(),
            None,
        )
    };
    assert!(me.is_null());
}

#[test]
fn every_function_of_fmi3_functions_h_is_exported() {
    // The 75 functions of fmi3Functions.h (FMI 3.0.2); each must be a `#[no_mangle]` item above.
    let src: String = [
        include_str!("../export.rs"),
        include_str!("../export_unsupported.rs"),
    ]
    .concat()
    .split_whitespace()
    .collect();
    // `extern "C" fn fmi3Foo(` or an argument of `__export_fmi3_no_type!(.., fmi3GetX, fmi3SetX, ..)`.
    let defined =
        |name: &str| src.contains(&format!("fn{name}(")) || src.contains(&format!(",{name},"));
    let names: Vec<&str> = crate::FUNCTIONS.to_vec();
    assert_eq!(names.len(), 75);
    let missing: Vec<&&str> = names.iter().filter(|n| !defined(n)).collect();
    assert!(missing.is_empty(), "missing: {missing:?}");
    // Compile-time check of a few signatures against the header's function types.
    type DoStep = unsafe extern "C" fn(
        fmi3Instance,
        f64,
        f64,
        bool,
        *mut bool,
        *mut bool,
        *mut bool,
        *mut f64,
    ) -> fmi3Status;
    type GetFloat64 =
        unsafe extern "C" fn(fmi3Instance, *const u32, usize, *mut f64, usize) -> fmi3Status;
    let _: DoStep = fmi3DoStep;
    let _: GetFloat64 = fmi3GetFloat64;
}
