//! The FMU shell: the variable table of `airfilm.fmu` and the `fmi_core::model::Model` implementation that maps
//! FMI variables onto [`AirFilm`]. The physics knows nothing of this module.
//!
//! Value references are part of the product (third-party masters store them): append, never renumber.

use crate::{AirFilm, BearingParams, FilmError, FilmOutputs, JournalState};
use fmi_core::model::{Log, Model, StepInputs, StepOutcome, Store};
use fmi_core::variables::{DefaultExperiment, ModelInfo, Variable};
use serde::{Deserialize, Serialize};

/// Real value references.
pub mod vr {
    pub const R: u32 = 0;
    pub const B: u32 = 1;
    pub const C: u32 = 2;
    pub const DH: u32 = 3;
    pub const PHI_T: u32 = 4;
    pub const ALPHA: u32 = 5;
    pub const ETA: u32 = 6;
    pub const P_A: u32 = 7;
    pub const H_CON_REL: u32 = 8;
    pub const C_CON: u32 = 9;
    pub const RTOL: u32 = 10;
    pub const ATOL: u32 = 11;
    pub const H_MAX: u32 = 12;
    pub const DX: u32 = 13;
    pub const DY: u32 = 14;
    pub const VX: u32 = 15;
    pub const VY: u32 = 16;
    pub const OMEGA: u32 = 17;
    pub const FX: u32 = 18;
    pub const FY: u32 = 19;
    pub const EPS: u32 = 20;
    pub const H_MIN: u32 = 21;
    pub const P_MAX: u32 = 22;
    pub const F_CONTACT: u32 = 23;
    pub const FRICTION_TORQUE: u32 = 24;
    pub const POWER_LOSS: u32 = 25;
    pub const MESH_GRADING: u32 = 26;
    /// Integer value references.
    pub const N_LOBES: u32 = 0;
    pub const N_ELEM_PHI: u32 = 1;
    pub const N_ELEM_Z: u32 = 2;
    pub const N_SUBSTEPS: u32 = 3;
    pub const N_NEWTON: u32 = 4;
    pub const N_JACOBIANS: u32 = 5;
    pub const N_REJECTED: u32 = 6;
    pub const N_PRESSURE_FLOORED: u32 = 7;
    /// Boolean value references.
    pub const PLAIN_BORE: u32 = 0;
    pub const START_STEADY: u32 = 1;
    pub const CONTACT_IN_FORCE: u32 = 2;
}

const DOC: &str = include_str!("shell_doc.html");

/// The FMU's model: the film plus what FMI needs on top (output derivatives).
#[derive(Debug, Serialize, Deserialize)]
pub struct AirFilmFmu {
    film: AirFilm,
    outputs: FilmOutputs,
    /// Forces at the previous communication point and its time, for the output derivatives.
    previous: Option<(f64, [f64; 2])>,
    time_s: f64,
    /// The vacuum floor was reported (warned once per instance, kept across state restores).
    /// Not serialized.
    #[serde(skip)]
    floor_reported: bool,
}

/// FMU states: `clone_from` (fmi2GetFMUstate into an existing state, fmi2SetFMUstate) goes
/// through the film's buffer-reusing `clone_from`.
impl Clone for AirFilmFmu {
    fn clone(&self) -> Self {
        AirFilmFmu {
            film: self.film.clone(),
            outputs: self.outputs,
            previous: self.previous,
            time_s: self.time_s,
            floor_reported: self.floor_reported,
        }
    }

    fn clone_from(&mut self, src: &Self) {
        let AirFilmFmu {
            film,
            outputs,
            previous,
            time_s,
            floor_reported,
        } = src;
        self.film.clone_from(film);
        (self.outputs, self.previous, self.time_s) = (*outputs, *previous, *time_s);
        // Sticky: a roll-back to a state from before the warning must not repeat it.
        self.floor_reported |= *floor_reported;
    }
}

impl AirFilmFmu {
    /// The film's scaled nodal pressures p / p_a (the master's full-state orbit search reads them
    /// in a deserialized FMU state).
    pub fn pressures_rel(&self) -> &[f64] {
        self.film.pressures_rel()
    }

