//! The C side of the 34 FMI 2.0 co-simulation functions, generic over the model. The `export_fmu!`
//! macro emits `#[no_mangle]` wrappers that call these. Each body runs under `catch_unwind`, so a panic
//! becomes fmi2Error with a log line and never unwinds into (or aborts) the host.

use crate::types::*;
use fmi_core::instance::{Core, Instance, Phase, INSTANCE_MAGIC};
use fmi_core::model::Model;
use std::ffi::{c_char, c_int, CStr};
use std::panic::{catch_unwind, AssertUnwindSafe};

const ERROR: Fmi2StatusRaw = Status::Error as Fmi2StatusRaw;

fn panic_message(payload: &(dyn std::any::Any + Send)) -> String {
    if let Some(s) = payload.downcast_ref::<&str>() {
        s.to_string()
    } else if let Some(s) = payload.downcast_ref::<String>() {
        s.clone()
    } else {
        "unknown panic".into()
    }
}

/// # Safety
/// `c` must be null or a pointer returned by `instantiate::<M>` and not yet freed.
unsafe fn instance<'a, M: Model>(c: Fmi2Component) -> Option<&'a mut Instance<M>> {
    if c.is_null() {
        return None;
    }
    // SAFETY: per the contract above; the magic check catches a mismatched model type or a stale pointer
    // whose memory has been reused (best effort: a truly foreign pointer cannot be detected).
    let inst = unsafe { &mut *(c as *mut Instance<M>) };
    (inst.magic == INSTANCE_MAGIC).then_some(inst)
}

/// Runs `body` on the instance behind `c`, catching panics.
fn with<M: Model>(
    c: Fmi2Component,
    function: &str,
    body: impl FnOnce(&mut Instance<M>) -> Status,
) -> Fmi2StatusRaw {
    // SAFETY: FMI contract: the importer passes the component it got from fmi2Instantiate.
    let Some(inst) = (unsafe { instance::<M>(c) }) else {
        return ERROR;
    };
    let inst_ptr: *mut Instance<M> = inst;
    match catch_unwind(AssertUnwindSafe(|| body(inst))) {
        Ok(s) => s as Fmi2StatusRaw,
        Err(payload) => {
            // SAFETY: the closure that borrowed the instance has ended (it unwound).
            let inst = unsafe { &mut *inst_ptr };
            inst.core.phase = Phase::Error;
            inst.logger.reject(
                Status::Error,
                function,
                &format!(
                    "internal error (panic caught): {}",
                    panic_message(&*payload)
                ),
            );
            ERROR
        }
    }
}

/// A slice from a C array; `None` if the pointer is null while `n > 0`.
///
/// # Safety
/// If non-null, `p` must point to `n` valid elements.
unsafe fn slice<'a, T>(p: *const T, n: usize) -> Option<&'a [T]> {
    if n == 0 {
        Some(&[])
    } else if p.is_null() {
        None
    } else {
        // SAFETY: see the contract above.
        Some(unsafe { std::slice::from_raw_parts(p, n) })
    }
}

/// # Safety
/// If non-null, `p` must point to `n` writable elements.
unsafe fn slice_mut<'a, T>(p: *mut T, n: usize) -> Option<&'a mut [T]> {
    if n == 0 {
        Some(&mut [])
    } else if p.is_null() {
        None
    } else {
        // SAFETY: see the contract above.
        Some(unsafe { std::slice::from_raw_parts_mut(p, n) })
    }
}

/// # Safety
/// `s` must be null or a NUL-terminated string.
unsafe fn string<'a>(s: Fmi2String) -> Option<&'a str> {
    if s.is_null() {
        None
    } else {
        // SAFETY: see the contract above.
        unsafe { CStr::from_ptr(s) }.to_str().ok()
    }
}

fn null_argument(inst: &Instance<impl Model>, function: &str, what: &str) -> Status {
    inst.logger.reject(
        Status::Error,
        function,
        &format!("{what} is a null pointer"),
    );
    Status::Error
}

