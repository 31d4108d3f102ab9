//! The optimisation file (TOML): the base design, the design variables, the requirement, the
//! tolerances, the objectives and the search settings. Every key is checked here, before any
//! evaluation runs; errors name the file, the table and the key.

use crate::sweep::{flatten, is_fmu_key, short_and_unit, KEYS};
use design_search::{Scale, Variable};
use std::collections::BTreeMap;
use std::path::Path;

/// Study keys a design variable or a tolerance may name besides FMU parameters (PREFIX.NAME):
/// the bearing and ring quantities of a run-up.
pub const DESIGN_KEYS: &[&str] = &["clearance", "dh", "c", "d", "m_r"];

/// Whether `v` is a physical value of the design key `key`: sizes, stiffness, damping and mass
/// above zero; the step height from zero (a circular bore, the paper's dH = 0).
fn physical(key: &str, v: f64) -> bool {
    if key == "dh" {
        v >= 0.0
    } else {
        v > 0.0
    }
}

/// Keys of `[base]` that the optimisation sets itself.
const BASE_RESERVED: &[&str] = &["profile", "stop", "fmu_dir"];

/// A quantity an objective can name besides a design variable.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Quantity {
    /// A design variable's nominal value (index into the variables).
    Variable(usize),
    /// The linear threshold speed of instability, the lowest over the tolerance corners [Hz].
    ThresholdHz,
    /// The friction power of both films at the nominal corner at the objective's speed [W].
    PowerLossW,
    /// The smallest film thickness over the speed range and the corners [um].
    MinFilmUm,
    /// The normalized distance to the nearest limit of the requirement (1 = at zero film, or
    /// zero whirl; 0 = on a limit).
    Margin,
}

impl Quantity {
    pub const NAMES: &'static [&'static str] =
        &["threshold_hz", "power_loss_w", "min_film_um", "margin"];

    pub fn label(self, variables: &[DesignVariable]) -> String {
        match self {
            Quantity::Variable(i) => variables[i].label(),
            Quantity::ThresholdHz => "linear threshold speed [Hz]".into(),
            Quantity::PowerLossW => "friction power [W]".into(),
            Quantity::MinFilmUm => "minimum film thickness [um]".into(),
            Quantity::Margin => "margin to the nearest limit [1]".into(),
        }
    }

    pub fn key(self, variables: &[DesignVariable]) -> String {
        match self {
            Quantity::Variable(i) => variables[i].key.clone(),
            Quantity::ThresholdHz => "threshold_hz".into(),
            Quantity::PowerLossW => "power_loss_w".into(),
            Quantity::MinFilmUm => "min_film_um".into(),
            Quantity::Margin => "margin".into(),
        }
    }
}

#[derive(Clone, Debug, PartialEq)]
pub struct Objective {
    pub quantity: Quantity,
    pub maximize: bool,
}

/// A design variable: a study key, its bounds in the key's unit, its scale, integer or not.
#[derive(Clone, Debug, PartialEq)]
pub struct DesignVariable {
    pub key: String,
    pub unit: &'static str,
    pub bounds: Variable,
    pub integer: bool,
}

impl DesignVariable {
    pub fn label(&self) -> String {
        let (short, unit) = short_and_unit(&self.key);
        if unit.is_empty() {
            short
        } else {
            format!("{short} [{unit}]")
        }
    }

    /// A value as the design takes it: 4 significant digits (a run name and a drawing both
    /// read it; tolerances are far coarser), whole numbers for integer variables.
    pub fn round(&self, x: f64) -> f64 {
        if self.integer {
            return x.round();
        }
        significant(x, 4)
    }
}

/// `x` to `digits` significant digits.
pub fn significant(x: f64, digits: i32) -> f64 {
    if x == 0.0 || !x.is_finite() {
        return x;
    }
    let scale = 10f64.powi(digits - 1 - x.abs().log10().floor() as i32);
    (x * scale).round() / scale
}

/// A tolerance on a study key: +- an absolute amount in the key's unit, or +- a fraction.
#[derive(Clone, Debug, PartialEq)]
pub enum Tolerance {
    Absolute(f64),
    Relative(f64),
}

