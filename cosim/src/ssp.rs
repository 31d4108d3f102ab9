//! A system file as an SSP 1.0 archive (`airring export-ssp`) (System Structure and Parameterization,
//! Modelica Association) for other tools: `SystemStructure.ssd` with one component per FMU instance,
//! its parameter values (inline ParameterBindings, in the FMU's SI units after the same unit
//! conversion `airring run` applies), the connections, and the FMUs under `resources/`.
//!
//! SSP 1.0 has no place for a co-simulation algorithm. The macro step and stop time go into
//! `DefaultExperiment` (with OSP's `FixedStepAlgorithm` annotation, which libcosim reads as its
//! step: without a step it crashes) and an `org.airring.algorithm` annotation (kind, order,
//! polynomial orders); other tools ignore the annotations. Connectors carry their type element
//! (libcosim refuses untyped ones); all parameter sets share one name (`SspNames::parameter_set`). Components are written in `algorithm.order`, which is the order in
//! which FMPy's SSP runner steps them (its algorithm is Jacobi-like whatever the order: see
//! docs/fmu-guide.md).
//!
//! Connectors: the connected inputs and outputs, plus the outputs listed in `[output].variables` so
//! that tools record them. Unconnected inputs are left out on purpose: FMPy 0.3.32 looks up a
//! connection for every input connector and, finding none, fails or silently reuses the source of
//! the input before it.

use crate::setup::{parameter_value, ParamValue};
use crate::slave::LoadedFmus;
use crate::system::{split_port, System, SystemError};
use fmi_core::description::ModelDescription;
use fmi_core::variables::Causality;
use std::collections::BTreeMap;
use std::fmt::Write as _;
use std::io::Write as _;
use std::path::{Path, PathBuf};

/// The names an SSP archive carries of the tool that wrote it: the caller's, not the library's.
#[derive(Clone, Debug, PartialEq)]
pub struct SspNames {
    /// `generationTool` of the SSD (e.g. "airring 0.1.0"), and who exported it in the system's
    /// description ("exported by {tool} from FILE").
    pub tool: String,
    /// The name of every component's parameter set: one name, because ecos applies the sets of
    /// one name (`init(parameter_set=...)`); libcosim and FMPy apply each component's set
    /// whatever its name.
    pub parameter_set: String,
    /// The `type` of the annotation that records the algorithm (macro step, orders), in the
    /// tool's own namespace (e.g. "org.airring.algorithm").
    pub algorithm_annotation: String,
}

/// One FMU instance as it goes into the SSD.
struct Component {
    name: String,
    /// `resources/<file>.fmu` inside the archive.
    source: String,
    /// (variable, kind, type) in the FMU's variable order.
    connectors: Vec<(String, &'static str, fmi_core::variables::VarType)>,
    /// (variable, value) in the system file's (sorted) order.
    parameters: Vec<(String, ParamValue)>,
}

/// What was written, for the command's report and for tests.
#[derive(Debug, PartialEq)]
pub struct Exported {
    pub components: usize,
    pub connections: usize,
    pub parameters: usize,
    pub resources: Vec<String>,
}

fn xml_escape(s: &str) -> String {
    s.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
        .replace('"', "&quot;")
}

/// (instance, variable) of "instance.variable" after checking that the variable has `want`.
fn port<'a>(
    sys: &System,
    at: &'a toml::Spanned<String>,
    field: &str,
    fmus: &BTreeMap<String, ModelDescription>,
    want: Causality,
) -> Result<(&'a str, &'a str), SystemError> {
    let (inst, var) = split_port(at.get_ref())
        .ok_or_else(|| sys.error_at(at, field, "expected 'instance.variable'"))?;
    let md = fmus
        .get(inst)
        .ok_or_else(|| sys.error_at(at, field, format!("no FMU instance '{inst}'")))?;
    let v = md
        .variable(var)
        .ok_or_else(|| sys.error_at(at, field, format!("'{inst}' has no variable '{var}'")))?;
    if v.causality != want {
        return Err(sys.error_at(
            at,
            field,
            format!("'{inst}.{var}' is not an {}", want.as_str()),
        ));
    }
    Ok((inst, var))
}

