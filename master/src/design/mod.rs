//! A design file: one rotor in two air ring bearings, each quantity written once, in a file an
//! engineer keeps under version control and runs with `airring runup --design FILE`,
//! `airring stability --design FILE` (flags override it).
//!
//! ```toml
//! [bearing]              # both bearings: bore, contact law, gas (air-film parameter names),
//! C = "20 um"            # and the ring's mount and mass
//! dH = "40 um"
//! mount_c = "1000 N/mm"
//! mount_d = "50 N.s/m"
//! ring_mass = "50 g"
//!
//! [bearing.turbine]      # the turbine bearing only (overrides [bearing]); [bearing.compressor]
//! C = "25 um"            # likewise (the old names [bearing.T], [bearing.C] are read where the
//!                        # file parses: [bearing.C] collides with the clearance key C)
//!
//! [rotor]                # rotor.fmu parameters: mass, inertia, journal and wheel positions, imbalance
//! m = "4.5 kg"
//! ```
//!
//! Values are numbers in SI units or strings "number unit" with a display unit the FMU declares;
//! names and ranges are checked against the FMUs' variable tables. The file becomes the same
//! FMU parameter entries as `--set` (`film_C.C`, `rotor.c_T`, ...), so a design, a study key and a
//! flag edit one description; the rotor's contact geometry is derived from the films (runup/mod.rs).

pub mod shaft;

use crate::fmu_params::FmuParameter;
use std::path::Path;

/// Air-film parameters that describe the bearing itself (not the mesh or the solver).
const FILM_KEYS: &[&str] = &[
    "r",
    "b",
    "C",
    "dH",
    "phi_t",
    "alpha",
    "n_lobes",
    "plain_bore",
    "h_con_rel",
    "c_con",
    "eta",
    "p_a",
];

/// Bearing keys that are rotor.fmu parameters per bearing: (design key, rotor name without _C/_T).
const MOUNT_KEYS: &[(&str, &str)] = &[("mount_c", "c"), ("mount_d", "d"), ("ring_mass", "m_R")];

/// A design: its FMU parameter entries (PREFIX.NAME, value text), in the order they apply, and
/// where in the file each came from ("[bearing] mount_c").
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Design {
    pub entries: Vec<(String, String)>,
    pub sources: Vec<String>,
    /// `[shaft]`: a flexible rotor and its bearing nodes (`airring stability`, `airring modal`).
    pub shaft: Option<crate::design::shaft::ShaftSpec>,
}

impl Design {
    pub fn load(path: &Path) -> Result<Design, String> {
        let text = std::fs::read_to_string(path).map_err(|e| format!("{}: {e}", path.display()))?;
        Design::parse_in(&text, path.parent()).map_err(|e| format!("{}: {e}", path.display()))
    }

    /// Parses a design file's text. A TOML error names the line and column and what is wrong,
    /// never the line's text: a file that is not a design (`design = "/etc/passwd"`) must not
    /// have its content echoed.
    pub fn parse(text: &str) -> Result<Design, String> {
        Design::parse_in(text, None)
    }

    /// `parse`, with the design file's folder `dir` (a `[shaft]` rotor_file is relative to it).
    pub fn parse_in(text: &str, dir: Option<&Path>) -> Result<Design, String> {
        let table: toml::Table = text
            .parse()
            .map_err(|e: toml::de::Error| toml_error_without_text(text, &e))?;
        let mut d = Design::default();
        for (section, value) in &table {
            let t = value
                .as_table()
                .ok_or_else(|| format!("'{section}' must be a table ([{section}])"))?;
            match section.as_str() {
                "bearing" => {
                    // Both bearings first, then the per-bearing tables, so those win.
                    d.bearing(t, None)?;
                    // `[bearing.compressor]` and `[bearing.turbine]`; `[bearing.C]` and
                    // `[bearing.T]` are read too, where the file parses (they collide with the
                    // clearance key `C` in `[bearing]`: TOML refuses a key defined twice).
                    let mut seen: [Option<&str>; 2] = [None, None];
                    for (name, v) in t.iter().filter(|(_, v)| v.is_table()) {
                        let (k, side) = match name.as_str() {
                            "compressor" | "C" => (0, "C"),
                            "turbine" | "T" => (1, "T"),
                            other => {
                                return Err(format!(
                                    "[bearing.{other}]: the per-bearing tables are \
                                     [bearing.compressor] and [bearing.turbine]"
                                ))
                            }
                        };
                        if let Some(first) = seen[k] {
                            return Err(format!(
                                "[bearing.{first}] and [bearing.{name}] describe the same bearing: \
                                 keep one ([bearing.{}])",
                                ["compressor", "turbine"][k]
                            ));
                        }
                        seen[k] = Some(name.as_str());
                        d.bearing_side(v.as_table().expect("a table"), side, name)?;
                    }
                }
                "rotor" => d.rotor(t)?,
                "shaft" => d.shaft = Some(crate::design::shaft::parse(t, dir)?),
                other => {
                    return Err(format!(
                        "unknown section [{other}] (a design has [bearing], [bearing.compressor], \
                         [bearing.turbine], [rotor] and [shaft])"
                    ))
                }
            }
        }
        Ok(d)
    }

