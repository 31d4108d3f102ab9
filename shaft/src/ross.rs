//! Rotors saved by ROSS (`Rotor.save("rotor.toml")`, ross-rotordynamics 2.3.0): read as they are,
//! so an engineer brings the model she already has.
//!
//! The file holds `ross_version`, a `[parameters]` table (operating speeds, not needed here) and
//! one table per element, named `ClassName_tag`: `ShaftElement_*` (with its `material`),
//! `DiskElement_*`, `BearingElement_*`, `PointMass_*`. Elements of other classes (seals,
//! magnetic or ball bearings, couplings) are refused by name, and so is anything this model
//! would otherwise drop: frequency-dependent bearing coefficients, bearings linked to support
//! masses (`n_link`), point masses off the shaft, anisotropic point masses.

use crate::element::{Material, ShaftElement, ShearCoefficient};
use crate::model::{Disk, PointMass, ShaftModel, Support};
use crate::ShaftError;
use std::path::Path;
use toml::{Table, Value};

/// The ROSS version whose file format this reader knows (the one the tests install).
pub const ROSS_VERSION: &str = "2.3.0";

/// A rotor read from a ROSS file, and what of the file the model does not use (the axial
/// coefficients of bearings: AirRing's rotor has no axial motion).
#[derive(Clone, Debug)]
pub struct RossRotor {
    pub model: ShaftModel,
    pub notes: Vec<String>,
}

/// Reads a rotor file saved by ROSS.
pub fn read(path: &Path) -> Result<RossRotor, ShaftError> {
    let name = path.display();
    if path
        .extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("json"))
    {
        return Err(ShaftError::File(format!(
            "{name}: ROSS's JSON rotor files are not read; save the rotor as TOML \
             (rotor.save(\"rotor.toml\"))"
        )));
    }
    let text = std::fs::read_to_string(path)
        .map_err(|e| ShaftError::File(format!("{name}: cannot be read: {e}")))?;
    parse(&text).map_err(|e| ShaftError::File(format!("{name}: {e}")))
}

