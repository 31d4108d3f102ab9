//! Eigenvalues and eigenvectors of a small real non-symmetric matrix (the 16 x 16 state matrix
//! of the lateral motion): balancing (`balance`, from the `shaft` crate), then faer's dense
//! eigendecomposition (Householder reduction to Hessenberg form, the real Schur form by Francis
//! QR, eigenvectors by back-substitution in the Schur form).
//!
//! The balancing matters: the state matrix mixes an identity block with -M^-1 K entries of
//! 1e6 to 1e9, and faer does not balance. Unbalanced, faer's eigenvalues differ from the balanced
//! ones by up to 7e-9 relative (and an undamped mode shows a damping ratio of 5e-9); balanced,
//! they agree with the former EISPACK port to 1e-14. Kernel tests: tests/eigen_kernels.rs.

use crate::params::RotorError;

/// The complex scalar of the eigenproblem (faer's `c64`, i.e. `num_complex::Complex64`:
/// `re`/`im` fields, the arithmetic operators, `norm`, `conj`, `scale`).
pub type C64 = faer::c64;

const NO_CONVERGENCE: &str = "QR eigenvalue iteration did not converge";

/// Balancing of a state matrix (the `shaft` crate's, shared with the flexible rotor).
pub use shaft::eigen::balance;

/// Eigenvalues of the row-major n x n matrix `a` (balanced first). Complex ones come in exactly
/// conjugate pairs, real ones have an imaginary part of exactly 0.
pub fn eigenvalues(n: usize, a: &[f64]) -> Result<Vec<C64>, RotorError> {
    shaft::eigen::eigenvalues(n, a).ok_or(RotorError::Singular(NO_CONVERGENCE))
}

/// Eigenvalues of the row-major n x n matrix `a` (balanced first) with their eigenvectors, each
/// vector normalized so that its largest component (by modulus; the first of equal ones) is
/// exactly 1.
pub fn eigenpairs(n: usize, a: &[f64]) -> Result<Vec<(C64, Vec<C64>)>, RotorError> {
    shaft::eigen::eigenpairs(n, a).ok_or(RotorError::Singular(NO_CONVERGENCE))
}
