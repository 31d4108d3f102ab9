//! The FMI core both standards' importers share: a co-simulation master drives an FMU of either
//! version through [`CoSimSlave`], and reads what went wrong as a [`CallError`] with a
//! version-neutral [`Status`]. `fmi2::importer::Slave` and `fmi3::importer::Slave` implement the
//! trait; the master (`cosim`) holds a `Box<dyn CoSimSlave>` and knows no version (it reads the
//! version only to choose the importer that loads an FMU).
//!
//! FMI 2.0 and 3.0 number their statuses alike (OK 0, Warning 1, Discard 2, Error 3, Fatal 4;
//! FMI 2.0 adds Pending 5), so one [`Status::from_raw`] serves both; a message names the status
//! in the words of the standard the failed function belongs to ("fmi3DoStep returned
//! fmi3Discard"). The exporters (`fmi2`, `fmi3`) return the same `Status`.
//!
//! The exporters' shared description of a model lives here too: `variables` (the variable table,
//! the single source of truth of an interface: value references, causality, units, start values,
//! the GUID) and `units` (display units, values in them, a refused parameter in its units);
//! each standard's modelDescription.xml is written from it by `fmi2::xml` and `fmi3::xml`.

#[cfg(feature = "archive")]
pub mod archive;
pub mod description;
pub mod instance;
pub mod logging;
pub mod model;
pub mod snapshot;
pub mod states;
pub mod units;
pub mod variables;
pub mod xml;

use std::any::Any;

/// The outcome of an FMI call, either version; the discriminants are the C values of both
/// standards (`fmi2Status`, `fmi3Status`), so an exporter returns `status as i32`.
#[repr(i32)]
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum Status {
    Ok = 0,
    Warning = 1,
    Discard = 2,
    Error = 3,
    Fatal = 4,
    /// FMI 2.0's asynchronous step in progress (FMI 3.0 has none).
    Pending = 5,
}

impl Status {
    /// The status of a C call's return value; None for a value no standard defines.
    pub fn from_raw(raw: i32) -> Option<Status> {
        Some(match raw {
            0 => Status::Ok,
            1 => Status::Warning,
            2 => Status::Discard,
            3 => Status::Error,
            4 => Status::Fatal,
            5 => Status::Pending,
            _ => return None,
        })
    }

    /// The status's name without the standard's prefix ("OK", "Discard", ...).
    pub fn name(self) -> &'static str {
        match self {
            Status::Ok => "OK",
            Status::Warning => "Warning",
            Status::Discard => "Discard",
            Status::Error => "Error",
            Status::Fatal => "Fatal",
            Status::Pending => "Pending",
        }
    }
}

/// The standard an exported instance answers in: its logging rules and the names of its
/// functions in messages.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Standard {
    Fmi2,
    Fmi3,
}

impl Standard {
    /// The function that instantiates a co-simulation FMU.
    pub fn instantiate(self) -> &'static str {
        match self {
            Standard::Fmi2 => "fmi2Instantiate",
            Standard::Fmi3 => "fmi3InstantiateCoSimulation",
        }
    }

    /// The function that gives the start and stop time and the tolerance.
    pub fn setup_experiment(self) -> &'static str {
        match self {
            Standard::Fmi2 => "fmi2SetupExperiment",
            Standard::Fmi3 => "fmi3EnterInitializationMode",
        }
    }

    /// The function that resets an instance.
    pub fn reset(self) -> &'static str {
        match self {
            Standard::Fmi2 => "fmi2Reset",
            Standard::Fmi3 => "fmi3Reset",
        }
    }
}

/// A non-OK status from an FMI call (a Warning is treated as success and only logged).
#[derive(Clone, Debug, PartialEq)]
pub struct CallError {
    /// The C function, with its standard's prefix (`fmi2DoStep`, `fmi3GetFloat64`).
    pub function: &'static str,
    pub status: Status,
}

impl CallError {
    /// The standard's prefix of the function ("fmi2", "fmi3"), "fmi2" for names without one.
    fn prefix(&self) -> &'static str {
        if self.function.starts_with("fmi3") {
            "fmi3"
        } else {
            "fmi2"
        }
    }
}

impl std::fmt::Display for CallError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "{} returned {}{}",
            self.function,
            self.prefix(),
            self.status.name()
        )
    }
}

impl std::error::Error for CallError {}

/// A raw status as a result: Ok and Warning succeed, every other value (or one no standard
/// defines: Fatal) is the error of `function`.
pub fn check(function: &'static str, raw: i32) -> Result<(), CallError> {
    match Status::from_raw(raw) {
        Some(Status::Ok | Status::Warning) => Ok(()),
        Some(status) => Err(CallError { function, status }),
        None => Err(CallError {
            function,
            status: Status::Fatal,
        }),
    }
}

/// One message an FMU logged.
#[derive(Clone, Debug)]
pub struct LogRecord {
    pub instance: String,
    pub status: Status,
    /// The standard of the FMU that logged it ("fmi2", "fmi3"): the prefix of the status's C
    /// name (`fmi2Warning`, `fmi3Warning`).
    pub standard: &'static str,
    pub category: String,
    pub message: String,
}

/// Receives every message the FMU logs (called on the thread that called into the FMU).
pub type LogHandler = std::sync::Arc<dyn Fn(&LogRecord) + Send + Sync>;

