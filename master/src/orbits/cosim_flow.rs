//! The co-simulated rotor in its two air films as a [`Flow`] at constant speed: the period map
//! the shooting works on is the co-simulation itself, run from a chosen start state.
//!
//! The state is the rotor's lateral state (the rigid rotor's 16 values: rotor centre x, y,
//! tilts, ring positions, and their rates, `fmu_rotor::rotor::LATERAL_COORDS`; a flexible
//! rotor's reduced coordinates and rings, and their rates). A flow restores a base checkpoint of
//! the whole system (FMU states and the algorithm's coupling history), puts the start state
//! into the rotor's FMU state (decoded, the rotor restarted there, encoded again: FMU state
//! get/set is what makes the period map a function of the start state), restarts the input
//! polynomials and co-simulates. The films start from the base's pressure field, so this is the
//! reduced shooting in the mechanical coordinates with the film pressures relaxed onto them:
//! after a converged orbit the base moves to the orbit's end ([`RotorFilmFlow::rebase`]) and
//! the shooting repeats until the film's start field no longer moves the orbit.

use super::continuation::ParamFlow;
use super::shooting::Flow;
use crate::runup::RunupSettings;
use cosim::algorithm::{AlgorithmState, CoSim};
use fmi_core::model::{Model, Store};
use fmu_airfilm::shell::AirFilmFmu;
use fmu_rotor::shell::RotorFmu;
use std::path::Path;

pub struct RotorFilmFlow {
    /// The lateral state's length (16 for the rigid rotor).
    n_lateral: usize,
    cosim: CoSim,
    rotor: usize,
    films: [usize; 2],
    rotor_guid: String,
    rotor_shape: Store,
    /// GUIDs of the film FMUs (C, T) and a store of the film's variable table, for decoding
    /// their FMU states (the full-state shooting sets their pressure fields).
    film_guids: [String; 2],
    film_shape: Store,
    base: (AlgorithmState, Vec<Vec<u8>>),
    speed_hz: f64,
    macro_step_s: f64,
    clearance_m: [f64; 2],
    scale: Vec<f64>,
    /// Flows run, macro steps co-simulated (the cost measures).
    pub flows: usize,
    pub macro_steps: u64,
}

/// What the orbit through a start state does, sampled at every macro step of one period.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct OrbitMeasures {
    /// Largest eccentricity |d| / C per bearing (C, T).
    pub max_eps: [f64; 2],
    /// Whirl amplitude per bearing: the largest distance of d from its mean over the orbit,
    /// relative to C.
    pub whirl_amplitude: [f64; 2],
    /// Smallest film thickness per bearing [m].
    pub h_min_m: [f64; 2],
}

/// The measures as the orbit records name them.
pub fn measures_list(m: &OrbitMeasures) -> Vec<(String, f64)> {
    vec![
        ("max_eps_C".into(), m.max_eps[0]),
        ("max_eps_T".into(), m.max_eps[1]),
        ("whirl_amplitude_C".into(), m.whirl_amplitude[0]),
        ("whirl_amplitude_T".into(), m.whirl_amplitude[1]),
        ("h_min_C_m".into(), m.h_min_m[0]),
        ("h_min_T_m".into(), m.h_min_m[1]),
    ]
}

/// Macro step of the period map [us]: fixed, whatever the run-up default or `--macro-step`. A
/// flow restarts from saved states on a fixed macro grid; at 20 us the control never refines in
/// the whirls shot so far, so phi_T stays one smooth function, and the orbits of docs/orbits.md
/// were measured at it.
pub const ORBIT_MACRO_STEP_US: f64 = 20.0;

/// Loosest air-film tolerances of the period map [rtol, atol in Pa]: a looser tolerance (e.g.
/// `--film-tolerance 3e-3,300`) is tightened to this, a tighter one kept; the run-up default is
/// this one. The shooting's
/// monodromy matrix comes from differences of perturbed flows, which the film's error must stay
/// well below: at 3e-3 / 300 Pa path 2a's stable orbit at 500 Hz got real multipliers 1.062 and
/// 0.941 where the trivial multiplier 1 belongs (master/tests/orbits.rs failed on it); at 1e-3 /
/// 100 Pa it is stable as in docs/orbits.md. A looser tolerance in the settings (a library
/// caller's) is tightened too.
pub const ORBIT_FILM_TOLERANCE: [f64; 2] = [1e-3, 100.0];

