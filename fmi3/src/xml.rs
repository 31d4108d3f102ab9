//! FMI 3.0 modelDescription.xml from the fmi2 variable table: the same names, units, causalities,
//! variabilities, initials and start values as the FMI 2.0 description, with FMI 3.0 value
//! references (`value_refs`) and the independent variable `time` that FMI 3.0 requires.

use crate::logging::all_log_categories;
use crate::value_refs::{self, TIME_NAME, TIME_VR};
use fmi_core::variables::{Causality, Initial, ModelInfo, VarType};
use fmi_core::xml::{escape, num, unit_definitions};
use std::fmt::Write;

pub const GENERATION_TOOL: &str = "AirRing fmi3 layer";

/// The declared type of a Float64 in `unit` shown in `display`: "m", or "m, shown in um".
fn type_name(unit: &str, display: Option<&str>) -> String {
    match display {
        Some(d) => format!("{unit}, shown in {d}"),
        None => unit.to_string(),
    }
}

/// Every (unit, display unit) of the model's Real variables, and "s" for time; sorted.
fn float_types(info: &ModelInfo) -> Vec<(&'static str, Option<&'static str>)> {
    let mut t: Vec<(&str, Option<&str>)> = info
        .variables
        .iter()
        .filter(|v| v.var_type == VarType::Real)
        .filter_map(|v| v.unit.map(|u| (u, v.display_unit)))
        .chain(std::iter::once(("s", None)))
        .collect();
    t.sort_unstable();
    t.dedup();
    t
}

/// Highest output derivative order: fmi3GetOutputDerivatives serves `Model::output_derivative`,
/// and the `Model` trait does not declare an order; 1, as in the FMI 2.0 description.
pub const MAX_OUTPUT_DERIVATIVE_ORDER: u32 = 1;

