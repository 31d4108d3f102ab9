//! The FMU shell: the variable table of `rotor.fmu` and the `fmi_core::model::Model` implementation over
//! [`Rotor`]. The multibody library knows nothing of this module.
//!
//! Value references are part of the product (third-party masters store them): append, never renumber.

use crate::flexible::{FlexRotor, FlexibleSpec};
use crate::params::MAX_SPEED_POINTS;
use crate::{BearingForces, Disturbance, Imbalance, Rotor, RotorError, RotorParams};
use bearing::{Bore, BoreContact, ContactLaw};
use fmi_core::model::{Log, Model, StepInputs, StepOutcome, Store};
use fmi_core::variables::{DefaultExperiment, ModelInfo, Variable};

/// Real value references (Integer ones at the end).
pub mod vr {
    pub const M: u32 = 0;
    pub const J_T: u32 = 1;
    pub const J_P: u32 = 2;
    pub const Z_CM: u32 = 3;
    pub const Z_JC: u32 = 4;
    pub const Z_JT: u32 = 5;
    pub const M_R_C: u32 = 6;
    pub const M_R_T: u32 = 7;
    pub const C_C: u32 = 8;
    pub const D_C: u32 = 9;
    pub const C_T: u32 = 10;
    pub const D_T: u32 = 11;
    pub const G: u32 = 12;
    pub const F_MAX: u32 = 13;
    pub const T_RAMP: u32 = 14;
    /// Imbalance masses: (mass, radius, z, phase) for the compressor wheel, then the turbine wheel.
    pub const IMB_C: u32 = 15;
    pub const IMB_T: u32 = 19;
    pub const RTOL: u32 = 23;
    pub const ATOL: u32 = 24;
    pub const H_MAX: u32 = 25;
    pub const F_C_X: u32 = 26;
    pub const F_C_Y: u32 = 27;
    pub const F_T_X: u32 = 28;
    pub const F_T_Y: u32 = 29;
    pub const DX_C: u32 = 30;
    pub const DY_C: u32 = 31;
    pub const VX_C: u32 = 32;
    pub const VY_C: u32 = 33;
    pub const DX_T: u32 = 34;
    pub const DY_T: u32 = 35;
    pub const VX_T: u32 = 36;
    pub const VY_T: u32 = 37;
    pub const OMEGA: u32 = 38;
    pub const X_JC: u32 = 39;
    pub const Y_JC: u32 = 40;
    pub const X_JT: u32 = 41;
    pub const Y_JT: u32 = 42;
    pub const X_RC: u32 = 43;
    pub const Y_RC: u32 = 44;
    pub const X_RT: u32 = 45;
    pub const Y_RT: u32 = 46;
    pub const TILT_X: u32 = 47;
    pub const TILT_Y: u32 = 48;
    pub const SPIN_ANGLE: u32 = 49;
    pub const DRIFT_POS: u32 = 50;
    pub const DRIFT_VEL: u32 = 51;
    /// Random journal disturbance (see `crate::disturbance`).
    pub const DIST_FORCE: u32 = 52;
    pub const DIST_INTERVAL: u32 = 53;
    /// Contact evaluated in the rotor (Boolean CONTACT): force magnitudes and bearing geometry.
    pub const F_CONTACT_C: u32 = 54;
    pub const F_CONTACT_T: u32 = 55;
    pub const BEARING_R: u32 = 56;
    pub const BEARING_B: u32 = 57;
    pub const BEARING_C: u32 = 58;
    pub const BEARING_DH: u32 = 59;
    pub const BEARING_PHI_T: u32 = 60;
    pub const BEARING_ALPHA: u32 = 61;
    pub const BEARING_H_CON_REL: u32 = 62;
    pub const BEARING_C_CON: u32 = 63;
    /// Speed table: times speed_table_t_01 ..= _16 [s], then speeds speed_table_f_01 ..= _16 [Hz].
    pub const SPEED_TABLE_T: u32 = 64;
    pub const SPEED_TABLE_F: u32 = 80;
    /// Integer value references.
    pub const N_STEPS: u32 = 0;
    pub const N_REJECTED: u32 = 1;
    pub const N_NEWTON: u32 = 2;
    pub const DIST_SEED: u32 = 3;
    pub const MAX_STEPS: u32 = 4;
    pub const BEARING_N_LOBES: u32 = 5;
    /// Points of the speed table in use (0: the linear run-up f_max, t_ramp).
    pub const SPEED_TABLE_POINTS: u32 = 6;
    /// Boolean value references.
    pub const CONTACT: u32 = 0;
    pub const BEARING_PLAIN_BORE: u32 = 1;
}

