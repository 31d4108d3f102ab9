//! Version, instantiation, freeing, debug logging and the state transitions of the instance.

use super::{null_argument, slice, string, with};
use crate::instance::{Instance, Shell};
use crate::logging::{all_log_categories, log_without_instance};
use crate::state;
use crate::types::*;
use fmi_core::model::Model;
use fmi_core::Status;
use std::ffi::c_char;
use std::panic::{catch_unwind, AssertUnwindSafe};
use std::path::PathBuf;

pub fn version() -> *const c_char {
    VERSION.as_ptr() as *const c_char
}

/// # Safety
/// Arguments as in FMI 3.0 `fmi3InstantiateCoSimulation`.
pub unsafe fn instantiate_co_simulation<M: Model>(
    instance_name: fmi3String,
    instantiation_token: fmi3String,
    resource_path: fmi3String,
    logging_on: fmi3Boolean,
    event_mode_used: fmi3Boolean,
    early_return_allowed: fmi3Boolean,
    required_intermediate_variables: *const fmi3ValueReference,
    n_required_intermediate_variables: usize,
    instance_environment: fmi3InstanceEnvironment,
    log_message: fmi3LogMessageCallback,
    intermediate_update: fmi3IntermediateUpdateCallback,
) -> fmi3Instance {
    const F: &str = "fmi3InstantiateCoSimulation";
    let result = catch_unwind(AssertUnwindSafe(|| {
        let refuse = |reason: &str| {
            // SAFETY: the importer's callback and environment, as given to this call.
            unsafe {
                log_without_instance(log_message, instance_environment, logging_on, F, reason)
            };
            std::ptr::null_mut()
        };
        // SAFETY: FMI contract: NUL-terminated strings or null.
        let (name, token, resources) = unsafe {
            (
                string(instance_name),
                string(instantiation_token),
                string(resource_path),
            )
        };
        let Some(name) = name else {
            return refuse("instanceName is null or not UTF-8");
        };
        let Some(token) = token else {
            return refuse("instantiationToken is null or not UTF-8");
        };
        // FMI 3.0 section 2.3.1: eventModeUsed may be true only if hasEventMode = true.
        if event_mode_used {
            return refuse(
                "eventModeUsed = true, but this FMU has no Event Mode (hasEventMode=\"false\")",
            );
        }
        let info = M::info();
        // Only variables with intermediateUpdate="true" may be required: the Float64 inputs.
        // SAFETY: FMI contract: an array of n_required_intermediate_variables value references.
        let Some(required) = (unsafe {
            slice(
                required_intermediate_variables,
                n_required_intermediate_variables,
            )
        }) else {
            return refuse("requiredIntermediateVariables is null");
        };
        if let Some(vr) = required
            .iter()
            .find(|vr| !crate::value_refs::is_float64_input(&info, **vr))
        {
            return refuse(&format!(
                "requiredIntermediateVariables: value reference {vr} is not a Float64 input (only those have intermediateUpdate=\"true\")"
            ));
        }
        if let Err(e) = crate::value_refs::check(&info) {
            return refuse(&format!(
                "the model's variable table does not fit FMI 3.0: {e}"
            ));
        }
        let logger = crate::logging::logger(
            log_message,
            instance_environment,
            name,
            logging_on,
            &all_log_categories(&info),
        );
        // FMI 3.0 passes a native path, and an absolute one (section 2.3.1).
        let resources = match resources.filter(|p| !p.is_empty()) {
            None => Ok(None),
            Some(p) if std::path::Path::new(p).is_absolute() => Ok(Some(PathBuf::from(p))),
            Some(p) => Err(format!("resource path '{p}' is not absolute")),
        };
        match fmi_core::instance::Instance::<M>::new(name, token, resources, logger) {
            Ok(inner) => Box::into_raw(Box::new(Shell::new(
                Instance::new(inner),
                early_return_allowed,
                intermediate_update,
                instance_environment,
            ))) as fmi3Instance,
            Err((logger, reason)) => {
                logger.reject(Status::Error, F, &reason);
                std::ptr::null_mut()
            }
        }
    }));
    result.unwrap_or(std::ptr::null_mut())
}

