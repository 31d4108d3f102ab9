//! Writing files whole: a temporary file beside the target, synced, renamed over it, the folder
//! synced, so a crash or a full disk leaves the old content or the new one, never a part.

use std::path::{Path, PathBuf};

/// `path` with `.tmp` appended to its file name (in the same folder, so the rename is atomic).
pub fn temporary_name(path: &Path) -> PathBuf {
    let mut name = path.file_name().unwrap_or_default().to_os_string();
    name.push(".tmp");
    path.with_file_name(name)
}

/// Writes `bytes` to `path` whole or not at all. On failure the temporary file is removed (on a
/// full disk it would only take the space the next attempt needs) and `path` is as it was.
pub fn write_whole(path: &Path, bytes: &[u8]) -> std::io::Result<()> {
    use std::io::Write;
    let tmp = temporary_name(path);
    let written = std::fs::File::create(&tmp).and_then(|mut f| {
        f.write_all(bytes)?;
        f.sync_all()
    });
    if let Err(e) = written.and_then(|()| std::fs::rename(&tmp, path)) {
        let _ = std::fs::remove_file(&tmp);
        return Err(e);
    }
    if let Some(parent) = path.parent().filter(|p| !p.as_os_str().is_empty()) {
        std::fs::File::open(parent)?.sync_all()?;
    }
    Ok(())
}
