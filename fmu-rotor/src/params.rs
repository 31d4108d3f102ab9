//! Parameters of the paper's rotor system (MODEL.md section 2) and the crate's error type.

use crate::disturbance::Disturbance;
use serde::{Deserialize, Serialize};
use std::fmt;

/// Everything that can go wrong in this crate. Bad input is reported, never a panic or a NaN.
#[derive(Clone, Debug, PartialEq)]
pub enum RotorError {
    /// A parameter is out of its physical range (name, value, reason).
    InvalidParameter {
        name: &'static str,
        value: f64,
        reason: &'static str,
    },
    /// An input (film force, time, step size) is not finite or not allowed.
    InvalidInput(String),
    /// The step-size controller reached its minimum step, or Newton kept failing.
    StepFailure { t_s: f64, h_s: f64, reason: String },
    /// A linear system was singular (should not happen for a valid model).
    Singular(&'static str),
}

impl fmt::Display for RotorError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            RotorError::InvalidParameter {
                name,
                value,
                reason,
            } => {
                write!(
                    f,
                    "invalid parameter {name} = {}: {reason}",
                    bearing::num::Num(*value)
                )
            }
            RotorError::InvalidInput(s) => write!(f, "invalid input: {s}"),
            RotorError::StepFailure { t_s, h_s, reason } => {
                write!(
                    f,
                    "integration failed at t = {} s (h = {} s): {reason}",
                    bearing::num::Num(*t_s),
                    bearing::num::Num(*h_s)
                )
            }
            RotorError::Singular(what) => write!(f, "singular matrix in {what}"),
        }
    }
}

impl std::error::Error for RotorError {}

/// One imbalance mass fixed on a wheel: a point mass at radius `radius_m`, axial position `z_m`
/// (same z origin as the rest: turbine-side rotor end) and angle `phase_rad` measured in the
/// rotor-fixed frame from its x axis (so at spin angle 0 it sits at (r cos phase, r sin phase)).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct Imbalance {
    pub mass_kg: f64,
    pub radius_m: f64,
    pub z_m: f64,
    pub phase_rad: f64,
}

/// Rotor-system parameters, SI units. Defaults (`paper()`) are MODEL.md section 2 / path 1.
/// Largest [`RotorParams::max_steps_per_call`]: 1e6 BDF steps are minutes of CPU, beyond that a
/// call that does not finish is a parameter error, not a budget question.
pub const MAX_STEPS_LIMIT: u64 = 1_000_000;

/// The smallest relative tolerance (`rtol`, and the tolerance of fmi2SetupExperiment) the
/// rotor's BDF2 reaches in double precision: at 1e-14 the packed FMU failed its first steps under
/// constant bearing forces (FMPy), 1e-13 ran; a decade of margin.
pub const MIN_RTOL: f64 = 1e-12;

#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct RotorParams {
    /// Rotor mass (shaft and both wheels).
    pub m_kg: f64,
    /// Transverse moment of inertia about the centre of mass.
    pub j_t_kg_m2: f64,
    /// Polar moment of inertia.
    pub j_p_kg_m2: f64,
    /// Axial positions, measured from the turbine-side rotor end.
    pub z_cm_m: f64,
    pub z_jc_m: f64,
    pub z_jt_m: f64,
    /// Ring masses (compressor / turbine side).
    pub m_r_c_kg: f64,
    pub m_r_t_kg: f64,
    /// Ring mounts F = -c r_R - d r_R'.
    pub c_c_n_m: f64,
    pub d_c_n_s_m: f64,
    pub c_t_n_m: f64,
    pub d_t_n_s_m: f64,
    /// Gravity acts in -y.
    pub g_m_s2: f64,
    /// Run-up Omega(t) = 2 pi f_max t / t_ramp, constant f_max afterwards (unless `speed_table`).
    pub f_max_hz: f64,
    pub t_ramp_s: f64,
    /// A piecewise-linear speed table (time [s], speed [Hz]) in place of the linear run-up: ramps,
    /// dwells and run-downs; constant at the last speed after the last point. Empty: the run-up.
    #[serde(default)]
    pub speed_table: Vec<(f64, f64)>,
    /// Imbalance masses: [compressor wheel, turbine wheel].
    pub imbalance: [Imbalance; 2],
    /// Random disturbance force on the journals (the whirl seed; off by default).
    pub disturbance: Disturbance,
    /// Relative tolerance of the integrator's local error test.
    pub rtol: f64,
    /// Absolute tolerance for coordinates [m or rad].
    pub atol: f64,
    /// Absolute tolerance for velocities [m/s or rad/s].
    pub atol_vel: f64,
    /// Largest internal step [s].
    pub h_max_s: f64,
    /// Internal steps allowed per communication step beyond 10 interval/h_max (at most 1e5; CVODE's mxstep);
    /// exceeding it is a StepFailure (fmi2Discard). Raise it together with very tight tolerances.
    #[serde(default = "default_max_steps")]
    pub max_steps_per_call: u64,
    /// Journal-ring contact evaluated inside the rotor (both bearings, this geometry and
    /// penalty law; only the geometry and contact fields are used). None: the contact force
    /// arrives with the film force inputs. Inside the rotor the stiff contact is integrated
    /// implicitly instead of being extrapolated over a macro step (docs/convergence.md).
    pub contact: Option<[bearing::BoreContact; 2]>,
}