/// fmi3InstantiateModelExchange / fmi3InstantiateScheduledExecution: refused with a log line.
///
/// # Safety
/// `instance_environment` and `log_message` as the importer passed them.
pub unsafe fn refuse_instantiation(
    function: &str,
    logging_on: fmi3Boolean,
    instance_environment: fmi3InstanceEnvironment,
    log_message: fmi3LogMessageCallback,
) -> fmi3Instance {
    let _ = catch_unwind(AssertUnwindSafe(|| {
        // SAFETY: the importer's callback and environment, as given to this call.
        unsafe {
            log_without_instance(
                log_message,
                instance_environment,
                logging_on,
                function,
                "this FMU supports Co-Simulation only",
            )
        }
    }));
    std::ptr::null_mut()
}

/// # Safety
/// `c` null or from `instantiate_co_simulation::<M>`; it is invalid afterwards.
pub unsafe fn free_instance<M: Model>(c: fmi3Instance) {
    // SAFETY: contract above.
    match unsafe { super::shell::<M>(c) } {
        // Freeing from inside an intermediateUpdate callback would free the stepping model.
        Some(shell) if shell.stepping.get() => {
            super::refuse_while_stepping(
                shell,
                "fmi3FreeInstance",
                "not allowed in an intermediateUpdate callback",
            );
        }
        Some(_) => {
            let _ = catch_unwind(|| {
                // SAFETY: created by Box::into_raw in `instantiate_co_simulation`; clearing the magic
                // makes a second free of the same (not yet reused) memory a detected no-op, not a
                // double free.
                let mut shell = unsafe { Box::from_raw(c as *mut Shell<M>) };
                shell.magic = 0;
                drop(shell);
            });
        }
        None => {}
    }
}

/// # Safety
/// FMI 3.0 `fmi3SetDebugLogging`: `categories` holds `n` strings.
pub unsafe fn set_debug_logging<M: Model>(
    c: fmi3Instance,
    logging_on: fmi3Boolean,
    n: usize,
    categories: *const fmi3String,
) -> fmi3Status {
    const F: &str = "fmi3SetDebugLogging";
    with::<M>(c, F, |inst| {
        // SAFETY: FMI contract: n category strings.
        let Some(cats) = (unsafe { slice(categories, n) }) else {
            return null_argument(inst, F, "categories");
        };
        // SAFETY: each entry is a C string or null (null is refused below).
        let names: Option<Vec<String>> = cats
            .iter()
            .map(|s| unsafe { string(*s) }.map(str::to_owned))
            .collect();
        let Some(names) = names else {
            return null_argument(inst, F, "a category name");
        };
        // The core instance's call: the FMI 3.0 logger switches the listed categories and
        // warns about names it does not know, as the FMI 2.0 one does.
        inst.run(F, state::MASK_SET_DEBUG_LOGGING, |i| {
            i.inner.set_debug_logging(logging_on, &names)
        })
    })
}

pub fn enter_initialization_mode<M: Model>(
    c: fmi3Instance,
    tolerance_defined: fmi3Boolean,
    tolerance: f64,
    start_time_s: f64,
    stop_time_defined: fmi3Boolean,
    stop_time_s: f64,
) -> fmi3Status {
    const F: &str = "fmi3EnterInitializationMode";
    with::<M>(c, F, |inst| {
        inst.run(F, state::MASK_ENTER_INITIALIZATION_MODE, |i| {
            // FMI 2.0's fmi2SetupExperiment is folded into this call in FMI 3.0.
            i.inner.setup_experiment(
                tolerance_defined.then_some(tolerance),
                start_time_s,
                stop_time_defined.then_some(stop_time_s),
            )?;
            i.inner.enter_initialization_mode()
        })
    })
}

pub fn exit_initialization_mode<M: Model>(c: fmi3Instance) -> fmi3Status {
    const F: &str = "fmi3ExitInitializationMode";
    with::<M>(c, F, |inst| {
        inst.run(F, state::MASK_EXIT_INITIALIZATION_MODE, |i| {
            i.inner.exit_initialization_mode()
        })
    })
}

pub fn terminate<M: Model>(c: fmi3Instance) -> fmi3Status {
    const F: &str = "fmi3Terminate";
    with::<M>(c, F, |inst| {
        inst.run(F, state::MASK_TERMINATE, |i| i.inner.terminate())
    })
}

pub fn reset<M: Model>(c: fmi3Instance) -> fmi3Status {
    const F: &str = "fmi3Reset";
    with::<M>(c, F, |inst| {
        inst.run(F, state::MASK_RESET, |i| i.inner.reset())
    })
}