pub fn types_platform() -> *const c_char {
    TYPES_PLATFORM.as_ptr() as *const c_char
}

pub fn version() -> *const c_char {
    VERSION.as_ptr() as *const c_char
}

/// # Safety
/// Arguments as in FMI 2.0 `fmi2Instantiate`.
pub unsafe fn instantiate<M: Model>(
    instance_name: Fmi2String,
    fmu_type: Fmi2Type,
    guid: Fmi2String,
    resource_location: Fmi2String,
    functions: *const Fmi2CallbackFunctions,
    _visible: Fmi2Boolean,
    logging_on: Fmi2Boolean,
) -> Fmi2Component {
    let result = catch_unwind(AssertUnwindSafe(|| {
        // SAFETY: FMI contract: a null or valid callback struct.
        let callbacks = unsafe { functions.as_ref() }.copied();
        // SAFETY: FMI contract: NUL-terminated strings or null.
        let (name, guid, res) = unsafe {
            (
                string(instance_name),
                string(guid),
                string(resource_location),
            )
        };
        let refuse = |reason: &str| {
            let logger = crate::logging::logger(callbacks, name.unwrap_or("?"), true, &[]);
            logger.reject(Status::Error, "fmi2Instantiate", reason);
            std::ptr::null_mut()
        };
        let Some(name) = name else {
            return refuse("instanceName is null or not UTF-8");
        };
        let Some(guid) = guid else {
            return refuse("fmuGUID is null or not UTF-8");
        };
        if fmu_type != FMI2_CO_SIMULATION {
            return refuse(
                "this FMU supports Co-Simulation only (fmuType must be fmi2CoSimulation)",
            );
        }
        let logger = crate::logging::logger(
            callbacks,
            name,
            logging_on != 0,
            &M::info().all_log_categories(),
        );
        let resources = match res {
            None | Some("") => Ok(None),
            Some(uri) => crate::resource::uri_to_path(uri).map(Some),
        };
        match Instance::<M>::new(name, guid, resources, logger) {
            Ok(inst) => Box::into_raw(Box::new(inst)) as Fmi2Component,
            Err((logger, reason)) => {
                logger.reject(Status::Error, "fmi2Instantiate", &reason);
                std::ptr::null_mut()
            }
        }
    }));
    result.unwrap_or(std::ptr::null_mut())
}

/// # Safety
/// `c` null or from `instantiate::<M>`; it is invalid afterwards.
pub unsafe fn free_instance<M: Model>(c: Fmi2Component) {
    // SAFETY: contract above.
    if unsafe { instance::<M>(c) }.is_some() {
        let _ = catch_unwind(|| {
            // SAFETY: created by Box::into_raw in `instantiate`; clearing the magic makes a second
            // free of the same (not yet reused) memory a detected no-op rather than a double free.
            let mut inst = unsafe { Box::from_raw(c as *mut Instance<M>) };
            inst.magic = 0;
            drop(inst);
        });
    }
}

/// # Safety
/// FMI 2.0 `fmi2SetDebugLogging`.
pub unsafe fn set_debug_logging<M: Model>(
    c: Fmi2Component,
    on: Fmi2Boolean,
    n: usize,
    categories: *const Fmi2String,
) -> Fmi2StatusRaw {
    with::<M>(c, "fmi2SetDebugLogging", |inst| {
        // SAFETY: FMI contract: n category strings.
        let Some(cats) = (unsafe { slice(categories, n) }) else {
            return null_argument(inst, "fmi2SetDebugLogging", "categories");
        };
        // SAFETY: each entry is a C string or null (null is refused below).
        let names: Option<Vec<String>> = cats
            .iter()
            .map(|s| unsafe { string(*s) }.map(str::to_owned))
            .collect();
        let Some(names) = names else {
            return null_argument(inst, "fmi2SetDebugLogging", "a category name");
        };
        inst.run("fmi2SetDebugLogging", |i| {
            i.set_debug_logging(on != 0, &names)
        })
    })
}

