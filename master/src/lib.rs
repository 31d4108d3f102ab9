//! The AirRing application as a library: the paper's run-ups on the generic `cosim` master,
//! their analysis and plots, sweeps, the linear stability analysis, modal analysis, orbits.
//! `main.rs` is only the command line. The run-up analysis, the figures and the periodic-orbit
//! numerics are library crates of their own (`runup-analysis`, `figures`, `periodic-orbits`);
//! `analysis` and `plot` name the first two here.

pub use figures as plot;
pub use runup_analysis as analysis;

pub mod calm_steps;
pub mod design;
pub mod error;
pub mod export_ssp;
pub mod film_orbit;
pub mod flexible;
pub mod fmu_params;
pub mod linear_cache;
pub mod modal;
pub mod optimize;
pub mod orbits;
pub mod output;
pub mod report;
pub mod run;
pub mod runup;
pub mod stability;
pub mod summary;
pub mod sweep;
