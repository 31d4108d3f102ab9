//! Run-up analysis: onset detection, spectra, classification.
//!
//! Pure functions over one run's sampled time series ([`RunSeries`]): [`classify`] finds the onset of
//! self-excited vibration and sorts the run into the paper's bifurcation paths; [`spectrogram`] gives the
//! waterfall data. The criteria are documented in [`onset`] and [`classify()`]'s module.

pub mod classify;
pub mod csv_series;
pub mod hysteresis;
pub mod onset;
pub mod power;
pub mod series;
pub mod spectrum;
/// Synthetic run-ups (a Hopf-like whirl on a ramp) for tests and examples, here and in the
/// crates that draw or classify run-ups.
pub mod synth;
#[cfg(test)]
mod tests;

pub use classify::{classify, Classification, RunClass, WhirlSample};
pub use csv_series::{load_run, series_from_csv};
pub use hysteresis::{hysteresis, Hysteresis};
pub use power::{power_loss_summary, PowerLossSummary};
pub use series::{Bearing, RunSeries};
pub use spectrum::{spectrogram, Spectrogram};
