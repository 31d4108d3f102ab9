//! Synchronous response of the linearized lateral system to the rotor's imbalance (beyond the
//! paper): the forced vibration ROSS or COMSOL users read next to a Campbell diagram.
//!
//! An imbalance turns with the rotor: its force on the lateral coordinates is
//! f(t) = Re(F e^{i Omega t}), and the steady response q(t) = Re(Q e^{i Omega t}) solves
//!
//!   (K + i Omega (D + G) - Omega^2 M) Q = F,
//!
//! with the films' coefficients taken at the whirl frequency Omega (synchronous, forward: the
//! caller builds `LateralMatrices` with them). F is not written down by hand: it is the difference
//! of the multibody force vector with and without the imbalance point masses, at spin angles 0 and
//! pi/2 (F = f(0) - i f(pi/2)), so it uses exactly the equations the run-ups integrate (centrifugal
//! force and its moment about the CM from the wheels' axial offsets).

use crate::eigen::C64;
use crate::linear::{LateralMatrices, LATERAL_COORDS};
use crate::params::{RotorError, RotorParams};
use crate::rotor::{build_system, initial_state, N_INPUTS};

/// Complex amplitudes (x, y) [m] of the four bearing points: a point moves as
/// x(t) = Re(X e^{i Omega t}), y(t) = Re(Y e^{i Omega t}).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ForcedResponse {
    /// The lateral coordinates (order of `LATERAL_COORDS`).
    pub dof: [C64; 8],
    pub journal_c: [C64; 2],
    pub journal_t: [C64; 2],
    pub ring_c: [C64; 2],
    pub ring_t: [C64; 2],
}

/// The imbalance force on the lateral coordinates at spin speed `omega_rad_s` (complex amplitude
/// F of f(t) = Re(F e^{i omega t}), rotor centred, no gravity).
pub fn imbalance_force(params: &RotorParams, omega_rad_s: f64) -> [C64; 8] {
    let with = RotorParams {
        g_m_s2: 0.0,
        ..params.clone()
    };
    let without = RotorParams {
        imbalance: with
            .imbalance
            .map(|im| crate::params::Imbalance { mass_kg: 0.0, ..im }),
        ..with.clone()
    };
    let force_at = |p: &RotorParams, spin_rad: f64| -> Vec<f64> {
        let sys = build_system(p, None);
        let (mut x, mut v) = initial_state(p);
        x[5] = spin_rad;
        v[5] = omega_rad_s;
        let mut mb = vec![[0.0; 36]; sys.bodies.len()];
        let mut f = vec![0.0; sys.n_coords()];
        sys.eval(&x, &v, &[0.0; N_INPUTS], &mut mb, &mut f);
        f
    };
    let lateral = |spin: f64| -> [f64; 8] {
        let (a, b) = (force_at(&with, spin), force_at(&without, spin));
        LATERAL_COORDS.map(|i| a[i] - b[i])
    };
    let (f0, f90) = (lateral(0.0), lateral(0.5 * std::f64::consts::PI));
    std::array::from_fn(|k| C64::new(f0[k], -f90[k]))
}

/// The steady response Q to the force amplitude `force` of the system `lm` at its spin speed.
pub fn forced_response(
    lm: &LateralMatrices,
    force: &[C64; 8],
) -> Result<ForcedResponse, RotorError> {
    use faer::linalg::solvers::Solve;
    let w = lm.omega_rad_s;
    let z = faer::Mat::<C64>::from_fn(8, 8, |i, j| {
        C64::new(
            lm.k[i][j] - w * w * lm.m[i][j],
            w * (lm.d[i][j] + lm.g[i][j]),
        )
    });
    let rhs = faer::Mat::<C64>::from_fn(8, 1, |i, _| force[i]);
    let q = z.partial_piv_lu().solve(&rhs);
    let dof: [C64; 8] = std::array::from_fn(|i| q[(i, 0)]);
    if dof.iter().any(|c| !(c.re.is_finite() && c.im.is_finite())) {
        return Err(RotorError::Singular(
            "the dynamic stiffness matrix is singular at this speed (undamped resonance)",
        ));
    }
    let (ac, at) = (lm.a_c_m, lm.a_t_m);
    // Small-angle journal kinematics, as in `linear::modes`: x_J = x + a beta, y_J = y - a alpha.
    Ok(ForcedResponse {
        journal_c: [dof[0] + dof[3] * ac, dof[1] - dof[2] * ac],
        journal_t: [dof[0] + dof[3] * at, dof[1] - dof[2] * at],
        ring_c: [dof[4], dof[5]],
        ring_t: [dof[6], dof[7]],
        dof,
    })
}

