//! The journal's state relative to its ring: what the air film takes as input.

use serde::{Deserialize, Serialize};

/// Journal displacement and velocity relative to the ring (global x, y frame) and the rotor
/// speed.
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

    /// The first component that is NaN or infinite, as (name, value).
    pub fn first_non_finite(&self) -> Option<(&'static str, f64)> {
        [
            ("dx", self.dx_m),
            ("dy", self.dy_m),
            ("vx", self.vx_m_s),
            ("vy", self.vy_m_s),
            ("omega", self.omega_rad_s),
        ]
        .into_iter()
        .find(|(_, v)| !v.is_finite())
    }

    /// Eccentricity |d| / C for clearance `c_m`.
    pub fn eccentricity(&self, c_m: f64) -> f64 {
        self.dx_m.hypot(self.dy_m) / c_m
    }
}
