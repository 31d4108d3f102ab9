//! A Co-Simulation instance of an imported FMI 3.0 FMU, with safe methods over the raw C calls.
//!
//! Inputs within a step: FMI 3.0 has no input derivatives. A master gives this importer the same
//! Taylor polynomials it gives an FMI 2.0 FMU (`set_real_input_derivatives`); when the FMU asks
//! for its inputs at an internal time (intermediate update), the importer answers with the
//! polynomials' values there, computed by `fmi2::taylor_at`, the sum an FMI 2.0 FMU of this
//! layer computes itself. So an FMU pair built from one model gives the same inputs to its model
//! through either version, bit for bit.

use super::library::Api;
use crate::types::*;
use fmi_core::archive::ImportError;
use fmi_core::model::MAX_INPUT_DERIVATIVE_ORDER;
use fmi_core::Status;
use fmi_core::{check, CallError};
use fmi_core::{lossy, LogHandler, LogRecord};
use std::cell::{Cell, RefCell};
use std::ffi::{c_char, c_void, CString};
use std::path::Path;
use std::sync::Arc;

/// The input polynomials of the current step: per Float64 input, the value set last and the
/// derivatives given for this step.
#[derive(Default)]
struct Polynomials {
    t0: f64,
    vrs: Vec<u32>,
    values: Vec<f64>,
    derivatives: Vec<[f64; MAX_INPUT_DERIVATIVE_ORDER]>,
    /// The inputs with a polynomial this step and their values at the requested time (scratch).
    send_vrs: Vec<u32>,
    at: Vec<f64>,
}

impl Polynomials {
    fn slot(&mut self, vr: u32) -> usize {
        match self.vrs.iter().position(|v| *v == vr) {
            Some(i) => i,
            None => {
                self.vrs.push(vr);
                self.values.push(0.0);
                self.derivatives.push([0.0; MAX_INPUT_DERIVATIVE_ORDER]);
                self.vrs.len() - 1
            }
        }
    }
}

/// The instance environment handed to the FMU (boxed: its address is fixed while the FMU holds it).
struct Env {
    name: String,
    handler: LogHandler,
    set_float64: unsafe extern "C" fn(
        fmi3Instance,
        *const fmi3ValueReference,
        usize,
        *const f64,
        usize,
    ) -> fmi3Status,
    instance: Cell<fmi3Instance>,
    polynomials: RefCell<Polynomials>,
    /// Inputs are sent in intermediate updates (some derivative is non-zero this step).
    answering: Cell<bool>,
    /// The first status other than OK of an fmi3SetFloat64 inside a callback in this step.
    failed: Cell<Option<Status>>,
    /// Intermediate updates answered since instantiation.
    updates: Cell<u64>,
}

unsafe extern "C" fn log_message(
    env: fmi3InstanceEnvironment,
    status: fmi3Status,
    category: fmi3String,
    message: fmi3String,
) {
    // A panicking handler must not unwind into the FMU's frames.
    let _ = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| {
        // SAFETY: env is the Env we passed at instantiation; it outlives the instance.
        let env = unsafe { &*(env as *const Env) };
        let record = LogRecord {
            instance: env.name.clone(),
            status: Status::from_raw(status).unwrap_or(Status::Fatal),
            standard: "fmi3",
            // SAFETY: strings from the FMU, valid for this call.
            category: unsafe { lossy(category) },
            message: unsafe { lossy(message) },
        };
        (env.handler)(&record);
    }));
}

