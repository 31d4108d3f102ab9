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
//!
//! Modules: `study` (study files, run names, the run-up arguments of a grid point, shards),
//! `table` (the run folders read back, study.csv, merging), `map` (the bifurcation maps); this
//! file runs the run-ups.

pub mod linear;
mod map;
mod report_page;
pub mod sensitivity;
mod study;
mod table;

pub use map::{plot_grid_maps, plot_maps, LEGEND};
pub use study::{
    flatten, is_fmu_key, key_order, parse_shard, plan_json_lines, run_name, runup_args,
    short_and_unit, RunSpec, Study, KEYS,
};
pub use table::{collect, merge, write_table, RunRecord};

use crate::summary::{RunStatus, RunSummary};
use std::collections::BTreeMap;
use std::io::{BufRead, BufReader, IsTerminal, Write as _};
use std::path::{Path, PathBuf};
use std::process::{Child, Command, Stdio};
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Arc, Mutex};
use std::time::{Duration, Instant};

pub struct SweepOptions {
    pub out: PathBuf,
    pub jobs: usize,
    pub shard: Option<(usize, usize)>,
    /// The `airring` executable the run-ups are started with.
    pub exe: PathBuf,
    pub quiet: bool,
    /// Run again completed runs whose settings differ from the study's (else refused).
    pub overwrite: bool,
    /// Pass --serial-films to every run-up (one core each; set when jobs exceed half the cores).
    pub serial_films: bool,
    /// Set by Ctrl-C or SIGTERM: no new run-ups are started; the running ones are told to stop
    /// (`Running::pass_stop_on`) and leave a checkpoint, from which the next sweep resumes them.
    pub stop: Arc<AtomicBool>,
    /// Passed to every run-up as --checkpoint-every [s of simulated time]: bounds what a killed
    /// (not interrupted) run-up loses.
    pub checkpoint_every_s: Option<f64>,
}

/// The folder of linear analyses a sweep into `out` shares among its prediction and run-ups
/// (`crate::linear_cache`).
pub fn linear_cache_dir(out: &Path) -> PathBuf {
    out.join("linear_cache")
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
    /// Runs stopped by an interrupt of the sweep (they resume when the sweep runs again).
    pub interrupted: Vec<String>,
    pub wall_time_s: f64,
    pub table: PathBuf,
    pub maps: Vec<PathBuf>,
}

impl SweepReport {
    /// Counts a finished run by its status: an interrupted one is not a failed one.
    fn tally(&mut self, name: &str, status: RunStatus) {
        match status {
            RunStatus::Completed => {}
            RunStatus::Interrupted => self.interrupted.push(name.to_string()),
            _ => self.failed.push(name.to_string()),
        }
    }
}

pub(super) fn read_json(p: &Path) -> Option<serde_json::Value> {
    serde_json::from_str(&std::fs::read_to_string(p).ok()?).ok()
}

/// The run-up settings a run gets from its preset and the defaults where the study sets nothing
/// (macro step, step control, film tolerances, contact side, disturbance, mesh, the film-mesh
/// rule, ...): recorded in each run's sweep_run.json and each orbit cell's cell.json, so that a
/// run or cell made with other defaults (an older airring) is computed again instead of being
/// mixed into the map with different numerics.
pub fn defaults_of(args: &BTreeMap<String, String>) -> serde_json::Value {
    let preset = args.get("preset").map_or("path1", String::as_str);
    let mut defaults = crate::runup::RunupSettings::preset(preset)
        .ok()
        .and_then(|s| serde_json::to_value(s).ok())
        .unwrap_or_default();
    // The film mesh a run-up chooses by its bearing number is a default too, but no field of the
    // preset's settings: recorded as the rule's choice across its range (mesh and the films'
    // tolerance with it), so that a run made with another rule (e.g. 10 x 3 at 1e-3 / 100 Pa up
    // to bearing number 10, 20 x 3 or 20 x 6 throughout) runs again.
    if let Some(map) = defaults.as_object_mut() {
        let rule: Vec<(u32, u32, f64, [f64; 2])> = FILM_MESH_RULE_SAMPLES
            .iter()
            .map(|&lambda| {
                let m = crate::runup::film_mesh_for(lambda);
                (m.along, m.across, m.grading, m.tolerance)
            })
            .collect();
        map.insert("film_mesh_rule".into(), serde_json::json!(rule));
    }
    defaults
}

/// Bearing numbers at which a sweep records the run-up's film-mesh rule (`defaults_of`): a point
/// in each of its four ranges and its three thresholds (10, 20, 40).
const FILM_MESH_RULE_SAMPLES: [f64; 7] = [5.0, 10.0, 15.0, 20.0, 30.0, 40.0, 60.0];

