//! Parameter validation, bad inputs, clone/serialize determinism, output derivatives.
use fmu_rotor::*;

fn forces(t: f64) -> BearingForces {
    BearingForces {
        fc_x_n: 2.0 * (4000.0 * t).sin(),
        fc_y_n: 4.0 + t,
        ft_x_n: -1.0,
        ft_y_n: 3.0 * (5000.0 * t).cos(),
    }
}

#[test]
fn invalid_parameters_are_reported() {
    type Edit = Box<dyn Fn(&mut RotorParams)>;
    let cases: Vec<(&str, Edit)> = vec![
        ("m", Box::new(|p| p.m_kg = -1.0)),
        ("J_t", Box::new(|p| p.j_t_kg_m2 = 0.0)),
        ("J_p", Box::new(|p| p.j_p_kg_m2 = -1e-6)),
        ("c_C", Box::new(|p| p.c_c_n_m = -5.0)),
        ("t_ramp", Box::new(|p| p.t_ramp_s = 0.0)),
        ("g", Box::new(|p| p.g_m_s2 = f64::NAN)),
        // The FMU's variable names (imbalance[0] is the compressor wheel's, C).
        ("m_imb_C", Box::new(|p| p.imbalance[0].mass_kg = -1e-3)),
        ("r_imb_T", Box::new(|p| p.imbalance[1].radius_m = -1e-3)),
        (
            "disturbance_interval",
            Box::new(|p| p.disturbance.interval_s = 0.0),
        ),
        (
            "speed_table_t_03",
            Box::new(|p| p.speed_table = vec![(0.0, 0.0), (1.0, 100.0), (1.0, 200.0)]),
        ),
        (
            "speed_table_f_02",
            Box::new(|p| p.speed_table = vec![(0.0, 0.0), (1.0, -100.0)]),
        ),
        ("max_internal_steps", Box::new(|p| p.max_steps_per_call = 0)),
        ("rtol", Box::new(|p| p.rtol = 1.0)),
        // Below what BDF2 reaches in double precision (MIN_RTOL).
        ("rtol", Box::new(|p| p.rtol = 1e-13)),
        ("f_max", Box::new(|p| p.f_max_hz = 1e300)),
        ("z_JT", Box::new(|p| p.z_jt_m = -1e300)),
        ("m_imb_T", Box::new(|p| p.imbalance[1].mass_kg = 1e300)),
        ("z_imb_C", Box::new(|p| p.imbalance[0].z_m = 1e3)),
    ];
    for (name, f) in cases {
        let mut p = RotorParams::paper();
        f(&mut p);
        let e = Rotor::new(p).unwrap_err();
        println!("{e}");
        assert!(
            matches!(e, RotorError::InvalidParameter { name: n, .. } if n == name),
            "{name}: {e}"
        );
    }
    assert!(RotorParams::paper().validate().is_ok());
}

#[test]
fn the_step_budget_ends_a_call_that_needs_too_many_steps() {
    // rtol 1e-11 needs ~2500 BDF2 steps per 100 us: beyond the default budget of
    // 500 + 10 x (100 us / h_max), within a raised one.
    let mut p = RotorParams::paper();
    p.rtol = 1e-11;
    p.atol = 1e-16;
    p.atol_vel = 1e-13;
    let mut r = Rotor::new(p.clone()).unwrap();
    let e = r.advance(0.0, 1e-4, &forces).unwrap_err();
    println!("{e}");
    assert!(
        matches!(&e, RotorError::StepFailure { reason, .. } if reason.contains("internal steps")),
        "{e}"
    );
    p.max_steps_per_call = 20_000;
    let mut r = Rotor::new(p).unwrap();
    let st = r.advance(0.0, 1e-4, &forces).unwrap();
    println!("{st:?}");
    assert!(
        st.steps > 510,
        "the raised budget was needed: {} steps",
        st.steps
    );
    // An absurdly long interval gets a capped budget, not billions of steps.
    let mut r = Rotor::new(RotorParams::paper()).unwrap();
    let e = r.advance(0.0, 1e300, &forces).unwrap_err();
    println!("{e}");
    assert!(
        matches!(&e, RotorError::StepFailure { reason, .. } if reason.contains("100500 internal steps")),
        "{e}"
    );
}

#[test]
fn nan_force_and_bad_times_are_errors_not_panics() {
    let mut r = Rotor::new(RotorParams::paper()).unwrap();
    r.advance(0.0, 1e-5, &forces).unwrap();
    let before = r.outputs();
    let e = r
        .advance(1e-5, 1e-5, &|_| BearingForces {
            fc_x_n: f64::NAN,
            ..Default::default()
        })
        .unwrap_err();
    println!("{e}");
    assert!(matches!(e, RotorError::InvalidInput(_)));
    assert_eq!(
        before,
        r.outputs(),
        "a rejected input must not change the state"
    );
    assert!(r.advance(1e-5, -1.0, &forces).is_err());
    assert!(r.advance(5.0, 1e-5, &forces).is_err());
    r.advance(1e-5, 1e-5, &forces).unwrap();
}

fn run(r: &mut Rotor, n0: usize, n1: usize) -> Vec<RotorOutputs> {
    let h = 1e-5;
    (n0..n1)
        .map(|n| {
            r.advance(n as f64 * h, h, &forces).unwrap();
            r.outputs()
        })
        .collect()
}

