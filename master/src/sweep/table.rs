//! The run folders of a study read back (`RunRecord`), the study table (study.csv) and merging
//! the folders of several shards.

use super::study::{is_fmu_key, keys_in, short_and_unit, KEYS};
use super::{plot_grid_maps, plot_maps, read_json, Study};
use crate::summary::RunSummary;
use std::collections::{BTreeMap, HashMap};
use std::path::{Path, PathBuf};

/// One run's parameters and results, read from its folder.
#[derive(Debug, Clone, PartialEq)]
pub struct RunRecord {
    pub name: String,
    pub index: usize,
    pub args: BTreeMap<String, String>,
    pub status: String,
    pub classification: Option<String>,
    /// The class is borderline (a deciding criterion within 10 % of its bound).
    pub borderline: Option<bool>,
    pub onset_time_s: Option<f64>,
    pub onset_speed_hz: Option<f64>,
    pub max_eps_c: Option<f64>,
    pub max_eps_t: Option<f64>,
    pub wall_time_s: Option<f64>,
    pub settings: serde_json::Value,
    /// The run folder (its report.html is linked from the sweep's).
    pub dir: PathBuf,
}

impl RunRecord {
    /// A parameter: as the study gave it, else the run-up's effective setting.
    pub fn param(&self, key: &str) -> Option<f64> {
        if let Some(v) = self.args.get(key).and_then(|v| v.parse().ok()) {
            return Some(v);
        }
        if is_fmu_key(key) {
            return None;
        }
        let field = KEYS.iter().find(|e| e.0 == key)?.2;
        self.settings.get(field)?.as_f64()
    }
}

/// Every run folder (`runs/*` with `sweep_run.json`) under the given sweep output folders, in study
/// order (index, then name); a run present in several folders is taken once (a completed one first).
pub fn collect(dirs: &[PathBuf]) -> Vec<RunRecord> {
    let mut by_name: HashMap<String, RunRecord> = HashMap::new();
    for d in dirs {
        let Ok(entries) = std::fs::read_dir(d.join("runs")) else {
            continue;
        };
        for e in entries.flatten() {
            let dir = e.path();
            let Some(meta) = read_json(&dir.join("sweep_run.json")) else {
                continue;
            };
            let s = RunSummary::read(&dir);
            let args: BTreeMap<String, String> =
                serde_json::from_value(meta["args"].clone()).unwrap_or_default();
            let rec = RunRecord {
                name: meta["name"]
                    .as_str()
                    .map(String::from)
                    .unwrap_or_else(|| e.file_name().to_string_lossy().into_owned()),
                index: meta["index"].as_u64().unwrap_or(u64::MAX) as usize,
                args,
                status: s
                    .as_ref()
                    .map_or("missing", |s| s.status.as_str())
                    .to_string(),
                classification: s.as_ref().and_then(|s| s.classification.clone()),
                borderline: s.as_ref().and_then(|s| s.borderline),
                onset_time_s: s.as_ref().and_then(|s| s.onset_time_s),
                onset_speed_hz: s.as_ref().and_then(|s| s.onset_speed_hz),
                max_eps_c: s.as_ref().and_then(|s| s.max_eps_c),
                max_eps_t: s.as_ref().and_then(|s| s.max_eps_t),
                wall_time_s: s.as_ref().and_then(|s| s.wall_time_s),
                settings: s.map(|s| s.settings).unwrap_or_default(),
                dir: dir.clone(),
            };
            match by_name.get(&rec.name) {
                Some(old) if old.status == "completed" || rec.status != "completed" => {}
                _ => {
                    by_name.insert(rec.name.clone(), rec);
                }
            }
        }
    }
    let mut v: Vec<RunRecord> = by_name.into_values().collect();
    v.sort_by(|a, b| a.index.cmp(&b.index).then(a.name.cmp(&b.name)));
    v
}

fn opt(v: Option<f64>) -> String {
    v.map_or(String::new(), |x| format!("{x:?}"))
}

/// The study table: one row per run; parameter columns are the flags any run was given (FMU
/// parameters after the run-up flags, their values as the study gave them: SI unless they name
/// a unit).
pub fn write_table(records: &[RunRecord], path: &Path) -> Result<(), String> {
    let keys = keys_in(records.iter().map(|r| &r.args));
    let mut s = String::from("run");
    for k in &keys {
        let unit = short_and_unit(k).1;
        if unit.is_empty() {
            s.push_str(&format!(",{k}"));
        } else {
            s.push_str(&format!(",{k} [{unit}]"));
        }
    }
    s.push_str(",status,classification,borderline,onset_time [s],onset_speed [Hz],max_eps_C [1],max_eps_T [1],wall_time [s]\n");
    for r in records {
        s.push_str(&r.name);
        for k in &keys {
            s.push(',');
            let v = r.args.get(k).cloned().unwrap_or_default();
            if v.contains(',') {
                s.push_str(&format!("\"{v}\""));
            } else {
                s.push_str(&v);
            }
        }
        s.push_str(&format!(
            ",{},{},{},{},{},{},{},{}\n",
            r.status,
            r.classification.as_deref().unwrap_or(""),
            r.borderline.map_or(String::new(), |b| b.to_string()),
            opt(r.onset_time_s),
            opt(r.onset_speed_hz),
            opt(r.max_eps_c),
            opt(r.max_eps_t),
            r.wall_time_s.map_or(String::new(), |w| format!("{w:.1}"))
        ));
    }
    crate::output::write_whole(path, s.as_bytes())
}