/// True if the run folder's sweep_run.json has these flags and these defaults (folders from
/// before the defaults were recorded count as the same).
fn same_run(dir: &Path, args: &BTreeMap<String, String>) -> bool {
    read_json(&dir.join("sweep_run.json")).is_some_and(|r| {
        r["args"] == serde_json::to_value(args).unwrap_or_default()
            && r.get("defaults").is_none_or(|d| *d == defaults_of(args))
    })
}

/// True if `dir` holds a completed run with exactly these flags and defaults.
pub fn is_done(dir: &Path, args: &BTreeMap<String, String>) -> bool {
    let done = RunSummary::read(dir).is_some_and(|s| s.status == RunStatus::Completed);
    done && same_run(dir, args)
}

/// Err naming the completed runs in `out` that `runs` would replace: same name, other flags (an
/// edited study file, or another study into the same folder). They took their time and are not
/// thrown away without --overwrite. (Runs made with other run-up defaults, by an older airring,
/// run again without asking: their numerics are not this version's.)
fn refuse_replacing_other_runs(out: &Path, runs: &[&RunSpec]) -> Result<(), String> {
    let other: Vec<&str> = runs
        .iter()
        .filter(|r| {
            let dir = out.join("runs").join(&r.name);
            let done = RunSummary::read(&dir).is_some_and(|s| s.status == RunStatus::Completed);
            let flags = read_json(&dir.join("sweep_run.json")).map(|m| m["args"].clone());
            done && flags.is_some_and(|f| f != serde_json::to_value(&r.args).unwrap_or_default())
        })
        .map(|r| r.name.as_str())
        .collect();
    if other.is_empty() {
        return Ok(());
    }
    let shown = other.iter().take(3).copied().collect::<Vec<_>>().join(", ");
    let more = if other.len() > 3 {
        format!(" and {} more", other.len() - 3)
    } else {
        String::new()
    };
    Err(format!(
        "{}: {} completed run(s) there were made with other flags than this study's and would be \
         replaced: {shown}{more}; choose another --out, or pass --overwrite to run them again",
        out.display(),
        other.len()
    ))
}

/// True if `dir` holds an interrupted run (Ctrl-C, SIGTERM of a batch system's time limit) or a
/// killed one (SIGKILL, out of memory: its summary still says "running", or `ensure_summary`
/// marked it interrupted) with exactly these flags and a checkpoint: `airring resume` continues
/// it from there instead of starting it again from t = 0.
fn is_resumable(dir: &Path, args: &BTreeMap<String, String>) -> bool {
    // "running": killed (SIGKILL, the node lost) with the sweep, before anyone could say so.
    let interrupted = RunSummary::read(dir)
        .is_some_and(|s| matches!(s.status, RunStatus::Interrupted | RunStatus::Running));
    interrupted && same_run(dir, args) && dir.join("checkpoint/master.json").exists()
}

struct Running {
    spec: RunSpec,
    /// The summary a resumed run starts from: if it is still there unchanged when the run
    /// ends, the run wrote none.
    stale_summary: Option<String>,
    child: Child,
    fraction: Arc<Mutex<f64>>,
    reader: Option<std::thread::JoinHandle<()>>,
    /// The sweep's stop was passed on to it (SIGTERM, once).
    stop_sent: bool,
}