const DOC: &str = include_str!("shell_doc.html");

/// The simulator behind the FMU: the paper's rigid rotor, or a flexible shaft where the FMU's
/// resources hold one (`resources/shaft.json`, see [`crate::flexible`]).
#[derive(Clone, Debug)]
pub enum Simulator {
    Rigid(Box<Rotor>),
    Flexible(Box<FlexRotor>),
}

#[derive(Clone, Debug)]
pub struct RotorFmu {
    sim: Simulator,
}

/// The first bytes of a flexible rotor's serialized state (a rigid rotor's state is the rotor
/// alone, as it always was, so saved states of either kind read back).
const FLEXIBLE_MAGIC: &[u8; 8] = b"FLEXROT1";

impl RotorFmu {
    /// The simulator inside (the master's periodic-orbit search reads and restarts it in a
    /// deserialized FMU state).
    pub fn simulator(&self) -> &Simulator {
        &self.sim
    }

    /// The rigid rotor, if this is one.
    pub fn rotor(&self) -> Option<&Rotor> {
        match &self.sim {
            Simulator::Rigid(r) => Some(r),
            Simulator::Flexible(_) => None,
        }
    }

    /// The state a periodic-orbit search varies (the rigid rotor's 16 lateral values; the
    /// flexible rotor's coordinates and rates).
    pub fn lateral_state(&self) -> Vec<f64> {
        match &self.sim {
            Simulator::Rigid(r) => r.lateral_state().to_vec(),
            Simulator::Flexible(f) => f.lateral_state(),
        }
    }

    /// Typical magnitudes of the lateral state's values, given a clearance `c_m`, the journal
    /// span `span_m` (rigid rotor: a tilt moving a journal by one clearance) and a whirl
    /// frequency `w_rad_s` (the rates).
    pub fn lateral_scales(&self, c_m: f64, span_m: f64, w_rad_s: f64) -> Vec<f64> {
        let pos: Vec<f64> = match &self.sim {
            Simulator::Rigid(_) => vec![c_m, c_m, c_m / span_m, c_m / span_m, c_m, c_m, c_m, c_m],
            Simulator::Flexible(f) => f.coordinate_scales().iter().map(|s| c_m / s).collect(),
        };
        pos.iter()
            .copied()
            .chain(pos.iter().map(|p| p * w_rad_s))
            .collect()
    }

    /// Starts again from `state` (as [`RotorFmu::lateral_state`] gives it) at a constant speed.
    pub fn restart_constant_speed(
        &mut self,
        state: &[f64],
        speed_hz: f64,
    ) -> Result<(), RotorError> {
        match &mut self.sim {
            Simulator::Rigid(r) => {
                let lateral = state.try_into().map_err(|_| {
                    RotorError::InvalidInput(format!(
                        "the rigid rotor's lateral state has 16 values, not {}",
                        state.len()
                    ))
                })?;
                r.restart_constant_speed(lateral, speed_hz)
            }
            Simulator::Flexible(f) => f.restart_constant_speed(state, speed_hz),
        }
    }

    fn outputs(&self) -> crate::RotorOutputs {
        match &self.sim {
            Simulator::Rigid(r) => r.outputs(),
            Simulator::Flexible(f) => f.outputs(),
        }
    }

    fn output_derivatives(&self) -> crate::OutputDerivatives {
        match &self.sim {
            Simulator::Rigid(r) => r.output_derivatives(),
            Simulator::Flexible(f) => f.output_derivatives(),
        }
    }

    fn totals(&self) -> &crate::StepStats {
        match &self.sim {
            Simulator::Rigid(r) => &r.integrator().totals,
            Simulator::Flexible(f) => f.totals(),
        }
    }

    fn time_s(&self) -> f64 {
        match &self.sim {
            Simulator::Rigid(r) => r.time_s(),
            Simulator::Flexible(f) => f.time_s(),
        }
    }
}

/// The flexible rotor in `resources` (its `shaft.json`), if the FMU carries one.
fn flexible_spec(resources: Option<&std::path::Path>) -> Result<Option<FlexibleSpec>, String> {
    let Some(path) = resources.map(|r| r.join(crate::flexible::RESOURCE_FILE)) else {
        return Ok(None);
    };
    if !path.exists() {
        return Ok(None);
    }
    let text = std::fs::read_to_string(&path)
        .map_err(|e| format!("{}: cannot read it: {e}", path.display()))?;
    serde_json::from_str(&text)
        .map(Some)
        .map_err(|e| format!("{}: not a flexible rotor: {e}", path.display()))
}

