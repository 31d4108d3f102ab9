//! A generic FMI 2.0 co-simulation master. It knows FMI and system files, nothing of the models
//! it couples (no physics crate, no command line, no plots).
//!
//! - [`system`]: TOML system files (FMUs, parameters, connections, algorithm, outputs); errors
//!   name file, line and field.
//! - [`setup`]: load, parameterize (unit conversion through the FMUs' display units), connect and
//!   initialize: a [`Built`] co-simulation.
//! - [`algorithm`]: the macro step ([`CoSim`]): Gauss-Seidel or Jacobi with input polynomials
//!   ([`polynomial`]), parallel groups ([`parallel`]), roll-back and replay, macro-step control
//!   ([`step_control`]); [`subsystem`]: one FMU instance in it. [`step_plan`]: longer macro
//!   steps in time windows the caller declares calm.
//! - [`execution`]: the run loop to the stop time, checkpoints ([`checkpoint`]) and resume;
//!   everything that watches a run is an [`Observer`] ([`observer`]), such as the CSV writer
//!   ([`timeseries::CsvObserver`]).
//! - [`ssp`]: a system file as an SSP 1.0 archive.
//!
//! The library prints nothing: FMU messages go to the caller's log handler, algorithm events
//! to the observers.

pub mod algorithm;
pub mod checkpoint;
pub mod error;
pub mod execution;
pub mod files;
pub mod number;
pub mod observer;
pub mod parallel;
pub mod parallel_choice;
pub mod polynomial;
pub mod report;
pub mod setup;
pub mod slave;
pub mod ssp;
pub mod step_control;
pub mod step_plan;
pub mod subsystem;
pub mod system;
pub mod timeseries;

pub use algorithm::{AlgorithmConfig, CoSim, Event, Scheme};
pub use error::{RestoreError, RunError, StepError};
pub use execution::{run, RunConfig};
/// What an FMU logged and the caller's handler of it (the FMI core's, for FMUs of either version).
pub use fmi_core::{LogHandler, LogRecord};
pub use observer::{Observer, RunStart};
pub use report::RunReport;
pub use setup::{build, Built, Recorded};
pub use step_control::{ControlStats, StepControl};
pub use step_plan::LongSteps;
pub use system::{System, SystemError};
