//! The linear prediction of a study's bifurcation map (`airring sweep STUDY --linear`): for every
//! grid point the linear stability analysis (`crate::stability`) instead of a run-up, in seconds.
//!
//! What it predicts: the threshold speed of instability and, from the growth exponent N accumulated
//! along the run-up ramp above it, the speed where a whirl becomes visible: where N reaches
//! [`N_VISIBLE`]. That number is calibrated on the paper's Section 3 run-ups with the default journal
//! disturbance (their onsets lie at N = 11.5-13, docs/stability.md). A point whose N stays below it up
//! to f_max is predicted stable. The linear model cannot tell path 1 from 2a or 2b (that is the
//! nonlinear behaviour after onset); its cells read "unstable (linear)".

use crate::runup::RunupSettings;
use crate::stability::{self, StabilityReport};
use crate::sweep::{plot_maps, write_table, RunRecord, Study};
use std::fmt::Write as _;
use std::path::{Path, PathBuf};
use std::time::Instant;

/// Default film mesh per lobe of the prediction when the study does not set one: on the path-1
/// parameters it gives the paper mesh's threshold within 0.15 % and its growth exponents within 1 %
/// at a tenth of the time (docs/stability.md).
pub const DEFAULT_MESH: (u32, u32) = (8, 2);

/// Accumulated growth exponent at which a whirl seeded by the default disturbance becomes visible
/// to the run-up classifier (0.02 C): calibrated on the three Section 3 run-ups.
pub const N_VISIBLE: f64 = 12.0;

/// Run-up settings of a study point: the preset, then the flags the linear model depends on.
/// Flags that only concern the time integration (macro step, orders, output, ...) are ignored.
pub fn settings_for(
    args: &std::collections::BTreeMap<String, String>,
) -> Result<RunupSettings, String> {
    let preset = args.get("preset").map_or("path1", String::as_str);
    let mut s = RunupSettings::preset(preset)?;
    let num = |k: &str, v: &str| -> Result<f64, String> {
        v.trim()
            .parse::<f64>()
            .map_err(|_| format!("'{k}' = '{v}' is not a number"))
    };
    for (k, v) in args {
        match k.as_str() {
            "clearance" => s.clearance_um = num(k, v)?,
            "dh" => s.dh_um = num(k, v)?,
            "c" => s.c_n_per_mm = num(k, v)?,
            "d" => s.d_n_s_per_m = num(k, v)?,
            "m_r" => s.m_r_g = num(k, v)?,
            "f_max" => s.f_max_hz = num(k, v)?,
            "t_ramp" => s.t_ramp_s = num(k, v)?,
            "mesh" => (s.n_elem_phi, s.n_elem_z) = crate::runup::parse_mesh(v, "mesh")?,
            _ => {}
        }
    }
    s.validate()?;
    Ok(s)
}

/// The speed where the growth exponent first reaches `n_visible` (linear between grid speeds).
pub fn visible_onset_hz(r: &StabilityReport, n_visible: f64) -> Option<f64> {
    let n = &r.growth_exponent;
    let k = n.iter().position(|x| *x >= n_visible)?;
    if k == 0 {
        return Some(r.speeds[0].speed_hz);
    }
    let (f0, f1) = (r.speeds[k - 1].speed_hz, r.speeds[k].speed_hz);
    let w = (n_visible - n[k - 1]) / (n[k] - n[k - 1]);
    Some(f0 + w * (f1 - f0))
}

/// One predicted grid point.
#[derive(Debug, Clone)]
pub struct Prediction {
    pub name: String,
    pub threshold_hz: Option<f64>,
    pub mode_freq_hz: Option<f64>,
    pub mode: Option<String>,
    pub n_at_f_max: f64,
    pub onset_hz: Option<f64>,
    pub onset_time_s: Option<f64>,
    pub wall_time_s: f64,
}