/// The rotor parameters from the FMU's variable values (also used by the master's linear
/// stability analysis, which must read parameters exactly as the FMU does).
pub fn params_from(s: &Store) -> RotorParams {
    let mut p = RotorParams::paper();
    p.m_kg = s.real(vr::M);
    p.j_t_kg_m2 = s.real(vr::J_T);
    p.j_p_kg_m2 = s.real(vr::J_P);
    p.z_cm_m = s.real(vr::Z_CM);
    p.z_jc_m = s.real(vr::Z_JC);
    p.z_jt_m = s.real(vr::Z_JT);
    p.m_r_c_kg = s.real(vr::M_R_C);
    p.m_r_t_kg = s.real(vr::M_R_T);
    p.c_c_n_m = s.real(vr::C_C);
    p.d_c_n_s_m = s.real(vr::D_C);
    p.c_t_n_m = s.real(vr::C_T);
    p.d_t_n_s_m = s.real(vr::D_T);
    p.g_m_s2 = s.real(vr::G);
    p.f_max_hz = s.real(vr::F_MAX);
    p.t_ramp_s = s.real(vr::T_RAMP);
    // The Integer's range (0 ..= 16) is checked by the FMI layer on every set.
    let n = s
        .integer(vr::SPEED_TABLE_POINTS)
        .clamp(0, MAX_SPEED_POINTS as i32) as u32;
    p.speed_table = (0..n)
        .map(|k| (s.real(vr::SPEED_TABLE_T + k), s.real(vr::SPEED_TABLE_F + k)))
        .collect();
    for (k, base) in [vr::IMB_C, vr::IMB_T].into_iter().enumerate() {
        p.imbalance[k] = Imbalance {
            mass_kg: s.real(base),
            radius_m: s.real(base + 1),
            z_m: s.real(base + 2),
            phase_rad: s.real(base + 3),
        };
    }
    p.rtol = s.real(vr::RTOL);
    p.atol = s.real(vr::ATOL);
    p.h_max_s = s.real(vr::H_MAX);
    // The Integer's range (1 ..= 1e6) is checked by the FMI layer on every set.
    p.max_steps_per_call = s.integer(vr::MAX_STEPS).max(0) as u64;
    p.disturbance = Disturbance {
        force_rms_n: s.real(vr::DIST_FORCE),
        interval_s: s.real(vr::DIST_INTERVAL),
        // Any Integer is a valid seed; its bit pattern is used as is.
        seed: s.integer(vr::DIST_SEED) as u32 as u64,
    };
    p.contact = s.boolean(vr::CONTACT).then(|| {
        let b = BoreContact {
            bore: Bore {
                r_m: s.real(vr::BEARING_R),
                b_m: s.real(vr::BEARING_B),
                c_m: s.real(vr::BEARING_C),
                dh_m: s.real(vr::BEARING_DH),
                phi_t_rad: s.real(vr::BEARING_PHI_T),
                alpha_rad: s.real(vr::BEARING_ALPHA),
                n_lobes: s.integer(vr::BEARING_N_LOBES).max(0) as usize,
                plain_bore: s.boolean(vr::BEARING_PLAIN_BORE),
            },
            law: ContactLaw {
                h_con_rel: s.real(vr::BEARING_H_CON_REL),
                c_con_n_per_m3: s.real(vr::BEARING_C_CON),
            },
        };
        [b.clone(), b]
    });
    p
}

