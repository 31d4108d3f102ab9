//! The linear prediction of a study's bifurcation map (`airring sweep STUDY --linear`): for every
//! grid point the linear stability analysis (`crate::stability`) instead of a run-up, in seconds.
//!
//! What it predicts: the threshold speed of instability and, from the growth exponent N accumulated
//! along the run-up ramp above it, the speed where a whirl becomes visible: where N reaches
//! [`N_VISIBLE`]. That number is calibrated on the paper's Section 3 run-ups with the default journal
//! disturbance (their onsets lie at N = 11.5-13, docs/stability.md). A point whose N stays below it up
//! to f_max is predicted stable. The linear model cannot tell path 1 from 2a or 2b (that is the
//! nonlinear behaviour after onset); its cells read "unstable (linear)".

use crate::linear_cache::LinearCache;
use crate::runup::RunupSettings;
use crate::stability::{self, StabilityReport};
use crate::sweep::{plot_grid_maps, plot_maps, write_table, RunRecord, Study};
use std::collections::BTreeSet;
use std::fmt::Write as _;
use std::path::{Path, PathBuf};
use std::time::Instant;

/// Default film mesh per lobe of the prediction when the study does not set one.
pub const DEFAULT_MESH: (u32, u32) = crate::stability::LINEAR_PREDICTION_MESH;

/// Accumulated growth exponent at which a whirl seeded by the default disturbance becomes visible
/// to the run-up classifier (0.02 C): calibrated on the three Section 3 run-ups.
pub const N_VISIBLE: f64 = 12.0;

