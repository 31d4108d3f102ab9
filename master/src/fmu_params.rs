//! FMU parameters by name (`--set "film.eta=1.9e-5 Pa.s"`, study keys such as `rotor.m`), checked
//! and converted in-process against the FMUs' own variable tables, the tables the shipped
//! modelDescription.xml files are generated from. The run-up writes them into its system file;
//! the linear stability analysis applies them to the same parameter mapping the FMUs use
//! (`shell::params_from`), so both see the same physics.

use fmi_core::model::{Model, Store};
use fmi_core::variables::{Causality, ModelInfo, VarType};
use fmu_airfilm::shell::AirFilmFmu;
use fmu_rotor::shell::RotorFmu;

/// A TOML value (design files, system files) as the value text `FmuParameter::parse` reads:
/// strings as they are ("20 um"), floats in Rust's exact round-trip form, integers and booleans
/// as written; None for arrays and tables. (Study keys keep their own text form: it names runs.)
pub fn toml_value_text(v: &toml::Value) -> Option<String> {
    match v {
        toml::Value::String(s) => Some(s.clone()),
        toml::Value::Float(f) => Some(format!("{f:?}")),
        toml::Value::Integer(i) => Some(i.to_string()),
        toml::Value::Boolean(b) => Some(b.to_string()),
        _ => None,
    }
}

/// Which FMU instances of a run-up a parameter goes to.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Target {
    Rotor,
    /// Both air films.
    Films,
    FilmC,
    FilmT,
}

impl Target {
    /// Prefixes accepted before the dot.
    pub const PREFIXES: &'static [&'static str] = &["rotor", "film", "film_C", "film_T"];

    fn parse(s: &str) -> Option<Target> {
        match s {
            "rotor" => Some(Target::Rotor),
            "film" => Some(Target::Films),
            "film_C" => Some(Target::FilmC),
            "film_T" => Some(Target::FilmT),
            _ => None,
        }
    }

    /// The run-up's instance names this target covers.
    pub fn instances(self) -> &'static [&'static str] {
        match self {
            Target::Rotor => &["rotor"],
            Target::Films => &["film_C", "film_T"],
            Target::FilmC => &["film_C"],
            Target::FilmT => &["film_T"],
        }
    }

    fn info(self) -> ModelInfo {
        match self {
            Target::Rotor => RotorFmu::info(),
            _ => AirFilmFmu::info(),
        }
    }
}

/// A parameter value in the variable's own type; Reals in SI.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Value {
    Real(f64),
    Integer(i32),
    Boolean(bool),
}

/// One checked FMU parameter.
#[derive(Clone, Debug, PartialEq)]
pub struct FmuParameter {
    pub target: Target,
    /// Variable name in the FMU.
    pub name: String,
    /// The value as given ("15 um", "1e-5", "true"): written as is into system files, whose
    /// reader converts units through the FMU's declared display units.
    pub text: String,
    pub vr: u32,
    pub value: Value,
}

impl FmuParameter {
    /// `key` = "PREFIX.NAME" (PREFIX: rotor, film (both films), film_C, film_T) and the value
    /// text: a number (SI), "number unit" with a display unit the FMU declares for the variable,
    /// an integer, or true/false.
    pub fn parse(key: &str, text: &str) -> Result<FmuParameter, String> {
        let (target, var) = lookup(key)?;
        let name = var.name;
        let bad = |what: &str| format!("'{key}' = '{text}': {what}");
        let t = match var.var_type {
            VarType::Real => unit_spaces_as_dots(text.trim()),
            _ => text.trim().to_string(),
        };
        let t = t.as_str();
        let value = match var.var_type {
            VarType::Boolean => match t {
                "true" => Value::Boolean(true),
                "false" => Value::Boolean(false),
                _ => return Err(bad("expected true or false")),
            },
            VarType::Integer => Value::Integer(t.parse().map_err(|_| bad("expected an integer"))?),
            VarType::Real => Value::Real(real_si(&var, t).map_err(|e| bad(&e))?),
        };
        let as_f64 = match value {
            Value::Real(x) => x,
            Value::Integer(i) => i as f64,
            Value::Boolean(_) => 0.0,
        };
        if var.min.is_some_and(|m| as_f64 < m) || var.max.is_some_and(|m| as_f64 > m) {
            let bound = |b: Option<f64>, inf: &str| match (b, var.var_type) {
                (Some(m), VarType::Real) => quantity_text(&var, m),
                (Some(m), _) => m.to_string(),
                (None, _) => inf.to_string(),
            };
            return Err(bad(&format!(
                "outside the variable's range [{}, {}]",
                bound(var.min, "-inf"),
                bound(var.max, "inf")
            )));
        }
        Ok(FmuParameter {
            target,
            name: name.to_string(),
            text: t.to_string(),
            vr: var.vr,
            value,
        })
    }

