//! FMI 3.0 value references from the fmi2 variable table.
//!
//! FMI 2.0 value references are unique per type only (our tables number Real 0.., Integer 0..,
//! Boolean 0..); FMI 3.0 requires them unique across all variables. The mapping is fixed, so a
//! Float64 keeps the number an FMI 2.0 importer knows and SSP files translate by an offset:
//!
//! | FMI 3.0 variable              | value reference            |
//! |-------------------------------|----------------------------|
//! | Float64 (fmi2 Real `vr`)      | `vr`                       |
//! | Int32 (fmi2 Integer `vr`)     | `INT32_VR_OFFSET + vr`     |
//! | Boolean (fmi2 Boolean `vr`)   | `BOOLEAN_VR_OFFSET + vr`   |
//! | `time` (independent, Float64) | `TIME_VR`                  |
//!
//! FMI 3.0 requires exactly one independent variable; the fmi2 tables have none, so the layer adds
//! `time`. A table with `BLOCK_SIZE` or more variables of one type does not fit: `check` refuses it.

use fmi_core::variables::ModelInfo;
use fmi_core::variables::VarType;

/// Width of each type's block of value references.
pub const BLOCK_SIZE: u32 = 1_000_000;
pub const INT32_VR_OFFSET: u32 = BLOCK_SIZE;
pub const BOOLEAN_VR_OFFSET: u32 = 2 * BLOCK_SIZE;
/// The independent variable `time` (read-only: fmi3SetFloat64 refuses it).
pub const TIME_VR: u32 = 3 * BLOCK_SIZE;
pub const TIME_NAME: &str = "time";

/// What an FMI 3.0 value reference designates (before checking it exists in the table).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Target {
    /// A variable of the fmi2 table: its type and fmi2 value reference.
    Variable(VarType, u32),
    /// The independent variable.
    Time,
    /// Outside every block.
    Unknown,
}

/// FMI 3.0 value reference of an fmi2 variable.
pub fn to_fmi3(t: VarType, vr: u32) -> u32 {
    match t {
        VarType::Real => vr,
        VarType::Integer => INT32_VR_OFFSET + vr,
        VarType::Boolean => BOOLEAN_VR_OFFSET + vr,
    }
}

pub fn target(vr3: u32) -> Target {
    match vr3 / BLOCK_SIZE {
        0 => Target::Variable(VarType::Real, vr3),
        1 => Target::Variable(VarType::Integer, vr3 - INT32_VR_OFFSET),
        2 => Target::Variable(VarType::Boolean, vr3 - BOOLEAN_VR_OFFSET),
        _ if vr3 == TIME_VR => Target::Time,
        _ => Target::Unknown,
    }
}

/// FMI 3.0 type name of an fmi2 type.
pub fn type_name(t: VarType) -> &'static str {
    match t {
        VarType::Real => "Float64",
        VarType::Integer => "Int32",
        VarType::Boolean => "Boolean",
    }
}

/// The table fits the mapping and does not use the name of the added independent variable.
pub fn check(info: &ModelInfo) -> Result<(), String> {
    for t in [VarType::Real, VarType::Integer, VarType::Boolean] {
        if info.count(t) >= BLOCK_SIZE as usize {
            return Err(format!(
                "{} {} variables do not fit a block of {BLOCK_SIZE} value references",
                info.count(t),
                t.as_str()
            ));
        }
    }
    if info.by_name(TIME_NAME).is_some() {
        return Err(format!(
            "a variable is named '{TIME_NAME}', the name of the independent variable FMI 3.0 adds"
        ));
    }
    Ok(())
}

/// Is FMI 3.0 value reference `vr3` a Float64 input (the variables with `intermediateUpdate="true"`)?
pub fn is_float64_input(info: &ModelInfo, vr3: u32) -> bool {
    match target(vr3) {
        Target::Variable(VarType::Real, vr) => info.variables.iter().any(|v| {
            v.var_type == VarType::Real
                && v.vr == vr
                && v.causality == fmi_core::variables::Causality::Input
        }),
        _ => false,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn mapping_round_trips() {
        for t in [VarType::Real, VarType::Integer, VarType::Boolean] {
            for vr in [0, 1, 17, BLOCK_SIZE - 1] {
                assert_eq!(target(to_fmi3(t, vr)), Target::Variable(t, vr));
            }
        }
        assert_eq!(target(TIME_VR), Target::Time);
        assert_eq!(target(TIME_VR + 1), Target::Unknown);
        assert_eq!(target(u32::MAX), Target::Unknown);
    }
}
