//! The parts of a third-party modelDescription.xml that a co-simulation master needs, in the
//! same words for both standards: `fmi2::importer` and `fmi3::importer` each read their version's
//! file into a [`ModelDescription`], and the master (`cosim`) reads only this.

use crate::variables::{Causality, VarType, Variability};

#[derive(Clone, Debug)]
pub struct ScalarVariable {
    pub name: String,
    pub vr: u32,
    pub var_type: VarType,
    pub causality: Causality,
    pub variability: Variability,
    pub unit: Option<String>,
    pub display_unit: Option<String>,
    pub start: Option<f64>,
    pub description: String,
}

#[derive(Clone, Debug)]
pub struct UnitInfo {
    pub name: String,
    /// (name, factor, offset)
    pub display_units: Vec<(String, f64, f64)>,
}

#[derive(Clone, Debug)]
pub struct ModelDescription {
    pub fmi_version: String,
    pub model_name: String,
    pub guid: String,
    pub model_identifier: String,
    pub can_interpolate_inputs: bool,
    pub max_output_derivative_order: u32,
    pub can_get_and_set_fmu_state: bool,
    pub can_serialize_fmu_state: bool,
    pub can_handle_variable_step: bool,
    /// `canBeInstantiatedOnlyOncePerProcess`: a second instance needs its own copy of the
    /// library (another unpacked folder), not another instance of the loaded one.
    pub can_be_instantiated_only_once_per_process: bool,
    pub variables: Vec<ScalarVariable>,
    pub units: Vec<UnitInfo>,
    pub default_step_size: Option<f64>,
    pub default_stop_time: Option<f64>,
}

impl ModelDescription {
    pub fn variable(&self, name: &str) -> Option<&ScalarVariable> {
        self.variables.iter().find(|v| v.name == name)
    }

    /// Factor and offset that turn a value in `display` into the variable's unit, if `display` is the
    /// variable's unit itself or one of its display units.
    pub fn to_unit(&self, var: &ScalarVariable, display: &str) -> Option<(f64, f64)> {
        let unit = var.unit.as_deref()?;
        if unit == display {
            return Some((1.0, 0.0));
        }
        let u = self.units.iter().find(|u| u.name == unit)?;
        u.display_units
            .iter()
            .find(|d| d.0 == display)
            .map(|(_, f, o)| (*f, *o))
    }
}
