//! A run's output folder: who may write into it, and what a run that starts there replaces.
//!
//! A new run into a folder that holds a run refuses unless `--overwrite` is given; a run that is
//! refused or fails to start (bad flags, an FMU that rejects a parameter, too little memory)
//! leaves the folder as it was: the system file waits outside it until the FMUs are set up, and
//! [`StartGuard`], the first observer of every run, replaces the old outputs only once the run
//! has started.

use crate::summary::RunSummary;
use cosim::observer::{Observer, ObserverError, RunStart};
use std::path::{Path, PathBuf};

/// Why an output folder is refused; the text says what to do instead.
#[derive(Clone, Debug, PartialEq)]
pub enum FolderError {
    /// The path exists and is not a folder.
    NotAFolder { path: PathBuf },
    /// A sweep would write into a run's folder.
    HoldsRun { path: PathBuf },
    /// A run would write into a sweep's folder.
    HoldsSweep { path: PathBuf },
    /// A run is there already (and no --overwrite): its summary's status ("no summary" without
    /// one), and whether it can be resumed (it did not complete and left a checkpoint).
    RunExists {
        path: PathBuf,
        status: String,
        resumable: bool,
    },
    /// A live process holds the run lock (pid and host as the lock names them; an empty lock
    /// still being written names neither).
    InProgress {
        path: PathBuf,
        pid: Option<i32>,
        host: String,
        lock: PathBuf,
    },
    /// Two processes took turns at the lock and neither got it.
    LockContended { lock: PathBuf },
    /// The folder or the lock could not be created or written.
    Io { path: PathBuf, message: String },
}

impl std::fmt::Display for FolderError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            FolderError::NotAFolder { path } => {
                write!(f, "{}: exists and is not a folder", path.display())
            }
            FolderError::HoldsRun { path } => write!(
                f,
                "{} holds a run (its system.toml, summary.json, ...): a sweep writes its table \
                 and report into a folder of its own; choose another --out",
                path.display()
            ),
            FolderError::HoldsSweep { path } => write!(
                f,
                "{} holds a sweep (study.toml, study.csv): a run writes into a folder of its \
                 own; choose another --out",
                path.display()
            ),
            FolderError::RunExists {
                path,
                status,
                resumable,
            } => {
                let resume = if *resumable {
                    format!(", resume it with `airring resume {}`", path.display())
                } else {
                    String::new()
                };
                write!(
                    f,
                    "{} holds a run already ({status}); choose another --out{resume}, or pass \
                     --overwrite to replace it",
                    path.display()
                )
            }
            FolderError::InProgress {
                path,
                pid,
                host,
                lock,
            } => write!(
                f,
                "{}: a run is in progress here (process {} on {}); wait for it to end or stop it \
                 first (if that process is gone, remove {})",
                path.display(),
                pid.map_or("?".into(), |p| p.to_string()),
                if host.is_empty() { "?" } else { host },
                lock.display()
            ),
            FolderError::LockContended { lock } => write!(
                f,
                "{}: could not take the run lock (another run starting at the same time?)",
                lock.display()
            ),
            FolderError::Io { path, message } => write!(f, "{}: {message}", path.display()),
        }
    }
}

impl std::error::Error for FolderError {}

/// The commands report errors as text.
impl From<FolderError> for String {
    fn from(e: FolderError) -> Self {
        e.to_string()
    }
}

/// Files whose presence marks a folder as a run folder.
const RUN_FILES: &[&str] = &[
    "system.toml",
    "summary.json",
    "timeseries.csv",
    "checkpoint",
];

/// Outputs of a finished run that a new run in the same folder would not rewrite (the series
/// and the system file are rewritten anyway; the checkpoint is removed by the library).
const STALE_FILES: &[&str] = &["summary.json", "timeseries.parquet", "report.html"];

/// True if `dir` holds (part of) a run.
pub fn holds_run(dir: &Path) -> bool {
    RUN_FILES.iter().any(|f| dir.join(f).exists())
}

/// Files whose presence marks a folder as a sweep's (its study and table; the runs are below).
const SWEEP_FILES: &[&str] = &["study.toml", "study.csv"];

/// True if `dir` holds a sweep's outputs.
pub fn holds_sweep(dir: &Path) -> bool {
    SWEEP_FILES.iter().any(|f| dir.join(f).exists())
}

