//! Synthetic run-ups for tests and examples.
//!
//! The base run follows the paper's Section 3 profile (0 to 2000 Hz in 3 s): the journals start centred, drop
//! onto the film (a decaying start-up oscillation), then sit at a quasi-static equilibrium that drifts with
//! speed, plus small noise. Whirls are added per bearing with a given amplitude and frequency history.

use std::f64::consts::TAU;

use super::series::{Bearing, RunSeries};

pub const C_M: f64 = 20e-6;
pub const F_MAX_HZ: f64 = 2000.0;
pub const T_RAMP_S: f64 = 3.0;

/// Deterministic noise in [-0.5, 0.5) (xorshift64*), so the tests are reproducible.
struct Noise(u64);
impl Noise {
    fn next(&mut self) -> f64 {
        self.0 ^= self.0 >> 12;
        self.0 ^= self.0 << 25;
        self.0 ^= self.0 >> 27;
        (self.0.wrapping_mul(0x2545_f491_4f6c_dd1d) >> 11) as f64 / (1u64 << 53) as f64 - 0.5
    }
}

/// A stable run-up: start-up drop, slow sag drift with speed, noise of 0.2% C.
pub fn base(dt_s: f64, t_end_s: f64) -> RunSeries {
    let n = (t_end_s / dt_s).round() as usize + 1;
    let mut s = RunSeries {
        clearance_m: [C_M; 2],
        ..Default::default()
    };
    let mut noise = Noise(0x9e37_79b9_7f4a_7c15);
    for i in 0..n {
        let t = i as f64 * dt_s;
        let f = F_MAX_HZ * (t / T_RAMP_S).min(1.0);
        // Static sag: 0.9 C at standstill, lifting to 0.2 C at top speed; the C side sags a little more.
        let sag = C_M * (0.2 + 0.7 * (-f / 300.0).exp());
        let drop = (-t / 0.004).exp();
        // Start-up: from the centre, the journal falls and rings down at 150 Hz within ~10 ms.
        let settle =
            |s: f64| -s * (1.0 - drop) + 0.3 * C_M * (-t / 0.004).exp() * (TAU * 150.0 * t).sin();
        let sx = 0.1 * C_M * (f / F_MAX_HZ); // attitude angle: the journal moves sideways as it lifts
        s.t_s.push(t);
        s.omega_rad_s.push(TAU * f);
        s.dx_c_m.push(sx + 0.002 * C_M * noise.next());
        s.dy_c_m
            .push(settle(1.1 * sag) + 0.002 * C_M * noise.next());
        s.dx_t_m.push(sx + 0.002 * C_M * noise.next());
        s.dy_t_m.push(settle(sag) + 0.002 * C_M * noise.next());
        // Absolute journal positions: the ring sags too (mount c ~ 1000 N/mm, ~4 N per ring: 4 um).
        s.y_jc_m.push(-4e-6 + s.dy_c_m[i]);
        s.y_jt_m.push(-4e-6 + s.dy_t_m[i]);
    }
    s
}

/// Add a forward circular whirl to one bearing from `t_on_s`: radius `amp(t)` and frequency `freq(t)` in Hz
/// (the phase is the integral of the frequency, so frequency jumps are continuous in phase).
pub fn add_whirl(
    s: &mut RunSeries,
    b: Bearing,
    t_on_s: f64,
    amp: impl Fn(f64) -> f64,
    freq: impl Fn(f64) -> f64,
) {
    let dt = s.dt_s();
    let mut phase = 0.0;
    for i in 0..s.len() {
        let t = s.t_s[i];
        if t < t_on_s {
            continue;
        }
        phase += TAU * freq(t) * dt;
        let a = amp(t);
        let (x, y) = (a * phase.cos(), a * phase.sin());
        match b {
            Bearing::C => {
                s.dx_c_m[i] += x;
                s.dy_c_m[i] += y;
                s.y_jc_m[i] += y;
            }
            Bearing::T => {
                s.dx_t_m[i] += x;
                s.dy_t_m[i] += y;
                s.y_jt_m[i] += y;
            }
        }
    }
}

/// Supercritical Hopf growth in a slow passage: amplitude ~ sqrt(t - t_on) until it saturates at `a_max`
/// after `t_grow_s`.
pub fn hopf_amp(t_on_s: f64, a_max: f64, t_grow_s: f64) -> impl Fn(f64) -> f64 {
    move |t| a_max * ((t - t_on_s).max(0.0) / t_grow_s).min(1.0).sqrt()
}

pub fn speed_hz(t: f64) -> f64 {
    F_MAX_HZ * (t / T_RAMP_S).min(1.0)
}
