//! Air-film physics of one air ring bearing (paper Section 2.2, MODEL.md section 3).
//!
//! The isothermal compressible Reynolds equation (paper eq. (5)) on each lobe of a lobed ring,
//! discretized with 9-node biquadratic elements on the half width (mid-plane symmetry), integrated
//! in time with variable-step BDF1/BDF2 and modified Newton (banded LU per lobe, reused across
//! iterations and steps). No FFI and no FMI code here: the FMU shell wraps [`AirFilm`].
//!
//! Conventions: ring-fixed angle phi, global angle theta = phi + alpha, Omega > 0 right-handed
//! about +z, (dx, dy) = journal minus ring centre. Forces are on the journal; the ring feels -F.
//! Unknowns are scaled, P = p / p_a.

pub mod column_integrals;
pub mod contact;
pub mod dynamic;
pub mod error;
pub mod factor_slots;
pub mod forces;
pub mod friction;
pub mod geometry;
pub mod integrator;
mod jacobian_assembly;
#[cfg(test)]
mod lane_test_cases;
pub mod linsolve;
pub mod mesh;
pub mod node_functionals;
pub mod params;
mod residual_assembly;
pub mod reynolds;
pub mod shell;
pub mod steady;
#[cfg(test)]
mod test_rng;
pub mod verify;

pub use error::FilmError;
pub use forces::FilmOutputs;
pub use integrator::{AirFilm, StepStats, P_FLOOR_REL};
pub use params::BearingParams;
pub use steady::{static_stiffness, steady_state, SteadySolution};

pub use bearing::{Bore, ContactLaw, JournalState};

/// Err if any component of the journal state is NaN or infinite.
pub fn check_finite(j: &JournalState, t_s: f64) -> Result<(), FilmError> {
    match j.first_non_finite() {
        Some((what, value)) => Err(FilmError::InvalidInput { what, value, t_s }),
        None => Ok(()),
    }
}
