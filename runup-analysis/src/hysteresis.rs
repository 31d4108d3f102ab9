//! Where a whirl starts and where it stops when the speed goes up and comes back down (a speed
//! profile with a run-down, `airring runup --profile`): the two speeds differ when the Hopf
//! bifurcation is subcritical or the whirl has found a large orbit that outlives the linear
//! threshold (hysteresis).
//!
//! The start is the run's onset (`onset`: the oscillation amplitude of a bearing crosses 2 % of its
//! clearance and stays). The stop is the last crossing back below that level, for the bearing
//! whose whirl lasts longest, interpolated between the amplitude windows; a whirl still above it in
//! the last window persists to the end.

use super::classify::Classification;
use super::onset::{self, OscTrack};
use super::series::{Bearing, RunSeries};

/// A run-down is a fall of the speed below this share of the top speed after reaching it.
const RUN_DOWN_FRACTION: f64 = 0.9;

#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Hysteresis {
    /// When the speed starts to fall from its top (the last sample at >= 99.5 % of the top).
    pub run_down_from_s: f64,
    pub whirl_start_time_s: Option<f64>,
    pub whirl_start_speed_hz: Option<f64>,
    pub whirl_stop_time_s: Option<f64>,
    pub whirl_stop_speed_hz: Option<f64>,
    /// The whirl was still there at the end of the run.
    pub persists_to_end: bool,
}

/// Index of the last sample at >= 99.5 % of the top speed, if the speed then falls below 90 % of
/// the top (a run-down), else None.
pub fn run_down_start(series: &RunSeries) -> Option<usize> {
    let speed = series.speed_hz();
    let top = series.max_speed_hz();
    if top <= 0.0 {
        return None;
    }
    let last_top = speed.iter().rposition(|f| *f >= 0.995 * top)?;
    speed[last_top..]
        .iter()
        .any(|f| *f < RUN_DOWN_FRACTION * top)
        .then_some(last_top)
}

/// The start and stop of the whirl of a run with a run-down (None: no run-down in the series).
pub fn hysteresis(series: &RunSeries, class: &Classification) -> Option<Hysteresis> {
    let down = run_down_start(series)?;
    let spin = series.spin();
    let tracks: Vec<(Bearing, OscTrack)> = Bearing::BOTH
        .iter()
        .map(|b| {
            let tr =
                onset::oscillation_track(series, *b, &spin, onset::AMP_WINDOW_S, onset::AMP_HOP_S);
            (*b, tr)
        })
        .collect();
    let mut stop: Option<f64> = None;
    let mut persists = false;
    if let Some(t_on) = class.onset_time_s {
        for (b, tr) in &tracks {
            let thr = onset::ONSET_AMP_REL * series.clearance(*b);
            let Some(last) = tr
                .amp_m
                .iter()
                .zip(&tr.t_s)
                .rposition(|(a, t)| *a > thr && *t >= t_on)
            else {
                continue;
            };
            if last + 1 == tr.amp_m.len() {
                persists = true;
                continue;
            }
            let (a0, a1) = (tr.amp_m[last], tr.amp_m[last + 1]);
            let (t0, t1) = (tr.t_s[last], tr.t_s[last + 1]);
            let w = ((a0 - thr) / (a0 - a1)).clamp(0.0, 1.0);
            let t = t0 + w * (t1 - t0);
            stop = Some(stop.map_or(t, |s: f64| s.max(t)));
        }
    }
    let (stop, persists) = if persists {
        (None, true)
    } else {
        (stop, false)
    };
    Some(Hysteresis {
        run_down_from_s: series.t_s[down],
        whirl_start_time_s: class.onset_time_s,
        whirl_start_speed_hz: class.onset_speed_hz,
        whirl_stop_time_s: stop,
        whirl_stop_speed_hz: stop.map(|t| series.speed_hz_at(t)),
        persists_to_end: persists,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::classify;
    use crate::synth::{base, C_M};
    use std::f64::consts::TAU;

    /// A ramp-dwell-rundown profile 0 -> 2000 Hz (1.5 s), dwell to 3 s, down to 0 at 4.5 s.
    fn profile_hz(t: f64) -> f64 {
        if t < 1.5 {
            2000.0 * t / 1.5
        } else if t < 3.0 {
            2000.0
        } else {
            (2000.0 * (4.5 - t) / 1.5).max(0.0)
        }
    }

    /// A whirl that starts at 900 Hz going up and stops at 600 Hz coming down (a subcritical
    /// loop): start and stop speeds are found within the amplitude windows' resolution.
    #[test]
    fn finds_where_the_whirl_starts_and_where_it_stops() {
        let mut s = base(5e-5, 4.5);
        for (i, t) in s.t_s.clone().into_iter().enumerate() {
            s.omega_rad_s[i] = TAU * profile_hz(t);
        }
        let (t_on, t_off) = (0.675, 3.0 + 1.5 * (1.0 - 600.0 / 2000.0));
        let mut phase = 0.0;
        for i in 0..s.len() {
            let t = s.t_s[i];
            phase += TAU * 300.0 * 5e-5;
            if t >= t_on && t < t_off {
                // A quick growth to 0.3 C and a quick collapse: a jump on and a jump off.
                let a = 0.3 * C_M * ((t - t_on) / 0.01).min(1.0) * ((t_off - t) / 0.01).min(1.0);
                s.dx_c_m[i] += a * phase.cos();
                s.dy_c_m[i] += a * phase.sin();
            }
        }
        let cl = classify(&s);
        let h = hysteresis(&s, &cl).expect("a run-down");
        // The last sample at >= 99.5 % of the top: 10 Hz below 2000 Hz at 1333 Hz/s is 7.5 ms on.
        assert!((h.run_down_from_s - 3.0075).abs() < 1e-4, "{h:?}");
        let start = h.whirl_start_speed_hz.unwrap();
        let stop = h.whirl_stop_speed_hz.unwrap();
        // The 20 ms amplitude window smears a jump by +-10 ms: 13 Hz at 1333 Hz/s.
        assert!((start - 900.0).abs() < 20.0, "{h:?}");
        assert!((stop - 600.0).abs() < 20.0, "{h:?}");
        assert!(!h.persists_to_end);
    }

    #[test]
    fn a_whirl_to_the_end_persists_and_a_plain_runup_has_no_rundown() {
        let mut s = base(5e-5, 4.5);
        for (i, t) in s.t_s.clone().into_iter().enumerate() {
            s.omega_rad_s[i] = TAU * profile_hz(t);
        }
        let mut phase = 0.0;
        for i in 0..s.len() {
            phase += TAU * 300.0 * 5e-5;
            if s.t_s[i] >= 0.9 {
                s.dx_t_m[i] += 0.2 * C_M * phase.cos();
                s.dy_t_m[i] += 0.2 * C_M * phase.sin();
            }
        }
        let h = hysteresis(&s, &classify(&s)).unwrap();
        assert!(
            h.persists_to_end && h.whirl_stop_speed_hz.is_none(),
            "{h:?}"
        );
        let plain = base(5e-5, 3.0);
        assert!(run_down_start(&plain).is_none());
        assert!(hysteresis(&plain, &classify(&plain)).is_none());
    }
}
