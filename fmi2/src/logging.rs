//! The instance's logger: forwards messages to the importer's variadic `fmi2CallbackLogger` with the
//! format `"%s"` (so a `%` in a message is never interpreted), honouring fmi2SetDebugLogging.
//!
//! Policy: messages with status fmi2Warning or worse are always sent (a rejected call must say why);
//! debug messages (status fmi2OK) are sent only when logging is on and their category is enabled.

use crate::types::{Fmi2CallbackFunctions, Status};
use std::ffi::{c_char, CString};

pub struct Logger {
    callbacks: Option<Fmi2CallbackFunctions>,
    instance_name: CString,
    logging_on: bool,
    categories: Vec<(&'static str, bool)>,
}

// The component environment pointer is opaque to us and only handed back to the importer's logger.
unsafe impl Send for Logger {}

impl Logger {
    pub fn new(
        callbacks: Option<Fmi2CallbackFunctions>,
        instance_name: &str,
        logging_on: bool,
        categories: &[(&'static str, &'static str)],
    ) -> Logger {
        Logger {
            callbacks,
            instance_name: to_cstring(instance_name),
            logging_on,
            // fmi2Instantiate(loggingOn = true) enables every category, as if fmi2SetDebugLogging
            // had been called with nCategories = 0.
            categories: categories.iter().map(|(n, _)| (*n, true)).collect(),
        }
    }

    pub fn instance_name(&self) -> &str {
        self.instance_name.to_str().unwrap_or("?")
    }

    /// fmi2SetDebugLogging. Returns the names it did not know (the caller warns about them).
    pub fn set_debug_logging(&mut self, on: bool, names: &[String]) -> Vec<String> {
        self.logging_on = on;
        let mut unknown = Vec::new();
        if names.is_empty() {
            for c in &mut self.categories {
                c.1 = on;
            }
        } else {
            for n in names {
                match self.categories.iter_mut().find(|c| c.0 == n) {
                    Some(c) => c.1 = on,
                    None => unknown.push(n.clone()),
                }
            }
        }
        unknown
    }

    fn enabled(&self, category: &str) -> bool {
        self.logging_on
            && self
                .categories
                .iter()
                .any(|(n, on)| *on && (*n == category || *n == "logAll"))
    }

    /// Sends one message. Statuses of fmi2Warning and worse are always sent.
    pub fn log(&self, status: Status, category: &str, message: &str) {
        if status == Status::Ok && !self.enabled(category) {
            return;
        }
        let Some(cb) = self.callbacks else { return };
        let Some(logger) = cb.logger else { return };
        let category = to_cstring(category);
        let message = to_cstring(message);
        const FORMAT: &[u8] = b"%s\0";
        // SAFETY: the importer promised a valid logger in fmi2Instantiate; every pointer we pass is a
        // valid NUL-terminated string that outlives the call, and "%s" consumes exactly one argument.
        unsafe {
            logger(
                cb.component_environment,
                self.instance_name.as_ptr(),
                status as i32,
                category.as_ptr(),
                FORMAT.as_ptr() as *const c_char,
                message.as_ptr(),
            );
        }
    }

    /// Logs a rejected call with its reason under the category matching `status`.
    pub fn reject(&self, status: Status, function: &str, reason: &str) {
        let category = status_category(status);
        self.log(status, category, &format!("{function}: {reason}"));
    }
}

pub fn status_category(status: Status) -> &'static str {
    match status {
        Status::Warning => "logStatusWarning",
        Status::Discard => "logStatusDiscard",
        Status::Error => "logStatusError",
        Status::Fatal => "logStatusFatal",
        _ => "logAll",
    }
}

/// A C string from any Rust string: interior NULs (which C cannot carry) become spaces.
pub fn to_cstring(s: &str) -> CString {
    CString::new(s.replace('\0', " ")).expect("NULs were replaced")
}
