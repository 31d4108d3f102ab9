//! Early return: a step the model cannot finish ends at its last good internal time with fmi3OK
//! and earlyReturn = true when the master allows it, and with fmi3Discard when it does not.

use super::fmi3_exports::*;
use super::fmu::token;
use super::lag::{vr, Lag};
use crate::types::*;
use crate::value_refs::INT32_VR_OFFSET;
use std::ffi::CString;

/// A lag that, from t = 0.05 s on, stops every step half-way (`fault_mode` 3) or at its start (2).
fn started(early_return_allowed: bool, fault_mode: i32) -> fmi3Instance {
    let name = CString::new("early").unwrap();
    // SAFETY: valid strings; no logger, no environment.
    let c = unsafe {
        fmi3InstantiateCoSimulation(
            name.as_ptr(),
            token().as_ptr(),
            std::ptr::null(),
            false,
            false,
            false,
            early_return_allowed,
            std::ptr::null(),
            0,
            std::ptr::null_mut(),
            None,
            None,
        )
    };
    assert!(!c.is_null());
    let (reals, values) = ([vr::TAU, vr::U, vr::FAULT_TIME], [0.25, 1.0, 0.05]);
    let mode = [INT32_VR_OFFSET + vr::FAULT_MODE];
    // SAFETY: arrays of the given lengths.
    unsafe {
        assert_eq!(
            fmi3SetFloat64(c, reals.as_ptr(), 3, values.as_ptr(), 3),
            FMI3_OK
        );
        assert_eq!(fmi3SetInt32(c, mode.as_ptr(), 1, &fault_mode, 1), FMI3_OK);
    }
    assert_eq!(
        fmi3EnterInitializationMode(c, false, 0.0, 0.0, false, 0.0),
        FMI3_OK
    );
    assert_eq!(fmi3ExitInitializationMode(c), FMI3_OK);
    c
}

/// (status, earlyReturn, lastSuccessfulTime)
fn step(c: fmi3Instance, t: f64, h: f64) -> (fmi3Status, bool, f64) {
    let (mut event, mut terminate, mut early, mut last) = (true, true, true, f64::NAN);
    // SAFETY: four writable outputs.
    let s = unsafe {
        fmi3DoStep(
            c,
            t,
            h,
            false,
            &mut event,
            &mut terminate,
            &mut early,
            &mut last,
        )
    };
    assert!(!event && !terminate);
    (s, early, last)
}

fn y(c: fmi3Instance) -> f64 {
    let mut y = [f64::NAN];
    // SAFETY: arrays of length 1.
    assert_eq!(
        unsafe { fmi3GetFloat64(c, &vr::Y, 1, y.as_mut_ptr(), 1) },
        FMI3_OK
    );
    y[0]
}

fn free(c: fmi3Instance) {
    // SAFETY: from fmi3InstantiateCoSimulation, freed once.
    unsafe { fmi3FreeInstance(c) };
}

#[test]
fn an_unfinished_step_returns_early_where_the_master_allows_it() {
    let c = started(true, 3);
    let (h, mut t, mut y_exact) = (0.01, 0.0, 0.0);
    for _ in 0..5 {
        assert_eq!(step(c, t, h), (FMI3_OK, false, t + h));
        t += h;
        y_exact = Lag::exact(y_exact, 1.0, 0.25, h);
    }
    // From 0.05 s on each step ends half-way: fmi3OK, earlyReturn, and the master continues from
    // lastSuccessfulTime without restoring a state.
    for _ in 0..3 {
        let (s, early, last) = step(c, t, h);
        assert_eq!((s, early), (FMI3_OK, true));
        assert_eq!(last.to_bits(), (t + h / 2.0).to_bits());
        t = last;
        y_exact = Lag::exact(y_exact, 1.0, 0.25, h / 2.0);
        assert_eq!(y(c).to_bits(), y_exact.to_bits());
    }
    free(c);
}

#[test]
fn without_early_return_or_progress_the_step_is_discarded() {
    // Not allowed: fmi3Discard, lastSuccessfulTime where the model stopped; only a state restore
    // goes on (the instance is in its step-failed state).
    let c = started(false, 3);
    assert_eq!(step(c, 0.0, 0.05).0, FMI3_OK);
    let (s, early, last) = step(c, 0.05, 0.01);
    assert_eq!((s, early), (FMI3_DISCARD, false));
    assert_eq!(last.to_bits(), 0.055f64.to_bits());
    assert_eq!(step(c, 0.055, 0.01).0, FMI3_ERROR);
    free(c);
    // Allowed, but the model made no progress: nothing to return early with.
    let c = started(true, 2);
    assert_eq!(step(c, 0.0, 0.05).0, FMI3_OK);
    assert_eq!(step(c, 0.05, 0.01), (FMI3_DISCARD, false, 0.05));
    free(c);
}
