//! Intermediate update: a master that answers the FMU's requests for inputs inside fmi3DoStep,
//! and one that misbehaves there.

use super::fmi3_exports::*;
use super::fmu::token;
use super::lag::{vr, Lag};
use crate::types::*;
use std::cell::RefCell;
use std::ffi::{c_void, CStr, CString};

/// What the test master does inside an intermediateUpdate callback.
type Answer = dyn Fn(fmi3Instance, f64) -> Vec<fmi3Status>;

/// An intermediateUpdate call: (time, setRequested, getAllowed, stepFinished, canReturnEarly).
type Call = (f64, bool, bool, bool, bool);

/// The instance environment: the log, the answer, and what happened in the callbacks.
struct Master {
    log: RefCell<Vec<(fmi3Status, String)>>,
    instance: RefCell<fmi3Instance>,
    answer: Box<Answer>,
    calls: RefCell<Vec<Call>>,
    /// Statuses of the master's own calls inside the callbacks.
    statuses: RefCell<Vec<fmi3Status>>,
}

unsafe extern "C" fn log(
    env: fmi3InstanceEnvironment,
    status: fmi3Status,
    _category: fmi3String,
    message: fmi3String,
) {
    // SAFETY: env is a live `Master`; the message is valid during the call.
    let (m, message) = unsafe {
        (
            &*(env as *const Master),
            CStr::from_ptr(message).to_string_lossy().into_owned(),
        )
    };
    m.log.borrow_mut().push((status, message));
}

#[allow(clippy::too_many_arguments)]
unsafe extern "C" fn intermediate_update(
    env: fmi3InstanceEnvironment,
    time_s: fmi3Float64,
    set_requested: fmi3Boolean,
    get_allowed: fmi3Boolean,
    step_finished: fmi3Boolean,
    can_return_early: fmi3Boolean,
    early_return_requested: *mut fmi3Boolean,
    _early_return_time: *mut fmi3Float64,
) {
    // SAFETY: env is a live `Master`; the out pointer is valid during the call.
    let m = unsafe { &*(env as *const Master) };
    unsafe { *early_return_requested = false };
    m.calls.borrow_mut().push((
        time_s,
        set_requested,
        get_allowed,
        step_finished,
        can_return_early,
    ));
    let instance = *m.instance.borrow();
    let s = (m.answer)(instance, time_s);
    m.statuses.borrow_mut().extend(s);
}

/// An instance of the lag with `answer` as its master's intermediate update, started at t = 0.
fn started(answer: Box<Answer>, with_callback: bool) -> (Box<Master>, fmi3Instance) {
    let m = Box::new(Master {
        log: RefCell::default(),
        instance: RefCell::new(std::ptr::null_mut()),
        answer,
        calls: RefCell::default(),
        statuses: RefCell::default(),
    });
    let name = CString::new("iu").unwrap();
    let required = [vr::U];
    // SAFETY: valid strings; the environment outlives the instance (freed by the test first).
    let c = unsafe {
        fmi3InstantiateCoSimulation(
            name.as_ptr(),
            token().as_ptr(),
            std::ptr::null(),
            false,
            true,
            false,
            false,
            required.as_ptr(),
            1,
            &*m as *const Master as *mut c_void,
            Some(log),
            if with_callback {
                Some(intermediate_update)
            } else {
                None
            },
        )
    };
    assert!(!c.is_null(), "{:?}", m.log.borrow());
    *m.instance.borrow_mut() = c;
    set(c, &[vr::TAU, vr::U], &[0.25, 1.0]);
    assert_eq!(
        fmi3EnterInitializationMode(c, false, 0.0, 0.0, false, 0.0),
        FMI3_OK
    );
    assert_eq!(fmi3ExitInitializationMode(c), FMI3_OK);
    (m, c)
}

fn set(c: fmi3Instance, vrs: &[u32], values: &[f64]) -> fmi3Status {
    // SAFETY: arrays of the given lengths.
    unsafe { fmi3SetFloat64(c, vrs.as_ptr(), vrs.len(), values.as_ptr(), values.len()) }
}

fn get(c: fmi3Instance, vrs: &[u32]) -> (fmi3Status, Vec<f64>) {
    let mut out = vec![f64::NAN; vrs.len()];
    // SAFETY: arrays of the given lengths.
    let s = unsafe { fmi3GetFloat64(c, vrs.as_ptr(), vrs.len(), out.as_mut_ptr(), out.len()) };
    (s, out)
}

fn step(c: fmi3Instance, t: f64, h: f64) -> fmi3Status {
    let (mut event, mut terminate, mut early, mut last) = (true, true, true, f64::NAN);
    // SAFETY: four writable outputs.
    unsafe {
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
    }
}

fn free(c: fmi3Instance) {
    // SAFETY: from fmi3InstantiateCoSimulation, freed once.
    unsafe { fmi3FreeInstance(c) };
}

/// The master's ramp u(t) = 1 + 2 t.
fn ramp(t: f64) -> f64 {
    1.0 + 2.0 * t
}

