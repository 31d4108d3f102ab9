//! `airring sweep`: parameter studies of run-ups, their result table and bifurcation maps.
//!
//! A study file (TOML) names fixed run-up flags and one or more grids of parameter lists:
//!
//! ```toml
//! name = "smoke"
//! [fixed]                      # any `airring runup` flag (without --, '-' or '_'), for every run
//! preset = "path1"
//! stop = 0.01
//! [[grid]]                     # the Cartesian product of its lists; several grids are concatenated
//! cases = [{ clearance = 15, dh = 30 }]   # paired values, varied together
//! c = [500, 1000]
//! d = [50, 500]
//! ```
//!
//! Every grid point is one run-up, run as a child process `airring runup ... --out DIR/runs/NAME`
//! (a crash or a failed run stays in its folder), `--jobs` at a time. The run name is built from the
//! grid parameters (`C15_dH30_c500_d50`), so a point listed twice runs once, and a run whose
//! `summary.json` says `completed` with the same flags (`sweep_run.json`) is not run again.
//! `--shard k/n` runs the points with index i (0-based, in study order) where i mod n = k - 1;
//! `airring sweep-merge` collects the run folders of several output folders into one table and map.

use crate::plot::canvas::{Anchor, Canvas, Item, Rgb};
use std::collections::{BTreeMap, HashMap};
use std::io::{BufRead, BufReader, IsTerminal, Write as _};
use std::path::{Path, PathBuf};
use std::process::{Child, Command, Stdio};
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Arc, Mutex};
use std::time::{Duration, Instant};

/// Run-up flags a study may set, in the order used for run names and table columns:
/// (key, short name in run names, field of the run-up settings in summary.json, unit).
pub const KEYS: &[(&str, &str, &str, &str)] = &[
    ("preset", "", "preset", ""),
    ("clearance", "C", "clearance_um", "um"),
    ("dh", "dH", "dh_um", "um"),
    ("c", "c", "c_n_per_mm", "N/mm"),
    ("d", "d", "d_n_s_per_m", "N s/m"),
    ("m_r", "mR", "m_r_g", "g"),
    ("f_max", "fmax", "f_max_hz", "Hz"),
    ("t_ramp", "tramp", "t_ramp_s", "s"),
    ("stop", "stop", "stop_time_s", "s"),
    ("macro_step", "H", "macro_step_us", "us"),
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
    ("fmu_dir", "fmu", "", ""),
];

/// Flags that choose how a run-up is computed, not what is computed: runs that differ only in
/// these share a map panel.
const NUMERICS: &[&str] = &["contact", "fmu_dir"];

/// A set of (flag, value) pairs.
type Params = Vec<(String, String)>;

fn key_index(k: &str) -> Option<usize> {
    KEYS.iter().position(|e| e.0 == k)
}

/// One grid point: its run name, its index in the study, and its run-up flags (key -> value text).
#[derive(Debug, Clone, PartialEq)]
pub struct RunSpec {
    pub index: usize,
    pub name: String,
    pub args: BTreeMap<String, String>,
}

