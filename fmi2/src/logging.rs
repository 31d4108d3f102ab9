//! The FMI 2.0 log sink: an instance's messages go to the importer's variadic
//! `fmi2CallbackLogger` with the format `"%s"` (so a `%` in a message is never interpreted).
//! Filtering (fmi2SetDebugLogging) is the FMI core's `Logger` with FMI 2.0's rules.

use crate::types::Fmi2CallbackFunctions;
use fmi_core::logging::{to_cstring, LogSink, Logger};
use fmi_core::{Standard, Status};
use std::ffi::c_char;

/// The importer's callbacks of fmi2Instantiate.
pub struct Fmi2Sink(Fmi2CallbackFunctions);

// SAFETY: the component environment pointer is opaque to us and only handed back to the
// importer's logger, on the thread that called into the FMU.
unsafe impl Send for Fmi2Sink {}

impl LogSink for Fmi2Sink {
    fn emit(&self, instance_name: &str, status: Status, category: &str, message: &str) {
        let Some(logger) = self.0.logger else { return };
        let name = to_cstring(instance_name);
        let category = to_cstring(category);
        let message = to_cstring(message);
        const FORMAT: &[u8] = b"%s\0";
        // SAFETY: the importer promised a valid logger in fmi2Instantiate; every pointer we pass is a
        // valid NUL-terminated string that outlives the call, and "%s" consumes exactly one argument.
        unsafe {
            logger(
                self.0.component_environment,
                name.as_ptr(),
                status as i32,
                category.as_ptr(),
                FORMAT.as_ptr() as *const c_char,
                message.as_ptr(),
            );
        }
    }
}

/// The logger of an instance named `instance_name`, sending to the importer's callbacks (if any).
pub fn logger(
    callbacks: Option<Fmi2CallbackFunctions>,
    instance_name: &str,
    logging_on: bool,
    categories: &[(&'static str, &'static str)],
) -> Logger {
    let sink = callbacks.map(|c| Box::new(Fmi2Sink(c)) as Box<dyn LogSink>);
    Logger::new(sink, Standard::Fmi2, instance_name, logging_on, categories)
}