    /// Does this parameter go to instance `inst` ("rotor", "film_C", "film_T")?
    pub fn applies_to(&self, inst: &str) -> bool {
        self.target.instances().contains(&inst)
    }

    /// The value for a system file (a quantity with a unit stays the string it was given).
    pub fn toml_value(&self) -> toml::Value {
        match self.value {
            Value::Real(_) if self.text.parse::<f64>().is_err() => {
                toml::Value::String(self.text.clone())
            }
            Value::Real(x) => toml::Value::Float(x),
            Value::Integer(i) => toml::Value::Integer(i64::from(i)),
            Value::Boolean(b) => toml::Value::Boolean(b),
        }
    }

    /// Writes the value into a store of the FMU's variable values.
    pub fn apply(&self, store: &mut Store) {
        let i = self.vr as usize;
        match self.value {
            Value::Real(x) => store.reals[i] = x,
            Value::Integer(v) => store.integers[i] = v,
            Value::Boolean(b) => store.booleans[i] = b,
        }
    }
}

/// The FMU and the parameter variable a key PREFIX.NAME names.
fn lookup(key: &str) -> Result<(Target, fmi_core::variables::Variable), String> {
    let (prefix, name) = key.split_once('.').ok_or_else(|| {
        format!("'{key}': an FMU parameter is PREFIX.NAME with PREFIX one of rotor, film, film_C, film_T")
    })?;
    let target = Target::parse(prefix).ok_or_else(|| {
        format!(
            "'{key}': unknown FMU '{prefix}' (one of {})",
            Target::PREFIXES.join(", ")
        )
    })?;
    let info = target.info();
    let params = || {
        info.variables
            .iter()
            .filter(|v| v.causality == Causality::Parameter)
    };
    match params().find(|v| v.name == name) {
        Some(v) => Ok((target, v.clone())),
        None => {
            let names: Vec<&str> = params().map(|v| v.name).collect();
            Err(format!(
                "'{key}': '{}' has no parameter '{name}' (parameters: {})",
                info.model_name,
                names.join(", ")
            ))
        }
    }
}

/// A value of `var` in its SI unit and, where the variable declares one, its display unit:
/// "-5000 N/m (-5 N/mm)", "2.5e-5 m (25 um)"; the bare number for a variable without a unit.
pub fn quantity_text(var: &fmi_core::variables::Variable, si: f64) -> String {
    fmi_core::units::quantity_text(var, si, &fmt_si)
}

/// Seven significant digits, without the rounding noise of a unit conversion (25, not
/// 24.999999999999996), and with an exponent where the number is long: the FMUs' own short
/// numbers (`bearing::num::Num`), so the master and the FMUs' logs print a value alike.
fn fmt_si(x: f64) -> String {
    bearing::num::Num(x).to_string()
}

/// An FMU's refusal of one of its parameters ("rotor: invalid parameter c_C = -5000: must be >=
/// 0", the libraries' SI text) with the value's units, the SI one and the display unit the
/// FMU declares for it: "... c_C = -5000 N/m (-5 N/mm): must be >= 0". `model` is the FMU
/// ("rotor", or a film instance); any other text is returned as it is.
pub fn with_units(model: &str, error: String) -> String {
    let info = if model == "rotor" {
        RotorFmu::info()
    } else {
        AirFilmFmu::info()
    };
    fmi_core::units::parameter_error_with_units(&info, error, &fmt_si)
}

/// Checks that `key` names a parameter of one of the run-up's FMUs.
pub fn check_key(key: &str) -> Result<(), String> {
    lookup(key).map(|_| ())
}

