//! Unbalance (forced) response from the linear model: `airring stability --unbalance-c
//! "g,mm,deg" --unbalance-t "g,mm,deg"`. At each speed of the grid, the rotor about its static
//! equilibrium with the films' coefficients at the speed itself (a synchronous, forward whirl),
//! driven by the wheels' imbalance (`fmu_rotor::forced`): amplitude and phase of the journals and
//! rings (Bode plots), and the critical speeds with their amplification factors (half-power
//! method, API 684). Above the threshold speed of instability the steady response still exists
//! mathematically, but a self-excited whirl grows on top of it: those speeds are flagged.

use super::equilibrium::SolvedBearing;
use super::SpeedResult;
use fmu_rotor::eigen::C64;
use fmu_rotor::forced::{forced_response, imbalance_force, semi_major_axis, ForcedResponse};
use fmu_rotor::linear::lateral_matrices;
use fmu_rotor::{FilmCoefficients, RotorParams};
use serde::Serialize;
use std::f64::consts::TAU;

/// One point's synchronous motion: amplitude [um] and phase [deg] of x and y (x(t) = A cos(Omega
/// t + phase), the spin angle Omega t measured from the imbalance's phase reference), and the
/// orbit's semi-major axis [um].
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct PointMotion {
    pub x_um: f64,
    pub x_phase_deg: f64,
    pub y_um: f64,
    pub y_phase_deg: f64,
    pub semi_major_um: f64,
}

impl PointMotion {
    fn of(p: &[C64; 2]) -> Self {
        let deg = |c: C64| c.im.atan2(c.re).to_degrees();
        PointMotion {
            x_um: p[0].norm() * 1e6,
            x_phase_deg: deg(p[0]),
            y_um: p[1].norm() * 1e6,
            y_phase_deg: deg(p[1]),
            semi_major_um: semi_major_axis(p) * 1e6,
        }
    }
}

/// The response at one speed.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct UnbalancePoint {
    pub speed_hz: f64,
    pub journal_c: PointMotion,
    pub journal_t: PointMotion,
    pub ring_c: PointMotion,
    pub ring_t: PointMotion,
    /// Journal relative to its ring: the film's dynamic gap change [um] (semi-major axis).
    pub film_c_um: f64,
    pub film_t_um: f64,
    /// The linear system is unstable at this speed (a self-excited whirl grows on top).
    pub unstable: bool,
}

/// A peak of a journal's response over the speed grid.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct CriticalSpeed {
    /// "C" or "T".
    pub journal: String,
    pub speed_hz: f64,
    pub peak_um: f64,
    /// Half-power amplification factor f_peak / (f_2 - f_1), where the response is peak / sqrt 2
    /// on either side (linear interpolation on the grid); None if the grid does not reach both.
    pub amplification_factor: Option<f64>,
}

#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct UnbalanceReport {
    /// Each wheel's imbalance: mass [g], radius [mm], phase [deg] (compressor, turbine).
    pub imbalance_c: (f64, f64, f64),
    pub imbalance_t: (f64, f64, f64),
    /// A flexible rotor's imbalance: node, size [g mm], phase [deg] (the wheels' are then 0).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub imbalance_at_node: Option<(usize, f64, f64)>,
    pub points: Vec<UnbalancePoint>,
    pub critical_speeds: Vec<CriticalSpeed>,
}

/// A film's coefficients about its equilibrium at whirl frequency `w` [rad/s].
fn film_at(b: &SolvedBearing, w: f64) -> Result<FilmCoefficients, String> {
    let (k, d) = b.lin.impedance(w).map_err(|e| e.to_string())?;
    Ok(FilmCoefficients {
        k_n_m: k,
        d_n_s_m: d,
    })
}

/// The response at `speed_hz` about the equilibria `eq` ([C, T]).
pub fn response_at(
    rotor: &RotorParams,
    speed_hz: f64,
    eq: &[SolvedBearing; 2],
) -> Result<ForcedResponse, String> {
    let w = TAU * speed_hz;
    let films = [film_at(&eq[0], w)?, film_at(&eq[1], w)?];
    let lm = lateral_matrices(rotor, w, &films);
    forced_response(&lm, &imbalance_force(rotor, w)).map_err(|e| format!("at {speed_hz} Hz: {e}"))
}