    /// Per entry of `pressures_rel`: a node held at ambient pressure (Dirichlet boundary), not
    /// a state of the film's dynamics.
    pub fn fixed_nodes(&self) -> Vec<bool> {
        let mesh = self.film.mesh();
        (0..mesh.n_blocks * mesh.npb)
            .map(|i| mesh.dirichlet[i % mesh.npb])
            .collect()
    }

    /// Restarts the film at its current time and journal state with the pressures `p_rel`
    /// (first-order steps again, outputs of the new field, no output derivative history).
    pub fn restart_with_pressures(&mut self, p_rel: &[f64]) -> Result<(), String> {
        let journal = self.film.journal();
        self.film
            .set_pressures_rel(self.time_s, journal, p_rel)
            .map_err(|e| e.to_string())?;
        self.outputs = self.film.outputs();
        self.previous = None;
        Ok(())
    }
}

/// The film parameters from the FMU's variable values (also used by `airring orbit`, which drives
/// the library with exactly the FMU's parameter mapping).
pub fn params_from(store: &Store) -> BearingParams {
    let mut p = BearingParams::paper();
    p.bore.r_m = store.real(vr::R);
    p.bore.b_m = store.real(vr::B);
    p.bore.c_m = store.real(vr::C);
    p.bore.dh_m = store.real(vr::DH);
    p.bore.phi_t_rad = store.real(vr::PHI_T);
    p.bore.alpha_rad = store.real(vr::ALPHA);
    p.eta_pa_s = store.real(vr::ETA);
    p.p_a_pa = store.real(vr::P_A);
    p.contact.h_con_rel = store.real(vr::H_CON_REL);
    p.contact.c_con_n_per_m3 = store.real(vr::C_CON);
    p.rtol = store.real(vr::RTOL);
    p.atol_pa = store.real(vr::ATOL);
    p.h_max_s = store.real(vr::H_MAX);
    p.bore.n_lobes = store.integer(vr::N_LOBES).max(0) as usize;
    p.n_elem_phi = store.integer(vr::N_ELEM_PHI).max(0) as usize;
    p.n_elem_z = store.integer(vr::N_ELEM_Z).max(0) as usize;
    p.mesh_grading = store.real(vr::MESH_GRADING);
    p.bore.plain_bore = store.boolean(vr::PLAIN_BORE);
    p.contact_in_force = store.boolean(vr::CONTACT_IN_FORCE);
    p
}

fn journal_at(inputs: &dyn StepInputs, t: f64) -> JournalState {
    JournalState {
        dx_m: inputs.real_at(vr::DX, t),
        dy_m: inputs.real_at(vr::DY, t),
        vx_m_s: inputs.real_at(vr::VX, t),
        vy_m_s: inputs.real_at(vr::VY, t),
        omega_rad_s: inputs.real_at(vr::OMEGA, t),
    }
}

