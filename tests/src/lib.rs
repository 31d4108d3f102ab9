//! Shared helpers for the cross-crate tests: where the packed FMUs are, and a log collector.
//!
//! The FMUs are built and packed by `cargo xtask fmus` (the README's test command runs it first).

use fmi2::importer::{Fmu, LogHandler, LogRecord, Slave};
use std::path::PathBuf;
use std::sync::{Arc, Mutex};

pub fn workspace_root() -> PathBuf {
    // Cargo sets CARGO_MANIFEST_DIR for the running test too; the compile-time value would be
    // stale in a binary reused from another checkout sharing this target directory.
    let manifest =
        std::env::var_os("CARGO_MANIFEST_DIR").unwrap_or_else(|| env!("CARGO_MANIFEST_DIR").into());
    PathBuf::from(manifest).parent().unwrap().to_path_buf()
}

/// Path of a packed FMU; panics with the fix if it is missing.
pub fn fmu_path(model_identifier: &str) -> PathBuf {
    let p = workspace_root()
        .join("target/fmu")
        .join(format!("{model_identifier}.fmu"));
    assert!(
        p.exists(),
        "{} is missing: run `cargo xtask fmus` first",
        p.display()
    );
    p
}

pub fn load(model_identifier: &str) -> Fmu {
    Fmu::load(&fmu_path(model_identifier)).expect("the packed FMU loads")
}

/// Collects every log record of the instances it is given to.
#[derive(Clone, Default)]
pub struct LogBook(pub Arc<Mutex<Vec<LogRecord>>>);

impl LogBook {
    pub fn handler(&self) -> LogHandler {
        let book = self.0.clone();
        Arc::new(move |r: &LogRecord| book.lock().unwrap().push(r.clone()))
    }
    pub fn len(&self) -> usize {
        self.0.lock().unwrap().len()
    }
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }
    pub fn last(&self) -> Option<LogRecord> {
        self.0.lock().unwrap().last().cloned()
    }
    pub fn contains(&self, needle: &str) -> bool {
        self.0
            .lock()
            .unwrap()
            .iter()
            .any(|r| r.message.contains(needle))
    }
}

/// Instantiates, sets up from t = 0 and enters the step phase.
pub fn initialized(fmu: &Fmu, name: &str, book: &LogBook, set: impl FnOnce(&Slave)) -> Slave {
    let s = fmu
        .instantiate(name, false, book.handler())
        .expect("instantiate");
    s.setup_experiment(None, 0.0, None).unwrap();
    s.enter_initialization_mode().unwrap();
    set(&s);
    s.exit_initialization_mode().unwrap();
    s
}