#[allow(clippy::too_many_arguments)]
unsafe extern "C" fn intermediate_update(
    env: fmi3InstanceEnvironment,
    time_s: fmi3Float64,
    set_requested: fmi3Boolean,
    _get_allowed: fmi3Boolean,
    _step_finished: fmi3Boolean,
    _can_return_early: fmi3Boolean,
    early_return_requested: *mut fmi3Boolean,
    _early_return_time: *mut fmi3Float64,
) {
    let _ = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| {
        if !early_return_requested.is_null() {
            // SAFETY: FMI contract: a writable flag. This importer never asks to return early.
            unsafe { *early_return_requested = false };
        }
        // SAFETY: env is the Env we passed at instantiation; it outlives the instance.
        let env = unsafe { &*(env as *const Env) };
        if !set_requested || !env.answering.get() {
            return;
        }
        env.updates.set(env.updates.get() + 1);
        let mut p = env.polynomials.borrow_mut();
        let p = &mut *p;
        p.at.clear();
        p.send_vrs.clear();
        // Inputs without derivatives keep the value set before the step (FMI 2.0: u0 + 0).
        for ((vr, u0), d) in p.vrs.iter().zip(&p.values).zip(&p.derivatives) {
            if d.iter().any(|x| *x != 0.0) {
                p.send_vrs.push(*vr);
                p.at.push(fmi_core::model::taylor_at(*u0, d, time_s - p.t0));
            }
        }
        // SAFETY: the FMU's own instance, inside its callback (Intermediate Update Mode), with
        // arrays of equal length.
        let s = unsafe {
            (env.set_float64)(
                env.instance.get(),
                p.send_vrs.as_ptr(),
                p.send_vrs.len(),
                p.at.as_ptr(),
                p.at.len(),
            )
        };
        match Status::from_raw(s) {
            Some(Status::Ok | Status::Warning) => {}
            other => {
                if env.failed.get().is_none() {
                    env.failed.set(Some(other.unwrap_or(Status::Fatal)));
                }
            }
        }
    }));
}

/// An instance's handle: its library's functions and its C instance, freed when dropped.
pub struct Inner {
    api: Arc<Api>,
    c: fmi3Instance,
    env: Box<Env>,
}

impl Drop for Inner {
    fn drop(&mut self) {
        // SAFETY: c came from fmi3InstantiateCoSimulation of this api and is freed once.
        unsafe { (self.api.free_instance)(self.c) }
    }
}

/// An instance. Methods take `&self` (the C side holds the state); it is `Send` but not `Sync`:
/// one thread at a time, as FMI 3.0 requires.
pub struct Slave {
    inner: Arc<Inner>,
    experiment: Cell<(Option<f64>, f64, Option<f64>)>,
    last_successful_time: Cell<f64>,
}

// FMI 3.0 allows an instance to be used from different threads, one call at a time (no Sync).
unsafe impl Send for Slave {}

/// An FMU state of a slave; freed (fmi3FreeFMUState) on drop. Keeps its instance alive.
pub type FmuState = fmi_core::states::FmuState<Inner>;

// SAFETY: each call is the FMU's own function for this live instance (`c`, freed only when
// `Inner` drops), with the arguments as given.
unsafe impl fmi_core::states::StateCalls for Inner {
    const NAMES: fmi_core::states::StateNames = fmi_core::states::StateNames {
        get: "fmi3GetFMUState",
        set: "fmi3SetFMUState",
        size: "fmi3SerializedFMUStateSize",
        serialize: "fmi3SerializeFMUState",
        deserialize: "fmi3DeserializeFMUState",
    };
    unsafe fn get(&self, state: *mut fmi3FMUState) -> i32 {
        unsafe { (self.api.get_fmu_state)(self.c, state) }
    }
    unsafe fn set(&self, state: fmi3FMUState) -> i32 {
        unsafe { (self.api.set_fmu_state)(self.c, state) }
    }
    unsafe fn free(&self, state: *mut fmi3FMUState) -> i32 {
        unsafe { (self.api.free_fmu_state)(self.c, state) }
    }
    unsafe fn size(&self, state: fmi3FMUState, size: *mut usize) -> i32 {
        unsafe { (self.api.serialized_fmu_state_size)(self.c, state, size) }
    }
    unsafe fn serialize(&self, state: fmi3FMUState, bytes: *mut u8, size: usize) -> i32 {
        unsafe { (self.api.serialize_fmu_state)(self.c, state, bytes, size) }
    }
    unsafe fn deserialize(&self, bytes: *const u8, size: usize, state: *mut fmi3FMUState) -> i32 {
        unsafe { (self.api.deserialize_fmu_state)(self.c, bytes, size, state) }
    }
}