/// Parses the text of a ROSS rotor file.
pub fn parse(text: &str) -> Result<RossRotor, String> {
    let doc: Table = text.parse().map_err(|e: toml::de::Error| {
        // Line and column, not the file's text.
        let at = e
            .span()
            .map(|s| {
                let line = text[..s.start].matches('\n').count() + 1;
                let col = s.start - text[..s.start].rfind('\n').map_or(0, |p| p + 1) + 1;
                format!(" at line {line}, column {col}")
            })
            .unwrap_or_default();
        format!("not a TOML file{at}: {}", e.message())
    })?;
    match doc.get("ross_version") {
        Some(Value::String(v)) if v == ROSS_VERSION => {}
        Some(Value::String(v)) => {
            return Err(format!(
                "written by ROSS {v}; AirRing reads the files of ROSS {ROSS_VERSION}: load the \
                 rotor in ROSS {ROSS_VERSION} (pip install ross-rotordynamics=={ROSS_VERSION}) \
                 and save it again"
            ))
        }
        _ => return Err("no ross_version: not a rotor saved by ROSS (Rotor.save)".to_string()),
    }
    let mut shafts: Vec<(i64, String, ShaftElement)> = vec![];
    let mut model = ShaftModel::default();
    let mut notes = vec![];
    let mut point_masses: Vec<(String, PointMass)> = vec![];
    for (key, value) in &doc {
        if key == "ross_version" || key == "parameters" || key.starts_with('_') {
            continue;
        }
        let Value::Table(t) = value else {
            return Err(format!("[{key}] is not a table"));
        };
        let class = key.split('_').next().unwrap_or("");
        let tag = t
            .get("tag")
            .and_then(Value::as_str)
            .unwrap_or(key)
            .to_string();
        let f = Fields { section: key, t };
        match class {
            "ShaftElement" => {
                let (n, e) = shaft_element(&f)?;
                shafts.push((n, key.clone(), e));
            }
            "DiskElement" => model.disks.push(Disk {
                node: f.node("n")?,
                mass_kg: f.num("m")?,
                id_kg_m2: f.num("Id")?,
                ip_kg_m2: f.num("Ip")?,
                tag,
            }),
            "BearingElement" => {
                let (s, note) = bearing(&f, tag)?;
                model.supports.push(s);
                notes.extend(note);
            }
            "PointMass" => {
                let m = f.opt_num("m")?;
                let (mx, my) = (f.opt_num("mx")?, f.opt_num("my")?);
                let (mx, my) = match (m, mx, my) {
                    (Some(m), _, _) => (m, m),
                    (None, Some(x), Some(y)) => (x, y),
                    _ => return Err(format!("[{key}]: no mass m (or mx and my)")),
                };
                if mx != my {
                    return Err(format!(
                        "[{key}]: mx = {} and my = {} differ; anisotropic point masses are not \
                         modelled (give one mass m)",
                        bearing::num::Num(mx),
                        bearing::num::Num(my)
                    ));
                }
                point_masses.push((
                    key.clone(),
                    PointMass {
                        node: f.node("n")?,
                        mass_kg: mx,
                        tag,
                    },
                ));
            }
            other => {
                return Err(format!(
                    "[{key}]: a ROSS {other} is not modelled by AirRing (it models shaft \
                     elements, disks, point masses and linear bearings); remove it or replace \
                     it by a BearingElement with its coefficients"
                ))
            }
        }
    }
    if shafts.is_empty() {
        return Err("no ShaftElement: the file holds no shaft".into());
    }
    shafts.sort_by_key(|(n, _, _)| *n);
    for (i, (n, key, _)) in shafts.iter().enumerate() {
        if *n != i as i64 {
            return Err(format!(
                "[{key}]: element number n = {n}, expected {i}: the shaft elements must be \
                 numbered 0, 1, 2, ... without gaps or repeats"
            ));
        }
    }
    model.elements = shafts.into_iter().map(|(_, _, e)| e).collect();
    let nodes = model.n_nodes();
    for (key, p) in point_masses {
        if p.node >= nodes {
            return Err(format!(
                "[{key}]: a point mass at node {}, off the shaft (nodes 0 to {}): support \
                 structures (a bearing's n_link to a mass) are not modelled",
                p.node,
                nodes - 1
            ));
        }
        model.point_masses.push(p);
    }
    model.validate().map_err(|e| e.to_string())?;
    Ok(RossRotor { model, notes })
}

struct Fields<'a> {
    section: &'a str,
    t: &'a Table,
}

impl Fields<'_> {
    fn get(&self, field: &str) -> Result<&Value, String> {
        self.t
            .get(field)
            .ok_or_else(|| format!("[{}]: no field {field}", self.section))
    }
    fn num_of(&self, field: &str, v: &Value) -> Result<f64, String> {
        match v {
            Value::Float(x) => Ok(*x),
            Value::Integer(i) => Ok(*i as f64),
            _ => Err(format!("[{}]: {field} is not a number", self.section)),
        }
    }
    fn num(&self, field: &str) -> Result<f64, String> {
        self.num_of(field, self.get(field)?)
    }
    fn opt_num(&self, field: &str) -> Result<Option<f64>, String> {
        match self.t.get(field) {
            None => Ok(None),
            Some(v) => self.num_of(field, v).map(Some),
        }
    }
    fn node(&self, field: &str) -> Result<usize, String> {
        match self.get(field)? {
            Value::Integer(i) if *i >= 0 => Ok(*i as usize),
            _ => Err(format!(
                "[{}]: {field} is not a node number (an integer >= 0)",
                self.section
            )),
        }
    }
    fn bool_or(&self, field: &str, default: bool) -> Result<bool, String> {
        match self.t.get(field) {
            None => Ok(default),
            Some(Value::Boolean(b)) => Ok(*b),
            Some(_) => Err(format!("[{}]: {field} is not true or false", self.section)),
        }
    }
    /// A bearing coefficient: a number or a list of numbers (one per frequency); returns the
    /// list.
    fn coefficients(&self, field: &str) -> Result<Vec<f64>, String> {
        match self.t.get(field) {
            None => Ok(vec![0.0]),
            Some(Value::Array(a)) => a.iter().map(|v| self.num_of(field, v)).collect(),
            Some(v) => Ok(vec![self.num_of(field, v)?]),
        }
    }
}

