//! A small random disturbance force on the two journals: the seed of self-excited whirl.
//!
//! Why it exists: with zero imbalance, a co-simulation that is accurate to round-off has almost
//! nothing to start a whirl from, so the visible onset of an unstable run-up depends on how
//! much numerical noise a particular code makes (see docs/stability.md). A real rotor is never
//! that quiet (ground vibration, turbulence, wheel aerodynamics). This force makes the seed a
//! stated, physical model input instead of an accident of the integrator.
//!
//! The force is a pure function of time (never of the step sequence), so rollbacks, checkpoint /
//! resume, other masters and other step sizes see exactly the same disturbance: four independent
//! Gaussian sequences (journal C x, y; journal T x, y) with standard deviation `force_rms_n`,
//! drawn on a grid of `interval_s` from a counter-based generator and interpolated linearly.
//! Its spectrum is flat to about 1 / (2 interval), so it excites every mode below that.

use serde::{Deserialize, Serialize};

/// Number of disturbance channels: (x, y) at the compressor-side journal, then at the turbine side.
pub const CHANNELS: usize = 4;

#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct Disturbance {
    /// Standard deviation of each force component [N]; 0 switches the disturbance off.
    pub force_rms_n: f64,
    /// Grid spacing of the random values [s] (bandwidth about 1 / (2 interval)).
    pub interval_s: f64,
    /// Seed of the generator: different seeds give independent realisations.
    pub seed: u64,
}

impl Disturbance {
    pub const OFF: Disturbance = Disturbance {
        force_rms_n: 0.0,
        interval_s: 1e-4,
        seed: 1,
    };

    pub fn is_off(&self) -> bool {
        self.force_rms_n == 0.0
    }

    /// The four force components [N] at time `t_s`: (F_C_x, F_C_y, F_T_x, F_T_y).
    pub fn forces_n(&self, t_s: f64) -> [f64; CHANNELS] {
        DisturbanceGrid::new(*self).forces_n(t_s)
    }

    /// The grid interval holding `t_s` and the fraction of it passed, or None where the force is 0.
    fn locate(&self, t_s: f64) -> Option<(u64, f64)> {
        if self.is_off() || !t_s.is_finite() || t_s < 0.0 {
            return None;
        }
        let s = t_s / self.interval_s;
        let k = s.floor();
        Some((k as u64, s - k))
    }

    /// The standard normal values of the four channels at grid point `k`.
    fn grid_values(&self, k: u64) -> [f64; CHANNELS] {
        std::array::from_fn(|ch| self.sample(ch as u64, k))
    }

    /// A standard normal value for channel `ch` at grid point `k` (Box-Muller on two
    /// counter-based uniforms: independent of evaluation order).
    fn sample(&self, ch: u64, k: u64) -> f64 {
        let key = self.seed ^ ch.wrapping_mul(0xA24B_AED4_963E_E407);
        let u1 = uniform_open(splitmix64(key ^ splitmix64(2 * k)));
        let u2 = uniform_open(splitmix64(key ^ splitmix64(2 * k + 1)));
        (-2.0 * u1.ln()).sqrt() * (std::f64::consts::TAU * u2).cos()
    }
}

/// A [`Disturbance`] that keeps the grid values of the interval it was last asked about: a rotor
/// step takes its inputs at a few times between two grid points (100 us apart at the default;
/// 3-4 evaluations per 50 us macro step), and each channel's value costs a logarithm, a cosine
/// and six hashes. Drawing all eight at every evaluation was ~14 % of the rotor's samples in a
/// path-1 run-up, beside the logarithms and cosines in libm. The same
/// values, so the same forces, bit for bit.
#[derive(Clone, Copy, Debug)]
pub struct DisturbanceGrid {
    d: Disturbance,
    /// Grid index k of the values kept, and the values at k and k + 1.
    kept: Option<(u64, [f64; CHANNELS], [f64; CHANNELS])>,
}

impl DisturbanceGrid {
    pub fn new(d: Disturbance) -> DisturbanceGrid {
        DisturbanceGrid { d, kept: None }
    }

    /// The disturbance whose values it keeps.
    pub fn disturbance(&self) -> Disturbance {
        self.d
    }

    /// The four force components [N] at time `t_s` (see [`Disturbance::forces_n`]).
    pub fn forces_n(&mut self, t_s: f64) -> [f64; CHANNELS] {
        let Some((k, w)) = self.d.locate(t_s) else {
            return [0.0; CHANNELS];
        };
        let (a, b) = match self.kept {
            Some((kk, a, b)) if kk == k => (a, b),
            // The next interval: its left values are the kept right ones.
            Some((kk, _, b)) if kk.checked_add(1) == Some(k) => (b, self.d.grid_values(k + 1)),
            _ => (self.d.grid_values(k), self.d.grid_values(k + 1)),
        };
        self.kept = Some((k, a, b));
        std::array::from_fn(|ch| self.d.force_rms_n * (a[ch] + w * (b[ch] - a[ch])))
    }
}

