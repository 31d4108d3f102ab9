//! Study files (TOML): the flags a study may set, the grid points they expand to, run names, the
//! `airring runup` arguments of a point, shards and the plan external drivers read.

use std::collections::BTreeMap;
use std::path::Path;

/// Run-up flags a study may set, in the order used for run names and table columns:
/// (key, short name in run names, field of the run-up settings in summary.json, unit).
pub const KEYS: &[(&str, &str, &str, &str)] = &[
    ("preset", "", "preset", ""),
    ("design", "design", "design", ""),
    ("clearance", "C", "clearance_um", "um"),
    ("dh", "dH", "dh_um", "um"),
    ("c", "c", "c_n_per_mm", "N/mm"),
    ("d", "d", "d_n_s_per_m", "N s/m"),
    ("m_r", "mR", "m_r_g", "g"),
    ("f_max", "fmax", "f_max_hz", "Hz"),
    ("t_ramp", "tramp", "t_ramp_s", "s"),
    ("profile", "prof", "", ""),
    ("stop", "stop", "stop_time_s", "s"),
    ("macro_step", "H", "macro_step_us", "us"),
    ("calm_macro_step", "calm", "calm_macro_step_us", "us"),
    ("extrapolation_order", "ex", "extrapolation_order", ""),
    ("interpolation_order", "in", "interpolation_order", ""),
    ("mesh", "mesh", "", ""),
    ("imbalance_c", "imbC", "", ""),
    ("imbalance_t", "imbT", "", ""),
    ("disturbance", "dist", "disturbance_mn", "mN"),
    ("disturbance_seed", "seed", "disturbance_seed", ""),
    ("output_interval", "out", "output_interval_us", "us"),
    ("jacobi", "jacobi", "jacobi", ""),
    ("contact", "contact", "contact", ""),
    ("step_control", "sc", "step_control", ""),
    ("film_tolerance", "ftol", "film_tolerance", ""),
    ("halt_film", "halt", "halt_film_um", "um"),
    ("halt_whirl", "haltw", "halt_whirl_um", "um"),
    ("halt_speeds", "haltf", "", ""),
    ("fmu_dir", "fmu", "", ""),
];

/// Flags that choose how a run-up is computed, not what is computed: runs that differ only in
/// these share a map panel.
pub(super) const NUMERICS: &[&str] = &[
    "contact",
    "step_control",
    "film_tolerance",
    "fmu_dir",
    "calm_macro_step",
    "halt_film",
    "halt_whirl",
    "halt_speeds",
];

/// Study keys that take true or false.
const BOOLEAN_KEYS: &[&str] = &["jacobi"];

/// A set of (flag, value) pairs.
pub(super) type Params = Vec<(String, String)>;

fn key_index(k: &str) -> Option<usize> {
    KEYS.iter().position(|e| e.0 == k)
}

/// An FMU parameter key (PREFIX.NAME, `crate::fmu_params`) rather than a run-up flag.
pub fn is_fmu_key(k: &str) -> bool {
    k.contains('.')
}

/// Where a key goes in run names, table columns, map titles and the nesting of a grid: the
/// run-up flags in KEYS order, then FMU parameters by name.
pub fn key_order(k: &str) -> (usize, String) {
    match key_index(k) {
        Some(i) => (i, String::new()),
        None => (KEYS.len(), k.to_string()),
    }
}

/// The keys used by any of the argument sets, in `key_order`.
pub fn keys_in<'a>(args: impl Iterator<Item = &'a BTreeMap<String, String>>) -> Vec<String> {
    let mut keys: Vec<String> = args.flat_map(|a| a.keys().cloned()).collect();
    keys.sort_by_key(|k| key_order(k));
    keys.dedup();
    keys
}

/// Short name of a key in run names and map labels ("C", "dH", "film.eta") and its unit ("" for
/// FMU parameters, whose values carry their unit when not SI).
pub fn short_and_unit(k: &str) -> (String, &'static str) {
    match KEYS.iter().find(|e| e.0 == k) {
        Some((key, short, _, unit)) => {
            let short = if short.is_empty() { key } else { short };
            (short.to_string(), unit)
        }
        None => (k.to_string(), ""),
    }
}