    /// The entries of one bearing's table (`side` "C" or "T"; `table` its name in the file).
    fn bearing_side(&mut self, t: &toml::Table, side: &str, table: &str) -> Result<(), String> {
        if let Some((key, _)) = t.iter().find(|(_, v)| v.is_table()) {
            return Err(format!(
                "[bearing.{table}.{key}]: a bearing's table holds values only"
            ));
        }
        self.bearing_entries(t, Some(side), &format!("[bearing.{table}]"))
    }

    /// The entries of `[bearing]`, for both bearings.
    fn bearing(&mut self, t: &toml::Table, side: Option<&str>) -> Result<(), String> {
        self.bearing_entries(t, side, "[bearing]")
    }

    /// The values of a bearing table (`side` None: both bearings; `table` as the file names it).
    fn bearing_entries(
        &mut self,
        t: &toml::Table,
        side: Option<&str>,
        table: &str,
    ) -> Result<(), String> {
        let at = |key: &str| format!("{table} {key}");
        for (key, v) in t.iter().filter(|(_, v)| !v.is_table()) {
            let text = crate::fmu_params::toml_value_text(v).ok_or_else(|| {
                format!(
                    "{}: expected a number, a \"number unit\" string or a boolean",
                    at(key)
                )
            })?;
            if let Some((_, rotor_name)) = MOUNT_KEYS.iter().find(|(k, _)| k == key) {
                for s in side.map_or(vec!["C", "T"], |s| vec![s]) {
                    self.push(format!("rotor.{rotor_name}_{s}"), &text, &at(key))?;
                }
            } else if FILM_KEYS.contains(&key.as_str()) {
                let prefix = side.map_or("film".to_string(), |s| format!("film_{s}"));
                self.push(format!("{prefix}.{key}"), &text, &at(key))?;
            } else {
                return Err(format!(
                    "{}: not a bearing quantity (bore, contact and gas: {}; mount and ring: {}; the mesh and \
                     the solver are run flags: --mesh, --film-tolerance, --set)",
                    at(key),
                    FILM_KEYS.join(", "),
                    MOUNT_KEYS.iter().map(|m| m.0).collect::<Vec<_>>().join(", ")
                ));
            }
        }
        Ok(())
    }

    fn rotor(&mut self, t: &toml::Table) -> Result<(), String> {
        for (key, v) in t {
            let at = format!("[rotor] {key}");
            let text = crate::fmu_params::toml_value_text(v).ok_or_else(|| {
                format!("{at}: expected a number, a \"number unit\" string or a boolean")
            })?;
            let per_bearing = ["c_C", "c_T", "d_C", "d_T", "m_R_C", "m_R_T"];
            if per_bearing.contains(&key.as_str())
                || key.starts_with("bearing_")
                || key == "contact"
            {
                return Err(format!(
                    "{at}: belongs to a bearing: write it in [bearing] (mount_c, mount_d, ring_mass; \
                     the contact geometry is the air films' bore)"
                ));
            }
            if ["f_max", "t_ramp"].contains(&key.as_str()) {
                return Err(format!("{at}: the speed profile is a run flag (--f-max, --t-ramp), not part of a design"));
            }
            self.push(format!("rotor.{key}"), &text, &at)?;
        }
        Ok(())
    }

    fn push(&mut self, key: String, text: &str, at: &str) -> Result<(), String> {
        FmuParameter::parse(&key, text).map_err(|e| format!("{at}: {e}"))?;
        self.entries.push((key, text.to_string()));
        self.sources.push(at.to_string());
        Ok(())
    }

    /// Where the design sets variable `name` of FMU instance `inst` ("rotor", "film_C",
    /// "film_T"): the last entry that does (later ones override), as "[bearing] mount_c".
    /// With the entry itself (key, value text).
    pub fn source_of(&self, inst: &str, name: &str) -> Option<(&(String, String), &str)> {
        self.entries
            .iter()
            .zip(&self.sources)
            .rev()
            .find(|((key, _), _)| applies_to(key, inst, name))
            .map(|(entry, at)| (entry, at.as_str()))
    }

