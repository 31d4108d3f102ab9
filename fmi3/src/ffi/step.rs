//! fmi3DoStep.
//!
//! The inputs are held at the values set before the call over the whole step: FMI 3.0 has no
//! fmi3SetInputDerivatives, so the fmi2 instance builds `Inputs` with zero derivatives, exactly as
//! for an FMI 2.0 master that never calls fmi2SetRealInputDerivatives. Intermediate update (the
//! FMI 3.0 way to exchange inputs inside a step) is not implemented.

use super::{null_argument, with};
use crate::instance::Instance;
use crate::state;
use crate::types::*;
use fmi2::instance::Phase;
use fmi2::Model;

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
    with::<M>(c, F, |inst: &mut Instance<M>| {
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
            // No events are ever signalled (hasEventMode="false") and no step returns early.
            *event_handling_needed = false;
            *early_return = false;
            // Written before the step: if the model panics, these are what the importer sees.
            *terminate_simulation = true;
            *last_successful_time_s = inst.inner.core.last_successful_time;
        }
        let status = inst.run(F, state::MASK_DO_STEP, |i| {
            i.inner
                .do_step(current_communication_point_s, communication_step_size_s)
        });
        // SAFETY: as above.
        unsafe {
            // A model failure ends the run; a discarded step can be retried from a saved state.
            *terminate_simulation = inst.phase() == Phase::Error;
            *last_successful_time_s = inst.inner.core.last_successful_time;
        }
        status
    })
}
