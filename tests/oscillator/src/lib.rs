//! Test model for the FMI layer: an undamped forced linear oscillator `m x'' + k x = F(t)` whose step is
//! exact for any input polynomial of degree <= 3 (the particular solution of a polynomial forcing is a
//! polynomial), so tests can compare with closed forms to round-off.
//!
//! It also has fault injection (`fault_mode`): 1 panics inside fmi2DoStep once the time passes
//! `fault_time`, 2 returns fmi2Discard there, 3 returns fmi2Discard for any step longer than
//! `fault_time` seconds (a model that needs smaller communication steps: tests the master's retry). This is how the layer's panic containment and discard
//! handling are tested through the real C ABI.

use fmi_core::model::{Log, Model, StepInputs, StepOutcome, Store};
use fmi_core::variables::{DefaultExperiment, ModelInfo, Variable};
use serde::{Deserialize, Serialize};

pub mod vr {
    pub const M: u32 = 0;
    pub const K: u32 = 1;
    pub const X0: u32 = 2;
    pub const F: u32 = 3;
    pub const X: u32 = 4;
    pub const V: u32 = 5;
    pub const FAULT_TIME: u32 = 6;
    /// Integer
    pub const FAULT_MODE: u32 = 0;
    /// Integer output
    pub const STEPS: u32 = 1;
}

#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct Oscillator {
    m: f64,
    k: f64,
    t: f64,
    x: f64,
    v: f64,
    f: f64,
    fault_mode: i32,
    fault_time: f64,
    steps: i32,
}

impl Oscillator {
    /// Exact step of `x'' + w2 x = P(t)/m` with `P(t0 + s) = f0 + f1 s + f2 s^2/2 + f3 s^3/6`.
    pub fn exact_step(&mut self, h: f64, f: [f64; 4]) {
        let w2 = self.k / self.m;
        let w = w2.sqrt();
        // Particular solution x_p(s) = (P(s) - P''(s)/w2) / (m w2), valid because P'''' = 0.
        let p = |s: f64| f[0] + s * (f[1] + s * (f[2] / 2.0 + s * f[3] / 6.0));
        let dp = |s: f64| f[1] + s * (f[2] + s * f[3] / 2.0);
        let ddp = |s: f64| f[2] + s * f[3];
        let dddp = f[3];
        let xp = |s: f64| (p(s) - ddp(s) / w2) / (self.m * w2);
        let vp = |s: f64| (dp(s) - dddp / w2) / (self.m * w2);
        let (a, b) = (self.x - xp(0.0), (self.v - vp(0.0)) / w);
        let (c, sn) = ((w * h).cos(), (w * h).sin());
        self.x = a * c + b * sn + xp(h);
        self.v = w * (-a * sn + b * c) + vp(h);
        self.f = p(h);
        self.t += h;
    }
}

const DOC: &str = "<p>Forced undamped oscillator m x'' + k x = F(t), stepped exactly for input polynomials up to degree 3. A test model of the AirRing FMI layer.</p>";

impl Model for Oscillator {
    fn info() -> ModelInfo {
        ModelInfo {
            model_name: "oscillator",
            model_identifier: "oscillator",
            description: "Forced linear oscillator with an exact step (FMI layer test model)",
            version: env!("CARGO_PKG_VERSION"),
            variables: vec![
                Variable::real_parameter("m", vr::M, 1.0, "kg", "mass").range(Some(1e-12), None),
                Variable::real_parameter(
                    "k",
                    vr::K,
                    4.0 * std::f64::consts::PI.powi(2),
                    "N/m",
                    "stiffness",
                )
                .range(Some(1e-12), None),
                Variable::real_parameter("x0", vr::X0, 0.0, "m", "initial position"),
                Variable::real_input("F", vr::F, 0.0, "N", "force"),
                Variable::real_output("x", vr::X, "m", "position"),
                Variable::real_output("v", vr::V, "m/s", "velocity"),
                Variable::real_parameter(
                    "fault_time",
                    vr::FAULT_TIME,
                    0.0,
                    "s",
                    "time after which the fault is injected",
                ),
                Variable::integer_parameter(
                    "fault_mode",
                    vr::FAULT_MODE,
                    0,
                    "0 none, 1 panic in doStep after fault_time, 2 fmi2Discard after fault_time, 3 fmi2Discard for steps longer than fault_time",
                )
                .range(Some(0.0), Some(3.0)),
                Variable::integer_output("steps", vr::STEPS, "number of completed steps"),
            ],
            log_categories: vec![("logSteps", "one line per step")],
            default_experiment: DefaultExperiment {
                start_time: 0.0,
                stop_time: 1.0,
                tolerance: 1e-6,
                step_size: 1e-2,
            },
            documentation_html: DOC,
        }
    }