impl Tolerance {
    /// The low and high values of `x` under this tolerance.
    pub fn range(&self, x: f64) -> (f64, f64) {
        match *self {
            Tolerance::Absolute(a) => (x - a, x + a),
            Tolerance::Relative(r) => (x * (1.0 - r), x * (1.0 + r)),
        }
    }
}

/// How the next points are chosen.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SearchMethod {
    Ego,
    Random,
    Grid,
}

#[derive(Clone, Debug, PartialEq)]
pub struct Problem {
    pub name: String,
    /// The base design: study keys (preset or design, f_max, t_ramp, mesh, imbalance, FMU keys).
    pub base: BTreeMap<String, String>,
    pub variables: Vec<DesignVariable>,
    /// The requirement covers this speed range [Hz] (low, high); high is the run-up's top speed.
    pub speed_range_hz: (f64, f64),
    pub min_film_um: f64,
    pub max_whirl_um: Option<f64>,
    /// Allowed run-up classes (empty: any).
    pub classes: Vec<String>,
    /// (key, tolerance), in key order; their corners are checked around every candidate.
    pub tolerances: Vec<(String, Tolerance)>,
    pub objectives: Vec<Objective>,
    /// Where the friction power is taken [Hz].
    pub operating_speed_hz: f64,
    pub method: SearchMethod,
    pub budget: usize,
    pub initial: usize,
    pub batch: usize,
    pub seed: u64,
    /// Speed step of the linear stage's grid [Hz].
    pub linear_step_hz: f64,
    /// Film mesh of the linear stage.
    pub linear_mesh: (u32, u32),
    /// Run-up ramp time of the nonlinear stage [s] (the run-down takes as long).
    pub t_ramp_s: f64,
    /// Film mesh and ramp time of the verification runs.
    pub verify_mesh: (u32, u32),
    pub verify_t_ramp_s: f64,
}

/// Classes a run-up can end in (`runup_analysis::RunClass` names).
pub const CLASSES: &[&str] = &[
    "stable",
    "path1",
    "path2a",
    "path2b",
    "unstable_low_speed",
    "contact",
    "unclassified",
];

impl Problem {
    pub fn load(path: &Path) -> Result<Problem, String> {
        let text = std::fs::read_to_string(path).map_err(|e| format!("{}: {e}", path.display()))?;
        Problem::parse(&text, path)
    }

    pub fn parse(text: &str, path: &Path) -> Result<Problem, String> {
        parse(text).map_err(|e| format!("{}: {e}", path.display()))
    }

    pub fn dim(&self) -> usize {
        self.variables.len()
    }

    /// The points each candidate is checked at: its nominal design and, with k toleranced keys,
    /// the 2^k corners of its tolerance box.
    pub fn corner_count(&self) -> usize {
        match self.tolerances.len() {
            0 => 1,
            k => (1usize << k) + 1,
        }
    }

    /// The corners of the tolerance box around `x` (variables' nominal values): first the
    /// nominal design itself, then every combination of low and high of the toleranced keys.
    /// Each corner is a set of study keys (the base's own values for keys that are no
    /// variables, taken from `base_values`).
    pub fn corners(
        &self,
        x: &[f64],
        base_values: &BTreeMap<String, f64>,
    ) -> Result<Vec<BTreeMap<String, String>>, String> {
        let mut nominal = self.base.clone();
        let mut values: BTreeMap<String, f64> = base_values.clone();
        for (v, &xi) in self.variables.iter().zip(x) {
            values.insert(v.key.clone(), xi);
            nominal.insert(v.key.clone(), number_text(xi));
        }
        let mut out = vec![nominal.clone()];
        let k = self.tolerances.len();
        // Without tolerances the nominal design is the only corner.
        let masks = if k == 0 { 0 } else { 1usize << k };
        for mask in 0..masks {
            let mut corner = nominal.clone();
            for (bit, (key, tol)) in self.tolerances.iter().enumerate() {
                let x = *values.get(key).ok_or_else(|| {
                    format!("the tolerance on '{key}' needs a nominal value of '{key}'")
                })?;
                let (lo, hi) = tol.range(x);
                let v = if mask & (1 << bit) == 0 { lo } else { hi };
                let v = significant(v, 4);
                if v.is_nan() || !physical(key, v) {
                    return Err(format!(
                        "the tolerance on '{key}' takes it to {v} at a corner around {x}: a \
                         corner must stay a physical design ({} 0)",
                        if key == "dh" { ">=" } else { ">" }
                    ));
                }
                corner.insert(key.clone(), number_text(v));
            }
            out.push(corner);
        }
        Ok(out)
    }
}

