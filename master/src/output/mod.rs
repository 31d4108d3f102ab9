//! What a run leaves behind: the time series (written as the run goes), `summary.json`, and
//! checkpoints from which `airring resume` continues.

pub mod checkpoint;
pub mod timeseries;
