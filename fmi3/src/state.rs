//! The FMI 3.0 Co-Simulation call-state rules: one allowed-state mask per function, checked before
//! the call reaches the core instance (as `MASK_fmi3*` in the Reference FMUs' fmi3Functions.c).
//!
//! The state itself is the core instance's `Phase` (one source of truth), read as an FMI 3.0 state:
//!
//! | core `Phase`         | FMI 3.0 state                                                   |
//! |----------------------|-----------------------------------------------------------------|
//! | `Instantiated`       | Instantiated                                                    |
//! | `InitializationMode` | Initialization Mode                                             |
//! | `StepComplete`       | Step Mode                                                       |
//! | `StepFailed`         | Step Mode after fmi3DoStep returned fmi3Discard ("StepDiscarded" |
//! |                      | in the Reference FMUs): no further step until fmi3SetFMUState    |
//! | `Terminated`         | Terminated                                                      |
//! | `Error`              | Terminated after fmi3Error (FMI 3.0 section 2.3): kept apart so  |
//! |                      | that fmi3GetFMUState and fmi3Terminate refuse it                 |
//!
//! Configuration, Reconfiguration, Event, Intermediate Update, Continuous-Time and Clock
//! Activation Mode are never entered: no structural parameters, `hasEventMode="false"`,
//! `providesIntermediateUpdate="false"`, Co-Simulation only. A wrong-state call returns fmi3Error,
//! is logged, and leaves the state unchanged (as in the Reference FMUs).

use fmi_core::instance::Phase;

pub type Mask = u32;

pub const INSTANTIATED: Mask = 1 << 0;
pub const INITIALIZATION_MODE: Mask = 1 << 1;
pub const STEP_MODE: Mask = 1 << 2;
pub const STEP_DISCARDED: Mask = 1 << 3;
pub const TERMINATED: Mask = 1 << 4;
pub const ERROR: Mask = 1 << 5;

pub const ANY: Mask =
    INSTANTIATED | INITIALIZATION_MODE | STEP_MODE | STEP_DISCARDED | TERMINATED | ERROR;

pub fn of(phase: Phase) -> Mask {
    match phase {
        Phase::Instantiated => INSTANTIATED,
        Phase::InitializationMode => INITIALIZATION_MODE,
        Phase::StepComplete => STEP_MODE,
        Phase::StepFailed => STEP_DISCARDED,
        Phase::Terminated => TERMINATED,
        Phase::Error => ERROR,
    }
}

/// Name of a state for log messages.
pub fn name(phase: Phase) -> &'static str {
    match phase {
        Phase::Instantiated => "Instantiated",
        Phase::InitializationMode => "Initialization Mode",
        Phase::StepComplete => "Step Mode",
        Phase::StepFailed => "Step Mode after a discarded step",
        Phase::Terminated => "Terminated",
        Phase::Error => "Terminated after an error",
    }
}

// Functions this FMU does not provide (Model Exchange, Scheduled Execution, Event and Configuration
// Mode, clocks, directional derivatives, variable dependencies, types it has no variables of)
// return fmi3Error in every state, so they have no mask. fmi3GetVersion, fmi3Instantiate* and
// fmi3FreeInstance are allowed in any state.

// Common functions.
pub const MASK_SET_DEBUG_LOGGING: Mask = ANY;
pub const MASK_ENTER_INITIALIZATION_MODE: Mask = INSTANTIATED;
pub const MASK_EXIT_INITIALIZATION_MODE: Mask = INITIALIZATION_MODE;
pub const MASK_TERMINATE: Mask = STEP_MODE | STEP_DISCARDED;
pub const MASK_RESET: Mask = ANY;
/// fmi3Get{VariableType}: not in Instantiated (FMI 3.0 allows only Set there); in Terminated for
/// the final values, after an error for debugging.
pub const MASK_GET: Mask = INITIALIZATION_MODE | STEP_MODE | STEP_DISCARDED | TERMINATED | ERROR;
/// fmi3Set{VariableType}: which variables may be set in each state is checked per variable.
pub const MASK_SET: Mask = INSTANTIATED | INITIALIZATION_MODE | STEP_MODE;
/// An FMU state after an error is not worth keeping: the model may be half-updated.
pub const MASK_GET_FMU_STATE: Mask = ANY & !ERROR;
/// Restoring a state is the way out of an error (FMI 3.0 section 2.2.3, fmi3Error).
pub const MASK_SET_FMU_STATE: Mask = ANY;
pub const MASK_FREE_FMU_STATE: Mask = ANY;
pub const MASK_SERIALIZE_FMU_STATE: Mask = ANY;
pub const MASK_DESERIALIZE_FMU_STATE: Mask = ANY;

// Co-Simulation functions.
pub const MASK_GET_OUTPUT_DERIVATIVES: Mask = STEP_MODE | STEP_DISCARDED | TERMINATED;
pub const MASK_DO_STEP: Mask = STEP_MODE;