/// `film_tolerance` no looser than [`ORBIT_FILM_TOLERANCE`] (None, the FMU's own 1e-4 / 10 Pa,
/// is tighter and stays).
pub fn orbit_film_tolerance(film_tolerance: Option<[f64; 2]>) -> Option<[f64; 2]> {
    film_tolerance.map(|[rtol, atol]| {
        [
            rtol.min(ORBIT_FILM_TOLERANCE[0]),
            atol.min(ORBIT_FILM_TOLERANCE[1]),
        ]
    })
}

/// A time within this fraction of a macro step of its target is on it: the summed time of many
/// steps drifts from k H by 1e-13 s and more, and the rest used to be taken as a step of its
/// own. A step of 2e-14 s is below the rotor's smallest step: contact whirls at 2000 Hz failed
/// with "step size below minimum" right after the settle (C30/dH60/c1500/d50: a step of
/// 1.2e-13 s at t = 0.72 s, one of 2.0e-14 s at 0.7364 s, the failure there).
const GRID_ROUNDING: f64 = 1e-6;

/// The next step towards a target `left_s` ahead with macro step `h_s`: none when the target is
/// reached to rounding, the rest when it is within rounding of one step (the last step takes
/// the rounding with it instead of leaving it for a step of its own), else `h_s`.
pub fn grid_step(left_s: f64, h_s: f64) -> Option<f64> {
    if left_s <= GRID_ROUNDING * h_s {
        None
    } else if left_s < h_s * (1.0 + GRID_ROUNDING) {
        Some(left_s)
    } else {
        Some(h_s)
    }
}

/// Refuses a rotor with an imbalance: it is forced at its spin frequency, so its whirls are
/// not periodic orbits of an autonomous system.
pub fn check_autonomous(settings: &RunupSettings) -> Result<(), String> {
    let p = settings.rotor_params()?;
    if p.imbalance.iter().any(|i| i.mass_kg != 0.0) {
        return Err(format!(
            "an imbalance ({} g and {} g) forces the rotor at its spin frequency: its whirls are then not periodic orbits; set the imbalance masses to 0",
            p.imbalance[0].mass_kg * 1e3,
            p.imbalance[1].mass_kg * 1e3
        ));
    }
    Ok(())
}

impl RotorFilmFlow {
    /// Builds the system of `settings` (FMUs from `fmu_dir`) spinning at `speed_hz` from t = 0,
    /// without imbalance or disturbance (an autonomous system: its whirls are periodic
    /// orbits), and writes the system file used to `system_file`.
    pub fn new(
        settings: &RunupSettings,
        fmu_dir: &Path,
        speed_hz: f64,
        system_file: &Path,
    ) -> Result<Self, String> {
        if !(speed_hz.is_finite() && speed_hz > 0.0) {
            return Err(format!("speed {speed_hz} Hz: must be positive and finite"));
        }
        check_autonomous(settings)?;
        let mut s = settings.clone();
        if let (Some(shaft), None) = (&s.shaft, &s.rotor_fmu) {
            s.rotor_fmu = Some(crate::runup::shaft_fmu::rotor_fmu_with_shaft(
                fmu_dir, shaft,
            )?);
        }
        s.speed_profile = vec![(0.0, speed_hz), (1.0, speed_hz)];
        s.disturbance_mn = 0.0;
        s.stop_time_s = 1e3;
        s.macro_step_us = ORBIT_MACRO_STEP_US;
        s.film_tolerance = orbit_film_tolerance(s.film_tolerance);
        let text = s.system_toml(&fmu_dir.display().to_string());
        crate::output::write_whole(system_file, text.as_bytes())?;
        let sys = cosim::system::System::load(system_file).map_err(|e| e.to_string())?;
        let built =
            cosim::setup::build(&sys, crate::run::stderr_logger()).map_err(|e| e.to_string())?;
        let cosim = built.cosim;
        let find = |name: &str| {
            cosim
                .index(name)
                .ok_or_else(|| format!("the system has no instance {name}"))
        };
        let rotor = find("rotor")?;
        let films = [find("film_C")?, find("film_T")?];
        let guid = |name: &str| {
            built
                .guids
                .iter()
                .find(|(n, _)| n == name)
                .map(|(_, g)| g.clone())
                .ok_or_else(|| format!("no GUID for {name}"))
        };
        let rotor_guid = guid("rotor")?;
        let film_guids = [guid("film_C")?, guid("film_T")?];
        let params = s.film_params()?;
        let clearance_m = [params[0].bore.c_m, params[1].bore.c_m];
        let c = clearance_m[0].min(clearance_m[1]);
        let span_m = {
            let p = s.rotor_params()?;
            (p.z_jt_m - p.z_jc_m).abs().max(1e-3)
        };
        let base = cosim.checkpoint().map_err(|e| e.to_string())?;
        let rotor_shape = Store::from_info(&RotorFmu::info());
        // Typical magnitudes: a clearance, the tilt that moves a journal by one (the rigid
        // rotor) or a mode's share that does (a flexible one), and both at a whirl of 500 Hz.
        let scale = {
            let core = fmi_core::snapshot::deserialize::<RotorFmu>(
                &base.1[rotor],
                &rotor_guid,
                &rotor_shape,
            )?;
            let m = core
                .model
                .as_ref()
                .ok_or("the rotor's FMU state holds no model")?;
            m.lateral_scales(c, span_m, 2.0 * std::f64::consts::PI * 500.0)
        };
        let n_lateral = scale.len();
        Ok(RotorFilmFlow {
            n_lateral,
            cosim,
            rotor,
            films,
            rotor_guid,
            rotor_shape,
            film_guids,
            film_shape: Store::from_info(&AirFilmFmu::info()),
            base,
            speed_hz,
            macro_step_s: built.macro_step_s,
            clearance_m,
            scale,
            flows: 0,
            macro_steps: 0,
        })
    }

