//! FMI 2.0 co-simulation layer shared by all AirRing FMUs, and an importer for the master and tests.
//!
//! - `types`: `#[repr(C)]` mirror of the FMI 2.0 headers.
//! - `xml`: modelDescription.xml from the FMI core's variable table (`fmi_core::variables`, the
//!   single source of truth of an interface).
//! - The model layer is the FMI core's (`fmi_core::model`: the `Model` trait a physics library
//!   implements; `fmi_core::instance`: the call-state machine around it; `fmi_core::snapshot`:
//!   FMU-state blobs); this crate is the FMI 2.0 glue over it: `logging` (the sink to the
//!   importer's variadic logger), `resource` (fmuResourceLocation URIs).
//! - `ffi` + `export_fmu!`: the 34 exported `fmi2*` functions, each behind `catch_unwind`.
//! - `importer` (feature `importer`): load any FMI 2.0 co-simulation FMU with libloading.

pub mod export;
pub mod ffi;
pub mod logging;
pub mod resource;
pub mod types;
pub mod xml;

#[cfg(feature = "importer")]
pub mod importer;

pub use types::Status;