pub fn setup_experiment<M: Model>(
    c: Fmi2Component,
    tolerance_defined: Fmi2Boolean,
    tolerance: f64,
    start: f64,
    stop_defined: Fmi2Boolean,
    stop: f64,
) -> Fmi2StatusRaw {
    with::<M>(c, "fmi2SetupExperiment", |inst| {
        inst.run("fmi2SetupExperiment", |i| {
            i.setup_experiment(
                (tolerance_defined != 0).then_some(tolerance),
                start,
                (stop_defined != 0).then_some(stop),
            )
        })
    })
}

pub fn enter_initialization_mode<M: Model>(c: Fmi2Component) -> Fmi2StatusRaw {
    with::<M>(c, "fmi2EnterInitializationMode", |i| {
        i.run("fmi2EnterInitializationMode", |i| {
            i.enter_initialization_mode()
        })
    })
}

pub fn exit_initialization_mode<M: Model>(c: Fmi2Component) -> Fmi2StatusRaw {
    with::<M>(c, "fmi2ExitInitializationMode", |i| {
        i.run("fmi2ExitInitializationMode", |i| {
            i.exit_initialization_mode()
        })
    })
}

pub fn terminate<M: Model>(c: Fmi2Component) -> Fmi2StatusRaw {
    with::<M>(c, "fmi2Terminate", |i| {
        i.run("fmi2Terminate", |i| i.terminate())
    })
}

pub fn reset<M: Model>(c: Fmi2Component) -> Fmi2StatusRaw {
    with::<M>(c, "fmi2Reset", |i| i.run("fmi2Reset", |i| i.reset()))
}

macro_rules! getter {
    // Same type on both sides (Real, Integer): written straight into the caller's array, no
    // allocation per call (a master calls this every macro step).
    ($name:ident, $fmi:literal, $ty:ty, $method:ident) => {
        /// # Safety
        /// FMI 2.0 getter: `vr` and `value` point to `n` elements.
        pub unsafe fn $name<M: Model>(
            c: Fmi2Component,
            vr: *const Fmi2ValueReference,
            n: usize,
            value: *mut $ty,
        ) -> Fmi2StatusRaw {
            with::<M>(c, $fmi, |inst| {
                // SAFETY: FMI contract.
                let (Some(vrs), Some(out)) =
                    (unsafe { slice(vr, n) }, unsafe { slice_mut(value, n) })
                else {
                    return null_argument(inst, $fmi, "vr or value");
                };
                inst.run($fmi, |i| i.$method(vrs, out))
            })
        }
    };
    ($name:ident, $fmi:literal, $ty:ty, $method:ident, $conv:expr) => {
        /// # Safety
        /// FMI 2.0 getter: `vr` and `value` point to `n` elements.
        pub unsafe fn $name<M: Model>(
            c: Fmi2Component,
            vr: *const Fmi2ValueReference,
            n: usize,
            value: *mut $ty,
        ) -> Fmi2StatusRaw {
            with::<M>(c, $fmi, |inst| {
                // SAFETY: FMI contract.
                let (Some(vrs), Some(out)) =
                    (unsafe { slice(vr, n) }, unsafe { slice_mut(value, n) })
                else {
                    return null_argument(inst, $fmi, "vr or value");
                };
                let mut tmp = vec![Default::default(); n];
                let s = inst.run($fmi, |i| i.$method(vrs, &mut tmp));
                if s == Status::Ok {
                    for (o, t) in out.iter_mut().zip(tmp) {
                        *o = $conv(t);
                    }
                }
                s
            })
        }
    };
}

getter!(get_real, "fmi2GetReal", f64, get_real);
getter!(get_integer, "fmi2GetInteger", i32, get_integer);
getter!(
    get_boolean,
    "fmi2GetBoolean",
    Fmi2Boolean,
    get_boolean,
    |x: bool| x as Fmi2Boolean
);