/// A C string from an FMU as owned text (lossy UTF-8; empty for null). Both importers
/// read their FMUs' log messages with it.
///
/// # Safety
/// `s` is null or NUL-terminated.
pub unsafe fn lossy(s: *const std::ffi::c_char) -> String {
    if s.is_null() {
        String::new()
    } else {
        // SAFETY: FMU passes NUL-terminated strings.
        unsafe { std::ffi::CStr::from_ptr(s) }
            .to_string_lossy()
            .into_owned()
    }
}

/// An FMU state saved by a slave, opaque to the master: each importer keeps its own kind inside.
/// Handing a state to a slave of another kind (another version) is a call error, not a crash.
pub struct SavedState(Box<dyn Any + Send>);

impl SavedState {
    pub fn new<T: Any + Send>(state: T) -> Self {
        SavedState(Box::new(state))
    }

    /// The importer's own state, or the error of `function` if this is another kind's.
    pub fn get<T: Any>(&self, function: &'static str) -> Result<&T, CallError> {
        self.0.downcast_ref::<T>().ok_or(CallError {
            function,
            status: Status::Error,
        })
    }

    /// As [`SavedState::get`], to update in place.
    pub fn get_mut<T: Any>(&mut self, function: &'static str) -> Result<&mut T, CallError> {
        self.0.downcast_mut::<T>().ok_or(CallError {
            function,
            status: Status::Error,
        })
    }
}

/// One instance of a co-simulation FMU, of either standard, as a master drives it. The calls
/// take `&self` (the C side holds the state); an instance is `Send`, used from one thread at a
/// time as both standards require. Reals are FMI 3.0's Float64, integers its Int32.
pub trait CoSimSlave: Send {
    /// The instance name it was instantiated with.
    fn name(&self) -> &str;
    /// FMI 2.0 fmi2SetupExperiment; FMI 3.0 keeps the values for fmi3EnterInitializationMode.
    fn setup_experiment(
        &self,
        tolerance: Option<f64>,
        start: f64,
        stop: Option<f64>,
    ) -> Result<(), CallError>;
    fn enter_initialization_mode(&self) -> Result<(), CallError>;
    fn exit_initialization_mode(&self) -> Result<(), CallError>;
    fn terminate(&self) -> Result<(), CallError>;
    fn set_real(&self, vrs: &[u32], values: &[f64]) -> Result<(), CallError>;
    fn get_real(&self, vrs: &[u32], values: &mut [f64]) -> Result<(), CallError>;
    fn set_integer(&self, vrs: &[u32], values: &[i32]) -> Result<(), CallError>;
    fn get_integer(&self, vrs: &[u32], values: &mut [i32]) -> Result<(), CallError>;
    fn set_boolean(&self, vrs: &[u32], values: &[bool]) -> Result<(), CallError>;
    fn get_boolean(&self, vrs: &[u32], values: &mut [bool]) -> Result<(), CallError>;
    /// The inputs' time derivatives of the next step: FMI 2.0 fmi2SetRealInputDerivatives; FMI
    /// 3.0 the polynomials its importer answers the FMU's intermediate updates with.
    fn set_real_input_derivatives(
        &self,
        vrs: &[u32],
        orders: &[i32],
        values: &[f64],
    ) -> Result<(), CallError>;
    fn do_step(&self, t: f64, h: f64) -> Result<(), CallError>;
    /// The time a discarded step reached.
    fn last_successful_time(&self) -> Result<f64, CallError>;
    fn get_state(&self) -> Result<SavedState, CallError>;
    /// Saves into an existing state (the FMU may reuse its memory).
    fn update_state(&self, state: &mut SavedState) -> Result<(), CallError>;
    fn set_state(&self, state: &SavedState) -> Result<(), CallError>;
    fn serialize_state(&self, state: &SavedState) -> Result<Vec<u8>, CallError>;
    fn deserialize_state(&self, bytes: &[u8]) -> Result<SavedState, CallError>;
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_call_error_names_the_status_in_its_standards_words() {
        let e = |function, status| CallError { function, status }.to_string();
        assert_eq!(
            e("fmi2DoStep", Status::Discard),
            "fmi2DoStep returned fmi2Discard"
        );
        assert_eq!(
            e("fmi3DoStep", Status::Discard),
            "fmi3DoStep returned fmi3Discard"
        );
        assert_eq!(
            e("fmi3GetFloat64", Status::Ok),
            "fmi3GetFloat64 returned fmi3OK"
        );
        assert_eq!(check("fmi2DoStep", 1), Ok(()));
        assert_eq!(check("fmi2DoStep", 17).unwrap_err().status, Status::Fatal);
        assert_eq!(Status::from_raw(5), Some(Status::Pending));
    }

    #[test]
    fn a_state_of_another_kind_is_a_call_error() {
        let mut s = SavedState::new(7u32);
        assert_eq!(*s.get::<u32>("fmi2SetFMUstate").unwrap(), 7);
        *s.get_mut::<u32>("fmi2GetFMUstate").unwrap() = 8;
        assert_eq!(*s.get::<u32>("x").unwrap(), 8);
        let e = s.get::<String>("fmi3SetFMUState").unwrap_err();
        assert_eq!(e.status, Status::Error);
        assert_eq!(e.function, "fmi3SetFMUState");
    }
}
