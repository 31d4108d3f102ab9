//! The Hopf normal form as a test problem with exact periodic orbits, for the shooting and the
//! continuation (and for anyone checking them):
//!
//!   r' = r (mu + a r^2 + c r^4),   theta' = omega + b r^2,   z' = -z
//!
//! written in Cartesian (x, y, z) and advanced by classical Runge-Kutta with steps of at most
//! `dt_max_s`. The orbits are circles r = r*, z = 0 with mu + a r*^2 + c r*^4 = 0, period
//! 2 pi / (omega + b r*^2), and nontrivial Floquet multipliers exp(T g'(r*)) (radial,
//! g(r) = r (mu + a r^2 + c r^4)) and exp(-T) (the z direction).
//! a = -1, c = 0: supercritical (r*^2 = mu for mu > 0, stable).
//! a = +1, c = -1: subcritical (r*^2 = (1 +- sqrt(1 + 4 mu)) / 2 for -1/4 < mu, the inner orbit
//! unstable, the outer stable, a fold at mu = -1/4, r*^2 = 1/2).

use super::continuation::ParamFlow;
use super::shooting::Flow;

#[derive(Clone, Debug)]
pub struct HopfNormalForm {
    pub mu: f64,
    pub a: f64,
    pub c: f64,
    pub omega: f64,
    pub b: f64,
    pub dt_max_s: f64,
    /// Flow calls so far (the cost measure of shooting and continuation).
    pub flows: usize,
}

impl HopfNormalForm {
    pub fn supercritical(mu: f64) -> Self {
        HopfNormalForm {
            mu,
            a: -1.0,
            c: 0.0,
            omega: 2.0 * std::f64::consts::PI,
            b: 0.5,
            dt_max_s: 1e-3,
            flows: 0,
        }
    }

    pub fn subcritical(mu: f64) -> Self {
        HopfNormalForm {
            a: 1.0,
            c: -1.0,
            ..Self::supercritical(mu)
        }
    }

    /// g(r) / r: the radial growth rate.
    fn growth(&self, r2: f64) -> f64 {
        self.mu + self.a * r2 + self.c * r2 * r2
    }

    fn field(&self, s: &[f64; 3]) -> [f64; 3] {
        let r2 = s[0] * s[0] + s[1] * s[1];
        let g = self.growth(r2);
        let w = self.omega + self.b * r2;
        [g * s[0] - w * s[1], w * s[0] + g * s[1], -s[2]]
    }

    fn rk4(&self, s: &mut [f64; 3], h: f64) {
        let add = |s: &[f64; 3], k: &[f64; 3], f: f64| {
            [s[0] + f * k[0], s[1] + f * k[1], s[2] + f * k[2]]
        };
        let k1 = self.field(s);
        let k2 = self.field(&add(s, &k1, 0.5 * h));
        let k3 = self.field(&add(s, &k2, 0.5 * h));
        let k4 = self.field(&add(s, &k3, h));
        for i in 0..3 {
            s[i] += h / 6.0 * (k1[i] + 2.0 * k2[i] + 2.0 * k3[i] + k4[i]);
        }
    }

    /// The exact orbit radii r* at the current mu (ascending).
    pub fn exact_radii(&self) -> Vec<f64> {
        let mut r2s = Vec::new();
        if self.c == 0.0 {
            r2s.push(-self.mu / self.a);
        } else {
            let disc = self.a * self.a - 4.0 * self.c * self.mu;
            if disc >= 0.0 {
                for sign in [-1.0, 1.0] {
                    r2s.push((-self.a + sign * disc.sqrt()) / (2.0 * self.c));
                }
            }
        }
        let mut r: Vec<f64> = r2s
            .into_iter()
            .filter(|r2| *r2 > 0.0)
            .map(f64::sqrt)
            .collect();
        r.sort_by(f64::total_cmp);
        r
    }

    pub fn exact_period_s(&self, r: f64) -> f64 {
        2.0 * std::f64::consts::PI / (self.omega + self.b * r * r)
    }

    /// The exact nontrivial multipliers of the orbit of radius r: radial, then z.
    pub fn exact_multipliers(&self, r: f64) -> [f64; 2] {
        let r2 = r * r;
        // g'(r) = mu + 3 a r^2 + 5 c r^4
        let dg = self.mu + 3.0 * self.a * r2 + 5.0 * self.c * r2 * r2;
        let t = self.exact_period_s(r);
        [(dg * t).exp(), (-t).exp()]
    }
}

impl Flow for HopfNormalForm {
    fn dim(&self) -> usize {
        3
    }
    fn scale(&self) -> Vec<f64> {
        vec![1.0; 3]
    }
    fn flow(&mut self, x0: &[f64], at_s: &[f64]) -> Result<Vec<Vec<f64>>, String> {
        self.flows += 1;
        let mut s = [x0[0], x0[1], x0[2]];
        let mut t = 0.0;
        let mut out = Vec::with_capacity(at_s.len());
        for &t_end in at_s {
            if t_end < t {
                return Err(format!("times must increase ({t_end} after {t})"));
            }
            let n = ((t_end - t) / self.dt_max_s).ceil().max(1.0) as usize;
            let h = (t_end - t) / n as f64;
            for _ in 0..n {
                self.rk4(&mut s, h);
            }
            t = t_end;
            out.push(s.to_vec());
        }
        Ok(out)
    }
    fn measures(&mut self, x0: &[f64], _period_s: f64) -> Result<Vec<(String, f64)>, String> {
        Ok(vec![("radius".into(), x0[0].hypot(x0[1]))])
    }
}

impl ParamFlow for HopfNormalForm {
    fn param(&self) -> f64 {
        self.mu
    }
    fn set_param(&mut self, value: f64) -> Result<(), String> {
        self.mu = value;
        Ok(())
    }
    fn param_scale(&self) -> f64 {
        1.0
    }
}