/// # Safety
/// FMI 2.0 `fmi2GetString`.
pub unsafe fn get_string<M: Model>(
    c: Fmi2Component,
    vr: *const Fmi2ValueReference,
    n: usize,
    _value: *mut Fmi2String,
) -> Fmi2StatusRaw {
    with::<M>(c, "fmi2GetString", |inst| {
        // SAFETY: FMI contract.
        let Some(vrs) = (unsafe { slice(vr, n) }) else {
            return null_argument(inst, "fmi2GetString", "vr");
        };
        inst.run("fmi2GetString", |i| i.no_strings(vrs))
    })
}

/// # Safety
/// FMI 2.0 `fmi2SetString`.
pub unsafe fn set_string<M: Model>(
    c: Fmi2Component,
    vr: *const Fmi2ValueReference,
    n: usize,
    _value: *const Fmi2String,
) -> Fmi2StatusRaw {
    with::<M>(c, "fmi2SetString", |inst| {
        // SAFETY: FMI contract.
        let Some(vrs) = (unsafe { slice(vr, n) }) else {
            return null_argument(inst, "fmi2SetString", "vr");
        };
        inst.run("fmi2SetString", |i| i.no_strings(vrs))
    })
}

macro_rules! setter {
    // Same type on both sides (Real, Integer): no copy, no allocation per call.
    ($name:ident, $fmi:literal, $ty:ty, $method:ident) => {
        /// # Safety
        /// FMI 2.0 setter: `vr` and `value` point to `n` elements.
        pub unsafe fn $name<M: Model>(
            c: Fmi2Component,
            vr: *const Fmi2ValueReference,
            n: usize,
            value: *const $ty,
        ) -> Fmi2StatusRaw {
            with::<M>(c, $fmi, |inst| {
                // SAFETY: FMI contract.
                let (Some(vrs), Some(vals)) = (unsafe { slice(vr, n) }, unsafe { slice(value, n) })
                else {
                    return null_argument(inst, $fmi, "vr or value");
                };
                inst.run($fmi, |i| i.$method(vrs, vals))
            })
        }
    };
    ($name:ident, $fmi:literal, $ty:ty, $method:ident, $conv:expr) => {
        /// # Safety
        /// FMI 2.0 setter: `vr` and `value` point to `n` elements.
        pub unsafe fn $name<M: Model>(
            c: Fmi2Component,
            vr: *const Fmi2ValueReference,
            n: usize,
            value: *const $ty,
        ) -> Fmi2StatusRaw {
            with::<M>(c, $fmi, |inst| {
                // SAFETY: FMI contract.
                let (Some(vrs), Some(vals)) = (unsafe { slice(vr, n) }, unsafe { slice(value, n) })
                else {
                    return null_argument(inst, $fmi, "vr or value");
                };
                let vals: Vec<_> = vals.iter().map(|x| $conv(*x)).collect();
                inst.run($fmi, |i| i.$method(vrs, &vals))
            })
        }
    };
}

setter!(set_real, "fmi2SetReal", f64, set_real);
setter!(set_integer, "fmi2SetInteger", i32, set_integer);
setter!(
    set_boolean,
    "fmi2SetBoolean",
    Fmi2Boolean,
    set_boolean,
    |x: Fmi2Boolean| x != 0
);

/// An FMU state handed to the importer: a boxed core plus a magic to recognise it.
pub struct StateBox<M: Model> {
    magic: u64,
    core: Core<M>,
}

const STATE_MAGIC: u64 = 0x5354_4154_4531_4149; // "STATE1AI"

/// # Safety
/// `s` null or from `get_fmu_state::<M>`/`de_serialize_fmu_state::<M>` and not yet freed.
unsafe fn state_ref<'a, M: Model>(s: Fmi2FmuState) -> Option<&'a mut StateBox<M>> {
    if s.is_null() {
        return None;
    }
    // SAFETY: contract above.
    let b = unsafe { &mut *(s as *mut StateBox<M>) };
    (b.magic == STATE_MAGIC).then_some(b)
}

