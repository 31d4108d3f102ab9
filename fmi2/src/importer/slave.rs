//! A co-simulation instance of an imported FMU, with safe methods over the raw C calls.

use super::{Api, ImportError};
use crate::types::*;
pub use fmi_core::{lossy, LogHandler, LogRecord};
use std::ffi::{c_char, c_void, CString};
use std::sync::Arc;

/// Component environment handed to the FMU; the C shim reads `sink` (first field) and calls it.
#[repr(C)]
struct LogEnv {
    sink: unsafe extern "C" fn(*mut c_void, Fmi2String, Fmi2StatusRaw, Fmi2String, Fmi2String),
    handler: LogHandler,
}

extern "C" {
    fn airring_fmi2_logger(
        env: *mut c_void,
        instance: Fmi2String,
        status: Fmi2StatusRaw,
        category: Fmi2String,
        format: Fmi2String,
        ...
    );
    fn calloc(n: usize, size: usize) -> *mut c_void;
    fn free(p: *mut c_void);
}

unsafe extern "C" fn sink(
    env: *mut c_void,
    instance: Fmi2String,
    status: Fmi2StatusRaw,
    category: Fmi2String,
    message: Fmi2String,
) {
    // A panicking handler must not unwind into the FMU's C frames.
    let _ = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| {
        // SAFETY: env is the LogEnv we passed in fmi2Instantiate; it outlives the instance.
        let env = unsafe { &*(env as *const LogEnv) };
        let record = LogRecord {
            // SAFETY: strings from the FMU (or the shim), valid for this call.
            instance: unsafe { lossy(instance) },
            status: Status::from_raw(status).unwrap_or(Status::Fatal),
            standard: "fmi2",
            category: unsafe { lossy(category) },
            message: unsafe { lossy(message) },
        };
        (env.handler)(&record);
    }));
}

unsafe extern "C" fn alloc(n: usize, size: usize) -> *mut c_void {
    // SAFETY: libc calloc.
    unsafe { calloc(n, size) }
}

unsafe extern "C" fn dealloc(p: *mut c_void) {
    // SAFETY: libc free of memory from `alloc`.
    unsafe { free(p) }
}

pub use fmi_core::{check, CallError};

/// An instance's handle: its library's functions and its C instance, freed when dropped.
pub struct Inner {
    api: Arc<Api>,
    c: Fmi2Component,
    // Boxed so their addresses stay fixed while the FMU holds them.
    _env: Box<LogEnv>,
    _callbacks: Box<Fmi2CallbackFunctions>,
    name: String,
}

impl Drop for Inner {
    fn drop(&mut self) {
        // SAFETY: c came from fmi2Instantiate of this api and is freed once.
        unsafe { (self.api.free_instance)(self.c) }
    }
}

/// An instance. Methods take `&self` (the C side holds the state); it is `Send` but not `Sync`: one
/// thread at a time, as FMI 2.0 requires.
pub struct Slave {
    inner: Arc<Inner>,
}

// FMI 2.0 allows an instance to be used from different threads, one call at a time (no Sync).
unsafe impl Send for Slave {}

/// An FMU state of a slave; freed (fmi2FreeFMUstate) on drop. Keeps its instance alive.
pub type FmuState = fmi_core::states::FmuState<Inner>;

