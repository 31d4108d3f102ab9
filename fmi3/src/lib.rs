//! FMI 3.0 Co-Simulation export of any `fmi_core::model::Model`: the sibling of `fmi2`'s glue.
//!
//! The model code is version-neutral (`fmi_core::model::Model`); this crate wraps the FMI core's
//! instance (its call-state machine, store, model and FMU-state blobs, as the FMI 2.0 glue uses
//! them) in the FMI 3.0 C ABI:
//!
//! - `types`: `#[repr(C)]` mirror of `fmi3PlatformTypes.h` / `fmi3FunctionTypes.h`.
//! - `value_refs`: FMI 3.0 value references (unique across types) from the variable table's
//!   per-type ones (FMI 2.0's),
//!   plus the independent variable `time`.
//! - `state`: the FMI 3.0 call-state masks, one per function, over the core instance's phase.
//! - `logging`: the log sink to the FMI 3.0 callback, behind the core's logger with FMI 3.0's filter.
//! - `instance`: one FMI 3.0 instance around an `fmi_core::instance::Instance`.
//! - `ffi` + `export_fmu!`: all 75 `fmi3*` functions of `fmi3Functions.h`, each behind
//!   `catch_unwind`; the Co-Simulation ones are real, the others return fmi3Error with a reason.
//! - `xml`: the FMI 3.0 modelDescription.xml.
//!
//! - `intermediate`: intermediate update, the FMI 3.0 way to take inputs within a step.
//!
//! Inputs within a step: FMI 3.0 has no input derivatives. A master that passes an
//! `intermediateUpdate` callback is asked for the Float64 inputs (all marked
//! `intermediateUpdate="true"`) at every internal time the model reads them; the model sees those
//! values through `fmi_core::model::StepInputs`. Without a callback an input keeps the value set before
//! fmi3DoStep over the whole step (the `Inputs` get zero derivatives, as for an FMI 2.0
//! master that sets none).
//!
//! Events are not used: `hasEventMode="false"`, fmi3InstantiateCoSimulation refuses
//! `eventModeUsed = true` (FMI 3.0 requires that), and fmi3DoStep never signals an event. It
//! returns early where the model stopped short of the step's end and the master allows it
//! (`ffi::step`). Several instances per process are independent (no globals).

/// The 75 functions of fmi3Functions.h (FMI 3.0.2): what `export_fmu!` defines, and exactly what
/// an FMI 3.0 FMU's library exports (tests/tests/fmu_binaries.rs).
pub const FUNCTIONS: [&str; 75] = [
    "fmi3ActivateModelPartition",
    "fmi3CompletedIntegratorStep",
    "fmi3DeserializeFMUState",
    "fmi3DoStep",
    "fmi3EnterConfigurationMode",
    "fmi3EnterContinuousTimeMode",
    "fmi3EnterEventMode",
    "fmi3EnterInitializationMode",
    "fmi3EnterStepMode",
    "fmi3EvaluateDiscreteStates",
    "fmi3ExitConfigurationMode",
    "fmi3ExitInitializationMode",
    "fmi3FreeFMUState",
    "fmi3FreeInstance",
    "fmi3GetAdjointDerivative",
    "fmi3GetBinary",
    "fmi3GetBoolean",
    "fmi3GetClock",
    "fmi3GetContinuousStateDerivatives",
    "fmi3GetContinuousStates",
    "fmi3GetDirectionalDerivative",
    "fmi3GetEventIndicators",
    "fmi3GetFMUState",
    "fmi3GetFloat32",
    "fmi3GetFloat64",
    "fmi3GetInt16",
    "fmi3GetInt32",
    "fmi3GetInt64",
    "fmi3GetInt8",
    "fmi3GetIntervalDecimal",
    "fmi3GetIntervalFraction",
    "fmi3GetNominalsOfContinuousStates",
    "fmi3GetNumberOfContinuousStates",
    "fmi3GetNumberOfEventIndicators",
    "fmi3GetNumberOfVariableDependencies",
    "fmi3GetOutputDerivatives",
    "fmi3GetShiftDecimal",
    "fmi3GetShiftFraction",
    "fmi3GetString",
    "fmi3GetUInt16",
    "fmi3GetUInt32",
    "fmi3GetUInt64",
    "fmi3GetUInt8",
    "fmi3GetVariableDependencies",
    "fmi3GetVersion",
    "fmi3InstantiateCoSimulation",
    "fmi3InstantiateModelExchange",
    "fmi3InstantiateScheduledExecution",
    "fmi3Reset",
    "fmi3SerializeFMUState",
    "fmi3SerializedFMUStateSize",
    "fmi3SetBinary",
    "fmi3SetBoolean",
    "fmi3SetClock",
    "fmi3SetContinuousStates",
    "fmi3SetDebugLogging",
    "fmi3SetFMUState",
    "fmi3SetFloat32",
    "fmi3SetFloat64",
    "fmi3SetInt16",
    "fmi3SetInt32",
    "fmi3SetInt64",
    "fmi3SetInt8",
    "fmi3SetIntervalDecimal",
    "fmi3SetIntervalFraction",
    "fmi3SetShiftDecimal",
    "fmi3SetShiftFraction",
    "fmi3SetString",
    "fmi3SetTime",
    "fmi3SetUInt16",
    "fmi3SetUInt32",
    "fmi3SetUInt64",
    "fmi3SetUInt8",
    "fmi3Terminate",
    "fmi3UpdateDiscreteStates",
];

pub mod export;
pub mod export_unsupported;
pub mod ffi;
#[cfg(feature = "importer")]
pub mod importer;
pub mod instance;
pub mod intermediate;
pub mod logging;
pub mod state;
pub mod types;
pub mod value_refs;
pub mod xml;

#[cfg(test)]
mod tests;
