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
            // had been called with nCategories = 0; with loggingOn = false every category starts
            // off, so that a later fmi2SetDebugLogging(true, categories) turns on only those listed
            // (were all to start on, listing one category would leave all of them on).
            categories: categories.iter().map(|(n, _)| (*n, logging_on)).collect(),
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

    /// Logging on, and every category switched to `on(name)`: a wrapper with its own filter (the
    /// FMI 3.0 sink of crate `fmi3`) keeps this logger's categories equal to it, so that a model
    /// that asks [`Logger::enabled`] before it formats a debug message skips the ones the filter
    /// would drop. Warnings and errors are sent regardless, as always; the wrapper filters them.
    pub fn mirror(&mut self, on: impl Fn(&str) -> bool) {
        self.logging_on = true;
        for c in &mut self.categories {
            c.1 = on(c.0);
        }
    }

    /// Whether a debug message (status fmi2OK) in `category` would be sent.
    pub fn enabled(&self, category: &str) -> bool {
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

#[cfg(test)]
mod tests {
    use super::*;

    /// A debug category is on only while logging is on and it (or logAll) is switched on: what a
    /// model asks before it formats a message.
    #[test]
    fn a_category_is_enabled_only_while_logging_is_on_and_it_is_switched_on() {
        let cats = [
            ("logSteps", "steps"),
            ("logOther", "other"),
            ("logAll", "all"),
        ];
        let mut off = Logger::new(None, "x", false, &cats);
        assert!(!off.enabled("logSteps"));
        off.set_debug_logging(true, &["logSteps".to_string()]);
        assert!(off.enabled("logSteps"));
        assert!(!off.enabled("logOther"));
        off.set_debug_logging(false, &[]);
        assert!(!off.enabled("logSteps"));
        let mut on = Logger::new(None, "x", true, &cats);
        assert!(on.enabled("logSteps") && on.enabled("logOther"));
        on.set_debug_logging(false, &["logAll".to_string(), "logSteps".to_string()]);
        assert!(!on.enabled("logSteps"));
        // logOther is still on, but fmi2SetDebugLogging(false, ...) turned logging off.
        assert!(!on.enabled("logOther"));
        on.set_debug_logging(true, &["logAll".to_string()]);
        assert!(on.enabled("logSteps"), "logAll covers every category");
    }
}