impl Slave {
    /// fmi3InstantiateCoSimulation. With `intermediate_update`, the importer answers the FMU's
    /// intermediate updates with the input polynomials (see the module comment).
    pub fn instantiate(
        api: Arc<Api>,
        token: &str,
        resource_dir: &Path,
        name: &str,
        logging_on: bool,
        handler: LogHandler,
        intermediate_update_vrs: &[u32],
    ) -> Result<Slave, ImportError> {
        let env = Box::new(Env {
            name: name.to_string(),
            handler,
            set_float64: api.set_float64,
            instance: Cell::new(std::ptr::null_mut()),
            polynomials: RefCell::default(),
            answering: Cell::new(false),
            failed: Cell::new(None),
            updates: Cell::new(0),
        });
        let cname =
            CString::new(name).map_err(|_| ImportError("instance name contains NUL".into()))?;
        let ctoken = CString::new(token)
            .map_err(|_| ImportError("instantiation token contains NUL".into()))?;
        // FMI 3.0: an absolute native path with a trailing separator.
        let mut res = resource_dir.display().to_string();
        if !res.ends_with('/') {
            res.push('/');
        }
        let cres =
            CString::new(res).map_err(|_| ImportError("resource path contains NUL".into()))?;
        let callback: fmi3IntermediateUpdateCallback = if intermediate_update_vrs.is_empty() {
            None
        } else {
            Some(intermediate_update)
        };
        // SAFETY: valid strings and an environment that outlives the instance (owned by Inner).
        let c = unsafe {
            (api.instantiate_co_simulation)(
                cname.as_ptr(),
                ctoken.as_ptr(),
                cres.as_ptr(),
                false,
                logging_on,
                false,
                false,
                intermediate_update_vrs.as_ptr(),
                intermediate_update_vrs.len(),
                &*env as *const Env as *mut c_void,
                Some(log_message),
                callback,
            )
        };
        if c.is_null() {
            return Err(ImportError(format!(
                "fmi3InstantiateCoSimulation of '{name}' failed (see the FMU's log)"
            )));
        }
        env.instance.set(c);
        // Arc (not Rc) so that Slave and FmuState can be Send; one thread at a time still.
        #[allow(clippy::arc_with_non_send_sync)]
        let inner = Arc::new(Inner { api, c, env });
        Ok(Slave {
            inner,
            experiment: Cell::new((None, 0.0, None)),
            last_successful_time: Cell::new(f64::NAN),
        })
    }

    pub fn name(&self) -> &str {
        &self.inner.env.name
    }

    /// Intermediate updates this importer has answered with input values.
    pub fn intermediate_updates(&self) -> u64 {
        self.inner.env.updates.get()
    }

    fn api(&self) -> &Api {
        &self.inner.api
    }

    fn c(&self) -> fmi3Instance {
        self.inner.c
    }

    pub fn set_debug_logging(&self, on: bool, categories: &[&str]) -> Result<(), CallError> {
        let owned: Vec<CString> = categories
            .iter()
            .map(|s| CString::new(s.replace('\0', " ")).unwrap_or_default())
            .collect();
        let ptrs: Vec<*const c_char> = owned.iter().map(|s| s.as_ptr()).collect();
        // SAFETY: valid array of C strings.
        check("fmi3SetDebugLogging", unsafe {
            (self.api().set_debug_logging)(self.c(), on, ptrs.len(), ptrs.as_ptr())
        })
    }

    /// Tolerance, start and stop time for fmi3EnterInitializationMode (FMI 2.0's
    /// fmi2SetupExperiment, kept apart so both importers read alike).
    pub fn setup_experiment(
        &self,
        tolerance: Option<f64>,
        start: f64,
        stop: Option<f64>,
    ) -> Result<(), CallError> {
        self.experiment.set((tolerance, start, stop));
        Ok(())
    }

