//! Periodic orbits of autonomous flows, knowing nothing of what flows: a flow is anything that
//! implements [`shooting::Flow`] (advance a state by a time, with a scale per component).
//!
//! - `shooting`: Newton shooting for a periodic orbit (start state and period, a phase
//!   condition), its Floquet multipliers from the monodromy matrix.
//! - `krylov`: the same matrix-free (GMRES on directional derivatives), for flows of many states;
//!   multipliers as Ritz values.
//! - `continuation`: pseudo-arclength continuation of a branch in a parameter ([`continuation::ParamFlow`]),
//!   its fold, its Hopf point and the bifurcation's criticality.
//! - `normal_form`: the Hopf normal form with a decaying third state, whose orbits, periods,
//!   multipliers, fold and Hopf point are known exactly; every method above is tested on it.

pub mod continuation;
pub mod krylov;
pub mod normal_form;
pub mod shooting;

#[cfg(test)]
mod krylov_tests;
#[cfg(test)]
mod tests;