    /// The lateral state's length.
    pub fn n_lateral(&self) -> usize {
        self.n_lateral
    }

    /// Nominal clearance per bearing (C, T) [m].
    pub fn clearance_m(&self) -> [f64; 2] {
        self.clearance_m
    }

    pub fn speed_hz(&self) -> f64 {
        self.speed_hz
    }

    pub fn time_s(&self) -> f64 {
        self.cosim.time_s()
    }

    fn step_to(&mut self, t_target: f64) -> Result<(), String> {
        while let Some(step) = grid_step(t_target - self.cosim.time_s(), self.macro_step_s) {
            self.cosim.step(step).map_err(|e| e.to_string())?;
            self.macro_steps += 1;
        }
        Ok(())
    }

    /// Co-simulates on from the current state for `duration_s` (the whirl settles) and makes
    /// the end the new base.
    pub fn settle(&mut self, duration_s: f64) -> Result<(), String> {
        let t = self.cosim.time_s() + duration_s;
        self.step_to(t)?;
        self.base = self.cosim.checkpoint().map_err(|e| e.to_string())?;
        Ok(())
    }

    /// Co-simulates on for `span_s` (a whirl period) and makes the macro point where the larger
    /// of the two films' eccentricities is smallest the new base. Every flow restarts the rotor
    /// there (order-1 BDF, fresh coupling polynomials): at a point where a journal rubs its ring
    /// such a restart is discarded (path 1 at 560 Hz: "journal beyond the contact limit" at
    /// the first step), at the whirl's quietest point it is not.
    pub fn move_base_to_quietest(&mut self, span_s: f64) -> Result<(), String> {
        let (state, blobs) = self.cosim.checkpoint().map_err(|e| e.to_string())?;
        let t0 = self.cosim.time_s();
        let (mut best_eps, mut best_k, mut k) = (self.max_eps_now()?, 0usize, 0usize);
        while self.cosim.time_s() < t0 + span_s - 1e-9 * self.macro_step_s {
            self.cosim
                .step(self.macro_step_s)
                .map_err(|e| e.to_string())?;
            self.macro_steps += 1;
            k += 1;
            let e = self.max_eps_now()?;
            if e < best_eps {
                (best_eps, best_k) = (e, k);
            }
        }
        self.cosim
            .restore_checkpoint(state, &blobs)
            .map_err(|e| e.to_string())?;
        for _ in 0..best_k {
            self.cosim
                .step(self.macro_step_s)
                .map_err(|e| e.to_string())?;
            self.macro_steps += 1;
        }
        self.base = self.cosim.checkpoint().map_err(|e| e.to_string())?;
        Ok(())
    }