fn shaft_element(f: &Fields) -> Result<(i64, ShaftElement), String> {
    let n = match f.get("n")? {
        Value::Integer(i) => *i,
        _ => return Err(format!("[{}]: n is not an integer", f.section)),
    };
    let Value::Table(mt) = f.get("material")? else {
        return Err(format!("[{}]: material is not a table", f.section));
    };
    let msec = format!("{}.material", f.section);
    let m = Fields {
        section: &msec,
        t: mt,
    };
    let material = Material {
        name: mt
            .get("name")
            .and_then(Value::as_str)
            .unwrap_or("")
            .to_string(),
        rho_kg_m3: m.num("rho")?,
        e_pa: m.num("E")?,
        g_pa: m.num("G_s")?,
    };
    let idl = f.num("idl")?;
    let odl = f.num("odl")?;
    let shear_coefficient = match f.t.get("shear_method_calc").and_then(Value::as_str) {
        None | Some("cowper") => ShearCoefficient::Cowper,
        Some("hutchinson") => ShearCoefficient::Hutchinson,
        Some(other) => {
            return Err(format!(
                "[{}]: shear_method_calc = {other:?}: ROSS knows \"cowper\" and \"hutchinson\"",
                f.section
            ))
        }
    };
    let e = ShaftElement {
        length_m: f.num("L")?,
        id_left_m: idl,
        od_left_m: odl,
        id_right_m: f.opt_num("idr")?.unwrap_or(idl),
        od_right_m: f.opt_num("odr")?.unwrap_or(odl),
        material,
        shear_effects: f.bool_or("shear_effects", true)?,
        rotary_inertia: f.bool_or("rotary_inertia", true)?,
        gyroscopic: f.bool_or("gyroscopic", true)?,
        shear_coefficient,
        axial_force_n: f.opt_num("axial_force")?.unwrap_or(0.0),
        torque_n_m: f.opt_num("torque")?.unwrap_or(0.0),
        alpha_1_s: f.opt_num("alpha")?.unwrap_or(0.0),
        beta_s: f.opt_num("beta")?.unwrap_or(0.0),
    };
    e.validate(n.max(0) as usize)
        .map_err(|err| format!("[{}]: {err}", f.section))?;
    Ok((n, e))
}

fn bearing(f: &Fields, tag: String) -> Result<(Support, Option<String>), String> {
    if let Some(link) = f.t.get("n_link") {
        if !matches!(link, Value::String(s) if s == "None") {
            return Err(format!(
                "[{}]: n_link links the bearing to a support mass; support structures are not \
                 modelled (attach the bearing to the ground: remove n_link and the point mass)",
                f.section
            ));
        }
    }
    let mut constant = |field: &str| -> Result<f64, String> {
        let c = f.coefficients(field)?;
        let first = *c
            .first()
            .ok_or_else(|| format!("[{}]: {field} is an empty list", f.section))?;
        if c.iter().any(|v| *v != first) {
            return Err(format!(
                "[{}]: {field} changes with frequency ({} values); frequency-dependent \
                 bearing coefficients are not modelled: give constant coefficients",
                f.section,
                c.len()
            ));
        }
        Ok(first)
    };
    let mat = |c: &mut dyn FnMut(&str) -> Result<f64, String>, p: &str| {
        Ok::<_, String>([
            [c(&format!("{p}xx"))?, c(&format!("{p}xy"))?],
            [c(&format!("{p}yx"))?, c(&format!("{p}yy"))?],
        ])
    };
    let k = mat(&mut constant, "k")?;
    let c = mat(&mut constant, "c")?;
    let m = mat(&mut constant, "m")?;
    let axial: Vec<String> = ["kzz", "czz", "mzz"]
        .into_iter()
        .filter(|a| f.coefficients(a).is_ok_and(|v| v.iter().any(|x| *x != 0.0)))
        .map(String::from)
        .collect();
    let note = (!axial.is_empty()).then(|| {
        format!(
            "[{}]: {} act on the axial motion, which AirRing's rotor does not have; not used",
            f.section,
            axial.join(", ")
        )
    });
    Ok((
        Support {
            node: f.node("n")?,
            k_n_m: k,
            c_n_s_m: c,
            m_kg: m,
            tag,
        },
        note,
    ))
}