    pub fn enter_initialization_mode(&self) -> Result<(), CallError> {
        let (tol, start, stop) = self.experiment.get();
        // SAFETY: plain values.
        check("fmi3EnterInitializationMode", unsafe {
            (self.api().enter_initialization_mode)(
                self.c(),
                tol.is_some(),
                tol.unwrap_or(0.0),
                start,
                stop.is_some(),
                stop.unwrap_or(0.0),
            )
        })
    }

    pub fn exit_initialization_mode(&self) -> Result<(), CallError> {
        // SAFETY: valid instance.
        check("fmi3ExitInitializationMode", unsafe {
            (self.api().exit_initialization_mode)(self.c())
        })
    }

    pub fn terminate(&self) -> Result<(), CallError> {
        // SAFETY: valid instance.
        check("fmi3Terminate", unsafe { (self.api().terminate)(self.c()) })
    }

    pub fn reset(&self) -> Result<(), CallError> {
        // SAFETY: valid instance.
        check("fmi3Reset", unsafe { (self.api().reset)(self.c()) })
    }

    pub fn set_float64(&self, vrs: &[u32], values: &[f64]) -> Result<(), CallError> {
        assert_eq!(vrs.len(), values.len(), "one value per value reference");
        {
            // The values at the next step's start: the polynomials' constant terms.
            let mut p = self.inner.env.polynomials.borrow_mut();
            for (vr, v) in vrs.iter().zip(values) {
                let i = p.slot(*vr);
                p.values[i] = *v;
            }
        }
        // SAFETY: arrays of equal length.
        check("fmi3SetFloat64", unsafe {
            (self.api().set_float64)(
                self.c(),
                vrs.as_ptr(),
                vrs.len(),
                values.as_ptr(),
                values.len(),
            )
        })
    }

    pub fn get_float64(&self, vrs: &[u32], values: &mut [f64]) -> Result<(), CallError> {
        assert_eq!(vrs.len(), values.len(), "one value per value reference");
        // SAFETY: arrays of equal length.
        check("fmi3GetFloat64", unsafe {
            (self.api().get_float64)(
                self.c(),
                vrs.as_ptr(),
                vrs.len(),
                values.as_mut_ptr(),
                values.len(),
            )
        })
    }

    pub fn set_int32(&self, vrs: &[u32], values: &[i32]) -> Result<(), CallError> {
        assert_eq!(vrs.len(), values.len(), "one value per value reference");
        // SAFETY: arrays of equal length.
        check("fmi3SetInt32", unsafe {
            (self.api().set_int32)(
                self.c(),
                vrs.as_ptr(),
                vrs.len(),
                values.as_ptr(),
                values.len(),
            )
        })
    }

    pub fn get_int32(&self, vrs: &[u32], values: &mut [i32]) -> Result<(), CallError> {
        assert_eq!(vrs.len(), values.len(), "one value per value reference");
        // SAFETY: arrays of equal length.
        check("fmi3GetInt32", unsafe {
            (self.api().get_int32)(
                self.c(),
                vrs.as_ptr(),
                vrs.len(),
                values.as_mut_ptr(),
                values.len(),
            )
        })
    }

    pub fn set_boolean(&self, vrs: &[u32], values: &[bool]) -> Result<(), CallError> {
        assert_eq!(vrs.len(), values.len(), "one value per value reference");
        // SAFETY: arrays of equal length.
        check("fmi3SetBoolean", unsafe {
            (self.api().set_boolean)(
                self.c(),
                vrs.as_ptr(),
                vrs.len(),
                values.as_ptr(),
                values.len(),
            )
        })
    }

