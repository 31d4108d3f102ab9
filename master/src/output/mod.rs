//! What a run leaves behind beyond the `cosim` library's time series and checkpoints: the
//! optional Parquet copy of the series (written when the run ends), and whole-file writes.

pub mod parquet_file;

use std::path::{Path, PathBuf};

/// `path` with `.tmp` appended to its file name (in the same folder, so a rename is atomic).
pub fn temporary_name(path: &Path) -> PathBuf {
    let mut name = path.file_name().unwrap_or_default().to_os_string();
    name.push(".tmp");
    path.with_file_name(name)
}

/// Writes `bytes` to `path` whole or not at all: a temporary file, synced, renamed over `path`.
/// On failure (a full disk) the old `path`, if any, is left as it was.
pub fn write_whole(path: &Path, bytes: &[u8]) -> Result<(), String> {
    use std::io::Write;
    let tmp = temporary_name(path);
    let result = std::fs::File::create(&tmp)
        .and_then(|mut f| {
            f.write_all(bytes)?;
            f.sync_all()
        })
        .and_then(|()| std::fs::rename(&tmp, path));
    if result.is_err() {
        let _ = std::fs::remove_file(&tmp);
    }
    result.map_err(|e| format!("{}: {e}", path.display()))
}