/// The contact switch, the bearing geometry it uses (the air film's parameters with a
/// `bearing_` prefix, same defaults) and the contact force outputs.
fn contact_vars() -> Vec<Variable> {
    use Variable as V;
    let BoreContact { bore: b, law } = BoreContact::paper();
    vec![
        V::boolean_parameter(
            "contact",
            vr::CONTACT,
            false,
            "evaluate the journal-ring contact of both bearings here, implicitly inside the rotor's steps (set the films' contact_in_force = false then); false: the contact force arrives with F_C_x ... F_T_y",
        ),
        V::real_parameter("bearing_r", vr::BEARING_R, b.r_m, "m", "journal radius of the contact geometry; set it equal to the air films' r")
            .display("mm"),
        V::real_parameter("bearing_b", vr::BEARING_B, b.b_m, "m", "bearing width of the contact geometry; set it equal to the air films' b")
            .display("mm"),
        V::real_parameter("bearing_C", vr::BEARING_C, b.c_m, "m", "nominal clearance of the contact geometry; set it equal to the air films' C")
            .display("um"),
        V::real_parameter("bearing_dH", vr::BEARING_DH, b.dh_m, "m", "step height of the contact geometry; set it equal to the air films' dH")
            .display("um"),
        V::real_parameter("bearing_phi_t", vr::BEARING_PHI_T, b.phi_t_rad, "rad", "lobe angle of the contact geometry; set it equal to the air films' phi_t")
            .display("deg"),
        V::real_parameter("bearing_alpha", vr::BEARING_ALPHA, b.alpha_rad, "rad", "ring orientation of the contact geometry; set it equal to the air films' alpha")
            .display("deg"),
        V::real_parameter("bearing_h_con_rel", vr::BEARING_H_CON_REL, law.h_con_rel, "1", "contact threshold h_con / C; set it equal to the air films' h_con_rel"),
        V::real_parameter("bearing_c_con", vr::BEARING_C_CON, law.c_con_n_per_m3, "N/m3", "penalty stiffness of the contact pressure; set it equal to the air films' c_con")
            .display("N/mm3"),
        V::integer_parameter("bearing_n_lobes", vr::BEARING_N_LOBES, b.n_lobes as i32, "number of lobes of the contact geometry; set it equal to the air films' n_lobes")
            .range(Some(1.0), Some(12.0)),
        V::boolean_parameter("bearing_plain_bore", vr::BEARING_PLAIN_BORE, false, "plain 360-degree bore as contact geometry; set it equal to the air films' plain_bore"),
        V::real_output("F_contact_C", vr::F_CONTACT_C, "N", "magnitude of the contact force evaluated here, compressor side (0 unless contact)"),
        V::real_output("F_contact_T", vr::F_CONTACT_T, "N", "magnitude of the contact force evaluated here, turbine side (0 unless contact)"),
    ]
}

/// The speed table's parameters: how many points are in use, then each point's time and speed.
fn speed_table_vars() -> Vec<Variable> {
    let mut v = vec![Variable::integer_parameter(
        "speed_table_points",
        vr::SPEED_TABLE_POINTS,
        0,
        "points of the piecewise-linear speed table in use (2 to 16; 0: the linear run-up to f_max in t_ramp); the first point is at t = 0, times increase, the speed stays at the last point's afterwards",
    )
    .range(Some(0.0), Some(MAX_SPEED_POINTS as f64))];
    for k in 0..MAX_SPEED_POINTS as u32 {
        v.push(Variable::real_parameter(
            crate::params::SPEED_TABLE_T[k as usize],
            vr::SPEED_TABLE_T + k,
            0.0,
            "s",
            "time of a speed-table point",
        ));
    }
    for k in 0..MAX_SPEED_POINTS as u32 {
        v.push(Variable::real_parameter(
            crate::params::SPEED_TABLE_F[k as usize],
            vr::SPEED_TABLE_F + k,
            0.0,
            "Hz",
            "rotor speed at a speed-table point",
        ));
    }
    v
}

fn imbalance_vars(side: &'static [&'static str; 4], base: u32, d: &Imbalance) -> Vec<Variable> {
    vec![
        Variable::real_parameter(
            side[0],
            base,
            d.mass_kg,
            "kg",
            "imbalance mass on the wheel",
        )
        .display("g"),
        Variable::real_parameter(
            side[1],
            base + 1,
            d.radius_m,
            "m",
            "radius of the imbalance mass",
        )
        .display("mm"),
        Variable::real_parameter(
            side[2],
            base + 2,
            d.z_m,
            "m",
            "axial position of the imbalance mass (from the turbine-side end)",
        )
        .display("mm"),
        Variable::real_parameter(
            side[3],
            base + 3,
            d.phase_rad,
            "rad",
            "angle of the imbalance mass in the rotor frame",
        )
        .display("deg"),
    ]
}

