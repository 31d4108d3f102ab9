//! The `[shaft]` table of a design file: a flexible rotor written out (shaft elements, material,
//! disks, point masses) or a ROSS rotor file named, and the nodes of bearings C and T.
//!
//! ```toml
//! [shaft]
//! material = "steel"                       # or { rho = "7810 kg/m3", E = "211 GPa", G = "81.2 GPa" }
//! elements = [                             # from the turbine end; n repeats a row
//!   { L = "12 mm", od = "18 mm", n = 5 },
//!   { L = "12 mm", od = "22 mm", id = "6 mm", n = 10 },
//!   { L = "12 mm", od = "18 mm", n = 5 },
//! ]
//! disks = [{ node = 1, m = "350 g", Id = "2.0e-4 kg.m2", Ip = "3.6e-4 kg.m2", tag = "compressor" }]
//! point_masses = [{ node = 10, m = "20 g" }]
//! bearing_nodes = { compressor = 5, turbine = 15 }
//! ```
//!
//! or `rotor_file = "rotor.toml"` (saved by ROSS 2.3.0; relative to the design file) with
//! `bearing_nodes`. A conical element gives `od_right` (and `id_right`). Values are numbers in SI
//! units or "number unit" strings; every error names the entry.

use shaft::{Disk, Material, PointMass, ShaftElement, ShaftModel};
use std::path::Path;
use toml::{Table, Value};

/// A flexible rotor of a design file and the nodes of its two air ring bearings [C, T].
#[derive(Clone, Debug, PartialEq)]
pub struct ShaftSpec {
    pub model: ShaftModel,
    pub bearing_nodes: [usize; 2],
    /// Notes of the ROSS reader (what of the file is not used).
    pub notes: Vec<String>,
}

/// Units by quantity: (unit, factor to SI).
const LENGTH: &[(&str, f64)] = &[("m", 1.0), ("mm", 1e-3), ("um", 1e-6), ("cm", 1e-2)];
const MASS: &[(&str, f64)] = &[("kg", 1.0), ("g", 1e-3)];
const INERTIA: &[(&str, f64)] = &[
    ("kg.m2", 1.0),
    ("kg m2", 1.0),
    ("kg*m2", 1.0),
    ("kg.mm2", 1e-6),
    ("kg mm2", 1e-6),
    ("g.mm2", 1e-9),
    ("g mm2", 1e-9),
];
const MODULUS: &[(&str, f64)] = &[("Pa", 1.0), ("kPa", 1e3), ("MPa", 1e6), ("GPa", 1e9)];
const DENSITY: &[(&str, f64)] = &[("kg/m3", 1.0), ("g/cm3", 1e3)];

/// A value: a number (SI) or "number unit" with one of `units`.
fn quantity(v: &Value, at: &str, units: &[(&str, f64)]) -> Result<f64, String> {
    let x = match v {
        Value::Float(x) => *x,
        Value::Integer(i) => *i as f64,
        Value::String(s) => {
            let s = s.trim();
            let split = s
                .find(|c: char| c.is_whitespace())
                .ok_or_else(|| format!("{at} = {s:?}: write \"number unit\" or a number in SI"))?;
            let (num, unit) = (s[..split].trim(), s[split..].trim());
            let x: f64 = num
                .parse()
                .map_err(|_| format!("{at} = {s:?}: {num:?} is not a number"))?;
            let factor = units
                .iter()
                .find(|(u, _)| *u == unit)
                .map(|(_, f)| *f)
                .ok_or_else(|| {
                    format!(
                        "{at} = {s:?}: unit {unit:?} not known here (one of {})",
                        units.iter().map(|(u, _)| *u).collect::<Vec<_>>().join(", ")
                    )
                })?;
            x * factor
        }
        _ => return Err(format!("{at} must be a number or a \"number unit\" string")),
    };
    if x.is_finite() {
        Ok(x)
    } else {
        Err(format!("{at} must be finite"))
    }
}