/// Writes the SSP archive for the system file at `system_path`, under the caller's `names`.
pub fn export(system_path: &Path, out: &Path, names: &SspNames) -> Result<Exported, String> {
    let sys = System::load(system_path).map_err(|e| e.to_string())?;
    let f = &sys.file;
    let macro_step_s = sys
        .seconds(&f.algorithm.macro_step, "algorithm.macro_step")
        .map_err(|e| e.to_string())?;
    let stop_time_s = sys
        .seconds(&f.algorithm.stop_time, "algorithm.stop_time")
        .map_err(|e| e.to_string())?;

    // Descriptions and archive names of the FMU files (one copy per distinct file).
    let mut fmus: BTreeMap<String, ModelDescription> = BTreeMap::new();
    let mut files: Vec<(PathBuf, String)> = vec![];
    let mut comps: Vec<Component> = vec![];
    let mut loaded = LoadedFmus::default();
    for e in &f.fmu {
        let name = e.name.get_ref().clone();
        if fmus.contains_key(&name) {
            return Err(sys
                .error_at(
                    &e.name,
                    "fmu.name",
                    format!("instance name '{name}' is used twice"),
                )
                .to_string());
        }
        let path = sys.resolve(e.path.get_ref());
        let fmu = loaded
            .get(&path)
            .map_err(|err| sys.error_at(&e.path, "fmu.path", err).to_string())?;
        let canonical = path
            .canonicalize()
            .map_err(|err| format!("{}: {err}", path.display()))?;
        let source = match files.iter().find(|(p, _)| *p == canonical) {
            Some((_, s)) => s.clone(),
            None => {
                let stem = canonical
                    .file_stem()
                    .and_then(|s| s.to_str())
                    .unwrap_or("fmu");
                let mut s = format!("resources/{stem}.fmu");
                let mut k = 2;
                while files.iter().any(|(_, o)| *o == s) {
                    s = format!("resources/{stem}-{k}.fmu");
                    k += 1;
                }
                files.push((canonical, s.clone()));
                s
            }
        };
        let mut parameters = vec![];
        for (pname, value) in &e.parameters {
            let (_, v) = parameter_value(&sys, fmu.description(), &name, pname, value)
                .map_err(|e| e.to_string())?;
            parameters.push((pname.clone(), v));
        }
        comps.push(Component {
            name: name.clone(),
            source,
            connectors: vec![],
            parameters,
        });
        fmus.insert(name, fmu.description().clone());
    }

    // Connections, and the connectors they and the recorded outputs need.
    let mut used: BTreeMap<(String, String), &'static str> = BTreeMap::new();
    let mut connections = vec![];
    for c in &f.connection {
        let (si, sv) = port(&sys, &c.from, "connection.from", &fmus, Causality::Output)
            .map_err(|e| e.to_string())?;
        let (di, dv) = port(&sys, &c.to, "connection.to", &fmus, Causality::Input)
            .map_err(|e| e.to_string())?;
        if used.insert((di.into(), dv.into()), "input").is_some() {
            return Err(sys
                .error_at(&c.to, "connection.to", "this input is already connected")
                .to_string());
        }
        used.insert((si.into(), sv.into()), "output");
        connections.push((si, sv, di, dv));
    }
    for v in &f.output.variables {
        let (inst, var) = split_port(v.get_ref()).ok_or_else(|| {
            sys.error_at(v, "output.variables", "expected 'instance.variable'")
                .to_string()
        })?;
        let md = fmus.get(inst).ok_or_else(|| {
            sys.error_at(v, "output.variables", format!("no FMU instance '{inst}'"))
                .to_string()
        })?;
        match md.variable(var) {
            Some(sv) if sv.causality == Causality::Output => {
                used.insert((inst.into(), var.into()), "output");
            }
            // Parameters and locals are no SSP connectors of an FMU component; inputs are
            // connectors only when connected.
            Some(_) => {}
            None => {
                return Err(sys
                    .error_at(
                        v,
                        "output.variables",
                        format!("'{inst}' has no variable '{var}'"),
                    )
                    .to_string())
            }
        }
    }
    for c in &mut comps {
        for v in &fmus[&c.name].variables {
            if let Some(kind) = used.get(&(c.name.clone(), v.name.clone())) {
                c.connectors.push((v.name.clone(), kind, v.var_type));
            }
        }
    }
    // FMPy steps the components in document order: write them in the algorithm's order.
    if let Some(order) = &f.algorithm.order {
        let rank = |n: &str| {
            order
                .get_ref()
                .iter()
                .position(|o| o == n)
                .unwrap_or(usize::MAX)
        };
        comps.sort_by_key(|c| rank(&c.name));
    }

    let name = system_path
        .file_stem()
        .and_then(|s| s.to_str())
        .unwrap_or("system")
        .to_string();
    let ssd = ssd_xml(
        &name,
        &comps,
        &connections,
        &sys,
        macro_step_s,
        stop_time_s,
        &system_path.display().to_string(),
        names,
    );
    write_archive(out, &ssd, &files)?;
    Ok(Exported {
        components: comps.len(),
        connections: connections.len(),
        parameters: comps.iter().map(|c| c.parameters.len()).sum(),
        resources: files.into_iter().map(|(_, s)| s).collect(),
    })
}

