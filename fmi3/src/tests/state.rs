//! FMU states: a restored or deserialized state continues bit for bit.

use super::fmi3_exports::*;
use super::fmu::Fmu;
use super::lag::vr;
use crate::types::*;

/// Steps from `t0` with a varying input and returns the output bits after each step.
fn run(f: &Fmu, t0: f64, n: usize) -> Vec<u64> {
    let h = 0.01;
    (0..n)
        .map(|k| {
            let t = t0 + k as f64 * h;
            assert_eq!(f.set_f64(&[vr::U], &[(7.0 * t).sin()]), FMI3_OK);
            assert_eq!(f.step(t, h).0, FMI3_OK);
            f.get_f64(&[vr::Y]).1[0].to_bits()
        })
        .collect()
}

#[test]
fn restored_and_deserialized_states_reproduce_the_run() {
    let a = Fmu::started("a", &[(vr::TAU, 0.3)]);
    run(&a, 0.0, 5);
    let t5 = 5.0 * 0.01;
    let mut state: fmi3FMUState = std::ptr::null_mut();
    let mut size = 0usize;
    // SAFETY: writable handle and size; the buffer has `size` bytes.
    let bytes = unsafe {
        assert_eq!(fmi3GetFMUState(a.instance, &mut state), FMI3_OK);
        assert_eq!(
            fmi3SerializedFMUStateSize(a.instance, state, &mut size),
            FMI3_OK
        );
        let mut bytes = vec![0u8; size];
        assert_eq!(
            fmi3SerializeFMUState(a.instance, state, bytes.as_mut_ptr(), size),
            FMI3_OK
        );
        assert_eq!(
            fmi3SerializeFMUState(a.instance, state, bytes.as_mut_ptr(), size - 1),
            FMI3_ERROR
        );
        bytes
    };
    let reference = run(&a, t5, 5);

    // Same instance, state restored (and the handle reused by a second get).
    // SAFETY: a state of this FMU.
    unsafe { assert_eq!(fmi3SetFMUState(a.instance, state), FMI3_OK) };
    assert_eq!(run(&a, t5, 5), reference);

    // Another instance, from the bytes.
    let b = Fmu::new("b");
    let mut restored: fmi3FMUState = std::ptr::null_mut();
    // SAFETY: `bytes` holds `size` bytes; handles are writable.
    unsafe {
        assert_eq!(
            fmi3DeserializeFMUState(b.instance, bytes.as_ptr(), size, &mut restored),
            FMI3_OK
        );
        assert_eq!(fmi3SetFMUState(b.instance, restored), FMI3_OK);
    }
    assert_eq!(b.get_f64(&[crate::value_refs::TIME_VR]).1[0], t5);
    assert_eq!(run(&b, t5, 5), reference);

    // Corrupted bytes are refused; states are freed and the handles nulled.
    let mut bad = bytes.clone();
    bad[size / 2] ^= 1;
    let mut none: fmi3FMUState = std::ptr::null_mut();
    // SAFETY: as above.
    unsafe {
        assert_eq!(
            fmi3DeserializeFMUState(b.instance, bad.as_ptr(), size, &mut none),
            FMI3_ERROR
        );
        assert!(none.is_null());
        assert_eq!(fmi3FreeFMUState(b.instance, &mut restored), FMI3_OK);
        assert_eq!(fmi3FreeFMUState(a.instance, &mut state), FMI3_OK);
        assert_eq!(
            fmi3FreeFMUState(a.instance, &mut state),
            FMI3_OK,
            "null handle: no-op"
        );
        assert_eq!(
            fmi3SetFMUState(a.instance, std::ptr::null_mut()),
            FMI3_ERROR
        );
    }
    assert!(state.is_null() && restored.is_null());
}