/// "50 N s/m" as the units are declared, "50 N.s/m": a product of units written with spaces.
fn unit_spaces_as_dots(t: &str) -> String {
    match t.split_once(char::is_whitespace) {
        Some((num, unit)) => {
            let unit = unit.split_whitespace().collect::<Vec<_>>().join(".");
            format!("{num} {unit}")
        }
        None => t.to_string(),
    }
}

/// "number" (SI) or "number unit" (the SI unit or one of its declared display units) -> SI.
fn real_si(var: &fmi_core::variables::Variable, t: &str) -> Result<f64, String> {
    let (num, unit) =
        cosim::system::split_quantity(t).ok_or("expected 'number' or 'number unit'")?;
    let si = if unit.is_empty() || Some(unit) == var.unit {
        num
    } else {
        let def = var.unit.and_then(fmi_core::units::unit);
        let (_, factor, offset) = def
            .and_then(|d| d.display_units.iter().find(|u| u.0 == unit))
            .ok_or_else(|| {
                let mut units: Vec<&str> = var.unit.into_iter().collect();
                if let Some(d) = def {
                    units.extend(d.display_units.iter().map(|u| u.0));
                }
                format!(
                    "unit '{unit}' does not fit (accepted: {})",
                    units.join(", ")
                )
            })?;
        (num - offset) / factor
    };
    if si.is_finite() {
        Ok(si)
    } else {
        Err("not a finite number".into())
    }
}

/// Parses and checks `--set PREFIX.NAME=VALUE` entries into (PREFIX.NAME, VALUE) pairs.
/// The same key twice is refused: which value was meant is not for the run-up to guess.
pub fn parse_set_flags(flags: &[String]) -> Result<Vec<(String, String)>, String> {
    let mut out: Vec<(String, String)> = Vec::with_capacity(flags.len());
    for f in flags {
        let (k, v) = f.split_once('=').ok_or_else(|| {
            format!("--set '{f}': expected PREFIX.NAME=VALUE, e.g. film.eta=1.9e-5")
        })?;
        let p = FmuParameter::parse(k.trim(), v).map_err(|e| format!("--set {e}"))?;
        if let Some((_, first)) = out.iter().find(|(key, _)| key == k.trim()) {
            return Err(format!(
                "--set {}: given twice ('{first}' and '{}'); give it once",
                k.trim(),
                p.text
            ));
        }
        out.push((k.trim().to_string(), p.text));
    }
    Ok(out)
}

