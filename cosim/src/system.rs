//! System files: which FMUs, their parameters, how outputs feed inputs, and the algorithm.
//!
//! ```toml
//! [[fmu]]
//! name = "rotor"
//! path = "rotor.fmu"                 # relative to this file
//! parameters = { c_C = "1000 N/mm", d_C = 50.0 }   # a number is SI; a string carries its unit
//!
//! [[connection]]
//! from = "rotor.dx_C"
//! to = "film_C.dx"
//!
//! [algorithm]
//! kind = "gauss-seidel"              # or "jacobi"
//! order = ["rotor", "film_C", "film_T"]
//! macro_step = "10 us"
//! stop_time = "3 s"
//! extrapolation_order = 1            # 0, 1, 2: inputs from subsystems not yet stepped
//! interpolation_order = 1            # 0, 1, 2: inputs from subsystems already stepped (Gauss-Seidel)
//! # optional: refine the macro step (down to 1/64) where an extrapolated input misses the
//! # actual output at T_N+1 by more than atol + rtol |u| (units of those inputs; needs rollback)
//! step_control = { rtol = 0.1, atol = 1.0 }
//! # optional: macro steps of `factor` x macro_step inside these windows of time [s]
//! long_steps = { factor = 2, windows = [[0.08, 0.55]] }
//!
//! [output]
//! interval = "100 us"                # rows at its multiples, and at the stop time
//! variables = ["rotor.omega", "film_C.Fx"]
//! ```
//! Every error names the file, the line and the field. A run's copy of a system file whose FMU
//! paths are relative gets a first key `base_dir`, the original file's folder, which relative
//! paths are then taken from.