/// Default of the integrator's step budget per `advance` call (CVODE's `mxstep` default is the
/// same 500).
pub const MAX_STEPS_PER_CALL: u64 = 500;

fn default_max_steps() -> u64 {
    MAX_STEPS_PER_CALL
}

impl RotorParams {
    /// The paper's rotor, path-1 ring mount (c = 1000 N/mm, d = 50 N s/m), zero imbalance.
    /// The wheel positions of the (zero) imbalance masses are not given by the paper; 20 mm
    /// from each rotor end is an assumption that only matters once a mass is set.
    pub fn paper() -> Self {
        let none = |z_m| Imbalance {
            mass_kg: 0.0,
            radius_m: 0.0,
            z_m,
            phase_rad: 0.0,
        };
        RotorParams {
            m_kg: 0.830,
            j_t_kg_m2: 2500e-6,
            j_p_kg_m2: 120e-6,
            z_cm_m: 0.125,
            z_jc_m: 0.170,
            z_jt_m: 0.060,
            m_r_c_kg: 0.050,
            m_r_t_kg: 0.050,
            c_c_n_m: 1.0e6,
            d_c_n_s_m: 50.0,
            c_t_n_m: 1.0e6,
            d_t_n_s_m: 50.0,
            g_m_s2: 9.81,
            f_max_hz: 2000.0,
            t_ramp_s: 3.0,
            speed_table: vec![],
            imbalance: [none(0.230), none(0.020)],
            disturbance: Disturbance::OFF,
            // Displacements of interest are ~1 um (clearance 20 um): 1e-8 m is 0.05 % of C.
            rtol: 1e-4,
            atol: 1e-8,
            atol_vel: 1e-5,
            h_max_s: 1e-4,
            max_steps_per_call: MAX_STEPS_PER_CALL,
            contact: None,
        }
    }