/// SplitMix64 finaliser: a well-mixed 64-bit hash of a counter.
fn splitmix64(x: u64) -> u64 {
    let mut z = x.wrapping_add(0x9E37_79B9_7F4A_7C15);
    z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    z ^ (z >> 31)
}

/// Uniform in (0, 1], never 0 (so its logarithm is finite).
fn uniform_open(bits: u64) -> f64 {
    ((bits >> 11) as f64 + 1.0) / (1u64 << 53) as f64
}

#[cfg(test)]
mod tests {
    use super::*;

    fn dist(seed: u64) -> Disturbance {
        Disturbance {
            force_rms_n: 2.0,
            interval_s: 1e-4,
            seed,
        }
    }

    #[test]
    fn off_is_exactly_zero() {
        assert_eq!(Disturbance::OFF.forces_n(0.123), [0.0; 4]);
    }

    #[test]
    fn grid_values_have_the_stated_mean_and_rms_and_channels_are_uncorrelated() {
        let d = dist(7);
        let n = 200_000;
        let mut sum = [0.0; 4];
        let mut sq = [0.0; 4];
        let mut cross = 0.0;
        for k in 0..n {
            let f = d.forces_n(k as f64 * 1e-4 + 1e-12);
            for c in 0..4 {
                sum[c] += f[c];
                sq[c] += f[c] * f[c];
            }
            cross += f[0] * f[3];
        }
        for c in 0..4 {
            let mean = sum[c] / n as f64;
            let rms = (sq[c] / n as f64).sqrt();
            // Standard error of the mean 2/sqrt(n) = 0.0045; of the rms about 0.0032.
            assert!(mean.abs() < 0.02, "channel {c}: mean {mean} N");
            assert!((rms - 2.0).abs() < 0.015, "channel {c}: rms {rms} N");
        }
        let corr = cross / n as f64 / 4.0;
        assert!(corr.abs() < 0.01, "correlation C_x / T_y = {corr}");
    }

    #[test]
    fn piecewise_linear_in_time_and_independent_of_evaluation_order() {
        let d = dist(3);
        let a = d.forces_n(5e-4);
        let b = d.forces_n(6e-4);
        let mid = d.forces_n(5.5e-4);
        for c in 0..4 {
            assert!((mid[c] - 0.5 * (a[c] + b[c])).abs() < 1e-12);
        }
        // Same time, any history: the same value, bit for bit.
        let later_first = d.forces_n(0.37);
        let _ = d.forces_n(0.01);
        assert_eq!(later_first, d.forces_n(0.37));
    }

    /// The kept grid values give the fresh evaluation's forces bit for bit, forwards, across
    /// grid points, backwards (a roll-back) and after a jump.
    #[test]
    fn the_kept_grid_gives_the_fresh_forces_bit_for_bit() {
        let d = dist(5);
        let mut grid = DisturbanceGrid::new(d);
        let mut times: Vec<f64> = (0..2_000).map(|i| i as f64 * 7.3e-6).collect();
        times.extend([
            1e-2,
            0.5e-2,
            0.3,
            0.30001,
            0.0,
            2e-4,
            1.0000000001e-4,
            -1.0,
            f64::NAN,
        ]);
        for t in times {
            let fresh = d.forces_n(t);
            let kept = grid.forces_n(t);
            for c in 0..4 {
                assert_eq!(
                    kept[c].to_bits(),
                    fresh[c].to_bits(),
                    "t = {t} s, channel {c}"
                );
            }
        }
        let mut off = DisturbanceGrid::new(Disturbance::OFF);
        assert_eq!(off.forces_n(0.1), [0.0; 4]);
    }

    #[test]
    fn seeds_give_different_realisations() {
        assert_ne!(dist(1).forces_n(0.01), dist(2).forces_n(0.01));
    }

    #[test]
    fn one_sided_spectrum_is_flat_below_the_grid_frequency() {
        // Mean square of differences of successive grid values equals 2 rms^2 for white
        // samples (it would be ~0 for a slowly varying or correlated sequence).
        let d = dist(11);
        let n = 50_000;
        let mut s = 0.0;
        let mut prev = d.forces_n(0.0)[1];
        for k in 1..n {
            let f = d.forces_n(k as f64 * 1e-4)[1];
            s += (f - prev).powi(2);
            prev = f;
        }
        let ratio = s / (n - 1) as f64 / (2.0 * 4.0);
        assert!(
            (ratio - 1.0).abs() < 0.03,
            "increment variance ratio {ratio}"
        );
    }
}