/// A number as a study value (the run name's spelling).
pub fn number_text(x: f64) -> String {
    x.to_string()
}

fn parse(text: &str) -> Result<Problem, String> {
    let doc: toml::Table = text.parse().map_err(|e| format!("{e}"))?;
    const TABLES: &[&str] = &[
        "name",
        "base",
        "variables",
        "requirement",
        "tolerances",
        "objective",
        "search",
        "verify",
    ];
    for k in doc.keys() {
        if !TABLES.contains(&k.as_str()) {
            return Err(format!(
                "unknown key or table '{k}' (an optimisation file has {})",
                TABLES.join(", ")
            ));
        }
    }
    let name = match doc.get("name") {
        None => "optimize".to_string(),
        Some(toml::Value::String(s)) if plain_name(s) => s.clone(),
        Some(_) => {
            return Err("'name' must be a string of letters, digits, '-', '_' and '.'".into())
        }
    };
    let table = |k: &str| -> Result<Option<&toml::Table>, String> {
        match doc.get(k) {
            None => Ok(None),
            Some(toml::Value::Table(t)) => Ok(Some(t)),
            Some(_) => Err(format!("'{k}' must be a table ([{k}])")),
        }
    };
    let base = parse_base(table("base")?)?;
    let variables = parse_variables(table("variables")?.ok_or(
        "no [variables]: name at least one design variable with its bounds, e.g. \
         clearance = { min = 10, max = 30 }",
    )?)?;
    let f_max = match base.get("f_max") {
        Some(v) => v
            .parse::<f64>()
            .map_err(|_| format!("[base] f_max = '{v}' is not a number"))?,
        None => 2000.0,
    };
    let t_ramp_base = match base.get("t_ramp") {
        Some(v) => v
            .parse::<f64>()
            .map_err(|_| format!("[base] t_ramp = '{v}' is not a number"))?,
        None => 3.0,
    };
    if !(f_max > 0.0 && t_ramp_base > 0.0) {
        return Err(format!(
            "[base] f_max = {f_max} Hz and t_ramp = {t_ramp_base} s must be > 0"
        ));
    }
    let req = table("requirement")?.ok_or(
        "no [requirement]: give at least min_film_um, the film thickness the design must keep \
         over the speed range",
    )?;
    let (speed_range_hz, min_film_um, max_whirl_um, classes) = parse_requirement(req, f_max)?;
    let tolerances = match table("tolerances")? {
        None => vec![],
        Some(t) => parse_tolerances(t, &variables, &base)?,
    };
    let objectives = parse_objectives(doc.get("objective"), &variables)?;
    let search = table("search")?.cloned().unwrap_or_default();
    let verify = table("verify")?.cloned().unwrap_or_default();
    let mut s = Section::new("search", &search);
    let method = match s.string("method")?.as_deref() {
        None | Some("ego") => SearchMethod::Ego,
        Some("random") => SearchMethod::Random,
        Some("grid") => SearchMethod::Grid,
        Some(other) => {
            return Err(format!(
                "[search] method = '{other}': expected 'ego', 'random' or 'grid'"
            ))
        }
    };
    let budget = s.count("budget")?.unwrap_or(40);
    let dim = variables.len();
    let initial = s
        .count("initial")?
        .unwrap_or_else(|| (2 * dim + 2).max(budget / 4).min(budget));
    let batch = s.count("batch")?.unwrap_or(4);
    let seed = s.count("seed")?.unwrap_or(1) as u64;
    let operating_speed_hz = s
        .positive("operating_speed_hz")?
        .unwrap_or(speed_range_hz.1);
    let linear_step_hz = s
        .positive("linear_step_hz")?
        .unwrap_or_else(|| ((speed_range_hz.1 - speed_range_hz.0) / 30.0).max(1.0));
    let linear_mesh = match s.string("linear_mesh")? {
        None => crate::stability::LINEAR_PREDICTION_MESH,
        Some(m) => crate::runup::parse_mesh(&m, "[search] linear_mesh")?,
    };
    let t_ramp_s = s.positive("t_ramp")?.unwrap_or(t_ramp_base);
    s.done()?;
    if budget < 2 {
        return Err(format!(
            "[search] budget = {budget}: at least 2 evaluations"
        ));
    }
    if method == SearchMethod::Ego && !(2..=budget).contains(&initial) {
        return Err(format!(
            "[search] initial = {initial}: the initial design needs 2 to budget ({budget}) points"
        ));
    }
    if batch == 0 {
        return Err("[search] batch = 0: at least one point per round".into());
    }
    if operating_speed_hz > f_max {
        return Err(format!(
            "[search] operating_speed_hz = {operating_speed_hz} Hz lies above the run-up's top \
             speed f_max = {f_max} Hz"
        ));
    }
    let mut v = Section::new("verify", &verify);
    let verify_mesh = match v.string("mesh")? {
        None => (20, 6),
        Some(m) => crate::runup::parse_mesh(&m, "[verify] mesh")?,
    };
    let verify_t_ramp_s = v.positive("t_ramp")?.unwrap_or(2.0 * t_ramp_s);
    v.done()?;
    Ok(Problem {
        name,
        base,
        variables,
        speed_range_hz,
        min_film_um,
        max_whirl_um,
        classes,
        tolerances,
        objectives,
        operating_speed_hz,
        method,
        budget,
        initial,
        batch,
        seed,
        linear_step_hz,
        linear_mesh,
        t_ramp_s,
        verify_mesh,
        verify_t_ramp_s,
    })
}

