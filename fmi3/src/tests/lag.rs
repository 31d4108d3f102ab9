//! Test model: a first-order lag `tau y' = u - y`, stepped exactly for an input held over the step,
//! with fault injection (`fault_mode`: 1 panics in doStep once past `fault_time`, 2 discards there,
//! 3 discards there after half the step).

use fmi_core::model::{Log, Model, StepInputs, StepOutcome, Store};
use fmi_core::variables::{DefaultExperiment, ModelInfo, Variable};

pub mod vr {
    pub const TAU: u32 = 0;
    pub const Y0: u32 = 1;
    pub const U: u32 = 2;
    pub const Y: u32 = 3;
    pub const FAULT_TIME: u32 = 4;
    /// Integer
    pub const FAULT_MODE: u32 = 0;
    /// Integer output
    pub const STEPS: u32 = 1;
    /// Boolean
    pub const FROZEN: u32 = 0;
}

#[derive(Clone, Debug)]
pub struct Lag {
    tau_s: f64,
    y: f64,
    u: f64,
    frozen: bool,
    fault_mode: i32,
    fault_time_s: f64,
    steps: i32,
}

impl Lag {
    /// The exact step with `u` held: y(t + h) = u + (y - u) exp(-h / tau).
    pub fn exact(y: f64, u: f64, tau_s: f64, h_s: f64) -> f64 {
        u + (y - u) * (-h_s / tau_s).exp()
    }
}

impl Model for Lag {
    fn info() -> ModelInfo {
        ModelInfo {
            model_name: "lag",
            model_identifier: "lag",
            description: "First-order lag (fmi3 layer test model)",
            version: "1.0",
            variables: vec![
                Variable::real_parameter("tau", vr::TAU, 0.5, "s", "time constant")
                    .range(Some(1e-9), None),
                Variable::real_parameter("y0", vr::Y0, 0.0, "m", "initial output"),
                Variable::real_input("u", vr::U, 0.0, "m", "input").display("mm"),
                Variable::real_output("y", vr::Y, "m", "output"),
                Variable::real_parameter(
                    "fault_time",
                    vr::FAULT_TIME,
                    0.0,
                    "s",
                    "fault after this time",
                ),
                Variable::integer_parameter(
                    "fault_mode",
                    vr::FAULT_MODE,
                    0,
                    "0 none, 1 panic, 2 discard, 3 discard half-way",
                )
                .range(Some(0.0), Some(3.0)),
                Variable::integer_output("steps", vr::STEPS, "completed steps"),
                Variable::boolean_parameter("frozen", vr::FROZEN, false, "hold the output"),
            ],
            log_categories: vec![("logSteps", "one line per step")],
            default_experiment: DefaultExperiment {
                start_time: 0.0,
                stop_time: 1.0,
                tolerance: 1e-6,
                step_size: 1e-2,
            },
            documentation_html: "<p>First-order lag.</p>",
        }
    }

    fn new(
        store: &Store,
        _start_time: f64,
        _resources: Option<&std::path::Path>,
        _log: &mut dyn Log,
    ) -> Result<Self, String> {
        Ok(Lag {
            tau_s: store.real(vr::TAU),
            y: store.real(vr::Y0),
            u: store.real(vr::U),
            frozen: store.boolean(vr::FROZEN),
            fault_mode: store.integer(vr::FAULT_MODE),
            fault_time_s: store.real(vr::FAULT_TIME),
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
        if self.fault_mode == 1 && t + h > self.fault_time_s {
            panic!("injected fault at t = {t}");
        }
        if self.fault_mode == 2 && t + h > self.fault_time_s {
            return StepOutcome::Discard {
                reason: "injected discard".into(),
                reached_time: t,
            };
        }
        // Half the step done, then a discard (as the films stop at their last good sub-step).
        if self.fault_mode == 3 && t + h > self.fault_time_s {
            self.u = inputs.real_at(vr::U, t + h / 2.0);
            self.y = Lag::exact(self.y, self.u, self.tau_s, h / 2.0);
            self.steps += 1;
            return StepOutcome::Discard {
                reason: "injected discard half-way".into(),
                reached_time: t + h / 2.0,
            };
        }
        // Without intermediate update the layer holds inputs over the step: value at t, zero
        // derivatives.
        if let Some((_, d)) = inputs.polynomial(vr::U) {
            assert_eq!(d, [0.0; 3]);
        }
        self.u = inputs.real_at(vr::U, t + h);
        if !self.frozen {
            self.y = Lag::exact(self.y, self.u, self.tau_s, h);
        }
        self.steps += 1;
        log.debug("logSteps", &format!("step {t} -> {}", t + h));
        StepOutcome::Ok
    }

    fn write_outputs(&self, store: &mut Store) {
        store.reals[vr::Y as usize] = self.y;
        store.integers[vr::STEPS as usize] = self.steps;
    }

    fn output_derivative(&self, vr: u32, order: i32) -> Option<f64> {
        match (vr, order) {
            (vr::Y, 1) if self.frozen => Some(0.0),
            (vr::Y, 1) => Some((self.u - self.y) / self.tau_s),
            _ => None,
        }
    }

    fn serialize(&self) -> Vec<u8> {
        let mut b = Vec::new();
        for x in [self.tau_s, self.y, self.u, self.fault_time_s] {
            b.extend_from_slice(&x.to_le_bytes());
        }
        b.extend_from_slice(&self.fault_mode.to_le_bytes());
        b.extend_from_slice(&self.steps.to_le_bytes());
        b.push(self.frozen as u8);
        b
    }

    fn deserialize(bytes: &[u8]) -> Result<Self, String> {
        if bytes.len() != 41 {
            return Err(format!("{} bytes, expected 41", bytes.len()));
        }
        let f = |i: usize| f64::from_le_bytes(bytes[8 * i..8 * i + 8].try_into().unwrap());
        let i32_at = |o: usize| i32::from_le_bytes(bytes[o..o + 4].try_into().unwrap());
        Ok(Lag {
            tau_s: f(0),
            y: f(1),
            u: f(2),
            fault_time_s: f(3),
            fault_mode: i32_at(32),
            steps: i32_at(36),
            frozen: bytes[40] != 0,
        })
    }
}