impl Model for AirFilmFmu {
    fn info() -> ModelInfo {
        let p = BearingParams::paper();
        use Variable as V;
        ModelInfo {
            model_name: "airfilm",
            model_identifier: "airfilm",
            description: "Air film of one three-lobe air ring bearing: isothermal compressible Reynolds equation, 9-node FE, implicit BDF, mixed-lubrication contact",
            version: env!("CARGO_PKG_VERSION"),
            variables: vec![
                V::real_parameter("r", vr::R, p.bore.r_m, "m", "journal radius").display("mm"),
                V::real_parameter("b", vr::B, p.bore.b_m, "m", "bearing (ring) width").display("mm"),
                V::real_parameter("C", vr::C, p.bore.c_m, "m", "nominal clearance (gap at each lobe's trailing edge)").display("um"),
                V::real_parameter("dH", vr::DH, p.bore.dh_m, "m", "step height: extra gap at each lobe's leading edge").display("um"),
                V::real_parameter("phi_t", vr::PHI_T, p.bore.phi_t_rad, "rad", "lobe angle, in (0, 2 pi/n_lobes)").display("deg"),
                V::real_parameter("alpha", vr::ALPHA, p.bore.alpha_rad, "rad", "ring orientation: global angle = ring angle + alpha (paper: pi - phi_t)")
                    .display("deg"),
                V::real_parameter("eta", vr::ETA, p.eta_pa_s, "Pa.s", "dynamic viscosity of the gas"),
                V::real_parameter("p_a", vr::P_A, p.p_a_pa, "Pa", "ambient pressure").display("bar"),
                V::real_parameter("h_con_rel", vr::H_CON_REL, p.contact.h_con_rel, "1", "contact threshold h_con / C (mixed lubrication)"),
                V::real_parameter("c_con", vr::C_CON, p.contact.c_con_n_per_m3, "N/m3", "penalty stiffness of the asperity contact pressure").display("N/mm3"),
                V::real_parameter("rtol", vr::RTOL, p.rtol, "1", "relative tolerance of the time integration's error control"),
                V::real_parameter("atol", vr::ATOL, p.atol_pa, "Pa", "absolute pressure tolerance of the error control"),
                V::real_parameter("h_max", vr::H_MAX, p.h_max_s, "s", "largest internal sub-step").display("ms"),
                V::real_input("dx", vr::DX, 0.0, "m", "journal displacement relative to the ring, x (horizontal)").display("um"),
                V::real_input("dy", vr::DY, 0.0, "m", "journal displacement relative to the ring, y (vertical, up)").display("um"),
                V::real_input("vx", vr::VX, 0.0, "m/s", "journal velocity relative to the ring, x").display("mm/s"),
                V::real_input("vy", vr::VY, 0.0, "m/s", "journal velocity relative to the ring, y").display("mm/s"),
                V::real_input("omega", vr::OMEGA, 0.0, "rad/s", "rotor speed (positive: right-handed about +z)").display("Hz"),
                V::real_output("Fx", vr::FX, "N", "force of the film (and of the contact if contact_in_force) on the journal, x (the ring feels -Fx)"),
                V::real_output("Fy", vr::FY, "N", "force of the film (and of the contact if contact_in_force) on the journal, y (the ring feels -Fy)"),
                V::real_output("eps", vr::EPS, "1", "eccentricity ratio |d| / C (may exceed 1 without contact)"),
                V::real_output("h_min", vr::H_MIN, "m", "minimum gap on the lobes").display("um"),
                V::real_output("p_max", vr::P_MAX, "Pa", "peak film pressure (absolute)").display("bar"),
                V::real_output("F_contact", vr::F_CONTACT, "N", "magnitude of the mixed-lubrication contact force (reported even when contact_in_force = false)"),
                V::real_output("friction_torque", vr::FRICTION_TORQUE, "N.m", "friction torque of the film on the journal, against its rotation: wall shear (Couette and pressure-driven) over the lobes, Couette shear over the pockets (modelled as deep as the step; see the documentation)").display("N.mm"),
                V::real_output("power_loss", vr::POWER_LOSS, "W", "power the film dissipates: friction_torque * omega"),
                V::integer_parameter("n_lobes", vr::N_LOBES, p.bore.n_lobes as i32, "number of lobes").range(Some(1.0), Some(12.0)),
                V::integer_parameter("n_elem_phi", vr::N_ELEM_PHI, p.n_elem_phi as i32, "elements along each lobe (paper: 20; at least 8 for a plain bore)")
                    .range(Some(4.0), Some(2000.0)),
                V::integer_parameter("n_elem_z", vr::N_ELEM_Z, p.n_elem_z as i32, "elements across the half width (paper: 6)")
                    .range(Some(2.0), Some(500.0)),
                V::real_parameter("mesh_grading", vr::MESH_GRADING, p.mesh_grading, "1", "each element along a lobe is this many times as long as the one before it: 1 uniform (paper), below 1 finer toward the lobe's trailing edge, where the pressure falls to ambient in a thin layer; a plain bore's mesh is always uniform")
                    .range(Some(crate::params::MIN_MESH_GRADING), Some(1.0)),
                V::integer_output("n_substeps", vr::N_SUBSTEPS, "accepted internal sub-steps so far"),
                V::integer_output("n_newton", vr::N_NEWTON, "Newton iterations so far"),
                V::integer_output("n_jacobians", vr::N_JACOBIANS, "Jacobian evaluations and factorizations so far"),
                V::integer_output("n_rejected", vr::N_REJECTED, "rejected internal sub-steps so far"),
                V::integer_output("n_pressure_floored", vr::N_PRESSURE_FLOORED, "nodal pressures raised to the vacuum floor of 1e-3 p_a so far (0 in a well-resolved film; see the documentation)"),
                V::boolean_parameter("plain_bore", vr::PLAIN_BORE, false, "plain 360-degree bore with periodic boundary conditions (needs dH = 0)"),
                V::boolean_parameter(
                    "contact_in_force",
                    vr::CONTACT_IN_FORCE,
                    p.contact_in_force,
                    "add the contact force to Fx, Fy; false when the rotor evaluates the contact itself (rotor.fmu parameter contact = true), which keeps the stiff contact out of the explicit coupling",
                ),
                V::boolean_parameter(
                    "start_steady",
                    vr::START_STEADY,
                    false,
                    "start from the steady pressure field at the initial inputs instead of p = p_a",
                ),
            ],
            log_categories: vec![("logSolverStatistics", "sub-steps, Newton iterations and Jacobians per communication step")],
            default_experiment: DefaultExperiment { start_time: 0.0, stop_time: 0.01, tolerance: 1e-4, step_size: 1e-5 },
            documentation_html: DOC,
        }
    }

