//! Importer: load any FMI 2.0 co-simulation FMU (`.fmu` archive or unpacked folder) and drive it.
//!
//! Used by the `airring` master and the integration tests. Unlike the `fmi` crate it can set input
//! derivatives, get and serialize FMU states, and it reports every status code faithfully.

pub mod description;
mod library;
mod slave;

pub use fmi_core::archive::{folder_of, unpack, unpack_unless_folder, ImportError, UnpackedDir};
pub use fmi_core::description::{ModelDescription, ScalarVariable, UnitInfo};
pub use library::Api;
pub use slave::{check, lossy, CallError, FmuState, LogHandler, LogRecord, Slave};

use std::path::{Path, PathBuf};
use std::sync::Arc;

/// A loaded FMU: its description and its shared library. Instances are created with `instantiate`.
pub struct Fmu {
    pub path: PathBuf,
    /// Unpacked folder.
    pub dir: PathBuf,
    pub description: ModelDescription,
    pub api: Arc<Api>,
    /// The folder, when this `Fmu` unpacked it: removed when the `Fmu` is dropped (declared last,
    /// so the library is released first).
    _unpacked: Option<UnpackedDir>,
}

impl Fmu {
    /// Loads a `.fmu` archive (unpacked into a fresh temporary folder) or an unpacked FMU folder.
    pub fn load(path: &Path) -> Result<Fmu, ImportError> {
        // A failed (or panicking) load drops the guard: nothing stays in the temporary folder.
        let (unpacked, _) = unpack_unless_folder(path)?;
        Self::from_unpacked(path, unpacked)
    }

    /// An FMU already unpacked (by `unpack`, e.g. to read its FMI version first), or the folder
    /// `path` itself when `unpacked` is `None`.
    pub fn from_unpacked(path: &Path, unpacked: Option<UnpackedDir>) -> Result<Fmu, ImportError> {
        let dir = folder_of(path, unpacked.as_ref());
        let (description, api) = Self::open_unpacked(path, &dir)?;
        Ok(Fmu {
            path: path.to_path_buf(),
            dir,
            description,
            api,
            _unpacked: unpacked,
        })
    }

    /// Reads the description of an unpacked FMU in `dir` and loads its library.
    fn open_unpacked(path: &Path, dir: &Path) -> Result<(ModelDescription, Arc<Api>), ImportError> {
        let md_path = dir.join("modelDescription.xml");
        let xml = std::fs::read_to_string(&md_path).map_err(|e| {
            ImportError(format!(
                "{}: cannot read modelDescription.xml: {e}",
                path.display()
            ))
        })?;
        let description = description::parse(&xml)
            .map_err(|e| ImportError(format!("{}: {e}", md_path.display())))?;
        let lib = dir
            .join("binaries")
            .join("linux64")
            .join(format!("{}.so", description.model_identifier));
        let api = Arc::new(Api::load(&lib)?);
        Ok((description, api))
    }

    /// `file:///…/resources` URI of the unpacked FMU.
    pub fn resource_uri(&self) -> String {
        crate::resource::path_to_uri(&self.dir.join("resources"))
    }

    /// Creates an instance (fmi2Instantiate, co-simulation).
    pub fn instantiate(
        &self,
        instance_name: &str,
        logging_on: bool,
        log: LogHandler,
    ) -> Result<Slave, ImportError> {
        Slave::instantiate(
            self.api.clone(),
            &self.description.guid,
            &self.resource_uri(),
            instance_name,
            logging_on,
            log,
        )
    }
}
