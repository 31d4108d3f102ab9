//! The variable table: the single source of truth for a model's interface.
//!
//! Each model declares a `ModelInfo` in Rust; the modelDescription.xml generator (`xml.rs`), the
//! value store, the call checks and the GUID are all derived from it. Value references are dense per
//! type (Real 0..n, Integer 0..m, Boolean 0..k), fixed by the table and stable across versions.

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Causality {
    Parameter,
    CalculatedParameter,
    Input,
    Output,
    Local,
    Independent,
}

impl Causality {
    pub fn as_str(self) -> &'static str {
        match self {
            Causality::Parameter => "parameter",
            Causality::CalculatedParameter => "calculatedParameter",
            Causality::Input => "input",
            Causality::Output => "output",
            Causality::Local => "local",
            Causality::Independent => "independent",
        }
    }
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Variability {
    Constant,
    Fixed,
    Tunable,
    Discrete,
    Continuous,
}

impl Variability {
    pub fn as_str(self) -> &'static str {
        match self {
            Variability::Constant => "constant",
            Variability::Fixed => "fixed",
            Variability::Tunable => "tunable",
            Variability::Discrete => "discrete",
            Variability::Continuous => "continuous",
        }
    }
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Initial {
    Exact,
    Approx,
    Calculated,
}

impl Initial {
    pub fn as_str(self) -> &'static str {
        match self {
            Initial::Exact => "exact",
            Initial::Approx => "approx",
            Initial::Calculated => "calculated",
        }
    }
}

#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum VarType {
    Real,
    Integer,
    Boolean,
}

impl VarType {
    pub fn as_str(self) -> &'static str {
        match self {
            VarType::Real => "Real",
            VarType::Integer => "Integer",
            VarType::Boolean => "Boolean",
        }
    }
}

/// One entry of the variable table. `start` is stored as f64 for every type (Integer and Boolean
/// values are exact in f64); it is `None` for calculated variables.
#[derive(Clone, Debug)]
pub struct Variable {
    pub name: &'static str,
    pub vr: u32,
    pub var_type: VarType,
    pub causality: Causality,
    pub variability: Variability,
    pub initial: Option<Initial>,
    pub start: Option<f64>,
    /// SI unit, one of the units known to `units.rs`.
    pub unit: Option<&'static str>,
    /// The unit an engineer reads (um, N/mm, Hz, ...), declared as a DisplayUnit of `unit`.
    pub display_unit: Option<&'static str>,
    pub min: Option<f64>,
    pub max: Option<f64>,
    pub description: &'static str,
}

impl Variable {
    fn base(name: &'static str, vr: u32, var_type: VarType, description: &'static str) -> Self {
        Variable {
            name,
            vr,
            var_type,
            causality: Causality::Local,
            variability: Variability::Continuous,
            initial: None,
            start: None,
            unit: None,
            display_unit: None,
            min: None,
            max: None,
            description,
        }
    }
    /// A fixed Real parameter with a start value.
    pub fn real_parameter(
        name: &'static str,
        vr: u32,
        start: f64,
        unit: &'static str,
        description: &'static str,
    ) -> Self {
        Variable {
            causality: Causality::Parameter,
            variability: Variability::Fixed,
            initial: Some(Initial::Exact),
            start: Some(start),
            unit: non_empty(unit),
            ..Self::base(name, vr, VarType::Real, description)
        }
    }
    /// A fixed Integer parameter.
    pub fn integer_parameter(
        name: &'static str,
        vr: u32,
        start: i32,
        description: &'static str,
    ) -> Self {
        Variable {
            causality: Causality::Parameter,
            variability: Variability::Fixed,
            initial: Some(Initial::Exact),
            start: Some(start as f64),
            ..Self::base(name, vr, VarType::Integer, description)
        }
    }
    /// A fixed Boolean parameter.
    pub fn boolean_parameter(
        name: &'static str,
        vr: u32,
        start: bool,
        description: &'static str,
    ) -> Self {
        Variable {
            causality: Causality::Parameter,
            variability: Variability::Fixed,
            initial: Some(Initial::Exact),
            start: Some(if start { 1.0 } else { 0.0 }),
            ..Self::base(name, vr, VarType::Boolean, description)
        }
    }
    /// A continuous Real input with a start value.
    pub fn real_input(
        name: &'static str,
        vr: u32,
        start: f64,
        unit: &'static str,
        description: &'static str,
    ) -> Self {
        Variable {
            causality: Causality::Input,
            variability: Variability::Continuous,
            start: Some(start),
            unit: non_empty(unit),
            ..Self::base(name, vr, VarType::Real, description)
        }
    }
    /// A continuous Real output computed by the model.
    pub fn real_output(
        name: &'static str,
        vr: u32,
        unit: &'static str,
        description: &'static str,
    ) -> Self {
        Variable {
            causality: Causality::Output,
            variability: Variability::Continuous,
            initial: Some(Initial::Calculated),
            unit: non_empty(unit),
            ..Self::base(name, vr, VarType::Real, description)
        }
    }
    /// A discrete Integer output (counters, statistics).
    pub fn integer_output(name: &'static str, vr: u32, description: &'static str) -> Self {
        Variable {
            causality: Causality::Output,
            variability: Variability::Discrete,
            initial: Some(Initial::Calculated),
            ..Self::base(name, vr, VarType::Integer, description)
        }
    }
    pub fn display(mut self, display_unit: &'static str) -> Self {
        self.display_unit = Some(display_unit);
        self
    }
    pub fn range(mut self, min: Option<f64>, max: Option<f64>) -> Self {
        self.min = min;
        self.max = max;
        self
    }
    /// May be set (through fmi2SetXXX) in the given instance phase.
    pub fn settable_before_init(&self) -> bool {
        matches!(self.causality, Causality::Parameter | Causality::Input)
            && self.variability != Variability::Constant
    }
    pub fn settable_during_run(&self) -> bool {
        self.causality == Causality::Input
            || (self.causality == Causality::Parameter && self.variability == Variability::Tunable)
    }
}