/// The report over the speeds of a stability analysis (its equilibria `solved`, same order).
pub fn unbalance_report(
    rotor: &RotorParams,
    imbalance: [(f64, f64, f64); 2],
    speeds: &[SpeedResult],
    solved: &[[SolvedBearing; 2]],
) -> Result<UnbalanceReport, String> {
    let mut points = Vec::with_capacity(speeds.len());
    for (sp, eq) in speeds.iter().zip(solved) {
        let r = response_at(rotor, sp.speed_hz, eq)?;
        let rel = |j: &[C64; 2], g: &[C64; 2]| semi_major_axis(&[j[0] - g[0], j[1] - g[1]]) * 1e6;
        points.push(UnbalancePoint {
            speed_hz: sp.speed_hz,
            journal_c: PointMotion::of(&r.journal_c),
            journal_t: PointMotion::of(&r.journal_t),
            ring_c: PointMotion::of(&r.ring_c),
            ring_t: PointMotion::of(&r.ring_t),
            film_c_um: rel(&r.journal_c, &r.ring_c),
            film_t_um: rel(&r.journal_t, &r.ring_t),
            unstable: sp.max_growth_per_s() > 0.0,
        });
    }
    Ok(UnbalanceReport {
        imbalance_c: imbalance[0],
        imbalance_t: imbalance[1],
        imbalance_at_node: None,
        critical_speeds: critical_speeds_of(&points),
        points,
    })
}

/// The peaks of each journal's response over the grid, by speed.
fn critical_speeds_of(points: &[UnbalancePoint]) -> Vec<CriticalSpeed> {
    let mut critical_speeds = vec![];
    for (name, amp) in [
        (
            "C",
            points
                .iter()
                .map(|p| p.journal_c.semi_major_um)
                .collect::<Vec<_>>(),
        ),
        (
            "T",
            points.iter().map(|p| p.journal_t.semi_major_um).collect(),
        ),
    ] {
        let f: Vec<f64> = points.iter().map(|p| p.speed_hz).collect();
        critical_speeds.extend(peaks(&f, &amp).into_iter().map(|(speed_hz, peak_um, q)| {
            CriticalSpeed {
                journal: name.to_string(),
                speed_hz,
                peak_um,
                amplification_factor: q,
            }
        }));
    }
    critical_speeds.sort_by(|a, b| a.speed_hz.total_cmp(&b.speed_hz));
    critical_speeds
}

/// The report of a flexible rotor with an imbalance of `g_mm` [g mm] at `node`, phase
/// `phase_deg`, over the speeds of its stability analysis (equilibria `solved`, same order): the
/// films at each speed's own frequency (synchronous, forward).
pub fn flexible_unbalance_report(
    rotor: &super::structure::FlexibleRotor,
    (node, g_mm, phase_deg): (usize, f64, f64),
    speeds: &[SpeedResult],
    solved: &[[SolvedBearing; 2]],
) -> Result<UnbalanceReport, String> {
    let mut points = Vec::with_capacity(speeds.len());
    for (sp, eq) in speeds.iter().zip(solved) {
        let w = TAU * sp.speed_hz;
        let films = [film_at(&eq[0], w)?, film_at(&eq[1], w)?];
        let [jc, jt, rc, rt] = rotor
            .synchronous_response(w, &films, node, g_mm * 1e-6, phase_deg.to_radians())
            .map_err(|e| format!("at {} Hz: {e}", sp.speed_hz))?;
        let rel = |j: &[C64; 2], g: &[C64; 2]| semi_major_axis(&[j[0] - g[0], j[1] - g[1]]) * 1e6;
        points.push(UnbalancePoint {
            speed_hz: sp.speed_hz,
            journal_c: PointMotion::of(&jc),
            journal_t: PointMotion::of(&jt),
            ring_c: PointMotion::of(&rc),
            ring_t: PointMotion::of(&rt),
            film_c_um: rel(&jc, &rc),
            film_t_um: rel(&jt, &rt),
            unstable: sp.max_growth_per_s() > 0.0,
        });
    }
    Ok(UnbalanceReport {
        imbalance_c: (0.0, 0.0, 0.0),
        imbalance_t: (0.0, 0.0, 0.0),
        imbalance_at_node: Some((node, g_mm, phase_deg)),
        critical_speeds: critical_speeds_of(&points),
        points,
    })
}