    /// The entries without those that set any of the FMU variables `keys` (for a flag that
    /// overrides the design, e.g. --clearance removes film.C, film_C.C and film_T.C).
    pub fn without(&self, keys: &[&str]) -> Design {
        let (entries, sources) = self
            .entries
            .iter()
            .zip(&self.sources)
            .filter(|((k, _), _)| !keys.iter().any(|x| covers(x, k)))
            .map(|(e, at)| (e.clone(), at.clone()))
            .unzip();
        Design {
            entries,
            sources,
            shaft: self.shaft.clone(),
        }
    }
}

/// A TOML error as "line L, column C: message", without the snippet of the file's text that
/// the parser's own message quotes.
pub fn toml_error_without_text(text: &str, e: &toml::de::Error) -> String {
    match e.span() {
        Some(span) => {
            let before = &text[..span.start.min(text.len())];
            let line = before.matches('\n').count() + 1;
            let column = before.rsplit('\n').next().map_or(0, |l| l.chars().count()) + 1;
            format!("line {line}, column {column}: {}", e.message())
        }
        None => e.message().to_string(),
    }
}

/// Does the entry key `key` ("film.C", "film_T.C", "rotor.c_C") set variable `name` of FMU
/// instance `inst`?
fn applies_to(key: &str, inst: &str, name: &str) -> bool {
    key.split_once('.').is_some_and(|(prefix, n)| {
        n == name && (prefix == inst || (prefix == "film" && inst.starts_with("film_")))
    })
}

/// `error`, from the FMUs' own parameter checks ("rotor: invalid parameter c_C = -5000: ..."),
/// with the design file and the entry that set that parameter in front, where the design file
/// `path` set it and no later `--set` (in `parameters`, the run-up's after the design's) did.
pub fn blame(path: &Path, parameters: &[(String, String)], error: String) -> String {
    let Some((inst, rest)) = error.split_once(": ") else {
        return error;
    };
    let Some(name) = rest
        .split_once("parameter ")
        .and_then(|(_, r)| r.split_once(" = "))
        .map(|(n, _)| n.to_string())
    else {
        return error;
    };
    let Ok(design) = Design::load(path) else {
        return error;
    };
    let Some((entry, at)) = design.source_of(inst, &name) else {
        return error;
    };
    // The last of the run-up's parameters that sets the variable is the value the FMU checked:
    // the design's entry, unless a --set came after it (or a flag replaced it: then none).
    let last = parameters
        .iter()
        .rev()
        .find(|(k, _)| applies_to(k, inst, &name));
    if last != Some(entry) {
        return error;
    }
    format!("{}: {at}: {error}", path.display())
}

