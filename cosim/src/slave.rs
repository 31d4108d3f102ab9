//! An FMU of either FMI version, as the co-simulation drives it.
//!
//! `fmi2::importer` and `fmi3::importer` each drive their version's C functions; this enum gives
//! the algorithm one surface over both. FMI 3.0 has no input derivatives: its importer answers the
//! FMU's intermediate updates with the same input polynomials (see `fmi3::importer`), so a system
//! of FMI 3.0 twins runs the same macro steps with the same inputs as its FMI 2.0 original.

use fmi2::importer::{unpack_unless_folder, CallError, ImportError, LogHandler, ModelDescription};
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
            Fmu::V2(f) => Slave::V2(f.instantiate(instance_name, logging_on, log)?),
            Fmu::V3(f) => Slave::V3(f.instantiate(instance_name, logging_on, log)?),
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

/// An instance of either version.
pub enum Slave {
    V2(fmi2::importer::Slave),
    V3(fmi3::importer::Slave),
}

/// A saved state of either version.
pub enum FmuState {
    V2(fmi2::importer::FmuState),
    V3(fmi3::importer::FmuState),
}

fn mismatch() -> CallError {
    CallError {
        function: "an FMU state of the other FMI version",
        status: fmi2::Status::Error,
    }
}

/// One call on either version with the same arguments.
macro_rules! both {
    ($self:ident, $s:ident => $e:expr) => {
        match $self {
            Slave::V2($s) => $e,
            Slave::V3($s) => $e,
        }
    };
}

impl Slave {
    pub fn name(&self) -> &str {
        both!(self, s => s.name())
    }

    pub fn setup_experiment(
        &self,
        tolerance: Option<f64>,
        start: f64,
        stop: Option<f64>,
    ) -> Result<(), CallError> {
        both!(self, s => s.setup_experiment(tolerance, start, stop))
    }

    pub fn enter_initialization_mode(&self) -> Result<(), CallError> {
        both!(self, s => s.enter_initialization_mode())
    }

    pub fn exit_initialization_mode(&self) -> Result<(), CallError> {
        both!(self, s => s.exit_initialization_mode())
    }

    pub fn terminate(&self) -> Result<(), CallError> {
        both!(self, s => s.terminate())
    }

    pub fn set_real(&self, vrs: &[u32], values: &[f64]) -> Result<(), CallError> {
        match self {
            Slave::V2(s) => s.set_real(vrs, values),
            Slave::V3(s) => s.set_float64(vrs, values),
        }
    }

    pub fn get_real(&self, vrs: &[u32], values: &mut [f64]) -> Result<(), CallError> {
        match self {
            Slave::V2(s) => s.get_real(vrs, values),
            Slave::V3(s) => s.get_float64(vrs, values),
        }
    }

    pub fn set_integer(&self, vrs: &[u32], values: &[i32]) -> Result<(), CallError> {
        match self {
            Slave::V2(s) => s.set_integer(vrs, values),
            Slave::V3(s) => s.set_int32(vrs, values),
        }
    }

    pub fn get_integer(&self, vrs: &[u32], values: &mut [i32]) -> Result<(), CallError> {
        match self {
            Slave::V2(s) => s.get_integer(vrs, values),
            Slave::V3(s) => s.get_int32(vrs, values),
        }
    }

    pub fn set_boolean(&self, vrs: &[u32], values: &[bool]) -> Result<(), CallError> {
        both!(self, s => s.set_boolean(vrs, values))
    }

    pub fn get_boolean(&self, vrs: &[u32], values: &mut [bool]) -> Result<(), CallError> {
        both!(self, s => s.get_boolean(vrs, values))
    }

    /// FMI 2.0: fmi2SetRealInputDerivatives. FMI 3.0: the polynomials the importer answers the
    /// FMU's intermediate updates with, in the next step.
    pub fn set_real_input_derivatives(
        &self,
        vrs: &[u32],
        orders: &[i32],
        values: &[f64],
    ) -> Result<(), CallError> {
        match self {
            Slave::V2(s) => s.set_real_input_derivatives(vrs, orders, values),
            Slave::V3(s) => s.set_input_derivatives(vrs, orders, values),
        }
    }

    pub fn do_step(&self, t: f64, h: f64) -> Result<(), CallError> {
        both!(self, s => s.do_step(t, h))
    }

    /// The time a discarded step reached.
    pub fn last_successful_time(&self) -> Result<f64, CallError> {
        match self {
            Slave::V2(s) => s.last_successful_time(),
            Slave::V3(s) => Ok(s.last_successful_time()),
        }
    }

    pub fn get_state(&self) -> Result<FmuState, CallError> {
        match self {
            Slave::V2(s) => s.get_state().map(FmuState::V2),
            Slave::V3(s) => s.get_state().map(FmuState::V3),
        }
    }

    pub fn update_state(&self, state: &mut FmuState) -> Result<(), CallError> {
        match (self, state) {
            (Slave::V2(s), FmuState::V2(st)) => s.update_state(st),
            (Slave::V3(s), FmuState::V3(st)) => s.update_state(st),
            _ => Err(mismatch()),
        }
    }

    pub fn set_state(&self, state: &FmuState) -> Result<(), CallError> {
        match (self, state) {
            (Slave::V2(s), FmuState::V2(st)) => s.set_state(st),
            (Slave::V3(s), FmuState::V3(st)) => s.set_state(st),
            _ => Err(mismatch()),
        }
    }

    pub fn serialize_state(&self, state: &FmuState) -> Result<Vec<u8>, CallError> {
        match (self, state) {
            (Slave::V2(s), FmuState::V2(st)) => s.serialize_state(st),
            (Slave::V3(s), FmuState::V3(st)) => s.serialize_state(st),
            _ => Err(mismatch()),
        }
    }

    pub fn deserialize_state(&self, bytes: &[u8]) -> Result<FmuState, CallError> {
        match self {
            Slave::V2(s) => s.deserialize_state(bytes).map(FmuState::V2),
            Slave::V3(s) => s.deserialize_state(bytes).map(FmuState::V3),
        }
    }
}

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
