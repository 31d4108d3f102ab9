//! One description of an air ring bearing's bore and contact, shared by the air film
//! (`fmu-airfilm`), the rotor (`fmu-rotor`, which evaluates the contact itself) and the master's
//! analysis (MODEL.md section 3). No FFI, no FMI, no solver state.
//!
//! Conventions: ring-fixed angle phi, global angle theta = phi + alpha, (dx, dy) = journal minus
//! ring centre in the global x, y frame. Forces are on the journal; the ring feels -F.

pub mod bore;
pub mod contact;
pub mod journal;
pub mod num;
pub mod quadrature;

pub use bore::{gap_m, lobe_minimum, min_gap_m, sampled_min_gap_m, Bore};
pub use contact::{contact_force_at_n, contact_force_n, BoreContact, ContactLaw};
pub use journal::JournalState;

use std::fmt;

/// A bore or contact parameter that cannot describe a bearing; `name` is the film's parameter
/// name (the rotor prefixes it with `bearing_`).
#[derive(Clone, Debug, PartialEq)]
pub struct InvalidParameter {
    pub name: &'static str,
    pub value: f64,
    pub reason: &'static str,
}

impl fmt::Display for InvalidParameter {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "invalid bearing parameter {} = {}: {}",
            self.name,
            num::Num(self.value),
            self.reason
        )
    }
}

impl std::error::Error for InvalidParameter {}
