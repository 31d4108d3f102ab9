//! The SI units used on AirRing interfaces and the display units engineers read.
//!
//! FMI 2.0: `display_value = factor * value + offset`.

use crate::variables::{ModelInfo, VarType, Variable};

pub struct UnitDef {
    pub name: &'static str,
    /// SI base-unit exponents: kg, m, s, A, K, mol, cd, rad.
    pub base: [i32; 8],
    /// (name, factor, offset)
    pub display_units: &'static [(&'static str, f64, f64)],
}

const TWO_PI: f64 = std::f64::consts::TAU;

pub const UNITS: &[UnitDef] = &[
    UnitDef {
        name: "m",
        base: [0, 1, 0, 0, 0, 0, 0, 0],
        display_units: &[("um", 1e6, 0.0), ("mm", 1e3, 0.0)],
    },
    UnitDef {
        name: "m/s",
        base: [0, 1, -1, 0, 0, 0, 0, 0],
        display_units: &[("mm/s", 1e3, 0.0)],
    },
    UnitDef {
        name: "m/s2",
        base: [0, 1, -2, 0, 0, 0, 0, 0],
        display_units: &[],
    },
    UnitDef {
        name: "s",
        base: [0, 0, 1, 0, 0, 0, 0, 0],
        display_units: &[("ms", 1e3, 0.0), ("us", 1e6, 0.0)],
    },
    UnitDef {
        name: "kg",
        base: [1, 0, 0, 0, 0, 0, 0, 0],
        display_units: &[("g", 1e3, 0.0)],
    },
    UnitDef {
        name: "kg.m2",
        base: [1, 2, 0, 0, 0, 0, 0, 0],
        display_units: &[("kg.mm2", 1e6, 0.0)],
    },
    UnitDef {
        name: "N",
        base: [1, 1, -2, 0, 0, 0, 0, 0],
        display_units: &[("mN", 1e3, 0.0)],
    },
    UnitDef {
        name: "N/m",
        base: [1, 0, -2, 0, 0, 0, 0, 0],
        display_units: &[("N/mm", 1e-3, 0.0)],
    },
    UnitDef {
        name: "N.s/m",
        base: [1, 0, -1, 0, 0, 0, 0, 0],
        display_units: &[],
    },
    UnitDef {
        name: "N/m3",
        base: [1, -2, -2, 0, 0, 0, 0, 0],
        display_units: &[("N/mm3", 1e-9, 0.0)],
    },
    UnitDef {
        name: "Pa",
        base: [1, -1, -2, 0, 0, 0, 0, 0],
        display_units: &[("bar", 1e-5, 0.0), ("kPa", 1e-3, 0.0)],
    },
    UnitDef {
        name: "Pa.s",
        base: [1, -1, -1, 0, 0, 0, 0, 0],
        display_units: &[],
    },
    UnitDef {
        name: "rad",
        base: [0, 0, 0, 0, 0, 0, 0, 1],
        display_units: &[("deg", 360.0 / TWO_PI, 0.0)],
    },
    UnitDef {
        name: "rad/s",
        base: [0, 0, -1, 0, 0, 0, 0, 1],
        display_units: &[("Hz", 1.0 / TWO_PI, 0.0), ("rpm", 60.0 / TWO_PI, 0.0)],
    },
    UnitDef {
        name: "Hz",
        base: [0, 0, -1, 0, 0, 0, 0, 0],
        display_units: &[],
    },
    UnitDef {
        name: "N.m",
        base: [1, 2, -2, 0, 0, 0, 0, 0],
        display_units: &[("N.mm", 1e3, 0.0)],
    },
    UnitDef {
        name: "W",
        base: [1, 2, -3, 0, 0, 0, 0, 0],
        display_units: &[],
    },
    UnitDef {
        name: "1",
        base: [0, 0, 0, 0, 0, 0, 0, 0],
        display_units: &[],
    },
];

pub fn unit(name: &str) -> Option<&'static UnitDef> {
    UNITS.iter().find(|u| u.name == name)
}

/// `si`, a value of `var` in its SI unit, with that unit and, where the variable declares one,
/// its display unit: "-5000 N/m (-5 N/mm)", "2.5e-5 m (25 um)"; the bare number where the
/// variable has no unit or the dimensionless "1" (not "rtol = 2 1"). `number` prints a number
/// (the model's own short form).
pub fn quantity_text(var: &Variable, si: f64, number: &dyn Fn(f64) -> String) -> String {
    let Some(unit_name) = var.unit.filter(|u| *u != "1") else {
        return number(si);
    };
    let display = var.display_unit.and_then(|d| {
        let (_, factor, offset) = unit(unit_name)?.display_units.iter().find(|u| u.0 == d)?;
        Some(format!(" ({} {d})", number(si * factor + offset)))
    });
    format!("{} {unit_name}{}", number(si), display.unwrap_or_default())
}

/// A model's refusal of one of its parameters, "... parameter NAME = VALUE: REASON" with VALUE a
/// bare SI number (the libraries' text), with VALUE in the units `info` declares for NAME:
/// "... parameter c_C = -5000 N/m (-5 N/mm): must be >= 0". Any other text comes back as it
/// is, and so does one whose NAME is no Real variable of `info` (a library's internal setting)
/// or whose VALUE is not finite or already has its unit.
pub fn parameter_error_with_units(
    info: &ModelInfo,
    error: String,
    number: &dyn Fn(f64) -> String,
) -> String {
    let Some(at) = error.find("parameter ").map(|i| i + "parameter ".len()) else {
        return error;
    };
    let rest = &error[at..];
    let Some((name, tail)) = rest.split_once(" = ") else {
        return error;
    };
    let (value_text, reason) = tail.split_once(": ").unwrap_or((tail, ""));
    let (Ok(value), Some(var)) = (
        value_text.parse::<f64>(),
        info.variables.iter().find(|v| v.name == name),
    ) else {
        return error;
    };
    if var.var_type != VarType::Real || !value.is_finite() {
        return error;
    }
    let sep = if reason.is_empty() { "" } else { ": " };
    format!(
        "{}{name} = {}{sep}{reason}",
        &error[..at],
        quantity_text(var, value, number)
    )
}
