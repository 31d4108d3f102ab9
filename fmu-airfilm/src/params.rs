//! Bearing, gas, contact, mesh and solver parameters with the paper's defaults (SI units).

use crate::error::FilmError;
use serde::{Deserialize, Serialize};
use std::f64::consts::PI;

/// All parameters of one air film. Units are in the field names.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct BearingParams {
    /// Journal radius r.
    pub r_m: f64,
    /// Bearing width b (full width; only the half width is meshed).
    pub b_m: f64,
    /// Nominal clearance C (gap at each lobe's trailing edge for a centred journal).
    pub c_m: f64,
    /// Step height dH (extra gap at each lobe's leading edge). Must be 0 for a plain bore.
    pub dh_m: f64,
    /// Lobe angle phi_t, in (0, 2 pi / n_lobes). Ignored for a plain bore.
    pub phi_t_rad: f64,
    /// Ring orientation alpha: global angle theta = phi + alpha.
    pub alpha_rad: f64,
    /// Number of lobes n. Ignored for a plain bore.
    pub n_lobes: usize,
    /// Dynamic viscosity of the gas.
    pub eta_pa_s: f64,
    /// Ambient pressure (pockets, lobe edges, bearing edges).
    pub p_a_pa: f64,
    /// Contact threshold h_con / C.
    pub h_con_rel: f64,
    /// Penalty stiffness of the asperity contact pressure c_con (N/m^3).
    pub c_con_n_per_m3: f64,
    /// Elements along each lobe (or around the whole plain bore).
    pub n_elem_phi: usize,
    /// Elements across the half width.
    pub n_elem_z: usize,
    /// Plain 360-degree bore with periodic boundary conditions (dH must be 0).
    pub plain_bore: bool,
    /// Add the contact force to the film force output (false when the rotor model evaluates
    /// the contact itself, implicitly inside its own steps; see docs/fmu-guide.md).
    pub contact_in_force: bool,
    /// Relative tolerance of the local error control.
    pub rtol: f64,
    /// Absolute pressure tolerance of the local error control.
    pub atol_pa: f64,
    /// Maximum number of accepted sub-steps inside one `advance` call.
    pub max_substeps: usize,
    /// First sub-step after initialisation.
    pub h_init_s: f64,
    /// Largest sub-step the error control may choose.
    pub h_max_s: f64,
    /// If > 0: fixed step size without error control (for convergence studies only).
    pub fixed_step_s: f64,
}

impl BearingParams {
    /// The paper's three-lobe bearing (MODEL.md section 3) on the paper's mesh (1599 nodes).
    pub fn paper() -> Self {
        let phi_t = 110f64.to_radians();
        BearingParams {
            r_m: 15e-3,
            b_m: 28.6e-3,
            c_m: 20e-6,
            dh_m: 40e-6,
            phi_t_rad: phi_t,
            alpha_rad: PI - phi_t,
            n_lobes: 3,
            eta_pa_s: 20.936e-6,
            p_a_pa: 101_325.0,
            h_con_rel: 0.04,
            c_con_n_per_m3: 1e16,
            n_elem_phi: 20,
            n_elem_z: 6,
            plain_bore: false,
            contact_in_force: true,
            rtol: 1e-4,
            atol_pa: 10.0,
            max_substeps: 100_000,
            h_init_s: 1e-7,
            h_max_s: 1e-4,
            fixed_step_s: 0.0,
        }
    }

    /// A plain 360-degree bore of the paper's radius, width and clearance (dH = 0, periodic in phi).
    pub fn plain_bore() -> Self {
        BearingParams {
            dh_m: 0.0,
            plain_bore: true,
            n_elem_phi: 40,
            alpha_rad: 0.0,
            ..Self::paper()
        }
    }

    /// Number of pressure blocks that are solved independently (lobes; 1 for a plain bore).
    pub fn n_blocks(&self) -> usize {
        if self.plain_bore {
            1
        } else {
            self.n_lobes
        }
    }

    /// Angular span of one block (lobe angle or 2 pi).
    pub fn block_span_rad(&self) -> f64 {
        if self.plain_bore {
            2.0 * PI
        } else {
            self.phi_t_rad
        }
    }

    /// Ring-fixed start angle of block k.
    pub fn block_start_rad(&self, k: usize) -> f64 {
        if self.plain_bore {
            0.0
        } else {
            k as f64 * 2.0 * PI / self.n_lobes as f64
        }
    }

