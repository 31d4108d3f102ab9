//! Friction power of the two air films along a run-up: what the bearings cost at the speeds an
//! engineer quotes, and at most. From the films' own `power_loss` outputs (the wall shear of
//! the film, `fmu_airfilm::friction`).

use serde::{Deserialize, Serialize};

/// Speeds [Hz] the summary quotes the power loss at (those the run reaches).
pub const QUOTED_SPEEDS_HZ: [f64; 4] = [500.0, 1000.0, 1500.0, 2000.0];

/// The power loss is averaged over this window [s] centred where the run-up passes a quoted speed
/// (a whirl makes it oscillate; 10 ms covers several whirl periods at the paper's 300-900 Hz).
pub const WINDOW_S: f64 = 0.01;

/// Power loss of each bearing [W] at one speed.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct PowerAtSpeed {
    pub speed_hz: f64,
    #[serde(rename = "C")]
    pub c_w: f64,
    #[serde(rename = "T")]
    pub t_w: f64,
    pub total_w: f64,
}

/// The power-loss part of summary.json.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct PowerLossSummary {
    /// Averaged over `WINDOW_S` where the run first passes each quoted speed it reaches.
    pub at_speeds: Vec<PowerAtSpeed>,
    /// Largest sample of the sum of both bearings, with the bearings' shares then [W].
    pub max: PowerAtSpeed,
    pub window_s: f64,
}

/// The summary from the samples: time [s], speed [Hz], power loss of bearing C and T [W]. None
/// without samples.
pub fn power_loss_summary(
    t_s: &[f64],
    speed_hz: &[f64],
    p_c_w: &[f64],
    p_t_w: &[f64],
) -> Option<PowerLossSummary> {
    let n = t_s.len();
    if n == 0 || [speed_hz.len(), p_c_w.len(), p_t_w.len()] != [n; 3] {
        return None;
    }
    let at = |i: usize| PowerAtSpeed {
        speed_hz: speed_hz[i],
        c_w: p_c_w[i],
        t_w: p_t_w[i],
        total_w: p_c_w[i] + p_t_w[i],
    };
    let i_max = (0..n)
        .filter(|&i| (p_c_w[i] + p_t_w[i]).is_finite())
        .max_by(|&a, &b| (p_c_w[a] + p_t_w[a]).total_cmp(&(p_c_w[b] + p_t_w[b])))?;
    let mut at_speeds = vec![];
    for f in QUOTED_SPEEDS_HZ {
        let Some(i) = speed_hz.iter().position(|s| *s >= f) else {
            continue;
        };
        let (t0, t1) = (t_s[i] - 0.5 * WINDOW_S, t_s[i] + 0.5 * WINDOW_S);
        let window: Vec<usize> = (0..n).filter(|&k| t_s[k] >= t0 && t_s[k] <= t1).collect();
        let mean = |v: &[f64]| window.iter().map(|&k| v[k]).sum::<f64>() / window.len() as f64;
        let (c, t) = (mean(p_c_w), mean(p_t_w));
        at_speeds.push(PowerAtSpeed {
            speed_hz: f,
            c_w: c,
            t_w: t,
            total_w: c + t,
        });
    }
    Some(PowerLossSummary {
        at_speeds,
        max: at(i_max),
        window_s: WINDOW_S,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A linear run-up to 1200 Hz whose loss grows as speed^2 (Petroff: torque ~ speed): the quoted
    /// values are the window means, the maximum is at the end, unreached speeds are left out.
    #[test]
    fn quoted_speeds_and_maximum_of_a_runup() {
        let t: Vec<f64> = (0..=12_000).map(|k| k as f64 * 1e-4).collect();
        let speed: Vec<f64> = t.iter().map(|t| 1000.0 * t).collect();
        let pc: Vec<f64> = speed.iter().map(|f| 1e-6 * f * f).collect();
        let pt: Vec<f64> = pc.iter().map(|p| 0.5 * p).collect();
        let s = power_loss_summary(&t, &speed, &pc, &pt).unwrap();
        let speeds: Vec<f64> = s.at_speeds.iter().map(|a| a.speed_hz).collect();
        assert_eq!(speeds, [500.0, 1000.0]);
        // Mean of 1e-6 f^2 over the 101 samples f = 495, 495.1, ..., 505 Hz: 0.25 + 1e-6 * 8.5
        // (the samples' variance (101^2 - 1) / 12 * 0.1^2 Hz^2).
        let c500 = &s.at_speeds[0];
        assert!((c500.c_w - (0.25 + 8.5e-6)).abs() < 1e-12, "{c500:?}");
        assert!((c500.total_w - 1.5 * c500.c_w).abs() < 1e-12);
        assert_eq!(s.max.speed_hz, 1200.0);
        assert!((s.max.total_w - 1.5 * 1.44).abs() < 1e-12);
        assert!(power_loss_summary(&[], &[], &[], &[]).is_none());
    }
}