    /// The larger of the two films' eccentricities now.
    pub fn max_eps_now(&self) -> Result<f64, String> {
        let mut worst = 0.0f64;
        for &f in &self.films {
            let mut e = 0.0;
            self.cosim
                .get(f, fmu_airfilm::shell::vr::EPS, &mut e)
                .map_err(|e| e.to_string())?;
            worst = worst.max(e);
        }
        Ok(worst)
    }

    /// The rotor's lateral state at the base point.
    pub fn base_lateral_state(&self) -> Result<Vec<f64>, String> {
        self.decode_lateral(&self.base.1[self.rotor])
    }

    /// Time of the base point [s].
    pub fn base_time_s(&self) -> f64 {
        self.base.0.t_s
    }

    fn decode_lateral(&self, blob: &[u8]) -> Result<Vec<f64>, String> {
        let core =
            fmi_core::snapshot::deserialize::<RotorFmu>(blob, &self.rotor_guid, &self.rotor_shape)?;
        let m = core
            .model
            .as_ref()
            .ok_or("the rotor's FMU state holds no model")?;
        Ok(m.lateral_state())
    }

    /// The rotor's lateral state now.
    pub fn lateral_state(&self) -> Result<Vec<f64>, String> {
        let (_, blobs) = self.cosim.checkpoint().map_err(|e| e.to_string())?;
        self.decode_lateral(&blobs[self.rotor])
    }

    /// Samples `n` values of the rotor's lateral state and the films' journal displacement
    /// over `duration_s` from now (for the period estimate of a settled whirl).
    pub fn sample(&mut self, duration_s: f64, n: usize) -> Result<Vec<(f64, [f64; 4])>, String> {
        let t0 = self.cosim.time_s();
        let mut out = Vec::with_capacity(n);
        for k in 1..=n {
            self.step_to(t0 + duration_s * k as f64 / n as f64)?;
            out.push((self.cosim.time_s(), self.displacements()?));
        }
        Ok(out)
    }

    /// Journal-minus-ring displacement (dx, dy) in both films [m].
    fn displacements(&self) -> Result<[f64; 4], String> {
        let mut d = [0.0; 4];
        for (b, &f) in self.films.iter().enumerate() {
            self.cosim
                .get_many(
                    f,
                    &[fmu_airfilm::shell::vr::DX, fmu_airfilm::shell::vr::DY],
                    &mut d[2 * b..2 * b + 2],
                )
                .map_err(|e| e.to_string())?;
        }
        Ok(d)
    }

    /// Restores the base with the rotor at `x0` (spinning at the current speed).
    fn start_from(&mut self, x0: &[f64]) -> Result<(), String> {
        self.start_with(x0, None)
    }

    /// The films' scaled pressure fields at the base point (C, T).
    pub fn base_pressures(&self) -> Result<[Vec<f64>; 2], String> {
        let read = |b: usize| -> Result<Vec<f64>, String> {
            let blob = &self.base.1[self.films[b]];
            Ok(self.decode_film(b, blob)?.pressures_rel().to_vec())
        };
        Ok([read(0)?, read(1)?])
    }

    /// Per film (C, T), which pressure entries are held at ambient (Dirichlet nodes).
    pub fn fixed_pressure_nodes(&self) -> Result<[Vec<bool>; 2], String> {
        let read = |b: usize| -> Result<Vec<bool>, String> {
            Ok(self
                .decode_film(b, &self.base.1[self.films[b]])?
                .fixed_nodes())
        };
        Ok([read(0)?, read(1)?])
    }

    /// The films' pressure fields now (C, T).
    pub fn pressures_now(&self) -> Result<[Vec<f64>; 2], String> {
        let (_, blobs) = self.cosim.checkpoint().map_err(|e| e.to_string())?;
        let read = |b: usize| -> Result<Vec<f64>, String> {
            Ok(self
                .decode_film(b, &blobs[self.films[b]])?
                .pressures_rel()
                .to_vec())
        };
        Ok([read(0)?, read(1)?])
    }

