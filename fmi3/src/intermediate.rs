//! Intermediate update: the FMU asks the master for its inputs at the model's internal times.
//!
//! FMI 3.0 has no input derivatives. With an `intermediateUpdate` callback, fmi3DoStep calls it
//! whenever the model reads an input at a time other than the step's start
//! (`intermediateVariableSetRequested = true`); inside the callback the master calls
//! fmi3SetFloat64 for inputs marked `intermediateUpdate="true"`. Those calls re-enter the instance
//! while its model is in the middle of a step, so they must not touch the model: they write into
//! [`Buffer`], which lives beside the instance (in the [`Shell`](crate::instance::Shell)), never
//! inside it. Reads at one internal time call the master once (the model reads all its inputs at
//! the same time).
//!
//! An input the master does not set in a callback keeps its last value: a master that answers
//! nothing gets the inputs held over the step, as without a callback.

use crate::types::*;
use fmi_core::model::{Inputs, IntermediateInputs};
use std::cell::{Cell, RefCell};

/// Real values as the master sets them inside intermediateUpdate callbacks.
#[derive(Debug, Default)]
pub struct Buffer {
    /// Inside a callback: fmi3SetFloat64 of an input is allowed.
    pub(crate) open: bool,
    /// All Real values by per-type value reference; the inputs are overwritten by the master.
    pub(crate) reals: Vec<f64>,
    /// Which per-type Real value references are inputs (may be set in a callback).
    pub(crate) is_input: Vec<bool>,
    /// The Real variables' names by per-type value reference, for messages (the master knows its
    /// variables by name and FMI 3.0 value reference, not by ours).
    pub(crate) names: Vec<&'static str>,
    /// Calls refused while the model stepped (logged by fmi3DoStep afterwards: the logger belongs
    /// to the stepping instance).
    pub(crate) refused: Vec<(String, String)>,
}

impl Buffer {
    /// A buffer for a model with these variables (which Reals are inputs is fixed per model).
    pub(crate) fn for_model(info: &fmi_core::variables::ModelInfo) -> Self {
        let n = info.count(fmi_core::variables::VarType::Real);
        let mut is_input = vec![false; n];
        let mut names = vec![""; n];
        for v in &info.variables {
            if v.var_type == fmi_core::variables::VarType::Real {
                names[v.vr as usize] = v.name;
                is_input[v.vr as usize] = v.causality == fmi_core::variables::Causality::Input;
            }
        }
        Buffer {
            is_input,
            names,
            ..Default::default()
        }
    }

    /// Starts a step whose inputs hold `reals` at its start.
    pub(crate) fn start(&mut self, reals: &[f64]) {
        self.open = false;
        self.reals.clear();
        self.reals.extend_from_slice(reals);
        self.refused.clear();
    }

    /// fmi3SetFloat64 inside a callback (`vrs` are per-type Real value references).
    pub(crate) fn set(&mut self, vrs: &[u32], values: &[f64]) -> Result<(), String> {
        if !self.open {
            return Err("called during fmi3DoStep outside an intermediateUpdate callback".into());
        }
        let name = |vr: u32| match self.names.get(vr as usize) {
            Some(n) if !n.is_empty() => format!("'{n}'"),
            _ => format!("Float64 value reference {vr} (of this FMU's numbering)"),
        };
        if let Some(vr) = vrs
            .iter()
            .find(|vr| !self.is_input.get(**vr as usize).copied().unwrap_or(false))
        {
            return Err(format!(
                "{} is not an input with intermediateUpdate=\"true\"",
                name(*vr)
            ));
        }
        if let Some((vr, v)) = vrs.iter().zip(values).find(|(_, v)| !v.is_finite()) {
            return Err(format!("value {v} for {} is not finite", name(*vr)));
        }
        for (vr, v) in vrs.iter().zip(values) {
            self.reals[*vr as usize] = *v;
        }
        Ok(())
    }
}

/// The master's callback as the model's input source for one step.
pub(crate) struct CallbackInputs<'a> {
    pub callback: unsafe extern "C" fn(
        fmi3InstanceEnvironment,
        fmi3Float64,
        fmi3Boolean,
        fmi3Boolean,
        fmi3Boolean,
        fmi3Boolean,
        *mut fmi3Boolean,
        *mut fmi3Float64,
    ),
    pub environment: fmi3InstanceEnvironment,
    pub buffer: &'a RefCell<Buffer>,
    /// The internal time the buffer was last filled for (NaN: none yet).
    pub asked_at: Cell<f64>,
}

impl IntermediateInputs for CallbackInputs<'_> {
    fn real_at(&self, held: &Inputs, vr: u32, t: f64) -> f64 {
        // At the step's start the inputs are the values set before fmi3DoStep.
        if t == held.t0 {
            return held.values[vr as usize];
        }
        if self.asked_at.get().to_bits() != t.to_bits() {
            self.buffer.borrow_mut().open = true;
            let mut early_return_requested = false;
            let mut early_return_time = t;
            // SAFETY: the master's callback with its own environment (FMI 3.0 section 4.2.1); the
            // out pointers are valid locals. Inside it the master may call fmi3SetFloat64, which
            // writes into `buffer` only (no borrow of it is held here).
            unsafe {
                (self.callback)(
                    self.environment,
                    t,
                    true,
                    false,
                    false,
                    false,
                    &mut early_return_requested,
                    &mut early_return_time,
                )
            };
            self.buffer.borrow_mut().open = false;
            self.asked_at.set(t);
        }
        self.buffer.borrow().reals[vr as usize]
    }
}
