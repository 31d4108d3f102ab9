//! An FMU of either FMI version, as the co-simulation drives it.
//!
//! `fmi2::importer` and `fmi3::importer` each drive their version's C functions and implement one
//! version-neutral interface, `fmi_core::CoSimSlave`, which the algorithm drives. FMI 3.0 has no input derivatives: its importer answers the
//! FMU's intermediate updates with the same input polynomials (see `fmi3::importer`), so a system
//! of FMI 3.0 twins runs the same macro steps with the same inputs as its FMI 2.0 original.

use fmi_core::archive::{unpack_unless_folder, ImportError};
use fmi_core::description::ModelDescription;
pub use fmi_core::CoSimSlave;
use fmi_core::LogHandler;
use std::path::{Path, PathBuf};
use std::sync::Arc;

/// A loaded FMU.
pub enum Fmu {
    V2(fmi2::importer::Fmu),
    V3(fmi3::importer::Fmu),
}

/// The `fmiVersion` attribute of a modelDescription.xml.
fn fmi_version(xml: &str) -> Option<&str> {
    let start = xml.find("<fmiModelDescription")?;
    let rest = &xml[start..];
    let end = rest.find('>')?;
    let head = &rest[..end];
    let at = head.find("fmiVersion")?;
    let value = head[at..].split_once(['"', '\''])?.1;
    value.split(['"', '\'']).next()
}

impl Fmu {
    /// Loads a `.fmu` archive or an unpacked folder of FMI 2.0 or 3.0, by its `fmiVersion`.
    pub fn load(path: &Path) -> Result<Fmu, ImportError> {
        let (unpacked, dir) = unpack_unless_folder(path)?;
        let xml = std::fs::read_to_string(dir.join("modelDescription.xml")).map_err(|e| {
            ImportError(format!(
                "{}: cannot read modelDescription.xml: {e}",
                path.display()
            ))
        })?;
        match fmi_version(&xml) {
            Some(v) if v.starts_with("2.") => {
                fmi2::importer::Fmu::from_unpacked(path, unpacked).map(Fmu::V2)
            }
            Some(v) if v.starts_with("3.") => {
                fmi3::importer::Fmu::from_unpacked(path, unpacked).map(Fmu::V3)
            }
            v => Err(ImportError(format!(
                "{}: fmiVersion '{}' is neither FMI 2.0 nor FMI 3.0",
                path.display(),
                v.unwrap_or("(none)")
            ))),
        }
    }

    pub fn description(&self) -> &ModelDescription {
        match self {
            Fmu::V2(f) => &f.description,
            Fmu::V3(f) => &f.description,
        }
    }

    pub fn instantiate(
        &self,
        instance_name: &str,
        logging_on: bool,
        log: LogHandler,
    ) -> Result<Slave, ImportError> {
        Ok(match self {
            Fmu::V2(f) => Slave::new(f.instantiate(instance_name, logging_on, log)?),
            Fmu::V3(f) => Slave::new(f.instantiate(instance_name, logging_on, log)?),
        })
    }
}

/// The FMUs of a system's instances, each file loaded (unpacked, its library opened) once and
/// shared by the instances that name it: a run-up's two air films are two instances of one
/// `airfilm.fmu`, and loading it twice cost a second unpacked copy and ~6 ms of the start. An
/// FMU whose description says `canBeInstantiatedOnlyOncePerProcess` gets a copy of its own per
/// instance instead, as before (an unpacked folder is not copied: its library is opened from the
/// same file, so the process shares it, as any dynamic loader does).
#[derive(Default)]
pub struct LoadedFmus {
    loaded: Vec<(PathBuf, Arc<Fmu>)>,
}

impl LoadedFmus {
    /// The FMU at `path`, loaded now or shared with an earlier instance of the same file.
    pub fn get(&mut self, path: &Path) -> Result<Arc<Fmu>, ImportError> {
        // The same file under two spellings (a relative and an absolute path) is one FMU.
        let key = std::fs::canonicalize(path).unwrap_or_else(|_| path.to_path_buf());
        let shared = self
            .loaded
            .iter()
            .find(|(p, f)| *p == key && !f.description().can_be_instantiated_only_once_per_process);
        if let Some((_, f)) = shared {
            return Ok(Arc::clone(f));
        }
        let fmu = Arc::new(Fmu::load(path)?);
        self.loaded.push((key, Arc::clone(&fmu)));
        Ok(fmu)
    }
}

/// An instance of either version, behind the version-neutral interface both importers
/// implement (`fmi_core::CoSimSlave`): the algorithm calls it without knowing which.
pub struct Slave(Box<dyn CoSimSlave>);

impl Slave {
    pub fn new(slave: impl CoSimSlave + 'static) -> Self {
        Slave(Box::new(slave))
    }
}

impl std::ops::Deref for Slave {
    type Target = dyn CoSimSlave;
    fn deref(&self) -> &Self::Target {
        &*self.0
    }
}

/// A saved state of either version (opaque: each importer keeps its own kind inside).
pub type FmuState = fmi_core::SavedState;

#[cfg(test)]
mod tests {
    use super::fmi_version;

    #[test]
    fn reads_the_fmi_version_of_either_quote() {
        let xml = r#"<?xml version="1.0"?>
<fmiModelDescription fmiVersion="3.0" modelName="x"><CoSimulation/></fmiModelDescription>"#;
        assert_eq!(fmi_version(xml), Some("3.0"));
        assert_eq!(
            fmi_version("<fmiModelDescription modelName='a' fmiVersion='2.0'>"),
            Some("2.0")
        );
        assert_eq!(fmi_version("<fmiModelDescription modelName='a'>"), None);
        assert_eq!(fmi_version("<other fmiVersion='2.0'>"), None);
    }
}