// SAFETY: each call is the FMU's own function for this live instance (`c`, freed only when
// `Inner` drops), with the arguments as given; fmi2Byte is c_char, passed as u8 of the same size.
unsafe impl fmi_core::states::StateCalls for Inner {
    const NAMES: fmi_core::states::StateNames = fmi_core::states::StateNames {
        get: "fmi2GetFMUstate",
        set: "fmi2SetFMUstate",
        size: "fmi2SerializedFMUstateSize",
        serialize: "fmi2SerializeFMUstate",
        deserialize: "fmi2DeSerializeFMUstate",
    };
    unsafe fn get(&self, state: *mut Fmi2FmuState) -> i32 {
        unsafe { (self.api.get_fmu_state)(self.c, state) }
    }
    unsafe fn set(&self, state: Fmi2FmuState) -> i32 {
        unsafe { (self.api.set_fmu_state)(self.c, state) }
    }
    unsafe fn free(&self, state: *mut Fmi2FmuState) -> i32 {
        unsafe { (self.api.free_fmu_state)(self.c, state) }
    }
    unsafe fn size(&self, state: Fmi2FmuState, size: *mut usize) -> i32 {
        unsafe { (self.api.serialized_fmu_state_size)(self.c, state, size) }
    }
    unsafe fn serialize(&self, state: Fmi2FmuState, bytes: *mut u8, size: usize) -> i32 {
        unsafe { (self.api.serialize_fmu_state)(self.c, state, bytes as *mut Fmi2Byte, size) }
    }
    unsafe fn deserialize(&self, bytes: *const u8, size: usize, state: *mut Fmi2FmuState) -> i32 {
        unsafe { (self.api.de_serialize_fmu_state)(self.c, bytes as *const Fmi2Byte, size, state) }
    }
}

impl Slave {
    pub fn instantiate(
        api: Arc<Api>,
        guid: &str,
        resource_uri: &str,
        name: &str,
        logging_on: bool,
        handler: LogHandler,
    ) -> Result<Slave, ImportError> {
        let env = Box::new(LogEnv { sink, handler });
        let callbacks = Box::new(Fmi2CallbackFunctions {
            // SAFETY: same ABI as fmi2CallbackLogger (the shim is C-variadic).
            logger: Some(airring_fmi2_logger),
            allocate_memory: Some(alloc),
            free_memory: Some(dealloc),
            step_finished: None,
            component_environment: &*env as *const LogEnv as *mut c_void,
        });
        let cname =
            CString::new(name).map_err(|_| ImportError("instance name contains NUL".into()))?;
        let cguid = CString::new(guid).map_err(|_| ImportError("GUID contains NUL".into()))?;
        let cres = CString::new(resource_uri)
            .map_err(|_| ImportError("resource URI contains NUL".into()))?;
        // SAFETY: valid strings and callbacks that outlive the instance (owned by Inner).
        let c = unsafe {
            (api.instantiate)(
                cname.as_ptr(),
                FMI2_CO_SIMULATION,
                cguid.as_ptr(),
                cres.as_ptr(),
                &*callbacks,
                FMI2_FALSE,
                logging_on as Fmi2Boolean,
            )
        };
        if c.is_null() {
            return Err(ImportError(format!(
                "fmi2Instantiate of '{name}' failed (see the FMU's log)"
            )));
        }
        // Arc (not Rc) so that Slave and FmuState can be Send; the instance is still used by one thread
        // at a time (Slave is not Sync), as FMI 2.0 requires.
        #[allow(clippy::arc_with_non_send_sync)]
        let inner = Arc::new(Inner {
            api,
            c,
            _env: env,
            _callbacks: callbacks,
            name: name.to_string(),
        });
        Ok(Slave { inner })
    }

    pub fn name(&self) -> &str {
        &self.inner.name
    }

    /// Raw access for tests that drive the C ABI directly.
    pub fn raw(&self) -> (&Api, Fmi2Component) {
        (&self.inner.api, self.inner.c)
    }

    fn api(&self) -> &Api {
        &self.inner.api
    }

    fn c(&self) -> Fmi2Component {
        self.inner.c
    }

    pub fn set_debug_logging(&self, on: bool, categories: &[&str]) -> Result<(), CallError> {
        let owned: Vec<CString> = categories
            .iter()
            .map(|s| fmi_core::logging::to_cstring(s))
            .collect();
        let ptrs: Vec<*const c_char> = owned.iter().map(|s| s.as_ptr()).collect();
        // SAFETY: valid array of C strings.
        check("fmi2SetDebugLogging", unsafe {
            (self.api().set_debug_logging)(self.c(), on as i32, ptrs.len(), ptrs.as_ptr())
        })
    }

