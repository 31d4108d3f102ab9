//! Errors of the air-film library. Every failure is reported as a value, never a panic or a NaN.

use bearing::num::Num;
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
    /// The mesh's Newton matrices would not fit in the memory a film may take
    /// ([`crate::integrator::MAX_NEWTON_MATRIX_BYTES`]): an allocation that size would abort
    /// the host process instead of failing.
    MeshTooLarge {
        n_elem_phi: usize,
        n_elem_z: usize,
        bytes: f64,
    },
    /// A grading that would make a lobe's last column less than
    /// [`crate::params::MIN_GRADED_COLUMN_RATIO`] of its first.
    MeshGradingTooStrong {
        mesh_grading: f64,
        n_elem_phi: usize,
    },
}

impl fmt::Display for FilmError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            FilmError::InvalidParameter {
                name,
                value,
                reason,
            } => {
                write!(
                    f,
                    "invalid air-film parameter {name} = {}: {reason}",
                    Num(*value)
                )
            }
            FilmError::InvalidInput { what, value, t_s } => {
                write!(
                    f,
                    "invalid air-film input {what} = {} at t = {} s",
                    Num(*value),
                    Num(*t_s)
                )
            }
            FilmError::BeyondContactLimit { h_min_m, t_s } => write!(
                f,
                "journal beyond the contact limit at t = {} s: minimum gap {} m <= 0 (the \
                 journal would penetrate the ring)",
                Num(*t_s),
                Num(*h_min_m)
            ),
            FilmError::NewtonFailure {
                t_reached_s,
                h_s,
                lobe,
                cause,
            } => write!(
                f,
                "Newton iteration of the Reynolds equation failed at t = {t} s even with \
                 sub-step {h} s (last failure: lobe {lobe}, {cause}); state kept at t = {t} s",
                t = Num(*t_reached_s),
                h = Num(*h_s)
            ),
            FilmError::TooManySubsteps {
                t_reached_s,
                max_substeps,
            } => write!(
                f,
                "more than {max_substeps} sub-steps needed; state kept at t = {} s",
                Num(*t_reached_s)
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
            FilmError::MeshTooLarge {
                n_elem_phi,
                n_elem_z,
                bytes,
            } => write!(
                f,
                "mesh n_elem_phi x n_elem_z = {n_elem_phi} x {n_elem_z} per lobe needs ~{:.3} GB \
                 for its Newton matrices, more than the {} GB a film may take: choose a coarser \
                 mesh (the paper's is 20 x 6)",
                bytes / 1e9,
                crate::integrator::MAX_NEWTON_MATRIX_BYTES / 1e9
            ),
            FilmError::MeshGradingTooStrong {
                mesh_grading,
                n_elem_phi,
            } => {
                let n = *n_elem_phi as f64;
                let ratio = crate::params::MIN_GRADED_COLUMN_RATIO;
                write!(
                    f,
                    "invalid air-film parameter mesh_grading = {mesh_grading}: with {n_elem_phi} \
                     elements along the lobe the last would be {:.1e} of the first, below {ratio} \
                     (its node lines crowd at the trailing edge); take a grading of at least {:.3} \
                     for this many elements, or fewer elements",
                    mesh_grading.powf(n - 1.0),
                    ratio.powf(1.0 / (n - 1.0)),
                )
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
