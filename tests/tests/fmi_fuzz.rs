//! Property test: thousands of random FMI call sequences with hostile values (NaN, inf, huge,
//! negative, unknown value references, null pointers where a check is possible) through the C ABI.
//! Asserts: no crash or abort, only legal status codes, and every rejection logged with a reason.

use fmi2::importer::Slave;
use fmi2::types::*;
use integration_tests::{load, LogBook};
use proptest::prelude::*;
use std::ptr::{null, null_mut};

#[derive(Clone, Debug)]
enum Op {
    Setup(bool, f64, f64, bool, f64),
    Enter,
    Exit,
    Terminate,
    Reset,
    SetReal(Vec<u32>, Vec<f64>),
    GetReal(Vec<u32>),
    SetInteger(Vec<u32>, Vec<i32>),
    GetInteger(Vec<u32>),
    SetBoolean(Vec<u32>, Vec<i32>),
    GetString(Vec<u32>),
    DoStep(f64, f64),
    DoStepAtNow(f64),
    InputDerivative(u32, i32, f64),
    OutputDerivative(u32, i32),
    GetSetState,
    Serialize(Option<usize>),
    Status(i32),
    CancelStep,
    DirectionalDerivative,
    NullArrays(u8),
    DebugLogging(bool, Vec<String>),
}

fn value() -> impl Strategy<Value = f64> {
    prop_oneof![
        3 => -10.0..10.0f64,
        1 => Just(f64::NAN),
        1 => Just(f64::INFINITY),
        1 => Just(f64::NEG_INFINITY),
        1 => Just(1e300),
        1 => Just(-1e-300),
        1 => Just(0.0),
    ]
}

fn vrs() -> impl Strategy<Value = Vec<u32>> {
    prop::collection::vec(
        prop_oneof![8 => 0u32..8, 1 => Just(u32::MAX), 1 => 8u32..1000],
        0..4,
    )
}

fn op() -> impl Strategy<Value = Op> {
    prop_oneof![
        (any::<bool>(), value(), value(), any::<bool>(), value())
            .prop_map(|(a, b, c, d, e)| Op::Setup(a, b, c, d, e)),
        Just(Op::Enter),
        Just(Op::Exit),
        Just(Op::Terminate),
        Just(Op::Reset),
        (vrs(), prop::collection::vec(value(), 4)).prop_map(|(v, x)| Op::SetReal(v, x)),
        vrs().prop_map(Op::GetReal),
        (
            vrs(),
            prop::collection::vec(
                prop_oneof![Just(0), Just(-1), Just(3), Just(i32::MAX), Just(2)],
                4
            )
        )
            .prop_map(|(v, x)| Op::SetInteger(v, x)),
        vrs().prop_map(Op::GetInteger),
        (vrs(), prop::collection::vec(any::<i32>(), 4)).prop_map(|(v, x)| Op::SetBoolean(v, x)),
        vrs().prop_map(Op::GetString),
        (value(), value()).prop_map(|(t, h)| Op::DoStep(t, h)),
        // Listed twice: steps at the right time are what moves a sequence deep into the state machine.
        prop_oneof![
            Just(0.01),
            Just(1e-3),
            Just(0.0),
            Just(-0.1),
            Just(f64::NAN)
        ]
        .prop_map(Op::DoStepAtNow),
        prop_oneof![Just(0.01), Just(1e-3)].prop_map(Op::DoStepAtNow),
        (0u32..10, -1i32..5, value()).prop_map(|(v, o, x)| Op::InputDerivative(v, o, x)),
        (0u32..10, -1i32..3).prop_map(|(v, o)| Op::OutputDerivative(v, o)),
        Just(Op::GetSetState),
        prop::option::of(0usize..400).prop_map(Op::Serialize),
        (-1i32..5).prop_map(Op::Status),
        Just(Op::CancelStep),
        Just(Op::DirectionalDerivative),
        (0u8..6).prop_map(Op::NullArrays),
        (
            any::<bool>(),
            prop::collection::vec(
                prop_oneof![Just("logAll".to_string()), Just("bogus".to_string())],
                0..2
            )
        )
            .prop_map(|(o, c)| Op::DebugLogging(o, c)),
    ]
}