    pub fn setup_experiment(
        &self,
        tolerance: Option<f64>,
        start: f64,
        stop: Option<f64>,
    ) -> Result<(), CallError> {
        // SAFETY: plain values.
        let s = unsafe {
            (self.api().setup_experiment)(
                self.c(),
                tolerance.is_some() as i32,
                tolerance.unwrap_or(0.0),
                start,
                stop.is_some() as i32,
                stop.unwrap_or(0.0),
            )
        };
        check("fmi2SetupExperiment", s)
    }

    pub fn enter_initialization_mode(&self) -> Result<(), CallError> {
        // SAFETY: valid component.
        check("fmi2EnterInitializationMode", unsafe {
            (self.api().enter_initialization_mode)(self.c())
        })
    }

    pub fn exit_initialization_mode(&self) -> Result<(), CallError> {
        // SAFETY: valid component.
        check("fmi2ExitInitializationMode", unsafe {
            (self.api().exit_initialization_mode)(self.c())
        })
    }

    pub fn terminate(&self) -> Result<(), CallError> {
        // SAFETY: valid component.
        check("fmi2Terminate", unsafe { (self.api().terminate)(self.c()) })
    }

    pub fn reset(&self) -> Result<(), CallError> {
        // SAFETY: valid component.
        check("fmi2Reset", unsafe { (self.api().reset)(self.c()) })
    }

    pub fn set_real(&self, vrs: &[u32], values: &[f64]) -> Result<(), CallError> {
        assert_eq!(vrs.len(), values.len(), "one value per value reference");
        // SAFETY: arrays of equal length.
        check("fmi2SetReal", unsafe {
            (self.api().set_real)(self.c(), vrs.as_ptr(), vrs.len(), values.as_ptr())
        })
    }

    pub fn get_real(&self, vrs: &[u32], values: &mut [f64]) -> Result<(), CallError> {
        assert_eq!(vrs.len(), values.len(), "one value per value reference");
        // SAFETY: arrays of equal length.
        check("fmi2GetReal", unsafe {
            (self.api().get_real)(self.c(), vrs.as_ptr(), vrs.len(), values.as_mut_ptr())
        })
    }

    pub fn set_integer(&self, vrs: &[u32], values: &[i32]) -> Result<(), CallError> {
        assert_eq!(vrs.len(), values.len(), "one value per value reference");
        // SAFETY: arrays of equal length.
        check("fmi2SetInteger", unsafe {
            (self.api().set_integer)(self.c(), vrs.as_ptr(), vrs.len(), values.as_ptr())
        })
    }

    pub fn get_integer(&self, vrs: &[u32], values: &mut [i32]) -> Result<(), CallError> {
        assert_eq!(vrs.len(), values.len(), "one value per value reference");
        // SAFETY: arrays of equal length.
        check("fmi2GetInteger", unsafe {
            (self.api().get_integer)(self.c(), vrs.as_ptr(), vrs.len(), values.as_mut_ptr())
        })
    }

    pub fn set_boolean(&self, vrs: &[u32], values: &[bool]) -> Result<(), CallError> {
        let v: Vec<Fmi2Boolean> = values.iter().map(|b| *b as Fmi2Boolean).collect();
        assert_eq!(vrs.len(), v.len(), "one value per value reference");
        // SAFETY: arrays of equal length.
        check("fmi2SetBoolean", unsafe {
            (self.api().set_boolean)(self.c(), vrs.as_ptr(), vrs.len(), v.as_ptr())
        })
    }

    pub fn get_boolean(&self, vrs: &[u32], values: &mut [bool]) -> Result<(), CallError> {
        let mut v = vec![0; vrs.len()];
        // SAFETY: arrays of equal length.
        check("fmi2GetBoolean", unsafe {
            (self.api().get_boolean)(self.c(), vrs.as_ptr(), vrs.len(), v.as_mut_ptr())
        })?;
        for (o, x) in values.iter_mut().zip(v) {
            *o = x != 0;
        }
        Ok(())
    }