/// # Safety
/// FMI 2.0 `fmi2GetFMUstate`: `state` points to a (possibly non-null, then reused) state handle.
pub unsafe fn get_fmu_state<M: Model>(c: Fmi2Component, state: *mut Fmi2FmuState) -> Fmi2StatusRaw {
    with::<M>(c, "fmi2GetFMUstate", |inst| {
        if state.is_null() {
            return null_argument(inst, "fmi2GetFMUstate", "FMUstate");
        }
        inst.run("fmi2GetFMUstate", |i| {
            // SAFETY: FMI contract: *state is null or a state from this FMU, which we may overwrite.
            unsafe {
                match state_ref::<M>(*state) {
                    Some(existing) => i.snapshot_into(&mut existing.core),
                    None => {
                        let core = i.snapshot()?;
                        *state = Box::into_raw(Box::new(StateBox {
                            magic: STATE_MAGIC,
                            core,
                        })) as Fmi2FmuState;
                        Ok(Status::Ok)
                    }
                }
            }
        })
    })
}

/// # Safety
/// FMI 2.0 `fmi2SetFMUstate`.
pub unsafe fn set_fmu_state<M: Model>(c: Fmi2Component, state: Fmi2FmuState) -> Fmi2StatusRaw {
    with::<M>(c, "fmi2SetFMUstate", |inst| {
        // SAFETY: FMI contract.
        let Some(b) = (unsafe { state_ref::<M>(state) }) else {
            inst.logger.reject(
                Status::Error,
                "fmi2SetFMUstate",
                "FMUstate is null or not a state of this FMU",
            );
            return Status::Error;
        };
        inst.run("fmi2SetFMUstate", |i| i.restore(&b.core))
    })
}

/// # Safety
/// FMI 2.0 `fmi2FreeFMUstate`.
pub unsafe fn free_fmu_state<M: Model>(
    c: Fmi2Component,
    state: *mut Fmi2FmuState,
) -> Fmi2StatusRaw {
    with::<M>(c, "fmi2FreeFMUstate", |inst| {
        if state.is_null() {
            return null_argument(inst, "fmi2FreeFMUstate", "FMUstate");
        }
        // SAFETY: FMI contract; null *state is a no-op.
        unsafe {
            if (*state).is_null() {
                return Status::Ok;
            }
            if state_ref::<M>(*state).is_none() {
                inst.logger
                    .reject(Status::Error, "fmi2FreeFMUstate", "not a state of this FMU");
                return Status::Error;
            }
            let mut b = Box::from_raw(*state as *mut StateBox<M>);
            b.magic = 0;
            drop(b);
            *state = std::ptr::null_mut();
        }
        Status::Ok
    })
}

/// # Safety
/// FMI 2.0 `fmi2SerializedFMUstateSize`.
pub unsafe fn serialized_fmu_state_size<M: Model>(
    c: Fmi2Component,
    state: Fmi2FmuState,
    size: *mut usize,
) -> Fmi2StatusRaw {
    with::<M>(c, "fmi2SerializedFMUstateSize", |inst| {
        // SAFETY: FMI contract.
        let (Some(b), false) = (unsafe { state_ref::<M>(state) }, size.is_null()) else {
            return null_argument(inst, "fmi2SerializedFMUstateSize", "FMUstate or size");
        };
        // SAFETY: checked non-null.
        unsafe { *size = fmi_core::snapshot::serialize(&b.core, &inst.guid).len() };
        Status::Ok
    })
}

