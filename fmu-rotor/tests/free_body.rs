//! Free rigid body: energy and angular momentum conservation; prescribed spin: constraint drift.
use fmu_rotor::body::{BodyKinematics, RigidBody};
use fmu_rotor::integrator::{GglBdf, Tolerances};
use fmu_rotor::system::MultibodySystem;
use fmu_rotor::*;

fn energy_momentum(sys: &MultibodySystem, x: &[f64], v: &[f64]) -> (f64, [f64; 3]) {
    let k = BodyKinematics::new(x, v);
    (
        sys.bodies[0].kinetic_energy(&k),
        sys.bodies[0].angular_momentum(&k),
    )
}

#[test]
fn free_body_conserves_energy_and_angular_momentum() {
    // Slightly non-axisymmetric rotor-like body, spinning at 1000 rad/s with a nutation of a few
    // degrees and a drift velocity; no forces, no constraints.
    let body = RigidBody {
        mass_kg: 0.83,
        inertia_kg_m2: [[2400e-6, 0.0, 0.0], [0.0, 2600e-6, 0.0], [0.0, 0.0, 120e-6]],
        point_masses: vec![],
    };
    let sys = MultibodySystem {
        bodies: vec![body],
        constraints: vec![],
        forces: vec![],
        gravity_m_s2: [0.0; 3],
    };
    let x0 = vec![0.0, 0.0, 0.1, 0.01, -0.02, 0.0];
    let v0 = vec![0.01, -0.02, 0.0, 5.0, -3.0, 1000.0];
    let tol = Tolerances {
        rtol: 1e-8,
        atol_pos: 1e-10,
        atol_vel: 1e-8,
        h_max_s: 1e-3,
        ..Default::default()
    };
    let mut ig = GglBdf::new(sys.clone(), tol, 0.0, x0.clone(), v0.clone(), vec![]).unwrap();
    let (e0, l0) = energy_momentum(&sys, &x0, &v0);
    let l0n = (l0[0] * l0[0] + l0[1] * l0[1] + l0[2] * l0[2]).sqrt();
    let (mut de, mut dl) = (0.0f64, 0.0f64);
    let mut max_tilt = 0.0f64;
    for i in 1..=200 {
        ig.advance_to(i as f64 * 1e-3, &mut |_, _| Ok(())).unwrap();
        let (e, l) = energy_momentum(&sys, ig.x(), ig.v());
        de = de.max(((e - e0) / e0).abs());
        let d = ((l[0] - l0[0]).powi(2) + (l[1] - l0[1]).powi(2) + (l[2] - l0[2]).powi(2)).sqrt();
        dl = dl.max(d / l0n);
        max_tilt = max_tilt.max(ig.x()[3].abs()).max(ig.x()[4].abs());
    }
    let st = ig.totals;
    println!(
        "free body 0.2 s (spin 1000 rad/s, max tilt {:.3} rad): max rel. energy error {de:.2e}, max rel. |dL| {dl:.2e}, steps {}, rejected {}, newton its {}",
        max_tilt, st.steps, st.rejected_steps, st.newton_iterations
    );
    assert!(max_tilt > 0.02, "the test must tumble the body");
    assert!(de < 1e-5, "energy drift {de}");
    assert!(dl < 1e-5, "angular momentum drift {dl}");
}

#[test]
fn prescribed_spin_keeps_constraints_at_tolerance() {
    // Paper rotor with linear films, gravity and a fast run-up (2000 Hz in 20 ms).
    let mut p = RotorParams::paper();
    p.t_ramp_s = 0.02;
    let mut r = Rotor::with_linear_films(p, [FilmCoefficients::isotropic(2e6, 100.0); 2]).unwrap();
    let mut tot = StepStats::default();
    let h = 1e-5;
    for i in 0..3000 {
        let s = r
            .advance(i as f64 * h, h, &|t| BearingForces {
                fc_x_n: (3000.0 * t).sin(),
                ..Default::default()
            })
            .unwrap();
        tot.accumulate(&s);
    }
    let o = r.outputs();
    let lam = r.integrator().multipliers();
    let mu_max = lam.1.iter().fold(0.0f64, |a, b| a.max(b.abs()));
    println!(
        "run-up to {:.0} Hz: max |g| {:.2e}, max |g'| {:.2e}, max |mu| {:.2e}, spin angle {:.6} rad (exact {:.6})",
        o.omega_rad_s / (2.0 * std::f64::consts::PI),
        tot.max_drift_pos,
        tot.max_drift_vel,
        mu_max,
        o.spin_angle_rad,
        SpeedProfile { f_max_hz: 2000.0, t_ramp_s: 0.02, table: None }.angle_rad(o.t_s)
    );
    assert!(tot.max_drift_pos < 1e-9 && tot.max_drift_vel < 1e-9);
    assert!(mu_max < 1e-6);
}