/// Runs one op through the raw C functions and returns the raw status.
/// `step_scale` shrinks the step sizes of `DoStepAtNow` (the air film's steps cost ~0.1 ms per 10 us).
fn apply(s: &Slave, op: &Op, now: &mut f64, step_scale: f64) -> Fmi2StatusRaw {
    let (api, c) = s.raw();
    let mut buf = [0.0f64; 8];
    let mut ibuf = [0i32; 8];
    // SAFETY: every array passed is as long as the count passed with it; null pointers are passed only
    // where the count makes the FMU read through them, which it must refuse.
    unsafe {
        match op {
            Op::Setup(td, tol, start, sd, stop) => {
                (api.setup_experiment)(c, *td as i32, *tol, *start, *sd as i32, *stop)
            }
            Op::Enter => (api.enter_initialization_mode)(c),
            Op::Exit => (api.exit_initialization_mode)(c),
            Op::Terminate => (api.terminate)(c),
            Op::Reset => {
                *now = 0.0;
                (api.reset)(c)
            }
            Op::SetReal(v, x) => (api.set_real)(c, v.as_ptr(), v.len(), x.as_ptr()),
            Op::GetReal(v) => (api.get_real)(c, v.as_ptr(), v.len(), buf.as_mut_ptr()),
            Op::SetInteger(v, x) => (api.set_integer)(c, v.as_ptr(), v.len(), x.as_ptr()),
            Op::GetInteger(v) => (api.get_integer)(c, v.as_ptr(), v.len(), ibuf.as_mut_ptr()),
            Op::SetBoolean(v, x) => (api.set_boolean)(c, v.as_ptr(), v.len(), x.as_ptr()),
            Op::GetString(v) => {
                let mut out = [null::<std::ffi::c_char>(); 8];
                (api.get_string)(c, v.as_ptr(), v.len(), out.as_mut_ptr())
            }
            Op::DoStep(t, h) => (api.do_step)(c, *t, *h, 1),
            Op::DoStepAtNow(h) => {
                let h = h * step_scale;
                let st = (api.do_step)(c, *now, h, 1);
                if st == 0 {
                    *now += h;
                }
                st
            }
            Op::InputDerivative(v, o, x) => (api.set_real_input_derivatives)(c, v, 1, o, x),
            Op::OutputDerivative(v, o) => {
                (api.get_real_output_derivatives)(c, v, 1, o, buf.as_mut_ptr())
            }
            Op::GetSetState => {
                let mut st: Fmi2FmuState = null_mut();
                let a = (api.get_fmu_state)(c, &mut st);
                if a != 0 {
                    return a;
                }
                let b = (api.set_fmu_state)(c, st);
                let f = (api.free_fmu_state)(c, &mut st);
                assert_eq!(f, 0, "freeing a valid state must succeed");
                b
            }
            Op::Serialize(cut) => {
                let mut st: Fmi2FmuState = null_mut();
                let a = (api.get_fmu_state)(c, &mut st);
                if a != 0 {
                    return a;
                }
                let mut n = 0usize;
                assert_eq!((api.serialized_fmu_state_size)(c, st, &mut n), 0);
                let mut bytes = vec![0 as Fmi2Byte; n];
                assert_eq!((api.serialize_fmu_state)(c, st, bytes.as_mut_ptr(), n), 0);
                let len = cut.map(|k| k.min(n)).unwrap_or(n);
                let mut back: Fmi2FmuState = null_mut();
                let r = (api.de_serialize_fmu_state)(c, bytes.as_ptr(), len, &mut back);
                (api.free_fmu_state)(c, &mut back);
                (api.free_fmu_state)(c, &mut st);
                r
            }
            Op::Status(kind) => {
                let mut x = 0.0;
                (api.get_real_status)(c, *kind, &mut x)
            }
            Op::CancelStep => (api.cancel_step)(c),
            Op::DirectionalDerivative => {
                (api.get_directional_derivative)(c, null(), 0, null(), 0, null(), null_mut())
            }
            Op::NullArrays(which) => match which {
                0 => (api.set_real)(c, null(), 2, null()),
                1 => (api.get_real)(c, null(), 1, null_mut()),
                2 => (api.get_fmu_state)(c, null_mut()),
                3 => (api.set_fmu_state)(c, null_mut()),
                4 => (api.get_real_status)(c, FMI2_LAST_SUCCESSFUL_TIME, null_mut()),
                _ => (api.set_debug_logging)(c, 1, 3, null()),
            },
            Op::DebugLogging(on, cats) => {
                let cs: Vec<std::ffi::CString> = cats
                    .iter()
                    .map(|s| std::ffi::CString::new(s.as_str()).unwrap())
                    .collect();
                let ptrs: Vec<*const std::ffi::c_char> = cs.iter().map(|s| s.as_ptr()).collect();
                (api.set_debug_logging)(c, *on as i32, ptrs.len(), ptrs.as_ptr())
            }
        }
    }
}