    fn new(
        store: &Store,
        start_time: f64,
        _resources: Option<&std::path::Path>,
        _log: &mut dyn Log,
    ) -> Result<Self, String> {
        Ok(Oscillator {
            m: store.real(vr::M),
            k: store.real(vr::K),
            t: start_time,
            x: store.real(vr::X0),
            v: 0.0,
            f: store.real(vr::F),
            fault_mode: store.integer(vr::FAULT_MODE),
            fault_time: store.real(vr::FAULT_TIME),
            steps: 0,
        })
    }

    fn do_step(
        &mut self,
        t: f64,
        h: f64,
        inputs: &dyn StepInputs,
        log: &mut dyn Log,
    ) -> StepOutcome {
        if self.fault_mode == 1 && t + h > self.fault_time {
            panic!("injected fault at t = {t}");
        }
        if self.fault_mode == 2 && t + h > self.fault_time {
            return StepOutcome::Discard {
                reason: "injected discard".into(),
                reached_time: t,
            };
        }
        if self.fault_mode == 3 && h > self.fault_time {
            return StepOutcome::Discard {
                reason: format!("step {h} s longer than {} s", self.fault_time),
                reached_time: t,
            };
        }
        // The exact solution needs the force's polynomial; inputs that come at internal times only
        // (FMI 3.0 intermediate update, which this FMI 2.0 test model never sees) are held.
        let (f0, d) = inputs
            .polynomial(vr::F)
            .unwrap_or((inputs.real_at(vr::F, t), [0.0; 3]));
        self.exact_step(h, [f0, d[0], d[1], d[2]]);
        self.steps += 1;
        if log.enabled("logSteps") {
            log.debug("logSteps", &format!("step {t} -> {} x = {}", t + h, self.x));
        }
        StepOutcome::Ok
    }

    fn write_outputs(&self, store: &mut Store) {
        store.reals[vr::X as usize] = self.x;
        store.reals[vr::V as usize] = self.v;
        store.integers[vr::STEPS as usize] = self.steps;
    }

    fn output_derivative(&self, vr: u32, order: i32) -> Option<f64> {
        match (vr, order) {
            (vr::X, 1) => Some(self.v),
            (vr::V, 1) => Some((self.f - self.k * self.x) / self.m),
            _ => None,
        }
    }

    fn serialize(&self) -> Vec<u8> {
        bincode::serialize(self).expect("plain data serializes")
    }

    fn deserialize(bytes: &[u8]) -> Result<Self, String> {
        bincode::deserialize(bytes).map_err(|e| e.to_string())
    }
}

#[cfg(feature = "fmu")]
fmi2::export_fmu!(Oscillator);

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ramp_forcing_matches_closed_form() {
        // x'' + w^2 x = a t, x(0) = v(0) = 0  =>  x = a/w^2 (t - sin(w t)/w).
        let mut o = Oscillator {
            m: 1.0,
            k: 4.0,
            t: 0.0,
            x: 0.0,
            v: 0.0,
            f: 0.0,
            fault_mode: 0,
            fault_time: 0.0,
            steps: 0,
        };
        let a = 3.0;
        let h = 0.1;
        for n in 0..50 {
            let t = n as f64 * h;
            o.exact_step(h, [a * t, a, 0.0, 0.0]);
        }
        let (t, w) = (5.0, 2.0);
        let exact = a / (w * w) * (t - (w * t).sin() / w);
        assert!((o.x - exact).abs() < 1e-12, "{} vs {exact}", o.x);
    }
}