/// Orbit of a point moving as (Re(X e^{i w t}), Re(Y e^{i w t})): its semi-major axis [same unit]
/// (the largest distance from the centre over a period).
pub fn semi_major_axis(p: &[C64; 2]) -> f64 {
    // |x|^2 + |y|^2 over a period: A + Re(B e^{2 i w t}), A = (|X|^2 + |Y|^2)/2, B = (X^2 + Y^2)/2.
    let a = 0.5 * (p[0].norm_sqr() + p[1].norm_sqr());
    let b = 0.5 * (p[0] * p[0] + p[1] * p[1]).norm();
    (a + b).sqrt()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::params::Imbalance;
    use crate::rotor::FilmCoefficients;

    /// A single imbalance at the CM plane: a rotating force m e Omega^2 on x and y, a quarter
    /// period apart (forward), in the phase of the mass, and no moment.
    #[test]
    fn imbalance_force_is_the_centrifugal_force_of_the_mass() {
        let mut p = RotorParams::paper();
        let (m, e, phase) = (1e-4, 0.01, 0.3);
        p.imbalance[0] = Imbalance {
            mass_kg: m,
            radius_m: e,
            z_m: p.z_cm_m,
            phase_rad: phase,
        };
        let w = 2.0 * std::f64::consts::PI * 500.0;
        let f = imbalance_force(&p, w);
        let amp = m * e * w * w;
        let expect_x = C64::new(amp * phase.cos(), amp * phase.sin());
        let expect_y = expect_x * C64::new(0.0, -1.0);
        assert!((f[0] - expect_x).norm() <= 1e-6 * amp, "{:?}", f[0]);
        assert!((f[1] - expect_y).norm() <= 1e-6 * amp, "{:?}", f[1]);
        for k in 2..8 {
            assert!(f[k].norm() <= 1e-6 * amp, "{k}: {:?}", f[k]);
        }
    }

    /// A point mass on an isotropic spring-damper (a rigid rotor on equal films, rings fixed by
    /// very stiff mounts) at the CM plane: |Q| = F / |k - m w^2 + i w d| for the translation,
    /// with the right phase lag.
    #[test]
    fn translation_response_matches_the_single_degree_of_freedom_formula() {
        let mut p = RotorParams::paper();
        // Equal bearings about the CM (no tilt coupling): both journals at +-a.
        let a = 0.05;
        p.z_jc_m = p.z_cm_m + a;
        p.z_jt_m = p.z_cm_m - a;
        p.c_c_n_m = 1e12;
        p.c_t_n_m = 1e12;
        let (m_imb, e) = (1e-4, 0.01);
        p.imbalance[0] = Imbalance {
            mass_kg: m_imb,
            radius_m: e,
            z_m: p.z_cm_m,
            phase_rad: 0.0,
        };
        let (k, d) = (2e6, 300.0);
        let films = [FilmCoefficients::isotropic(k, d); 2];
        for f_hz in [100.0, 300.0, 800.0] {
            let w = 2.0 * std::f64::consts::PI * f_hz;
            let lm = crate::linear::lateral_matrices(&p, w, &films);
            let r = forced_response(&lm, &imbalance_force(&p, w)).unwrap();
            let mass = lm.m[0][0];
            let z = C64::new(2.0 * k - mass * w * w, w * 2.0 * d);
            let expect = C64::new(m_imb * e * w * w, 0.0) / z;
            assert!(
                (r.dof[0] - expect).norm() <= 1e-3 * expect.norm(),
                "{f_hz} Hz: {:?} vs {expect:?}",
                r.dof[0]
            );
            // A circular forward orbit: semi-major axis = |X|.
            assert!((semi_major_axis(&r.journal_c) - expect.norm()).abs() <= 1e-3 * expect.norm());
        }
    }
}
