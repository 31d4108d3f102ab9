//! The SI units used on AirRing interfaces and the display units engineers read.
//!
//! FMI 2.0: `display_value = factor * value + offset`.

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
