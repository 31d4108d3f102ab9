//! AirRing rotor subsystem: a small rigid multibody library (Cardan-angle bodies, holonomic
//! constraints, the Gear-Gupta-Leimkuhler stabilized index-2 formulation integrated with
//! variable-step BDF) and the paper's turbo-compressor rotor in two air ring bearings
//! (MODEL.md section 2), plus linearization and modal analysis (paper Section 2.3).
//!
//! Units are SI throughout. The FMU shell (FFI, FMI) lives elsewhere in this crate and only
//! calls [`Rotor`].

pub mod body;
pub mod constraint;
pub mod disturbance;
pub mod eigen;
pub mod flexible;
pub mod forced;
pub mod ggl;
pub mod integrator;
pub mod linalg;
pub mod linear;
pub mod params;
pub mod rotor;
pub mod shell;
pub mod system;

pub use disturbance::Disturbance;
pub use integrator::StepStats;
pub use params::{Imbalance, RotorError, RotorParams, SpeedProfile};
pub use rotor::{
    BearingDerivatives, BearingForces, BearingOutputs, FilmCoefficients, OutputDerivatives, Rotor,
    RotorOutputs,
};
