//! What a run leaves behind beyond the `cosim` library's time series and checkpoints: the
//! optional Parquet copy of the series (written when the run ends).

pub mod parquet_file;
