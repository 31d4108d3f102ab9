//! Flexible rotors for AirRing: the shaft as Timoshenko beam finite elements bending in two
//! planes (rotary inertia, shear, gyroscopic terms), rigid disks and point masses at nodes,
//! linear supports; their modes at a spin speed, the Campbell diagram, critical speeds and the
//! unbalance response; rotors saved by ROSS (`Rotor.save`) read as they are.
//!
//! SI units throughout. Knows no FMI and no air film: the air ring bearings attach to a model of
//! this crate in the rotor FMU and the application.

pub mod eigen;
pub mod element;
pub mod modal;
pub mod model;
pub mod ross;

pub use element::{Material, ShaftElement, ShearCoefficient};
pub use modal::{critical_speeds, modes, unbalance_response, CriticalSpeed, Mode, Whirl};
pub use model::{Disk, Matrices, PointMass, Ring, ShaftModel, Support, DOF_PER_NODE};

use std::fmt;

/// What went wrong, naming the element, node or field.
#[derive(Clone, Debug, PartialEq)]
pub enum ShaftError {
    /// A shaft element's field is out of range.
    Element {
        index: usize,
        field: &'static str,
        value: f64,
        reason: &'static str,
    },
    /// A disk, point mass, support or the assembly is not valid.
    Model(String),
    /// A rotor file cannot be read (the message names the file's section and field).
    File(String),
    /// An eigenvalue or linear solve failed.
    Numerical(String),
}

impl fmt::Display for ShaftError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            ShaftError::Element {
                index,
                field,
                value,
                reason,
            } => write!(
                f,
                "shaft element {index}: {field} = {} {reason}",
                bearing::num::Num(*value)
            ),
            ShaftError::Model(s) | ShaftError::File(s) | ShaftError::Numerical(s) => f.write_str(s),
        }
    }
}

impl std::error::Error for ShaftError {}