    /// Check every parameter; the first violation is returned.
    pub fn validate(&self) -> Result<(), RotorError> {
        fn bad(name: &'static str, value: f64, reason: &'static str) -> Result<(), RotorError> {
            Err(RotorError::InvalidParameter {
                name,
                value,
                reason,
            })
        }
        let finite = [
            ("m", self.m_kg),
            ("J_t", self.j_t_kg_m2),
            ("J_p", self.j_p_kg_m2),
            ("z_cm", self.z_cm_m),
            ("z_JC", self.z_jc_m),
            ("z_JT", self.z_jt_m),
            ("m_R_C", self.m_r_c_kg),
            ("m_R_T", self.m_r_t_kg),
            ("c_C", self.c_c_n_m),
            ("d_C", self.d_c_n_s_m),
            ("c_T", self.c_t_n_m),
            ("d_T", self.d_t_n_s_m),
            ("g", self.g_m_s2),
            ("f_max", self.f_max_hz),
            ("t_ramp", self.t_ramp_s),
            ("rtol", self.rtol),
            ("atol", self.atol),
            ("atol_vel", self.atol_vel),
            ("h_max", self.h_max_s),
        ];
        for (name, v) in finite {
            if !v.is_finite() {
                return bad(name, v, "must be finite");
            }
        }
        for (name, v) in [
            ("m", self.m_kg),
            ("m_R_C", self.m_r_c_kg),
            ("m_R_T", self.m_r_t_kg),
        ] {
            if v <= 0.0 {
                return bad(name, v, "mass must be > 0");
            }
        }
        if self.j_t_kg_m2 <= 0.0 {
            return bad(
                "J_t",
                self.j_t_kg_m2,
                "inertia must be positive definite (J_t > 0)",
            );
        }
        if self.j_p_kg_m2 <= 0.0 {
            return bad(
                "J_p",
                self.j_p_kg_m2,
                "inertia must be positive definite (J_p > 0)",
            );
        }
        // A rigid body's principal moments obey the triangle inequality J_p <= 2 J_t.
        if self.j_p_kg_m2 > 2.0 * self.j_t_kg_m2 {
            return bad(
                "J_p",
                self.j_p_kg_m2,
                "J_p > 2 J_t is not a rigid-body inertia",
            );
        }
        for (name, v) in [
            ("c_C", self.c_c_n_m),
            ("d_C", self.d_c_n_s_m),
            ("c_T", self.c_t_n_m),
            ("d_T", self.d_t_n_s_m),
            ("f_max", self.f_max_hz),
        ] {
            if v < 0.0 {
                return bad(name, v, "must be >= 0");
            }
        }
        // Sane bounds far outside any turbo-compressor, inside what the model and f64 carry
        // (f_max = 1e300 Hz gave an omega output of 2e297 rad/s).
        if self.f_max_hz > MAX_SPEED_LIMIT_HZ {
            return bad("f_max", self.f_max_hz, "must lie between 0 and 1e5 Hz");
        }
        for (name, v) in [
            ("z_cm", self.z_cm_m),
            ("z_JC", self.z_jc_m),
            ("z_JT", self.z_jt_m),
        ] {
            if v.abs() > 10.0 {
                return bad(
                    name,
                    v,
                    "axial positions must lie within 10 m of the rotor end",
                );
            }
        }
        if self.t_ramp_s <= 0.0 {
            return bad("t_ramp", self.t_ramp_s, "run-up time must be > 0");
        }
        if !self.speed_table.is_empty() {
            SpeedTable::new(&self.speed_table)?;
        }
        if self.z_jc_m == self.z_jt_m {
            return bad("z_JC", self.z_jc_m, "the two bearings must not coincide");
        }
        for (name, v) in [
            ("rtol", self.rtol),
            ("atol", self.atol),
            ("atol_vel", self.atol_vel),
            ("h_max", self.h_max_s),
        ] {
            if v <= 0.0 {
                return bad(name, v, "must be > 0");
            }
        }
        // As the air film's: a relative tolerance of 1 or more accepts any error.
        if !(MIN_RTOL..1.0).contains(&self.rtol) {
            return bad(
                "rtol",
                self.rtol,
                "must lie in [1e-12, 1): below 1e-12 the BDF2 steps cannot reach it in double precision",
            );
        }
        if self.max_steps_per_call == 0 || self.max_steps_per_call > MAX_STEPS_LIMIT {
            return bad(
                "max_internal_steps",
                self.max_steps_per_call as f64,
                "must be 1 ..= 1000000",
            );
        }
        // The FMU's own variable names, so that its log names what the user set.
        let dist = &self.disturbance;
        if !(dist.force_rms_n.is_finite() && dist.force_rms_n >= 0.0) {
            return bad(
                "disturbance_force",
                dist.force_rms_n,
                "must be finite and >= 0",
            );
        }
        if !(dist.interval_s.is_finite() && dist.interval_s > 0.0) {
            return bad("disturbance_interval", dist.interval_s, "must be > 0");
        }
        let imbalance_names = [
            ["m_imb_C", "r_imb_C", "z_imb_C", "phase_imb_C"],
            ["m_imb_T", "r_imb_T", "z_imb_T", "phase_imb_T"],
        ];
        for (im, [mass, radius, z, phase]) in self.imbalance.iter().zip(imbalance_names) {
            for (name, v) in [
                (mass, im.mass_kg),
                (radius, im.radius_m),
                (z, im.z_m),
                (phase, im.phase_rad),
            ] {
                if !v.is_finite() {
                    return bad(name, v, "must be finite");
                }
            }
            if im.mass_kg < 0.0 {
                return bad(mass, im.mass_kg, "must be >= 0");
            }
            // An imbalance is a small part of the rotor: 1e300 kg made the first step's
            // iteration matrix singular.
            if im.mass_kg > self.m_kg {
                return bad(mass, im.mass_kg, "must not exceed the rotor mass m");
            }
            if im.radius_m < 0.0 {
                return bad(radius, im.radius_m, "must be >= 0");
            }
            if im.radius_m > 1.0 || im.z_m.abs() > 10.0 {
                let (name, v) = if im.radius_m > 1.0 {
                    (radius, im.radius_m)
                } else {
                    (z, im.z_m)
                };
                return bad(
                    name,
                    v,
                    "must lie within 1 m (radius) and 10 m (z) of the rotor",
                );
            }
        }
        for b in self.contact.iter().flatten() {
            if let Err(bearing::InvalidParameter {
                name,
                value,
                reason,
            }) = b.validate()
            {
                return bad(contact_name(name), value, reason);
            }
        }
        Ok(())
    }
}