/// Checks that a sweep (or a merge of sweeps) may write its table, maps and report into `dir`:
/// not a run's folder, whose report.html and maps it would replace.
pub fn check_sweep_out(dir: &Path) -> Result<(), FolderError> {
    if dir.exists() && !dir.is_dir() {
        return Err(FolderError::NotAFolder { path: dir.into() });
    }
    if holds_run(dir) {
        return Err(FolderError::HoldsRun { path: dir.into() });
    }
    Ok(())
}

/// Checks that a new run may write into `dir`: it is new, empty of runs, or `overwrite` is set;
/// never a sweep's folder (its report would be replaced, its runs are in `runs/`).
pub fn check_new_run(dir: &Path, overwrite: bool) -> Result<(), FolderError> {
    if dir.exists() && !dir.is_dir() {
        return Err(FolderError::NotAFolder { path: dir.into() });
    }
    if holds_sweep(dir) {
        return Err(FolderError::HoldsSweep { path: dir.into() });
    }
    if overwrite || !holds_run(dir) {
        return Ok(());
    }
    let summary = RunSummary::read(dir);
    let status = summary.as_ref().map_or_else(
        || "no summary".to_string(),
        |s| format!("status {}", s.status.as_str()),
    );
    // Resuming is offered only where there is something to resume: a checkpoint of a run that
    // did not complete.
    let completed = summary.is_some_and(|s| s.status == crate::summary::RunStatus::Completed);
    Err(FolderError::RunExists {
        path: dir.into(),
        status,
        resumable: !completed && dir.join("checkpoint").exists(),
    })
}

/// The file that marks a folder a run is writing into (see [`RunLock`]).
pub const LOCK_FILE: &str = "run.lock";

/// A run folder held by the process running in it: `run.lock` names the process and its host
/// while the run goes on and is removed when the run ends (dropped). A second run, resume or
/// `--overwrite` into the folder is refused meanwhile: two processes writing one folder leave a
/// summary that belongs to neither. A lock left by a process that is gone (killed) is taken over;
/// one from another host (a cluster's shared file system) cannot be checked and is respected.
pub struct RunLock {
    path: PathBuf,
}

impl RunLock {
    /// Creates `dir` if needed and takes its lock.
    pub fn acquire(dir: &Path) -> Result<RunLock, FolderError> {
        let io = |path: &Path, e: std::io::Error| FolderError::Io {
            path: path.into(),
            message: e.to_string(),
        };
        std::fs::create_dir_all(dir).map_err(|e| io(dir, e))?;
        let path = dir.join(LOCK_FILE);
        let me = format!("{} {}\n", std::process::id(), host_name());
        for _ in 0..2 {
            match std::fs::OpenOptions::new()
                .write(true)
                .create_new(true)
                .open(&path)
            {
                Ok(mut f) => {
                    use std::io::Write;
                    f.write_all(me.as_bytes()).map_err(|e| io(&path, e))?;
                    return Ok(RunLock { path });
                }
                Err(e) if e.kind() == std::io::ErrorKind::AlreadyExists => {
                    if let Some(held) = live_holder(&path) {
                        return Err(held.refusal(dir, &path));
                    }
                    // Left by a run that was killed: taken over.
                    let _ = std::fs::remove_file(&path);
                }
                Err(e) => return Err(io(&path, e)),
            }
        }
        Err(FolderError::LockContended { lock: path })
    }
}

impl Drop for RunLock {
    fn drop(&mut self) {
        let _ = std::fs::remove_file(&self.path);
    }
}

/// The process that holds a run lock.
struct Holder {
    pid: Option<i32>,
    host: String,
}

impl Holder {
    fn refusal(&self, dir: &Path, lock: &Path) -> FolderError {
        FolderError::InProgress {
            path: dir.into(),
            pid: self.pid,
            host: self.host.clone(),
            lock: lock.into(),
        }
    }
}

/// The live process holding the lock file `path`, if any: one on this host that still runs,
/// one on another host (a cluster's shared file system: it cannot be checked from here), or a
/// lock still being written (empty and young). None: no lock, or one a killed run left.
fn live_holder(path: &Path) -> Option<Holder> {
    if std::fs::symlink_metadata(path).is_err() {
        return None;
    }
    let held = std::fs::read_to_string(path).unwrap_or_default();
    let mut words = held.split_whitespace();
    let pid = words.next().and_then(|p| p.parse::<i32>().ok());
    let host = words.next().unwrap_or("").to_string();
    let alive = match pid {
        Some(pid) if host == host_name() => process_alive(pid),
        Some(_) => true,
        // Empty or unreadable: a lock still being written (respected while it is young), or one
        // a crash cut short.
        None => path
            .symlink_metadata()
            .and_then(|m| m.modified())
            .ok()
            .and_then(|t| t.elapsed().ok())
            .is_none_or(|age| age < std::time::Duration::from_secs(10)),
    };
    alive.then_some(Holder { pid, host })
}