    fn decode_film(&self, b: usize, blob: &[u8]) -> Result<AirFilmFmu, String> {
        let core = fmi_core::snapshot::deserialize::<AirFilmFmu>(
            blob,
            &self.film_guids[b],
            &self.film_shape,
        )?;
        core.model
            .ok_or_else(|| "a film's FMU state holds no model".to_string())
    }

    /// Restores the base with the rotor at `x0` and, if given, the films restarted with these
    /// pressure fields (C, T).
    pub fn start_with(&mut self, x0: &[f64], pressures: Option<[&[f64]; 2]>) -> Result<(), String> {
        if x0.len() != self.n_lateral {
            return Err(format!(
                "a lateral state has {} values, not {}",
                self.n_lateral,
                x0.len()
            ));
        }
        let lateral = x0;
        let (state, mut blobs) = self.base.clone();
        if let Some(p) = pressures {
            for b in 0..2 {
                let blob = &blobs[self.films[b]];
                let mut core = fmi_core::snapshot::deserialize::<AirFilmFmu>(
                    blob,
                    &self.film_guids[b],
                    &self.film_shape,
                )?;
                let model = core
                    .model
                    .as_mut()
                    .ok_or("a film's FMU state holds no model")?;
                model.restart_with_pressures(p[b])?;
                model.write_outputs(&mut core.store);
                blobs[self.films[b]] = fmi_core::snapshot::serialize(&core, &self.film_guids[b]);
            }
        }
        let mut core = fmi_core::snapshot::deserialize::<RotorFmu>(
            &blobs[self.rotor],
            &self.rotor_guid,
            &self.rotor_shape,
        )?;
        let model = core
            .model
            .as_mut()
            .ok_or("the rotor's FMU state holds no model")?;
        model
            .restart_constant_speed(lateral, self.speed_hz)
            .map_err(|e| e.to_string())?;
        model.write_outputs(&mut core.store);
        blobs[self.rotor] = fmi_core::snapshot::serialize(&core, &self.rotor_guid);
        self.cosim
            .restore_checkpoint(state, &blobs)
            .map_err(|e| e.to_string())?;
        self.cosim
            .restart_coupling_histories()
            .map_err(|e| e.to_string())?;
        self.flows += 1;
        Ok(())
    }

    /// Moves the base to the end of one period from `x0`: the films' pressure field there has
    /// relaxed onto the orbit.
    pub fn rebase(&mut self, x0: &[f64], period_s: f64) -> Result<(), String> {
        self.start_from(x0)?;
        let t = self.base.0.t_s + period_s;
        self.step_to(t)?;
        self.base = self.cosim.checkpoint().map_err(|e| e.to_string())?;
        Ok(())
    }

    /// The measures of the orbit through `x0` over one period.
    pub fn orbit_measures(&mut self, x0: &[f64], period_s: f64) -> Result<OrbitMeasures, String> {
        self.orbit_measures_with(x0, None, period_s)
    }

    /// The measures of the orbit through the rotor state `x0` and, if given, the films'
    /// pressure fields (C, T) over one period.
    pub fn orbit_measures_with(
        &mut self,
        x0: &[f64],
        pressures: Option<[&[f64]; 2]>,
        period_s: f64,
    ) -> Result<OrbitMeasures, String> {
        self.start_with(x0, pressures)?;
        let t0 = self.base.0.t_s;
        let mut pts: Vec<[f64; 4]> = vec![];
        let mut h_min = [f64::INFINITY; 2];
        let mut max_eps = [0.0f64; 2];
        loop {
            pts.push(self.displacements()?);
            for (b, &f) in self.films.iter().enumerate() {
                let mut v = [0.0; 2];
                self.cosim
                    .get_many(
                        f,
                        &[fmu_airfilm::shell::vr::EPS, fmu_airfilm::shell::vr::H_MIN],
                        &mut v,
                    )
                    .map_err(|e| e.to_string())?;
                max_eps[b] = max_eps[b].max(v[0]);
                h_min[b] = h_min[b].min(v[1]);
            }
            if self.cosim.time_s() >= t0 + period_s - 1e-12 {
                break;
            }
            let next = (self.cosim.time_s() + self.macro_step_s).min(t0 + period_s);
            self.step_to(next)?;
        }
        let mut amp = [0.0f64; 2];
        for b in 0..2 {
            let n = pts.len() as f64;
            let mx = pts.iter().map(|p| p[2 * b]).sum::<f64>() / n;
            let my = pts.iter().map(|p| p[2 * b + 1]).sum::<f64>() / n;
            amp[b] = pts
                .iter()
                .map(|p| (p[2 * b] - mx).hypot(p[2 * b + 1] - my))
                .fold(0.0, f64::max)
                / self.clearance_m[b];
        }
        Ok(OrbitMeasures {
            max_eps,
            whirl_amplitude: amp,
            h_min_m: h_min,
        })
    }
}

