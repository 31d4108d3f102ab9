//! Co-simulation of FMUs: set-up from a system file (`setup.rs`), the macro step of the sequential
//! Gauss-Seidel and the Jacobi scheme (`gauss_seidel.rs`), and the coupling polynomials
//! (`polynomial.rs`).

pub mod gauss_seidel;
pub mod parallel;
pub mod polynomial;
pub mod setup;

pub use gauss_seidel::{CoSim, Scheme};
pub use setup::{build, Built};