/// # Safety
/// FMI 2.0 `fmi2SerializeFMUstate`: `bytes` has room for `size` bytes.
pub unsafe fn serialize_fmu_state<M: Model>(
    c: Fmi2Component,
    state: Fmi2FmuState,
    bytes: *mut Fmi2Byte,
    size: usize,
) -> Fmi2StatusRaw {
    with::<M>(c, "fmi2SerializeFMUstate", |inst| {
        // SAFETY: FMI contract.
        let (Some(b), Some(out)) = (unsafe { state_ref::<M>(state) }, unsafe {
            slice_mut(bytes as *mut u8, size)
        }) else {
            return null_argument(inst, "fmi2SerializeFMUstate", "FMUstate or serializedState");
        };
        let blob = fmi_core::snapshot::serialize(&b.core, &inst.guid);
        if blob.len() != size {
            inst.logger.reject(
                Status::Error,
                "fmi2SerializeFMUstate",
                &format!(
                    "size {size} differs from fmi2SerializedFMUstateSize {}",
                    blob.len()
                ),
            );
            return Status::Error;
        }
        out.copy_from_slice(&blob);
        Status::Ok
    })
}

/// # Safety
/// FMI 2.0 `fmi2DeSerializeFMUstate`.
pub unsafe fn de_serialize_fmu_state<M: Model>(
    c: Fmi2Component,
    bytes: *const Fmi2Byte,
    size: usize,
    state: *mut Fmi2FmuState,
) -> Fmi2StatusRaw {
    with::<M>(c, "fmi2DeSerializeFMUstate", |inst| {
        // SAFETY: FMI contract.
        let (Some(data), false) = (unsafe { slice(bytes as *const u8, size) }, state.is_null())
        else {
            return null_argument(
                inst,
                "fmi2DeSerializeFMUstate",
                "serializedState or FMUstate",
            );
        };
        let shape = fmi_core::model::Store::from_info(&inst.info);
        match fmi_core::snapshot::deserialize::<M>(data, &inst.guid, &shape) {
            Ok(core) => {
                // SAFETY: FMI contract: *state is null or one of our states, which we may overwrite.
                unsafe {
                    match state_ref::<M>(*state) {
                        Some(existing) => existing.core = core,
                        None => {
                            *state = Box::into_raw(Box::new(StateBox {
                                magic: STATE_MAGIC,
                                core,
                            })) as Fmi2FmuState
                        }
                    }
                }
                Status::Ok
            }
            Err(e) => {
                inst.logger
                    .reject(Status::Error, "fmi2DeSerializeFMUstate", &e);
                Status::Error
            }
        }
    })
}

pub fn unsupported<M: Model>(c: Fmi2Component, function: &str, what: &str) -> Fmi2StatusRaw {
    with::<M>(c, function, |inst| {
        inst.logger.reject(Status::Error, function, what);
        Status::Error
    })
}

/// # Safety
/// FMI 2.0 `fmi2SetRealInputDerivatives`.
pub unsafe fn set_real_input_derivatives<M: Model>(
    c: Fmi2Component,
    vr: *const Fmi2ValueReference,
    n: usize,
    order: *const Fmi2Integer,
    value: *const f64,
) -> Fmi2StatusRaw {
    const F: &str = "fmi2SetRealInputDerivatives";
    with::<M>(c, F, |inst| {
        // SAFETY: FMI contract.
        let (Some(vrs), Some(ord), Some(vals)) = (
            unsafe { slice(vr, n) },
            unsafe { slice(order, n) },
            unsafe { slice(value, n) },
        ) else {
            return null_argument(inst, F, "vr, order or value");
        };
        inst.run(F, |i| i.set_input_derivatives(vrs, ord, vals))
    })
}