impl Model for RotorFmu {
    fn info() -> ModelInfo {
        let p = RotorParams::paper();
        use Variable as V;
        let mut variables = vec![
            V::real_parameter(
                "m",
                vr::M,
                p.m_kg,
                "kg",
                "rotor mass (shaft and both wheels)",
            )
            .display("g"),
            V::real_parameter(
                "J_t",
                vr::J_T,
                p.j_t_kg_m2,
                "kg.m2",
                "transverse moment of inertia about the centre of mass",
            )
            .display("kg.mm2"),
            V::real_parameter(
                "J_p",
                vr::J_P,
                p.j_p_kg_m2,
                "kg.m2",
                "polar moment of inertia",
            )
            .display("kg.mm2"),
            V::real_parameter(
                "z_cm",
                vr::Z_CM,
                p.z_cm_m,
                "m",
                "axial position of the centre of mass (from the turbine-side end)",
            )
            .display("mm"),
            V::real_parameter(
                "z_JC",
                vr::Z_JC,
                p.z_jc_m,
                "m",
                "axial position of the compressor-side bearing mid-plane",
            )
            .display("mm"),
            V::real_parameter(
                "z_JT",
                vr::Z_JT,
                p.z_jt_m,
                "m",
                "axial position of the turbine-side bearing mid-plane",
            )
            .display("mm"),
            V::real_parameter(
                "m_R_C",
                vr::M_R_C,
                p.m_r_c_kg,
                "kg",
                "mass of the compressor-side bearing ring",
            )
            .display("g"),
            V::real_parameter(
                "m_R_T",
                vr::M_R_T,
                p.m_r_t_kg,
                "kg",
                "mass of the turbine-side bearing ring",
            )
            .display("g"),
            V::real_parameter(
                "c_C",
                vr::C_C,
                p.c_c_n_m,
                "N/m",
                "stiffness of the compressor-side ring mount",
            )
            .display("N/mm"),
            V::real_parameter(
                "d_C",
                vr::D_C,
                p.d_c_n_s_m,
                "N.s/m",
                "damping of the compressor-side ring mount",
            ),
            V::real_parameter(
                "c_T",
                vr::C_T,
                p.c_t_n_m,
                "N/m",
                "stiffness of the turbine-side ring mount",
            )
            .display("N/mm"),
            V::real_parameter(
                "d_T",
                vr::D_T,
                p.d_t_n_s_m,
                "N.s/m",
                "damping of the turbine-side ring mount",
            ),
            V::real_parameter("g", vr::G, p.g_m_s2, "m/s2", "gravity (acts in -y)"),
            V::real_parameter(
                "f_max",
                vr::F_MAX,
                p.f_max_hz,
                "Hz",
                "final rotor speed of the linear run-up",
            ),
            V::real_parameter(
                "t_ramp",
                vr::T_RAMP,
                p.t_ramp_s,
                "s",
                "duration of the linear run-up to f_max",
            )
            .display("ms"),
        ];
        variables.extend(imbalance_vars(
            &["m_imb_C", "r_imb_C", "z_imb_C", "phase_imb_C"],
            vr::IMB_C,
            &p.imbalance[0],
        ));
        variables.extend(imbalance_vars(
            &["m_imb_T", "r_imb_T", "z_imb_T", "phase_imb_T"],
            vr::IMB_T,
            &p.imbalance[1],
        ));
        variables.extend([
            V::real_parameter(
                "rtol",
                vr::RTOL,
                p.rtol,
                "1",
                "relative tolerance of the BDF error control",
            ),
            V::real_parameter(
                "atol",
                vr::ATOL,
                p.atol,
                "m",
                "absolute position tolerance of the error control",
            )
            .display("um"),
            V::real_parameter("h_max", vr::H_MAX, p.h_max_s, "s", "largest internal step")
                .display("ms"),
            V::real_input(
                "F_C_x",
                vr::F_C_X,
                0.0,
                "N",
                "air-film force on the compressor-side journal, x (the ring feels the opposite)",
            ),
            V::real_input(
                "F_C_y",
                vr::F_C_Y,
                0.0,
                "N",
                "air-film force on the compressor-side journal, y",
            ),
            V::real_input(
                "F_T_x",
                vr::F_T_X,
                0.0,
                "N",
                "air-film force on the turbine-side journal, x",
            ),
            V::real_input(
                "F_T_y",
                vr::F_T_Y,
                0.0,
                "N",
                "air-film force on the turbine-side journal, y",
            ),
            V::real_output(
                "dx_C",
                vr::DX_C,
                "m",
                "compressor-side journal relative to its ring, x",
            )
            .display("um"),
            V::real_output(
                "dy_C",
                vr::DY_C,
                "m",
                "compressor-side journal relative to its ring, y",
            )
            .display("um"),
            V::real_output(
                "vx_C",
                vr::VX_C,
                "m/s",
                "relative velocity, compressor side, x",
            )
            .display("mm/s"),
            V::real_output(
                "vy_C",
                vr::VY_C,
                "m/s",
                "relative velocity, compressor side, y",
            )
            .display("mm/s"),
            V::real_output(
                "dx_T",
                vr::DX_T,
                "m",
                "turbine-side journal relative to its ring, x",
            )
            .display("um"),
            V::real_output(
                "dy_T",
                vr::DY_T,
                "m",
                "turbine-side journal relative to its ring, y",
            )
            .display("um"),
            V::real_output(
                "vx_T",
                vr::VX_T,
                "m/s",
                "relative velocity, turbine side, x",
            )
            .display("mm/s"),
            V::real_output(
                "vy_T",
                vr::VY_T,
                "m/s",
                "relative velocity, turbine side, y",
            )
            .display("mm/s"),
            V::real_output("omega", vr::OMEGA, "rad/s", "rotor speed").display("Hz"),
            V::real_output(
                "x_JC",
                vr::X_JC,
                "m",
                "absolute compressor-side journal position, x",
            )
            .display("um"),
            V::real_output(
                "y_JC",
                vr::Y_JC,
                "m",
                "absolute compressor-side journal position, y",
            )
            .display("um"),
            V::real_output(
                "x_JT",
                vr::X_JT,
                "m",
                "absolute turbine-side journal position, x",
            )
            .display("um"),
            V::real_output(
                "y_JT",
                vr::Y_JT,
                "m",
                "absolute turbine-side journal position, y",
            )
            .display("um"),
            V::real_output("x_RC", vr::X_RC, "m", "compressor-side ring position, x").display("um"),
            V::real_output("y_RC", vr::Y_RC, "m", "compressor-side ring position, y").display("um"),
            V::real_output("x_RT", vr::X_RT, "m", "turbine-side ring position, x").display("um"),
            V::real_output("y_RT", vr::Y_RT, "m", "turbine-side ring position, y").display("um"),
            V::real_output(
                "tilt_x",
                vr::TILT_X,
                "rad",
                "rotor tilt angle about x (Cardan)",
            )
            .display("deg"),
            V::real_output(
                "tilt_y",
                vr::TILT_Y,
                "rad",
                "rotor tilt angle about y (Cardan)",
            )
            .display("deg"),
            V::real_output("spin_angle", vr::SPIN_ANGLE, "rad", "rotor spin angle"),
            V::real_output(
                "drift_pos",
                vr::DRIFT_POS,
                "1",
                "largest position-level constraint residual |g| of the last step",
            ),
            V::real_output(
                "drift_vel",
                vr::DRIFT_VEL,
                "1",
                "largest velocity-level constraint residual of the last step",
            ),
            V::integer_output("n_steps", vr::N_STEPS, "accepted internal BDF steps so far"),
            V::integer_output(
                "n_rejected",
                vr::N_REJECTED,
                "rejected internal steps so far",
            ),
            V::integer_output("n_newton", vr::N_NEWTON, "Newton iterations so far"),
            V::real_parameter(
                "disturbance_force",
                vr::DIST_FORCE,
                p.disturbance.force_rms_n,
                "N",
                "standard deviation of a random force on each journal, x and y (seed of whirl; 0 = off)",
            )
            .display("mN")
            .range(Some(0.0), None),
            V::real_parameter(
                "disturbance_interval",
                vr::DIST_INTERVAL,
                p.disturbance.interval_s,
                "s",
                "grid spacing of the random disturbance values (bandwidth about 1/(2 interval))",
            )
            .display("us"),
            V::integer_parameter(
                "disturbance_seed",
                vr::DIST_SEED,
                p.disturbance.seed as i32,
                "seed of the disturbance generator (other seeds: independent realisations)",
            ),
            V::integer_parameter(
                "max_internal_steps",
                vr::MAX_STEPS,
                p.max_steps_per_call as i32,
                "internal BDF steps allowed per fmi2DoStep beyond 10 x interval/h_max (that part at most 100000); more end in fmi2Discard (raise it with very tight tolerances)",
            )
            .range(Some(1.0), Some(crate::params::MAX_STEPS_LIMIT as f64)),
        ]);
        variables.extend(contact_vars());
        variables.extend(speed_table_vars());
        ModelInfo {
            model_name: "rotor",
            model_identifier: "rotor",
            description: "Turbo-compressor rotor with two visco-elastically mounted bearing rings: rigid (GGL stabilized index-2 multibody model), or a flexible shaft where resources/shaft.json holds one (Timoshenko elements, Craig-Bampton reduction)",
            version: env!("CARGO_PKG_VERSION"),
            variables,
            log_categories: vec![
                ("logSolverStatistics", "steps, Newton iterations and constraint drift per communication step"),
                ("logModel", "what the model was built from: a flexible rotor's shaft and its reduction, with the reduction's measured error"),
            ],
            default_experiment: DefaultExperiment { start_time: 0.0, stop_time: 0.1, tolerance: 1e-4, step_size: 1e-5 },
            documentation_html: DOC,
        }
    }

