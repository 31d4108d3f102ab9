//! Periodic whirl orbits of the co-simulated rotor (`airring orbits`, `airring sweep-orbits`).
//! The numerics (shooting, Floquet multipliers, Newton-Krylov, continuation in speed) are the
//! `periodic-orbits` crate's, generic over its `Flow`; `cosim_flow.rs` and `full_state.rs` make
//! the co-simulation such a flow.

pub use periodic_orbits::{continuation, krylov, normal_form, shooting};

pub mod cli;
pub mod cosim_flow;
pub mod driver;
pub mod figure;
pub mod full_state;
pub mod study;

#[cfg(test)]
mod study_tests;
#[cfg(test)]
mod tests;