fn plain_name(s: &str) -> bool {
    !s.is_empty()
        && !s.starts_with('.')
        && s.chars()
            .all(|c| c.is_ascii_alphanumeric() || matches!(c, '-' | '_' | '.'))
}

/// A table's keys taken one by one; `done` refuses what is left.
struct Section<'a> {
    name: &'static str,
    table: &'a toml::Table,
    used: Vec<&'static str>,
}

impl<'a> Section<'a> {
    fn new(name: &'static str, table: &'a toml::Table) -> Self {
        Section {
            name,
            table,
            used: vec![],
        }
    }

    fn get(&mut self, key: &'static str) -> Option<&'a toml::Value> {
        self.used.push(key);
        self.table.get(key)
    }

    fn string(&mut self, key: &'static str) -> Result<Option<String>, String> {
        let name = self.name;
        match self.get(key) {
            None => Ok(None),
            Some(toml::Value::String(s)) => Ok(Some(s.clone())),
            Some(v) => Err(format!("[{name}] {key} = {v}: expected a string")),
        }
    }

    fn count(&mut self, key: &'static str) -> Result<Option<usize>, String> {
        let name = self.name;
        match self.get(key) {
            None => Ok(None),
            Some(toml::Value::Integer(i)) if *i >= 0 => Ok(Some(*i as usize)),
            Some(v) => Err(format!(
                "[{name}] {key} = {v}: expected a whole number >= 0"
            )),
        }
    }

    fn positive(&mut self, key: &'static str) -> Result<Option<f64>, String> {
        let name = self.name;
        match self.get(key).map(number) {
            None => Ok(None),
            Some(Some(x)) if x > 0.0 && x.is_finite() => Ok(Some(x)),
            Some(_) => Err(format!("[{name}] {key}: expected a number > 0")),
        }
    }

    fn done(self) -> Result<(), String> {
        for k in self.table.keys() {
            if !self.used.contains(&k.as_str()) {
                return Err(format!(
                    "[{}] unknown key '{k}' (known: {})",
                    self.name,
                    self.used.join(", ")
                ));
            }
        }
        Ok(())
    }
}

fn number(v: &toml::Value) -> Option<f64> {
    match v {
        toml::Value::Integer(i) => Some(*i as f64),
        toml::Value::Float(f) => Some(*f),
        _ => None,
    }
}

fn parse_base(t: Option<&toml::Table>) -> Result<BTreeMap<String, String>, String> {
    let mut base = BTreeMap::new();
    let Some(t) = t else {
        base.insert("preset".into(), "path1".into());
        return Ok(base);
    };
    for (k, v) in flatten(t) {
        if BASE_RESERVED.contains(&k.as_str()) {
            return Err(format!(
                "[base] {k}: the optimisation sets it (a run-up to f_max and a run-down of the \
                 same length); give f_max and t_ramp instead"
            ));
        }
        if !is_fmu_key(&k) && !KEYS.iter().any(|e| e.0 == k) {
            return Err(format!(
                "[base] unknown key '{k}': the base takes the keys of a study's [fixed] \
                 (docs/reference/study-file.md)"
            ));
        }
        let text = match &v {
            toml::Value::String(s) => s.clone(),
            toml::Value::Integer(i) => i.to_string(),
            toml::Value::Float(f) if f.is_finite() => f.to_string(),
            toml::Value::Boolean(b) => b.to_string(),
            other => {
                return Err(format!(
                    "[base] {k} = {other}: expected a number or a string"
                ))
            }
        };
        base.insert(k, text);
    }
    if !base.contains_key("preset") && !base.contains_key("design") {
        base.insert("preset".into(), "path1".into());
    }
    Ok(base)
}

fn check_design_key(table: &str, k: &str) -> Result<&'static str, String> {
    if is_fmu_key(k) {
        let (prefix, _) = k.split_once('.').unwrap_or_default();
        if !crate::fmu_params::Target::PREFIXES.contains(&prefix) {
            return Err(format!(
                "[{table}] '{k}': an FMU parameter is PREFIX.NAME with PREFIX one of {}",
                crate::fmu_params::Target::PREFIXES.join(", ")
            ));
        }
        return Ok("");
    }
    if DESIGN_KEYS.contains(&k) {
        return Ok(short_and_unit(k).1);
    }
    Err(format!(
        "[{table}] '{k}' is no design quantity: use {} (in the units of a study: um, um, N/mm, \
         N s/m, g) or an FMU parameter PREFIX.NAME in SI units",
        DESIGN_KEYS.join(", ")
    ))
}