impl Running {
    /// Passes the sweep's stop on: SIGTERM, which a run-up answers by stopping at its next macro
    /// step with a checkpoint and its summary (a second one would make it exit at once). A
    /// run-up runs in a process group of its own (`start_run`), so a signal to the sweep alone
    /// (`kill PID`, `timeout`, a batch system's time limit) and Ctrl-C in the terminal reach it
    /// this way, and only this way: it used to share the sweep's group, so Ctrl-C reached it
    /// directly but `kill PID` never did, and it ran on to its end.
    fn pass_stop_on(&mut self) {
        if self.stop_sent {
            return;
        }
        self.stop_sent = true;
        if let Ok(pid) = libc::pid_t::try_from(self.child.id()) {
            // SAFETY: kill(2) with a pid this process spawned and has not reaped (`try_wait`
            // reaps it only after this) and a valid signal number; it touches no memory.
            unsafe {
                libc::kill(pid, libc::SIGTERM);
            }
        }
    }
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
    // A linked run folder is refused: the run would write into (and replace) the link's target.
    cosim::files::real_folder(&dir).map_err(|e| format!("{}: {e}", dir.display()))?;
    let mut cmd = Command::new(&opts.exe);
    let resuming = is_resumable(&dir, &spec.args);
    let mut stale_summary = None;
    if resuming {
        stale_summary = std::fs::read_to_string(dir.join("summary.json")).ok();
        // `resume` reads the run-up settings from the interrupted run's summary.json and writes
        // a new one; a stale one left behind by a crash is replaced (`ensure_summary`).
        cmd.arg("resume").arg(&dir);
    } else {
        // A stale summary must not count as this run's result.
        let _ = std::fs::remove_file(dir.join("summary.json"));
        let meta = serde_json::json!({
            "name": spec.name, "index": spec.index, "args": spec.args,
            "defaults": defaults_of(&spec.args),
        });
        crate::output::write_whole(
            &dir.join("sweep_run.json"),
            serde_json::to_string_pretty(&meta)
                .expect("json")
                .as_bytes(),
        )?;
        cmd.args(runup_args(&spec.args));
        // The sweep owns its run folders: a failed or stale run there is replaced.
        cmd.arg("--overwrite");
        if opts.serial_films {
            cmd.arg("--serial-films");
        }
        cmd.arg("--out").arg(&dir);
        cmd.arg("--linear-cache").arg(linear_cache_dir(&opts.out));
    }
    if let Some(dt) = opts.checkpoint_every_s {
        cmd.arg("--checkpoint-every").arg(dt.to_string());
    }
    cmd.stdin(Stdio::null())
        .stdout(Stdio::null())
        .stderr(Stdio::piped());
    // Its own process group: the sweep passes its stop on (`Running::pass_stop_on`), once.
    std::os::unix::process::CommandExt::process_group(&mut cmd, 0);
    let mut child = cmd
        .spawn()
        .map_err(|e| format!("starting {}: {e}", opts.exe.display()))?;
    let stderr = child.stderr.take().expect("piped");
    let fraction = Arc::new(Mutex::new(0.0));
    let f = fraction.clone();
    let log_path = dir.join("runup.log");
    let reader = std::thread::spawn(move || {
        // A resumed run appends to the log of its first attempt.
        // Never through a link: a resumed run appends to a file of its own, a new one replaces
        // what stands there.
        let mut log = if resuming {
            cosim::files::open_existing_for_writing(&log_path)
                .and_then(|mut f| std::io::Seek::seek(&mut f, std::io::SeekFrom::End(0)).map(|_| f))
                .or_else(|_| cosim::files::create_replacing(&log_path))
        } else {
            cosim::files::create_replacing(&log_path)
        }
        .ok();
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
        stale_summary,
        child,
        fraction,
        reader: Some(reader),
        stop_sent: false,
    })
}

/// Writes a failure summary for a run-up that ended without writing one (crash, bad flags):
/// none is there, or only the `stale` one a resumed run started from. A run-up killed after it
/// started (its summary still says "running") is marked interrupted instead, with its settings
/// kept: the next sweep resumes it from its last checkpoint.
fn ensure_summary(dir: &Path, code: Option<i32>, stale: Option<&str>) {
    let p = dir.join("summary.json");
    let now = std::fs::read_to_string(&p).ok();
    let fresh = now.as_deref().is_some_and(|now| Some(now) != stale);
    let summary = now.and_then(|t| serde_json::from_str::<RunSummary>(&t).ok());
    if let Some(s) = summary.filter(|s| fresh && s.status == RunStatus::Running) {
        let resumable = dir.join("checkpoint/master.json").exists();
        let _ = RunSummary {
            status: RunStatus::Interrupted,
            interrupted: true,
            error: Some(format!(
                "the run-up was killed (exit code {code:?}) before it ended; {}",
                if resumable {
                    "the next sweep resumes it from its last checkpoint"
                } else {
                    "it had written no checkpoint, so the next sweep starts it again"
                }
            )),
            ..s
        }
        .write(dir);
        return;
    }
    if fresh {
        return;
    }
    let exit = code.map_or("no exit code (killed by a signal)".into(), |c| {
        format!("exit code {c}")
    });
    let why =
        last_error_line(&dir.join("runup.log")).map_or(String::new(), |line| format!(": {line}"));
    let _ = RunSummary::failure(format!(
        "the run-up ended with {exit} and wrote no summary{why} (runup.log)"
    ))
    .write(dir);
}