fn fuzz(model: &str, cases: u32, max_len: usize, step_scale: f64) {
    // Successful steps over all cases: proves the sequences reach deep into the state machine.
    let steps_done = std::cell::Cell::new(0usize);
    let fmu = load(model);
    let mut runner = proptest::test_runner::TestRunner::new(ProptestConfig {
        cases,
        ..ProptestConfig::default()
    });
    runner
        .run(
            &(any::<bool>(), prop::collection::vec(op(), 1..max_len)),
            |(initialize, ops)| {
                let book = LogBook::default();
                let s = fmu
                    .instantiate("fuzz", false, book.handler())
                    .expect("instantiate");
                let mut now = 0.0;
                // Half of the sequences start initialized, so the step phase is explored as deeply as setup.
                let prefix = [Op::Setup(false, 0.0, 0.0, false, 0.0), Op::Enter, Op::Exit];
                let prefix: &[Op] = if initialize { &prefix } else { &[] };
                for op in prefix.iter().chain(&ops) {
                    let before = book.len();
                    let st = apply(&s, op, &mut now, step_scale);
                    if matches!(op, Op::DoStepAtNow(_)) && st == 0 {
                        steps_done.set(steps_done.get() + 1);
                    }
                    prop_assert!((0..=3).contains(&st), "{op:?} returned illegal status {st}");
                    if st != 0 {
                        prop_assert!(
                            book.len() > before,
                            "{op:?} returned {st} without a log message"
                        );
                        let r = book.last().unwrap();
                        prop_assert!(!r.message.trim().is_empty());
                    }
                }
                Ok(())
            },
        )
        .unwrap();
    let steps = steps_done.get();
    println!("{model}: {cases} random sequences, {steps} successful steps");
    assert!(
        steps > cases as usize / 10,
        "too few sequences reached the step phase ({steps})"
    );
}

#[test]
fn random_call_sequences_on_the_oscillator() {
    fuzz("oscillator", 3000, 40, 1.0);
}

#[test]
fn null_component_is_refused() {
    let fmu = load("oscillator");
    let api = &fmu.api;
    // SAFETY: a null component is the one invalid handle the FMU can detect; it must not touch it.
    unsafe {
        assert_eq!((api.do_step)(null_mut(), 0.0, 0.1, 1), 3);
        assert_eq!((api.enter_initialization_mode)(null_mut()), 3);
        (api.free_instance)(null_mut());
    }
}

#[test]
fn random_call_sequences_on_the_air_film() {
    fuzz("airfilm", 200, 25, 1e-3);
}

#[test]
fn random_call_sequences_on_the_rotor() {
    fuzz("rotor", 300, 30, 1e-2);
}
