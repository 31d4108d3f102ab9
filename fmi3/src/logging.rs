//! FMI 3.0 logging: an instance's messages go to the importer's `fmi3LogMessageCallback`.
//!
//! The filter is the FMI core's `Logger` with FMI 3.0's rules (`fmi_core::Standard::Fmi3`): a
//! message goes out when its category, or `logAll`, is on, whatever its status; `loggingOn =
//! false` at instantiation turns every category off and the callback is never called;
//! fmi3SetDebugLogging switches the listed categories (all of them when none are listed). A model
//! that asks whether a debug category is on before it formats a message (the film's and the
//! rotor's per-step solver statistics) gets the filter's answer.

use crate::types::*;
use fmi_core::logging::{to_cstring, LogSink, Logger};
use fmi_core::variables::ModelInfo;
use fmi_core::{Standard, Status};

/// The log categories of every AirRing FMU (same names as fmi2's, FMI 3.0 wording).
pub const STANDARD_LOG_CATEGORIES: &[(&str, &str)] = &[
    ("logEvents", "Log events"),
    ("logStatusWarning", "Log messages with status fmi3Warning"),
    ("logStatusDiscard", "Log messages with status fmi3Discard"),
    ("logStatusError", "Log messages with status fmi3Error"),
    ("logStatusFatal", "Log messages with status fmi3Fatal"),
    ("logAll", "Log all messages"),
];

/// All categories of a model: the standard ones, then the model's own.
pub fn all_log_categories(info: &ModelInfo) -> Vec<(&'static str, &'static str)> {
    let mut all = STANDARD_LOG_CATEGORIES.to_vec();
    all.extend(info.log_categories.iter().copied());
    all
}

/// The importer's callback and environment of fmi3InstantiateCoSimulation.
struct Fmi3Sink {
    callback: fmi3LogMessageCallback,
    environment: fmi3InstanceEnvironment,
}

// SAFETY: the environment pointer is opaque to us and only handed back to the importer's
// callback, on the thread that called into the FMU (FMI 3.0: one call at a time per instance).
unsafe impl Send for Fmi3Sink {}

impl LogSink for Fmi3Sink {
    fn emit(&self, _instance_name: &str, status: Status, category: &str, message: &str) {
        // FMI 3.0 messages carry no instance name: the environment identifies the instance.
        let Some(callback) = self.callback else {
            return;
        };
        // Statuses 0..=4 are the fmi3 ones; FMI 2.0's Pending (5) has none and is never logged.
        let status = match status as i32 {
            s @ FMI3_OK..=FMI3_FATAL => s,
            _ => FMI3_ERROR,
        };
        let category = to_cstring(category);
        let message = to_cstring(message);
        // SAFETY: the importer gave this callback and environment at instantiation; the strings
        // live until we return.
        unsafe {
            callback(
                self.environment,
                status,
                category.as_ptr(),
                message.as_ptr(),
            )
        };
    }
}

/// The logger of an instance, with FMI 3.0's filter, sending to the importer's callback.
pub fn logger(
    callback: fmi3LogMessageCallback,
    environment: fmi3InstanceEnvironment,
    instance_name: &str,
    logging_on: bool,
    categories: &[(&'static str, &'static str)],
) -> Logger {
    let sink = Fmi3Sink {
        callback,
        environment,
    };
    Logger::new(
        Some(Box::new(sink)),
        Standard::Fmi3,
        instance_name,
        logging_on,
        categories,
    )
}

/// One message before an instance exists (refused instantiation), honouring `loggingOn`.
///
/// # Safety
/// `callback` and `environment` as the importer passed them to an fmi3Instantiate* function.
pub unsafe fn log_without_instance(
    callback: fmi3LogMessageCallback,
    environment: fmi3InstanceEnvironment,
    logging_on: bool,
    function: &str,
    reason: &str,
) {
    let Some(callback) = callback else { return };
    if !logging_on {
        return;
    }
    let message = to_cstring(&format!("{function}: {reason}"));
    // SAFETY: the importer's callback with its own environment; both strings live until we return.
    unsafe {
        callback(
            environment,
            FMI3_ERROR,
            c"logStatusError".as_ptr(),
            message.as_ptr(),
        )
    };
}
