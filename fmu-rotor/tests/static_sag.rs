//! Static sag under gravity with ring mounts and given film springs versus the hand calculation:
//! bearing loads from the lever rule, film deflection F/k, ring deflection (F + m_R g)/c.
use fmu_rotor::*;

#[test]
fn static_sag_matches_hand_calculation() {
    let mut p = RotorParams::paper();
    p.f_max_hz = 0.0; // no spin needed for statics
    p.d_c_n_s_m = 400.0;
    p.d_t_n_s_m = 400.0;
    p.h_max_s = 2e-3;
    let (k_c, k_t) = (2.0e6, 1.5e6);
    let films = [
        FilmCoefficients::isotropic(k_c, 400.0),
        FilmCoefficients::isotropic(k_t, 400.0),
    ];
    let mut r = Rotor::with_linear_films(p.clone(), films).unwrap();
    let mut t = 0.0;
    for _ in 0..400 {
        r.advance(t, 1e-3, &|_| BearingForces::default()).unwrap();
        t += 1e-3;
    }
    let o = r.outputs();
    let w = p.m_kg * p.g_m_s2;
    let span = p.z_jc_m - p.z_jt_m;
    let f_c = w * (p.z_cm_m - p.z_jt_m) / span;
    let f_t = w * (p.z_jc_m - p.z_cm_m) / span;
    let ring_c = -(f_c + p.m_r_c_kg * p.g_m_s2) / p.c_c_n_m;
    let ring_t = -(f_t + p.m_r_t_kg * p.g_m_s2) / p.c_t_n_m;
    let dy_c = -f_c / k_c;
    let dy_t = -f_t / k_t;
    let hand = [ring_c, ring_t, dy_c, dy_t, ring_c + dy_c, ring_t + dy_t];
    let sim = [
        o.bearing_c.ring_m[1],
        o.bearing_t.ring_m[1],
        o.bearing_c.dy_m,
        o.bearing_t.dy_m,
        o.bearing_c.journal_m[1],
        o.bearing_t.journal_m[1],
    ];
    let names = [
        "ring C y",
        "ring T y",
        "film C dy",
        "film T dy",
        "journal C y",
        "journal T y",
    ];
    for i in 0..6 {
        let rel = ((sim[i] - hand[i]) / hand[i]).abs();
        println!(
            "{:12}: simulated {:+.6e} m, hand {:+.6e} m, rel. diff {:.1e}",
            names[i], sim[i], hand[i], rel
        );
        assert!(rel < 1e-5, "{} differs by {rel}", names[i]);
    }
    assert!(o.bearing_c.dx_m.abs() < 1e-15 && o.bearing_t.dx_m.abs() < 1e-15);
    println!(
        "rotor tilt about x {:.4e} rad, steps total {}",
        o.tilt_x_rad,
        r.integrator().totals.steps
    );
}