/// The complete modelDescription.xml of a model. Deterministic: no date, so a checked-in copy can
/// be compared byte for byte with what the code generates.
///
/// # Panics
/// If the table does not fit the value-reference mapping (`value_refs::check`).
pub fn model_description(info: &ModelInfo) -> String {
    if let Err(e) = value_refs::check(info) {
        panic!("{}: {e}", info.model_identifier);
    }
    let mut x = String::new();
    let id = info.model_identifier;
    let de = info.default_experiment;
    writeln!(x, r#"<?xml version="1.0" encoding="UTF-8"?>"#).unwrap();
    // The instantiation token is the fmi2 GUID (braces included): fmi3InstantiateCoSimulation
    // compares it exactly as fmi2Instantiate does.
    writeln!(
        x,
        r#"<fmiModelDescription fmiVersion="3.0" modelName="{}" instantiationToken="{}" description="{}" version="{}" generationTool="{GENERATION_TOOL}" variableNamingConvention="flat">"#,
        escape(info.model_name),
        info.guid(),
        escape(info.description),
        escape(info.version)
    )
    .unwrap();
    writeln!(
        x,
        r#"  <CoSimulation modelIdentifier="{id}" needsExecutionTool="false" canBeInstantiatedOnlyOncePerProcess="false" canGetAndSetFMUState="true" canSerializeFMUState="true" providesDirectionalDerivatives="false" providesAdjointDerivatives="false" providesPerElementDependencies="false" canHandleVariableCommunicationStepSize="true" maxOutputDerivativeOrder="{MAX_OUTPUT_DERIVATIVE_ORDER}" providesIntermediateUpdate="true" mightReturnEarlyFromDoStep="true" canReturnEarlyAfterIntermediateUpdate="false" hasEventMode="false" providesEvaluateDiscreteStates="false"/>"#
    )
    .unwrap();

    // `s` always: the unit of `time`.
    let mut used: Vec<&str> = info.variables.iter().filter_map(|v| v.unit).collect();
    used.push("s");
    used.sort_unstable();
    used.dedup();
    x.push_str(&unit_definitions(&used));

    // Units reach the Float64 variables through declared types (one per unit and display unit),
    // not as attributes of each variable: both are valid FMI 3.0, and importers with a strict
    // schema (rust-fmi 0.8) accept only this form.
    writeln!(x, "  <TypeDefinitions>").unwrap();
    for (unit, display) in float_types(info) {
        let display_attr = display
            .map(|d| format!(r#" displayUnit="{}""#, escape(d)))
            .unwrap_or_default();
        writeln!(
            x,
            r#"    <Float64Type name="{}" unit="{}"{display_attr}/>"#,
            escape(&type_name(unit, display)),
            escape(unit)
        )
        .unwrap();
    }
    writeln!(x, "  </TypeDefinitions>").unwrap();

    writeln!(x, "  <LogCategories>").unwrap();
    for (name, desc) in all_log_categories(info) {
        writeln!(
            x,
            r#"    <Category name="{}" description="{}"/>"#,
            escape(name),
            escape(desc)
        )
        .unwrap();
    }
    writeln!(x, "  </LogCategories>").unwrap();
    writeln!(
        x,
        r#"  <DefaultExperiment startTime="{}" stopTime="{}" tolerance="{}" stepSize="{}"/>"#,
        num(de.start_time),
        num(de.stop_time),
        num(de.tolerance),
        num(de.step_size)
    )
    .unwrap();

    writeln!(x, "  <ModelVariables>").unwrap();
    writeln!(
        x,
        r#"    <Float64 name="{TIME_NAME}" valueReference="{TIME_VR}" description="Simulation time" causality="independent" variability="continuous" declaredType="s"/>"#
    )
    .unwrap();
    for v in &info.variables {
        let mut attrs = format!(
            r#"name="{}" valueReference="{}" description="{}" causality="{}" variability="{}""#,
            escape(v.name),
            value_refs::to_fmi3(v.var_type, v.vr),
            escape(v.description),
            v.causality.as_str(),
            v.variability.as_str()
        );
        if let Some(init) = v.initial {
            write!(attrs, r#" initial="{}""#, init.as_str()).unwrap();
        }
        // The inputs a master may set inside an intermediateUpdate callback (crate::intermediate).
        if v.var_type == VarType::Real && v.causality == Causality::Input {
            attrs.push_str(r#" intermediateUpdate="true""#);
        }
        match v.var_type {
            VarType::Real => {
                if let Some(u) = v.unit {
                    let t = type_name(u, v.display_unit);
                    write!(attrs, r#" declaredType="{}""#, escape(&t)).unwrap();
                }
                if let Some(m) = v.min {
                    write!(attrs, r#" min="{}""#, num(m)).unwrap();
                }
                if let Some(m) = v.max {
                    write!(attrs, r#" max="{}""#, num(m)).unwrap();
                }
                if let Some(s) = v.start {
                    write!(attrs, r#" start="{}""#, num(s)).unwrap();
                }
            }
            VarType::Integer => {
                if let Some(m) = v.min {
                    write!(attrs, r#" min="{}""#, m as i64).unwrap();
                }
                if let Some(m) = v.max {
                    write!(attrs, r#" max="{}""#, m as i64).unwrap();
                }
                if let Some(s) = v.start {
                    write!(attrs, r#" start="{}""#, s as i64).unwrap();
                }
            }
            VarType::Boolean => {
                if let Some(s) = v.start {
                    write!(attrs, r#" start="{}""#, s != 0.0).unwrap();
                }
            }
        }
        writeln!(x, "    <{} {attrs}/>", value_refs::type_name(v.var_type)).unwrap();
    }
    writeln!(x, "  </ModelVariables>").unwrap();

    writeln!(x, "  <ModelStructure>").unwrap();
    // No output depends directly on an input: outputs change only in fmi3DoStep (see the same
    // note in fmi2's xml.rs), so a master sees no algebraic loop between coupled FMUs.
    for v in info
        .variables
        .iter()
        .filter(|v| v.causality == Causality::Output)
    {
        writeln!(
            x,
            r#"    <Output valueReference="{}" dependencies=""/>"#,
            value_refs::to_fmi3(v.var_type, v.vr)
        )
        .unwrap();
    }
    // Outputs with initial approx/calculated and calculated parameters (FMI 3.0 section 2.4.8);
    // no dependencies attribute: in Initialization Mode they may depend on every known.
    for v in info.variables.iter().filter(|v| {
        (v.causality == Causality::Output
            && matches!(v.initial, Some(Initial::Approx | Initial::Calculated)))
            || v.causality == Causality::CalculatedParameter
    }) {
        writeln!(
            x,
            r#"    <InitialUnknown valueReference="{}"/>"#,
            value_refs::to_fmi3(v.var_type, v.vr)
        )
        .unwrap();
    }
    writeln!(x, "  </ModelStructure>").unwrap();
    writeln!(x, "</fmiModelDescription>").unwrap();
    x
}