/// Table entries with dotted keys (`film.eta = ...` in TOML is a table `film` holding `eta`)
/// flattened to "film.eta".
pub fn flatten(t: &toml::Table) -> Vec<(String, toml::Value)> {
    let mut out = Vec::new();
    for (k, v) in t {
        match v {
            toml::Value::Table(sub)
                if crate::fmu_params::Target::PREFIXES.contains(&k.as_str()) =>
            {
                out.extend(sub.iter().map(|(sk, sv)| (format!("{k}.{sk}"), sv.clone())));
            }
            _ => out.push((k.clone(), v.clone())),
        }
    }
    out
}

/// One grid point: its run name, its index in the study, and its run-up flags (key -> value text).
#[derive(Debug, Clone, PartialEq)]
pub struct RunSpec {
    pub index: usize,
    pub name: String,
    pub args: BTreeMap<String, String>,
    /// The grids that list this point (their `name`, or "grid N"): one run may serve several.
    pub grids: Vec<String>,
}

#[derive(Debug, Clone)]
pub struct Study {
    pub name: String,
    pub runs: Vec<RunSpec>,
}

/// A study value's text: also the run names' spelling (floats in Display form, "0.00001"), so
/// it stays as it is rather than `fmu_params::toml_value_text` (which writes "1e-5").
fn value_text(v: &toml::Value) -> Option<String> {
    match v {
        toml::Value::Integer(i) => Some(i.to_string()),
        toml::Value::Float(f) if f.is_finite() => Some(f.to_string()),
        toml::Value::String(s) => Some(s.clone()),
        toml::Value::Boolean(b) => Some(b.to_string()),
        _ => None,
    }
}

fn normalize(k: &str) -> String {
    k.replace('-', "_").to_lowercase()
}

impl Study {
    pub fn load(path: &Path) -> Result<Study, String> {
        let text = std::fs::read_to_string(path).map_err(|e| format!("{}: {e}", path.display()))?;
        Study::parse(&text, path)
    }