    pub fn set_real_input_derivatives(
        &self,
        vrs: &[u32],
        orders: &[i32],
        values: &[f64],
    ) -> Result<(), CallError> {
        assert!(
            vrs.len() == orders.len() && vrs.len() == values.len(),
            "equal lengths"
        );
        // SAFETY: arrays of equal length.
        let s = unsafe {
            (self.api().set_real_input_derivatives)(
                self.c(),
                vrs.as_ptr(),
                vrs.len(),
                orders.as_ptr(),
                values.as_ptr(),
            )
        };
        check("fmi2SetRealInputDerivatives", s)
    }

    pub fn get_real_output_derivatives(
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
        let s = unsafe {
            (self.api().get_real_output_derivatives)(
                self.c(),
                vrs.as_ptr(),
                vrs.len(),
                orders.as_ptr(),
                values.as_mut_ptr(),
            )
        };
        check("fmi2GetRealOutputDerivatives", s)
    }

    pub fn do_step(&self, t: f64, h: f64) -> Result<(), CallError> {
        // SAFETY: plain values.
        check("fmi2DoStep", unsafe {
            (self.api().do_step)(self.c(), t, h, FMI2_TRUE)
        })
    }

    /// fmi2LastSuccessfulTime (after a discarded step).
    pub fn last_successful_time(&self) -> Result<f64, CallError> {
        let mut t = f64::NAN;
        // SAFETY: one f64 out.
        check("fmi2GetRealStatus", unsafe {
            (self.api().get_real_status)(self.c(), FMI2_LAST_SUCCESSFUL_TIME, &mut t)
        })?;
        Ok(t)
    }

    pub fn get_state(&self) -> Result<FmuState, CallError> {
        FmuState::get(&self.inner)
    }

    /// fmi2GetFMUstate into an existing state (the FMU may reuse its memory).
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

/// The version-neutral surface `cosim` drives (fmi_core::CoSimSlave): the same calls.
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
        Slave::set_real(self, vrs, values)
    }
    fn get_real(&self, vrs: &[u32], values: &mut [f64]) -> Result<(), CallError> {
        Slave::get_real(self, vrs, values)
    }
    fn set_integer(&self, vrs: &[u32], values: &[i32]) -> Result<(), CallError> {
        Slave::set_integer(self, vrs, values)
    }
    fn get_integer(&self, vrs: &[u32], values: &mut [i32]) -> Result<(), CallError> {
        Slave::get_integer(self, vrs, values)
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
        Slave::set_real_input_derivatives(self, vrs, orders, values)
    }
    fn do_step(&self, t: f64, h: f64) -> Result<(), CallError> {
        Slave::do_step(self, t, h)
    }
    fn last_successful_time(&self) -> Result<f64, CallError> {
        Slave::last_successful_time(self)
    }
    fn get_state(&self) -> Result<fmi_core::SavedState, CallError> {
        Slave::get_state(self).map(fmi_core::SavedState::new)
    }
    fn update_state(&self, state: &mut fmi_core::SavedState) -> Result<(), CallError> {
        Slave::update_state(self, state.get_mut::<FmuState>("fmi2GetFMUstate")?)
    }
    fn set_state(&self, state: &fmi_core::SavedState) -> Result<(), CallError> {
        Slave::set_state(self, state.get::<FmuState>("fmi2SetFMUstate")?)
    }
    fn serialize_state(&self, state: &fmi_core::SavedState) -> Result<Vec<u8>, CallError> {
        Slave::serialize_state(self, state.get::<FmuState>("fmi2SerializeFMUstate")?)
    }
    fn deserialize_state(&self, bytes: &[u8]) -> Result<fmi_core::SavedState, CallError> {
        Slave::deserialize_state(self, bytes).map(fmi_core::SavedState::new)
    }
}
