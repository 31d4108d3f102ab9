//! What both standards' modelDescription.xml writers share (`fmi2::xml`, `fmi3::xml`): attribute
//! escaping, numbers that read back exactly, and the unit definitions from the unit table.

use crate::units;
use std::fmt::Write;

/// XML attribute escaping.
pub fn escape(s: &str) -> String {
    s.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
        .replace('"', "&quot;")
}

/// Shortest decimal that reads back to the same f64.
pub fn num(x: f64) -> String {
    format!("{x:?}")
}

/// The `<UnitDefinitions>` element (indented as a child of the root) for the named units, from the
/// unit table; the same in FMI 2.0 and 3.0.
pub fn unit_definitions(used: &[&str]) -> String {
    let mut x = String::new();
    writeln!(x, "  <UnitDefinitions>").unwrap();
    for name in used {
        let u = units::unit(name).expect("units checked by ModelInfo::check");
        writeln!(x, r#"    <Unit name="{}">"#, escape(u.name)).unwrap();
        let labels = ["kg", "m", "s", "A", "K", "mol", "cd", "rad"];
        let mut base = String::new();
        for (l, e) in labels.iter().zip(u.base) {
            if e != 0 {
                write!(base, r#" {l}="{e}""#).unwrap();
            }
        }
        writeln!(x, "      <BaseUnit{base}/>").unwrap();
        for (dn, factor, offset) in u.display_units {
            writeln!(
                x,
                r#"      <DisplayUnit name="{}" factor="{}" offset="{}"/>"#,
                escape(dn),
                num(*factor),
                num(*offset)
            )
            .unwrap();
        }
        writeln!(x, "    </Unit>").unwrap();
    }
    writeln!(x, "  </UnitDefinitions>").unwrap();
    x
}