/// Does the flag key `flag` ("film.C", "rotor.c_C") set the same variable as the entry `entry`?
fn covers(flag: &str, entry: &str) -> bool {
    let name = |k: &str| {
        k.split_once('.')
            .map(|(_, n)| n.to_string())
            .unwrap_or_default()
    };
    let prefix = |k: &str| {
        k.split_once('.')
            .map(|(p, _)| p.to_string())
            .unwrap_or_default()
    };
    name(flag) == name(entry)
        && (prefix(flag) == prefix(entry)
            || (prefix(flag) == "film" && prefix(entry).starts_with("film_")))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn each_bearing_quantity_becomes_its_fmu_parameters() {
        let d = Design::parse(
            r#"
[bearing]
C = "20 um"
mount_c = "1000 N/mm"
ring_mass = 0.05

[bearing.T]
C = "25 um"
mount_d = 80.0

[rotor]
m = "4.5 kg"
"#,
        )
        .unwrap();
        let keys: Vec<&str> = d.entries.iter().map(|(k, _)| k.as_str()).collect();
        assert_eq!(
            keys,
            [
                "film.C",
                "rotor.c_C",
                "rotor.c_T",
                "rotor.m_R_C",
                "rotor.m_R_T",
                "film_T.C",
                "rotor.d_T",
                "rotor.m"
            ]
        );
        // A flag overriding the design drops every entry of the same variable.
        let k: Vec<String> = d
            .without(&["film.C", "rotor.c_C", "rotor.c_T"])
            .entries
            .into_iter()
            .map(|e| e.0)
            .collect();
        assert_eq!(k, ["rotor.m_R_C", "rotor.m_R_T", "rotor.d_T", "rotor.m"]);
    }

    #[test]
    fn what_is_not_a_design_quantity_is_refused_naming_where_it_goes() {
        for (text, expect) in [
            ("[bearing]\nn_elem_phi = 30", "--mesh"),
            ("[bearing]\nC = \"20 furlongs\"", "[bearing] C"),
            (
                "[bearing.X]\nC = 1e-5",
                "[bearing.compressor] and [bearing.turbine]",
            ),
            (
                "[bearing.C]\nC = 1e-5\n[bearing.compressor]\nC = 2e-5",
                "describe the same bearing",
            ),
            ("[bearing.turbine.x]\nC = 1e-5", "holds values only"),
            ("[rotor]\nc_C = \"1 N/mm\"", "mount_c"),
            ("[rotor]\nbearing_C = 1e-5", "[bearing]"),
            ("[rotor]\nf_max = 1000.0", "--f-max"),
            ("[rotor]\nbogus = 1", "[rotor] bogus"),
            ("[wheels]\nx = 1", "unknown section [wheels]"),
            ("[bearing]\nC = [1, 2]", "expected a number"),
            ("[bearing\nC = 1", "TOML"),
        ] {
            let e = Design::parse(text).unwrap_err();
            assert!(
                e.contains(expect) || (expect == "TOML" && !e.is_empty()),
                "{text}: {e}"
            );
        }
    }

    /// The clearance of both bearings and a table for one of them: the docs' first format put
    /// `C = ...` and `[bearing.C]` in one table, which TOML refuses (a key defined twice). The
    /// per-bearing tables are `[bearing.compressor]` and `[bearing.turbine]`; the old names are
    /// read where they parse.
    #[test]
    fn the_clearance_and_the_compressor_bearings_table_do_not_collide() {
        let text = "[bearing]\nC = \"20 um\"\n[bearing.compressor]\nC = \"22 um\"\n\
                    [bearing.turbine]\nmount_d = 80.0\n";
        let d = Design::parse(text).unwrap();
        let keys: Vec<&str> = d.entries.iter().map(|(k, _)| k.as_str()).collect();
        assert_eq!(keys, ["film.C", "film_C.C", "rotor.d_T"]);
        assert_eq!(d.sources[1], "[bearing.compressor] C");
        // The old format fails in TOML itself where it collides ...
        let e =
            Design::parse("[bearing]\nC = \"20 um\"\n[bearing.C]\nmount_d = 1.0\n").unwrap_err();
        assert!(e.starts_with("line 3, column"), "{e}");
        // ... and is read where it does not.
        let old =
            Design::parse("[bearing.C]\nC = \"22 um\"\n[bearing.T]\nmount_d = 80.0\n").unwrap();
        assert_eq!(old.entries, d.entries[1..].to_vec());
        assert_eq!(old.sources, ["[bearing.C] C", "[bearing.T] mount_d"]);
    }

    /// A file that is not a design (a study's `design = "/etc/passwd"`) is refused naming the
    /// line and column, without echoing its content.
    #[test]
    fn a_toml_error_does_not_echo_the_file() {
        let secret = "root:x:0:0:root:/root:/bin/bash\n";
        let e = Design::parse(secret).unwrap_err();
        assert!(!e.contains("root"), "{e}");
        assert!(e.starts_with("line 1, column"), "{e}");
    }

    /// An FMU's refusal of a value the design file set names the file and the entry; not where
    /// a flag or a later --set gave the value.
    #[test]
    fn a_refused_design_value_names_the_file_and_entry() {
        let path = std::env::temp_dir().join(format!("airring-blame-{}.toml", std::process::id()));
        std::fs::write(
            &path,
            "[bearing]\nmount_c = \"-5 N/mm\"\n[bearing.T]\nC = \"50 mm\"\n",
        )
        .unwrap();
        let design = Design::load(&path).unwrap();
        let rotor_error = "rotor: invalid parameter c_C = -5000: must be >= 0".to_string();
        let film_error =
            "film_T: invalid air-film parameter C = 0.05: must lie between".to_string();
        let p = path.display();
        assert_eq!(
            blame(&path, &design.entries, rotor_error.clone()),
            format!("{p}: [bearing] mount_c: {rotor_error}")
        );
        assert_eq!(
            blame(&path, &design.entries, film_error.clone()),
            format!("{p}: [bearing.T] C: {film_error}")
        );
        // A later --set of the same variable is what the FMU refused.
        let mut with_set = design.entries.clone();
        with_set.push(("rotor.c_C".into(), "-3 N/mm".into()));
        assert_eq!(blame(&path, &with_set, rotor_error.clone()), rotor_error);
        // A flag that replaced the design's value removed its entry.
        let flagged = design.without(&["rotor.c_C", "rotor.c_T"]);
        assert_eq!(
            blame(&path, &flagged.entries, rotor_error.clone()),
            rotor_error
        );
        assert_eq!(flagged.entries.len(), flagged.sources.len());
        // An error about something else is left as it is.
        let other = "rotor: invalid parameter m = 0: mass must be > 0".to_string();
        assert_eq!(blame(&path, &design.entries, other.clone()), other);
        let _ = std::fs::remove_file(&path);
    }
}