    /// The speed profile and the ring rest positions are defined from t = 0.
    fn check_start_time(start_time_s: f64) -> Result<(), String> {
        if start_time_s != 0.0 {
            return Err(format!(
                "the run-up profile starts at t = 0; startTime {} s is not supported",
                bearing::num::Num(start_time_s)
            ));
        }
        Ok(())
    }

    fn check_tolerance(tolerance: f64) -> Result<(), String> {
        if tolerance < crate::params::MIN_RTOL {
            return Err(format!(
                "tolerance {} is below {}, the smallest relative tolerance the rotor's BDF2 \
                 steps reach in double precision",
                bearing::num::Num(tolerance),
                bearing::num::Num(crate::params::MIN_RTOL)
            ));
        }
        Ok(())
    }

    fn new(
        store: &Store,
        start_time: f64,
        resources: Option<&std::path::Path>,
        log: &mut dyn Log,
    ) -> Result<Self, String> {
        Self::check_start_time(start_time)?;
        let params = params_from(store);
        params.validate().map_err(|e| in_units(e.to_string()))?;
        let sim = match flexible_spec(resources)? {
            None => Simulator::Rigid(Box::new(Rotor::new(params).map_err(|e| e.to_string())?)),
            Some(spec) => {
                let f = FlexRotor::new(params, spec).map_err(|e| in_units(e.to_string()))?;
                let r = &f.reduction;
                log.debug(
                    "logModel",
                    &format!(
                        "flexible rotor of resources/{}: {} elements, {} coordinates reduced to {} \
                         ({} fixed-interface modes kept, up to {:.0} Hz; {} dropped), natural \
                         frequencies up to {:.0} Hz within {:.3} % of the full model; m, J_t, \
                         J_p, z_cm, z_JC and z_JT are not used",
                        crate::flexible::RESOURCE_FILE,
                        f.spec().shaft.elements.len(),
                        r.full_dof,
                        r.reduced_dof,
                        r.kept_modes_hz.len(),
                        r.kept_modes_hz.last().copied().unwrap_or(0.0),
                        r.dropped_modes,
                        r.compared_up_to_hz,
                        100.0 * r.frequency_error
                    ),
                );
                Simulator::Flexible(Box::new(f))
            }
        };
        Ok(RotorFmu { sim })
    }

