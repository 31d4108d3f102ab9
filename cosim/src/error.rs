//! Typed errors of the co-simulation library.

use fmi_core::CallError;

/// Why a macro step failed.
#[derive(Debug)]
pub struct StepError {
    pub subsystem: String,
    pub error: CallError,
    pub t_s: f64,
}

impl std::fmt::Display for StepError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "{}: {} at t = {} s (see its log above)",
            self.subsystem, self.error, self.t_s
        )
    }
}

impl std::error::Error for StepError {}

/// Why a checkpoint could not be restored.
#[derive(Debug)]
pub enum RestoreError {
    /// The checkpoint's algorithm state does not fit this co-simulation.
    Mismatch(String),
    /// An FMU refused its saved state.
    Fmu(StepError),
}

impl std::fmt::Display for RestoreError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            RestoreError::Mismatch(e) => write!(f, "the checkpoint does not fit this system: {e}"),
            RestoreError::Fmu(e) => write!(f, "{e}"),
        }
    }
}

impl std::error::Error for RestoreError {}

impl From<StepError> for RestoreError {
    fn from(e: StepError) -> Self {
        RestoreError::Fmu(e)
    }
}

/// Why a run could not start (a run that starts reports its end in `RunReport`).
#[derive(Debug)]
pub enum RunError {
    /// A file or folder of the run could not be read or written.
    Io {
        path: std::path::PathBuf,
        source: std::io::Error,
    },
    /// The system file is invalid or its FMUs could not be set up.
    System(crate::system::SystemError),
    /// The checkpoint to resume from is missing or unreadable.
    Checkpoint(String),
    /// A setting of the run itself (`RunConfig`) is unusable.
    Config(String),
    /// An observer refused the run before it started (its reason).
    Observer(ObserverError),
}

impl std::fmt::Display for RunError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            RunError::Io { path, source } => write!(f, "{}: {source}", path.display()),
            RunError::System(e) => write!(f, "{e}"),
            RunError::Checkpoint(e) | RunError::Config(e) => write!(f, "{e}"),
            RunError::Observer(e) => write!(f, "{e}"),
        }
    }
}

impl std::error::Error for RunError {}

impl From<crate::system::SystemError> for RunError {
    fn from(e: crate::system::SystemError) -> Self {
        RunError::System(e)
    }
}

/// Why an observer refused a run or ended it.
#[derive(Debug)]
pub enum ObserverError {
    /// A file the observer writes or reads could not be (the time series, the summary, ...).
    Io {
        path: std::path::PathBuf,
        source: std::io::Error,
    },
    /// The observer refuses the run as it is set up (too large for memory, a folder in use).
    Refused(String),
    /// Anything else, in the observer's words.
    Other(String),
}

impl ObserverError {
    /// An I/O error on `path`.
    pub fn io(path: impl Into<std::path::PathBuf>, source: std::io::Error) -> Self {
        ObserverError::Io {
            path: path.into(),
            source,
        }
    }
}

impl std::fmt::Display for ObserverError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            ObserverError::Io { path, source } => write!(f, "{}: {source}", path.display()),
            ObserverError::Refused(e) | ObserverError::Other(e) => write!(f, "{e}"),
        }
    }
}

impl std::error::Error for ObserverError {
    fn source(&self) -> Option<&(dyn std::error::Error + 'static)> {
        match self {
            ObserverError::Io { source, .. } => Some(source),
            _ => None,
        }
    }
}

impl From<String> for ObserverError {
    fn from(e: String) -> Self {
        ObserverError::Other(e)
    }
}

/// The run loop reports an observer's error as text (`RunReport::error`).
impl From<ObserverError> for String {
    fn from(e: ObserverError) -> Self {
        e.to_string()
    }
}