/// The rotor FMU's name of a bearing-geometry parameter of the contact (the air film's name
/// with a `bearing_` prefix).
fn contact_name(film_name: &str) -> &'static str {
    match film_name {
        "r" => "bearing_r",
        "b" => "bearing_b",
        "C" => "bearing_C",
        "dH" => "bearing_dH",
        "phi_t" => "bearing_phi_t",
        "alpha" => "bearing_alpha",
        "n_lobes" => "bearing_n_lobes",
        "h_con_rel" => "bearing_h_con_rel",
        "c_con" => "bearing_c_con",
        _ => "bearing geometry",
    }
}

/// Highest speed a rotor takes [Hz]: 50 times the paper's top speed.
pub const MAX_SPEED_LIMIT_HZ: f64 = 1e5;

/// Most points of a speed table (the FMU's `speed_table_t_01` ... `_16`).
pub const MAX_SPEED_POINTS: usize = 16;

/// A piecewise-linear speed table: knots (t [s], f [Hz]) from t = 0, the spin angle at each knot
/// precomputed, so every evaluation is one segment's closed form.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct SpeedTable {
    n: usize,
    t_s: [f64; MAX_SPEED_POINTS],
    f_hz: [f64; MAX_SPEED_POINTS],
    /// Spin angle at each knot [rad].
    phi_rad: [f64; MAX_SPEED_POINTS],
}

/// The FMU's names of the speed table's points: its variable table's names and the errors that
/// name a point. Literals: a variable name is `&'static str`, and names built at run time would
/// have to be leaked, memory that valgrind reports lost each time a master unloads the library.
pub(crate) const SPEED_TABLE_T: [&str; MAX_SPEED_POINTS] = [
    "speed_table_t_01",
    "speed_table_t_02",
    "speed_table_t_03",
    "speed_table_t_04",
    "speed_table_t_05",
    "speed_table_t_06",
    "speed_table_t_07",
    "speed_table_t_08",
    "speed_table_t_09",
    "speed_table_t_10",
    "speed_table_t_11",
    "speed_table_t_12",
    "speed_table_t_13",
    "speed_table_t_14",
    "speed_table_t_15",
    "speed_table_t_16",
];
pub(crate) const SPEED_TABLE_F: [&str; MAX_SPEED_POINTS] = [
    "speed_table_f_01",
    "speed_table_f_02",
    "speed_table_f_03",
    "speed_table_f_04",
    "speed_table_f_05",
    "speed_table_f_06",
    "speed_table_f_07",
    "speed_table_f_08",
    "speed_table_f_09",
    "speed_table_f_10",
    "speed_table_f_11",
    "speed_table_f_12",
    "speed_table_f_13",
    "speed_table_f_14",
    "speed_table_f_15",
    "speed_table_f_16",
];