fn parse_variables(t: &toml::Table) -> Result<Vec<DesignVariable>, String> {
    let mut out = vec![];
    for (key, v) in flatten(t) {
        let unit = check_design_key("variables", &key)?;
        let bad = || {
            format!(
                "[variables] {key}: expected {{ min = LOW, max = HIGH }} (optional scale = \
                 \"log\", integer = true) or [LOW, HIGH]"
            )
        };
        let (lo, hi, scale, integer) = match &v {
            toml::Value::Array(a) if a.len() == 2 => (
                number(&a[0]).ok_or_else(bad)?,
                number(&a[1]).ok_or_else(bad)?,
                Scale::Linear,
                false,
            ),
            toml::Value::Table(spec) => {
                for k in spec.keys() {
                    if !["min", "max", "scale", "integer"].contains(&k.as_str()) {
                        return Err(format!(
                            "[variables] {key}: unknown entry '{k}' (min, max, scale, integer)"
                        ));
                    }
                }
                let lo = spec.get("min").and_then(number).ok_or_else(bad)?;
                let hi = spec.get("max").and_then(number).ok_or_else(bad)?;
                let scale = match spec.get("scale") {
                    None => Scale::Linear,
                    Some(toml::Value::String(s)) if s == "linear" => Scale::Linear,
                    Some(toml::Value::String(s)) if s == "log" => Scale::Log,
                    Some(other) => {
                        return Err(format!(
                            "[variables] {key}: scale = {other}: expected \"linear\" or \"log\""
                        ))
                    }
                };
                let integer = match spec.get("integer") {
                    None => false,
                    Some(toml::Value::Boolean(b)) => *b,
                    Some(other) => {
                        return Err(format!(
                            "[variables] {key}: integer = {other}: expected true or false"
                        ))
                    }
                };
                (lo, hi, scale, integer)
            }
            _ => return Err(bad()),
        };
        if DESIGN_KEYS.contains(&key.as_str()) && !physical(&key, lo) {
            return Err(format!(
                "[variables] {key}: the lower bound {lo} must be {} ({key} is a physical \
                 size)",
                if key == "dh" { ">= 0" } else { "> 0" }
            ));
        }
        let bounds = Variable::new(&key, lo, hi, scale).map_err(|e| format!("[variables] {e}"))?;
        out.push(DesignVariable {
            key,
            unit,
            bounds,
            integer,
        });
    }
    if out.is_empty() {
        return Err("[variables] is empty: name at least one design variable".into());
    }
    out.sort_by_key(|v| crate::sweep::key_order(&v.key));
    Ok(out)
}