/// `airring sweep-merge`: one table and one map from the run folders of several sweep outputs
/// (shards), written into `out`.
pub fn merge(dirs: &[PathBuf], out: &Path) -> Result<(PathBuf, Vec<PathBuf>, usize), String> {
    check_same_study(dirs)?;
    std::fs::create_dir_all(out).map_err(|e| format!("{}: {e}", out.display()))?;
    let records = collect(dirs);
    if records.is_empty() {
        return Err(format!(
            "no run folders (runs/*/sweep_run.json) in {dirs:?}"
        ));
    }
    let table = out.join("study.csv");
    write_table(&records, &table)?;
    let mut maps = plot_maps(&records, out, "bifurcation_map").map_err(|e| format!("maps: {e}"))?;
    // The study file a sweep leaves in its folder tells which grid each run belongs to.
    let study = dirs
        .iter()
        .map(|d| d.join("study.toml"))
        .find_map(|p| Study::load(&p).ok());
    let title = study
        .as_ref()
        .map_or("(merged)".to_string(), |s| s.name.clone());
    if let Some(study) = study {
        maps.extend(
            plot_grid_maps(&records, &study, out, "bifurcation_map")
                .map_err(|e| format!("maps: {e}"))?,
        );
    }
    if let Err(e) = super::report_page::write_sweep_report(out, &title, &table, &maps, &records) {
        eprintln!("warning: report.html: {e}");
    }
    Ok((table, maps, records.len()))
}

/// The dotted keys under which `a` and `b` differ (a key missing on one side differs).
fn differing_keys(a: &serde_json::Value, b: &serde_json::Value, at: &str, out: &mut Vec<String>) {
    use serde_json::Value;
    match (a, b) {
        (Value::Object(x), Value::Object(y)) => {
            let keys: std::collections::BTreeSet<&String> = x.keys().chain(y.keys()).collect();
            for k in keys {
                let here = if at.is_empty() {
                    k.clone()
                } else {
                    format!("{at}.{k}")
                };
                match (x.get(k), y.get(k)) {
                    (Some(p), Some(q)) => differing_keys(p, q, &here, out),
                    _ => out.push(here),
                }
            }
        }
        _ if a != b => out.push(if at.is_empty() {
            "(the whole file)".into()
        } else {
            at.into()
        }),
        _ => {}
    }
}

/// Shards of one study only: every folder's study.toml says the same (name, fixed keys, grids),
/// and a run name found in several folders has the same flags and defaults (sweep_run.json) in
/// each. Folders of different studies would be merged into one table and map without a word.
fn check_same_study(dirs: &[PathBuf]) -> Result<(), String> {
    let study_of = |d: &PathBuf| -> Result<Option<serde_json::Value>, String> {
        let p = d.join("study.toml");
        match std::fs::read_to_string(&p) {
            Err(e) if e.kind() == std::io::ErrorKind::NotFound => Ok(None),
            Err(e) => Err(format!("{}: {e}", p.display())),
            Ok(text) => text
                .parse::<toml::Table>()
                .map_err(|e| format!("{}: {}", p.display(), e.message()))
                .and_then(|t| serde_json::to_value(t).map_err(|e| e.to_string()))
                .map(Some),
        }
    };
    let mut first: Option<(&PathBuf, serde_json::Value)> = None;
    for d in dirs {
        let Some(s) = study_of(d)? else { continue };
        match &first {
            None => first = Some((d, s)),
            Some((d0, s0)) => {
                let mut keys = vec![];
                differing_keys(s0, &s, "", &mut keys);
                if !keys.is_empty() {
                    return Err(format!(
                        "{} and {} hold sweeps of different studies (their study.toml differ in \
                         {}): sweep-merge joins the shards of one study only",
                        d0.display(),
                        d.display(),
                        keys.join(", ")
                    ));
                }
            }
        }
    }
    // The runs themselves: the same name must mean the same run-up.
    let mut seen: HashMap<String, (PathBuf, serde_json::Value)> = HashMap::new();
    for d in dirs {
        let Ok(entries) = std::fs::read_dir(d.join("runs")) else {
            continue;
        };
        for e in entries.flatten() {
            let Some(meta) = read_json(&e.path().join("sweep_run.json")) else {
                continue;
            };
            let name = e.file_name().to_string_lossy().into_owned();
            let what = serde_json::json!({ "args": meta["args"], "defaults": meta["defaults"] });
            match seen.get(&name) {
                None => {
                    seen.insert(name, (d.clone(), what));
                }
                Some((d0, w0)) => {
                    let mut keys = vec![];
                    differing_keys(w0, &what, "", &mut keys);
                    if !keys.is_empty() {
                        return Err(format!(
                            "run {name} is in {} and in {} with different settings ({}): these \
                             are not shards of one study",
                            d0.display(),
                            d.display(),
                            keys.join(", ")
                        ));
                    }
                }
            }
        }
    }
    Ok(())
}