/// Refuses `dir` while a live process holds its run lock (checked before anything else is said
/// of the folder: a run without a checkpoint that is still going is not a killed one).
pub fn check_not_in_progress(dir: &Path) -> Result<(), FolderError> {
    let path = dir.join(LOCK_FILE);
    match live_holder(&path) {
        Some(h) => Err(h.refusal(dir, &path)),
        None => Ok(()),
    }
}

/// This machine's name ("?" where it cannot be read).
fn host_name() -> String {
    let mut buf = [0u8; 256];
    // SAFETY: the buffer is valid for its length; gethostname writes at most that many bytes.
    let rc = unsafe { libc::gethostname(buf.as_mut_ptr().cast(), buf.len()) };
    if rc != 0 {
        return "?".into();
    }
    let end = buf.iter().position(|&b| b == 0).unwrap_or(buf.len());
    String::from_utf8_lossy(&buf[..end]).into_owned()
}

/// Does process `pid` exist on this machine? (Signal 0 checks without sending anything; EPERM
/// means it exists under another user.)
fn process_alive(pid: i32) -> bool {
    if pid <= 0 {
        return false;
    }
    // SAFETY: kill with signal 0 sends nothing; it only checks the process exists.
    let rc = unsafe { libc::kill(pid, 0) };
    rc == 0 || std::io::Error::last_os_error().raw_os_error() == Some(libc::EPERM)
}

/// A system file generated for a run, kept outside the run folder until the run has started
/// (removed when dropped).
pub struct StagedSystem {
    pub path: PathBuf,
}

/// Prefix of the staged system files' names in the temporary folder.
const STAGED_PREFIX: &str = "airring-system-";

impl StagedSystem {
    /// Writes `text` to a fresh temporary file (and removes those that killed runs left behind).
    pub fn new(text: &str) -> Result<Self, String> {
        let tmp = std::env::temp_dir();
        remove_orphans(&tmp);
        let nanos = std::time::SystemTime::now()
            .duration_since(std::time::UNIX_EPOCH)
            .map_or(0, |d| d.as_nanos());
        let path = tmp.join(format!(
            "{STAGED_PREFIX}{}-{nanos}.toml",
            std::process::id()
        ));
        // Created exclusively: the temporary folder is shared, and a link planted under this
        // name must not be written through.
        std::fs::OpenOptions::new()
            .write(true)
            .create_new(true)
            .open(&path)
            .and_then(|mut f| std::io::Write::write_all(&mut f, text.as_bytes()))
            .map_err(|e| format!("{}: {e}", path.display()))?;
        Ok(StagedSystem { path })
    }
}

impl StagedSystem {
    /// `error` without the staged file's "PATH:LINE: " prefix: the file is gone once the run
    /// has failed (it is the run-up's own, generated from its flags), so the prefix would name
    /// a file the user cannot open; what the error says of the parameter or FMU stays.
    pub fn strip_path(&self, error: String) -> String {
        let prefix = format!("{}:", self.path.display());
        let Some(rest) = error.strip_prefix(&prefix) else {
            return error;
        };
        let after_line = rest.trim_start_matches(|c: char| c.is_ascii_digit());
        match after_line.strip_prefix(": ") {
            Some(tail) if after_line.len() < rest.len() => tail.to_string(),
            _ => rest.trim_start().to_string(),
        }
    }
}

/// Removes the staged system files in `tmp` whose process is gone: a run killed before its
/// run folder took the file (SIGKILL, a batch system's time limit) cannot drop it. Only where
/// processes are visible in /proc (Linux); a file of a live process, or one whose name does not
/// parse, is left alone.
fn remove_orphans(tmp: &Path) {
    let proc = Path::new("/proc");
    if !proc.join("self").exists() {
        return;
    }
    let Ok(entries) = std::fs::read_dir(tmp) else {
        return;
    };
    for entry in entries.flatten() {
        let name = entry.file_name();
        let Some(pid) = name
            .to_str()
            .filter(|n| n.ends_with(".toml"))
            .and_then(|n| n.strip_prefix(STAGED_PREFIX))
            .and_then(|rest| rest.split_once('-'))
            .and_then(|(pid, _)| pid.parse::<u32>().ok())
        else {
            continue;
        };
        if !proc.join(pid.to_string()).exists() {
            let _ = std::fs::remove_file(entry.path());
        }
    }
}

