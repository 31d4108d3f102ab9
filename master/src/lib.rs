//! The `airring` co-simulation master as a library: system files, the Gauss-Seidel/Jacobi algorithms,
//! result output, run-up analysis and plots. `main.rs` is only the command line.

pub mod analysis;
pub mod cosim;
pub mod fmu_params;
pub mod modal;
pub mod orbit;
pub mod output;
pub mod plot;
pub mod run;
pub mod runup;
pub mod ssp;
pub mod stability;
pub mod sweep;
pub mod sweep_linear;
pub mod system;
