//! The sampled results of one run-up, as the analysis reads them.

/// One run-up's sampled results (uniform sampling interval, SI units).
///
/// `dx_*`/`dy_*` are the journal displacements relative to the ring (the air-film inputs, MODEL.md 2),
/// per bearing C (compressor) and T (turbine); `y_j*_m` are the absolute vertical journal positions.
/// All vectors have the length of `t_s`.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct RunSeries {
    pub t_s: Vec<f64>,
    pub omega_rad_s: Vec<f64>,
    pub dx_c_m: Vec<f64>,
    pub dy_c_m: Vec<f64>,
    pub dx_t_m: Vec<f64>,
    pub dy_t_m: Vec<f64>,
    pub y_jc_m: Vec<f64>,
    pub y_jt_m: Vec<f64>,
    /// Nominal (minimum) radial clearance C of each bearing [C, T]; a bearing's eccentricity is
    /// its |dr| / C.
    pub clearance_m: [f64; 2],
    /// The films' own eccentricity outputs [C, T] (`film_C.eps`, `film_T.eps`), when the run
    /// recorded them: the eccentricity each film computed with. `eps` falls back to |dr| / C
    /// from the rotor's outputs for series without them (earlier run folders, tests).
    pub eps_films: Option<[Vec<f64>; 2]>,
}

/// Which bearing.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Bearing {
    C,
    T,
}

impl Bearing {
    pub const BOTH: [Bearing; 2] = [Bearing::C, Bearing::T];

    pub fn label(self) -> &'static str {
        match self {
            Bearing::C => "C",
            Bearing::T => "T",
        }
    }
}

impl RunSeries {
    pub fn len(&self) -> usize {
        self.t_s.len()
    }

    pub fn is_empty(&self) -> bool {
        self.t_s.is_empty()
    }

    /// Sampling interval from the first and last sample (the series is uniformly sampled).
    pub fn dt_s(&self) -> f64 {
        let n = self.t_s.len();
        if n < 2 {
            return 0.0;
        }
        (self.t_s[n - 1] - self.t_s[0]) / (n - 1) as f64
    }

    /// Relative displacement (dx, dy) of one bearing.
    pub fn rel(&self, b: Bearing) -> (&[f64], &[f64]) {
        match b {
            Bearing::C => (&self.dx_c_m, &self.dy_c_m),
            Bearing::T => (&self.dx_t_m, &self.dy_t_m),
        }
    }

    /// Nominal clearance C of one bearing [m].
    pub fn clearance(&self, b: Bearing) -> f64 {
        match b {
            Bearing::C => self.clearance_m[0],
            Bearing::T => self.clearance_m[1],
        }
    }

    /// Eccentricity ratio eps = |dr| / C per sample of one bearing.
    pub fn eps(&self, b: Bearing) -> Vec<f64> {
        if let Some(films) = &self.eps_films {
            return films[b as usize].clone();
        }
        let (dx, dy) = self.rel(b);
        dx.iter()
            .zip(dy)
            .map(|(x, y)| x.hypot(*y) / self.clearance(b))
            .collect()
    }

    /// Rotor speed in Hz per sample.
    pub fn speed_hz(&self) -> Vec<f64> {
        self.omega_rad_s
            .iter()
            .map(|w| w / std::f64::consts::TAU)
            .collect()
    }

    /// Rotor speed in Hz at time `t` (linear interpolation, clamped at the ends).
    pub fn speed_hz_at(&self, t: f64) -> f64 {
        interp(&self.t_s, &self.omega_rad_s, t) / std::f64::consts::TAU
    }

    /// Highest rotor speed of the run in Hz.
    pub fn max_speed_hz(&self) -> f64 {
        self.omega_rad_s.iter().fold(0.0_f64, |m, w| m.max(*w)) / std::f64::consts::TAU
    }