    fn check_tolerance(tolerance: f64) -> Result<(), String> {
        if tolerance < crate::params::MIN_RTOL {
            return Err(format!(
                "tolerance {} is below {}, the smallest relative tolerance the air film's \
                 Newton iteration reaches in double precision",
                bearing::num::Num(tolerance),
                bearing::num::Num(crate::params::MIN_RTOL)
            ));
        }
        Ok(())
    }

    fn new(
        store: &Store,
        start_time: f64,
        _resources: Option<&std::path::Path>,
        _log: &mut dyn Log,
    ) -> Result<Self, String> {
        let params = params_from(store);
        params.validate().map_err(|e| in_units(e.to_string()))?;
        let mut film = AirFilm::new(params.clone()).map_err(|e| e.to_string())?;
        let journal = JournalState {
            dx_m: store.real(vr::DX),
            dy_m: store.real(vr::DY),
            vx_m_s: store.real(vr::VX),
            vy_m_s: store.real(vr::VY),
            omega_rad_s: store.real(vr::OMEGA),
        };
        crate::check_finite(&journal, start_time).map_err(|e| e.to_string())?;
        let p_rel = if store.boolean(vr::START_STEADY) {
            crate::steady_state(&params, journal)
                .map_err(|e| format!("steady start: {e}"))?
                .p_rel
        } else {
            vec![1.0; film.pressures_rel().len()]
        };
        film.set_pressures_rel(start_time, journal, &p_rel)
            .map_err(|e| e.to_string())?;
        let outputs = film.outputs();
        if outputs.h_min_m <= 0.0 {
            return Err(FilmError::BeyondContactLimit {
                h_min_m: outputs.h_min_m,
                t_s: start_time,
            }
            .to_string());
        }
        Ok(AirFilmFmu {
            film,
            outputs,
            previous: None,
            time_s: start_time,
            floor_reported: false,
        })
    }