    pub fn parse(text: &str, path: &Path) -> Result<Study, String> {
        let err = |m: String| format!("{}: {m}", path.display());
        let doc: toml::Table = text.parse().map_err(|e| err(format!("{e}")))?;
        let name = match doc.get("name") {
            Some(toml::Value::String(s)) => s.clone(),
            Some(_) => return Err(err("'name' must be a string".into())),
            // The file's name, made a folder-free one ("we ird.toml" -> "we_ird"): the user
            // gave no name to be refused.
            None => {
                let stem = path
                    .file_stem()
                    .map(|s| s.to_string_lossy().into_owned())
                    .unwrap_or_default();
                let plain: String = stem
                    .chars()
                    .map(|c| {
                        if c.is_ascii_alphanumeric() || matches!(c, '-' | '_' | '.') {
                            c
                        } else {
                            '_'
                        }
                    })
                    .collect();
                let plain = plain.trim_start_matches('.');
                if plain.is_empty() {
                    "study".into()
                } else {
                    plain.to_string()
                }
            }
        };
        check_study_name(&name).map_err(err)?;
        for k in doc.keys() {
            if !matches!(k.as_str(), "name" | "fixed" | "grid" | "description") {
                return Err(err(format!(
                    "unknown top-level key '{k}' (name, description, fixed, grid)"
                )));
            }
        }
        let check_key = |k: &str, where_: &str| -> Result<String, String> {
            if is_fmu_key(k) {
                crate::fmu_params::check_key(k).map_err(|e| err(format!("{where_}: {e}")))?;
                return Ok(k.to_string());
            }
            let n = normalize(k);
            if key_index(&n).is_none() {
                let known: Vec<&str> = KEYS.iter().map(|e| e.0).collect();
                return Err(err(format!(
                    "{where_}: '{k}' is not a run-up flag (known: {}; FMU parameters as \
                     rotor.NAME, film.NAME, film_C.NAME, film_T.NAME)",
                    known.join(", ")
                )));
            }
            Ok(n)
        };
        // A value's text, checked where a key's values have a known form (FMU parameters against
        // the FMU's variable table, booleans).
        let check_value = |key: &str, v: &toml::Value, where_: &str| -> Result<String, String> {
            let text = value_text(v)
                .ok_or_else(|| err(format!("{where_} {key}: expected a number, string or bool")))?;
            if is_fmu_key(key) {
                return crate::fmu_params::FmuParameter::parse(key, &text)
                    .map(|p| p.text)
                    .map_err(|e| err(format!("{where_}: {e}")));
            }
            if BOOLEAN_KEYS.contains(&key) && !matches!(text.as_str(), "true" | "false") {
                return Err(err(format!(
                    "{where_} {key} = '{text}': expected true or false"
                )));
            }
            Ok(text)
        };
        let mut fixed = BTreeMap::new();
        if let Some(f) = doc.get("fixed") {
            let t = f
                .as_table()
                .ok_or_else(|| err("[fixed] must be a table".into()))?;
            for (k, v) in flatten(t) {
                let n = check_key(&k, "[fixed]")?;
                let s = check_value(&n, &v, "[fixed]")?;
                fixed.insert(n, s);
            }
        }
        let grids = match doc.get("grid") {
            Some(toml::Value::Array(a)) => a.clone(),
            Some(_) => return Err(err("'grid' must be an array of tables ([[grid]])".into())),
            None => vec![toml::Value::Table(toml::Table::new())],
        };
        let mut runs: Vec<RunSpec> = Vec::new();
        for (gi, g) in grids.iter().enumerate() {
            let where_ = format!("grid {}", gi + 1);
            let t = g
                .as_table()
                .ok_or_else(|| err(format!("{where_} must be a table")))?;
            let grid_name = match t.get("name") {
                Some(toml::Value::String(n)) => n.clone(),
                Some(_) => return Err(err(format!("{where_}: 'name' must be a string"))),
                None => format!("grid{}", gi + 1),
            };
            // Axes of the product: each a list of alternatives, each alternative a set of (key, value).
            let mut axes: Vec<((usize, String), Vec<Params>)> = Vec::new();
            // Every key on one axis only: a key in two axes would silently overwrite itself.
            let mut seen: Vec<String> = Vec::new();
            let claim = |n: &str, seen: &mut Vec<String>| -> Result<(), String> {
                // The grid's value would silently win over the fixed one.
                if fixed.contains_key(n) {
                    return Err(err(format!(
                        "{where_}: '{n}' is also in [fixed]: a key is either fixed or varied"
                    )));
                }
                if seen.iter().any(|s| s == n) {
                    return Err(err(format!(
                        "{where_}: '{n}' is given twice (in cases and as a list, or in two cases \
                         tables with different keys)"
                    )));
                }
                seen.push(n.to_string());
                Ok(())
            };
            for (k, v) in flatten(t) {
                if k == "name" {
                    continue;
                }
                if k == "cases" {
                    let a = v.as_array().ok_or_else(|| {
                        err(format!("{where_}: 'cases' must be an array of tables"))
                    })?;
                    let mut alts = Vec::new();
                    let mut first = (usize::MAX, String::new());
                    let mut case_keys: Option<Vec<String>> = None;
                    for case in a {
                        let ct = case.as_table().ok_or_else(|| {
                            err(format!("{where_}: each case must be a table, e.g. {{ clearance = 15, dh = 30 }}"))
                        })?;
                        let mut alt = Vec::new();
                        for (ck, cv) in flatten(ct) {
                            let n = check_key(&ck, &format!("{where_} cases"))?;
                            first = first.min(key_order(&n));
                            let s = check_value(&n, &cv, &format!("{where_} cases"))?;
                            alt.push((n, s));
                        }
                        let keys: Vec<String> = alt.iter().map(|(k, _)| k.clone()).collect();
                        match &case_keys {
                            None => case_keys = Some(keys),
                            Some(first_keys) if *first_keys != keys => {
                                return Err(err(format!(
                                    "{where_}: every case must set the same keys ({} vs {})",
                                    first_keys.join(", "),
                                    keys.join(", ")
                                )))
                            }
                            Some(_) => {}
                        }
                        alts.push(alt);
                    }
                    for n in case_keys.unwrap_or_default() {
                        claim(&n, &mut seen)?;
                    }
                    axes.push((first, alts));
                    continue;
                }
                let n = check_key(&k, &where_)?;
                claim(&n, &mut seen)?;
                let list: Vec<toml::Value> = match v {
                    toml::Value::Array(a) => a,
                    other => vec![other],
                };
                let mut alts = Vec::new();
                for x in &list {
                    alts.push(vec![(n.clone(), check_value(&n, x, &where_)?)]);
                }
                axes.push((key_order(&n), alts));
            }
            if axes.iter().any(|(_, a)| a.is_empty()) {
                return Err(err(format!("{where_}: an empty list gives no runs")));
            }
            // Outer loops over the first keys (C, dH, ..., c, d innermost).
            axes.sort_by(|a, b| a.0.cmp(&b.0));
            let mut points: Vec<Vec<(String, String)>> = vec![vec![]];
            for (_, alts) in &axes {
                let mut next = Vec::with_capacity(points.len() * alts.len());
                for p in &points {
                    for a in alts {
                        let mut q = p.clone();
                        q.extend(a.iter().cloned());
                        next.push(q);
                    }
                }
                points = next;
            }
            for p in points {
                let mut args = fixed.clone();
                let mut varied = BTreeMap::new();
                for (k, v) in p {
                    args.insert(k.clone(), v.clone());
                    varied.insert(k, v);
                }
                let name = run_name(&varied);
                match runs.iter_mut().find(|r| r.name == name) {
                    // Listed twice: run once, in both grids.
                    Some(r) if r.args == args => {
                        if !r.grids.contains(&grid_name) {
                            r.grids.push(grid_name.clone());
                        }
                    }
                    Some(_) => {
                        return Err(err(format!(
                            "run '{name}' appears twice with different flags"
                        )))
                    }
                    None => {
                        let index = runs.len();
                        runs.push(RunSpec {
                            index,
                            name,
                            args,
                            grids: vec![grid_name.clone()],
                        })
                    }
                }
            }
        }
        // Files and folders a study names are relative to the study file's folder, as a system
        // file's FMU paths are (not to wherever the sweep is started from).
        let base = path
            .parent()
            .filter(|p| !p.as_os_str().is_empty() && *p != Path::new("."));
        for r in &mut runs {
            for key in ["design", "fmu_dir"] {
                match (r.args.get_mut(key), base) {
                    (Some(v), Some(base)) if Path::new(v.as_str()).is_relative() => {
                        *v = base.join(v.as_str()).to_string_lossy().into_owned();
                    }
                    _ => {}
                }
            }
            // A folder without the FMUs would fail every run only once the sweep runs them.
            if let Some(dir) = r.args.get("fmu_dir") {
                if let Some(f) = ["rotor.fmu", "airfilm.fmu"]
                    .iter()
                    .find(|f| !Path::new(dir).join(f).is_file())
                {
                    return Err(err(format!(
                        "run '{}': fmu_dir = '{dir}': no {f} there",
                        r.name
                    )));
                }
            }
        }
        // Every point through the run-up's own flag parser and checks, so that `--list` (and
        // the sweep, before it starts anything) refuses what the run-up would refuse.
        for r in &runs {
            crate::runup::flags::check_argv(&runup_args(&r.args))
                .map_err(|e| err(format!("run '{}' ({}): {e}", r.name, grid_list(&r.grids))))?;
        }
        Ok(Study { name, runs })
    }
}

