//! The paper's rotor system (MODEL.md section 2) on top of the multibody library, with the API
//! the FMU shell and the master call.
//!
//! Bodies and coordinates (6 each, see `body.rs`):
//! 0 = rotor, x[0..6] = (x, y, z of the centre of mass, alpha, beta, gamma = spin angle);
//! 1 = ring C, x[6..12]; 2 = ring T, x[12..18].
//! Constraints (10): rotor z = z_cm and gamma = phi(t) (run-up, rheonomic); each ring z fixed at
//! its bearing plane and its three angles 0 (planar rings).

use crate::body::{PointMass, RigidBody};
use crate::constraint::Constraint;
use crate::disturbance::DisturbanceGrid;
use crate::integrator::{GglBdf, StepStats, Tolerances};
use crate::params::{RotorError, RotorParams, SpeedProfile};
use crate::system::{ForceElement, MultibodySystem};
use serde::{Deserialize, Serialize};

pub const ROTOR: usize = 0;
pub const RING_C: usize = 1;
pub const RING_T: usize = 2;
/// The free lateral coordinates (indices into the 18 body coordinates): the rotor's centre
/// x, y and its tilts about x, y; each ring's x, y.
pub const LATERAL_COORDS: [usize; 8] = [
    0,
    1,
    3,
    4,
    6 * RING_C,
    6 * RING_C + 1,
    6 * RING_T,
    6 * RING_T + 1,
];
/// Integrator inputs: the two film forces (x, y each), then the four disturbance components.
pub const N_INPUTS: usize = 4 + crate::disturbance::CHANNELS;

/// Air-film forces ON the journals [N] (the ring gets the opposite force).
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct BearingForces {
    pub fc_x_n: f64,
    pub fc_y_n: f64,
    pub ft_x_n: f64,
    pub ft_y_n: f64,
}

impl BearingForces {
    pub fn is_finite(&self) -> bool {
        self.fc_x_n.is_finite()
            && self.fc_y_n.is_finite()
            && self.ft_x_n.is_finite()
            && self.ft_y_n.is_finite()
    }
}

/// A linear stand-in for an air film: F_journal = -K dr - D dr' (2x2, x-y, SI units).
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct FilmCoefficients {
    pub k_n_m: [[f64; 2]; 2],
    pub d_n_s_m: [[f64; 2]; 2],
}

impl FilmCoefficients {
    pub fn isotropic(k_n_m: f64, d_n_s_m: f64) -> Self {
        FilmCoefficients {
            k_n_m: [[k_n_m, 0.0], [0.0, k_n_m]],
            d_n_s_m: [[d_n_s_m, 0.0], [0.0, d_n_s_m]],
        }
    }
}

/// Kinematic outputs at one bearing.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct BearingOutputs {
    /// Journal minus ring, x and y [m].
    pub dx_m: f64,
    pub dy_m: f64,
    /// d/dt of (dx, dy) [m/s].
    pub vx_m_s: f64,
    pub vy_m_s: f64,
    /// Absolute journal centre (rotor point on its axis at the bearing mid-plane) [m].
    pub journal_m: [f64; 2],
    /// Absolute ring centre [m].
    pub ring_m: [f64; 2],
    /// Contact force on the journal evaluated by the rotor [N] (0 unless `RotorParams::contact`).
    pub contact_n: [f64; 2],
}

#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct RotorOutputs {
    pub t_s: f64,
    pub bearing_c: BearingOutputs,
    pub bearing_t: BearingOutputs,
    /// Prescribed spin speed Omega(t) [rad/s].
    pub omega_rad_s: f64,
    /// Spin angle (Cardan gamma) [rad].
    pub spin_angle_rad: f64,
    /// Rotor tilts: Cardan alpha (about x) and beta (about y) [rad].
    pub tilt_x_rad: f64,
    pub tilt_y_rad: f64,
    /// Rotor centre of mass [m].
    pub cm_m: [f64; 3],
    /// Constraint residuals max |g| [m or rad], max |g'| [m/s or rad/s].
    pub drift_pos: f64,
    pub drift_vel: f64,
}

/// First time derivatives of the coupling outputs.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct BearingDerivatives {
    /// d(dx)/dt, d(dy)/dt [m/s]
    pub ddx_m_s: f64,
    pub ddy_m_s: f64,
    /// d(vx)/dt, d(vy)/dt: relative acceleration journal minus ring [m/s^2]
    pub dvx_m_s2: f64,
    pub dvy_m_s2: f64,
}

#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct OutputDerivatives {
    pub bearing_c: BearingDerivatives,
    pub bearing_t: BearingDerivatives,
    pub domega_rad_s2: f64,
}

