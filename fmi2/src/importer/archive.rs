//! Unpacking `.fmu` archives into fresh temporary folders.

use super::ImportError;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicU64, Ordering};

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