impl Drop for StagedSystem {
    fn drop(&mut self) {
        let _ = std::fs::remove_file(&self.path);
    }
}

/// Bytes of memory this process may still use: the machine's MemAvailable, or less if a
/// cgroup (a batch job's limit) allows less; None if the system says neither.
fn available_memory_bytes() -> Option<f64> {
    let meminfo = std::fs::read_to_string("/proc/meminfo")
        .ok()
        .and_then(|text| {
            let line = text.lines().find(|l| l.starts_with("MemAvailable:"))?;
            let kib: f64 = line.split_whitespace().nth(1)?.parse().ok()?;
            Some(kib * 1024.0)
        });
    let read = |f: &str| -> Option<f64> {
        std::fs::read_to_string(Path::new("/sys/fs/cgroup").join(f))
            .ok()?
            .trim()
            .parse()
            .ok()
    };
    // cgroup v2 at the root of the process's namespace ("max" does not parse: no limit).
    let cgroup = read("memory.max").map(|max| max - read("memory.current").unwrap_or(0.0));
    match (meminfo, cgroup) {
        (Some(a), Some(b)) => Some(a.min(b)),
        (a, b) => a.or(b),
    }
}

/// The memory the samples of a run may take [bytes]: `AIRRING_MEMORY_LIMIT` (bytes) if set,
/// else half of what the process may still use.
fn samples_memory_limit() -> Option<f64> {
    match std::env::var("AIRRING_MEMORY_LIMIT") {
        Ok(v) => v.trim().parse().ok(),
        Err(_) => available_memory_bytes().map(|a| 0.5 * a),
    }
}

/// Memory the run's output samples take when kept for the analysis and Parquet [bytes].
pub fn samples_bytes(stop_time_s: f64, output_interval_s: f64, columns: usize) -> f64 {
    let rows = (stop_time_s / output_interval_s).floor() + 2.0;
    // Time and the values as f64, plus a Vec header per row.
    rows * ((columns + 1) as f64 * 8.0 + 24.0)
}

/// The first observer of every run: refuses a run whose samples would not fit in memory, then
/// (only then) replaces the folder's stale outputs and marks the run as running.
pub struct StartGuard {
    pub dir: PathBuf,
    /// The settings summary.json records (kept while the run is running and after a kill).
    pub settings: serde_json::Value,
    /// Memory the samples may take [bytes] (None: `AIRRING_MEMORY_LIMIT`, else half of what the
    /// process may still use).
    pub memory_limit_bytes: Option<f64>,
}

impl Observer for StartGuard {
    fn started(&mut self, run: &RunStart<'_>) -> Result<(), ObserverError> {
        let need = samples_bytes(run.stop_time_s, run.output_interval_s, run.columns.len());
        let limit = self.memory_limit_bytes.or_else(samples_memory_limit);
        if let Some(limit) = limit {
            if need > limit {
                return Err(ObserverError::Refused(format!(
                    "the run would keep {:.1} GB of output samples in memory ({:.3e} rows of {} \
                     values), more than the {:.1} GB it may use: choose a longer output interval \
                     or a shorter stop time",
                    need / 1e9,
                    run.stop_time_s / run.output_interval_s,
                    run.columns.len() + 1,
                    limit / 1e9
                )));
            }
        }
        Ok(())
    }

    /// Only once every observer has accepted the run (a refused resume leaves the folder byte
    /// for byte as it was): the old outputs go and the summary says "running".
    fn begun(&mut self, run: &RunStart<'_>) -> Result<(), ObserverError> {
        if run.resumed_from.is_none() {
            // The figures of the run this one replaces, as its summary lists them.
            let old_plots = RunSummary::read(&self.dir)
                .and_then(|s| s.plots)
                .unwrap_or_default();
            for f in STALE_FILES
                .iter()
                .map(|f| f.to_string())
                .chain(old_plots.into_iter().filter(|p| is_plain_file_name(p)))
            {
                // Only files: whatever else stands under such a name is not an old output.
                let path = self.dir.join(&f);
                if path.is_file() {
                    std::fs::remove_file(&path).map_err(|e| ObserverError::io(&path, e))?;
                }
            }
        }
        RunSummary::running(self.settings.clone())
            .write(&self.dir)
            .map_err(ObserverError::Other)
    }
}