/// The whole rotor simulator state. Cloning or serializing and restoring it continues
/// bit-identically (the integrator history, step size, Jacobian and LU factors are inside).
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct Rotor {
    params: RotorParams,
    profile: SpeedProfile,
    integ: GglBdf,
    /// The disturbance's grid values last used (a cache of a pure function of time: not part
    /// of the state, and rebuilt when the parameters change).
    #[serde(skip)]
    disturbance_grid: Option<DisturbanceGrid>,
}

fn ring_body(m: f64) -> RigidBody {
    // Rotations are locked; any positive inertia keeps M regular (thin ring, radius ~20 mm).
    let j = m * 4e-4;
    RigidBody {
        mass_kg: m,
        inertia_kg_m2: [[0.5 * j, 0.0, 0.0], [0.0, 0.5 * j, 0.0], [0.0, 0.0, j]],
        point_masses: vec![],
    }
}

/// Builds the multibody system of the paper; `films` adds linear film springs/dampers between
/// journal and ring (for tests, static sag and linearization), in addition to the input forces.
pub fn build_system(p: &RotorParams, films: Option<&[FilmCoefficients; 2]>) -> MultibodySystem {
    let profile = SpeedProfile::of(p);
    let point_masses = p
        .imbalance
        .iter()
        .map(|im| PointMass {
            mass_kg: im.mass_kg,
            s_m: [
                im.radius_m * im.phase_rad.cos(),
                im.radius_m * im.phase_rad.sin(),
                im.z_m - p.z_cm_m,
            ],
        })
        .collect();
    let rotor = RigidBody {
        mass_kg: p.m_kg,
        inertia_kg_m2: [
            [p.j_t_kg_m2, 0.0, 0.0],
            [0.0, p.j_t_kg_m2, 0.0],
            [0.0, 0.0, p.j_p_kg_m2],
        ],
        point_masses,
    };
    let s_c = [0.0, 0.0, p.z_jc_m - p.z_cm_m];
    let s_t = [0.0, 0.0, p.z_jt_m - p.z_cm_m];
    let mut constraints = vec![Constraint::fixed(2, p.z_cm_m), Constraint::spin(5, profile)];
    for (ring, z) in [(RING_C, p.z_jc_m), (RING_T, p.z_jt_m)] {
        constraints.push(Constraint::fixed(6 * ring + 2, z));
        for a in 3..6 {
            constraints.push(Constraint::fixed(6 * ring + a, 0.0));
        }
    }
    let mut forces = vec![
        ForceElement::Mount {
            body: RING_C,
            anchor_m: [0.0, 0.0],
            c_n_m: p.c_c_n_m,
            d_n_s_m: p.d_c_n_s_m,
        },
        ForceElement::Mount {
            body: RING_T,
            anchor_m: [0.0, 0.0],
            c_n_m: p.c_t_n_m,
            d_n_s_m: p.d_t_n_s_m,
        },
        ForceElement::InputForce {
            body: ROTOR,
            s_m: s_c,
            input: 0,
            reaction_body: Some(RING_C),
        },
        ForceElement::InputForce {
            body: ROTOR,
            s_m: s_t,
            input: 2,
            reaction_body: Some(RING_T),
        },
        // The disturbance acts on the journals only (no reaction on the rings: it comes from
        // outside the rotor-bearing system).
        ForceElement::InputForce {
            body: ROTOR,
            s_m: s_c,
            input: 4,
            reaction_body: None,
        },
        ForceElement::InputForce {
            body: ROTOR,
            s_m: s_t,
            input: 6,
            reaction_body: None,
        },
    ];
    if let Some(bearings) = &p.contact {
        for (bearing, (ring, s)) in bearings.iter().zip([(RING_C, s_c), (RING_T, s_t)]) {
            forces.push(ForceElement::RingContact {
                body_a: ROTOR,
                s_a_m: s,
                body_b: ring,
                bearing: Box::new(bearing.clone()),
            });
        }
    }
    if let Some(f) = films {
        for (i, (ring, s)) in [(RING_C, s_c), (RING_T, s_t)].into_iter().enumerate() {
            forces.push(ForceElement::Film {
                body_a: ROTOR,
                s_a_m: s,
                body_b: ring,
                k_n_m: f[i].k_n_m,
                d_n_s_m: f[i].d_n_s_m,
            });
        }
    }
    MultibodySystem {
        bodies: vec![rotor, ring_body(p.m_r_c_kg), ring_body(p.m_r_t_kg)],
        constraints,
        forces,
        gravity_m_s2: [0.0, -p.g_m_s2, 0.0],
    }
}

/// The centred initial state of `build_system` (x, v at t = 0).
pub fn initial_state(p: &RotorParams) -> (Vec<f64>, Vec<f64>) {
    let mut x = vec![0.0; 18];
    x[2] = p.z_cm_m;
    x[6 * RING_C + 2] = p.z_jc_m;
    x[6 * RING_T + 2] = p.z_jt_m;
    (x, vec![0.0; 18])
}