fn grid_list(grids: &[String]) -> String {
    grids.join(", ")
}

/// A study name names its output folder (`runs/sweep-NAME`): letters, digits, '-', '_' and
/// '.', not starting with a dot, so it cannot lead outside `runs/`.
fn check_study_name(name: &str) -> Result<(), String> {
    let plain = name
        .chars()
        .all(|c| c.is_ascii_alphanumeric() || matches!(c, '-' | '_' | '.'));
    if name.is_empty() || !plain || name.starts_with('.') {
        return Err(format!(
            "name '{name}': a study name names its output folder, so it may hold only letters, \
             digits, '-', '_' and '.', and may not start with a dot"
        ));
    }
    Ok(())
}

/// Folder name of a run from its grid parameters, e.g. `C15_dH30_c500_d50` (an FMU parameter
/// by its key: `film.eta1.9e-5`).
pub fn run_name(varied: &BTreeMap<String, String>) -> String {
    let clean = |s: &str, keep_dot: bool| -> String {
        s.chars()
            .filter(|c| *c != '_' || !keep_dot)
            .map(|c| {
                if c.is_ascii_alphanumeric() || c == '.' || c == '-' {
                    c
                } else {
                    '-'
                }
            })
            .collect()
    };
    let parts: Vec<String> = keys_in(std::iter::once(varied))
        .iter()
        .map(|k| {
            let v = clean(&varied[k], false);
            if is_fmu_key(k) {
                // "film_C.C" -> "filmC.C": '_' separates the parts of a name.
                format!("{}{v}", clean(k, true))
            } else {
                // The preset's short name is empty: its value names it ("path2b").
                let short = KEYS.iter().find(|e| e.0 == k.as_str()).map_or("", |e| e.1);
                format!("{short}{v}")
            }
        })
        .collect();
    if parts.is_empty() {
        return "base".into();
    }
    // A run name is a folder inside the sweep's `runs/`: never "..", never hidden (a preset
    // value "..", or one starting with a dot, would otherwise name the sweep's own folder).
    let name = parts.join("_").replace("..", "--");
    match name.strip_prefix('.') {
        Some(rest) => format!("-{rest}"),
        None => name,
    }
}