type Requirement = ((f64, f64), f64, Option<f64>, Vec<String>);

fn parse_requirement(t: &toml::Table, f_max: f64) -> Result<Requirement, String> {
    let mut s = Section::new("requirement", t);
    let min_film = s.positive("min_film_um")?.ok_or(
        "[requirement] min_film_um is missing: the smallest film thickness [um] the design must \
         keep over the speed range",
    )?;
    let max_whirl = s.positive("max_whirl_um")?;
    let range = match s.get("speed_range_hz") {
        None => (0.25 * f_max, f_max),
        Some(toml::Value::Array(a)) if a.len() == 2 => {
            let lo = number(&a[0]);
            let hi = number(&a[1]);
            match (lo, hi) {
                (Some(lo), Some(hi)) if 0.0 < lo && lo < hi => (lo, hi),
                _ => {
                    return Err(format!(
                        "[requirement] speed_range_hz = {}: expected [LOW, HIGH] with 0 < LOW < \
                         HIGH",
                        toml::Value::Array(a.clone())
                    ))
                }
            }
        }
        Some(v) => {
            return Err(format!(
                "[requirement] speed_range_hz = {v}: expected [LOW, HIGH]"
            ))
        }
    };
    if range.1 > f_max {
        return Err(format!(
            "[requirement] speed_range_hz ends at {} Hz, above the run-up's top speed f_max = \
             {f_max} Hz ([base] f_max)",
            range.1
        ));
    }
    let classes = match s.get("classes") {
        None => vec![],
        Some(toml::Value::Array(a)) => {
            let mut out = vec![];
            for c in a {
                match c.as_str() {
                    Some(c) if CLASSES.contains(&c) => out.push(c.to_string()),
                    _ => {
                        return Err(format!(
                            "[requirement] classes: {c} is no run-up class ({})",
                            CLASSES.join(", ")
                        ))
                    }
                }
            }
            out
        }
        Some(v) => {
            return Err(format!(
                "[requirement] classes = {v}: expected a list of names"
            ))
        }
    };
    s.done()?;
    Ok((range, min_film, max_whirl, classes))
}

fn parse_tolerances(
    t: &toml::Table,
    variables: &[DesignVariable],
    base: &BTreeMap<String, String>,
) -> Result<Vec<(String, Tolerance)>, String> {
    let mut out = vec![];
    for (key, v) in flatten(t) {
        check_design_key("tolerances", &key)?;
        if is_fmu_key(&key) && !variables.iter().any(|x| x.key == key) && !base.contains_key(&key) {
            return Err(format!(
                "[tolerances] '{key}': an FMU parameter toleranced must be a variable or set in \
                 [base] (its nominal value)"
            ));
        }
        let tol = match &v {
            toml::Value::String(s) if s.trim_end().ends_with('%') => {
                let p: f64 = s
                    .trim_end()
                    .trim_end_matches('%')
                    .trim()
                    .parse()
                    .map_err(|_| {
                        format!("[tolerances] {key} = \"{s}\": expected a percentage like \"20%\"")
                    })?;
                if !(p > 0.0 && p < 100.0) {
                    return Err(format!(
                        "[tolerances] {key} = \"{s}\": a relative tolerance lies in (0 %, 100 %)"
                    ));
                }
                Tolerance::Relative(p / 100.0)
            }
            v => match number(v) {
                Some(a) if a > 0.0 && a.is_finite() => Tolerance::Absolute(a),
                _ => {
                    return Err(format!(
                        "[tolerances] {key} = {v}: expected +- an amount > 0 in the key's unit, \
                         or a percentage string like \"20%\""
                    ))
                }
            },
        };
        out.push((key, tol));
    }
    if out.len() > 5 {
        return Err(format!(
            "[tolerances]: {} toleranced keys give {} corners per candidate; at most 5 keys (33 \
             checks per candidate)",
            out.len(),
            (1usize << out.len()) + 1
        ));
    }
    out.sort_by_key(|(k, _)| crate::sweep::key_order(k));
    Ok(out)
}