#[test]
fn the_model_gets_the_masters_inputs_at_its_internal_times() {
    let (m, c) = started(Box::new(|c, t| vec![set(c, &[vr::U], &[ramp(t)])]), true);
    let (h, mut y) = (0.01, 0.0);
    for n in 0..20 {
        let t = n as f64 * h;
        // The value at the communication point, as any master sets it.
        assert_eq!(set(c, &[vr::U], &[ramp(t)]), FMI3_OK);
        assert_eq!(step(c, t, h), FMI3_OK);
        // The lag reads its input at the step's end: the master's ramp there, not the held ramp(t).
        y = Lag::exact(y, ramp(t + h), 0.25, h);
    }
    assert_eq!(get(c, &[vr::Y]).1[0].to_bits(), y.to_bits());
    let calls = m.calls.borrow();
    assert_eq!(calls.len(), 20, "one request per step (one internal time)");
    for (n, call) in calls.iter().enumerate() {
        let t_end = (n as f64 * h) + h;
        assert_eq!(call.0.to_bits(), t_end.to_bits());
        // Inputs requested; outputs may not be read; no early return.
        assert_eq!(
            (call.1, call.2, call.3, call.4),
            (true, false, false, false)
        );
    }
    assert!(m.statuses.borrow().iter().all(|s| *s == FMI3_OK));
    // FMI 3.0: the input keeps the value the master set last.
    assert_eq!(get(c, &[vr::U]).1[0], ramp(0.2));
    free(c);
}

#[test]
fn a_master_that_sets_nothing_gets_the_inputs_held() {
    let run = |with_callback| {
        let (m, c) = started(Box::new(|_, _| vec![]), with_callback);
        for n in 0..10 {
            let t = n as f64 * 0.01;
            assert_eq!(set(c, &[vr::U], &[ramp(t)]), FMI3_OK);
            assert_eq!(step(c, t, 0.01), FMI3_OK);
        }
        let y = get(c, &[vr::Y]).1[0];
        free(c);
        let asked = m.calls.borrow().len();
        (y, asked)
    };
    let (held, asked) = run(true);
    let (plain, none) = run(false);
    assert_eq!(held.to_bits(), plain.to_bits());
    assert_eq!((asked, none), (10, 0));
}

#[test]
fn inside_a_callback_only_inputs_may_be_set() {
    let (m, c) = started(
        Box::new(|c, t| {
            let mut e = (true, true, true, 0.0);
            vec![
                // Refused: an output, a non-finite value (twice: logged once), a read, a nested
                // step, a state.
                set(c, &[vr::Y], &[1.0]),
                set(c, &[vr::U], &[f64::NAN]),
                set(c, &[vr::U], &[f64::NAN]),
                get(c, &[vr::U]).0,
                // SAFETY: four writable outputs.
                unsafe { fmi3DoStep(c, t, 0.01, false, &mut e.0, &mut e.1, &mut e.2, &mut e.3) },
                fmi3Terminate(c),
                // Allowed: the input.
                set(c, &[vr::U], &[5.0]),
            ]
        }),
        true,
    );
    assert_eq!(step(c, 0.0, 0.01), FMI3_OK);
    assert_eq!(
        *m.statuses.borrow(),
        [FMI3_ERROR, FMI3_ERROR, FMI3_ERROR, FMI3_ERROR, FMI3_ERROR, FMI3_ERROR, FMI3_OK]
    );
    let y = Lag::exact(0.0, 5.0, 0.25, 0.01);
    assert_eq!(get(c, &[vr::Y]).1[0].to_bits(), y.to_bits());
    // Each refusal is logged (after the step: the logger belongs to the stepping instance).
    let log = m.log.borrow().clone();
    let errors: Vec<&String> = log
        .iter()
        .filter(|(s, _)| *s == FMI3_ERROR)
        .map(|(_, msg)| msg)
        .collect();
    assert_eq!(errors.len(), 5, "{log:?}");
    // By the variables' names (not the layer's own value references).
    assert!(
        errors[0].contains("'y' is not an input with intermediateUpdate"),
        "{}",
        errors[0]
    );
    assert!(
        errors[1].contains("value NaN for 'u' is not finite (2 times in this step)"),
        "{}",
        errors[1]
    );
    for e in &errors[2..] {
        assert!(e.contains("intermediateUpdate callback"), "{e}");
    }
    // The instance is intact: it steps on.
    assert_eq!(step(c, 0.01, 0.01), FMI3_OK);
    free(c);
}

#[test]
fn only_inputs_may_be_required_intermediate_variables() {
    let name = CString::new("req").unwrap();
    for (required, accepted) in [(vr::U, true), (vr::Y, false), (vr::TAU, false)] {
        // SAFETY: valid strings, a one-element array, no environment needed without a logger.
        let c = unsafe {
            fmi3InstantiateCoSimulation(
                name.as_ptr(),
                token().as_ptr(),
                std::ptr::null(),
                false,
                false,
                false,
                false,
                &required,
                1,
                std::ptr::null_mut(),
                None,
                Some(intermediate_update),
            )
        };
        assert_eq!(!c.is_null(), accepted, "value reference {required}");
        if !c.is_null() {
            free(c);
        }
    }
}