/// The `airring runup` command-line arguments of a run (without --out).
pub fn runup_args(args: &BTreeMap<String, String>) -> Vec<String> {
    let mut out = vec!["runup".to_string()];
    for (k, v) in args {
        if is_fmu_key(k) {
            out.push("--set".into());
            out.push(format!("{k}={v}"));
            continue;
        }
        let flag = format!("--{}", k.replace('_', "-"));
        if BOOLEAN_KEYS.contains(&k.as_str()) {
            if v == "true" {
                out.push(flag);
            }
        } else {
            out.push(flag);
            out.push(v.clone());
        }
    }
    out
}

/// `--shard k/n` -> (k, n) with 1 <= k <= n.
pub fn parse_shard(s: &str) -> Result<(usize, usize), String> {
    let bad = || format!("--shard expects k/n with 1 <= k <= n, found '{s}'");
    let (k, n) = s.split_once('/').ok_or_else(bad)?;
    let (k, n): (usize, usize) = (
        k.trim().parse().map_err(|_| bad())?,
        n.trim().parse().map_err(|_| bad())?,
    );
    if k == 0 || n == 0 || k > n {
        return Err(bad());
    }
    Ok((k, n))
}

/// The runs of a study (or of one shard) as JSON lines: name, index, flags, and the `airring` arguments
/// (without --out) that run it; external drivers (scripts/dask_sweep.py) use it.
pub fn plan_json_lines(study: &Study, shard: Option<(usize, usize)>) -> String {
    let mut s = String::new();
    for r in study
        .runs
        .iter()
        .filter(|r| shard.is_none_or(|(k, n)| r.index % n == k - 1))
    {
        let line = serde_json::json!({
            "name": r.name, "index": r.index, "args": r.args, "argv": runup_args(&r.args),
        });
        s.push_str(&line.to_string());
        s.push('\n');
    }
    s
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn grids_cases_and_duplicates() {
        let s = Study::parse(
            r#"
name = "t"
[fixed]
preset = "path1"
stop = 0.01
[[grid]]
cases = [{ clearance = 10, dh = 20 }, { clearance = 15, dh = 30 }]
c = [500, 1000]
d = [50]
[[grid]]
clearance = 15
dh = [0, 30]
c = 1000
d = [50]
"#,
            Path::new("t.toml"),
        )
        .unwrap();
        let names: Vec<&str> = s.runs.iter().map(|r| r.name.as_str()).collect();
        assert_eq!(
            names,
            [
                "C10_dH20_c500_d50",
                "C10_dH20_c1000_d50",
                "C15_dH30_c500_d50",
                "C15_dH30_c1000_d50",
                "C15_dH0_c1000_d50"
            ]
        );
        let a = runup_args(&s.runs[0].args);
        assert_eq!(
            a.join(" "),
            "runup --c 500 --clearance 10 --d 50 --dh 20 --preset path1 --stop 0.01"
        );
        assert!(Study::parse("[[grid]]\nbogus = [1]\n", Path::new("x.toml"))
            .unwrap_err()
            .contains("'bogus' is not a run-up flag"));
        // A study without a name takes its file's, made folder-free; a name given is checked.
        let text = "[fixed]\nstop = 0.01\n[[grid]]\nc = [500]\n";
        for (file, name) in [
            ("we ird.toml", "we_ird"),
            (".x y.toml", "x_y"),
            ("t.toml", "t"),
        ] {
            assert_eq!(
                Study::parse(text, Path::new(file)).unwrap().name,
                name,
                "{file}"
            );
        }
        let e = Study::parse(&format!("name = \"a b\"\n{text}"), Path::new("t.toml")).unwrap_err();
        assert!(
            e.contains("name 'a b': a study name names its output folder"),
            "{e}"
        );
        // Files a study names are taken from its own folder; a folder without the FMUs is
        // refused by --list already.
        let dir = std::env::temp_dir().join(format!("airring-study-paths-{}", std::process::id()));
        std::fs::create_dir_all(dir.join("fm")).unwrap();
        std::fs::write(dir.join("d.toml"), "[bearing]\nmount_d = \"60 N.s/m\"\n").unwrap();
        let s = Study::parse(
            &text.replace("[fixed]\n", "[fixed]\ndesign = \"d.toml\"\n"),
            &dir.join("s.toml"),
        )
        .unwrap();
        assert_eq!(
            s.runs[0].args["design"],
            dir.join("d.toml").to_string_lossy()
        );
        let e = Study::parse(
            &text.replace("[fixed]\n", "[fixed]\nfmu_dir = \"fm\"\n"),
            &dir.join("s.toml"),
        )
        .unwrap_err();
        assert!(
            e.contains("fmu_dir = '") && e.contains("fm': no rotor.fmu there"),
            "{e}"
        );
        let _ = std::fs::remove_dir_all(&dir);
        assert_eq!(parse_shard("2/3"), Ok((2, 3)));
        assert!(parse_shard("0/3").is_err() && parse_shard("4/3").is_err());
    }

    /// The paper's Section 4 study: 44 grid points, 42 distinct run-ups; the step-height study's
    /// dH = 30 um points are case-2 runs and belong to both grids.
    #[test]
    fn paper_section4_study_points_and_grids() {
        let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../studies/paper_section4.toml");
        let s = Study::load(&path).unwrap();
        assert_eq!(s.runs.len(), 42);
        let grids = |name: &str| {
            s.runs
                .iter()
                .find(|r| r.name == name)
                .unwrap()
                .grids
                .clone()
        };
        assert_eq!(grids("C15_dH30_c1000_d50"), ["cases", "step_height"]);
        assert_eq!(grids("C15_dH0_c1000_d500"), ["step_height"]);
        assert_eq!(grids("C30_dH60_c500_d50"), ["cases"]);
        let listed: usize = s.runs.iter().map(|r| r.grids.len()).sum();
        assert_eq!(listed, 44);
    }

    /// Any FMU parameter can be a study key: dotted (`film.eta = [...]`) or quoted
    /// (`"rotor.m_R_C" = ...`), checked against the FMU's variable table when the study is read,
    /// and passed to the run-up as `--set`.
    #[test]
    fn fmu_parameters_are_study_keys() {
        let s = Study::parse(
            r#"
[fixed]
"rotor.c_C" = "1500 N/mm"
contact = "film"
[[grid]]
film.eta = [1.8e-5, 2e-5]
cases = [{ c = 500, film_T.C = "25 um" }]
d = 50
"#,
            Path::new("t.toml"),
        )
        .unwrap();
        let names: Vec<&str> = s.runs.iter().map(|r| r.name.as_str()).collect();
        assert_eq!(
            names,
            [
                "c500_d50_film.eta0.000018_filmT.C25-um",
                "c500_d50_film.eta0.00002_filmT.C25-um"
            ]
        );
        let a = runup_args(&s.runs[1].args).join(" ");
        assert_eq!(
            a,
            "runup --c 500 --contact film --d 50 --set film.eta=0.00002 --set film_T.C=25 um --set rotor.c_C=1500 N/mm"
        );
        for (text, why) in [
            (
                "[[grid]]\nfilm.viscosity = [1]\n",
                "no parameter 'viscosity'",
            ),
            (
                "[[grid]]\nrotor.c_C = [\"5 furlongs\"]\n",
                "unit 'furlongs'",
            ),
            ("[[grid]]\nstator.x = [1]\n", "is not a run-up flag"),
            ("[[grid]]\njacobi = [\"yes\"]\n", "expected true or false"),
            (
                "[[grid]]\ncases = [{ c = 500 }, { c = 1000 }]\nc = [1500]\n",
                "'c' is given twice",
            ),
            (
                "[[grid]]\ncases = [{ c = 500 }, { d = 50 }]\n",
                "every case must set the same keys",
            ),
            // Fixed and varied: the grid's value silently won.
            (
                "[fixed]\nc = 500\n[[grid]]\nc = [500, 1000]\n",
                "grid 1: 'c' is also in [fixed]",
            ),
            (
                "[fixed]\nclearance = 15\n[[grid]]\ncases = [{ clearance = 10, dh = 20 }]\n",
                "'clearance' is also in [fixed]",
            ),
        ] {
            let e = Study::parse(text, Path::new("x.toml")).unwrap_err();
            assert!(e.contains(why), "{text}: {e}");
        }
    }

    /// Every value goes through the run-up's own checks when the study is read (before: these
    /// passed `--list` and failed in every run, the reason only in runs/*/runup.log), and no
    /// name leads outside the output folder.
    #[test]
    fn studies_are_checked_completely_when_read() {
        for (text, why) in [
            ("[[grid]]\nc = [\"abc\"]\n", "invalid value 'abc'"),
            (
                "[[grid]]\nc = [500, -5]\n",
                "--c = -5 N/mm must be a finite number >= 0",
            ),
            ("[[grid]]\nmesh = \"8by2\"\n", "expected NxM"),
            (
                "[fixed]\nstop = 0\n",
                "--stop = 0 s must be a finite number > 0",
            ),
            ("[[grid]]\npreset = [\"..\"]\n", "unknown preset '..'"),
            ("name = \"../../../../x\"\n", "may not start with a dot"),
            ("name = \"a/b\"\n", "only letters"),
            ("[fixed]\n\"film.eta\" = -1\n", "eta"),
            (
                "[[grid]]\nprofile = [\"0:0,1:1500,2:0\", \"0:0,1:100,0.5:0\"]\n",
                "times must increase",
            ),
        ] {
            let e = Study::parse(text, Path::new("x.toml")).unwrap_err();
            assert!(e.contains(why), "{text}: {e}");
        }
        // The failing point is named with its grid.
        let e = Study::parse("[[grid]]\nc = [500, -5]\n", Path::new("x.toml")).unwrap_err();
        assert!(e.contains("run 'c-5' (grid1)"), "{e}");
        // Run names stay inside runs/: never "..", never hidden.
        let mut v = BTreeMap::new();
        v.insert("preset".to_string(), "..".to_string());
        assert_eq!(run_name(&v), "--");
        v.insert("preset".to_string(), ".hidden".to_string());
        assert_eq!(run_name(&v), "-hidden");
    }

    /// Speed profiles are a study key: each point its own run, named by its profile.
    #[test]
    fn speed_profiles_can_be_swept() {
        let text =
            "[fixed]\nstop = 0.002\n[[grid]]\nprofile = [\"0:0,1:1500,2:0\", \"0:0,1:1800,2:0\"]\n";
        let study = Study::parse(text, Path::new("x.toml")).unwrap();
        let names: Vec<&str> = study.runs.iter().map(|r| r.name.as_str()).collect();
        assert_eq!(names, ["prof0-0-1-1500-2-0", "prof0-0-1-1800-2-0"]);
    }
}
