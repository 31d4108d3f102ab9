//! The C side of the FMI 3.0 functions, generic over the model. `export_fmu!` emits the
//! `#[no_mangle]` wrappers that call these. Every body runs under `catch_unwind`: a panic becomes
//! fmi3Error with a log line (the instance goes to its error state, from which fmi3SetFMUState or
//! fmi3Reset recover) and never unwinds into the importer.
//!
//! - `lifecycle`: version, instantiate, free, debug logging, initialization, terminate, reset.
//! - `values`: fmi3Get/Set for Float64, Int32, Boolean, String; output derivatives.
//! - `step`: fmi3DoStep.
//! - `fmu_state`: get/set/free/serialize FMU states.
//! - `unsupported`: the functions this FMU does not provide (all return fmi3Error).

pub mod fmu_state;
pub mod lifecycle;
pub mod step;
pub mod unsupported;
pub mod values;

use crate::instance::{Instance, Shell, INSTANCE_MAGIC};
use crate::types::*;
use fmi_core::instance::Phase;
use fmi_core::model::Model;
use fmi_core::Status;
use std::ffi::CStr;
use std::panic::{catch_unwind, AssertUnwindSafe};

/// An fmi2 status on the FMI 3.0 wire (fmi2Pending has no FMI 3.0 counterpart and is never
/// produced by the core instance; it would be an error).
pub(crate) fn raw(s: Status) -> fmi3Status {
    match s {
        Status::Pending => FMI3_ERROR,
        s => s as fmi3Status,
    }
}

fn panic_message(payload: &(dyn std::any::Any + Send)) -> String {
    if let Some(s) = payload.downcast_ref::<&str>() {
        s.to_string()
    } else if let Some(s) = payload.downcast_ref::<String>() {
        s.clone()
    } else {
        "unknown panic".into()
    }
}

/// # Safety
/// `c` must be null or a pointer returned by `instantiate_co_simulation::<M>` and not yet freed.
pub(crate) unsafe fn shell<'a, M: Model>(c: fmi3Instance) -> Option<&'a Shell<M>> {
    if c.is_null() {
        return None;
    }
    // SAFETY: per the contract above; the magic check catches a mismatched model type or a stale
    // pointer whose memory has been reused (best effort: a truly foreign pointer cannot be detected).
    // A shared reference: a call that re-enters during fmi3DoStep (intermediate update) sees the
    // shell while the step holds the instance inside it mutably (an UnsafeCell).
    let shell = unsafe { &*(c as *const Shell<M>) };
    (shell.magic == INSTANCE_MAGIC).then_some(shell)
}

/// Runs `body` on the shell behind `c`, catching panics; a panic puts the instance in its error
/// state (`function` names the call in the log).
pub(crate) fn with_shell<M: Model>(
    c: fmi3Instance,
    function: &str,
    body: impl FnOnce(&Shell<M>) -> Status,
) -> fmi3Status {
    // SAFETY: FMI contract: the importer passes the instance it got from fmi3InstantiateCoSimulation.
    let Some(shell) = (unsafe { shell::<M>(c) }) else {
        return FMI3_ERROR;
    };
    match catch_unwind(AssertUnwindSafe(|| body(shell))) {
        Ok(s) => raw(s),
        Err(payload) => {
            let reason = format!(
                "internal error (panic caught): {}",
                panic_message(&*payload)
            );
            // A call made from inside an intermediateUpdate callback: the step that is running
            // holds the instance; the panic is logged after it (the stepping guard clears
            // `stepping` when the step itself unwinds, before this handler runs).
            if shell.stepping.get() {
                refuse_while_stepping(shell, function, reason);
                return FMI3_ERROR;
            }
            // SAFETY: the closure that borrowed the instance has ended (it unwound), and no other
            // call is inside this instance (FMI 3.0: one call at a time, re-entry only in a step).
            let inst = unsafe { &mut *shell.instance.get() };
            inst.inner.core.phase = Phase::Error;
            inst.reject(Status::Error, function, &reason);
            FMI3_ERROR
        }
    }
}

/// Runs `body` on the instance behind `c`, catching panics. A call that arrives while the
/// instance's model steps (from inside an intermediateUpdate callback) is refused: only
/// fmi3SetFloat64 of inputs is allowed there (`values::set_float64`).
pub(crate) fn with<M: Model>(
    c: fmi3Instance,
    function: &str,
    body: impl FnOnce(&mut Instance<M>) -> Status,
) -> fmi3Status {
    with_shell::<M>(c, function, |shell| {
        if shell.stepping.get() {
            return refuse_while_stepping(shell, function, "not allowed in an intermediateUpdate callback (Intermediate Update Mode allows fmi3SetFloat64 of inputs only)");
        }
        // SAFETY: not stepping, so no other reference to the instance exists (FMI 3.0: one call
        // at a time on an instance); it lives until fmi3FreeInstance.
        body(unsafe { &mut *shell.instance.get() })
    })
}

/// Refuses a call made while the model steps; the reason is logged by fmi3DoStep after the step
/// (the logger belongs to the stepping instance).
pub(crate) fn refuse_while_stepping<M: Model>(
    shell: &Shell<M>,
    function: &str,
    reason: impl Into<String>,
) -> Status {
    if let Ok(mut b) = shell.buffer.try_borrow_mut() {
        b.refused.push((function.to_string(), reason.into()));
    }
    Status::Error
}

/// A slice from a C array; `None` if the pointer is null while `n > 0`.
///
/// # Safety
/// If non-null, `p` must point to `n` valid elements.
pub(crate) unsafe fn slice<'a, T>(p: *const T, n: usize) -> Option<&'a [T]> {
    if n == 0 {
        Some(&[])
    } else if p.is_null() {
        None
    } else {
        // SAFETY: see the contract above.
        Some(unsafe { std::slice::from_raw_parts(p, n) })
    }
}

/// # Safety
/// If non-null, `p` must point to `n` writable elements.
pub(crate) unsafe fn slice_mut<'a, T>(p: *mut T, n: usize) -> Option<&'a mut [T]> {
    if n == 0 {
        Some(&mut [])
    } else if p.is_null() {
        None
    } else {
        // SAFETY: see the contract above.
        Some(unsafe { std::slice::from_raw_parts_mut(p, n) })
    }
}

/// # Safety
/// `s` must be null or a NUL-terminated string.
pub(crate) unsafe fn string<'a>(s: fmi3String) -> Option<&'a str> {
    if s.is_null() {
        None
    } else {
        // SAFETY: see the contract above.
        unsafe { CStr::from_ptr(s) }.to_str().ok()
    }
}

pub(crate) fn null_argument(inst: &Instance<impl Model>, function: &str, what: &str) -> Status {
    inst.reject(
        Status::Error,
        function,
        &format!("{what} is a null pointer"),
    );
    Status::Error
}

/// A function this FMU does not provide: logs `why` and returns fmi3Error in every state.
pub fn not_provided<M: Model>(c: fmi3Instance, function: &str, why: &str) -> fmi3Status {
    with::<M>(c, function, |inst| {
        inst.reject(Status::Error, function, why);
        Status::Error
    })
}