    fn do_step(
        &mut self,
        t: f64,
        h: f64,
        inputs: &dyn StepInputs,
        log: &mut dyn Log,
    ) -> StepOutcome {
        let forces = |tt: f64| BearingForces {
            fc_x_n: inputs.real_at(vr::F_C_X, tt),
            fc_y_n: inputs.real_at(vr::F_C_Y, tt),
            ft_x_n: inputs.real_at(vr::F_T_X, tt),
            ft_y_n: inputs.real_at(vr::F_T_Y, tt),
        };
        let result = match &mut self.sim {
            Simulator::Rigid(r) => r.advance(t, h, &forces),
            Simulator::Flexible(f) => f.advance(t, h, &forces),
        };
        match result {
            Ok(s) => {
                if log.enabled("logSolverStatistics") {
                    log.debug(
                        "logSolverStatistics",
                        &format!(
                            "t = {:.9} s: {} steps ({} rejected), {} Newton iterations, drift {:.2e} / {:.2e}",
                            t + h,
                            s.steps,
                            s.rejected_steps,
                            s.newton_iterations,
                            s.max_drift_pos,
                            s.max_drift_vel
                        ),
                    );
                }
                StepOutcome::Ok
            }
            Err(e @ RotorError::StepFailure { .. }) => StepOutcome::Discard {
                reason: e.to_string(),
                reached_time: self.time_s(),
            },
            Err(e) => StepOutcome::Error(e.to_string()),
        }
    }

