//! Bearing, gas, contact, mesh and solver parameters with the paper's defaults (SI units).

use crate::error::FilmError;
use bearing::{Bore, ContactLaw};
use serde::{Deserialize, Serialize};

/// All parameters of one air film. Units are in the field names.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct BearingParams {
    /// The bore: radius, width, clearance, step, lobes (the `bearing` crate's one description,
    /// shared with the rotor's contact and the master's analysis).
    pub bore: Bore,
    /// The mixed-lubrication contact law (threshold h_con / C, penalty stiffness).
    pub contact: ContactLaw,
    /// Dynamic viscosity of the gas.
    pub eta_pa_s: f64,
    /// Ambient pressure (pockets, lobe edges, bearing edges).
    pub p_a_pa: f64,
    /// Elements along each lobe (or around the whole plain bore).
    pub n_elem_phi: usize,
    /// Elements across the half width.
    pub n_elem_z: usize,
    /// Each element along a lobe is this many times as long as the one before it: 1 is a uniform
    /// mesh, below 1 the elements shrink geometrically toward the lobe's trailing edge, where the
    /// film is thinnest and the pressure falls to ambient in a thin layer (docs/convergence.md,
    /// "Where the mesh error along the lobe sits"). A plain bore's mesh is always uniform.
    #[serde(default = "uniform_grading")]
    pub mesh_grading: f64,
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
        BearingParams {
            bore: Bore::paper(),
            contact: ContactLaw::paper(),
            eta_pa_s: 20.936e-6,
            p_a_pa: 101_325.0,
            n_elem_phi: 20,
            n_elem_z: 6,
            mesh_grading: 1.0,
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
            bore: Bore::plain(),
            n_elem_phi: 40,
            ..Self::paper()
        }
    }

    /// Bearing number Lambda = 6 eta Omega r^2 / (p_a C^2).
    pub fn bearing_number(&self, omega_rad_s: f64) -> f64 {
        6.0 * self.eta_pa_s * omega_rad_s * self.bore.r_m * self.bore.r_m
            / (self.p_a_pa * self.bore.c_m * self.bore.c_m)
    }

    /// Squeeze time constant tau = 12 eta r^2 / (p_a C^2) of the scaled Reynolds equation.
    pub fn squeeze_time_s(&self) -> f64 {
        12.0 * self.eta_pa_s * self.bore.r_m * self.bore.r_m
            / (self.p_a_pa * self.bore.c_m * self.bore.c_m)
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
        self.bore.validate()?;
        self.contact.validate()?;
        // Named as the FMU names them where it has the parameter (atol, h_max).
        let floats = [
            ("eta", self.eta_pa_s),
            ("p_a", self.p_a_pa),
            ("rtol", self.rtol),
            ("atol", self.atol_pa),
            ("h_init_s", self.h_init_s),
            ("h_max", self.h_max_s),
            ("fixed_step_s", self.fixed_step_s),
        ];
        for (name, v) in floats {
            if !v.is_finite() {
                return bad(name, v, "must be finite (NaN or infinite given)");
            }
        }
        for (name, v) in [("eta", self.eta_pa_s), ("p_a", self.p_a_pa)] {
            if v <= 0.0 {
                return bad(name, v, "must be > 0");
            }
        }
        // Sane bounds of a gas film: any gas from rarefied to a pressurised one (the scaled
        // Reynolds equation's squeeze time and forces stay far inside f64).
        if !(1e-7..=1.0).contains(&self.eta_pa_s) {
            return bad(
                "eta",
                self.eta_pa_s,
                "must lie between 1e-7 and 1 Pa s (air: 1.8e-5)",
            );
        }
        if !(1e2..=1e8).contains(&self.p_a_pa) {
            return bad(
                "p_a",
                self.p_a_pa,
                "must lie between 100 Pa and 100 MPa (air at sea level: 101325)",
            );
        }
        let min_phi = if self.bore.plain_bore { 8 } else { 4 };
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
        if !(MIN_MESH_GRADING..=1.0).contains(&self.mesh_grading) {
            return bad(
                "mesh_grading",
                self.mesh_grading,
                "must lie between 0.5 and 1 (1: uniform; below 1 finer toward each lobe's trailing edge)",
            );
        }
        if self.n_elem_phi > 2000 || self.n_elem_z > 2000 {
            return bad(
                "n_elem_phi",
                self.n_elem_phi.max(self.n_elem_z) as f64,
                "mesh too fine (> 2000)",
            );
        }
        // A lobe's last column is grading^(n - 1) of its first: past a ratio of 1e-3 the node
        // lines crowd at the trailing edge (0.5 over 55 elements puts them within rounding of
        // each other, over 1075 a column's size underflows to 0) and the Newton matrix degrades.
        let last_to_first = self.mesh_grading.powi(self.n_elem_phi as i32 - 1);
        if !self.bore.plain_bore && last_to_first < MIN_GRADED_COLUMN_RATIO {
            return Err(FilmError::MeshGradingTooStrong {
                mesh_grading: self.mesh_grading,
                n_elem_phi: self.n_elem_phi,
            });
        }
        let bytes = crate::integrator::newton_matrix_bytes(self);
        if bytes > crate::integrator::MAX_NEWTON_MATRIX_BYTES {
            return Err(FilmError::MeshTooLarge {
                n_elem_phi: self.n_elem_phi,
                n_elem_z: self.n_elem_z,
                bytes,
            });
        }
        if !(self.rtol >= MIN_RTOL && self.rtol < 1.0) {
            return bad(
                "rtol",
                self.rtol,
                "must lie in [1e-10, 1): below 1e-10 the Newton iteration cannot reach it in double precision",
            );
        }
        if self.atol_pa <= 0.0 {
            return bad("atol", self.atol_pa, "must be > 0 Pa");
        }
        if self.max_substeps < 1 {
            return bad("max_substeps", 0.0, "must be >= 1");
        }
        // Below 1e-12 s the step control cannot step at all (its floor is 1e-13 s): 1e-300
        // failed the first step as a Newton failure that named no parameter.
        if self.h_max_s < 1e-12 {
            return bad("h_max", self.h_max_s, "largest sub-step must be >= 1e-12 s");
        }
        // An absolute tolerance above the ambient pressure controls nothing.
        if self.atol_pa > self.p_a_pa {
            return bad(
                "atol",
                self.atol_pa,
                "must not exceed the ambient pressure p_a",
            );
        }
        if self.h_init_s <= 0.0 {
            return bad("h_init_s", self.h_init_s, "first sub-step must be > 0 s");
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

fn uniform_grading() -> f64 {
    1.0
}

/// The strongest grading along a lobe: the last of 10 elements is then ~0.002 of the first
/// (0.8, the run-ups': ~0.13).
pub const MIN_MESH_GRADING: f64 = 0.5;

/// The smallest column along a graded lobe, as a fraction of the first.
pub const MIN_GRADED_COLUMN_RATIO: f64 = 1e-3;

/// The smallest relative tolerance (`rtol`, and the tolerance of fmi2SetupExperiment) the film's
/// time integration reaches in double precision: its Newton test asks for updates below 1/20 of
/// the tolerance, and below ~1e-11 of the pressures the Reynolds residual's rounding decides. At
/// 1e-11 an eccentric journal (FMPy, 0.3 C) failed its first step at t = 0 with "Newton iteration
/// ... failed ... step size below the minimum"; 1e-10 ran, at rest and in a 400 Hz whirl.
pub const MIN_RTOL: f64 = 1e-10;

impl Default for BearingParams {
    fn default() -> Self {
        Self::paper()
    }
}