/// The run-up's own error message, its log's last line that starts with "airring: " (prefix
/// removed), for a run that ended before it wrote a summary.
fn last_error_line(log: &Path) -> Option<String> {
    let text = std::fs::read_to_string(log).ok()?;
    text.lines()
        .rev()
        .find_map(|l| l.strip_prefix("airring: "))
        .map(|l| l.trim().to_string())
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
    let mine: Vec<&RunSpec> = study
        .runs
        .iter()
        .filter(|r| opts.shard.is_none_or(|(k, n)| r.index % n == k - 1))
        .collect();
    if !opts.overwrite {
        refuse_replacing_other_runs(&opts.out, &mine)?;
    }
    let runs = opts.out.join("runs");
    std::fs::create_dir_all(&opts.out).map_err(|e| format!("{}: {e}", opts.out.display()))?;
    cosim::files::real_folder(&runs).map_err(|e| format!("{}: {e}", runs.display()))?;
    crate::output::write_whole(&opts.out.join("study.toml"), study_text.as_bytes())?;
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
        if opts.stop.load(Ordering::Relaxed) {
            running.iter_mut().for_each(Running::pass_stop_on);
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
                    ensure_summary(&dir, status.code(), r.stale_summary.as_deref());
                    let s = RunSummary::read(&dir).unwrap_or_default();
                    let st = s.status.as_str();
                    report.tally(&r.spec.name, s.status);
                    report.ran += 1;
                    finished += 1;
                    changed = true;
                    if !opts.quiet {
                        let mut line = format!(
                            "[{finished}/{n_todo}] {}: {st}, {}, onset {} Hz, {} s",
                            r.spec.name,
                            s.classification.as_deref().unwrap_or("-"),
                            s.onset_speed_hz.map_or("-".into(), |v| format!("{v:.0}")),
                            s.wall_time_s.map_or("-".into(), |v| format!("{v:.0}"))
                        );
                        if let Some(e) = s
                            .error
                            .as_deref()
                            .filter(|_| s.status != RunStatus::Completed)
                        {
                            line += &format!(" ({e})");
                        }
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
    report.maps.extend(
        plot_grid_maps(&records, study, &opts.out, &map).map_err(|e| format!("maps: {e}"))?,
    );
    let page = report_page::write_sweep_report(
        &opts.out,
        &study.name,
        &report.table,
        &report.maps,
        &records,
    );
    if let Err(e) = page {
        eprintln!("warning: report.html: {e}");
    }
    if opts.stop.load(Ordering::Relaxed) {
        eprintln!("sweep interrupted: run the same command again to continue");
    }
    Ok(report)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn progress_is_read_from_the_run_up_line() {
        assert_eq!(
            progress_fraction("t = 0.1 s / 3 s ( 12.5 %) | x"),
            Some(0.125)
        );
        assert_eq!(progress_fraction("no progress here"), None);
    }

    #[test]
    fn runs_stopped_by_an_interrupt_are_not_counted_as_failed() {
        let mut r = SweepReport::default();
        r.tally("a", RunStatus::Completed);
        r.tally("b", RunStatus::Interrupted);
        r.tally("c", RunStatus::Failed);
        assert_eq!(
            (r.interrupted, r.failed),
            (vec!["b".to_string()], vec!["c".to_string()])
        );
    }

    #[test]
    fn a_run_that_writes_no_summary_is_recorded_as_failed() {
        let dir = std::env::temp_dir().join(format!("airring-ensure-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        std::fs::create_dir_all(&dir).unwrap();
        let status = || read_json(&dir.join("summary.json")).unwrap()["status"].clone();
        let error = || read_json(&dir.join("summary.json")).unwrap()["error"].clone();
        // None written: a failure summary naming the exit code, and the run-up's own error
        // where its log has one (the last "airring: " line).
        ensure_summary(&dir, Some(3), None);
        assert_eq!(status(), "failed");
        assert_eq!(
            error(),
            "the run-up ended with exit code 3 and wrote no summary (runup.log)"
        );
        std::fs::write(
            dir.join("runup.log"),
            "airring: an earlier line\nprogress\nairring: no rotor.fmu in /x\n\n",
        )
        .unwrap();
        std::fs::remove_file(dir.join("summary.json")).unwrap();
        ensure_summary(&dir, None, None);
        assert_eq!(
            error(),
            "the run-up ended with no exit code (killed by a signal) and wrote no summary: no \
             rotor.fmu in /x (runup.log)"
        );
        // A resumed run that left the interrupted summary as it was: failed too.
        let stale = r#"{"status": "interrupted"}"#;
        std::fs::write(dir.join("summary.json"), stale).unwrap();
        ensure_summary(&dir, None, Some(stale));
        assert_eq!(status(), "failed");
        // One that wrote its own is left alone.
        std::fs::write(dir.join("summary.json"), r#"{"status": "completed"}"#).unwrap();
        ensure_summary(&dir, Some(0), Some(stale));
        assert_eq!(status(), "completed");
        let _ = std::fs::remove_dir_all(&dir);
    }
}
