//! `airring sweep-sensitivity DIR`: how a study's map depends on the classifier's bounds. Every
//! completed run of the sweep folder is classified again with each bound moved down and up by a
//! factor (default +-20 %), the others at their defaults; `sensitivity.csv` gets one row per run
//! (its class, then its class under each moved bound), and the command prints, per moved bound,
//! the runs whose class changes.

use super::collect;
use crate::analysis::classify::{classify_with, Bounds};
use crate::analysis::load_run;
use std::fmt::Write as _;
use std::path::{Path, PathBuf};

/// One run's classes: with the default bounds, then per (bound, factor) in `variants` order.
#[derive(Debug, Clone, PartialEq)]
pub struct RunSensitivity {
    pub name: String,
    pub base: String,
    pub moved: Vec<String>,
}

/// The (bound name, factor) pairs for a relative move `delta`: each bound times 1 - delta and
/// 1 + delta.
pub fn variants(delta: f64) -> Vec<(&'static str, f64)> {
    Bounds::NAMES
        .iter()
        .flat_map(|n| [(*n, 1.0 - delta), (*n, 1.0 + delta)])
        .collect()
}

/// Why a run of the sweep is not classified again ("NAME: reason"), or None if it is.
fn left_out_reason(r: &super::table::RunRecord) -> Option<String> {
    if r.status == "completed" {
        return None;
    }
    let path = r.dir.join("summary.json");
    let why = match std::fs::read_to_string(&path) {
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => "no summary.json".to_string(),
        Err(e) => format!("summary.json unreadable ({e})"),
        Ok(text) => match serde_json::from_str::<crate::summary::RunSummary>(&text) {
            Err(e) => format!("summary.json unreadable ({e})"),
            Ok(_) => format!("not completed (status {})", r.status),
        },
    };
    Some(format!("{}: {why}", r.name))
}

/// Classifies every completed run of `dir` with the default bounds and with each variant; also
/// returns the runs left out, each with its reason ("NAME: reason").
pub fn sensitivity(dir: &Path, delta: f64) -> Result<(Vec<RunSensitivity>, Vec<String>), String> {
    if !(delta > 0.0 && delta < 1.0) {
        return Err(format!("--delta {delta}: must lie in (0, 1)"));
    }
    let records = collect(&[dir.to_path_buf()]);
    let mut left_out: Vec<String> = records.iter().filter_map(left_out_reason).collect();
    let runs: Vec<_> = records.iter().filter(|r| r.status == "completed").collect();
    if runs.is_empty() {
        return Err(format!(
            "{}: no completed run folders under runs/",
            dir.display()
        ));
    }
    let vs = variants(delta);
    let mut out = Vec::with_capacity(runs.len());
    for r in runs {
        let Some(bores) = crate::run::read_back::bores_of_run(&r.dir)? else {
            left_out.push(format!(
                "{}: its system.toml has no air films film_C and film_T to read the bores from",
                r.name
            ));
            continue;
        };
        let series = load_run(&r.dir, [bores[0].c_m, bores[1].c_m])?;
        let base = classify_with(&series, &Bounds::default());
        let moved = vs
            .iter()
            .map(|(name, f)| {
                let b = Bounds::default().scaled(name, *f).expect("known bound");
                classify_with(&series, &b).class.as_str().to_string()
            })
            .collect();
        out.push(RunSensitivity {
            name: r.name.clone(),
            base: base.class.as_str().to_string(),
            moved,
        });
    }
    Ok((out, left_out))
}

/// Writes `dir/sensitivity.csv` and returns it with a readable summary (per moved bound, the runs
/// whose class changes).
pub fn write(
    dir: &Path,
    delta: f64,
    runs: &[RunSensitivity],
    left_out: &[String],
) -> Result<(PathBuf, String), String> {
    let vs = variants(delta);
    let mut csv = String::from("run,class");
    for (n, f) in &vs {
        let _ = write!(csv, ",{n} x{f}");
    }
    csv.push('\n');
    for r in runs {
        let _ = write!(csv, "{},{}", r.name, r.base);
        for m in &r.moved {
            let _ = write!(csv, ",{m}");
        }
        csv.push('\n');
    }
    let path = dir.join("sensitivity.csv");
    crate::output::write_whole(&path, csv.as_bytes())?;
    let mut text = format!(
        "{} runs classified again with each bound moved by -{:.0} % and +{:.0} %:\n",
        runs.len(),
        100.0 * delta,
        100.0 * delta
    );
    for (k, (n, f)) in vs.iter().enumerate() {
        let changed: Vec<String> = runs
            .iter()
            .filter(|r| r.moved[k] != r.base)
            .map(|r| format!("{} ({} -> {})", r.name, r.base, r.moved[k]))
            .collect();
        let _ = writeln!(
            text,
            "  {n} x{f}: {} changed{}{}",
            changed.len(),
            if changed.is_empty() { "" } else { ": " },
            changed.join(", ")
        );
    }
    if !left_out.is_empty() {
        let _ = writeln!(text, "{} runs left out:", left_out.len());
        for l in left_out {
            let _ = writeln!(text, "  {l}");
        }
    }
    Ok((path, text))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_bound_moves_down_and_up() {
        let v = variants(0.2);
        assert_eq!(v.len(), 2 * Bounds::NAMES.len());
        assert_eq!(v[0], ("onset_amp_rel", 0.8));
        assert_eq!(v[1], ("onset_amp_rel", 1.2));
        let b = Bounds::default().scaled("large_eps", 1.2).unwrap();
        assert!((b.large_eps - 1.2).abs() < 1e-15);
        assert_eq!(b.large_whirl_amp_rel, Bounds::default().large_whirl_amp_rel);
        assert!(Bounds::default().scaled("bogus", 1.0).is_none());
    }
}