    /// Bearing number Lambda = 6 eta Omega r^2 / (p_a C^2).
    pub fn bearing_number(&self, omega_rad_s: f64) -> f64 {
        6.0 * self.eta_pa_s * omega_rad_s * self.r_m * self.r_m
            / (self.p_a_pa * self.c_m * self.c_m)
    }

    /// Squeeze time constant tau = 12 eta r^2 / (p_a C^2) of the scaled Reynolds equation.
    pub fn squeeze_time_s(&self) -> f64 {
        12.0 * self.eta_pa_s * self.r_m * self.r_m / (self.p_a_pa * self.c_m * self.c_m)
    }

    /// Checks every parameter; the error names the first offending one.
    pub fn validate(&self) -> Result<(), FilmError> {
        let bad = |name, value, reason| {
            Err(FilmError::InvalidParameter {
                name,
                value,
                reason,
            })
        };
        let floats = [
            ("r", self.r_m),
            ("b", self.b_m),
            ("C", self.c_m),
            ("dH", self.dh_m),
            ("phi_t", self.phi_t_rad),
            ("alpha", self.alpha_rad),
            ("eta", self.eta_pa_s),
            ("p_a", self.p_a_pa),
            ("h_con_rel", self.h_con_rel),
            ("c_con", self.c_con_n_per_m3),
            ("rtol", self.rtol),
            ("atol_pa", self.atol_pa),
            ("h_init_s", self.h_init_s),
            ("h_max_s", self.h_max_s),
            ("fixed_step_s", self.fixed_step_s),
        ];
        for (name, v) in floats {
            if !v.is_finite() {
                return bad(name, v, "must be finite (NaN or infinite given)");
            }
        }
        for (name, v) in [
            ("r", self.r_m),
            ("b", self.b_m),
            ("C", self.c_m),
            ("eta", self.eta_pa_s),
            ("p_a", self.p_a_pa),
        ] {
            if v <= 0.0 {
                return bad(name, v, "must be > 0");
            }
        }
        if self.dh_m < 0.0 {
            return bad("dH", self.dh_m, "must be >= 0");
        }
        if self.plain_bore {
            if self.dh_m != 0.0 {
                return bad("dH", self.dh_m, "a plain bore has no step: dH must be 0");
            }
        } else {
            if self.n_lobes < 1 {
                return bad("n_lobes", self.n_lobes as f64, "must be >= 1");
            }
            let max = 2.0 * PI / self.n_lobes as f64;
            if !(self.phi_t_rad > 0.0 && self.phi_t_rad < max) {
                return bad("phi_t", self.phi_t_rad, "must lie in (0, 2 pi / n_lobes)");
            }
        }
        if !(0.0..1.0).contains(&self.h_con_rel) {
            return bad("h_con_rel", self.h_con_rel, "must lie in [0, 1)");
        }
        if self.c_con_n_per_m3 < 0.0 {
            return bad("c_con", self.c_con_n_per_m3, "must be >= 0");
        }
        let min_phi = if self.plain_bore { 8 } else { 4 };
        if self.n_elem_phi < min_phi {
            return bad(
                "n_elem_phi",
                self.n_elem_phi as f64,
                "mesh too coarse (>= 4 per lobe, >= 8 for a plain bore)",
            );
        }
        if self.n_elem_z < 2 {
            return bad(
                "n_elem_z",
                self.n_elem_z as f64,
                "mesh too coarse (>= 2 across the half width)",
            );
        }
        if self.n_elem_phi > 2000 || self.n_elem_z > 2000 {
            return bad(
                "n_elem_phi",
                self.n_elem_phi.max(self.n_elem_z) as f64,
                "mesh too fine (> 2000)",
            );
        }
        if !(self.rtol > 0.0 && self.rtol < 1.0) {
            return bad("rtol", self.rtol, "must lie in (0, 1)");
        }
        if self.atol_pa <= 0.0 {
            return bad("atol_pa", self.atol_pa, "must be > 0");
        }
        if self.max_substeps < 1 {
            return bad("max_substeps", 0.0, "must be >= 1");
        }
        if self.h_init_s <= 0.0 || self.h_max_s <= 0.0 {
            return bad(
                "h_init_s",
                self.h_init_s.min(self.h_max_s),
                "initial and maximum step must be > 0",
            );
        }
        if self.fixed_step_s < 0.0 {
            return bad(
                "fixed_step_s",
                self.fixed_step_s,
                "must be >= 0 (0 = adaptive)",
            );
        }
        Ok(())
    }
}

impl Default for BearingParams {
    fn default() -> Self {
        Self::paper()
    }
}
