//! What a run leaves behind beyond the `cosim` library's time series and checkpoints: the
//! optional Parquet copy of the series (written when the run ends), and whole-file writes.

pub mod parquet_file;

use std::path::Path;

/// `cosim::files::write_whole` with the path in its error message.
pub fn write_whole(path: &Path, bytes: &[u8]) -> Result<(), String> {
    cosim::files::write_whole(path, bytes).map_err(|e| format!("{}: {e}", path.display()))
}
