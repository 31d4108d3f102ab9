//! Importer: load an FMI 3.0 Co-Simulation FMU (`.fmu` archive or unpacked folder) and drive it.
//!
//! The sibling of `fmi2::importer`: the archive handling, the call errors, the FMU states, the
//! slave interface, the description and the log records come from `fmi_core`. Used by the
//! `airring` master (through `cosim`'s slave) and the tests. It answers intermediate updates with the master's input
//! polynomials (`slave`), so FMI 3.0 FMUs take inputs within a step as FMI 2.0 ones do through
//! input derivatives.

mod description;
mod library;
mod slave;

pub use description::{parse, Fmi3Extras};
pub use library::Api;
pub use slave::{FmuState, Slave};

use fmi_core::archive::{folder_of, unpack_unless_folder, ImportError, UnpackedDir};
use fmi_core::description::ModelDescription;
use fmi_core::LogHandler;
use std::path::{Path, PathBuf};
use std::sync::Arc;

/// The platform folder of Linux x86-64 binaries in FMI 3.0 (`binaries/x86_64-linux`).
pub const PLATFORM: &str = "x86_64-linux";

/// A loaded FMU: its description and its shared library. Instances are created with `instantiate`.
pub struct Fmu {
    pub path: PathBuf,
    /// Unpacked folder.
    pub dir: PathBuf,
    pub description: ModelDescription,
    pub extras: Fmi3Extras,
    pub api: Arc<Api>,
    /// The folder, when this `Fmu` unpacked it: removed when the `Fmu` is dropped (declared last,
    /// so the library is released first).
    _unpacked: Option<UnpackedDir>,
}

impl Fmu {
    /// Loads a `.fmu` archive (unpacked into a fresh temporary folder) or an unpacked FMU folder.
    pub fn load(path: &Path) -> Result<Fmu, ImportError> {
        let (unpacked, _) = unpack_unless_folder(path)?;
        Self::from_unpacked(path, unpacked)
    }

    /// An FMU already unpacked (by `fmi_core::archive::unpack`, e.g. to read its version first), or
    /// the folder `path` itself when `unpacked` is `None`.
    pub fn from_unpacked(path: &Path, unpacked: Option<UnpackedDir>) -> Result<Fmu, ImportError> {
        let dir = folder_of(path, unpacked.as_ref());
        let md_path = dir.join("modelDescription.xml");
        let xml = std::fs::read_to_string(&md_path).map_err(|e| {
            ImportError(format!(
                "{}: cannot read modelDescription.xml: {e}",
                path.display()
            ))
        })?;
        let (description, extras) =
            parse(&xml).map_err(|e| ImportError(format!("{}: {e}", md_path.display())))?;
        let lib = dir
            .join("binaries")
            .join(PLATFORM)
            .join(format!("{}.so", description.model_identifier));
        let api = Arc::new(Api::load(&lib)?);
        Ok(Fmu {
            path: path.to_path_buf(),
            dir,
            description,
            extras,
            api,
            _unpacked: unpacked,
        })
    }

    /// Creates an instance (fmi3InstantiateCoSimulation). The importer answers intermediate
    /// updates when the FMU provides them.
    pub fn instantiate(
        &self,
        instance_name: &str,
        logging_on: bool,
        log: LogHandler,
    ) -> Result<Slave, ImportError> {
        let vrs: &[u32] = if self.extras.provides_intermediate_update {
            &self.extras.intermediate_update_vrs
        } else {
            &[]
        };
        Slave::instantiate(
            self.api.clone(),
            &self.description.guid,
            &self.dir.join("resources"),
            instance_name,
            logging_on,
            log,
            vrs,
        )
    }
}
