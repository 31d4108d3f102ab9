//! Convergence order of the BDF integrator on a damped linear oscillator (a ring on its mount,
//! z and rotations constrained, so the GGL machinery is active) with exact solution.
use fmu_rotor::body::RigidBody;
use fmu_rotor::constraint::Constraint;
use fmu_rotor::integrator::{GglBdf, Tolerances};
use fmu_rotor::system::{ForceElement, MultibodySystem};

fn error_at_end(h: f64) -> f64 {
    let (m, c, d) = (0.05, 1e6, 20.0);
    let body = RigidBody {
        mass_kg: m,
        inertia_kg_m2: [[1e-5, 0.0, 0.0], [0.0, 1e-5, 0.0], [0.0, 0.0, 2e-5]],
        point_masses: vec![],
    };
    let constraints = (2..6).map(|i| Constraint::fixed(i, 0.0)).collect();
    let forces = vec![ForceElement::Mount {
        body: 0,
        anchor_m: [0.0, 0.0],
        c_n_m: c,
        d_n_s_m: d,
    }];
    let sys = MultibodySystem {
        bodies: vec![body],
        constraints,
        forces,
        gravity_m_s2: [0.0; 3],
    };
    let x0 = 1e-5;
    let tol = Tolerances {
        rtol: 1e-12,
        atol_pos: 1e-16,
        atol_vel: 1e-13,
        h_max_s: h,
        h_init_s: h,
        error_control: false,
        ..Default::default()
    };
    let mut ig = GglBdf::new(
        sys,
        tol,
        0.0,
        vec![x0, 0.0, 0.0, 0.0, 0.0, 0.0],
        vec![0.0; 6],
        vec![],
    )
    .unwrap();
    let t_end = 2e-3;
    ig.advance_to(t_end, &mut |_, _| Ok(())).unwrap();
    // exact: x = x0 e^{-zeta w t} (cos wd t + zeta w / wd sin wd t)
    let w = (c / m).sqrt();
    let zeta = d / (2.0 * (c * m).sqrt());
    let wd = w * (1.0 - zeta * zeta).sqrt();
    let ex =
        x0 * (-zeta * w * t_end).exp() * ((wd * t_end).cos() + zeta * w / wd * (wd * t_end).sin());
    (ig.x()[0] - ex).abs()
}

#[test]
fn bdf_is_second_order() {
    let hs = [4e-6, 2e-6, 1e-6, 5e-7];
    let errs: Vec<f64> = hs.iter().map(|&h| error_at_end(h)).collect();
    let mut orders = vec![];
    for i in 1..hs.len() {
        let p = (errs[i - 1] / errs[i]).ln() / 2f64.ln();
        orders.push(p);
        println!(
            "h = {:.1e} s: error {:.3e} m, observed order {:.3}",
            hs[i], errs[i], p
        );
    }
    println!("h = {:.1e} s: error {:.3e} m", hs[0], errs[0]);
    for p in orders {
        assert!((p - 2.0).abs() < 0.1, "observed order {p}");
    }
}