/// A file name without folders (what a summary may ask to remove).
fn is_plain_file_name(name: &str) -> bool {
    !name.is_empty() && name != "." && name != ".." && !name.contains('/') && !name.contains('\\')
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A run does not write into a sweep's folder, nor a sweep into a run's (each replaced the
    /// other's report.html).
    #[test]
    fn runs_and_sweeps_keep_to_their_own_folders() {
        let dir = std::env::temp_dir().join(format!("airring-kinds-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        std::fs::create_dir_all(&dir).unwrap();
        assert!(check_new_run(&dir, false).is_ok() && check_sweep_out(&dir).is_ok());
        std::fs::write(dir.join("study.csv"), "").unwrap();
        for overwrite in [false, true] {
            let e = check_new_run(&dir, overwrite).unwrap_err();
            assert_eq!(e, FolderError::HoldsSweep { path: dir.clone() });
        }
        assert!(
            check_sweep_out(&dir).is_ok(),
            "a sweep runs again in its folder"
        );
        std::fs::remove_file(dir.join("study.csv")).unwrap();
        std::fs::write(dir.join("summary.json"), "{}").unwrap();
        let e = check_sweep_out(&dir).unwrap_err();
        assert_eq!(e, FolderError::HoldsRun { path: dir.clone() });
        // Resuming is offered for a run that did not complete and left a checkpoint, only.
        let mut s = RunSummary {
            status: crate::summary::RunStatus::Completed,
            ..Default::default()
        };
        s.write(&dir).unwrap();
        std::fs::create_dir_all(dir.join("checkpoint")).unwrap();
        let exists = |status: &str, resumable| FolderError::RunExists {
            path: dir.clone(),
            status: status.into(),
            resumable,
        };
        assert_eq!(
            check_new_run(&dir, false).unwrap_err(),
            exists("status completed", false)
        );
        s.status = crate::summary::RunStatus::Interrupted;
        s.write(&dir).unwrap();
        assert_eq!(
            check_new_run(&dir, false).unwrap_err(),
            exists("status interrupted", true)
        );
        std::fs::remove_dir_all(dir.join("checkpoint")).unwrap();
        assert_eq!(
            check_new_run(&dir, false).unwrap_err(),
            exists("status interrupted", false)
        );
        let _ = std::fs::remove_dir_all(&dir);
    }

    /// One process per run folder: a second lock is refused while the first is held, a lock
    /// left by a process that is gone is taken over, one from another host is respected.
    #[test]
    fn a_run_folder_is_held_by_one_process_at_a_time() {
        let dir = std::env::temp_dir().join(format!("airring-lock-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        let lock = RunLock::acquire(&dir).unwrap();
        let held = std::fs::read_to_string(dir.join(LOCK_FILE)).unwrap();
        assert_eq!(held, format!("{} {}\n", std::process::id(), host_name()));
        let held_by = |pid: Option<i32>, host: &str| FolderError::InProgress {
            path: dir.clone(),
            pid,
            host: host.into(),
            lock: dir.join(LOCK_FILE),
        };
        assert_eq!(
            RunLock::acquire(&dir).err().unwrap(),
            held_by(Some(std::process::id() as i32), &host_name())
        );
        drop(lock);
        assert!(!dir.join(LOCK_FILE).exists(), "removed when the run ends");
        // A finished child's process id: nothing runs under it now.
        let mut child = std::process::Command::new("true").spawn().unwrap();
        let gone = child.id();
        child.wait().unwrap();
        std::fs::write(dir.join(LOCK_FILE), format!("{gone} {}\n", host_name())).unwrap();
        let lock = RunLock::acquire(&dir).expect("a killed run's lock is taken over");
        drop(lock);
        std::fs::write(dir.join(LOCK_FILE), format!("{gone} another-host\n")).unwrap();
        assert_eq!(
            RunLock::acquire(&dir).err().unwrap(),
            held_by(Some(gone as i32), "another-host")
        );
        // An empty lock is one being written: respected while it is young.
        std::fs::write(dir.join(LOCK_FILE), "").unwrap();
        assert_eq!(RunLock::acquire(&dir).err().unwrap(), held_by(None, ""));
        let _ = std::fs::remove_dir_all(&dir);
    }

    /// The texts the commands print for each refusal, word for word.
    #[test]
    fn each_folder_refusal_reads_as_before() {
        let path = PathBuf::from("runs/x");
        let lock = path.join(LOCK_FILE);
        let text = |e: FolderError| e.to_string();
        assert_eq!(
            text(FolderError::NotAFolder { path: path.clone() }),
            "runs/x: exists and is not a folder"
        );
        assert_eq!(
            text(FolderError::HoldsRun { path: path.clone() }),
            "runs/x holds a run (its system.toml, summary.json, ...): a sweep writes its table \
             and report into a folder of its own; choose another --out"
        );
        assert_eq!(
            text(FolderError::HoldsSweep { path: path.clone() }),
            "runs/x holds a sweep (study.toml, study.csv): a run writes into a folder of its \
             own; choose another --out"
        );
        assert_eq!(
            text(FolderError::RunExists {
                path: path.clone(),
                status: "status interrupted".into(),
                resumable: true
            }),
            "runs/x holds a run already (status interrupted); choose another --out, resume it \
             with `airring resume runs/x`, or pass --overwrite to replace it"
        );
        assert_eq!(
            text(FolderError::InProgress {
                path: path.clone(),
                pid: Some(42),
                host: "node7".into(),
                lock: lock.clone()
            }),
            "runs/x: a run is in progress here (process 42 on node7); wait for it to end or \
             stop it first (if that process is gone, remove runs/x/run.lock)"
        );
        assert_eq!(
            text(FolderError::InProgress {
                path,
                pid: None,
                host: String::new(),
                lock: lock.clone()
            }),
            "runs/x: a run is in progress here (process ? on ?); wait for it to end or stop it \
             first (if that process is gone, remove runs/x/run.lock)"
        );
        assert_eq!(
            text(FolderError::LockContended { lock }),
            "runs/x/run.lock: could not take the run lock (another run starting at the same \
             time?)"
        );
    }

    /// A run-up's error names what went wrong, not the generated file that is gone.
    #[test]
    fn a_staged_system_files_path_is_left_out_of_errors() {
        let staged = StagedSystem {
            path: PathBuf::from("/tmp/airring-system-1-2.toml"),
        };
        let e = "/tmp/airring-system-1-2.toml:4: fmu.path: /x/rotor.fmu: not a valid FMU archive";
        assert_eq!(
            staged.strip_path(e.into()),
            "fmu.path: /x/rotor.fmu: not a valid FMU archive"
        );
        let e = "/tmp/airring-system-1-2.toml: no such file";
        assert_eq!(staged.strip_path(e.into()), "no such file");
        let e = "rotor: invalid parameter c_C";
        assert_eq!(staged.strip_path(e.into()), e);
    }

    #[test]
    fn only_folder_free_names_are_plain() {
        assert!(is_plain_file_name("orbit_C.svg"));
        for bad in ["", ".", "..", "../x.svg", "a/b", "a\\b"] {
            assert!(!is_plain_file_name(bad), "{bad}");
        }
    }

    /// A staged file whose process is gone is removed; one of a live process, another tool's
    /// file and a name that does not parse stay.
    #[test]
    fn orphaned_staged_system_files_are_removed() {
        if !Path::new("/proc/self").exists() {
            return; // processes are not visible: nothing is removed (checked on Linux CI)
        }
        let dir = std::env::temp_dir().join(format!("airring-orphans-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        std::fs::create_dir_all(&dir).unwrap();
        // Above Linux's largest pid (2^22): no such process.
        let dead = format!("{STAGED_PREFIX}4294967-1.toml");
        let live = format!("{STAGED_PREFIX}{}-2.toml", std::process::id());
        let keep = [
            live.as_str(),
            "other-system-4294967-1.toml",
            "airring-system-x-1.toml",
            "airring-system-4294967-1.txt",
        ];
        for f in keep.iter().chain([&dead.as_str()]) {
            std::fs::write(dir.join(f), "x").unwrap();
        }
        remove_orphans(&dir);
        assert!(!dir.join(&dead).exists(), "{dead} left behind");
        for f in keep {
            assert!(dir.join(f).exists(), "{f} removed");
        }
        std::fs::remove_dir_all(&dir).unwrap();
    }

    #[test]
    fn samples_of_a_default_runup_are_a_few_megabytes() {
        // path 1: 3 s at 100 us, 15 columns.
        let b = samples_bytes(3.0, 100e-6, 15);
        assert!((4e6..6e6).contains(&b), "{b}");
    }
}