/// # Safety
/// FMI 2.0 `fmi2GetRealOutputDerivatives`.
pub unsafe fn get_real_output_derivatives<M: Model>(
    c: Fmi2Component,
    vr: *const Fmi2ValueReference,
    n: usize,
    order: *const Fmi2Integer,
    value: *mut f64,
) -> Fmi2StatusRaw {
    const F: &str = "fmi2GetRealOutputDerivatives";
    with::<M>(c, F, |inst| {
        // SAFETY: FMI contract.
        let (Some(vrs), Some(ord), Some(out)) = (
            unsafe { slice(vr, n) },
            unsafe { slice(order, n) },
            unsafe { slice_mut(value, n) },
        ) else {
            return null_argument(inst, F, "vr, order or value");
        };
        inst.run(F, |i| i.get_output_derivatives(vrs, ord, out))
    })
}

pub fn do_step<M: Model>(
    c: Fmi2Component,
    t: f64,
    h: f64,
    _no_set_prior: Fmi2Boolean,
) -> Fmi2StatusRaw {
    with::<M>(c, "fmi2DoStep", |i| {
        i.run("fmi2DoStep", |i| i.do_step(t, h))
    })
}

pub fn cancel_step<M: Model>(c: Fmi2Component) -> Fmi2StatusRaw {
    unsupported::<M>(
        c,
        "fmi2CancelStep",
        "no asynchronous step is ever in progress (canRunAsynchronuously=false)",
    )
}

/// The four typed status getters share their checks here.
fn status_query<M: Model, T>(
    c: Fmi2Component,
    function: &str,
    kind: Fmi2StatusKind,
    out: *mut T,
    answer: impl FnOnce(&Instance<M>, Fmi2StatusKind) -> Option<T>,
) -> Fmi2StatusRaw {
    with::<M>(c, function, |inst| {
        if out.is_null() {
            return null_argument(inst, function, "value");
        }
        inst.run(function, |i| {
            i.status_allowed()?;
            let v = answer(i, kind).ok_or((
                Status::Discard,
                format!("status kind {kind} is not available here"),
            ))?;
            // SAFETY: checked non-null; FMI contract: points to one element.
            unsafe { *out = v };
            Ok(Status::Ok)
        })
    })
}

pub fn get_status<M: Model>(
    c: Fmi2Component,
    kind: Fmi2StatusKind,
    out: *mut Fmi2StatusRaw,
) -> Fmi2StatusRaw {
    status_query::<M, Fmi2StatusRaw>(c, "fmi2GetStatus", kind, out, |i, k| {
        (k == FMI2_DO_STEP_STATUS).then_some(match i.core.phase {
            Phase::StepFailed => Status::Discard as c_int,
            Phase::Error => Status::Error as c_int,
            _ => Status::Ok as c_int,
        })
    })
}

pub fn get_real_status<M: Model>(
    c: Fmi2Component,
    kind: Fmi2StatusKind,
    out: *mut f64,
) -> Fmi2StatusRaw {
    status_query::<M, f64>(c, "fmi2GetRealStatus", kind, out, |i, k| {
        (k == FMI2_LAST_SUCCESSFUL_TIME).then_some(i.core.last_successful_time)
    })
}

pub fn get_integer_status<M: Model>(
    c: Fmi2Component,
    kind: Fmi2StatusKind,
    out: *mut Fmi2Integer,
) -> Fmi2StatusRaw {
    status_query::<M, Fmi2Integer>(c, "fmi2GetIntegerStatus", kind, out, |_, _| None)
}

pub fn get_boolean_status<M: Model>(
    c: Fmi2Component,
    kind: Fmi2StatusKind,
    out: *mut Fmi2Boolean,
) -> Fmi2StatusRaw {
    // fmi2Terminated: true when the slave wants to end the simulation; ours never do.
    status_query::<M, Fmi2Boolean>(c, "fmi2GetBooleanStatus", kind, out, |_, k| {
        (k == FMI2_TERMINATED).then_some(FMI2_FALSE)
    })
}

pub fn get_string_status<M: Model>(
    c: Fmi2Component,
    kind: Fmi2StatusKind,
    out: *mut Fmi2String,
) -> Fmi2StatusRaw {
    status_query::<M, Fmi2String>(c, "fmi2GetStringStatus", kind, out, |_, _| None)
}
