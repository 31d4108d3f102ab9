//! An FMI 3.0 modelDescription.xml read into the importer's common description
//! (`fmi_core::description::ModelDescription`): Float64 as Real, Int32 (and the other integer types)
//! as Integer, Boolean as Boolean. Units come from the variable or its declared type.

use fmi_core::description::{ModelDescription, ScalarVariable, UnitInfo};
use fmi_core::variables::{Causality, VarType, Variability};

fn flag(node: roxmltree::Node, name: &str) -> bool {
    node.attribute(name)
        .map(|v| v == "true" || v == "1")
        .unwrap_or(false)
}

fn line(doc: &roxmltree::Document, node: roxmltree::Node) -> String {
    format!("line {}", doc.text_pos_at(node.range().start).row)
}

/// What FMI 3.0 adds to the common description.
#[derive(Clone, Debug)]
pub struct Fmi3Extras {
    /// The FMU calls intermediateUpdate inside fmi3DoStep.
    pub provides_intermediate_update: bool,
    /// Value references of the variables with `intermediateUpdate="true"`.
    pub intermediate_update_vrs: Vec<u32>,
}

/// Parses an FMI 3.0 description. `can_interpolate_inputs` of the result is true when the FMU
/// takes Float64 inputs within a step (intermediate update with every Float64 input marked),
/// which is what a master needs to know to send input polynomials.
pub fn parse(xml: &str) -> Result<(ModelDescription, Fmi3Extras), String> {
    let doc = roxmltree::Document::parse(xml).map_err(|e| format!("invalid XML: {e}"))?;
    let root = doc.root_element();
    if root.tag_name().name() != "fmiModelDescription" {
        return Err("root element is not fmiModelDescription".into());
    }
    let fmi_version = root.attribute("fmiVersion").unwrap_or("").to_string();
    if !fmi_version.starts_with("3.") {
        return Err(format!("fmiVersion '{fmi_version}' is not FMI 3.0"));
    }
    let cs = root
        .children()
        .find(|n| n.has_tag_name("CoSimulation"))
        .ok_or("the FMU does not support co-simulation (no <CoSimulation> element)")?;

    // Declared types: name -> (unit, displayUnit).
    let mut types: Vec<(String, Option<String>, Option<String>)> = vec![];
    if let Some(td) = root.children().find(|n| n.has_tag_name("TypeDefinitions")) {
        for t in td.children().filter(|n| n.is_element()) {
            if let Some(name) = t.attribute("name") {
                types.push((
                    name.to_string(),
                    t.attribute("unit").map(str::to_string),
                    t.attribute("displayUnit").map(str::to_string),
                ));
            }
        }
    }

    let mut variables = Vec::new();
    let mut intermediate_update_vrs = Vec::new();
    if let Some(mv) = root.children().find(|n| n.has_tag_name("ModelVariables")) {
        for v in mv.children().filter(|n| n.is_element()) {
            let at = line(&doc, v);
            let var_type = match v.tag_name().name() {
                "Float64" | "Float32" => VarType::Real,
                "Int8" | "UInt8" | "Int16" | "UInt16" | "Int32" | "UInt32" | "Enumeration" => {
                    VarType::Integer
                }
                "Boolean" => VarType::Boolean,
                _ => continue, // 64-bit integers, strings, binaries, clocks: not used by the master
            };
            let name = v
                .attribute("name")
                .ok_or(format!("{at}: variable without name"))?
                .to_string();
            let vr = v
                .attribute("valueReference")
                .and_then(|s| s.parse().ok())
                .ok_or(format!("{at}: '{name}' has no valid valueReference"))?;
            if v.children().any(|n| n.has_tag_name("Dimension")) {
                return Err(format!(
                    "{at}: '{name}' is an array variable (not supported by this importer)"
                ));
            }
            let causality = match v.attribute("causality").unwrap_or("local") {
                "parameter" => Causality::Parameter,
                "calculatedParameter" => Causality::CalculatedParameter,
                "input" => Causality::Input,
                "output" => Causality::Output,
                "independent" => Causality::Independent,
                _ => Causality::Local,
            };
            let variability = match v.attribute("variability").unwrap_or("continuous") {
                "constant" => Variability::Constant,
                "fixed" => Variability::Fixed,
                "tunable" => Variability::Tunable,
                "discrete" => Variability::Discrete,
                _ => Variability::Continuous,
            };
            let declared = v
                .attribute("declaredType")
                .and_then(|d| types.iter().find(|t| t.0 == d));
            let unit = v
                .attribute("unit")
                .map(str::to_string)
                .or_else(|| declared.and_then(|t| t.1.clone()));
            let display_unit = v
                .attribute("displayUnit")
                .map(str::to_string)
                .or_else(|| declared.and_then(|t| t.2.clone()));
            let start = v.attribute("start").and_then(|s| match s {
                "true" => Some(1.0),
                "false" => Some(0.0),
                s => s.parse().ok(),
            });
            if flag(v, "intermediateUpdate") {
                intermediate_update_vrs.push(vr);
            }
            variables.push(ScalarVariable {
                name,
                vr,
                var_type,
                causality,
                variability,
                unit,
                display_unit,
                start,
                description: v.attribute("description").unwrap_or("").to_string(),
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
                        let num = |a: &str, default: f64| {
                            d.attribute(a)
                                .and_then(|f| f.parse().ok())
                                .unwrap_or(default)
                        };
                        (
                            d.attribute("name").unwrap_or("").to_string(),
                            num("factor", 1.0),
                            num("offset", 0.0),
                        )
                    })
                    .collect(),
            });
        }
    }
    let provides_intermediate_update = flag(cs, "providesIntermediateUpdate");
    let takes_inputs_within_step = provides_intermediate_update
        && variables
            .iter()
            .filter(|v| v.causality == Causality::Input && v.var_type == VarType::Real)
            .all(|v| intermediate_update_vrs.contains(&v.vr));
    let de = root
        .children()
        .find(|n| n.has_tag_name("DefaultExperiment"));
    let description = ModelDescription {
        fmi_version,
        model_name: root.attribute("modelName").unwrap_or("").to_string(),
        guid: root
            .attribute("instantiationToken")
            .ok_or("no instantiationToken attribute")?
            .to_string(),
        model_identifier: cs
            .attribute("modelIdentifier")
            .ok_or("CoSimulation has no modelIdentifier")?
            .to_string(),
        can_interpolate_inputs: takes_inputs_within_step,
        max_output_derivative_order: cs
            .attribute("maxOutputDerivativeOrder")
            .and_then(|v| v.parse().ok())
            .unwrap_or(0),
        can_get_and_set_fmu_state: flag(cs, "canGetAndSetFMUState"),
        can_serialize_fmu_state: flag(cs, "canSerializeFMUState"),
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
    };
    Ok((
        description,
        Fmi3Extras {
            provides_intermediate_update,
            intermediate_update_vrs,
        },
    ))
}
