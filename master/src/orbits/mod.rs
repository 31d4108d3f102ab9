//! Periodic whirl orbits: shooting, Floquet multipliers and the continuation of a branch in
//! speed (`airring orbits`). The numerics are generic over [`shooting::Flow`]: the Hopf normal
//! form (`normal_form.rs`, exact orbits) tests them, the co-simulated rotor uses them.

pub mod cli;
pub mod continuation;
pub mod cosim_flow;
pub mod driver;
pub mod figure;
pub mod full_state;
pub mod krylov;
pub mod normal_form;
pub mod shooting;
pub mod study;

#[cfg(test)]
mod krylov_tests;
#[cfg(test)]
mod study_tests;
#[cfg(test)]
mod tests;