fn parse_objectives(
    v: Option<&toml::Value>,
    variables: &[DesignVariable],
) -> Result<Vec<Objective>, String> {
    let tables: Vec<&toml::Table> =
        match v {
            None => return Err(
                "no [objective]: say what to maximize or minimize, e.g. maximize = \"clearance\""
                    .into(),
            ),
            Some(toml::Value::Table(t)) => vec![t],
            Some(toml::Value::Array(a)) => a
                .iter()
                .map(|e| {
                    e.as_table()
                        .ok_or("[[objective]] entries must be tables".to_string())
                })
                .collect::<Result<_, _>>()?,
            Some(_) => return Err("'objective' must be a table or an array of tables".into()),
        };
    if tables.is_empty() || tables.len() > 2 {
        return Err(format!(
            "{} objectives: give one or two (two give a Pareto front)",
            tables.len()
        ));
    }
    let mut out = vec![];
    for t in tables {
        let mut s = Section::new("objective", t);
        let max = s.string("maximize")?;
        let min = s.string("minimize")?;
        s.done()?;
        let (name, maximize) = match (max, min) {
            (Some(n), None) => (n, true),
            (None, Some(n)) => (n, false),
            _ => {
                return Err(
                    "[objective]: give exactly one of maximize = \"...\" or minimize = \"...\""
                        .into(),
                )
            }
        };
        let quantity = match name.as_str() {
            "threshold_hz" => Quantity::ThresholdHz,
            "power_loss_w" => Quantity::PowerLossW,
            "min_film_um" => Quantity::MinFilmUm,
            "margin" => Quantity::Margin,
            k => match variables.iter().position(|v| v.key == k) {
                Some(i) => Quantity::Variable(i),
                None => {
                    return Err(format!(
                        "[objective] '{k}': expected a design variable ({}) or one of {}",
                        variables
                            .iter()
                            .map(|v| v.key.as_str())
                            .collect::<Vec<_>>()
                            .join(", "),
                        Quantity::NAMES.join(", ")
                    ))
                }
            },
        };
        out.push(Objective { quantity, maximize });
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    const GOOD: &str = r#"
        name = "robust"
        [base]
        preset = "path1"
        f_max = 2000
        [variables]
        clearance = { min = 10, max = 30 }
        c = { min = 200, max = 3000, scale = "log" }
        [requirement]
        min_film_um = 2.0
        max_whirl_um = 1.5
        speed_range_hz = [500, 2000]
        classes = ["stable", "path2a"]
        [tolerances]
        clearance = 2
        c = "20%"
        [objective]
        maximize = "clearance"
        [search]
        budget = 20
        batch = 2
    "#;

    fn parse_ok(text: &str) -> Problem {
        Problem::parse(text, Path::new("opt.toml")).unwrap()
    }

    fn refusal(text: &str) -> String {
        Problem::parse(text, Path::new("opt.toml")).unwrap_err()
    }

    #[test]
    fn a_full_file_is_read_with_its_defaults() {
        let p = parse_ok(GOOD);
        assert_eq!(p.name, "robust");
        assert_eq!(p.variables.len(), 2);
        assert_eq!(p.variables[0].key, "clearance");
        assert_eq!(p.variables[1].bounds.scale, Scale::Log);
        assert_eq!(p.speed_range_hz, (500.0, 2000.0));
        assert_eq!(p.tolerances[1], ("c".into(), Tolerance::Relative(0.2)));
        assert_eq!(
            p.objectives,
            vec![Objective {
                quantity: Quantity::Variable(0),
                maximize: true
            }]
        );
        assert_eq!((p.budget, p.initial, p.batch), (20, 6, 2));
        assert_eq!(p.verify_mesh, (20, 6));
        assert_eq!(p.verify_t_ramp_s, 6.0);
        assert_eq!(p.operating_speed_hz, 2000.0);
    }

    #[test]
    fn corners_are_the_nominal_design_and_every_low_high_combination() {
        let p = parse_ok(GOOD);
        let corners = p.corners(&[20.0, 1000.0], &BTreeMap::new()).unwrap();
        assert_eq!(corners.len(), 5);
        assert_eq!(corners[0]["clearance"], "20");
        assert_eq!(corners[0]["c"], "1000");
        assert_eq!(corners[0]["preset"], "path1");
        let pairs: Vec<(String, String)> = corners[1..]
            .iter()
            .map(|c| (c["clearance"].clone(), c["c"].clone()))
            .collect();
        for want in [("18", "800"), ("22", "800"), ("18", "1200"), ("22", "1200")] {
            assert!(
                pairs.contains(&(want.0.into(), want.1.into())),
                "{want:?} in {pairs:?}"
            );
        }
        // A tolerance that takes the design through zero is refused, not run.
        let e = p.corners(&[1.5, 1000.0], &BTreeMap::new()).unwrap_err();
        assert!(e.contains("tolerance on 'clearance'"), "{e}");
    }

    #[test]
    fn bad_files_are_refused_naming_table_and_key() {
        let cases = [
            (
                GOOD.replace("min = 10, max = 30", "min = 30, max = 10"),
                "clearance: the bounds",
            ),
            (GOOD.replace("min = 200", "min = -1"), "lower bound -1"),
            (
                GOOD.replace("clearance = { min", "clearence = { min"),
                "'clearence' is no design",
            ),
            (
                GOOD.replace("min_film_um = 2.0", ""),
                "min_film_um is missing",
            ),
            (GOOD.replace("c = \"20%\"", "c = \"120%\""), "(0 %, 100 %)"),
            (
                GOOD.replace("maximize = \"clearance\"", "maximize = \"speed\""),
                "'speed'",
            ),
            (
                GOOD.replace("[500, 2000]", "[500, 2500]"),
                "above the run-up's top speed",
            ),
            (GOOD.replace("\"path2a\"", "\"path3\""), "no run-up class"),
            (GOOD.replace("batch = 2", "batch = 0"), "batch = 0"),
            (
                GOOD.replace("batch = 2", "bacth = 2"),
                "[search] unknown key 'bacth'",
            ),
            (
                GOOD.replace("f_max = 2000", "profile = \"0:0,1:100\""),
                "the optimisation sets",
            ),
            (
                GOOD.replace("[tolerances]", "[tolerance]"),
                "unknown key or table 'tolerance'",
            ),
            (
                GOOD.replace("budget = 20", "budget = 20\ninitial = 40"),
                "initial = 40",
            ),
        ];
        for (text, want) in cases {
            let e = refusal(&text);
            assert!(e.starts_with("opt.toml: "), "{e}");
            assert!(e.contains(want), "'{want}' not in: {e}");
        }
    }

    #[test]
    fn the_example_files_are_read() {
        let p = parse_ok(include_str!("../../../studies/optimize_example.toml"));
        assert_eq!((p.dim(), p.tolerances.len(), p.budget), (2, 2, 24));
        let doc = include_str!("../../../docs/reference/optimization-file.md");
        let block = doc
            .split("```toml\n")
            .nth(1)
            .unwrap()
            .split("```")
            .next()
            .unwrap();
        let p = parse_ok(block);
        assert_eq!(p.variables.len(), 3);
        assert_eq!(p.classes, vec!["stable", "path2a"]);
    }

    #[test]
    fn values_keep_four_significant_digits_and_integers_stay_whole() {
        assert_eq!(significant(12.34567, 4), 12.35);
        assert_eq!(significant(1234.567, 4), 1235.0);
        assert_eq!(significant(0.001234567, 4), 0.001235);
        let p = parse_ok(&GOOD.replace(
            "c = { min = 200",
            "\"film.n_lobes\" = { min = 2, max = 5, integer = true }\nc = { min = 200",
        ));
        let lobes = p
            .variables
            .iter()
            .find(|v| v.key == "film.n_lobes")
            .unwrap();
        assert_eq!(lobes.round(3.6), 4.0);
    }
}
