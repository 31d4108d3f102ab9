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

pub mod contact;
pub mod dynamic;
pub mod error;
pub mod forces;
pub mod geometry;
pub mod integrator;
pub mod linsolve;
pub mod mesh;
pub mod params;
pub mod reynolds;
pub mod shell;
pub mod steady;
pub mod verify;

pub use error::FilmError;
pub use forces::FilmOutputs;
pub use integrator::{AirFilm, StepStats, P_FLOOR_REL};
pub use params::BearingParams;
pub use steady::{static_stiffness, steady_state, SteadySolution};

use serde::{Deserialize, Serialize};

/// Inputs of the film at one instant: journal displacement and velocity relative to the ring
/// (global x, y frame) and the rotor speed.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct JournalState {
    pub dx_m: f64,
    pub dy_m: f64,
    pub vx_m_s: f64,
    pub vy_m_s: f64,
    pub omega_rad_s: f64,
}

impl JournalState {
    /// Journal at rest at (dx, dy) with rotor speed omega.
    pub fn at(dx_m: f64, dy_m: f64, omega_rad_s: f64) -> Self {
        JournalState {
            dx_m,
            dy_m,
            vx_m_s: 0.0,
            vy_m_s: 0.0,
            omega_rad_s,
        }
    }

    /// Err if any component is NaN or infinite.
    pub fn check_finite(&self, t_s: f64) -> Result<(), FilmError> {
        for (what, value) in [
            ("dx", self.dx_m),
            ("dy", self.dy_m),
            ("vx", self.vx_m_s),
            ("vy", self.vy_m_s),
            ("omega", self.omega_rad_s),
        ] {
            if !value.is_finite() {
                return Err(FilmError::InvalidInput { what, value, t_s });
            }
        }
        Ok(())
    }
}