#[derive(Debug, Clone)]
pub struct Study {
    pub name: String,
    pub runs: Vec<RunSpec>,
}

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
            None => path
                .file_stem()
                .map(|s| s.to_string_lossy().into_owned())
                .unwrap_or_else(|| "study".into()),
        };
        for k in doc.keys() {
            if !matches!(k.as_str(), "name" | "fixed" | "grid" | "description") {
                return Err(err(format!(
                    "unknown top-level key '{k}' (name, description, fixed, grid)"
                )));
            }
        }
        let check_key = |k: &str, where_: &str| -> Result<String, String> {
            let n = normalize(k);
            if key_index(&n).is_none() {
                let known: Vec<&str> = KEYS.iter().map(|e| e.0).collect();
                return Err(err(format!(
                    "{where_}: '{k}' is not a run-up flag (known: {})",
                    known.join(", ")
                )));
            }
            Ok(n)
        };
        let mut fixed = BTreeMap::new();
        if let Some(f) = doc.get("fixed") {
            let t = f
                .as_table()
                .ok_or_else(|| err("[fixed] must be a table".into()))?;
            for (k, v) in t {
                let n = check_key(k, "[fixed]")?;
                let s = value_text(v).ok_or_else(|| {
                    err(format!("[fixed] {k}: expected a number, string or bool"))
                })?;
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
            // Axes of the product: each a list of alternatives, each alternative a set of (key, value).
            let mut axes: Vec<(usize, Vec<Params>)> = Vec::new();
            for (k, v) in t {
                if k == "name" {
                    continue;
                }
                if k == "cases" {
                    let a = v.as_array().ok_or_else(|| {
                        err(format!("{where_}: 'cases' must be an array of tables"))
                    })?;
                    let mut alts = Vec::new();
                    let mut first = usize::MAX;
                    for case in a {
                        let ct = case.as_table().ok_or_else(|| {
                            err(format!("{where_}: each case must be a table, e.g. {{ clearance = 15, dh = 30 }}"))
                        })?;
                        let mut alt = Vec::new();
                        for (ck, cv) in ct {
                            let n = check_key(ck, &format!("{where_} cases"))?;
                            first = first.min(key_index(&n).unwrap_or(usize::MAX));
                            let s = value_text(cv).ok_or_else(|| {
                                err(format!(
                                    "{where_} cases.{ck}: expected a number, string or bool"
                                ))
                            })?;
                            alt.push((n, s));
                        }
                        alts.push(alt);
                    }
                    axes.push((first, alts));
                    continue;
                }
                let n = check_key(k, &where_)?;
                let list: Vec<toml::Value> = match v {
                    toml::Value::Array(a) => a.clone(),
                    other => vec![other.clone()],
                };
                let mut alts = Vec::new();
                for x in &list {
                    let s = value_text(x).ok_or_else(|| {
                        err(format!("{where_}.{k}: expected numbers, strings or bools"))
                    })?;
                    alts.push(vec![(n.clone(), s)]);
                }
                axes.push((key_index(&n).unwrap_or(usize::MAX), alts));
            }
            if axes.iter().any(|(_, a)| a.is_empty()) {
                return Err(err(format!("{where_}: an empty list gives no runs")));
            }
            // Outer loops over the first keys (C, dH, ..., c, d innermost).
            axes.sort_by_key(|(i, _)| *i);
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
                match runs.iter().find(|r| r.name == name) {
                    Some(r) if r.args == args => continue, // listed twice: run once
                    Some(_) => {
                        return Err(err(format!(
                            "run '{name}' appears twice with different flags"
                        )))
                    }
                    None => runs.push(RunSpec {
                        index: runs.len(),
                        name,
                        args,
                    }),
                }
            }
        }
        Ok(Study { name, runs })
    }
}

/// Folder name of a run from its grid parameters, e.g. `C15_dH30_c500_d50`.
pub fn run_name(varied: &BTreeMap<String, String>) -> String {
    let mut parts = Vec::new();
    for (k, short, _, _) in KEYS {
        if let Some(v) = varied.get(*k) {
            let v: String = v
                .chars()
                .map(|c| {
                    if c.is_ascii_alphanumeric() || c == '.' || c == '-' {
                        c
                    } else {
                        '-'
                    }
                })
                .collect();
            parts.push(format!("{short}{v}"));
        }
    }
    if parts.is_empty() {
        "base".into()
    } else {
        parts.join("_")
    }
}