    fn do_step(
        &mut self,
        t: f64,
        h: f64,
        inputs: &dyn StepInputs,
        log: &mut dyn Log,
    ) -> StepOutcome {
        let before = [self.outputs.fx_n, self.outputs.fy_n];
        let result = self.film.advance(t, h, &|tt| journal_at(inputs, tt));
        let outputs = self.film.outputs();
        if !outputs.all_finite() {
            // Whatever the solver said, a NaN or infinite force must never reach an output (a
            // master would feed it to the rotor): the outputs stay those of the last good point.
            return StepOutcome::Error(format!(
                "t = {} s: the film's outputs became NaN or infinite (inputs dx = {} m, dy = {} m, \
                 omega = {} rad/s); the outputs keep their values at t = {t} s",
                self.film.time_s(),
                inputs.real_at(vr::DX, t + h),
                inputs.real_at(vr::DY, t + h),
                inputs.real_at(vr::OMEGA, t + h),
            ));
        }
        self.outputs = outputs;
        match result {
            Ok(stats) => {
                if stats.n_pressure_floored > 0 && !self.floor_reported {
                    self.floor_reported = true;
                    log.warning(&format!(
                        "t = {:.9} s: {} nodal pressures fell below the vacuum floor {} p_a and were \
                         raised to it (the film is under-resolved where the gap nearly closes; \
                         reported once, counted in n_pressure_floored)",
                        t + h,
                        stats.n_pressure_floored,
                        crate::P_FLOOR_REL
                    ));
                }
                self.previous = Some((t, before));
                self.time_s = t + h;
                if log.enabled("logSolverStatistics") {
                    log.debug(
                        "logSolverStatistics",
                        &format!(
                            "t = {:.9} s: {} sub-steps ({} rejected), {} Newton iterations, {} Jacobians, last sub-step {:.3e} s",
                            t + h,
                            stats.n_steps,
                            stats.n_rejected,
                            stats.n_newton_iters,
                            stats.n_jacobians,
                            stats.h_last_s
                        ),
                    );
                }
                StepOutcome::Ok
            }
            // A journal that crosses the contact limit inside the step usually does so because the
            // master's input polynomial overshoots over a long macro step (the journal is stopped by
            // the stiff contact force of the previous step's output): Discard lets the master roll
            // back and retry with smaller steps, which follow the contact more closely.
            Err(
                e @ (FilmError::NewtonFailure { .. }
                | FilmError::TooManySubsteps { .. }
                | FilmError::BeyondContactLimit { .. }),
            ) => {
                let reached = self.film.time_s();
                self.previous = None;
                self.time_s = reached;
                StepOutcome::Discard {
                    reason: e.to_string(),
                    reached_time: reached,
                }
            }
            Err(e) => StepOutcome::Error(e.to_string()),
        }
    }

    fn write_outputs(&self, store: &mut Store) {
        let o = &self.outputs;
        store.reals[vr::FX as usize] = o.fx_n;
        store.reals[vr::FY as usize] = o.fy_n;
        store.reals[vr::EPS as usize] = o.eps;
        store.reals[vr::H_MIN as usize] = o.h_min_m;
        store.reals[vr::P_MAX as usize] = o.p_max_pa;
        store.reals[vr::F_CONTACT as usize] = o.f_contact_n;
        store.reals[vr::FRICTION_TORQUE as usize] = o.friction_torque_nm;
        store.reals[vr::POWER_LOSS as usize] = o.power_loss_w;
        let s = self.film.total_stats();
        let clamp = |n: usize| n.min(i32::MAX as usize) as i32;
        store.integers[vr::N_SUBSTEPS as usize] = clamp(s.n_steps);
        store.integers[vr::N_NEWTON as usize] = clamp(s.n_newton_iters);
        store.integers[vr::N_JACOBIANS as usize] = clamp(s.n_jacobians);
        store.integers[vr::N_REJECTED as usize] = clamp(s.n_rejected);
        store.integers[vr::N_PRESSURE_FLOORED as usize] = clamp(s.n_pressure_floored);
    }

    /// First derivatives of Fx, Fy: the backward difference over the last communication step
    /// (0 before the first step). The film has no cheaper exact rate of its force.
    fn output_derivative(&self, vr: u32, order: i32) -> Option<f64> {
        if order != 1 {
            return None;
        }
        let rate = |now: f64, k: usize| match self.previous {
            Some((t0, f0)) if self.time_s > t0 => (now - f0[k]) / (self.time_s - t0),
            _ => 0.0,
        };
        match vr {
            vr::FX => Some(rate(self.outputs.fx_n, 0)),
            vr::FY => Some(rate(self.outputs.fy_n, 1)),
            _ => None,
        }
    }

    fn serialize(&self) -> Vec<u8> {
        bincode::serialize(self).expect("the film state serializes")
    }

    fn deserialize(bytes: &[u8]) -> Result<Self, String> {
        let fmu: AirFilmFmu =
            bincode::deserialize(bytes).map_err(|e| format!("not an air-film state: {e}"))?;
        fmu.film
            .check_layout()
            .map_err(|e| format!("not an air-film state of this build: {e}"))?;
        Ok(fmu)
    }
}

#[cfg(feature = "fmu")]
fmi2::export_fmu!(AirFilmFmu);

