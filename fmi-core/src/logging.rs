//! An instance's logger, for either standard: the category filter of fmi2SetDebugLogging /
//! fmi3SetDebugLogging, and a [`LogSink`] each standard's glue implements over its importer's
//! callback (`fmi2`: the variadic `fmi2CallbackLogger` with the format `"%s"`; `fmi3`: the
//! `fmi3LogMessageCallback`).
//!
//! The standards filter differently (the logger's [`Standard`]):
//! - FMI 2.0: messages with status Warning or worse are always sent (a rejected call must say
//!   why); debug messages (status OK) only when logging is on and their category is enabled.
//! - FMI 3.0: a message goes out when its category, or `logAll`, is on, whatever its status;
//!   `loggingOn = false` at instantiation turns every category off, and fmi3SetDebugLogging
//!   switches the listed categories (all of them when none are listed).
//!
//! A model asks [`Logger::enabled`] before it formats a debug message (the film's and the rotor's
//! per-step solver statistics), and gets the answer of the filter that would send or drop it.

use crate::{Standard, Status};
use std::ffi::CString;

/// Where an instance's messages go: the importer's callback, in the words of one standard.
/// Called only for messages the [`Logger`]'s filter lets through.
pub trait LogSink: Send {
    fn emit(&self, instance_name: &str, status: Status, category: &str, message: &str);
}

pub struct Logger {
    sink: Option<Box<dyn LogSink>>,
    instance_name: String,
    standard: Standard,
    logging_on: bool,
    categories: Vec<(&'static str, bool)>,
}

impl Logger {
    /// A logger of `instance_name` that sends to `sink` (None: nowhere). Every category starts as
    /// `logging_on`: fmi2Instantiate(loggingOn = true) enables every category, as if
    /// fmi2SetDebugLogging had been called with nCategories = 0; with loggingOn = false every
    /// category starts off, so that a later SetDebugLogging(true, categories) turns on only
    /// those listed (were all to start on, listing one category would leave all of them on).
    pub fn new(
        sink: Option<Box<dyn LogSink>>,
        standard: Standard,
        instance_name: &str,
        logging_on: bool,
        categories: &[(&'static str, &'static str)],
    ) -> Logger {
        Logger {
            sink,
            instance_name: instance_name.to_owned(),
            standard,
            logging_on,
            categories: categories.iter().map(|(n, _)| (*n, logging_on)).collect(),
        }
    }

    /// The standard whose rules (and function names) the instance follows.
    pub fn standard(&self) -> Standard {
        self.standard
    }

    pub fn instance_name(&self) -> &str {
        &self.instance_name
    }

    /// fmi2SetDebugLogging / fmi3SetDebugLogging. Returns the names it did not know (the caller
    /// warns about them).
    pub fn set_debug_logging(&mut self, on: bool, names: &[String]) -> Vec<String> {
        if self.standard == Standard::Fmi2 {
            self.logging_on = on;
        }
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

    /// Whether a debug message (status OK) in `category` would be sent.
    pub fn enabled(&self, category: &str) -> bool {
        (self.logging_on || self.standard == Standard::Fmi3)
            && self
                .categories
                .iter()
                .any(|(n, on)| *on && (*n == category || *n == "logAll"))
    }

    /// Sends one message if the filter lets it through.
    pub fn log(&self, status: Status, category: &str, message: &str) {
        let filtered = status == Status::Ok || self.standard == Standard::Fmi3;
        if filtered && !self.enabled(category) {
            return;
        }
        if let Some(sink) = &self.sink {
            sink.emit(&self.instance_name, status, category, message);
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
        let mut off = Logger::new(None, Standard::Fmi2, "x", false, &cats);
        assert!(!off.enabled("logSteps"));
        off.set_debug_logging(true, &["logSteps".to_string()]);
        assert!(off.enabled("logSteps"));
        assert!(!off.enabled("logOther"));
        off.set_debug_logging(false, &[]);
        assert!(!off.enabled("logSteps"));
        let mut on = Logger::new(None, Standard::Fmi2, "x", true, &cats);
        assert!(on.enabled("logSteps") && on.enabled("logOther"));
        on.set_debug_logging(false, &["logAll".to_string(), "logSteps".to_string()]);
        assert!(!on.enabled("logSteps"));
        // logOther is still on, but fmi2SetDebugLogging(false, ...) turned logging off.
        assert!(!on.enabled("logOther"));
        on.set_debug_logging(true, &["logAll".to_string()]);
        assert!(on.enabled("logSteps"), "logAll covers every category");
    }

    /// Records what reaches the importer.
    struct Book(std::sync::Arc<std::sync::Mutex<Vec<(Status, String)>>>);

    impl LogSink for Book {
        fn emit(&self, _name: &str, status: Status, category: &str, message: &str) {
            let line = format!("{category}: {message}");
            self.0.lock().unwrap().push((status, line));
        }
    }

    /// FMI 2.0 sends warnings and errors whatever the categories; FMI 3.0 sends a message only
    /// when its category (or logAll) is on, and its SetDebugLogging switches categories, not a
    /// global switch.
    #[test]
    fn each_standard_filters_by_its_own_rules() {
        let cats = [
            ("logStatusWarning", "w"),
            ("logSteps", "steps"),
            ("logAll", "all"),
        ];
        let book = || std::sync::Arc::new(std::sync::Mutex::new(Vec::new()));
        let (b2, b3) = (book(), book());
        let l2 = Logger::new(
            Some(Box::new(Book(b2.clone()))),
            Standard::Fmi2,
            "a",
            false,
            &cats,
        );
        let mut l3 = Logger::new(
            Some(Box::new(Book(b3.clone()))),
            Standard::Fmi3,
            "a",
            false,
            &cats,
        );
        for l in [&l2, &l3] {
            l.log(Status::Warning, "logStatusWarning", "w1");
            l.log(Status::Ok, "logSteps", "d1");
        }
        assert_eq!(b2.lock().unwrap().len(), 1, "FMI 2.0 always sends warnings");
        assert!(b3.lock().unwrap().is_empty(), "FMI 3.0: every category off");
        assert_eq!(
            l3.set_debug_logging(true, &["logSteps".into(), "x".into()]),
            ["x"]
        );
        l3.log(Status::Warning, "logStatusWarning", "w2");
        l3.log(Status::Ok, "logSteps", "d2");
        assert_eq!(
            *b3.lock().unwrap(),
            [(Status::Ok, "logSteps: d2".to_string())]
        );
        // Switching one category off leaves the others as they are (no global switch).
        l3.set_debug_logging(true, &["logStatusWarning".into()]);
        l3.set_debug_logging(false, &["logStatusWarning".into()]);
        assert!(l3.enabled("logSteps") && !l3.enabled("logStatusWarning"));
        l3.reject(Status::Error, "fmi3DoStep", "no");
        assert_eq!(b3.lock().unwrap().len(), 1, "logStatusError is off");
    }
}