/// Predicts every point of `study` on the speed grid `speeds_hz`; writes `study_linear.csv` and
/// `bifurcation_map_linear.svg/.png` into `out`. Progress on stderr unless `quiet`.
pub fn predict(
    study: &Study,
    speeds_hz: &[f64],
    mesh: (u32, u32),
    out: &Path,
    quiet: bool,
) -> Result<(Vec<Prediction>, Vec<PathBuf>), String> {
    std::fs::create_dir_all(out).map_err(|e| format!("{}: {e}", out.display()))?;
    let start = Instant::now();
    let mut preds = Vec::with_capacity(study.runs.len());
    let mut records = Vec::with_capacity(study.runs.len());
    for (k, spec) in study.runs.iter().enumerate() {
        let t0 = Instant::now();
        let mut args = spec.args.clone();
        args.entry("mesh".into())
            .or_insert_with(|| format!("{}x{}", mesh.0, mesh.1));
        let s = settings_for(&args).map_err(|e| format!("{}: {e}", spec.name))?;
        let grid: Vec<f64> = speeds_hz
            .iter()
            .copied()
            .filter(|f| *f <= s.f_max_hz)
            .collect();
        let r = stability::analyse(&s, &grid).map_err(|e| format!("{}: {e}", spec.name))?;
        let onset_hz = visible_onset_hz(&r, N_VISIBLE);
        let ramp = s.f_max_hz / s.t_ramp_s;
        let p = Prediction {
            name: spec.name.clone(),
            threshold_hz: r
                .threshold
                .as_ref()
                .map(|t| t.speed_hz)
                .or(r.unstable_at_first_speed.then_some(grid[0])),
            mode_freq_hz: r.threshold.as_ref().map(|t| t.mode.freq_hz),
            mode: r
                .threshold
                .as_ref()
                .map(|t| format!("{} whirl; {}", t.mode.whirl, t.mode.description)),
            n_at_f_max: r.growth_exponent.last().copied().unwrap_or(0.0),
            onset_hz,
            onset_time_s: onset_hz.map(|f| f / ramp),
            wall_time_s: t0.elapsed().as_secs_f64(),
        };
        records.push(RunRecord {
            name: spec.name.clone(),
            index: spec.index,
            args: spec.args.clone(),
            status: "completed".into(),
            classification: Some(
                if onset_hz.is_some() {
                    "unstable_linear"
                } else {
                    "stable"
                }
                .into(),
            ),
            onset_time_s: p.onset_time_s,
            onset_speed_hz: p.onset_hz,
            max_eps_c: None,
            max_eps_t: None,
            wall_time_s: Some(p.wall_time_s),
            settings: serde_json::to_value(&s).unwrap_or_default(),
        });
        if !quiet {
            eprintln!(
                "linear {}/{} {}: threshold {}, visible onset {} ({:.1} s)",
                k + 1,
                study.runs.len(),
                spec.name,
                p.threshold_hz
                    .map_or("none".into(), |f| format!("{f:.0} Hz")),
                p.onset_hz.map_or("none".into(), |f| format!("{f:.0} Hz")),
                p.wall_time_s
            );
        }
        preds.push(p);
    }
    write_csv(&preds, &out.join("study_linear.csv"))?;
    // The run table's format too, so `study.csv` readers can take the prediction as is.
    write_table(&records, &out.join("study_linear_table.csv"))?;
    let maps = plot_maps(&records, out, "bifurcation_map_linear")
        .map_err(|e| format!("{}: {e}", out.display()))?;
    if !quiet {
        eprintln!(
            "linear prediction of {} points in {:.1} s",
            preds.len(),
            start.elapsed().as_secs_f64()
        );
    }
    Ok((preds, maps))
}

fn write_csv(preds: &[Prediction], path: &Path) -> Result<(), String> {
    let mut s = String::from(
        "run,threshold_speed [Hz],unstable_mode_frequency [Hz],growth_exponent_at_f_max [-],predicted_onset_speed [Hz],predicted_onset_time [s],unstable_mode,wall_time [s]\n",
    );
    let o = |v: Option<f64>| v.map_or(String::new(), |x| format!("{x:.1}"));
    for p in preds {
        let _ = writeln!(
            s,
            "{},{},{},{:.2},{},{},\"{}\",{:.2}",
            p.name,
            o(p.threshold_hz),
            o(p.mode_freq_hz),
            p.n_at_f_max,
            o(p.onset_hz),
            p.onset_time_s.map_or(String::new(), |t| format!("{t:.4}")),
            p.mode.clone().unwrap_or_default().replace('"', "'"),
            p.wall_time_s
        );
    }
    std::fs::write(path, s).map_err(|e| format!("{}: {e}", path.display()))
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::collections::BTreeMap;

    #[test]
    fn settings_follow_the_study_flags_and_reject_bad_values() {
        let mut a = BTreeMap::new();
        a.insert("preset".to_string(), "path2b".to_string());
        a.insert("clearance".to_string(), "15".to_string());
        a.insert("mesh".to_string(), "10x4".to_string());
        a.insert("macro_step".to_string(), "5".to_string());
        let s = settings_for(&a).unwrap();
        assert_eq!(
            (s.clearance_um, s.c_n_per_mm, s.m_r_g),
            (15.0, 100.0, 150.0)
        );
        assert_eq!((s.n_elem_phi, s.n_elem_z), (10, 4));
        a.insert("c".to_string(), "stiff".to_string());
        assert!(settings_for(&a).unwrap_err().contains("'c'"));
        a.insert("c".to_string(), "-5".to_string());
        assert!(settings_for(&a).is_err());
    }
}