fn non_empty(s: &'static str) -> Option<&'static str> {
    (!s.is_empty()).then_some(s)
}

#[derive(Clone, Copy, Debug)]
pub struct DefaultExperiment {
    pub start_time: f64,
    pub stop_time: f64,
    pub tolerance: f64,
    pub step_size: f64,
}

/// Everything the FMI layer needs to know about a model's interface.
#[derive(Clone, Debug)]
pub struct ModelInfo {
    pub model_name: &'static str,
    pub model_identifier: &'static str,
    pub description: &'static str,
    pub version: &'static str,
    pub variables: Vec<Variable>,
    /// Model-specific log categories (name, description), in addition to the standard ones.
    pub log_categories: Vec<(&'static str, &'static str)>,
    pub default_experiment: DefaultExperiment,
    /// HTML body of documentation/index.html (the generic part, the variable table, is added by xtask).
    pub documentation_html: &'static str,
}

/// Where each variable sits in `ModelInfo::variables`, by type and value reference: every
/// fmi2Set/Get call looks its variables up, and a scan of the table per value cost ~1 us per call.
#[derive(Clone, Debug, Default)]
pub struct VarIndex {
    by_type: [Vec<usize>; 3],
}

impl VarIndex {
    const NONE: usize = usize::MAX;

    fn slot(t: VarType) -> usize {
        match t {
            VarType::Real => 0,
            VarType::Integer => 1,
            VarType::Boolean => 2,
        }
    }

    pub fn new(info: &ModelInfo) -> Self {
        let mut ix = VarIndex::default();
        for (i, v) in info.variables.iter().enumerate() {
            let list = &mut ix.by_type[Self::slot(v.var_type)];
            let vr = v.vr as usize;
            if list.len() <= vr {
                list.resize(vr + 1, Self::NONE);
            }
            list[vr] = i;
        }
        ix
    }

    /// Number of value references of a type (dense per type: `ModelInfo::check`).
    pub fn count(&self, t: VarType) -> usize {
        self.by_type[Self::slot(t)].len()
    }

    pub fn variable<'a>(&self, info: &'a ModelInfo, t: VarType, vr: u32) -> Option<&'a Variable> {
        match self.by_type[Self::slot(t)].get(vr as usize) {
            Some(&i) if i != Self::NONE => info.variables.get(i),
            _ => None,
        }
    }
}

/// The log categories every AirRing FMU declares (FMI 2.0 recommended names).
pub const STANDARD_LOG_CATEGORIES: &[(&str, &str)] = &[
    ("logEvents", "Log events"),
    ("logStatusWarning", "Log messages with status fmi2Warning"),
    ("logStatusDiscard", "Log messages with status fmi2Discard"),
    ("logStatusError", "Log messages with status fmi2Error"),
    ("logStatusFatal", "Log messages with status fmi2Fatal"),
    ("logAll", "Log all messages"),
];