    pub fn get_boolean(&self, vrs: &[u32], values: &mut [bool]) -> Result<(), CallError> {
        assert_eq!(vrs.len(), values.len(), "one value per value reference");
        // SAFETY: arrays of equal length.
        check("fmi3GetBoolean", unsafe {
            (self.api().get_boolean)(
                self.c(),
                vrs.as_ptr(),
                vrs.len(),
                values.as_mut_ptr(),
                values.len(),
            )
        })
    }

    /// The inputs' time derivatives at the next step's start (order k of input vrs[i] is
    /// values[i]): answered in the FMU's intermediate updates of that step only, as FMI 2.0's
    /// fmi2SetRealInputDerivatives applies to one step. Call after `set_float64` of the values.
    pub fn set_input_derivatives(
        &self,
        vrs: &[u32],
        orders: &[i32],
        values: &[f64],
    ) -> Result<(), CallError> {
        assert!(
            vrs.len() == orders.len() && vrs.len() == values.len(),
            "equal lengths"
        );
        let refuse = || {
            Err(CallError {
                function: "input derivatives (FMI 3.0 intermediate update)",
                status: Status::Error,
            })
        };
        let mut p = self.inner.env.polynomials.borrow_mut();
        for ((vr, order), v) in vrs.iter().zip(orders).zip(values) {
            if !(1..=MAX_INPUT_DERIVATIVE_ORDER as i32).contains(order) || !v.is_finite() {
                return refuse();
            }
            // A derivative without a value set before would start from 0: refused.
            let Some(i) = p.vrs.iter().position(|x| x == vr) else {
                return refuse();
            };
            p.derivatives[i][*order as usize - 1] = *v;
        }
        Ok(())
    }

    pub fn get_output_derivatives(
        &self,
        vrs: &[u32],
        orders: &[i32],
        values: &mut [f64],
    ) -> Result<(), CallError> {
        assert!(
            vrs.len() == orders.len() && vrs.len() == values.len(),
            "equal lengths"
        );
        // SAFETY: arrays of equal length.
        check("fmi3GetOutputDerivatives", unsafe {
            (self.api().get_output_derivatives)(
                self.c(),
                vrs.as_ptr(),
                vrs.len(),
                orders.as_ptr(),
                values.as_mut_ptr(),
                values.len(),
            )
        })
    }

    /// fmi3DoStep from `t` by `h`; the input polynomials answer the FMU's intermediate updates.
    pub fn do_step(&self, t: f64, h: f64) -> Result<(), CallError> {
        let env = &self.inner.env;
        {
            let mut p = env.polynomials.borrow_mut();
            p.t0 = t;
            let any = p.derivatives.iter().any(|d| d.iter().any(|x| *x != 0.0));
            env.answering.set(any);
        }
        env.failed.set(None);
        let (mut event, mut terminate, mut early, mut last) = (false, false, false, f64::NAN);
        // SAFETY: plain values and four writable outputs.
        let s = unsafe {
            (self.api().do_step)(
                self.c(),
                t,
                h,
                true,
                &mut event,
                &mut terminate,
                &mut early,
                &mut last,
            )
        };
        self.last_successful_time.set(last);
        env.answering.set(false);
        for d in env.polynomials.borrow_mut().derivatives.iter_mut() {
            *d = [0.0; MAX_INPUT_DERIVATIVE_ORDER];
        }
        check("fmi3DoStep", s)?;
        if let Some(status) = env.failed.get() {
            return Err(CallError {
                function: "fmi3SetFloat64 (inside intermediateUpdate)",
                status,
            });
        }
        if early || event {
            // This importer allows neither (earlyReturnAllowed = false, eventModeUsed = false).
            return Err(CallError {
                function: "fmi3DoStep (returned early or asked for event handling)",
                status: Status::Error,
            });
        }
        Ok(())
    }

    /// lastSuccessfulTime of the last fmi3DoStep.
    pub fn last_successful_time(&self) -> f64 {
        self.last_successful_time.get()
    }

    pub fn get_state(&self) -> Result<FmuState, CallError> {
        FmuState::get(&self.inner)
    }

