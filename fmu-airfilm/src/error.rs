//! Errors of the air-film library. Every failure is reported as a value, never a panic or a NaN.

use std::fmt;

/// What went wrong in the air-film solver.
#[derive(Clone, Debug, PartialEq)]
pub enum FilmError {
    /// A parameter is non-physical or the mesh is too coarse.
    InvalidParameter {
        name: &'static str,
        value: f64,
        reason: &'static str,
    },
    /// An input (journal state, time, step size) is NaN or infinite or otherwise unusable.
    InvalidInput {
        what: &'static str,
        value: f64,
        t_s: f64,
    },
    /// The journal penetrates the ring surface (gap <= 0 somewhere on a lobe): the film model is void.
    BeyondContactLimit { h_min_m: f64, t_s: f64 },
    /// Newton did not converge even after sub-steps were reduced to the minimum step size.
    /// The film state stays at the last accepted sub-step, `t_reached_s`.
    NewtonFailure {
        t_reached_s: f64,
        h_s: f64,
        /// Lobe (block) whose solve failed last, and why.
        lobe: usize,
        cause: &'static str,
    },
    /// The requested interval needed more than `max_substeps` accepted sub-steps.
    /// The film state stays at the last accepted sub-step, `t_reached_s`.
    TooManySubsteps {
        t_reached_s: f64,
        max_substeps: usize,
    },
    /// The steady-state iteration did not converge.
    SteadyNotConverged { iterations: usize, residual: f64 },
    /// The banded LU found an exactly zero pivot (singular Newton matrix).
    SingularMatrix { lobe: usize, row: usize },
}

impl fmt::Display for FilmError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            FilmError::InvalidParameter {
                name,
                value,
                reason,
            } => {
                write!(f, "invalid air-film parameter {name} = {value}: {reason}")
            }
            FilmError::InvalidInput { what, value, t_s } => {
                write!(f, "invalid air-film input {what} = {value} at t = {t_s} s")
            }
            FilmError::BeyondContactLimit { h_min_m, t_s } => write!(
                f,
                "journal beyond the contact limit at t = {t_s} s: minimum gap {h_min_m} m <= 0 \
                 (the journal would penetrate the ring)"
            ),
            FilmError::NewtonFailure {
                t_reached_s,
                h_s,
                lobe,
                cause,
            } => write!(
                f,
                "Newton iteration of the Reynolds equation failed at t = {t_reached_s} s even with \
                 sub-step {h_s} s (last failure: lobe {lobe}, {cause}); state kept at \
                 t = {t_reached_s} s"
            ),
            FilmError::TooManySubsteps {
                t_reached_s,
                max_substeps,
            } => write!(
                f,
                "more than {max_substeps} sub-steps needed; state kept at t = {t_reached_s} s"
            ),
            FilmError::SteadyNotConverged {
                iterations,
                residual,
            } => write!(
                f,
                "steady-state Reynolds solve did not converge in {iterations} iterations \
                 (residual {residual:e})"
            ),
            FilmError::SingularMatrix { lobe, row } => {
                write!(f, "singular Newton matrix in lobe {lobe} at row {row}")
            }
        }
    }
}

impl std::error::Error for FilmError {}

impl From<bearing::InvalidParameter> for FilmError {
    fn from(e: bearing::InvalidParameter) -> Self {
        FilmError::InvalidParameter {
            name: e.name,
            value: e.value,
            reason: e.reason,
        }
    }
}