fn table<'a>(v: &'a Value, at: &str) -> Result<&'a Table, String> {
    v.as_table()
        .ok_or_else(|| format!("{at} must be a table {{ ... }}"))
}

fn only_keys(t: &Table, at: &str, allowed: &[&str]) -> Result<(), String> {
    match t.keys().find(|k| !allowed.contains(&k.as_str())) {
        Some(k) => Err(format!(
            "{at}: unknown key {k:?} (known: {})",
            allowed.join(", ")
        )),
        None => Ok(()),
    }
}

fn node(t: &Table, at: &str) -> Result<usize, String> {
    match t.get("node") {
        Some(Value::Integer(i)) if *i >= 0 => Ok(*i as usize),
        Some(_) => Err(format!("{at}.node must be an integer >= 0")),
        None => Err(format!("{at}: no node")),
    }
}

/// Parses the `[shaft]` table; `dir` is the design file's folder (for `rotor_file`).
pub fn parse(t: &Table, dir: Option<&Path>) -> Result<ShaftSpec, String> {
    const AT: &str = "[shaft]";
    only_keys(
        t,
        AT,
        &[
            "rotor_file",
            "material",
            "elements",
            "disks",
            "point_masses",
            "bearing_nodes",
        ],
    )?;
    let bn = table(
        t.get("bearing_nodes")
            .ok_or_else(|| format!("{AT}: no bearing_nodes = {{ compressor = N, turbine = M }}"))?,
        "[shaft] bearing_nodes",
    )?;
    only_keys(bn, "[shaft] bearing_nodes", &["compressor", "turbine"])?;
    let side = |k: &str| match bn.get(k) {
        Some(Value::Integer(i)) if *i >= 0 => Ok(*i as usize),
        _ => Err(format!(
            "[shaft] bearing_nodes.{k} must be a node number (an integer >= 0)"
        )),
    };
    let bearing_nodes = [side("compressor")?, side("turbine")?];
    let (model, notes) = match t.get("rotor_file") {
        Some(v) => {
            if let Some(k) = ["material", "elements", "disks", "point_masses"]
                .iter()
                .find(|k| t.contains_key(**k))
            {
                return Err(format!(
                    "{AT}: rotor_file and {k} both describe the rotor: keep one"
                ));
            }
            let name = v
                .as_str()
                .ok_or_else(|| format!("{AT} rotor_file must be a path string"))?;
            let path = match dir {
                Some(d) => d.join(name),
                None => name.into(),
            };
            let r = shaft::ross::read(&path).map_err(|e| format!("{AT} rotor_file: {e}"))?;
            (r.model, r.notes)
        }
        None => (written_out(t)?, vec![]),
    };
    for (&n, s) in bearing_nodes.iter().zip(["compressor", "turbine"]) {
        if n >= model.n_nodes() {
            return Err(format!(
                "[shaft] bearing_nodes.{s} = {n} is off the shaft (nodes 0 to {})",
                model.n_nodes() - 1
            ));
        }
    }
    if bearing_nodes[0] == bearing_nodes[1] {
        return Err(format!(
            "[shaft] bearing_nodes: compressor and turbine at node {}: each bearing needs a node of \
             its own",
            bearing_nodes[0]
        ));
    }
    Ok(ShaftSpec {
        model,
        bearing_nodes,
        notes,
    })
}