/// The `airring runup` command-line arguments of a run (without --out).
pub fn runup_args(args: &BTreeMap<String, String>) -> Vec<String> {
    let mut out = vec!["runup".to_string()];
    for (k, v) in args {
        let flag = format!("--{}", k.replace('_', "-"));
        if k == "jacobi" {
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

pub struct SweepOptions {
    pub out: PathBuf,
    pub jobs: usize,
    pub shard: Option<(usize, usize)>,
    /// The `airring` executable the run-ups are started with.
    pub exe: PathBuf,
    pub quiet: bool,
    /// Pass --serial-films to every run-up (one core each; set when jobs exceed half the cores).
    pub serial_films: bool,
    /// Set by Ctrl-C: no new run-ups are started; running ones stop themselves (same signal).
    pub stop: Arc<AtomicBool>,
}

/// Cores available to this process.
pub fn cores() -> usize {
    std::thread::available_parallelism()
        .map(|n| n.get())
        .unwrap_or(1)
}

/// Default parallel run-ups: one per core, each stepping its two films one after the other
/// (throughput: no thread hand-over per macro step, and the rotor step does not leave a core idle).
pub fn default_jobs() -> usize {
    cores()
}

#[derive(Debug, Default)]
pub struct SweepReport {
    pub total: usize,
    pub skipped: usize,
    pub ran: usize,
    pub failed: Vec<String>,
    pub wall_time_s: f64,
    pub table: PathBuf,
    pub maps: Vec<PathBuf>,
}

fn read_json(p: &Path) -> Option<serde_json::Value> {
    serde_json::from_str(&std::fs::read_to_string(p).ok()?).ok()
}

/// True if `dir` holds a completed run with exactly these flags.
fn is_done(dir: &Path, args: &BTreeMap<String, String>) -> bool {
    let done = read_json(&dir.join("summary.json"))
        .is_some_and(|s| s["status"].as_str() == Some("completed"));
    let same = read_json(&dir.join("sweep_run.json"))
        .is_some_and(|r| r["args"] == serde_json::to_value(args).unwrap_or_default());
    done && same
}

struct Running {
    spec: RunSpec,
    child: Child,
    fraction: Arc<Mutex<f64>>,
    reader: Option<std::thread::JoinHandle<()>>,
}

/// Parses "( 12.5 %)" from a run-up's progress line.
fn progress_fraction(line: &str) -> Option<f64> {
    let open = line.find('(')?;
    let close = line[open..].find("%)")? + open;
    line[open + 1..close]
        .trim()
        .parse::<f64>()
        .ok()
        .map(|p| p / 100.0)
}

fn start_run(spec: &RunSpec, opts: &SweepOptions) -> Result<Running, String> {
    let dir = opts.out.join("runs").join(&spec.name);
    std::fs::create_dir_all(&dir).map_err(|e| format!("{}: {e}", dir.display()))?;
    // A stale summary must not count as this run's result.
    let _ = std::fs::remove_file(dir.join("summary.json"));
    let meta = serde_json::json!({ "name": spec.name, "index": spec.index, "args": spec.args });
    std::fs::write(
        dir.join("sweep_run.json"),
        serde_json::to_string_pretty(&meta).expect("json"),
    )
    .map_err(|e| format!("{}: {e}", dir.display()))?;
    let mut cmd = Command::new(&opts.exe);
    cmd.args(runup_args(&spec.args));
    if opts.serial_films {
        cmd.arg("--serial-films");
    }
    cmd.arg("--out")
        .arg(&dir)
        .stdin(Stdio::null())
        .stdout(Stdio::null())
        .stderr(Stdio::piped());
    let mut child = cmd
        .spawn()
        .map_err(|e| format!("starting {}: {e}", opts.exe.display()))?;
    let stderr = child.stderr.take().expect("piped");
    let fraction = Arc::new(Mutex::new(0.0));
    let f = fraction.clone();
    let log_path = dir.join("runup.log");
    let reader = std::thread::spawn(move || {
        let mut log = std::fs::File::create(&log_path).ok();
        for line in BufReader::new(stderr).lines().map_while(Result::ok) {
            if let Some(l) = log.as_mut() {
                let _ = writeln!(l, "{line}");
            }
            if let Some(p) = progress_fraction(&line) {
                *f.lock().expect("progress") = p;
            }
        }
    });
    Ok(Running {
        spec: spec.clone(),
        child,
        fraction,
        reader: Some(reader),
    })
}

/// Writes a failure summary for a run-up that ended without one (crash, bad flags).
fn ensure_summary(dir: &Path, code: Option<i32>) {
    let p = dir.join("summary.json");
    if p.exists() {
        return;
    }
    let s = serde_json::json!({
        "status": "failed",
        "error": format!("the run-up ended with exit code {code:?} and wrote no summary; see runup.log"),
        "classification": null, "onset_time_s": null, "max_eps_C": null, "max_eps_T": null,
        "wall_time_s": null,
    });
    let _ = std::fs::write(p, serde_json::to_string_pretty(&s).expect("json"));
}

fn stem_for(shard: Option<(usize, usize)>) -> (String, String) {
    match shard {
        None => ("study".into(), "bifurcation_map".into()),
        Some((k, n)) => (
            format!("study_shard-{k}-of-{n}"),
            format!("bifurcation_map_shard-{k}-of-{n}"),
        ),
    }
}

/// Runs (or resumes) a study into `opts.out`, then writes its table and maps.
pub fn sweep(study: &Study, study_text: &str, opts: &SweepOptions) -> Result<SweepReport, String> {
    std::fs::create_dir_all(opts.out.join("runs"))
        .map_err(|e| format!("{}: {e}", opts.out.display()))?;
    let _ = std::fs::write(opts.out.join("study.toml"), study_text);
    let mine: Vec<&RunSpec> = study
        .runs
        .iter()
        .filter(|r| opts.shard.is_none_or(|(k, n)| r.index % n == k - 1))
        .collect();
    let mut report = SweepReport {
        total: mine.len(),
        ..Default::default()
    };
    let todo: Vec<&RunSpec> = mine
        .iter()
        .copied()
        .filter(|r| !is_done(&opts.out.join("runs").join(&r.name), &r.args))
        .collect();
    report.skipped = mine.len() - todo.len();
    let start = Instant::now();
    let tty = std::io::stderr().is_terminal();
    if !opts.quiet {
        eprintln!(
            "sweep '{}'{}: {} runs, {} already completed, {} to run, {} at a time -> {}",
            study.name,
            opts.shard
                .map(|(k, n)| format!(" shard {k}/{n}"))
                .unwrap_or_default(),
            mine.len(),
            report.skipped,
            todo.len(),
            opts.jobs,
            opts.out.display()
        );
    }
    let mut queue = todo.into_iter();
    let mut running: Vec<Running> = Vec::new();
    let mut finished = 0usize;
    let n_todo = mine.len() - report.skipped;
    let mut last_print = Instant::now() - Duration::from_secs(3600);
    loop {
        while running.len() < opts.jobs.max(1) && !opts.stop.load(Ordering::Relaxed) {
            match queue.next() {
                Some(spec) => match start_run(spec, opts) {
                    Ok(r) => running.push(r),
                    Err(e) => {
                        eprintln!("sweep: {}: {e}", spec.name);
                        report.failed.push(spec.name.clone());
                        finished += 1;
                    }
                },
                None => break,
            }
        }
        if running.is_empty() {
            break;
        }
        let mut i = 0;
        let mut changed = false;
        while i < running.len() {
            match running[i].child.try_wait() {
                Ok(Some(status)) => {
                    let mut r = running.swap_remove(i);
                    if let Some(h) = r.reader.take() {
                        let _ = h.join();
                    }
                    let dir = opts.out.join("runs").join(&r.spec.name);
                    ensure_summary(&dir, status.code());
                    let s = read_json(&dir.join("summary.json")).unwrap_or_default();
                    let st = s["status"].as_str().unwrap_or("failed").to_string();
                    if st != "completed" {
                        report.failed.push(r.spec.name.clone());
                    }
                    report.ran += 1;
                    finished += 1;
                    changed = true;
                    if !opts.quiet {
                        let line = format!(
                            "[{finished}/{n_todo}] {}: {st}, {}, onset {} Hz, {:.0} s",
                            r.spec.name,
                            s["classification"].as_str().unwrap_or("-"),
                            s["onset_speed_hz"]
                                .as_f64()
                                .map_or("-".into(), |v| format!("{v:.0}")),
                            s["wall_time_s"].as_f64().unwrap_or(f64::NAN)
                        );
                        if tty {
                            eprint!("\r\x1b[2K");
                        }
                        eprintln!("{line}");
                    }
                }
                Ok(None) => i += 1,
                Err(e) => {
                    let r = running.swap_remove(i);
                    eprintln!("sweep: {}: {e}", r.spec.name);
                    report.failed.push(r.spec.name.clone());
                    finished += 1;
                }
            }
        }
        let due = if tty {
            last_print.elapsed() >= Duration::from_millis(500)
        } else {
            last_print.elapsed() >= Duration::from_secs(60) || changed
        };
        if !opts.quiet && due && !running.is_empty() {
            last_print = Instant::now();
            let part: f64 = running
                .iter()
                .map(|r| *r.fraction.lock().expect("progress"))
                .sum();
            let frac = (finished as f64 + part) / n_todo.max(1) as f64;
            let el = start.elapsed().as_secs_f64();
            let eta = if frac > 1e-3 {
                format!("{:.0} s", el * (1.0 - frac) / frac)
            } else {
                "?".into()
            };
            let names: Vec<String> = running
                .iter()
                .map(|r| {
                    format!(
                        "{} {:.0}%",
                        r.spec.name,
                        100.0 * *r.fraction.lock().expect("progress")
                    )
                })
                .collect();
            let line = format!(
                "study {:5.1} % | {finished}/{n_todo} done | running: {} | wall {el:.0} s, ETA {eta}",
                100.0 * frac,
                names.join(", ")
            );
            if tty {
                eprint!("\r\x1b[2K{line}");
            } else {
                eprintln!("{line}");
            }
        }
        std::thread::sleep(Duration::from_millis(100));
    }
    if tty && !opts.quiet {
        eprintln!();
    }
    report.wall_time_s = start.elapsed().as_secs_f64();
    let names: Vec<String> = mine.iter().map(|r| r.name.clone()).collect();
    let records: Vec<RunRecord> = collect(std::slice::from_ref(&opts.out))
        .into_iter()
        .filter(|r| names.contains(&r.name))
        .collect();
    let (table, map) = stem_for(opts.shard);
    report.table = opts.out.join(format!("{table}.csv"));
    write_table(&records, &report.table)?;
    report.maps = plot_maps(&records, &opts.out, &map).map_err(|e| format!("maps: {e}"))?;
    if opts.stop.load(Ordering::Relaxed) {
        eprintln!("sweep interrupted: run the same command again to continue");
    }
    Ok(report)
}

/// One run's parameters and results, read from its folder.
#[derive(Debug, Clone, PartialEq)]
pub struct RunRecord {
    pub name: String,
    pub index: usize,
    pub args: BTreeMap<String, String>,
    pub status: String,
    pub classification: Option<String>,
    pub onset_time_s: Option<f64>,
    pub onset_speed_hz: Option<f64>,
    pub max_eps_c: Option<f64>,
    pub max_eps_t: Option<f64>,
    pub wall_time_s: Option<f64>,
    pub settings: serde_json::Value,
}

impl RunRecord {
    /// A parameter: as the study gave it, else the run-up's effective setting.
    pub fn param(&self, key: &str) -> Option<f64> {
        if let Some(v) = self.args.get(key).and_then(|v| v.parse().ok()) {
            return Some(v);
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
            let s = read_json(&dir.join("summary.json")).unwrap_or_default();
            let args: BTreeMap<String, String> =
                serde_json::from_value(meta["args"].clone()).unwrap_or_default();
            let rec = RunRecord {
                name: meta["name"]
                    .as_str()
                    .map(String::from)
                    .unwrap_or_else(|| e.file_name().to_string_lossy().into_owned()),
                index: meta["index"].as_u64().unwrap_or(u64::MAX) as usize,
                args,
                status: s["status"].as_str().unwrap_or("missing").to_string(),
                classification: s["classification"].as_str().map(String::from),
                onset_time_s: s["onset_time_s"].as_f64(),
                onset_speed_hz: s["onset_speed_hz"].as_f64(),
                max_eps_c: s["max_eps_C"].as_f64(),
                max_eps_t: s["max_eps_T"].as_f64(),
                wall_time_s: s["wall_time_s"].as_f64(),
                settings: s["settings"].clone(),
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

/// The study table: one row per run; parameter columns are the flags any run was given.
pub fn write_table(records: &[RunRecord], path: &Path) -> Result<(), String> {
    let keys: Vec<&str> = KEYS
        .iter()
        .map(|e| e.0)
        .filter(|k| records.iter().any(|r| r.args.contains_key(*k)))
        .collect();
    let mut s = String::from("run");
    for k in &keys {
        let unit = KEYS.iter().find(|e| e.0 == *k).map_or("", |e| e.3);
        if unit.is_empty() {
            s.push_str(&format!(",{k}"));
        } else {
            s.push_str(&format!(",{k} [{unit}]"));
        }
    }
    s.push_str(",status,classification,onset_time [s],onset_speed [Hz],max_eps_C [1],max_eps_T [1],wall_time [s]\n");
    for r in records {
        s.push_str(&r.name);
        for k in &keys {
            s.push(',');
            let v = r.args.get(*k).cloned().unwrap_or_default();
            if v.contains(',') {
                s.push_str(&format!("\"{v}\""));
            } else {
                s.push_str(&v);
            }
        }
        s.push_str(&format!(
            ",{},{},{},{},{},{},{}\n",
            r.status,
            r.classification.as_deref().unwrap_or(""),
            opt(r.onset_time_s),
            opt(r.onset_speed_hz),
            opt(r.max_eps_c),
            opt(r.max_eps_t),
            r.wall_time_s.map_or(String::new(), |w| format!("{w:.1}"))
        ));
    }
    std::fs::write(path, s).map_err(|e| format!("{}: {e}", path.display()))
}

/// Run-up classes, their names in the legend and their (shorter) labels in a map cell.
const CLASS_NAMES: &[(&str, &str, &str)] = &[
    ("stable", "stable", "stable"),
    ("path1", "path 1", "path 1"),
    ("path2a", "path 2a", "path 2a"),
    ("path2b", "path 2b", "path 2b"),
    ("unstable_low_speed", "unstable low", "unst.low"),
    ("unstable_linear", "lin. unst.", "lin. unst."),
];

fn legend_color(name: &str) -> Rgb {
    LEGEND
        .iter()
        .find(|e| e.0 == name)
        .map_or(Rgb(240, 240, 240), |e| e.1)
}

/// What a map cell shows: its fill and a short label.
fn cell_style(r: &RunRecord) -> (Rgb, String) {
    let class = r
        .classification
        .as_deref()
        .and_then(|c| CLASS_NAMES.iter().find(|e| e.0 == c));
    if r.status == "completed" {
        return match class {
            Some(&(_, name, label)) => (legend_color(name), label.to_string()),
            None => (Rgb(240, 240, 240), "unclassified".into()),
        };
    }
    // A run that failed after its onset (the journal reached the contact limit or the film's
    // Newton iteration gave up in a violent whirl) keeps the unstable class it had reached: an
    // unstable run that ends in contact is no less unstable. Its label carries "(f)". A run
    // stopped by hand after its onset likewise, with "(i)".
    let interrupted = r.status == "interrupted";
    let reached =
        class.filter(|e| r.onset_time_s.is_some() && !["stable", "unstable_linear"].contains(&e.0));
    match reached {
        Some(&(_, name, label)) => {
            let marker = if interrupted { "i" } else { "f" };
            (legend_color(name), format!("{label} ({marker})"))
        }
        None if interrupted => (Rgb(225, 225, 225), "interrupted".into()),
        None => (legend_color("failed"), "failed".into()),
    }
}

/// The legend of the maps, in this order.
pub const LEGEND: &[(&str, Rgb)] = &[
    ("stable", Rgb(166, 219, 160)),
    ("path 1", Rgb(146, 197, 222)),
    ("path 2a", Rgb(253, 219, 132)),
    ("path 2b", Rgb(244, 165, 130)),
    ("unstable low", Rgb(214, 96, 77)),
    ("lin. unst.", Rgb(203, 180, 227)),
    ("failed", Rgb(190, 190, 190)),
];

/// "C = 15 um" for a flag and its value.
fn labelled(k: &str, v: &str) -> String {
    let (_, short, _, unit) = KEYS.iter().find(|e| e.0 == k).expect("known key");
    let short = if short.is_empty() { k } else { short };
    if unit.is_empty() {
        format!("{short} = {v}")
    } else {
        format!("{short} = {v} {unit}")
    }
}

fn fmt_num(v: f64) -> String {
    if v == v.round() && v.abs() < 1e12 {
        format!("{}", v as i64)
    } else {
        format!("{v}")
    }
}

/// The map panels: runs grouped by every flag except c, d and the numerical settings (in KEYS
/// order), in the order of first appearance; and the flags that make up the key. Cells of one
/// panel may come from runs with different numerics (the table lists them).
fn map_panels(records: &[RunRecord]) -> (Vec<&'static str>, Vec<(Params, Vec<&RunRecord>)>) {
    let panel_keys: Vec<&'static str> = KEYS
        .iter()
        .map(|e| e.0)
        .filter(|k| *k != "c" && *k != "d" && !NUMERICS.contains(k))
        .collect();
    let key_of = |r: &RunRecord| -> Params {
        panel_keys
            .iter()
            .filter_map(|k| r.args.get(*k).map(|v| (k.to_string(), v.clone())))
            .collect()
    };
    let mut panels: Vec<(Params, Vec<&RunRecord>)> = Vec::new();
    for r in records {
        let k = key_of(r);
        match panels.iter_mut().find(|p| p.0 == k) {
            Some(p) => p.1.push(r),
            None => panels.push((k, vec![r])),
        }
    }
    (panel_keys, panels)
}

/// Bifurcation maps as the paper's Fig. 17: one panel per combination of the parameters other than
/// c and d (the (C, dH) cases), c [N/mm] across, d [N s/m] upwards, each cell coloured by the run's
/// class and labelled with the onset speed. Writes `<stem>.svg` and `<stem>.png` into `dir`.
pub fn plot_maps(records: &[RunRecord], dir: &Path, stem: &str) -> std::io::Result<Vec<PathBuf>> {
    let (panel_keys, panels) = map_panels(records);
    // Title: the panel parameters that differ between panels (all of them if only one panel).
    let varying: Vec<String> = panel_keys
        .iter()
        .filter(|k| {
            let vals: Vec<Option<&String>> = panels
                .iter()
                .map(|p| p.0.iter().find(|(a, _)| a == *k).map(|(_, v)| v))
                .collect();
            vals.windows(2).any(|w| w[0] != w[1])
        })
        .map(|k| k.to_string())
        .collect();
    let sorted_unique = |vals: Vec<f64>| -> Vec<f64> {
        let mut v: Vec<f64> = vals.into_iter().filter(|x| x.is_finite()).collect();
        v.sort_by(|a, b| a.total_cmp(b));
        v.dedup();
        v
    };
    let grids: Vec<(Vec<f64>, Vec<f64>)> = panels
        .iter()
        .map(|(_, rs)| {
            (
                sorted_unique(rs.iter().filter_map(|r| r.param("c")).collect()),
                sorted_unique(rs.iter().filter_map(|r| r.param("d")).collect()),
            )
        })
        .collect();
    let max_nc = grids.iter().map(|g| g.0.len()).max().unwrap_or(1).max(1);
    let max_nd = grids.iter().map(|g| g.1.len()).max().unwrap_or(1).max(1);
    let (cell_w, cell_h) = (92.0, 46.0);
    let (ml, mt, mr, mb) = (78.0, 42.0, 18.0, 52.0);
    let pw = (ml + cell_w * max_nc as f64 + mr).max(300.0);
    let ph = mt + cell_h * max_nd as f64 + mb;
    let ncols = panels.len().clamp(1, 3);
    let nrows = panels.len().div_ceil(ncols).max(1);
    let legend_h = 60.0;
    let width = (pw * ncols as f64).max(6.0 * 145.0 + 20.0).ceil() as u32;
    let height = (ph * nrows as f64 + legend_h).ceil() as u32;
    let mut c = Canvas::new(width, height);
    for (pi, ((key, rs), (cs, ds))) in panels.iter().zip(&grids).enumerate() {
        let ox = pw * (pi % ncols) as f64;
        let oy = ph * (pi / ncols) as f64;
        let title: Vec<String> = key
            .iter()
            .filter(|(k, _)| {
                if varying.is_empty() {
                    k == "clearance" || k == "dh"
                } else {
                    varying.contains(k)
                }
            })
            .map(|(k, v)| labelled(k, v))
            .collect();
        let title = if title.is_empty() {
            "all runs".to_string()
        } else {
            title.join(", ")
        };
        let (gx, gy) = (ox + ml, oy + mt);
        let (gw, gh) = (cell_w * cs.len() as f64, cell_h * ds.len() as f64);
        // Centred over the grid, but kept inside the panel when the grid is narrower than the
        // title (the canvas font is ~0.85 em wide per character).
        let half_title = 0.5 * 0.85 * 14.0 * title.chars().count() as f64;
        let tx = (gx + 0.5 * gw).max(ox + half_title + 4.0);
        c.text(tx, oy + 22.0, &title, 14.0, Anchor::Middle);
        for r in rs {
            let (Some(cv), Some(dv)) = (r.param("c"), r.param("d")) else {
                continue;
            };
            let (Some(ic), Some(id)) = (
                cs.iter().position(|x| *x == cv),
                ds.iter().position(|x| *x == dv),
            ) else {
                continue;
            };
            let x = gx + cell_w * ic as f64;
            let y = gy + gh - cell_h * (id + 1) as f64;
            let (fill, label) = cell_style(r);
            c.items.push(Item::Rect {
                x,
                y,
                w: cell_w,
                h: cell_h,
                fill: Some(fill),
                stroke: Some(Rgb::WHITE),
            });
            // "path 1 (f)": the marker goes on the second line (such runs show no onset speed),
            // so the label fits a narrow cell.
            let (class, marker) = label.split_once(" (").unwrap_or((&label, ""));
            c.text(x + 0.5 * cell_w, y + 19.0, class, 12.0, Anchor::Middle);
            if !marker.is_empty() {
                let marker = format!("({marker}");
                c.text(x + 0.5 * cell_w, y + 36.0, &marker, 12.0, Anchor::Middle);
            }
            if let Some(f) = r.onset_speed_hz.filter(|_| r.status == "completed") {
                c.text(
                    x + 0.5 * cell_w,
                    y + 36.0,
                    &format!("{f:.0} Hz"),
                    12.0,
                    Anchor::Middle,
                );
            }
        }
        c.items.push(Item::Rect {
            x: gx,
            y: gy,
            w: gw,
            h: gh,
            fill: None,
            stroke: Some(Rgb::BLACK),
        });
        for (i, cv) in cs.iter().enumerate() {
            let x = gx + cell_w * (i as f64 + 0.5);
            c.text(x, gy + gh + 16.0, &fmt_num(*cv), 12.0, Anchor::Middle);
        }
        for (j, dv) in ds.iter().enumerate() {
            let y = gy + gh - cell_h * (j as f64 + 0.5) + 4.0;
            c.text(gx - 6.0, y, &fmt_num(*dv), 12.0, Anchor::End);
        }
        c.text(
            gx + 0.5 * gw,
            gy + gh + 36.0,
            "c [N/mm]",
            13.0,
            Anchor::Middle,
        );
        c.vtext(gx - 56.0, gy + 0.5 * gh, "d [N s/m]", 13.0);
    }
    let ly = ph * nrows as f64 + 10.0;
    for (i, (name, col)) in LEGEND.iter().enumerate() {
        let x = 10.0 + 145.0 * i as f64;
        c.items.push(Item::Rect {
            x,
            y: ly,
            w: 18.0,
            h: 18.0,
            fill: Some(*col),
            stroke: Some(Rgb::GREY),
        });
        c.text(x + 24.0, ly + 14.0, name, 12.0, Anchor::Start);
    }
    // The flags every run shares, as a footnote.
    let common: Vec<String> = KEYS
        .iter()
        .map(|e| e.0)
        .filter(|k| *k != "c" && *k != "d" && !varying.iter().any(|v| v == k))
        .filter(|k| !(varying.is_empty() && (*k == "clearance" || *k == "dh")))
        .filter_map(|k| {
            let first = records.first()?.args.get(k)?;
            records
                .iter()
                .all(|r| r.args.get(k) == Some(first))
                .then(|| labelled(k, first))
        })
        .collect();
    if !common.is_empty() {
        c.text(10.0, ly + 42.0, &common.join(", "), 12.0, Anchor::Start);
    }
    c.save(dir, stem)
}

/// `airring sweep-merge`: one table and one map from the run folders of several sweep outputs
/// (shards), written into `out`.
pub fn merge(dirs: &[PathBuf], out: &Path) -> Result<(PathBuf, Vec<PathBuf>, usize), String> {
    std::fs::create_dir_all(out).map_err(|e| format!("{}: {e}", out.display()))?;
    let records = collect(dirs);
    if records.is_empty() {
        return Err(format!(
            "no run folders (runs/*/sweep_run.json) in {dirs:?}"
        ));
    }
    let table = out.join("study.csv");
    write_table(&records, &table)?;
    let maps = plot_maps(&records, out, "bifurcation_map").map_err(|e| format!("maps: {e}"))?;
    Ok((table, maps, records.len()))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn failed_runs_keep_the_class_they_reached_after_onset() {
        let rec = |status: &str, class: Option<&str>, onset: Option<f64>| RunRecord {
            name: "r".into(),
            index: 0,
            args: BTreeMap::new(),
            status: status.into(),
            classification: class.map(String::from),
            onset_time_s: onset,
            onset_speed_hz: None,
            max_eps_c: None,
            max_eps_t: None,
            wall_time_s: None,
            settings: serde_json::Value::Null,
        };
        assert_eq!(
            cell_style(&rec("failed", Some("path2b"), Some(1.1))).1,
            "path 2b (f)"
        );
        assert_eq!(cell_style(&rec("failed", Some("stable"), None)).1, "failed");
        assert_eq!(
            cell_style(&rec("completed", Some("path2b"), Some(1.1))).1,
            "path 2b"
        );
        assert_eq!(
            cell_style(&rec("interrupted", Some("path1"), Some(1.1))).1,
            "path 1 (i)"
        );
        assert_eq!(
            cell_style(&rec("interrupted", Some("stable"), None)).1,
            "interrupted"
        );
    }

    #[test]
    fn runs_that_differ_only_in_numerics_share_a_panel() {
        let rec = |c: &str, contact: Option<&str>, clearance: &str| {
            let mut args: BTreeMap<String, String> =
                [("clearance", clearance), ("c", c), ("d", "50")]
                    .into_iter()
                    .map(|(k, v)| (k.to_string(), v.to_string()))
                    .collect();
            if let Some(side) = contact {
                args.insert("contact".into(), side.into());
            }
            RunRecord {
                name: format!("C{clearance}_c{c}"),
                index: 0,
                args,
                status: "completed".into(),
                classification: Some("stable".into()),
                onset_time_s: None,
                onset_speed_hz: None,
                max_eps_c: None,
                max_eps_t: None,
                wall_time_s: None,
                settings: serde_json::Value::Null,
            }
        };
        let records = [
            rec("500", None, "30"),
            rec("1000", Some("rotor"), "30"),
            rec("500", Some("film"), "20"),
        ];
        let (keys, panels) = map_panels(&records);
        assert!(!keys.contains(&"contact"));
        let sizes: Vec<usize> = panels.iter().map(|p| p.1.len()).collect();
        assert_eq!(sizes, [2, 1], "{panels:?}");
    }

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
        assert_eq!(parse_shard("2/3"), Ok((2, 3)));
        assert!(parse_shard("0/3").is_err() && parse_shard("4/3").is_err());
        assert_eq!(
            progress_fraction("t = 0.1 s / 3 s ( 12.5 %) | x"),
            Some(0.125)
        );
    }
}