impl Rotor {
    /// Centred, at rest, t = 0.
    pub fn new(params: RotorParams) -> Result<Self, RotorError> {
        Self::build(params, None)
    }

    /// Like `new`, with linear film springs/dampers between journals and rings in addition
    /// to the input forces (tests, static sag, cross-checks).
    pub fn with_linear_films(
        params: RotorParams,
        films: [FilmCoefficients; 2],
    ) -> Result<Self, RotorError> {
        for f in &films {
            if f.k_n_m
                .iter()
                .chain(f.d_n_s_m.iter())
                .flatten()
                .any(|v| !v.is_finite())
            {
                return Err(RotorError::InvalidInput(
                    "film coefficients must be finite".into(),
                ));
            }
        }
        Self::build(params, Some(&films))
    }

    fn build(
        params: RotorParams,
        films: Option<&[FilmCoefficients; 2]>,
    ) -> Result<Self, RotorError> {
        params.validate()?;
        let sys = build_system(&params, films);
        let (x0, v0) = initial_state(&params);
        let tol = Tolerances {
            rtol: params.rtol,
            atol_pos: params.atol,
            atol_vel: params.atol_vel,
            h_max_s: params.h_max_s,
            h_init_s: 1e-6_f64.min(params.h_max_s),
            h_min_s: 1e-14,
            error_control: true,
            max_steps_per_call: params.max_steps_per_call,
        };
        let integ = GglBdf::new(sys, tol, 0.0, x0, v0, vec![0.0; N_INPUTS])?;
        let profile = SpeedProfile::of(&params);
        Ok(Rotor {
            params,
            profile,
            integ,
            disturbance_grid: None,
        })
    }

    pub fn params(&self) -> &RotorParams {
        &self.params
    }
    pub fn time_s(&self) -> f64 {
        self.integ.t()
    }
    /// The integrator (state vectors, multipliers, cumulative statistics).
    pub fn integrator(&self) -> &GglBdf {
        &self.integ
    }

    /// The lateral state a periodic-orbit search varies: positions (rotor centre x, y [m], its
    /// tilts about x and y [rad], ring C x, y, ring T x, y [m]), then their rates (same order,
    /// per second). The axial and spin coordinates follow from the constraints.
    pub fn lateral_state(&self) -> [f64; 2 * LATERAL_COORDS.len()] {
        let (x, v) = (self.integ.x(), self.integ.v());
        let mut s = [0.0; 2 * LATERAL_COORDS.len()];
        for (k, &i) in LATERAL_COORDS.iter().enumerate() {
            s[k] = x[i];
            s[LATERAL_COORDS.len() + k] = v[i];
        }
        s
    }

    /// Starts again at the current time from `lateral` (as [`Rotor::lateral_state`] gives it),
    /// spinning at a constant `speed_hz` from t = 0 on (the spin angle 2 pi f t): the period map
    /// of a constant-speed whirl is this rotor advanced from a chosen state. The BDF history is
    /// dropped (the integrator restarts at order 1); the step statistics go on counting.
    pub fn restart_constant_speed(
        &mut self,
        lateral: &[f64; 2 * LATERAL_COORDS.len()],
        speed_hz: f64,
    ) -> Result<(), RotorError> {
        if lateral.iter().any(|v| !v.is_finite()) {
            return Err(RotorError::InvalidInput(format!(
                "lateral state must be finite: {lateral:?}"
            )));
        }
        if self
            .integ
            .sys
            .forces
            .iter()
            .any(|f| matches!(f, ForceElement::Film { .. }))
        {
            // The system is rebuilt from the parameters, which do not hold linear films.
            return Err(RotorError::InvalidInput(
                "a rotor with linear film springs cannot be restarted".into(),
            ));
        }
        let mut params = self.params.clone();
        let t = self.integ.t();
        params.speed_table = vec![(0.0, speed_hz), (t.max(0.0) + 1.0, speed_hz)];
        params.validate()?;
        let sys = build_system(&params, None);
        let mut x = self.integ.x().to_vec();
        let mut v = self.integ.v().to_vec();
        for (k, &i) in LATERAL_COORDS.iter().enumerate() {
            x[i] = lateral[k];
            v[i] = lateral[LATERAL_COORDS.len() + k];
        }
        let omega = 2.0 * std::f64::consts::PI * speed_hz;
        x[5] = omega * t;
        v[5] = omega;
        let totals = self.integ.totals;
        let u = self.integ.inputs_last().to_vec();
        let mut integ = GglBdf::new(sys, self.integ.tolerances(), t, x, v, u)?;
        integ.totals = totals;
        self.profile = SpeedProfile::of(&params);
        self.params = params;
        self.integ = integ;
        Ok(())
    }

