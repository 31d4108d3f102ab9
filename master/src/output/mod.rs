//! What a run leaves behind: the time series (CSV written as the run goes, optionally Parquet at
//! the end), `summary.json`, and checkpoints from which `airring resume` continues.

pub mod checkpoint;
pub mod parquet_file;
pub mod timeseries;