    /// Spin angle per sample, the trapezoidal integral of omega (needed to remove a 1x component).
    pub fn spin_angle_rad(&self) -> Vec<f64> {
        let mut phi = Vec::with_capacity(self.len());
        let mut acc = 0.0;
        for i in 0..self.len() {
            if i > 0 {
                acc += 0.5
                    * (self.omega_rad_s[i] + self.omega_rad_s[i - 1])
                    * (self.t_s[i] - self.t_s[i - 1]);
            }
            phi.push(acc);
        }
        phi
    }

    /// The spin angle with its cosine and sine per sample, for the windowed fits that remove a
    /// 1x component ([`Spin`]).
    pub fn spin(&self) -> Spin {
        Spin::new(self.spin_angle_rad())
    }

    /// Panics with a clear message if the vectors do not fit together (a caller's bug, not a data condition).
    pub fn check(&self) {
        let n = self.t_s.len();
        for (name, v) in [
            ("omega_rad_s", &self.omega_rad_s),
            ("dx_c_m", &self.dx_c_m),
            ("dy_c_m", &self.dy_c_m),
            ("dx_t_m", &self.dx_t_m),
            ("dy_t_m", &self.dy_t_m),
            ("y_jc_m", &self.y_jc_m),
            ("y_jt_m", &self.y_jt_m),
        ] {
            assert_eq!(
                v.len(),
                n,
                "RunSeries::{name} has {} samples, t_s has {n}",
                v.len()
            );
        }
        if let Some([c, t]) = &self.eps_films {
            assert!(
                c.len() == n && t.len() == n,
                "RunSeries::eps_films has {} and {} samples, t_s has {n}",
                c.len(),
                t.len()
            );
        }
        assert!(
            self.clearance_m.iter().all(|c| *c > 0.0),
            "RunSeries::clearance_m must be positive"
        );
    }
}

/// Linear interpolation of (xs, ys) at x, xs ascending; clamped outside.
pub fn interp(xs: &[f64], ys: &[f64], x: f64) -> f64 {
    if xs.is_empty() {
        return f64::NAN;
    }
    if x <= xs[0] {
        return ys[0];
    }
    let n = xs.len();
    if x >= xs[n - 1] {
        return ys[n - 1];
    }
    let i = xs.partition_point(|v| *v <= x).max(1);
    let (x0, x1) = (xs[i - 1], xs[i]);
    let w = if x1 > x0 { (x - x0) / (x1 - x0) } else { 0.0 };
    ys[i - 1] + w * (ys[i] - ys[i - 1])
}

/// The spin angle per sample and its cosine and sine, computed once per series: the onset's and
/// the whirl's windowed fits overlap (a window of many samples every hop), and evaluating cos and
/// sin per sample and window was a quarter of a run-up's analysis (~30 ms of path 1's
/// ~135 ms after the co-simulation). The same `cos` and `sin` of the same angles, so the fits are
/// bit-identical.
#[derive(Debug, Clone)]
pub struct Spin {
    pub angle_rad: Vec<f64>,
    pub cos: Vec<f64>,
    pub sin: Vec<f64>,
}

impl Spin {
    pub fn new(angle_rad: Vec<f64>) -> Spin {
        Spin {
            cos: angle_rad.iter().map(|a| a.cos()).collect(),
            sin: angle_rad.iter().map(|a| a.sin()).collect(),
            angle_rad,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn interp_and_spin_angle() {
        let t: Vec<f64> = (0..=100).map(|i| i as f64 * 0.01).collect();
        let s = RunSeries {
            omega_rad_s: t.iter().map(|t| 10.0 * t).collect(),
            t_s: t,
            clearance_m: [1.0, 1.0],
            ..Default::default()
        };
        // phi = 5 t^2 for omega = 10 t; the trapezoidal rule is exact for a linear integrand.
        let phi = s.spin_angle_rad();
        assert!((phi[100] - 5.0).abs() < 1e-12);
        assert!((s.speed_hz_at(0.505) * std::f64::consts::TAU - 5.05).abs() < 1e-12);
        assert!((s.dt_s() - 0.01).abs() < 1e-15);
    }
}
