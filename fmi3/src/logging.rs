//! FMI 3.0 logging for an fmi2 instance.
//!
//! The fmi2 instance (and the model through it) logs to an `fmi2CallbackLogger`, which is C-variadic.
//! We give it `airring_fmi3_log_bridge` (src/log_bridge.c) as that logger and a `LogSink` as its
//! component environment; the bridge formats the message and calls `LogSink::forward`, which
//! filters by category and calls the importer's `fmi3LogMessageCallback`.
//!
//! Filtering follows FMI 3.0, not fmi2's policy (which always sends warnings and errors):
//! `loggingOn = false` at instantiation turns every category off and the callback is never called;
//! fmi3SetDebugLogging switches the listed categories (all of them when none are listed). A message
//! goes out when its category, or `logAll`, is on. The fmi2 logger is created with logging on and
//! its categories follow the sink's (`Sink::mirror_into`, after instantiation and after every
//! fmi3SetDebugLogging): a model that asks whether a debug category is on before it formats a
//! message (the film's and the rotor's per-step solver statistics) gets the sink's answer; with
//! every category left on, an FMI 3.0 FMU would format them at every step for the sink to drop.
//! Warnings and errors always reach the sink, and this one policy decides.

use crate::types::*;
use fmi2::types::Fmi2CallbackFunctions;
use std::cell::Cell;
use std::ffi::{c_char, c_int, c_void, CStr};
use std::panic::{catch_unwind, AssertUnwindSafe};
use std::ptr::NonNull;

extern "C" {
    /// The variadic fmi2 logger of src/log_bridge.c.
    fn airring_fmi3_log_bridge(
        environment: *mut c_void,
        instance_name: *const c_char,
        status: c_int,
        category: *const c_char,
        format: *const c_char,
        ...
    );
}

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
pub fn all_log_categories(info: &fmi2::ModelInfo) -> Vec<(&'static str, &'static str)> {
    let mut all = STANDARD_LOG_CATEGORIES.to_vec();
    all.extend(info.log_categories.iter().copied());
    all
}

/// Shared with C: `forward` must stay the first field (the bridge reads only that).
#[repr(C)]
struct LogSink {
    forward: unsafe extern "C" fn(*const LogSink, c_int, *const c_char, *const c_char),
    callback: fmi3LogMessageCallback,
    environment: fmi3InstanceEnvironment,
    /// Category name and whether it is on; `Cell` because the bridge holds a shared pointer.
    categories: Vec<(&'static str, Cell<bool>)>,
}

impl LogSink {
    fn enabled(&self, category: &str) -> bool {
        self.categories
            .iter()
            .any(|(n, on)| on.get() && (*n == category || *n == "logAll"))
    }
}

/// Called by the C bridge with a formatted message.
///
/// # Safety
/// `sink` points to a live `LogSink`; `category` and `message` are NUL-terminated strings.
unsafe extern "C" fn forward(
    sink: *const LogSink,
    status: c_int,
    category: *const c_char,
    message: *const c_char,
) {
    // Nothing may unwind into the C bridge.
    let _ = catch_unwind(AssertUnwindSafe(|| {
        // SAFETY: per the contract above; the sink outlives the fmi2 logger that calls us.
        let sink = unsafe { &*sink };
        let Some(callback) = sink.callback else {
            return;
        };
        // SAFETY: the fmi2 logger passes NUL-terminated strings (or null for a missing category).
        let name = (!category.is_null())
            .then(|| unsafe { CStr::from_ptr(category) }.to_str().ok())
            .flatten()
            .unwrap_or("logAll");
        if !sink.enabled(name) {
            return;
        }
        // fmi2 statuses 0..=4 are the fmi3 ones; fmi2Pending (5) is never logged.
        let status = if (FMI3_OK..=FMI3_FATAL).contains(&status) {
            status
        } else {
            FMI3_ERROR
        };
        // SAFETY: the importer gave this callback and environment at instantiation; the strings
        // live until we return.
        unsafe { callback(sink.environment, status, category, message) };
    }));
}

/// Owner of a `LogSink` at a fixed address (the fmi2 logger keeps a raw pointer to it). Only shared
/// references to the sink are ever made, so the raw pointer stays valid until `Drop`.
pub struct Sink(NonNull<LogSink>);

impl Sink {
    pub fn new(
        callback: fmi3LogMessageCallback,
        environment: fmi3InstanceEnvironment,
        logging_on: bool,
        categories: &[(&'static str, &'static str)],
    ) -> Sink {
        let sink = Box::new(LogSink {
            forward,
            callback,
            environment,
            categories: categories
                .iter()
                .map(|(n, _)| (*n, Cell::new(logging_on)))
                .collect(),
        });
        Sink(NonNull::from(Box::leak(sink)))
    }

    fn get(&self) -> &LogSink {
        // SAFETY: allocated in `new`, freed only in `drop`; never mutably borrowed.
        unsafe { self.0.as_ref() }
    }

    /// The callback set for `fmi2::instance::Instance::new`: its logger is the C bridge, its
    /// environment this sink. The instance must not outlive the sink.
    pub fn fmi2_callbacks(&self) -> Fmi2CallbackFunctions {
        Fmi2CallbackFunctions {
            logger: Some(airring_fmi3_log_bridge),
            // Unused by the fmi2 instance (canNotUseMemoryManagementFunctions).
            allocate_memory: None,
            free_memory: None,
            step_finished: None,
            component_environment: self.0.as_ptr() as *mut c_void,
        }
    }

    /// Whether a message in `category` goes out to the importer.
    pub fn enabled(&self, category: &str) -> bool {
        self.get().enabled(category)
    }

    /// Switches the fmi2 logger's categories to this sink's filter (see the module's header).
    pub fn mirror_into(&self, logger: &mut fmi2::logging::Logger) {
        logger.mirror(|category| self.enabled(category));
    }

    /// fmi3SetDebugLogging: switches the named categories (all with no names). Returns the names it
    /// does not know.
    pub fn set_debug_logging(&self, on: bool, names: &[String]) -> Vec<String> {
        let cats = &self.get().categories;
        if names.is_empty() {
            cats.iter().for_each(|(_, c)| c.set(on));
            return Vec::new();
        }
        let mut unknown = Vec::new();
        for n in names {
            match cats.iter().find(|(c, _)| c == n) {
                Some((_, c)) => c.set(on),
                None => unknown.push(n.clone()),
            }
        }
        unknown
    }
}

impl Drop for Sink {
    fn drop(&mut self) {
        // SAFETY: from Box::leak in `new`; the owner drops the fmi2 instance (the only other user of
        // the pointer) first.
        drop(unsafe { Box::from_raw(self.0.as_ptr()) });
    }
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
    let message = fmi2::logging::to_cstring(&format!("{function}: {reason}"));
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