/// A refusal of a parameter with its value in the units this FMU declares for it ("C = -2.5e-5 m
/// (-25 um)"), as the libraries give it in bare SI ("C = -0.000025").
fn in_units(error: String) -> String {
    fmi_core::units::parameter_error_with_units(&<AirFilmFmu as Model>::info(), error, &|x| {
        bearing::num::Num(x).to_string()
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    struct NoLog;
    impl Log for NoLog {
        fn debug(&mut self, _category: &str, _message: &str) {}
        fn warning(&mut self, _message: &str) {}
    }

    /// The full-state orbit search's restart: the fixed nodes are the ambient-pressure boundary,
    /// a restart with the film's own field keeps its forces, another field gives its forces, and
    /// a field of the wrong length or with a non-positive pressure is refused.
    #[test]
    fn a_restart_with_pressures_gives_that_fields_outputs() {
        let info = AirFilmFmu::info();
        let mut store = Store::from_info(&info);
        store.integers[vr::N_ELEM_PHI as usize] = 8;
        store.integers[vr::N_ELEM_Z as usize] = 2;
        store.reals[vr::OMEGA as usize] = std::f64::consts::TAU * 1000.0;
        store.reals[vr::DY as usize] = -0.3 * store.reals[vr::C as usize];
        store.booleans[vr::START_STEADY as usize] = true;
        let mut m = AirFilmFmu::new(&store, 0.0, None, &mut NoLog).unwrap();
        let fixed = m.fixed_nodes();
        let p0 = m.pressures_rel().to_vec();
        assert_eq!(fixed.len(), p0.len());
        assert!(fixed.iter().any(|f| *f) && fixed.iter().any(|f| !*f));
        for (p, f) in p0.iter().zip(&fixed) {
            if *f {
                assert!(
                    (p - 1.0).abs() < 1e-12,
                    "a boundary node holds ambient pressure: {p}"
                );
            }
        }
        let before = m.outputs;
        m.restart_with_pressures(&p0).unwrap();
        assert_eq!(m.outputs, before);
        assert!(m.previous.is_none());
        // Ambient everywhere: no load.
        m.restart_with_pressures(&vec![1.0; p0.len()]).unwrap();
        assert!(
            m.outputs.fx_n.abs() < 1e-9 && m.outputs.fy_n.abs() < 1e-9,
            "{:?}",
            m.outputs
        );
        assert!(m.restart_with_pressures(&p0[1..]).is_err());
        let mut bad = p0.clone();
        bad[0] = 0.0;
        assert!(m.restart_with_pressures(&bad).is_err());
    }

    /// A step whose outputs would come out NaN or infinite (here: a film whose pressures overflow
    /// the force integral) is an error, and the outputs keep their last good values: a master
    /// never reads inf from this FMU, whatever the solver said about the step.
    #[test]
    fn a_step_with_non_finite_outputs_is_an_error_and_keeps_the_last_good_outputs() {
        let info = AirFilmFmu::info();
        let mut store = Store::from_info(&info);
        store.integers[vr::N_ELEM_PHI as usize] = 8;
        store.integers[vr::N_ELEM_Z as usize] = 2;
        store.reals[vr::OMEGA as usize] = std::f64::consts::TAU * 1000.0;
        let mut m = AirFilmFmu::new(&store, 0.0, None, &mut NoLog).unwrap();
        let good = m.outputs;
        assert!(good.all_finite());
        let n = m.film.pressures_rel().len();
        let j = m.film.journal();
        m.film.set_pressures_rel(0.0, j, &vec![1e307; n]).unwrap();
        let inputs = fmi_core::model::Inputs {
            t0: 0.0,
            values: store.reals.clone(),
            derivatives: vec![
                [0.0; fmi_core::model::MAX_INPUT_DERIVATIVE_ORDER];
                store.reals.len()
            ],
        };
        match m.do_step(0.0, 1e-5, &inputs, &mut NoLog) {
            StepOutcome::Error(e) => assert!(e.contains("NaN or infinite"), "{e}"),
            other => panic!("expected an error, got {other:?}"),
        }
        assert_eq!(m.outputs, good);
        let mut out = store.clone();
        m.write_outputs(&mut out);
        for v in [vr::FX, vr::FY, vr::EPS, vr::POWER_LOSS] {
            assert!(out.reals[v as usize].is_finite());
        }
    }
}
