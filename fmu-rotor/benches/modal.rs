//! Cost of the rotor side of `airring modal` and `airring stability` (hand-written timing, medians).
//!
//! * modal: `lateral_matrices` + `modes` per speed, the setup of paper Section 2.3 (ring mount
//!   500 N/mm, undamped, isotropic film springs 2000 N/mm) at 0, 250, ..., 2000 Hz, as
//!   `airring modal` runs it for each `--speed`.
//! * stability: the rotor side of one speed of `airring stability` (`system_modes`) at its
//!   minimum: `lateral_matrices` + `modes` 9 times (the start and one evaluation per mode; each
//!   further step of the self-consistent frequency iteration adds one more) and
//!   `lateral_matrices` + `real_eigenvalues` once, with damped, cross-coupled films at 1000 Hz.
//! * modes only / real eigenvalues only: the eigenproblem (state matrix, 8 x 8 mass-matrix LU,
//!   16 x 16 eigenvalues and eigenvectors) without the numerical linearization.
use fmu_rotor::linear::*;
use fmu_rotor::*;
use std::hint::black_box;
use std::time::Instant;

fn median(v: &mut [f64]) -> f64 {
    v.sort_by(|a, b| a.total_cmp(b));
    v[v.len() / 2]
}

fn time<F: FnMut()>(label: &str, reps: usize, mut f: F) {
    for _ in 0..reps / 10 {
        f();
    }
    let mut t = Vec::with_capacity(reps);
    for _ in 0..reps {
        let t0 = Instant::now();
        f();
        t.push(t0.elapsed().as_secs_f64() * 1e6);
    }
    let mut s = t.clone();
    let med = median(&mut s);
    let p90 = s[s.len() * 9 / 10];
    println!("{label}: median {med:.2} us, p90 {p90:.2} us over {reps} calls");
}

fn main() {
    let tau = std::f64::consts::TAU;
    let mut p = RotorParams::paper();
    p.c_c_n_m = 5e5;
    p.c_t_n_m = 5e5;
    p.d_c_n_s_m = 0.0;
    p.d_t_n_s_m = 0.0;
    let iso = [FilmCoefficients::isotropic(2e6, 0.0); 2];
    let speeds: Vec<f64> = (0..=8).map(|k| 250.0 * k as f64).collect();
    time(
        "modal (lateral_matrices + modes) at 9 speeds 0..2000 Hz",
        500,
        || {
            for &f in &speeds {
                let lm = lateral_matrices(&p, tau * f, &iso);
                black_box(modes(&lm).unwrap());
            }
        },
    );
    let lm = lateral_matrices(&p, tau * 1000.0, &iso);
    time("modes only (undamped, 1000 Hz)", 20000, || {
        black_box(modes(black_box(&lm)).unwrap());
    });

    let mut ps = RotorParams::paper();
    ps.c_c_n_m = 5e5;
    ps.c_t_n_m = 5e5;
    ps.d_c_n_s_m = 50.0;
    ps.d_t_n_s_m = 50.0;
    let film = FilmCoefficients {
        k_n_m: [[2e6, 6e5], [-6e5, 2e6]],
        d_n_s_m: [[150.0, 20.0], [-20.0, 150.0]],
    };
    let films = [film; 2];
    time(
        "stability, one speed (9 x lateral_matrices + modes, 1 x lateral_matrices + real_eigenvalues)",
        1000,
        || {
            for _ in 0..9 {
                let lm = lateral_matrices(&ps, tau * 1000.0, &films);
                black_box(modes(&lm).unwrap());
            }
            let lm = lateral_matrices(&ps, tau * 1000.0, &films);
            black_box(real_eigenvalues(&lm).unwrap());
        },
    );
    let lm = lateral_matrices(&ps, tau * 1000.0, &films);
    time("modes only (damped, 1000 Hz)", 20000, || {
        black_box(modes(black_box(&lm)).unwrap());
    });
    time("real_eigenvalues only (damped, 1000 Hz)", 20000, || {
        black_box(real_eigenvalues(black_box(&lm)).unwrap());
    });
}