    /// Integrate t0 -> t0 + h; `forces(t)` gives the film forces at any time inside (the
    /// master's extrapolation polynomial). `t0_s` must be the current time.
    pub fn advance(
        &mut self,
        t0_s: f64,
        h_s: f64,
        forces: &dyn Fn(f64) -> BearingForces,
    ) -> Result<StepStats, RotorError> {
        let t = self.integ.t();
        if !t0_s.is_finite() || (t0_s - t).abs() > 1e-9 * t.abs().max(1e-3) {
            return Err(RotorError::InvalidInput(format!(
                "advance from t0 = {t0_s} s but the rotor is at t = {t} s"
            )));
        }
        if h_s.is_nan() || h_s <= 0.0 || !h_s.is_finite() {
            return Err(RotorError::InvalidInput(format!(
                "step size h = {h_s} s must be positive and finite"
            )));
        }
        let mut disturbance = match self.disturbance_grid.take() {
            Some(g) if g.disturbance() == self.params.disturbance => g,
            _ => DisturbanceGrid::new(self.params.disturbance),
        };
        let mut inputs = |tt: f64, u: &mut [f64]| -> Result<(), RotorError> {
            let f = forces(tt);
            if !f.is_finite() {
                return Err(RotorError::InvalidInput(format!(
                    "non-finite bearing force at t = {tt} s: {f:?}"
                )));
            }
            u[..4].copy_from_slice(&[f.fc_x_n, f.fc_y_n, f.ft_x_n, f.ft_y_n]);
            u[4..].copy_from_slice(&disturbance.forces_n(tt));
            Ok(())
        };
        let r = self.integ.advance_to(t0_s + h_s, &mut inputs);
        self.disturbance_grid = Some(disturbance);
        r
    }

    fn bearing(&self, s: &[f64; 3], ring: usize) -> BearingOutputs {
        let x = self.integ.x();
        let v = self.integ.v();
        let k = crate::body::BodyKinematics::new(&x[0..6], &v[0..6]);
        let pj = k.point_pos(s);
        let vj = k.point_vel(s);
        let rr = [x[6 * ring], x[6 * ring + 1]];
        let vr = [v[6 * ring], v[6 * ring + 1]];
        let dr = [pj[0] - rr[0], pj[1] - rr[1]];
        BearingOutputs {
            dx_m: dr[0],
            dy_m: dr[1],
            vx_m_s: vj[0] - vr[0],
            vy_m_s: vj[1] - vr[1],
            journal_m: [pj[0], pj[1]],
            ring_m: rr,
            contact_n: match &self.params.contact {
                // Bodies 1 and 2 are the rings C and T: bearings[ring - 1].
                Some(bearings) => bearings[ring - RING_C].force_n(dr),
                None => [0.0, 0.0],
            },
        }
    }

    fn journal_offsets(&self) -> ([f64; 3], [f64; 3]) {
        let p = &self.params;
        (
            [0.0, 0.0, p.z_jc_m - p.z_cm_m],
            [0.0, 0.0, p.z_jt_m - p.z_cm_m],
        )
    }

    pub fn outputs(&self) -> RotorOutputs {
        let x = self.integ.x();
        let (s_c, s_t) = self.journal_offsets();
        let (dp, dv) = self.integ.drift();
        RotorOutputs {
            t_s: self.integ.t(),
            bearing_c: self.bearing(&s_c, RING_C),
            bearing_t: self.bearing(&s_t, RING_T),
            omega_rad_s: self.profile.rate_rad_s(self.integ.t()),
            spin_angle_rad: x[5],
            tilt_x_rad: x[3],
            tilt_y_rad: x[4],
            cm_m: [x[0], x[1], x[2]],
            drift_pos: dp,
            drift_vel: dv,
        }
    }

    /// d/dt of the coupling outputs, from the integrator's derivative at the current point
    /// (BDF derivative: accurate to the method's order).
    pub fn output_derivatives(&self) -> OutputDerivatives {
        let x = self.integ.x();
        let v = self.integ.v();
        let a = &self.integ.ydot()[18..];
        let k = crate::body::BodyKinematics::new(&x[0..6], &v[0..6]);
        let (s_c, s_t) = self.journal_offsets();
        let der = |s: &[f64; 3], ring: usize| {
            let vj = k.point_vel(s);
            let aj = k.point_acc(s, &a[0..6]);
            BearingDerivatives {
                ddx_m_s: vj[0] - v[6 * ring],
                ddy_m_s: vj[1] - v[6 * ring + 1],
                dvx_m_s2: aj[0] - a[6 * ring],
                dvy_m_s2: aj[1] - a[6 * ring + 1],
            }
        };
        OutputDerivatives {
            bearing_c: der(&s_c, RING_C),
            bearing_t: der(&s_t, RING_T),
            domega_rad_s2: self.profile.accel_rad_s2(self.integ.t()),
        }
    }
}