#[test]
fn clone_and_serialize_continue_bit_identically() {
    let mut p = RotorParams::paper();
    p.imbalance[0].mass_kg = 1e-4;
    p.imbalance[0].radius_m = 0.01;
    p.t_ramp_s = 0.05;
    let mut a = Rotor::new(p).unwrap();
    run(&mut a, 0, 300);
    let mut b = a.clone();
    let blob = bincode::serialize(&a).unwrap();
    let mut c: Rotor = bincode::deserialize(&blob).unwrap();
    let ra = run(&mut a, 300, 600);
    let rb = run(&mut b, 300, 600);
    let rc = run(&mut c, 300, 600);
    for i in 0..ra.len() {
        for (x, y) in [(ra[i], rb[i]), (ra[i], rc[i])] {
            assert_eq!(x.bearing_c.dx_m.to_bits(), y.bearing_c.dx_m.to_bits());
            assert_eq!(x.bearing_t.vy_m_s.to_bits(), y.bearing_t.vy_m_s.to_bits());
            assert_eq!(x, y);
        }
    }
    println!(
        "state blob {} bytes; restored copies identical over 300 further steps",
        blob.len()
    );
}

#[test]
fn output_derivatives_match_finite_differences() {
    let mut p = RotorParams::paper();
    p.t_ramp_s = 0.05;
    let mut r = Rotor::with_linear_films(p, [FilmCoefficients::isotropic(2e6, 100.0); 2]).unwrap();
    let h = 1e-6;
    let mut t = 0.0;
    for _ in 0..2000 {
        r.advance(t, h, &forces).unwrap();
        t += h;
    }
    let o0 = r.outputs();
    let d0 = r.output_derivatives();
    r.advance(t, h, &forces).unwrap();
    let o1 = r.outputs();
    let fd_v = (o1.bearing_c.vx_m_s - o0.bearing_c.vx_m_s) / h;
    let fd_x = (o1.bearing_c.dx_m - o0.bearing_c.dx_m) / h;
    println!(
        "d(vx_C)/dt: output derivative {:.5e}, finite difference {:.5e}",
        d0.bearing_c.dvx_m_s2, fd_v
    );
    assert_eq!(d0.bearing_c.ddx_m_s, o0.bearing_c.vx_m_s);
    assert!((fd_x - d0.bearing_c.ddx_m_s).abs() < 0.02 * d0.bearing_c.ddx_m_s.abs().max(1e-4));
    assert!((fd_v - d0.bearing_c.dvx_m_s2).abs() < 0.02 * d0.bearing_c.dvx_m_s2.abs().max(1.0));
}

/// The periodic-orbit search's restart: the lateral state reads back what was put in, the spin
/// follows the new constant speed from the same time, and a restart at the rotor's own state
/// and speed continues its motion (only the BDF history is new: within the integrator's
/// tolerance, not bit for bit).
#[test]
fn a_restart_at_a_lateral_state_and_constant_speed_continues_the_motion() {
    let mut p = RotorParams::paper();
    p.speed_table = vec![(0.0, 700.0), (1.0, 700.0)];
    let mut a = Rotor::new(p).unwrap();
    let h = 1e-5;
    for k in 0..200 {
        a.advance(k as f64 * h, h, &forces).unwrap();
    }
    let mut b = a.clone();
    let s = b.lateral_state();
    b.restart_constant_speed(&s, 700.0).unwrap();
    assert_eq!(b.lateral_state(), s, "the state put in reads back");
    assert_eq!(b.time_s(), a.time_s());
    for k in 200..400 {
        a.advance(k as f64 * h, h, &forces).unwrap();
        b.advance(k as f64 * h, h, &forces).unwrap();
    }
    let (sa, sb) = (a.lateral_state(), b.lateral_state());
    for i in 0..8 {
        let scale = sa[i].abs().max(1e-7);
        assert!(
            (sa[i] - sb[i]).abs() < 1e-3 * scale,
            "coordinate {i}: {} vs {}",
            sa[i],
            sb[i]
        );
    }
    // A new speed: the spin rate jumps, the angle stays 2 pi f t.
    let mut c = a.clone();
    c.restart_constant_speed(&a.lateral_state(), 900.0).unwrap();
    let t = c.time_s();
    let w = 2.0 * std::f64::consts::PI * 900.0;
    assert!((c.outputs().omega_rad_s - w).abs() < 1e-9 * w);
    assert!((c.outputs().spin_angle_rad - w * t).abs() < 1e-9 * w * t);
    // Non-finite states and speeds are refused, the rotor unchanged.
    let mut bad = a.lateral_state();
    bad[3] = f64::NAN;
    assert!(c.restart_constant_speed(&bad, 900.0).is_err());
    assert!(c
        .restart_constant_speed(&a.lateral_state(), f64::NAN)
        .is_err());
    assert!((c.outputs().omega_rad_s - w).abs() < 1e-9 * w);
    // A rotor with linear films (tests, static sag) is not rebuilt without them.
    let mut lin = Rotor::with_linear_films(
        RotorParams::paper(),
        [FilmCoefficients::isotropic(1e6, 10.0); 2],
    )
    .unwrap();
    let s = lin.lateral_state();
    let e = lin.restart_constant_speed(&s, 500.0).unwrap_err();
    assert!(e.to_string().contains("linear film"), "{e}");
}