impl SpeedTable {
    /// Checks the points: 2 ..= 16 of them, the first at t = 0, times strictly increasing, speeds
    /// finite and >= 0.
    pub fn new(points: &[(f64, f64)]) -> Result<SpeedTable, RotorError> {
        let bad = |name: &'static str, value: f64, reason: &'static str| {
            Err(RotorError::InvalidParameter {
                name,
                value,
                reason,
            })
        };
        let n = points.len();
        if !(2..=MAX_SPEED_POINTS).contains(&n) {
            return bad(
                "speed_table_points",
                n as f64,
                "a speed table has 2 to 16 points (0: the linear run-up)",
            );
        }
        for (k, &(t, f)) in points.iter().enumerate() {
            if !t.is_finite() {
                return bad(SPEED_TABLE_T[k], t, "must be finite");
            }
            if !(f.is_finite() && f >= 0.0) {
                return bad(SPEED_TABLE_F[k], f, "speed must be finite and >= 0 Hz");
            }
        }
        if points[0].0 != 0.0 {
            return bad(
                "speed_table_t_01",
                points[0].0,
                "the first point is at t = 0",
            );
        }
        for (k, w) in points.windows(2).enumerate() {
            if w[1].0 <= w[0].0 {
                return bad(
                    SPEED_TABLE_T[k + 1],
                    w[1].0,
                    "times must increase strictly from point to point",
                );
            }
        }
        let mut tab = SpeedTable {
            n,
            t_s: [0.0; MAX_SPEED_POINTS],
            f_hz: [0.0; MAX_SPEED_POINTS],
            phi_rad: [0.0; MAX_SPEED_POINTS],
        };
        for (k, &(t, f)) in points.iter().enumerate() {
            tab.t_s[k] = t;
            tab.f_hz[k] = f;
            if k > 0 {
                // Trapezoid: exact for a linear speed over the segment.
                let dt = t - tab.t_s[k - 1];
                tab.phi_rad[k] =
                    tab.phi_rad[k - 1] + std::f64::consts::PI * (tab.f_hz[k - 1] + f) * dt;
            }
        }
        Ok(tab)
    }

    /// The points as given.
    pub fn points(&self) -> Vec<(f64, f64)> {
        (0..self.n).map(|k| (self.t_s[k], self.f_hz[k])).collect()
    }

    /// Segment of `t` (index of its left knot; the last knot after the end) and the time into it.
    fn segment(&self, t_s: f64) -> (usize, f64) {
        let t = t_s.max(0.0);
        let k = self.t_s[..self.n]
            .partition_point(|tk| *tk <= t)
            .saturating_sub(1);
        (k, t - self.t_s[k])
    }

    /// Slope of segment k [Hz/s] (0 after the last knot).
    fn slope(&self, k: usize) -> f64 {
        if k + 1 < self.n {
            (self.f_hz[k + 1] - self.f_hz[k]) / (self.t_s[k + 1] - self.t_s[k])
        } else {
            0.0
        }
    }

    fn angle_rad(&self, t_s: f64) -> f64 {
        let (k, tau) = self.segment(t_s);
        self.phi_rad[k]
            + std::f64::consts::TAU * (self.f_hz[k] * tau + 0.5 * self.slope(k) * tau * tau)
    }

    fn rate_rad_s(&self, t_s: f64) -> f64 {
        let (k, tau) = self.segment(t_s);
        std::f64::consts::TAU * (self.f_hz[k] + self.slope(k) * tau)
    }

    fn accel_rad_s2(&self, t_s: f64) -> f64 {
        if t_s < 0.0 {
            return 0.0;
        }
        std::f64::consts::TAU * self.slope(self.segment(t_s).0)
    }
}

/// Prescribed spin: linear run-up to `f_max_hz` in `t_ramp_s`, constant afterwards; or a speed
/// table when `table` is set (boxed: 400 bytes that the ramp does not need to carry).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct SpeedProfile {
    pub f_max_hz: f64,
    pub t_ramp_s: f64,
    pub table: Option<Box<SpeedTable>>,
}

impl SpeedProfile {
    /// The profile the parameters prescribe (a table that fails its checks gives the run-up; the
    /// parameters' `validate` reports it).
    pub fn of(p: &RotorParams) -> SpeedProfile {
        SpeedProfile {
            f_max_hz: p.f_max_hz,
            t_ramp_s: p.t_ramp_s,
            table: (!p.speed_table.is_empty())
                .then(|| SpeedTable::new(&p.speed_table).ok().map(Box::new))
                .flatten(),
        }
    }