impl Flow for RotorFilmFlow {
    fn dim(&self) -> usize {
        self.n_lateral
    }
    fn scale(&self) -> Vec<f64> {
        self.scale.clone()
    }
    /// On the fixed macro grid (`states_at`).
    fn flow(&mut self, x0: &[f64], at_s: &[f64]) -> Result<Vec<Vec<f64>>, String> {
        self.start_from(x0)?;
        self.states_at(at_s, &Self::lateral_state)
    }

    fn measures(&mut self, x0: &[f64], period_s: f64) -> Result<Vec<(String, f64)>, String> {
        Ok(measures_list(&self.orbit_measures(x0, period_s)?))
    }
}

impl RotorFilmFlow {
    /// From the start just restored, the states `read` gives at the times `at_s` after the base.
    /// The macro steps lie on the grid t0 + k H whatever times are asked for: a time between two
    /// grid points is reached by one shorter step from a saved state, which is then restored.
    /// So phi_t(x0) is one function of (x0, t), whichever other times the same call asks for
    /// (the finite differences of the shooting compare flows of different calls).
    pub fn states_at(
        &mut self,
        at_s: &[f64],
        read: &dyn Fn(&Self) -> Result<Vec<f64>, String>,
    ) -> Result<Vec<Vec<f64>>, String> {
        let t0 = self.base.0.t_s;
        let h = self.macro_step_s;
        let mut out = Vec::with_capacity(at_s.len());
        for &t in at_s {
            let k = ((t / h) * (1.0 + 1e-12)).floor();
            self.step_to(t0 + k * h)?;
            if t - k * h <= GRID_ROUNDING * h {
                out.push(read(self)?);
                continue;
            }
            let (state, blobs) = self.cosim.checkpoint().map_err(|e| e.to_string())?;
            self.cosim.step(t - k * h).map_err(|e| e.to_string())?;
            self.macro_steps += 1;
            out.push(read(self)?);
            self.cosim
                .restore_checkpoint(state, &blobs)
                .map_err(|e| e.to_string())?;
        }
        Ok(out)
    }
}

impl ParamFlow for RotorFilmFlow {
    fn param(&self) -> f64 {
        self.speed_hz
    }
    fn set_param(&mut self, value: f64) -> Result<(), String> {
        if !(value.is_finite() && value > 0.0) {
            return Err(format!("speed {value} Hz: must be positive and finite"));
        }
        self.speed_hz = value;
        Ok(())
    }
    fn param_scale(&self) -> f64 {
        1000.0
    }
    fn accepted(&mut self, x0: &[f64], period_s: f64) -> Result<(), String> {
        self.rebase(x0, period_s)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The period map never runs the film looser than ORBIT_FILM_TOLERANCE: a looser one (3e-3 /
    /// 300 Pa) is tightened, the run-up default kept where it is no
    /// looser, a tighter choice kept, each of rtol and atol on its own.
    #[test]
    fn orbit_film_tolerance_only_tightens() {
        assert_eq!(
            orbit_film_tolerance(Some([3e-3, 300.0])),
            Some(ORBIT_FILM_TOLERANCE)
        );
        let run_up = crate::runup::DEFAULT_FILM_TOLERANCE;
        assert!(run_up[0] >= ORBIT_FILM_TOLERANCE[0] && run_up[1] >= ORBIT_FILM_TOLERANCE[1]);
        assert_eq!(
            orbit_film_tolerance(Some(run_up)),
            Some(ORBIT_FILM_TOLERANCE)
        );
        assert_eq!(orbit_film_tolerance(Some([1e-5, 1.0])), Some([1e-5, 1.0]));
        assert_eq!(orbit_film_tolerance(Some([1e-5, 1e3])), Some([1e-5, 100.0]));
        assert_eq!(orbit_film_tolerance(None), None);
    }
}
