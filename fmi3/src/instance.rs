//! One FMI 3.0 instance: the FMI core's instance (state machine, store, model, tolerances, the
//! logger with FMI 3.0's filter) plus what FMI 3.0 adds around it: the call-state masks and the
//! value-reference mapping.
//!
//! Safe Rust on slices, like `fmi_core::instance`; `ffi` turns C pointers into these calls.

use crate::state::{self, Mask};
use crate::types::{fmi3InstanceEnvironment, fmi3IntermediateUpdateCallback};
use crate::value_refs::{self, Target, TIME_VR};
use fmi_core::instance::Phase;
use fmi_core::model::Model;
use fmi_core::variables::VarType;
use fmi_core::Status;
use std::cell::{Cell, RefCell, UnsafeCell};

/// Marks a live instance; checked on every call so a null or foreign pointer is refused.
pub(crate) const INSTANCE_MAGIC: u64 = 0x4149_5252_494e_4733; // "AIRRING3"

pub type Res = Result<Status, (Status, String)>;

pub fn err<T>(msg: impl Into<String>) -> Result<T, (Status, String)> {
    Err((Status::Error, msg.into()))
}

/// What an `fmi3Instance` points to: the instance, and beside it what a call may touch while the
/// instance's model is inside fmi3DoStep (the master's answers to intermediateUpdate re-enter the
/// FMU then; they must not reach the stepping instance, see `intermediate`).
pub struct Shell<M: Model> {
    pub(crate) magic: u64,
    /// fmi3DoStep is running the model.
    pub(crate) stepping: Cell<bool>,
    /// The master handles a step that ends before its end (earlyReturnAllowed).
    pub(crate) early_return_allowed: bool,
    pub(crate) intermediate_update: fmi3IntermediateUpdateCallback,
    pub(crate) environment: fmi3InstanceEnvironment,
    pub(crate) buffer: RefCell<crate::intermediate::Buffer>,
    /// Borrowed mutably by one FMI call at a time (FMI 3.0: no concurrent calls on an instance);
    /// never by a call that arrives while `stepping`.
    pub(crate) instance: UnsafeCell<Instance<M>>,
}

impl<M: Model> Shell<M> {
    pub fn new(
        instance: Instance<M>,
        early_return_allowed: bool,
        intermediate_update: fmi3IntermediateUpdateCallback,
        environment: fmi3InstanceEnvironment,
    ) -> Self {
        Shell {
            magic: INSTANCE_MAGIC,
            stepping: Cell::new(false),
            early_return_allowed,
            intermediate_update,
            environment,
            buffer: RefCell::new(crate::intermediate::Buffer::for_model(&instance.inner.info)),
            instance: UnsafeCell::new(instance),
        }
    }
}

pub struct Instance<M: Model> {
    pub inner: fmi_core::instance::Instance<M>,
    /// per-type value references of the current call (reused: no allocation per fmi3Get/SetInt32).
    vrs2: Vec<u32>,
}

impl<M: Model> Instance<M> {
    pub fn new(inner: fmi_core::instance::Instance<M>) -> Self {
        Instance {
            inner,
            vrs2: Vec::new(),
        }
    }

    pub fn phase(&self) -> Phase {
        self.inner.core.phase
    }

    pub fn reject(&self, status: Status, function: &str, reason: &str) {
        self.inner.logger.reject(status, function, reason);
    }

    /// Runs a call body if the current state is in `mask`; logs the reason of a refusal.
    pub fn run(
        &mut self,
        function: &str,
        mask: Mask,
        body: impl FnOnce(&mut Self) -> Res,
    ) -> Status {
        let result = if state::of(self.phase()) & mask == 0 {
            err(format!(
                "illegal call sequence: not allowed in state {}",
                state::name(self.phase())
            ))
        } else {
            body(self)
        };
        match result {
            Ok(s) => s,
            Err((status, reason)) => {
                self.reject(status, function, &reason);
                status
            }
        }
    }

    /// Checks that every value reference designates an existing variable of type `t` (or `time`,
    /// where `time_ok`), and leaves their per-type value references in `self.vrs2`.
    fn translate(
        &mut self,
        t: VarType,
        vrs: &[u32],
        time_ok: bool,
    ) -> Result<(), (Status, String)> {
        self.vrs2.clear();
        for &vr in vrs {
            match value_refs::target(vr) {
                Target::Variable(tt, vr2)
                    if tt == t && (vr2 as usize) < self.inner.info.count(t) =>
                {
                    self.vrs2.push(vr2)
                }
                Target::Time if time_ok => {}
                Target::Time => {
                    return err(format!(
                    "value reference {vr} is the independent variable '{}' (fmi3GetFloat64 only)",
                    value_refs::TIME_NAME
                ))
                }
                Target::Variable(tt, vr2) if (vr2 as usize) < self.inner.info.count(tt) => {
                    return err(format!(
                        "value reference {vr} is of type {}, not {}",
                        value_refs::type_name(tt),
                        value_refs::type_name(t)
                    ))
                }
                _ => return err(format!("unknown value reference {vr}")),
            }
        }
        Ok(())
    }

    /// fmi3GetFloat64. Float64 value references equal the per-type Real ones, so without `time` in
    /// the request the caller's arrays go straight to the core instance.
    pub fn get_float64(&mut self, vrs: &[u32], out: &mut [f64]) -> Res {
        self.translate(VarType::Real, vrs, true)?;
        if self.vrs2.len() == vrs.len() {
            return self.inner.get_real(vrs, out);
        }
        let mut values = vec![0.0; self.vrs2.len()];
        let status = self.inner.get_real(&self.vrs2, &mut values)?;
        let mut values = values.into_iter();
        let time_s = self.inner.core.time;
        for (o, vr) in out.iter_mut().zip(vrs) {
            *o = if *vr == TIME_VR {
                time_s
            } else {
                values.next().expect("one value per non-time reference")
            };
        }
        Ok(status)
    }

    pub fn set_float64(&mut self, vrs: &[u32], values: &[f64]) -> Res {
        self.translate(VarType::Real, vrs, false)?;
        self.inner.set_real(vrs, values)
    }

    pub fn get_int32(&mut self, vrs: &[u32], out: &mut [i32]) -> Res {
        self.translate(VarType::Integer, vrs, false)?;
        self.inner.get_integer(&self.vrs2, out)
    }

    pub fn set_int32(&mut self, vrs: &[u32], values: &[i32]) -> Res {
        self.translate(VarType::Integer, vrs, false)?;
        self.inner.set_integer(&self.vrs2, values)
    }

    pub fn get_boolean(&mut self, vrs: &[u32], out: &mut [bool]) -> Res {
        self.translate(VarType::Boolean, vrs, false)?;
        self.inner.get_boolean(&self.vrs2, out)
    }

    pub fn set_boolean(&mut self, vrs: &[u32], values: &[bool]) -> Res {
        self.translate(VarType::Boolean, vrs, false)?;
        self.inner.set_boolean(&self.vrs2, values)
    }

    /// fmi3GetOutputDerivatives: only Float64 outputs (the core instance checks causality).
    pub fn get_output_derivatives(&mut self, vrs: &[u32], orders: &[i32], out: &mut [f64]) -> Res {
        self.translate(VarType::Real, vrs, false)?;
        self.inner.get_output_derivatives(vrs, orders, out)
    }
}
