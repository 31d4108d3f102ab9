//! FMI 2.0 co-simulation layer shared by all AirRing FMUs, and an importer for the master and tests.
//!
//! - `types`: `#[repr(C)]` mirror of the FMI 2.0 headers.
//! - `variables`, `units` (fmi-core's, re-exported), `xml`: the variable table (single source of
//!   truth) and the generated modelDescription.xml.
//! - `model`: the `Model` trait a physics library implements (knows nothing of C).
//! - `instance`: the call-state machine around a model; `logging`; `snapshot` (FMU-state blobs);
//!   `resource` (fmuResourceLocation URIs).
//! - `ffi` + `export_fmu!`: the 34 exported `fmi2*` functions, each behind `catch_unwind`.
//! - `importer` (feature `importer`): load any FMI 2.0 co-simulation FMU with libloading.

pub mod export;
pub mod ffi;
pub mod instance;
pub mod logging;
pub mod model;
pub mod resource;
pub mod snapshot;
pub mod types;
pub mod xml;

// The variable table and its units are version-neutral: they live in fmi-core, and the paths
// `fmi2::variables` and `fmi2::units` name them still.
pub use fmi_core::{units, variables};

#[cfg(feature = "importer")]
pub mod importer;

pub use model::{
    taylor_at, Inputs, IntermediateInputs, Log, Model, StepInputs, StepOutcome, Store,
    MAX_INPUT_DERIVATIVE_ORDER,
};
pub use types::Status;
pub use variables::{
    Causality, DefaultExperiment, Initial, ModelInfo, VarType, Variability, Variable,
};