    /// fmi3GetFMUState into an existing state (the FMU may reuse its memory).
    pub fn update_state(&self, state: &mut FmuState) -> Result<(), CallError> {
        state.update(&self.inner)
    }

    pub fn set_state(&self, state: &FmuState) -> Result<(), CallError> {
        state.set(&self.inner)
    }

    pub fn serialize_state(&self, state: &FmuState) -> Result<Vec<u8>, CallError> {
        state.serialize()
    }

    pub fn deserialize_state(&self, bytes: &[u8]) -> Result<FmuState, CallError> {
        FmuState::deserialize(&self.inner, bytes)
    }
}

/// The version-neutral surface `cosim` drives (fmi_core::CoSimSlave): Float64 as reals, Int32 as
/// integers, input derivatives as the polynomials of the intermediate updates.
impl fmi_core::CoSimSlave for Slave {
    fn name(&self) -> &str {
        Slave::name(self)
    }
    fn setup_experiment(
        &self,
        tolerance: Option<f64>,
        start: f64,
        stop: Option<f64>,
    ) -> Result<(), CallError> {
        Slave::setup_experiment(self, tolerance, start, stop)
    }
    fn enter_initialization_mode(&self) -> Result<(), CallError> {
        Slave::enter_initialization_mode(self)
    }
    fn exit_initialization_mode(&self) -> Result<(), CallError> {
        Slave::exit_initialization_mode(self)
    }
    fn terminate(&self) -> Result<(), CallError> {
        Slave::terminate(self)
    }
    fn set_real(&self, vrs: &[u32], values: &[f64]) -> Result<(), CallError> {
        Slave::set_float64(self, vrs, values)
    }
    fn get_real(&self, vrs: &[u32], values: &mut [f64]) -> Result<(), CallError> {
        Slave::get_float64(self, vrs, values)
    }
    fn set_integer(&self, vrs: &[u32], values: &[i32]) -> Result<(), CallError> {
        Slave::set_int32(self, vrs, values)
    }
    fn get_integer(&self, vrs: &[u32], values: &mut [i32]) -> Result<(), CallError> {
        Slave::get_int32(self, vrs, values)
    }
    fn set_boolean(&self, vrs: &[u32], values: &[bool]) -> Result<(), CallError> {
        Slave::set_boolean(self, vrs, values)
    }
    fn get_boolean(&self, vrs: &[u32], values: &mut [bool]) -> Result<(), CallError> {
        Slave::get_boolean(self, vrs, values)
    }
    fn set_real_input_derivatives(
        &self,
        vrs: &[u32],
        orders: &[i32],
        values: &[f64],
    ) -> Result<(), CallError> {
        Slave::set_input_derivatives(self, vrs, orders, values)
    }
    fn do_step(&self, t: f64, h: f64) -> Result<(), CallError> {
        Slave::do_step(self, t, h)
    }
    fn last_successful_time(&self) -> Result<f64, CallError> {
        Ok(Slave::last_successful_time(self))
    }
    fn get_state(&self) -> Result<fmi_core::SavedState, CallError> {
        Slave::get_state(self).map(fmi_core::SavedState::new)
    }
    fn update_state(&self, state: &mut fmi_core::SavedState) -> Result<(), CallError> {
        Slave::update_state(self, state.get_mut::<FmuState>("fmi3GetFMUState")?)
    }
    fn set_state(&self, state: &fmi_core::SavedState) -> Result<(), CallError> {
        Slave::set_state(self, state.get::<FmuState>("fmi3SetFMUState")?)
    }
    fn serialize_state(&self, state: &fmi_core::SavedState) -> Result<Vec<u8>, CallError> {
        Slave::serialize_state(self, state.get::<FmuState>("fmi3SerializeFMUState")?)
    }
    fn deserialize_state(&self, bytes: &[u8]) -> Result<fmi_core::SavedState, CallError> {
        Slave::deserialize_state(self, bytes).map(fmi_core::SavedState::new)
    }
}
