//! modelDescription.xml from the variable table (the only place the interface is written down).

use fmi_core::units;
use fmi_core::variables::{Causality, Initial, ModelInfo, VarType};
use fmi_core::xml::{escape, num, unit_definitions};
use std::fmt::Write;

pub const GENERATION_TOOL: &str = "AirRing fmi2 layer";

/// The complete modelDescription.xml of a model. Deterministic: no date, so the checked-in copies can
/// be compared byte for byte with what the code generates.
pub fn model_description(info: &ModelInfo) -> String {
    let mut x = String::new();
    let id = info.model_identifier;
    let de = info.default_experiment;
    writeln!(x, r#"<?xml version="1.0" encoding="UTF-8"?>"#).unwrap();
    writeln!(
        x,
        r#"<fmiModelDescription fmiVersion="2.0" modelName="{}" guid="{}" description="{}" version="{}" generationTool="{GENERATION_TOOL}" variableNamingConvention="flat" numberOfEventIndicators="0">"#,
        escape(info.model_name),
        info.guid(),
        escape(info.description),
        escape(info.version)
    )
    .unwrap();
    writeln!(
        x,
        r#"  <CoSimulation modelIdentifier="{id}" needsExecutionTool="false" canHandleVariableCommunicationStepSize="true" canInterpolateInputs="true" maxOutputDerivativeOrder="1" canRunAsynchronuously="false" canBeInstantiatedOnlyOncePerProcess="false" canNotUseMemoryManagementFunctions="true" canGetAndSetFMUstate="true" canSerializeFMUstate="true" providesDirectionalDerivative="false"/>"#
    )
    .unwrap();

    let mut used: Vec<&str> = info.variables.iter().filter_map(|v| v.unit).collect();
    used.sort_unstable();
    used.dedup();
    if !used.is_empty() {
        x.push_str(&unit_definitions(&used));
    }

    writeln!(x, "  <LogCategories>").unwrap();
    for (name, desc) in info.all_log_categories() {
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
    for (i, v) in info.variables.iter().enumerate() {
        writeln!(x, "    <!-- index {} -->", i + 1).unwrap();
        let mut attrs = format!(
            r#"name="{}" valueReference="{}" description="{}" causality="{}" variability="{}""#,
            escape(v.name),
            v.vr,
            escape(v.description),
            v.causality.as_str(),
            v.variability.as_str()
        );
        if let Some(init) = v.initial {
            write!(attrs, r#" initial="{}""#, init.as_str()).unwrap();
        }
        let mut typed = String::new();
        match v.var_type {
            VarType::Real => {
                if let Some(u) = v.unit {
                    write!(typed, r#" unit="{}""#, escape(u)).unwrap();
                }
                if let Some(d) = v.display_unit {
                    write!(typed, r#" displayUnit="{}""#, escape(d)).unwrap();
                }
                if let Some(m) = v.min {
                    write!(typed, r#" min="{}""#, num(m)).unwrap();
                }
                if let Some(m) = v.max {
                    write!(typed, r#" max="{}""#, num(m)).unwrap();
                }
                if let Some(s) = v.start {
                    write!(typed, r#" start="{}""#, num(s)).unwrap();
                }
            }
            VarType::Integer => {
                if let Some(m) = v.min {
                    write!(typed, r#" min="{}""#, m as i64).unwrap();
                }
                if let Some(m) = v.max {
                    write!(typed, r#" max="{}""#, m as i64).unwrap();
                }
                if let Some(s) = v.start {
                    write!(typed, r#" start="{}""#, s as i64).unwrap();
                }
            }
            VarType::Boolean => {
                if let Some(s) = v.start {
                    write!(typed, r#" start="{}""#, s != 0.0).unwrap();
                }
            }
        }
        writeln!(x, "    <ScalarVariable {attrs}>").unwrap();
        writeln!(x, "      <{}{typed}/>", v.var_type.as_str()).unwrap();
        writeln!(x, "    </ScalarVariable>").unwrap();
    }
    writeln!(x, "  </ModelVariables>").unwrap();

    writeln!(x, "  <ModelStructure>").unwrap();
    let outputs: Vec<usize> = info
        .variables
        .iter()
        .enumerate()
        .filter(|(_, v)| v.causality == Causality::Output)
        .map(|(i, _)| i + 1)
        .collect();
    if !outputs.is_empty() {
        writeln!(x, "    <Outputs>").unwrap();
        // No output depends directly on an input: this layer changes outputs only in doStep
        // (after fmi2SetReal of an input in step mode they keep their values until the next
        // step), so a master sees no algebraic loop between coupled FMUs. (In initialization
        // mode outputs do follow the inputs: InitialUnknowns keep the default, all dependencies.)
        for i in &outputs {
            writeln!(x, r#"      <Unknown index="{i}" dependencies=""/>"#).unwrap();
        }
        writeln!(x, "    </Outputs>").unwrap();
    }
    let initial: Vec<usize> = info
        .variables
        .iter()
        .enumerate()
        .filter(|(_, v)| {
            (v.causality == Causality::Output
                && matches!(v.initial, Some(Initial::Approx | Initial::Calculated)))
                || v.causality == Causality::CalculatedParameter
        })
        .map(|(i, _)| i + 1)
        .collect();
    if !initial.is_empty() {
        writeln!(x, "    <InitialUnknowns>").unwrap();
        for i in &initial {
            writeln!(x, r#"      <Unknown index="{i}"/>"#).unwrap();
        }
        writeln!(x, "    </InitialUnknowns>").unwrap();
    }
    writeln!(x, "  </ModelStructure>").unwrap();
    writeln!(x, "</fmiModelDescription>").unwrap();
    x
}

/// documentation/index.html: the model's own text plus the generated variable table.
pub fn documentation(info: &ModelInfo) -> String {
    let mut rows = String::new();
    for v in &info.variables {
        let start = v.start.map(num).unwrap_or_default();
        let display = match (v.unit, v.display_unit, v.start) {
            (Some(u), Some(d), Some(s)) => units::unit(u)
                .and_then(|ud| ud.display_units.iter().find(|x| x.0 == d))
                .map(|(_, f, o)| format!(" ({} {d})", num(f * s + o)))
                .unwrap_or_default(),
            _ => String::new(),
        };
        writeln!(
            rows,
            "<tr><td><code>{}</code></td><td>{}</td><td>{}</td><td>{}</td><td>{}{}</td><td>{}</td></tr>",
            escape(v.name),
            v.causality.as_str(),
            v.var_type.as_str(),
            escape(v.unit.unwrap_or("")),
            start,
            escape(&display),
            escape(v.description)
        )
        .unwrap();
    }
    format!(
        "<!DOCTYPE html>\n<html><head><meta charset=\"utf-8\"><title>{name}</title></head><body>\n<h1>{name}</h1>\n{doc}\n<h2>Variables</h2>\n<p>All values in SI units on the interface; display units are declared in modelDescription.xml.</p>\n<table border=\"1\" cellpadding=\"3\"><tr><th>name</th><th>causality</th><th>type</th><th>unit</th><th>default</th><th>description</th></tr>\n{rows}</table>\n</body></html>\n",
        name = escape(info.model_name),
        doc = info.documentation_html
    )
}