fn ssd_xml(
    name: &str,
    comps: &[Component],
    connections: &[(&str, &str, &str, &str)],
    sys: &System,
    macro_step_s: f64,
    stop_time_s: f64,
    origin: &str,
    names: &SspNames,
) -> String {
    let alg = &sys.file.algorithm;
    let mut s = String::new();
    let n = xml_escape(name);
    s.push_str("<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n");
    let _ = writeln!(
        s,
        "<ssd:SystemStructureDescription xmlns:ssc=\"http://ssp-standard.org/SSP1/SystemStructureCommon\" xmlns:ssd=\"http://ssp-standard.org/SSP1/SystemStructureDescription\" xmlns:ssv=\"http://ssp-standard.org/SSP1/SystemStructureParameterValues\" xmlns:osp=\"http://opensimulationplatform.com/SSP/OSPAnnotations\" version=\"1.0\" name=\"{n}\" generationTool=\"{}\">",
        xml_escape(&names.tool)
    );
    let _ = writeln!(
        s,
        "  <ssd:System name=\"{n}\" description=\"exported by {} from {}\">\n    <ssd:Elements>",
        xml_escape(&names.tool),
        xml_escape(origin)
    );
    for c in comps {
        let _ = writeln!(
            s,
            "      <ssd:Component name=\"{}\" type=\"application/x-fmu-sharedlibrary\" source=\"{}\">",
            xml_escape(&c.name),
            xml_escape(&c.source)
        );
        if !c.connectors.is_empty() {
            s.push_str("        <ssd:Connectors>\n");
            for (v, kind, var_type) in &c.connectors {
                // The type element is optional in SSP 1.0, but libcosim refuses a connector
                // without one ("A valid connector type was not found!").
                let _ = writeln!(
                    s,
                    "          <ssd:Connector name=\"{}\" kind=\"{kind}\"><ssc:{}/></ssd:Connector>",
                    xml_escape(v),
                    var_type.as_str()
                );
            }
            s.push_str("        </ssd:Connectors>\n");
        }
        if !c.parameters.is_empty() {
            let _ = writeln!(
                s,
                "        <ssd:ParameterBindings>\n          <ssd:ParameterBinding>\n            <ssd:ParameterValues>\n              <ssv:ParameterSet version=\"1.0\" name=\"{}\">\n                <ssv:Parameters>",
                xml_escape(&names.parameter_set)
            );
            for (p, v) in &c.parameters {
                // Values in the FMU variable's own (SI) unit, so no unit attribute is needed.
                let (tag, value) = match v {
                    ParamValue::Real(x) => ("Real", format!("{x:?}")),
                    ParamValue::Integer(i) => ("Integer", i.to_string()),
                    ParamValue::Boolean(b) => ("Boolean", b.to_string()),
                };
                let _ = writeln!(
                    s,
                    "                  <ssv:Parameter name=\"{}\"><ssv:{tag} value=\"{value}\"/></ssv:Parameter>",
                    xml_escape(p)
                );
            }
            s.push_str("                </ssv:Parameters>\n              </ssv:ParameterSet>\n            </ssd:ParameterValues>\n          </ssd:ParameterBinding>\n        </ssd:ParameterBindings>\n");
        }
        s.push_str("      </ssd:Component>\n");
    }
    s.push_str("    </ssd:Elements>\n");
    if !connections.is_empty() {
        s.push_str("    <ssd:Connections>\n");
        for (si, sv, di, dv) in connections {
            let _ = writeln!(
                s,
                "      <ssd:Connection startElement=\"{}\" startConnector=\"{}\" endElement=\"{}\" endConnector=\"{}\"/>",
                xml_escape(si),
                xml_escape(sv),
                xml_escape(di),
                xml_escape(dv)
            );
        }
        s.push_str("    </ssd:Connections>\n");
    }
    let order = comps
        .iter()
        .map(|c| c.name.as_str())
        .collect::<Vec<_>>()
        .join(" ");
    let _ = writeln!(
        s,
        "    <ssd:Annotations>\n      <ssc:Annotation type=\"{}\">\n        <Algorithm kind=\"{}\" order=\"{}\" macroStep=\"{macro_step_s:?}\" extrapolationOrder=\"{}\" interpolationOrder=\"{}\"/>\n      </ssc:Annotation>\n    </ssd:Annotations>",
        xml_escape(&names.algorithm_annotation),
        xml_escape(alg.kind.get_ref()),
        xml_escape(&order),
        alg.extrapolation_order.get_ref(),
        alg.interpolation_order.get_ref()
    );
    s.push_str("  </ssd:System>\n");
    let _ = writeln!(
        s,
        "  <ssd:DefaultExperiment startTime=\"0.0\" stopTime=\"{stop_time_s:?}\">\n    <ssd:Annotations>\n      <ssc:Annotation type=\"com.opensimulationplatform\">\n        <osp:Algorithm>\n          <osp:FixedStepAlgorithm baseStepSize=\"{macro_step_s:?}\"/>\n        </osp:Algorithm>\n      </ssc:Annotation>\n    </ssd:Annotations>\n  </ssd:DefaultExperiment>\n</ssd:SystemStructureDescription>"
    );
    s
}