    /// Spin angle phi(t) [rad] (phi(0) = 0; negative t is treated as t = 0).
    pub fn angle_rad(&self, t_s: f64) -> f64 {
        if let Some(tab) = &self.table {
            return tab.angle_rad(t_s);
        }
        let w = 2.0 * std::f64::consts::PI * self.f_max_hz;
        let t = t_s.max(0.0);
        if t <= self.t_ramp_s {
            0.5 * w * t * t / self.t_ramp_s
        } else {
            0.5 * w * self.t_ramp_s + w * (t - self.t_ramp_s)
        }
    }
    /// Omega(t) [rad/s].
    pub fn rate_rad_s(&self, t_s: f64) -> f64 {
        if let Some(tab) = &self.table {
            return tab.rate_rad_s(t_s);
        }
        let w = 2.0 * std::f64::consts::PI * self.f_max_hz;
        let t = t_s.max(0.0);
        if t <= self.t_ramp_s {
            w * t / self.t_ramp_s
        } else {
            w
        }
    }
    /// dOmega/dt [rad/s^2] (right-sided at the kinks).
    pub fn accel_rad_s2(&self, t_s: f64) -> f64 {
        if let Some(tab) = &self.table {
            return tab.accel_rad_s2(t_s);
        }
        if t_s >= 0.0 && t_s < self.t_ramp_s {
            2.0 * std::f64::consts::PI * self.f_max_hz / self.t_ramp_s
        } else {
            0.0
        }
    }
}

#[cfg(test)]
mod speed_tests {
    use super::*;

    /// The paper's ramp written as a table gives the ramp's speed, angle and acceleration (to
    /// round-off), and a ramp-dwell-rundown table matches its closed form: the angle is the exact
    /// integral of the speed (checked by fine quadrature) and the derivative of the angle.
    #[test]
    fn tables_match_the_ramp_and_integrate_exactly() {
        let ramp = SpeedProfile::of(&RotorParams::paper());
        let mut p = RotorParams::paper();
        p.speed_table = vec![(0.0, 0.0), (3.0, 2000.0)];
        p.validate().unwrap();
        let tab = SpeedProfile::of(&p);
        assert!(tab.table.is_some());
        for t in [0.0, 0.37, 1.5, 2.999, 3.0, 4.2] {
            let rel = |a: f64, b: f64| (a - b).abs() / b.abs().max(1.0);
            assert!(rel(tab.rate_rad_s(t), ramp.rate_rad_s(t)) < 1e-14, "{t}");
            assert!(rel(tab.angle_rad(t), ramp.angle_rad(t)) < 1e-13, "{t}");
            assert!(
                rel(tab.accel_rad_s2(t), ramp.accel_rad_s2(t)) < 1e-14,
                "{t}"
            );
        }
        p.speed_table = vec![(0.0, 0.0), (1.5, 2000.0), (3.0, 2000.0), (4.5, 100.0)];
        p.validate().unwrap();
        let prof = SpeedProfile::of(&p);
        assert!((prof.rate_rad_s(2.0) / std::f64::consts::TAU - 2000.0).abs() < 1e-9);
        assert!((prof.rate_rad_s(3.75) / std::f64::consts::TAU - 1050.0).abs() < 1e-9);
        assert!((prof.rate_rad_s(9.0) / std::f64::consts::TAU - 100.0).abs() < 1e-9);
        assert!(prof.accel_rad_s2(4.0) < 0.0 && prof.accel_rad_s2(2.0) == 0.0);
        // Angle = integral of the speed (midpoint rule, 1e5 intervals).
        let n = 100_000;
        let t_end = 5.0;
        let h = t_end / n as f64;
        let quad: f64 = (0..n)
            .map(|i| prof.rate_rad_s((i as f64 + 0.5) * h) * h)
            .sum();
        assert!((quad - prof.angle_rad(t_end)).abs() < 1e-6 * quad, "{quad}");
        // d(angle)/dt = rate, inside segments.
        for t in [0.7, 2.2, 3.9, 6.0] {
            let d = (prof.angle_rad(t + 1e-6) - prof.angle_rad(t - 1e-6)) / 2e-6;
            assert!((d - prof.rate_rad_s(t)).abs() < 1e-5 * prof.rate_rad_s(t));
        }
    }

    #[test]
    fn bad_tables_are_refused_with_their_reason() {
        let mut p = RotorParams::paper();
        for (table, why) in [
            (vec![(0.0, 0.0)], "2 to 16"),
            (vec![(0.1, 0.0), (1.0, 10.0)], "t = 0"),
            (vec![(0.0, 0.0), (1.0, 10.0), (1.0, 20.0)], "increase"),
            (vec![(0.0, 0.0), (1.0, -5.0)], ">= 0"),
            (vec![(0.0, 0.0), (f64::NAN, 5.0)], "finite"),
            ((0..17).map(|k| (k as f64, 1.0)).collect(), "2 to 16"),
        ] {
            p.speed_table = table;
            let e = p.validate().unwrap_err().to_string();
            assert!(e.contains(why), "{e}");
        }
    }
}