impl ModelInfo {
    /// Number of value references of each type (value references are dense per type).
    pub fn count(&self, t: VarType) -> usize {
        self.variables.iter().filter(|v| v.var_type == t).count()
    }

    pub fn variable(&self, t: VarType, vr: u32) -> Option<&Variable> {
        self.variables
            .iter()
            .find(|v| v.var_type == t && v.vr == vr)
    }

    pub fn by_name(&self, name: &str) -> Option<&Variable> {
        self.variables.iter().find(|v| v.name == name)
    }

    /// All log categories: standard ones first, then the model's.
    pub fn all_log_categories(&self) -> Vec<(&'static str, &'static str)> {
        let mut all: Vec<_> = STANDARD_LOG_CATEGORIES.to_vec();
        all.extend(self.log_categories.iter().copied());
        all
    }

    /// Checks the table's invariants: unique names, dense value references per type, start values
    /// where FMI requires them and none where it forbids them, known units.
    pub fn check(&self) -> Result<(), String> {
        for t in [VarType::Real, VarType::Integer, VarType::Boolean] {
            let mut vrs: Vec<u32> = self
                .variables
                .iter()
                .filter(|v| v.var_type == t)
                .map(|v| v.vr)
                .collect();
            vrs.sort_unstable();
            for (i, vr) in vrs.iter().enumerate() {
                if *vr != i as u32 {
                    return Err(format!(
                        "{} value references must be dense 0..n, found {vrs:?}",
                        t.as_str()
                    ));
                }
            }
        }
        for (i, a) in self.variables.iter().enumerate() {
            if self.variables[..i].iter().any(|b| b.name == a.name) {
                return Err(format!("variable name '{}' is used twice", a.name));
            }
            let needs_start = matches!(a.causality, Causality::Parameter | Causality::Input)
                || matches!(a.initial, Some(Initial::Exact | Initial::Approx));
            if needs_start && a.start.is_none() {
                return Err(format!("variable '{}' needs a start value", a.name));
            }
            if a.initial == Some(Initial::Calculated) && a.start.is_some() {
                return Err(format!(
                    "calculated variable '{}' must not have a start value",
                    a.name
                ));
            }
            if let Some(u) = a.unit {
                let def = crate::units::unit(u)
                    .ok_or_else(|| format!("variable '{}': unknown unit '{u}'", a.name))?;
                if let Some(d) = a.display_unit {
                    if !def.display_units.iter().any(|du| du.0 == d) {
                        return Err(format!(
                            "variable '{}': '{d}' is not a display unit of '{u}'",
                            a.name
                        ));
                    }
                }
            } else if a.display_unit.is_some() {
                return Err(format!(
                    "variable '{}' has a display unit but no unit",
                    a.name
                ));
            }
        }
        Ok(())
    }

    /// A GUID derived from the interface (identifier and every variable's name, type, value reference
    /// and causality): it changes exactly when the interface changes, so an importer holding an old
    /// modelDescription.xml is refused by fmi2Instantiate.
    pub fn guid(&self) -> String {
        let mut h = Fnv64::new();
        h.write(self.model_identifier.as_bytes());
        for v in &self.variables {
            h.write(v.name.as_bytes());
            h.write(v.var_type.as_str().as_bytes());
            h.write(&v.vr.to_le_bytes());
            h.write(v.causality.as_str().as_bytes());
            h.write(v.variability.as_str().as_bytes());
        }
        let a = h.finish();
        h.write(b"second half");
        let b = h.finish();
        format!(
            "{{{:08x}-{:04x}-{:04x}-{:04x}-{:012x}}}",
            (a >> 32) as u32,
            (a >> 16) as u16,
            a as u16,
            (b >> 48) as u16,
            b & 0xffff_ffff_ffff
        )
    }
}

/// FNV-1a, 64 bit: a small, dependency-free hash for GUIDs and blob checksums (not cryptographic).
#[derive(Clone, Copy)]
pub struct Fnv64(u64);

impl Fnv64 {
    pub fn new() -> Self {
        Fnv64(0xcbf2_9ce4_8422_2325)
    }
    pub fn write(&mut self, bytes: &[u8]) {
        for b in bytes {
            self.0 ^= *b as u64;
            self.0 = self.0.wrapping_mul(0x0000_0100_0000_01b3);
        }
    }
    pub fn finish(&self) -> u64 {
        self.0
    }
}

impl Default for Fnv64 {
    fn default() -> Self {
        Self::new()
    }
}
