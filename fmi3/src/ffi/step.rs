//! fmi3DoStep.
//!
//! FMI 3.0 has no fmi3SetInputDerivatives. Without an intermediateUpdate callback an input keeps
//! the value set before the call over the whole step (the core instance builds `Inputs` with zero
//! derivatives, exactly as for an FMI 2.0 master that never calls fmi2SetRealInputDerivatives).
//! With one, the model's reads at internal times ask the master (`crate::intermediate`).
//!
//! Early return: a model that cannot finish a step stops at its last good internal time
//! (`StepOutcome::Discard` with the time reached; the films when a journal crosses the contact
//! limit or Newton fails, the rotor when its error control gives up). FMI 2.0 can only say
//! fmi2Discard, and the master must restore a state and retry. A master that allows early return
//! (earlyReturnAllowed) instead gets fmi3OK with earlyReturn = true at lastSuccessfulTime, the
//! instance in Step Mode there: it continues from that time without a restore. A discard without
//! progress stays fmi3Discard.

use super::{null_argument, with_shell};
use crate::instance::{Instance, Shell};
use crate::intermediate::CallbackInputs;
use crate::state;
use crate::types::*;
use fmi_core::instance::Phase;
use fmi_core::model::{IntermediateInputs, Model};
use fmi_core::Status;
use std::cell::Cell;

/// Clears `stepping` when the step ends, also by a panic (caught further out).
struct SteppingGuard<'a>(&'a Cell<bool>);

impl Drop for SteppingGuard<'_> {
    fn drop(&mut self) {
        self.0.set(false);
    }
}

/// # Safety
/// FMI 3.0 `fmi3DoStep`: the four output pointers point to writable values.
pub unsafe fn do_step<M: Model>(
    c: fmi3Instance,
    current_communication_point_s: f64,
    communication_step_size_s: f64,
    _no_set_fmu_state_prior_to_current_point: fmi3Boolean,
    event_handling_needed: *mut fmi3Boolean,
    terminate_simulation: *mut fmi3Boolean,
    early_return: *mut fmi3Boolean,
    last_successful_time_s: *mut f64,
) -> fmi3Status {
    const F: &str = "fmi3DoStep";
    with_shell::<M>(c, F, |shell: &Shell<M>| {
        if shell.stepping.get() {
            return super::refuse_while_stepping(
                shell,
                F,
                "not allowed in an intermediateUpdate callback",
            );
        }
        // SAFETY: not stepping, so no other reference to the instance exists (FMI 3.0: one call at
        // a time). Calls that re-enter during the model's step see `stepping` and touch only the
        // shell's buffer, never this instance.
        let inst: &mut Instance<M> = unsafe { &mut *shell.instance.get() };
        if event_handling_needed.is_null()
            || terminate_simulation.is_null()
            || early_return.is_null()
            || last_successful_time_s.is_null()
        {
            return null_argument(
                inst,
                F,
                "eventHandlingNeeded, terminateSimulation, earlyReturn or lastSuccessfulTime",
            );
        }
        // SAFETY: checked non-null above; FMI contract: each points to one writable value.
        unsafe {
            // No events are ever signalled (hasEventMode="false").
            *event_handling_needed = false;
            *early_return = false;
            // Written before the step: if the model panics, these are what the importer sees.
            *terminate_simulation = true;
            *last_successful_time_s = inst.inner.core.last_successful_time;
        }
        let t_s = current_communication_point_s;
        let mut returned_early = false;
        let early_return_allowed = shell.early_return_allowed;
        let mut step = |i: &mut Instance<M>, source: Option<&dyn IntermediateInputs>| match i
            .inner
            .do_step_with(t_s, communication_step_size_s, source)
        {
            Err((Status::Discard, reason))
                if early_return_allowed && i.inner.core.last_successful_time > t_s =>
            {
                i.inner.core.phase = Phase::StepComplete;
                i.reject(Status::Warning, F, &format!("early return: {reason}"));
                returned_early = true;
                Ok(Status::Ok)
            }
            r => r,
        };
        let status = match shell.intermediate_update {
            None => inst.run(F, state::MASK_DO_STEP, |i| step(i, None)),
            Some(callback) => {
                shell
                    .buffer
                    .borrow_mut()
                    .start(&inst.inner.core.store.reals);
                let source = CallbackInputs {
                    callback,
                    environment: shell.environment,
                    buffer: &shell.buffer,
                    asked_at: Cell::new(f64::NAN),
                };
                shell.stepping.set(true);
                let guard = SteppingGuard(&shell.stepping);
                let status = inst.run(F, state::MASK_DO_STEP, |i| step(i, Some(&source)));
                drop(guard);
                let mut buffer = shell.buffer.borrow_mut();
                // Once per distinct refusal: a callback refused at every internal time would
                // otherwise log the same line 17 times for one step.
                let mut refused: Vec<((String, String), usize)> = vec![];
                for call in buffer.refused.drain(..) {
                    match refused.iter_mut().find(|(c, _)| *c == call) {
                        Some((_, n)) => *n += 1,
                        None => refused.push((call, 1)),
                    }
                }
                for ((function, reason), n) in refused {
                    let times = if n > 1 {
                        format!(" ({n} times in this step)")
                    } else {
                        String::new()
                    };
                    inst.reject(Status::Error, &function, &format!("{reason}{times}"));
                }
                // FMI 3.0: an input keeps the value the master set last.
                for (vr, v) in buffer.reals.iter().enumerate() {
                    if buffer.is_input[vr] {
                        inst.inner.core.store.reals[vr] = *v;
                    }
                }
                status
            }
        };
        // SAFETY: as above.
        unsafe {
            // A model failure ends the run; a discarded step can be retried from a saved state.
            *terminate_simulation = inst.phase() == Phase::Error;
            *early_return = returned_early;
            *last_successful_time_s = inst.inner.core.last_successful_time;
        }
        status
    })
}