use serde::Deserialize;
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use toml::Spanned;

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct FmuEntry {
    pub name: Spanned<String>,
    pub path: Spanned<String>,
    #[serde(default)]
    pub parameters: BTreeMap<String, Spanned<toml::Value>>,
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ConnectionEntry {
    pub from: Spanned<String>,
    pub to: Spanned<String>,
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct AlgorithmEntry {
    #[serde(default = "default_kind")]
    pub kind: Spanned<String>,
    #[serde(default)]
    pub order: Option<Spanned<Vec<String>>>,
    pub macro_step: Spanned<toml::Value>,
    pub stop_time: Spanned<toml::Value>,
    #[serde(default = "one")]
    pub extrapolation_order: Spanned<u8>,
    #[serde(default = "one")]
    pub interpolation_order: Spanned<u8>,
    /// Save FMU states every macro step so a discarded step can be retried with a smaller step.
    #[serde(default = "yes")]
    pub rollback: bool,
    /// Step independent subsystems (the two air films) in parallel threads.
    #[serde(default = "yes")]
    pub parallel: bool,
    /// Macro-step control by the coupling error (off when absent).
    #[serde(default)]
    pub step_control: Option<Spanned<StepControlEntry>>,
    /// Longer macro steps in given windows of time (`step_plan`; none when absent).
    #[serde(default)]
    pub long_steps: Option<Spanned<LongStepsEntry>>,
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct LongStepsEntry {
    /// Base macro steps per long step.
    pub factor: u64,
    /// [start, end] in seconds of simulated time, ordered.
    pub windows: Vec<[f64; 2]>,
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct StepControlEntry {
    pub rtol: f64,
    /// In the units of the extrapolated inputs.
    pub atol: f64,
}

fn default_kind() -> Spanned<String> {
    Spanned::new(0..0, "gauss-seidel".to_string())
}
fn one() -> Spanned<u8> {
    Spanned::new(0..0, 1)
}
fn yes() -> bool {
    true
}

#[derive(Debug, Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct OutputEntry {
    #[serde(default)]
    pub interval: Option<Spanned<toml::Value>>,
    #[serde(default)]
    pub variables: Vec<Spanned<String>>,
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SystemFile {
    /// The folder relative FMU paths are taken from, where it is not the file's own: a run
    /// writes it into its copy of a system file whose FMU paths are relative
    /// ([`System::text_for_copy_in`]), so that a resume from the run folder finds them.
    #[serde(default)]
    pub base_dir: Option<String>,
    pub fmu: Vec<FmuEntry>,
    #[serde(default)]
    pub connection: Vec<ConnectionEntry>,
    pub algorithm: AlgorithmEntry,
    #[serde(default)]
    pub output: OutputEntry,
}

/// A parsed system file with its source, for error messages with line numbers.
pub struct System {
    pub file: SystemFile,
    pub path: PathBuf,
    pub text: String,
}

/// An error that points at a place in the system file.
#[derive(Debug)]
pub struct SystemError(pub String);

impl std::fmt::Display for SystemError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(&self.0)
    }
}

impl std::error::Error for SystemError {}

impl System {
    pub fn load(path: &Path) -> Result<System, SystemError> {
        let text = std::fs::read_to_string(path)
            .map_err(|e| SystemError(format!("{}: {e}", path.display())))?;
        Self::parse(path, text)
    }

    pub fn parse(path: &Path, text: String) -> Result<System, SystemError> {
        let file: SystemFile = toml::from_str(&text).map_err(|e| {
            let line = e
                .span()
                .map(|s| line_of(&text, s.start))
                .map(|l| format!(":{l}"))
                .unwrap_or_default();
            // The parser's message names the type it wanted, not the key: the key the value
            // belongs to, read from the text before it ("integer `-1`, expected u8" alone did
            // not say which of the file's numbers was meant).
            let key = e
                .span()
                .and_then(|s| key_before(&text, s.start))
                .map(|k| format!(" {k}:"))
                .unwrap_or_default();
            SystemError(format!("{}{line}:{key} {}", path.display(), e.message()))
        })?;
        Ok(System {
            file,
            path: path.to_path_buf(),
            text,
        })
    }

    /// "file:line: field: message" for a spanned value.
    pub fn error_at<T>(
        &self,
        at: &Spanned<T>,
        field: &str,
        message: impl std::fmt::Display,
    ) -> SystemError {
        SystemError(format!(
            "{}:{}: {field}: {message}",
            self.path.display(),
            line_of(&self.text, at.span().start)
        ))
    }

    /// FMU paths are relative to the system file's folder (or its `base_dir`).
    pub fn resolve(&self, p: &str) -> PathBuf {
        let p = Path::new(p);
        if p.is_absolute() {
            p.to_path_buf()
        } else if let Some(base) = &self.file.base_dir {
            Path::new(base).join(p)
        } else {
            self.path.parent().unwrap_or(Path::new(".")).join(p)
        }
    }

    /// The text of this file for a copy in another folder: as it is, unless an FMU path is
    /// relative and the file names no `base_dir`; then with a first line `base_dir = "..."`
    /// naming this file's folder (absolute), so that the copy finds the same FMUs.
    pub fn text_for_copy_in(&self) -> String {
        let relative = self
            .file
            .fmu
            .iter()
            .any(|e| !Path::new(e.path.get_ref()).is_absolute());
        if !relative || self.file.base_dir.is_some() {
            return self.text.clone();
        }
        let folder = self.path.parent().unwrap_or(Path::new("."));
        let folder = if folder.as_os_str().is_empty() {
            Path::new(".")
        } else {
            folder
        };
        let folder = std::fs::canonicalize(folder).unwrap_or_else(|_| folder.to_path_buf());
        let quoted = toml::Value::String(folder.to_string_lossy().into_owned());
        format!(
            "# written by the run: its FMU paths are relative to the original system file's folder\n\
             base_dir = {quoted}\n{}",
            self.text
        )
    }

    /// A time quantity in seconds: a number (s) or a string "10 us", "2.5 ms", "3 s".
    pub fn seconds(&self, v: &Spanned<toml::Value>, field: &str) -> Result<f64, SystemError> {
        let x = match v.get_ref() {
            toml::Value::Float(x) => *x,
            toml::Value::Integer(i) => *i as f64,
            toml::Value::String(s) => {
                let (num, unit) = split_quantity(s).ok_or_else(|| {
                    self.error_at(v, field, format!("'{s}' is not 'number unit'"))
                })?;
                // Divide by an exact power of ten (rather than multiply by an inexact 1e-6) so
                // that "10 us" is the double nearest to 1e-5 s, as a user typing it expects.
                let per_second = match unit {
                    "s" | "" => 1.0,
                    "ms" => 1e3,
                    "us" => 1e6,
                    "ns" => 1e9,
                    _ => {
                        return Err(self.error_at(
                            v,
                            field,
                            format!("unknown time unit '{unit}' (use s, ms, us)"),
                        ))
                    }
                };
                num / per_second
            }
            other => {
                return Err(self.error_at(v, field, format!("expected a time, found {other}")))
            }
        };
        if !(x.is_finite() && x > 0.0) {
            return Err(self.error_at(
                v,
                field,
                format!(
                    "must be a positive time, found {} s",
                    crate::number::short(x)
                ),
            ));
        }
        Ok(x)
    }
}

/// The key whose value starts at `offset`, from the text before it on its line: `order = -1`
/// and `{ x0 = -1 }` give `order` and `x0`. None where no `=` precedes it on the line.
fn key_before(text: &str, offset: usize) -> Option<String> {
    let before = text.get(..offset)?;
    let line = &before[before.rfind('\n').map_or(0, |i| i + 1)..];
    let head = line.trim_end().strip_suffix('=')?.trim_end();
    let start = head
        .rfind(|c: char| !(c.is_alphanumeric() || matches!(c, '_' | '-' | '.' | '"')))
        .map_or(0, |i| i + 1);
    let key = head[start..].trim_matches('"');
    (!key.is_empty()).then(|| key.to_string())
}

/// 1-based line number of a byte offset.
pub fn line_of(text: &str, offset: usize) -> usize {
    text[..offset.min(text.len())]
        .bytes()
        .filter(|b| *b == b'\n')
        .count()
        + 1
}

/// "1000 N/mm" -> (1000, "N/mm"); "3" -> (3, "").
pub fn split_quantity(s: &str) -> Option<(f64, &str)> {
    let s = s.trim();
    let end = s.find(|c: char| c.is_whitespace()).unwrap_or(s.len());
    let num: f64 = s[..end].parse().ok()?;
    Some((num, s[end..].trim()))
}

/// "instance.variable" -> (instance, variable).
pub fn split_port(s: &str) -> Option<(&str, &str)> {
    s.split_once('.')
        .filter(|(a, b)| !a.is_empty() && !b.is_empty())
}

#[cfg(test)]
mod tests {
    use super::*;

    const GOOD: &str = r#"
[[fmu]]
name = "osc"
path = "osc.fmu"
parameters = { k = "4 N/m" }

[algorithm]
macro_step = "10 us"
stop_time = 0.5
"#;

    #[test]
    fn parses_and_converts_times() {
        let s = System::parse(Path::new("/x/sys.toml"), GOOD.into()).unwrap();
        assert_eq!(
            s.seconds(&s.file.algorithm.macro_step, "macro_step")
                .unwrap(),
            1e-5
        );
        assert_eq!(
            s.seconds(&s.file.algorithm.stop_time, "stop_time").unwrap(),
            0.5
        );
        assert_eq!(s.resolve("osc.fmu"), PathBuf::from("/x/osc.fmu"));
        assert_eq!(*s.file.algorithm.extrapolation_order.get_ref(), 1);
    }

    #[test]
    fn errors_name_file_line_and_field() {
        let bad = GOOD.replace("\"10 us\"", "\"10 parsecs\"");
        let s = System::parse(Path::new("sys.toml"), bad).unwrap();
        let e = s
            .seconds(&s.file.algorithm.macro_step, "algorithm.macro_step")
            .unwrap_err();
        assert_eq!(
            e.0,
            "sys.toml:8: algorithm.macro_step: unknown time unit 'parsecs' (use s, ms, us)"
        );
        let e = System::parse(Path::new("sys.toml"), GOOD.replace("stop_time", "stop_tim"))
            .err()
            .unwrap();
        assert!(
            e.0.starts_with("sys.toml:9: unknown field `stop_tim`"),
            "{}",
            e.0
        );
    }
}