    fn write_outputs(&self, store: &mut Store) {
        let o = self.outputs();
        let r = &mut store.reals;
        for (base, b) in [(vr::DX_C, &o.bearing_c), (vr::DX_T, &o.bearing_t)] {
            let base = base as usize;
            r[base] = b.dx_m;
            r[base + 1] = b.dy_m;
            r[base + 2] = b.vx_m_s;
            r[base + 3] = b.vy_m_s;
        }
        r[vr::OMEGA as usize] = o.omega_rad_s;
        r[vr::X_JC as usize] = o.bearing_c.journal_m[0];
        r[vr::Y_JC as usize] = o.bearing_c.journal_m[1];
        r[vr::X_JT as usize] = o.bearing_t.journal_m[0];
        r[vr::Y_JT as usize] = o.bearing_t.journal_m[1];
        r[vr::X_RC as usize] = o.bearing_c.ring_m[0];
        r[vr::Y_RC as usize] = o.bearing_c.ring_m[1];
        r[vr::X_RT as usize] = o.bearing_t.ring_m[0];
        r[vr::Y_RT as usize] = o.bearing_t.ring_m[1];
        r[vr::TILT_X as usize] = o.tilt_x_rad;
        r[vr::TILT_Y as usize] = o.tilt_y_rad;
        r[vr::SPIN_ANGLE as usize] = o.spin_angle_rad;
        r[vr::DRIFT_POS as usize] = o.drift_pos;
        r[vr::DRIFT_VEL as usize] = o.drift_vel;
        r[vr::F_CONTACT_C as usize] = o.bearing_c.contact_n[0].hypot(o.bearing_c.contact_n[1]);
        r[vr::F_CONTACT_T as usize] = o.bearing_t.contact_n[0].hypot(o.bearing_t.contact_n[1]);
        let s = self.totals();
        let clamp = |n: u64| n.min(i32::MAX as u64) as i32;
        store.integers[vr::N_STEPS as usize] = clamp(s.steps);
        store.integers[vr::N_REJECTED as usize] = clamp(s.rejected_steps);
        store.integers[vr::N_NEWTON as usize] = clamp(s.newton_iterations);
    }

    fn output_derivative(&self, vr: u32, order: i32) -> Option<f64> {
        if order != 1 {
            return None;
        }
        let d = self.output_derivatives();
        let o = self.outputs();
        Some(match vr {
            vr::DX_C => d.bearing_c.ddx_m_s,
            vr::DY_C => d.bearing_c.ddy_m_s,
            vr::VX_C => d.bearing_c.dvx_m_s2,
            vr::VY_C => d.bearing_c.dvy_m_s2,
            vr::DX_T => d.bearing_t.ddx_m_s,
            vr::DY_T => d.bearing_t.ddy_m_s,
            vr::VX_T => d.bearing_t.dvx_m_s2,
            vr::VY_T => d.bearing_t.dvy_m_s2,
            vr::OMEGA => d.domega_rad_s2,
            vr::SPIN_ANGLE => o.omega_rad_s,
            _ => return None,
        })
    }

    fn serialize(&self) -> Vec<u8> {
        match &self.sim {
            Simulator::Rigid(r) => bincode::serialize(r).expect("the rotor state serializes"),
            Simulator::Flexible(f) => {
                let mut out = FLEXIBLE_MAGIC.to_vec();
                bincode::serialize_into(&mut out, f).expect("the rotor state serializes");
                out
            }
        }
    }

    fn deserialize(bytes: &[u8]) -> Result<Self, String> {
        let sim = match bytes.strip_prefix(FLEXIBLE_MAGIC) {
            Some(rest) => Simulator::Flexible(
                bincode::deserialize(rest).map_err(|e| format!("not a rotor state: {e}"))?,
            ),
            None => Simulator::Rigid(
                bincode::deserialize(bytes).map_err(|e| format!("not a rotor state: {e}"))?,
            ),
        };
        Ok(RotorFmu { sim })
    }
}

#[cfg(feature = "fmu")]
fmi2::export_fmu!(RotorFmu);

/// A refusal of a parameter with its value in the units this FMU declares for it ("c_C = -5000
/// N/m (-5 N/mm)"), as the libraries give it in bare SI ("c_C = -5000").
fn in_units(error: String) -> String {
    fmi_core::units::parameter_error_with_units(&<RotorFmu as Model>::info(), error, &|x| {
        bearing::num::Num(x).to_string()
    })
}
