//! Reading an FMI 2.0 modelDescription.xml into the version-neutral description of the FMI core.

use fmi_core::description::{ModelDescription, ScalarVariable, UnitInfo};
use fmi_core::variables::{Causality, VarType, Variability};

fn flag(node: roxmltree::Node, name: &str) -> bool {
    node.attribute(name)
        .map(|v| v == "true" || v == "1")
        .unwrap_or(false)
}

fn pos(doc: &roxmltree::Document, node: roxmltree::Node) -> String {
    let p = doc.text_pos_at(node.range().start);
    format!("line {}", p.row)
}

/// The parts of an FMI 2.0 modelDescription.xml a master needs.
pub fn parse(xml: &str) -> Result<ModelDescription, String> {
    let doc = roxmltree::Document::parse(xml).map_err(|e| format!("invalid XML: {e}"))?;
    let root = doc.root_element();
    if root.tag_name().name() != "fmiModelDescription" {
        return Err("root element is not fmiModelDescription".into());
    }
    let fmi_version = root.attribute("fmiVersion").unwrap_or("").to_string();
    if !fmi_version.starts_with("2.") {
        return Err(format!("fmiVersion '{fmi_version}' is not FMI 2.0"));
    }
    let cs = root
        .children()
        .find(|n| n.has_tag_name("CoSimulation"))
        .ok_or("the FMU does not support co-simulation (no <CoSimulation> element)")?;
    let mut variables = Vec::new();
    if let Some(mv) = root.children().find(|n| n.has_tag_name("ModelVariables")) {
        for sv in mv.children().filter(|n| n.has_tag_name("ScalarVariable")) {
            let at = pos(&doc, sv);
            let name = sv
                .attribute("name")
                .ok_or(format!("{at}: ScalarVariable without name"))?
                .to_string();
            let vr = sv
                .attribute("valueReference")
                .and_then(|v| v.parse().ok())
                .ok_or(format!("{at}: '{name}' has no valid valueReference"))?;
            let causality = match sv.attribute("causality").unwrap_or("local") {
                "parameter" => Causality::Parameter,
                "calculatedParameter" => Causality::CalculatedParameter,
                "input" => Causality::Input,
                "output" => Causality::Output,
                "independent" => Causality::Independent,
                _ => Causality::Local,
            };
            let variability = match sv.attribute("variability").unwrap_or("continuous") {
                "constant" => Variability::Constant,
                "fixed" => Variability::Fixed,
                "tunable" => Variability::Tunable,
                "discrete" => Variability::Discrete,
                _ => Variability::Continuous,
            };
            let Some(ty) = sv.children().find(|n| n.is_element()) else {
                return Err(format!("{at}: '{name}' has no type element"));
            };
            let var_type = match ty.tag_name().name() {
                "Real" => VarType::Real,
                "Integer" | "Enumeration" => VarType::Integer,
                "Boolean" => VarType::Boolean,
                _ => continue, // String variables: not used by the master
            };
            let start = ty.attribute("start").and_then(|s| match s {
                "true" => Some(1.0),
                "false" => Some(0.0),
                s => s.parse().ok(),
            });
            variables.push(ScalarVariable {
                name,
                vr,
                var_type,
                causality,
                variability,
                unit: ty.attribute("unit").map(str::to_string),
                display_unit: ty.attribute("displayUnit").map(str::to_string),
                start,
                description: sv.attribute("description").unwrap_or("").to_string(),
            });
        }
    }
    let mut units = Vec::new();
    if let Some(ud) = root.children().find(|n| n.has_tag_name("UnitDefinitions")) {
        for u in ud.children().filter(|n| n.has_tag_name("Unit")) {
            units.push(UnitInfo {
                name: u.attribute("name").unwrap_or("").to_string(),
                display_units: u
                    .children()
                    .filter(|n| n.has_tag_name("DisplayUnit"))
                    .map(|d| {
                        (
                            d.attribute("name").unwrap_or("").to_string(),
                            d.attribute("factor")
                                .and_then(|f| f.parse().ok())
                                .unwrap_or(1.0),
                            d.attribute("offset")
                                .and_then(|f| f.parse().ok())
                                .unwrap_or(0.0),
                        )
                    })
                    .collect(),
            });
        }
    }
    let de = root
        .children()
        .find(|n| n.has_tag_name("DefaultExperiment"));
    Ok(ModelDescription {
        fmi_version,
        model_name: root.attribute("modelName").unwrap_or("").to_string(),
        guid: root
            .attribute("guid")
            .ok_or("no guid attribute")?
            .to_string(),
        model_identifier: cs
            .attribute("modelIdentifier")
            .ok_or("CoSimulation has no modelIdentifier")?
            .to_string(),
        can_interpolate_inputs: flag(cs, "canInterpolateInputs"),
        max_output_derivative_order: cs
            .attribute("maxOutputDerivativeOrder")
            .and_then(|v| v.parse().ok())
            .unwrap_or(0),
        can_get_and_set_fmu_state: flag(cs, "canGetAndSetFMUstate"),
        can_serialize_fmu_state: flag(cs, "canSerializeFMUstate"),
        can_handle_variable_step: flag(cs, "canHandleVariableCommunicationStepSize"),
        can_be_instantiated_only_once_per_process: flag(cs, "canBeInstantiatedOnlyOncePerProcess"),
        variables,
        units,
        default_step_size: de
            .and_then(|d| d.attribute("stepSize"))
            .and_then(|v| v.parse().ok()),
        default_stop_time: de
            .and_then(|d| d.attribute("stopTime"))
            .and_then(|v| v.parse().ok()),
    })
}