/// Interior local maxima of `a` over `f`: (speed, peak, half-power amplification factor).
pub fn peaks(f: &[f64], a: &[f64]) -> Vec<(f64, f64, Option<f64>)> {
    let mut out = vec![];
    for i in 1..a.len().saturating_sub(1) {
        if !(a[i] > a[i - 1] && a[i] >= a[i + 1]) {
            continue;
        }
        let half = a[i] / std::f64::consts::SQRT_2;
        // Where the response crosses peak / sqrt 2 below and above the peak.
        let below = (1..=i).rev().find(|&k| a[k - 1] <= half).map(|k| {
            let (f0, f1, a0, a1) = (f[k - 1], f[k], a[k - 1], a[k]);
            f0 + (half - a0) / (a1 - a0) * (f1 - f0)
        });
        let above = (i..a.len() - 1).find(|&k| a[k + 1] <= half).map(|k| {
            let (f0, f1, a0, a1) = (f[k], f[k + 1], a[k], a[k + 1]);
            f0 + (a0 - half) / (a0 - a1) * (f1 - f0)
        });
        let q = match (below, above) {
            (Some(f1), Some(f2)) if f2 > f1 => Some(f[i] / (f2 - f1)),
            _ => None,
        };
        out.push((f[i], a[i], q));
    }
    out
}

/// "mass_g,radius_mm,phase_deg" of `--unbalance-c` / `--unbalance-t`.
pub fn parse_imbalance(text: &str, flag: &str) -> Result<(f64, f64, f64), String> {
    let v: Vec<f64> = text
        .split(',')
        .map(|x| x.trim().parse::<f64>())
        .collect::<Result<_, _>>()
        .map_err(|_| format!("--{flag} '{text}': expected mass_g,radius_mm,phase_deg"))?;
    match v[..] {
        [m, r, p] if m >= 0.0 && r >= 0.0 && m.is_finite() && r.is_finite() && p.is_finite() => {
            Ok((m, r, p))
        }
        _ => Err(format!(
            "--{flag} '{text}': expected three finite numbers mass_g >= 0, radius_mm >= 0, phase_deg"
        )),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The half-power factor of a sampled single-degree-of-freedom resonance: Q = 1 / (2 zeta).
    #[test]
    fn half_power_factor_of_a_sampled_resonance() {
        let (fn_hz, zeta) = (500.0, 0.05);
        let f: Vec<f64> = (1..=2000).map(|k| k as f64 * 0.5).collect();
        let a: Vec<f64> = f
            .iter()
            .map(|x| {
                let r = x / fn_hz;
                1.0 / ((1.0 - r * r).powi(2) + (2.0 * zeta * r).powi(2)).sqrt()
            })
            .collect();
        let p = peaks(&f, &a);
        assert_eq!(p.len(), 1);
        let (f_peak, _, q) = p[0];
        assert!(
            (f_peak - fn_hz * (1.0 - 2.0 * zeta * zeta).sqrt()).abs() < 0.5,
            "{p:?}"
        );
        let q = q.unwrap();
        assert!((q - 1.0 / (2.0 * zeta)).abs() < 0.02 * q, "{q}");
        // A peak at the edge of the grid is no critical speed found.
        assert!(peaks(&f[..900], &a[..900]).is_empty());
    }

    #[test]
    fn imbalance_flags_are_checked() {
        assert_eq!(
            parse_imbalance("0.1, 15, 90", "unbalance-c"),
            Ok((0.1, 15.0, 90.0))
        );
        for bad in ["1,2", "-1,2,3", "a,b,c", "1,2,inf"] {
            assert!(parse_imbalance(bad, "unbalance-c")
                .unwrap_err()
                .contains("--unbalance-c"));
        }
    }
}
