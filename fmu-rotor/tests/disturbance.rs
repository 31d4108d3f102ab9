//! The journal disturbance: off means exactly no horizontal motion; on, it moves the rotor by
//! the order of F / k, and the response does not depend on how the time axis is cut into steps
//! (the force is a function of time only, so a master's macro step cannot change it).
use fmu_rotor::*;

fn rotor(force_rms_n: f64) -> Rotor {
    let mut p = RotorParams::paper();
    p.f_max_hz = 0.0;
    // Tight tolerances, so that step-size effects of the integrator stay far below the
    // quantity tested (a dependence of the force on the step sequence would not shrink).
    p.rtol = 1e-8;
    p.atol = 1e-13;
    p.atol_vel = 1e-10;
    p.disturbance = Disturbance {
        force_rms_n,
        interval_s: 1e-4,
        seed: 5,
    };
    let films = [
        FilmCoefficients::isotropic(2.0e6, 200.0),
        FilmCoefficients::isotropic(2.0e6, 200.0),
    ];
    Rotor::with_linear_films(p, films).unwrap()
}

/// Horizontal journal-C positions [m] every 1 ms over 40 ms with communication step `h`.
fn x_jc(force_rms_n: f64, h: f64) -> Vec<f64> {
    let mut r = rotor(force_rms_n);
    let mut out = vec![];
    let n = (1e-3 / h).round() as usize;
    let mut t = 0.0;
    for _ in 0..40 {
        for _ in 0..n {
            r.advance(t, h, &|_| BearingForces::default()).unwrap();
            t += h;
        }
        out.push(r.outputs().bearing_c.journal_m[0]);
    }
    out
}

#[test]
fn off_gives_no_horizontal_motion() {
    assert!(x_jc(0.0, 1e-4).iter().all(|x| *x == 0.0));
}

#[test]
fn on_moves_the_journal_by_the_order_of_f_over_k_independent_of_the_step() {
    let f = 1.0; // N
    let a = x_jc(f, 1e-5);
    let b = x_jc(f, 5e-5);
    let rms = (a.iter().map(|x| x * x).sum::<f64>() / a.len() as f64).sqrt();
    // Journal on a 2000 N/mm film in series with a 1000 N/mm mount: about 670 N/mm; the
    // response of the mount-film-rotor modes can amplify that a few times, not by 100.
    let quasi_static = f / 6.7e5;
    println!("x_JC rms {rms:.3e} m, F/k {quasi_static:.3e} m");
    assert!(rms > 0.2 * quasi_static && rms < 20.0 * quasi_static);
    let max_diff = a
        .iter()
        .zip(&b)
        .map(|(x, y)| (x - y).abs())
        .fold(0.0, f64::max);
    println!("max difference 10 us vs 50 us steps {max_diff:.3e} m");
    assert!(max_diff < 1e-4 * rms, "step dependence {max_diff:.3e} m");
}
