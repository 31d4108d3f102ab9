//! Holonomic constraints g(t, x) = 0 with Jacobian G = dg/dx.
//!
//! The paper's system only needs constraints on single coordinates (no axial motion, locked ring
//! rotations, prescribed spin), all linear in x, so G is constant and dG/dx = 0; the integrator
//! relies on that (it does not differentiate G v with respect to x). Each constraint is one scalar
//! row: g_i = x[coord] - value(t).

use crate::params::SpeedProfile;
use serde::{Deserialize, Serialize};

/// What a constrained coordinate must equal.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub enum Target {
    /// Scleronomic: a constant.
    Fixed(f64),
    /// Rheonomic: the spin angle of a run-up profile.
    Spin(SpeedProfile),
}

/// One scalar constraint x[coord] - target(t) = 0.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Constraint {
    pub coord: usize,
    pub target: Target,
}

impl Constraint {
    pub fn fixed(coord: usize, value: f64) -> Self {
        Constraint {
            coord,
            target: Target::Fixed(value),
        }
    }
    pub fn spin(coord: usize, profile: SpeedProfile) -> Self {
        Constraint {
            coord,
            target: Target::Spin(profile),
        }
    }
    /// target value, first and second time derivatives
    pub fn target(&self, t: f64) -> (f64, f64, f64) {
        match &self.target {
            Target::Fixed(v) => (*v, 0.0, 0.0),
            Target::Spin(p) => (p.angle_rad(t), p.rate_rad_s(t), p.accel_rad_s2(t)),
        }
    }
    /// g(t, x)
    pub fn value(&self, t: f64, x: &[f64]) -> f64 {
        x[self.coord] - self.target(t).0
    }
    /// g' = G v + dg/dt
    pub fn rate(&self, t: f64, v: &[f64]) -> f64 {
        v[self.coord] - self.target(t).1
    }
    /// Writes the Jacobian row dg/dx (length n_coords) into `row`.
    pub fn jacobian_row(&self, row: &mut [f64]) {
        row.iter_mut().for_each(|r| *r = 0.0);
        row[self.coord] = 1.0;
    }
    /// Right-hand side c of the acceleration-level constraint G a = c.
    pub fn accel_rhs(&self, t: f64) -> f64 {
        self.target(t).2
    }
}