/// Builds the archive in memory (an FMU is a few MB), then writes it whole under a temporary name
/// and renames it into place: a full disk leaves no truncated archive under the final name, and
/// a link at `out` is replaced, not written through.
fn write_archive(out: &Path, ssd: &str, files: &[(PathBuf, String)]) -> Result<(), String> {
    let err = |e: &dyn std::fmt::Display| format!("{}: {e}", out.display());
    let mut zip = zip::ZipWriter::new(std::io::Cursor::new(Vec::new()));
    let deflated = zip::write::SimpleFileOptions::default()
        .compression_method(zip::CompressionMethod::Deflated);
    // FMUs are zip archives already.
    let stored =
        zip::write::SimpleFileOptions::default().compression_method(zip::CompressionMethod::Stored);
    zip.start_file("SystemStructure.ssd", deflated)
        .map_err(|e| err(&e))?;
    zip.write_all(ssd.as_bytes()).map_err(|e| err(&e))?;
    for (path, name) in files {
        let bytes = std::fs::read(path).map_err(|e| format!("{}: {e}", path.display()))?;
        zip.start_file(name.as_str(), stored).map_err(|e| err(&e))?;
        zip.write_all(&bytes).map_err(|e| err(&e))?;
    }
    let bytes = zip.finish().map_err(|e| err(&e))?.into_inner();
    crate::files::write_whole(out, &bytes).map_err(|e| err(&e))
}
