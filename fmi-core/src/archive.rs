//! Unpacking `.fmu` archives (either standard: the same zip layout) into fresh temporary folders,
//! and the importers' load error.

use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicU64, Ordering};

#[derive(Debug)]
pub struct ImportError(pub String);

impl std::fmt::Display for ImportError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(&self.0)
    }
}

impl std::error::Error for ImportError {}

/// An FMU's folder: `path` itself when it is an unpacked FMU, else a fresh temporary folder the
/// archive is unpacked into (removed when the guard is dropped). Shared by both importers.
pub fn unpack_unless_folder(path: &Path) -> Result<(Option<UnpackedDir>, PathBuf), ImportError> {
    let unpacked = if path.is_dir() {
        None
    } else {
        Some(unpack(path)?)
    };
    let dir = folder_of(path, unpacked.as_ref());
    Ok((unpacked, dir))
}

/// The folder an FMU lives in: its unpacked copy, or `path` itself.
pub fn folder_of(path: &Path, unpacked: Option<&UnpackedDir>) -> PathBuf {
    unpacked.map_or_else(|| path.to_path_buf(), |u| u.path().to_path_buf())
}

static COUNTER: AtomicU64 = AtomicU64::new(0);

/// A folder an FMU archive was unpacked into: removed when dropped, on every path (a load that
/// fails half-way, a panic, or the end of the `Fmu` that owns it).
#[derive(Debug)]
pub struct UnpackedDir(PathBuf);

impl UnpackedDir {
    pub fn path(&self) -> &Path {
        &self.0
    }
}

impl Drop for UnpackedDir {
    fn drop(&mut self) {
        let _ = std::fs::remove_dir_all(&self.0);
    }
}

/// Unpacks the archive into a new folder under the system temp dir and returns it. Entries that would
/// escape the folder (`..`, absolute paths) are refused.
pub fn unpack(fmu: &Path) -> Result<UnpackedDir, ImportError> {
    let err = |e: &dyn std::fmt::Display| ImportError(format!("{}: {e}", fmu.display()));
    let file = std::fs::File::open(fmu).map_err(|e| err(&e))?;
    let mut zip =
        zip::ZipArchive::new(file).map_err(|e| err(&format!("not a valid FMU archive: {e}")))?;
    remove_stale_folders_once();
    let n = COUNTER.fetch_add(1, Ordering::Relaxed);
    let stem = fmu.file_stem().and_then(|s| s.to_str()).unwrap_or("fmu");
    let dir = std::env::temp_dir().join(format!("airring-{stem}-{}-{n}", std::process::id()));
    if dir.exists() {
        std::fs::remove_dir_all(&dir).map_err(|e| err(&e))?;
    }
    // From here on the guard removes the folder unless it is handed out whole.
    let guard = UnpackedDir(dir);
    extract(&mut zip, &guard.0, &err)?;
    Ok(guard)
}

/// Removes, once per process, the folders that processes which no longer exist unpacked (a run
/// killed outright, SIGKILL or out of memory, never runs `UnpackedDir::drop`): without this, each
/// such kill leaves ~6 MB per FMU in the temp dir, for good, on shared cluster nodes too.
fn remove_stale_folders_once() {
    static ONCE: std::sync::Once = std::sync::Once::new();
    ONCE.call_once(|| remove_stale_folders(&std::env::temp_dir()));
}

fn remove_stale_folders(temp_dir: &Path) {
    let Ok(entries) = std::fs::read_dir(temp_dir) else {
        return;
    };
    for entry in entries.flatten() {
        let path = entry.path();
        let name = entry.file_name();
        if let Some(pid) = name.to_str().and_then(unpacked_folder_pid) {
            if !process_alive(pid) && path.join("modelDescription.xml").is_file() {
                let _ = std::fs::remove_dir_all(&path);
            }
        }
    }
}

/// The process id in a folder name `unpack` makes (`airring-{stem}-{pid}-{n}`), else None.
fn unpacked_folder_pid(name: &str) -> Option<u32> {
    let rest = name.strip_prefix("airring-")?;
    let mut parts = rest.rsplitn(3, '-');
    let n = parts.next()?;
    let pid = parts.next()?;
    let stem = parts.next()?;
    if stem.is_empty() || n.is_empty() || !n.bytes().all(|b| b.is_ascii_digit()) {
        return None;
    }
    pid.parse().ok()
}

/// Whether a process with this id exists. Only Linux (/proc) can tell here; elsewhere every
/// process counts as alive, so nothing is removed.
fn process_alive(pid: u32) -> bool {
    if cfg!(target_os = "linux") && Path::new("/proc/self").exists() {
        Path::new(&format!("/proc/{pid}")).exists()
    } else {
        true
    }
}

/// Writes every entry of `zip` below `dir`, refusing paths that leave it.
fn extract(
    zip: &mut zip::ZipArchive<std::fs::File>,
    dir: &Path,
    err: &dyn Fn(&dyn std::fmt::Display) -> ImportError,
) -> Result<(), ImportError> {
    for i in 0..zip.len() {
        let mut entry = zip.by_index(i).map_err(|e| err(&e))?;
        let rel = entry
            .enclosed_name()
            .ok_or_else(|| err(&format!("unsafe path in archive: {}", entry.name())))?;
        let out = dir.join(rel);
        if entry.is_dir() {
            std::fs::create_dir_all(&out).map_err(|e| err(&e))?;
            continue;
        }
        if let Some(parent) = out.parent() {
            std::fs::create_dir_all(parent).map_err(|e| err(&e))?;
        }
        let mut f = std::fs::File::create(&out).map_err(|e| err(&e))?;
        std::io::copy(&mut entry, &mut f).map_err(|e| err(&e))?;
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn folder_names_give_their_process_id() {
        assert_eq!(unpacked_folder_pid("airring-airfilm-1234-0"), Some(1234));
        assert_eq!(unpacked_folder_pid("airring-my-rotor-77-12"), Some(77));
        for other in [
            "airring-airfilm-1234",
            "airring-sweep-sigkill-1234",
            "airring--1234-0",
            "airring-airfilm-x-0",
            "cosim-airfilm-1-0",
        ] {
            assert_eq!(unpacked_folder_pid(other), None, "{other}");
        }
    }

    /// A folder left by a process that no longer exists goes; one of a live process, or one
    /// that is not an unpacked FMU, stays.
    #[test]
    fn stale_folders_of_dead_processes_are_removed() {
        let tmp = std::env::temp_dir().join(format!("fmi2-stale-test-{}", std::process::id()));
        // Process ids above the kernel's pid_max (at most 2^22) never exist.
        let dead = tmp.join("airring-stale-4999999-0");
        let alive = tmp.join(format!("airring-stale-{}-999", std::process::id()));
        let not_fmu = tmp.join("airring-stale-4999998-0");
        for d in [&dead, &alive, &not_fmu] {
            std::fs::create_dir_all(d).unwrap();
        }
        std::fs::write(dead.join("modelDescription.xml"), "x").unwrap();
        std::fs::write(alive.join("modelDescription.xml"), "x").unwrap();
        remove_stale_folders(&tmp);
        assert!(!dead.exists(), "a dead process's folder is removed");
        assert!(alive.exists(), "a live process's folder stays");
        assert!(
            not_fmu.exists(),
            "a folder without modelDescription.xml stays"
        );
        let _ = std::fs::remove_dir_all(&tmp);
    }
}
