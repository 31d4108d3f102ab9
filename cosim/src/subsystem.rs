//! One FMU instance in the co-simulation: its slave, its input links, the coupling outputs at the
//! last macro points, and the scratch buffers that keep the macro step free of allocations.

use crate::slave::{FmuState, Slave};
use fmi_core::description::ModelDescription;
use fmi_core::CallError;
use fmi_core::Status;
use std::collections::VecDeque;
use std::time::{Duration, Instant};

/// An input fed by another subsystem's output.
#[derive(Clone, Debug)]
pub struct Link {
    pub to_vr: u32,
    pub from: usize,
    /// Index into the source's `coupling_vrs`.
    pub from_slot: usize,
}

/// One FMU instance in the co-simulation.
pub struct Subsystem {
    pub name: String,
    pub slave: Slave,
    pub can_interpolate: bool,
    pub inputs: Vec<Link>,
    /// Outputs that other subsystems read, in slot order.
    pub coupling_vrs: Vec<u32>,
    /// Coupling outputs at the last macro points, oldest first (at most 3 kept).
    pub history: VecDeque<(f64, Vec<f64>)>,
    pub(crate) state: Option<FmuState>,
    /// Wall time spent in this FMU's fmi2DoStep.
    pub step_wall: Duration,
    /// Integer outputs (name, value reference): solver counters, reported at the end of a run.
    pub counters: Vec<(String, u32)>,
    // Scratch for setting inputs without allocating each step.
    pub(crate) vrs: Vec<u32>,
    pub(crate) values: Vec<f64>,
    pub(crate) orders: Vec<i32>,
    pub(crate) der_vrs: Vec<u32>,
    pub(crate) der_values: Vec<f64>,
}

impl Subsystem {
    pub fn new(name: String, slave: Slave, md: &ModelDescription) -> Self {
        Subsystem {
            name,
            slave,
            can_interpolate: md.can_interpolate_inputs,
            inputs: vec![],
            coupling_vrs: vec![],
            history: VecDeque::with_capacity(4),
            state: None,
            step_wall: Duration::ZERO,
            counters: md
                .variables
                .iter()
                .filter(|v| {
                    v.var_type == fmi_core::variables::VarType::Integer
                        && v.causality == fmi_core::variables::Causality::Output
                })
                .map(|v| (v.name.clone(), v.vr))
                .collect(),
            vrs: vec![],
            values: vec![],
            orders: vec![],
            der_vrs: vec![],
            der_values: vec![],
        }
    }

    /// Slot of an output in `coupling_vrs` (added if new).
    pub fn coupling_slot(&mut self, vr: u32) -> usize {
        match self.coupling_vrs.iter().position(|v| *v == vr) {
            Some(i) => i,
            None => {
                self.coupling_vrs.push(vr);
                self.coupling_vrs.len() - 1
            }
        }
    }

    pub(crate) fn read_coupling(&self) -> Result<Vec<f64>, CallError> {
        let mut v = vec![0.0; self.coupling_vrs.len()];
        self.slave.get_real(&self.coupling_vrs, &mut v)?;
        Ok(v)
    }

    /// Reads the coupling outputs at `t` as the newest macro point, reusing the oldest point's
    /// vector once three are kept (no allocation per macro step).
    pub(crate) fn read_coupling_into_history(&mut self, t: f64) -> Result<(), CallError> {
        let mut v = if self.history.len() == 3 {
            self.history.pop_front().map(|p| p.1).unwrap_or_default()
        } else {
            vec![0.0; self.coupling_vrs.len()]
        };
        v.resize(self.coupling_vrs.len(), 0.0);
        self.slave.get_real(&self.coupling_vrs, &mut v)?;
        // A NaN or infinite output would travel silently into the other FMUs' inputs.
        let finite = v.iter().all(|x| x.is_finite());
        self.history.push_back((t, v));
        if !finite {
            return Err(CallError {
                function: "fmi2GetReal (a coupling output is NaN or infinite)",
                status: Status::Error,
            });
        }
        Ok(())
    }

    pub(crate) fn push_history(&mut self, t: f64, v: Vec<f64>) {
        if self.history.len() == 3 {
            self.history.pop_front();
        }
        self.history.push_back((t, v));
    }

    pub(crate) fn do_step(&mut self, t: f64, h: f64) -> Result<(), CallError> {
        let start = Instant::now();
        let r = self.slave.do_step(t, h);
        self.step_wall += start.elapsed();
        r
    }
}

impl crate::parallel::Step for Subsystem {
    fn step(&mut self, t: f64, h: f64) -> Result<(), CallError> {
        self.do_step(t, h)
    }
}