#[cfg(test)]
mod tests {
    use super::*;

    const SMALL: &str = r#"
ross_version = "2.3.0"
[parameters]
["ShaftElement_S1"]
L = 0.25
idl = 0.0
odl = 0.05
n = 1
tag = "S1"
["ShaftElement_S1".material]
name = "Steel"
rho = 7810.0
E = 211000000000.0
G_s = 81200000000.0
["ShaftElement_S0"]
L = 0.25
idl = 0.0
odl = 0.05
idr = 0.0
odr = 0.05
n = 0
tag = "S0"
["ShaftElement_S0".material]
name = "Steel"
rho = 7810.0
E = 211000000000.0
G_s = 81200000000.0
["DiskElement_D"]
n = 1
m = 32.5
Id = 0.178
Ip = 0.329
["BearingElement_B0"]
n = 0
kxx = [ 1000000.0,]
kyy = [ 800000.0,]
cxx = [ 50,]
kzz = [ 0,]
"#;

    #[test]
    fn a_small_rotor_is_read_in_element_order() {
        let r = parse(SMALL).unwrap();
        assert_eq!(r.model.elements.len(), 2);
        assert_eq!(r.model.disks[0].node, 1);
        assert_eq!(r.model.supports[0].k_n_m, [[1e6, 0.0], [0.0, 8e5]]);
        assert_eq!(r.model.supports[0].c_n_s_m[0][0], 50.0);
        assert!(r.notes.is_empty());
    }

    #[test]
    fn what_the_model_would_drop_is_refused_by_name() {
        let other = SMALL.replace("ross_version = \"2.3.0\"", "ross_version = \"1.5.0\"");
        let e = parse(&other).unwrap_err();
        assert!(e.contains("ROSS 1.5.0") && e.contains("2.3.0"), "{e}");

        let freq = SMALL.replace("kxx = [ 1000000.0,]", "kxx = [ 1e6, 2e6 ]");
        let e = parse(&freq).unwrap_err();
        assert!(e.contains("BearingElement_B0") && e.contains("kxx"), "{e}");

        let seal = format!("{SMALL}\n[\"SealElement_L\"]\nn = 0\n");
        let e = parse(&seal).unwrap_err();
        assert!(
            e.contains("SealElement_L") && e.contains("not modelled"),
            "{e}"
        );

        let gap = SMALL.replace("n = 1\ntag = \"S1\"", "n = 2\ntag = \"S1\"");
        let e = parse(&gap).unwrap_err();
        assert!(e.contains("ShaftElement_S1") && e.contains("n = 2"), "{e}");

        let inner = SMALL.replace(
            "idl = 0.0\nodl = 0.05\nn = 1",
            "idl = 0.06\nodl = 0.05\nn = 1",
        );
        let e = parse(&inner).unwrap_err();
        assert!(e.contains("ShaftElement_S1") && e.contains("idl"), "{e}");

        let off = SMALL.replace("[\"DiskElement_D\"]\nn = 1", "[\"DiskElement_D\"]\nn = 9");
        let e = parse(&off).unwrap_err();
        assert!(e.contains("DiskElement_D") && e.contains("node 9"), "{e}");

        let axial = SMALL.replace("kzz = [ 0,]", "kzz = [ 1e5,]");
        let r = parse(&axial).unwrap();
        assert!(r.notes[0].contains("kzz"), "{:?}", r.notes);
    }
}
