//! What the film benchmarks share: medians, the whirl orbit they time on, and a film warmed up on it.

use fmu_airfilm::{AirFilm, BearingParams, JournalState};
use std::f64::consts::PI;

pub fn median(mut v: Vec<f64>) -> f64 {
    v.sort_by(|a, b| a.total_cmp(b));
    v[v.len() / 2]
}

/// A circular whirl of eccentricity `eps` (of the clearance) at `f_whirl_hz`, shaft speed `f_spin_hz`.
pub fn whirl_orbit(
    prm: &BearingParams,
    eps: f64,
    f_whirl_hz: f64,
    f_spin_hz: f64,
) -> impl Fn(f64) -> JournalState {
    let e = eps * prm.bore.c_m;
    let w = 2.0 * PI * f_whirl_hz;
    let om = 2.0 * PI * f_spin_hz;
    move |t: f64| JournalState {
        dx_m: e * (w * t).cos(),
        dy_m: e * (w * t).sin(),
        vx_m_s: -e * w * (w * t).sin(),
        vy_m_s: e * w * (w * t).cos(),
        omega_rad_s: om,
    }
}

/// A film started at ambient pressure and advanced on `orbit` in steps of `h_s` for `t_warm_s`;
/// returns it and the number of steps taken (the next step starts at that times `h_s`).
pub fn film_warmed_up(
    prm: &BearingParams,
    orbit: &dyn Fn(f64) -> JournalState,
    h_s: f64,
    t_warm_s: f64,
) -> (AirFilm, usize) {
    let mut film = AirFilm::new(prm.clone()).unwrap();
    let mut k = 0usize;
    while (k as f64) * h_s < t_warm_s {
        film.advance(k as f64 * h_s, h_s, orbit).unwrap();
        k += 1;
    }
    (film, k)
}