/// Run-up settings of a study point: the preset, then the flags the linear model depends on.
/// Flags that only concern the time integration (macro step, orders, output, ...) are ignored.
pub fn settings_for(
    args: &std::collections::BTreeMap<String, String>,
) -> Result<RunupSettings, String> {
    let num = |k: &str| -> Result<Option<f64>, String> {
        args.get(k)
            .map(|v| {
                v.trim()
                    .parse::<f64>()
                    .map_err(|_| format!("'{k}' = '{v}' is not a number"))
            })
            .transpose()
    };
    // The same mapping as the command line's (`airring stability` flags).
    let flags = crate::runup::DesignArgs {
        preset: args
            .get("preset")
            .cloned()
            .unwrap_or_else(|| "path1".into()),
        design: args.get("design").map(std::path::PathBuf::from),
        c: num("c")?,
        d: num("d")?,
        m_r: num("m_r")?,
        clearance: num("clearance")?,
        dh: num("dh")?,
        mesh: args.get("mesh").cloned(),
        set: args
            .iter()
            .filter(|(k, _)| crate::sweep::is_fmu_key(k))
            .map(|(k, v)| format!("{k}={v}"))
            .collect(),
    };
    let mut s = flags.settings()?;
    s.f_max_hz = num("f_max")?.unwrap_or(s.f_max_hz);
    s.t_ramp_s = num("t_ramp")?.unwrap_or(s.t_ramp_s);
    s.validate()?;
    s.check_shaft()?;
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

/// Study keys that change a run-up's outcome but not the linear model: predictions of studies
/// that vary them are flagged (N_VISIBLE is calibrated on the default disturbance, no imbalance
/// and the full ramp).
const IGNORED_BY_LINEAR: &[&str] = &[
    "disturbance",
    "disturbance_seed",
    "imbalance_c",
    "imbalance_t",
    "profile",
    "stop",
];

/// One predicted grid point.
#[derive(Debug, Clone)]
pub struct Prediction {
    pub name: String,
    /// Why the point has no prediction (bad parameters, no static equilibrium, ...).
    pub error: Option<String>,
    /// Already unstable at the first speed of the grid: the threshold lies below it.
    pub unstable_below_grid: bool,
    pub threshold_hz: Option<f64>,
    pub mode_freq_hz: Option<f64>,
    pub mode: Option<String>,
    pub n_at_f_max: f64,
    pub onset_hz: Option<f64>,
    pub onset_time_s: Option<f64>,
    pub wall_time_s: f64,
}

/// Predicts every point of `study` on the speed grid `speeds_hz`; writes `study_linear.csv` and
/// `bifurcation_map_linear.svg/.png` into `out`. Progress on stderr unless `quiet`. The grid
/// speeds' least damping ratios go into `cache`, for the run-ups' calm-step plans.
pub fn predict(
    study: &Study,
    speeds_hz: &[f64],
    mesh: (u32, u32),
    out: &Path,
    quiet: bool,
    cache: Option<&LinearCache>,
) -> Result<(Vec<Prediction>, Vec<PathBuf>), String> {
    std::fs::create_dir_all(out).map_err(|e| format!("{}: {e}", out.display()))?;
    let start = Instant::now();
    let mut preds = Vec::with_capacity(study.runs.len());
    let mut records = Vec::with_capacity(study.runs.len());
    let ignored: BTreeSet<&str> = study
        .runs
        .iter()
        .flat_map(|r| r.args.keys())
        .filter_map(|k| IGNORED_BY_LINEAR.iter().copied().find(|i| *i == k.as_str()))
        .collect();
    if !ignored.is_empty() && !quiet {
        eprintln!(
            "linear prediction: the study sets {}, which the linear model does not see (its onset \
             level N = {N_VISIBLE} assumes the default disturbance, no imbalance and the full ramp)",
            ignored.into_iter().collect::<Vec<_>>().join(", ")
        );
    }
    // The points on all cores, each analysed on its own (the same results in any order); a
    // point's analysis spreads its grid speeds over the cores too, but its threshold bisection
    // is serial, and one point at a time left a core idle through it.
    let n_points = study.runs.len();
    let workers = std::thread::available_parallelism()
        .map_or(1, |n| n.get())
        .min(n_points)
        .max(1);
    let next = std::sync::atomic::AtomicUsize::new(0);
    let done = std::sync::atomic::AtomicUsize::new(0);
    let mut slots: Vec<Option<(Prediction, RunRecord)>> = (0..n_points).map(|_| None).collect();
    std::thread::scope(|scope| {
        let handles: Vec<_> = (0..workers)
            .map(|_| {
                scope.spawn(|| {
                    let mut mine = Vec::new();
                    loop {
                        let k = next.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
                        let Some(spec) = study.runs.get(k) else {
                            break;
                        };
                        let (p, record) = predict_point(spec, speeds_hz, mesh, cache);
                        let finished = done.fetch_add(1, std::sync::atomic::Ordering::Relaxed) + 1;
                        if !quiet {
                            eprintln!("{}", progress_line(&p, finished, n_points, speeds_hz));
                        }
                        mine.push((k, p, record));
                    }
                    mine
                })
            })
            .collect();
        for h in handles {
            for (k, p, record) in h.join().expect("prediction worker panicked") {
                slots[k] = Some((p, record));
            }
        }
    });
    for (p, record) in slots.into_iter().flatten() {
        preds.push(p);
        records.push(record);
    }
    write_csv(&preds, &out.join("study_linear.csv"))?;
    // The run table's format too, so `study.csv` readers can take the prediction as is.
    write_table(&records, &out.join("study_linear_table.csv"))?;
    let mut maps = plot_maps(&records, out, "bifurcation_map_linear")
        .map_err(|e| format!("{}: {e}", out.display()))?;
    maps.extend(
        plot_grid_maps(&records, study, out, "bifurcation_map_linear")
            .map_err(|e| format!("{}: {e}", out.display()))?,
    );
    if !quiet {
        eprintln!(
            "linear prediction of {} points in {:.1} s",
            preds.len(),
            start.elapsed().as_secs_f64()
        );
    }
    Ok((preds, maps))
}

/// One point's prediction and its row in the run table's format.
pub(crate) fn predict_point(
    spec: &crate::sweep::RunSpec,
    speeds_hz: &[f64],
    mesh: (u32, u32),
    cache: Option<&LinearCache>,
) -> (Prediction, RunRecord) {
    let t0 = Instant::now();
    let mut args = spec.args.clone();
    args.entry("mesh".into())
        .or_insert_with(|| format!("{}x{}", mesh.0, mesh.1));
    // A point that cannot be predicted is recorded as failed; the others go on.
    let result = settings_for(&args).and_then(|s| {
        let grid: Vec<f64> = speeds_hz
            .iter()
            .copied()
            .filter(|f| *f <= s.f_max_hz)
            .collect();
        if grid.is_empty() {
            return Err(format!(
                "no grid speed at or below f_max = {} Hz",
                s.f_max_hz
            ));
        }
        let report = stability::analyse(&s, &grid)?;
        // The calm plans' cache is keyed by the rigid rotor's parameters (and only rigid run-ups
        // take calm steps): a flexible rotor's damping must not be found there under them.
        if let (Some(cache), None) = (cache, &s.shaft) {
            keep_for_calm_plans(cache, &s, &report);
        }
        Ok((s, report))
    });
    let (p, settings) = match result {
        Ok((s, r)) => (
            prediction_of(&spec.name, &s, &r, t0),
            serde_json::to_value(&s),
        ),
        Err(e) => (
            Prediction {
                name: spec.name.clone(),
                error: Some(e),
                unstable_below_grid: false,
                threshold_hz: None,
                mode_freq_hz: None,
                mode: None,
                n_at_f_max: f64::NAN,
                onset_hz: None,
                onset_time_s: None,
                wall_time_s: t0.elapsed().as_secs_f64(),
            },
            Ok(serde_json::Value::Null),
        ),
    };
    let classification = match (&p.error, p.unstable_below_grid, p.onset_hz) {
        (Some(_), _, _) => None,
        // Unstable from the lowest speed analysed, as the run-up class of that name.
        (None, true, _) => Some("unstable_low_speed"),
        (None, false, Some(_)) => Some("unstable_linear"),
        (None, false, None) => Some("stable"),
    };
    let record = RunRecord {
        name: spec.name.clone(),
        index: spec.index,
        args: spec.args.clone(),
        status: if p.error.is_some() {
            "failed"
        } else {
            "completed"
        }
        .into(),
        classification: classification.map(String::from),
        borderline: None,
        onset_time_s: p.onset_time_s,
        onset_speed_hz: p.onset_hz,
        max_eps_c: None,
        max_eps_t: None,
        wall_time_s: Some(p.wall_time_s),
        settings: settings.unwrap_or_default(),
        // A prediction has no run folder.
        dir: std::path::PathBuf::new(),
    };
    (p, record)
}

/// The least damping ratio of every grid speed of `report` into `cache`. A point predicted on
/// another mesh than the calm plans' (`DEFAULT_MESH`) has other film parameters, whose entries no
/// plan would read: none are kept. A cache that cannot be written only costs the run-ups time (a
/// warning).
fn keep_for_calm_plans(cache: &LinearCache, s: &RunupSettings, report: &StabilityReport) {
    if (s.n_elem_phi, s.n_elem_z) != DEFAULT_MESH {
        return;
    }
    let Ok((rotor, films)) = stability::params_of(s) else {
        return;
    };
    for r in &report.speeds {
        let z = crate::stability::least_damping_ratio(r);
        if let Err(e) = cache.put(&rotor, &films, r.speed_hz, Some(z)) {
            eprintln!("warning: linear analyses not kept for reuse: {e}");
            return;
        }
    }
}

/// The progress line of a finished point (`finished` of `total`).
fn progress_line(p: &Prediction, finished: usize, total: usize, speeds_hz: &[f64]) -> String {
    let what = match (&p.error, p.unstable_below_grid) {
        (Some(e), _) => format!("failed: {e}"),
        (None, true) => format!("unstable already at {} Hz", speeds_hz[0]),
        (None, false) => format!(
            "threshold {}, visible onset {}",
            p.threshold_hz
                .map_or("none".into(), |f| format!("{f:.0} Hz")),
            p.onset_hz.map_or("none".into(), |f| format!("{f:.0} Hz"))
        ),
    };
    format!(
        "linear {finished}/{total} {}: {what} ({:.1} s)",
        p.name, p.wall_time_s
    )
}

/// The prediction of one point from its stability report.
fn prediction_of(name: &str, s: &RunupSettings, r: &StabilityReport, t0: Instant) -> Prediction {
    let below = r.unstable_at_first_speed;
    // Below the grid the growth exponent has no start: no visible onset is predicted.
    let onset_hz = if below {
        None
    } else {
        visible_onset_hz(r, N_VISIBLE)
    };
    let ramp = s.f_max_hz / s.t_ramp_s;
    Prediction {
        name: name.to_string(),
        error: None,
        unstable_below_grid: below,
        threshold_hz: r.threshold.as_ref().map(|t| t.speed_hz),
        mode_freq_hz: r.threshold.as_ref().map(|t| t.mode.freq_hz),
        mode: r
            .threshold
            .as_ref()
            .map(|t| format!("{} whirl; {}", t.mode.whirl, t.mode.description)),
        n_at_f_max: r.growth_exponent.last().copied().unwrap_or(0.0),
        onset_hz,
        onset_time_s: onset_hz.map(|f| f / ramp),
        wall_time_s: t0.elapsed().as_secs_f64(),
    }
}

/// Reorders the study's runs so the run-ups the prediction expects to take longest start first:
/// unstable from the lowest speed, then unstable by predicted onset (earlier onset, longer whirl;
/// whirls that graze the ring are the slow run-ups), then points without a prediction, then the
/// stable ones. Run indices (and so shard membership and table order) do not change; with
/// several jobs this packs the long runs into the start instead of the end of a study.
pub fn longest_first(study: &mut Study, preds: &[Prediction]) {
    let rank = |name: &str| -> (u8, f64) {
        match preds.iter().find(|p| p.name == name) {
            Some(p) if p.error.is_some() => (2, 0.0),
            Some(p) if p.unstable_below_grid => (0, 0.0),
            Some(p) => match p.onset_hz {
                Some(f) => (1, f),
                None => (3, 0.0),
            },
            None => (2, 0.0),
        }
    };
    study.runs.sort_by(|a, b| {
        let (ra, rb) = (rank(&a.name), rank(&b.name));
        ra.0.cmp(&rb.0)
            .then(ra.1.total_cmp(&rb.1))
            .then(a.index.cmp(&b.index))
    });
}

fn write_csv(preds: &[Prediction], path: &Path) -> Result<(), String> {
    let mut s = String::from(
        "run,threshold_speed [Hz],unstable_mode_frequency [Hz],growth_exponent_at_f_max [-],predicted_onset_speed [Hz],predicted_onset_time [s],unstable_mode,wall_time [s],note\n",
    );
    let o = |v: Option<f64>| v.map_or(String::new(), |x| format!("{x:.1}"));
    for p in preds {
        let note = match (&p.error, p.unstable_below_grid) {
            (Some(e), _) => format!("failed: {e}"),
            (None, true) => {
                "unstable at the first grid speed: the threshold lies below the grid".into()
            }
            (None, false) => String::new(),
        };
        let _ = writeln!(
            s,
            "{},{},{},{},{},{},\"{}\",{:.2},\"{}\"",
            p.name,
            o(p.threshold_hz),
            o(p.mode_freq_hz),
            if p.n_at_f_max.is_finite() {
                format!("{:.2}", p.n_at_f_max)
            } else {
                String::new()
            },
            o(p.onset_hz),
            p.onset_time_s.map_or(String::new(), |t| format!("{t:.4}")),
            p.mode.clone().unwrap_or_default().replace('"', "'"),
            p.wall_time_s,
            note.replace('"', "'")
        );
    }
    crate::output::write_whole(path, s.as_bytes())
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A sweep's prediction fills the cache under the keys its run-ups look up (the same model
    /// parameters from a study point's flags either way), and a plan from the cache is the plan
    /// without it, bit for bit; the speeds the prediction did not analyse are added.
    #[test]
    fn a_plan_reuses_the_predictions_analyses_and_is_unchanged_by_them() {
        let mut args = std::collections::BTreeMap::new();
        for (k, v) in [
            ("preset", "path1"),
            ("clearance", "20"),
            ("dh", "40"),
            ("c", "1000"),
            ("d", "500"),
            ("rotor.disturbance_seed", "3"),
            ("stop", "0.3"),
        ] {
            args.insert(k.to_string(), v.to_string());
        }
        let spec = crate::sweep::RunSpec {
            index: 0,
            name: "point".into(),
            args: args.clone(),
            grids: vec![],
        };
        let runup = crate::runup::flags::check_argv(&crate::sweep::runup_args(&args)).unwrap();
        let dir = std::env::temp_dir().join(format!("airring-calm-cache-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        let cache = crate::linear_cache::LinearCache::open_for_build(&dir, "test").unwrap();
        let entries = || std::fs::read_dir(&dir).unwrap().count();
        let (p, _) = predict_point(&spec, &[100.0, 200.0], DEFAULT_MESH, Some(&cache));
        assert!(p.error.is_none(), "{:?}", p.error);
        assert_eq!(entries(), 2);
        // 0.3 s of the ramp reaches 200 Hz: 50, 100, 150 and 200 Hz; two found, two analysed.
        let cached = crate::calm_steps::plan(&runup, Some(&cache));
        assert_eq!(entries(), 4);
        let fresh = crate::calm_steps::plan(&runup, None);
        assert_eq!(fresh.least_damping.len(), 4);
        let bits = |p: &crate::calm_steps::CalmPlan| -> Vec<(u64, Option<u64>)> {
            p.least_damping
                .iter()
                .map(|(f, z)| (f.to_bits(), z.map(f64::to_bits)))
                .collect()
        };
        assert_eq!(bits(&cached), bits(&fresh));
        assert_eq!(cached.windows_s, fresh.windows_s);
        assert!(!fresh.windows_s.is_empty(), "{fresh:?}");
        // A plan from the full cache: the same values, no new entries.
        assert_eq!(
            bits(&crate::calm_steps::plan(&runup, Some(&cache))),
            bits(&fresh)
        );
        assert_eq!(entries(), 4);
        std::fs::remove_dir_all(&dir).unwrap();
    }

    use crate::sweep::RunSpec;
    use std::collections::BTreeMap;

    #[test]
    fn predicted_long_runs_start_first_and_keep_their_index() {
        let p = |name: &str, below: bool, onset: Option<f64>, error: bool| Prediction {
            name: name.into(),
            error: error.then(|| "no equilibrium".to_string()),
            unstable_below_grid: below,
            threshold_hz: None,
            mode_freq_hz: None,
            mode: None,
            n_at_f_max: 0.0,
            onset_hz: onset,
            onset_time_s: None,
            wall_time_s: 0.0,
        };
        let preds = [
            p("stable", false, None, false),
            p("late", false, Some(1200.0), false),
            p("low", true, None, false),
            p("early", false, Some(700.0), false),
            p("failed", false, None, true),
        ];
        let mut study = Study {
            name: "t".into(),
            runs: preds
                .iter()
                .enumerate()
                .map(|(index, q)| RunSpec {
                    index,
                    name: q.name.clone(),
                    args: BTreeMap::new(),
                    grids: vec![],
                })
                .collect(),
        };
        longest_first(&mut study, &preds);
        let order: Vec<(&str, usize)> = study
            .runs
            .iter()
            .map(|r| (r.name.as_str(), r.index))
            .collect();
        assert_eq!(
            order,
            [
                ("low", 2),
                ("early", 3),
                ("late", 1),
                ("failed", 4),
                ("stable", 0)
            ]
        );
    }

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