/// The store of the variable values of instance `inst` ("rotor", "film_C", "film_T"): the FMU's
/// start values, then `parameters` as (name, TOML literal), e.g. a run-up's
/// `RunupSettings::instance_parameters`.
pub fn store_for(inst: &str, parameters: &[(String, toml::Value)]) -> Result<Store, String> {
    // Both films share one variable table: any film target gives it.
    let info = if inst == "rotor" {
        RotorFmu::info()
    } else {
        AirFilmFmu::info()
    };
    let mut store = Store::from_info(&info);
    for (name, value) in parameters {
        let text = toml_value_text(value)
            .ok_or_else(|| format!("{inst}.{name}: {value} is not a parameter value"))?;
        FmuParameter::parse(&format!("{inst}.{name}"), &text)?.apply(&mut store);
    }
    Ok(store)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn parameters_are_checked_and_converted_through_the_display_units() {
        let p = FmuParameter::parse("film.C", "15 um").unwrap();
        assert_eq!(p.target, Target::Films);
        assert_eq!(p.value, Value::Real(15e-6));
        assert!(p.applies_to("film_C") && p.applies_to("film_T") && !p.applies_to("rotor"));
        assert_eq!(p.toml_value(), toml::Value::String("15 um".into()));
        let p = FmuParameter::parse("rotor.c_C", "1500 N/mm").unwrap();
        assert_eq!(p.value, Value::Real(1.5e6));
        assert_eq!(
            FmuParameter::parse("film_T.eta", "2e-5")
                .unwrap()
                .toml_value(),
            toml::Value::Float(2e-5)
        );
        assert_eq!(
            FmuParameter::parse("film_C.n_elem_phi", "12")
                .unwrap()
                .value,
            Value::Integer(12)
        );
        // A product of units written with a space is the declared one with a dot.
        for (k, spaced, dotted) in [
            ("rotor.d_C", "50 N s/m", "50 N.s/m"),
            ("film.eta", " 2e-5  Pa s ", "2e-5 Pa.s"),
        ] {
            let (a, b) = (
                FmuParameter::parse(k, spaced).unwrap(),
                FmuParameter::parse(k, dotted).unwrap(),
            );
            assert_eq!((a.value, a.toml_value()), (b.value, b.toml_value()), "{k}");
        }
        for (k, v, why) in [
            ("eta", "1", "PREFIX.NAME"),
            ("stator.eta", "1", "unknown FMU"),
            ("film.viscosity", "1", "no parameter 'viscosity'"),
            ("film.Fx", "1", "no parameter 'Fx'"),
            ("film.C", "15 furlongs", "unit 'furlongs' does not fit"),
            ("film.C", "wide", "expected 'number'"),
            ("film.n_elem_phi", "1.5", "integer"),
            ("film.plain_bore", "yes", "true or false"),
            ("film.C", "inf", "finite"),
        ] {
            let e = FmuParameter::parse(k, v).unwrap_err();
            assert!(e.contains(why), "{k} = {v}: {e}");
        }
        assert!(parse_set_flags(&["film.eta".into()])
            .unwrap_err()
            .contains("PREFIX.NAME=VALUE"));
        assert_eq!(
            parse_set_flags(&["film.eta=2e-5".into(), "film.eta = 1.9e-5 Pa.s".into()])
                .unwrap_err(),
            "--set film.eta: given twice ('2e-5' and '1.9e-5 Pa.s'); give it once"
        );
        // Ranges in the variable's units.
        let e = FmuParameter::parse("film.n_elem_z", "1").unwrap_err();
        assert!(e.ends_with("outside the variable's range [2, 500]"), "{e}");
        // A film's own key beside both films' is another key, not a duplicate.
        assert!(parse_set_flags(&["film.eta=2e-5".into(), "film_T.eta=1.9e-5".into()]).is_ok());
    }

    /// The libraries name a refused parameter in SI, the FMU's name and a bare number; the
    /// master adds the SI unit and the display unit the FMU declares.
    #[test]
    fn refusals_of_parameters_are_given_in_their_units() {
        let cases = [
            (
                "rotor",
                "rotor: invalid parameter c_C = -5000: must be >= 0",
                "rotor: invalid parameter c_C = -5000 N/m (-5 N/mm): must be >= 0",
            ),
            (
                "film_T",
                "film_T: invalid bearing parameter C = -0.000025: must be > 0",
                "film_T: invalid bearing parameter C = -2.5e-5 m (-25 um): must be > 0",
            ),
            // A unit without a display unit; an integer; a name no variable has; no value.
            (
                "rotor",
                "rotor: invalid parameter d_C = -1: must be >= 0",
                "rotor: invalid parameter d_C = -1 N.s/m: must be >= 0",
            ),
            (
                "film",
                "invalid air-film parameter n_elem_phi = 2: mesh too coarse",
                "invalid air-film parameter n_elem_phi = 2: mesh too coarse",
            ),
            (
                "film",
                "invalid air-film parameter atol = -1: must be > 0 Pa",
                "invalid air-film parameter atol = -1 Pa: must be > 0 Pa",
            ),
            // Dimensionless ("1"): the bare number (was "rtol = 2 1").
            (
                "film_C",
                "film_C: invalid air-film parameter rtol = 2: must lie in (0, 1)",
                "film_C: invalid air-film parameter rtol = 2: must lie in (0, 1)",
            ),
            (
                "film",
                "invalid air-film parameter h_init_s = -1: first sub-step must be > 0 s",
                "invalid air-film parameter h_init_s = -1: first sub-step must be > 0 s",
            ),
            (
                "rotor",
                "rotor: no parameter here",
                "rotor: no parameter here",
            ),
        ];
        for (model, libraries, shown) in cases {
            assert_eq!(with_units(model, libraries.into()), shown);
        }
    }
}