fn written_out(t: &Table) -> Result<ShaftModel, String> {
    let material = match t.get("material") {
        None => Material::steel(),
        Some(Value::String(s)) if s == "steel" => Material::steel(),
        Some(Value::String(s)) => {
            return Err(format!(
                "[shaft] material = {s:?}: the named material is \"steel\"; give others as \
                 {{ rho = \"... kg/m3\", E = \"... GPa\", G = \"... GPa\" }}"
            ))
        }
        Some(v) => {
            let m = table(v, "[shaft] material")?;
            only_keys(m, "[shaft] material", &["name", "rho", "E", "G"])?;
            let get = |k: &str, units| {
                let v = m
                    .get(k)
                    .ok_or_else(|| format!("[shaft] material: no {k}"))?;
                quantity(v, &format!("[shaft] material.{k}"), units)
            };
            Material {
                name: m
                    .get("name")
                    .and_then(Value::as_str)
                    .unwrap_or("material")
                    .into(),
                rho_kg_m3: get("rho", DENSITY)?,
                e_pa: get("E", MODULUS)?,
                g_pa: get("G", MODULUS)?,
            }
        }
    };
    let rows = t
        .get("elements")
        .and_then(Value::as_array)
        .ok_or_else(|| "[shaft]: no elements = [ { L = ..., od = ... }, ... ]".to_string())?;
    let mut elements = vec![];
    for (i, row) in rows.iter().enumerate() {
        let at = format!("[shaft] elements[{i}]");
        let r = table(row, &at)?;
        only_keys(r, &at, &["L", "od", "id", "od_right", "id_right", "n"])?;
        let len = |k: &str| -> Result<Option<f64>, String> {
            r.get(k)
                .map(|v| quantity(v, &format!("{at}.{k}"), LENGTH))
                .transpose()
        };
        let l = len("L")?.ok_or_else(|| format!("{at}: no L"))?;
        let od = len("od")?.ok_or_else(|| format!("{at}: no od"))?;
        let id = len("id")?.unwrap_or(0.0);
        let n = match r.get("n") {
            None => 1,
            Some(Value::Integer(n)) if (1..=1000).contains(n) => *n as usize,
            Some(_) => return Err(format!("{at}.n must be an integer from 1 to 1000")),
        };
        let mut e = ShaftElement::cylinder(l, id, od, material.clone());
        e.od_right_m = len("od_right")?.unwrap_or(od);
        e.id_right_m = len("id_right")?.unwrap_or(id);
        e.validate(elements.len())
            .map_err(|err| format!("{at}: {err}"))?;
        elements.extend(std::iter::repeat_n(e, n));
    }
    if elements.is_empty() {
        return Err("[shaft] elements is empty".into());
    }
    let mut model = ShaftModel {
        elements,
        ..Default::default()
    };
    if let Some(v) = t.get("disks") {
        let rows = v
            .as_array()
            .ok_or("[shaft] disks must be a list of tables")?;
        for (i, row) in rows.iter().enumerate() {
            let at = format!("[shaft] disks[{i}]");
            let r = table(row, &at)?;
            only_keys(r, &at, &["node", "m", "Id", "Ip", "tag"])?;
            let q = |k: &str, units| {
                let v = r.get(k).ok_or_else(|| format!("{at}: no {k}"))?;
                quantity(v, &format!("{at}.{k}"), units)
            };
            model.disks.push(Disk {
                node: node(r, &at)?,
                mass_kg: q("m", MASS)?,
                id_kg_m2: q("Id", INERTIA)?,
                ip_kg_m2: q("Ip", INERTIA)?,
                tag: r
                    .get("tag")
                    .and_then(Value::as_str)
                    .map_or_else(|| format!("disk {i}"), String::from),
            });
        }
    }
    if let Some(v) = t.get("point_masses") {
        let rows = v
            .as_array()
            .ok_or("[shaft] point_masses must be a list of tables")?;
        for (i, row) in rows.iter().enumerate() {
            let at = format!("[shaft] point_masses[{i}]");
            let r = table(row, &at)?;
            only_keys(r, &at, &["node", "m", "tag"])?;
            let m = r.get("m").ok_or_else(|| format!("{at}: no m"))?;
            model.point_masses.push(PointMass {
                node: node(r, &at)?,
                mass_kg: quantity(m, &format!("{at}.m"), MASS)?,
                tag: r
                    .get("tag")
                    .and_then(Value::as_str)
                    .map_or_else(|| format!("point mass {i}"), String::from),
            });
        }
    }
    model.validate().map_err(|e| format!("[shaft]: {e}"))?;
    Ok(model)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn parse_text(text: &str) -> Result<ShaftSpec, String> {
        let t: Table = text.parse().unwrap();
        parse(t["shaft"].as_table().unwrap(), None)
    }

    const EXAMPLE: &str = r#"
[shaft]
elements = [
  { L = "12 mm", od = "18 mm", n = 5 },
  { L = "12 mm", od = "22 mm", id = "6 mm", n = 10 },
  { L = 0.012, od = "18 mm", od_right = "16 mm", n = 5 },
]
disks = [{ node = 1, m = "350 g", Id = "2.0e-4 kg.m2", Ip = "360 kg.mm2", tag = "compressor" }]
point_masses = [{ node = 10, m = "20 g" }]
bearing_nodes = { compressor = 5, turbine = 15 }
"#;

    #[test]
    fn a_written_out_shaft_is_read_with_its_units() {
        let s = parse_text(EXAMPLE).unwrap();
        assert_eq!(s.model.elements.len(), 20);
        assert_eq!(s.bearing_nodes, [5, 15]);
        let e = &s.model.elements[7];
        assert_eq!(
            (e.length_m, e.od_left_m, e.id_left_m),
            (0.012, 0.022, 0.006)
        );
        assert_eq!(s.model.elements[19].od_right_m, 0.016);
        assert!((s.model.disks[0].mass_kg - 0.35).abs() < 1e-15);
        assert!((s.model.disks[0].ip_kg_m2 - 3.6e-4).abs() < 1e-18);
        assert!((s.model.point_masses[0].mass_kg - 0.02).abs() < 1e-15);
        assert_eq!(s.model.elements[0].material, Material::steel());
    }

    #[test]
    fn each_mistake_names_its_entry() {
        for (from, to, says) in [
            (
                "od = \"22 mm\", id = \"6 mm\"",
                "od = \"22 mm\", id = \"30 mm\"",
                "elements[1]",
            ),
            (
                "L = \"12 mm\", od = \"18 mm\", n = 5 },\n  {",
                "L = \"-2 mm\", od = \"18 mm\", n = 5 },\n  {",
                "L = -0.002",
            ),
            (
                "m = \"350 g\"",
                "m = \"350 lb\"",
                "disks[0].m = \"350 lb\": unit \"lb\"",
            ),
            (
                "compressor = 5",
                "compressor = 25",
                "bearing_nodes.compressor = 25 is off the shaft",
            ),
            (
                "compressor = 5",
                "compressor = 15",
                "each bearing needs a node of its own",
            ),
            ("{ node = 10,", "{ node = 40,", "node 40, off the shaft"),
            (
                "n = 5 },\n  { L = \"12 mm\", od = \"22 mm\"",
                "n = 0 },\n  { L = \"12 mm\", od = \"22 mm\"",
                "elements[0].n",
            ),
            (
                "tag = \"compressor\"",
                "tag = \"compressor\", mass = 3",
                "unknown key \"mass\"",
            ),
        ] {
            assert!(EXAMPLE.contains(from), "{from}");
            let e = parse_text(&EXAMPLE.replacen(from, to, 1)).unwrap_err();
            assert!(e.contains(says), "{to}: {e}");
        }
        let e = parse_text("[shaft]\nelements = [{ L = 0.1, od = 0.02 }]").unwrap_err();
        assert!(e.contains("no bearing_nodes"), "{e}");
        let e = parse_text(
            "[shaft]\nrotor_file = \"r.toml\"\nelements = []\nbearing_nodes = { compressor = 0, turbine = 1 }",
        )
        .unwrap_err();
        assert!(e.contains("rotor_file and elements"), "{e}");
    }
}
