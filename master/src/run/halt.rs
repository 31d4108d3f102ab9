//! Limits that end a run where it crosses them (`runup --halt-film`, `--halt-whirl`): a search
//! that only needs to know that a design fails stops its run-up there, instead of running on
//! through a whirl or a rub it has already seen.

use crate::analysis::classify::{WHIRL_HOP_S, WHIRL_WINDOW_S};
use crate::analysis::onset::detrend_window;
use crate::analysis::series::Spin;
use cosim::observer::{Observer, ObserverError, RunStart};

/// A run that ends once it crosses a limit while the rotor speed lies in `speeds_hz`:
/// - the minimum film thickness of either bearing (`film_C.h_min`, `film_T.h_min`) below
///   `min_film_m`;
/// - the whirl amplitude of either bearing above `max_whirl_m`: the root mean square of the
///   journal's motion relative to its ring (`rotor.dx_*`, `rotor.dy_*`) over a window of
///   `WHIRL_WINDOW_S`, with its mean, drift and, once the window spans a revolution, the 1x
///   component removed; windows every `WHIRL_HOP_S` from the first sample. These are the
///   windows the run-up analysis and `airring optimize` measure the whirl amplitude with
///   (`runup_analysis::onset::oscillation_track`), so a run halted here shows the amplitude
///   that halted it. A resumed run's windows start again at its checkpoint.
///
/// Watched by an observer of the run (`LimitWatch`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Halt {
    pub min_film_m: Option<f64>,
    pub max_whirl_m: Option<f64>,
    pub speeds_hz: (f64, f64),
}

/// The samples so far for the whirl windows: time, rotor speed, the two bearings' relative
/// displacements and the spin angle, integrated as `RunSeries::spin_angle_rad` integrates it.
struct Track {
    t_s: Vec<f64>,
    omega_rad_s: Vec<f64>,
    /// [bearing C, T][x, y] [m].
    rel: [[Vec<f64>; 2]; 2],
    spin: Spin,
    /// First sample of the next window; samples per window and per hop, once known.
    start: usize,
    sizes: Option<(usize, usize)>,
}

impl Track {
    fn new() -> Self {
        Track {
            t_s: vec![],
            omega_rad_s: vec![],
            rel: Default::default(),
            spin: Spin::new(vec![]),
            start: 0,
            sizes: None,
        }
    }

    /// The rotor speed at `t` [rad/s], linear between samples (as `RunSeries::speed_hz_at`).
    fn omega_at(&self, t: f64) -> f64 {
        let (t_s, w) = (&self.t_s, &self.omega_rad_s);
        let i = t_s.partition_point(|x| *x < t);
        if i == 0 {
            return w[0];
        }
        if i >= t_s.len() {
            return w[t_s.len() - 1];
        }
        let f = (t - t_s[i - 1]) / (t_s[i] - t_s[i - 1]).max(1e-300);
        w[i - 1] + f * (w[i] - w[i - 1])
    }
}

/// The outputs a [`LimitWatch`] reads: the speed, the films' minimum thickness, the journals'
/// motion relative to their rings.
const COLUMNS: [&str; 7] = [
    "rotor.omega",
    "film_C.h_min",
    "film_T.h_min",
    "rotor.dx_C",
    "rotor.dy_C",
    "rotor.dx_T",
    "rotor.dy_T",
];

/// Watches the limits of a [`Halt`] and asks the run to halt where one is crossed: at the macro
/// point of the sample that crosses it (that sample is the series' last row, or, inside a long
/// calm macro step, the rows up to the step's end follow it).
pub(super) struct LimitWatch {
    rule: Halt,
    /// Where each of `COLUMNS` lies in a sample's values (the films' and the motions' only
    /// where watched).
    cols: [usize; 7],
    track: Track,
    reason: Option<String>,
}

impl LimitWatch {
    pub(super) fn new(rule: Halt) -> Self {
        LimitWatch {
            rule,
            cols: [0; 7],
            track: Track::new(),
            reason: None,
        }
    }

    fn in_range(&self, f_hz: f64) -> bool {
        let (lo, hi) = self.rule.speeds_hz;
        (lo..=hi).contains(&f_hz)
    }

    fn film(&mut self, t_s: f64, f_hz: f64, values: &[f64]) {
        let Some(limit) = self.rule.min_film_m else {
            return;
        };
        if !self.in_range(f_hz) {
            return;
        }
        for (bearing, col) in [("C", self.cols[1]), ("T", self.cols[2])] {
            let h = values[col];
            // A NaN thickness is no thickness above the limit either.
            if h < limit || h.is_nan() {
                self.reason = Some(format!(
                    "film_{bearing}.h_min = {} um < {} um at {} Hz (t = {} s)",
                    cosim::number::short(h * 1e6),
                    cosim::number::short(limit * 1e6),
                    cosim::number::short((f_hz * 10.0).round() / 10.0),
                    cosim::number::short(t_s)
                ));
                return;
            }
        }
    }

    fn whirl(&mut self, t_s: f64, omega: f64, values: &[f64]) {
        let Some(limit) = self.rule.max_whirl_m else {
            return;
        };
        let tr = &mut self.track;
        let angle = match (
            tr.t_s.last(),
            tr.omega_rad_s.last(),
            tr.spin.angle_rad.last(),
        ) {
            (Some(&t0), Some(&w0), Some(&a0)) => a0 + 0.5 * (omega + w0) * (t_s - t0),
            _ => 0.0,
        };
        tr.t_s.push(t_s);
        tr.omega_rad_s.push(omega);
        for (b, [cx, cy]) in [[3, 4], [5, 6]].into_iter().enumerate() {
            tr.rel[b][0].push(values[self.cols[cx]]);
            tr.rel[b][1].push(values[self.cols[cy]]);
        }
        tr.spin.angle_rad.push(angle);
        tr.spin.cos.push(angle.cos());
        tr.spin.sin.push(angle.sin());
        let n = tr.t_s.len();
        if tr.sizes.is_none() && n >= 2 {
            let dt = (tr.t_s[1] - tr.t_s[0]).max(1e-300);
            tr.sizes = Some((
                ((WHIRL_WINDOW_S / dt).round() as usize).max(3),
                ((WHIRL_HOP_S / dt).round() as usize).max(1),
            ));
        }
        let Some((n_win, hop)) = tr.sizes else {
            return;
        };
        while tr.start + n_win <= n && self.reason.is_none() {
            let range = tr.start..tr.start + n_win;
            let t_mid = 0.5 * (tr.t_s[range.start] + tr.t_s[range.end - 1]);
            // The speed at the window's centre, as the analysis reads it.
            let f_hz = tr.omega_at(t_mid) / std::f64::consts::TAU;
            let (lo, hi) = self.rule.speeds_hz;
            if (lo..=hi).contains(&f_hz) {
                for (b, name) in ["C", "T"].iter().enumerate() {
                    let (rx, ry) = detrend_window(
                        &tr.t_s,
                        &tr.rel[b][0],
                        &tr.rel[b][1],
                        &tr.spin,
                        range.clone(),
                    );
                    let ms =
                        rx.iter().zip(&ry).map(|(a, b)| a * a + b * b).sum::<f64>() / n_win as f64;
                    let amp = ms.sqrt();
                    if amp > limit || amp.is_nan() {
                        self.reason = Some(format!(
                            "whirl_{name} = {} um > {} um at {} Hz (t = {} s)",
                            cosim::number::short((amp * 1e9).round() / 1e3),
                            cosim::number::short(limit * 1e6),
                            cosim::number::short((f_hz * 10.0).round() / 10.0),
                            cosim::number::short(t_mid)
                        ));
                        break;
                    }
                }
            }
            tr.start += hop;
        }
        // Samples before the next window are no longer needed: a long run keeps its memory.
        if tr.start > 100_000 {
            let k = tr.start;
            tr.t_s.drain(..k);
            tr.omega_rad_s.drain(..k);
            for v in tr.rel.iter_mut().flatten() {
                v.drain(..k);
            }
            tr.spin.angle_rad.drain(..k);
            tr.spin.cos.drain(..k);
            tr.spin.sin.drain(..k);
            tr.start = 0;
        }
    }
}

impl Observer for LimitWatch {
    fn started(&mut self, run: &RunStart<'_>) -> Result<(), ObserverError> {
        // The speed always; the films' and the motions' columns only where watched.
        let (film, whirl) = (
            self.rule.min_film_m.is_some(),
            self.rule.max_whirl_m.is_some(),
        );
        let watched: Vec<(usize, &str)> = COLUMNS
            .iter()
            .copied()
            .enumerate()
            .filter(|(k, _)| *k == 0 || (*k < 3 && film) || (*k >= 3 && whirl))
            .collect();
        for &(k, name) in &watched {
            self.cols[k] = run
                .columns
                .iter()
                .position(|r| r.name == name)
                .ok_or_else(|| {
                    let names: Vec<&str> = watched.iter().map(|(_, n)| *n).collect();
                    ObserverError::Other(format!(
                        "the run's halt watches {}: the run records no output {name}",
                        names.join(", ")
                    ))
                })?;
        }
        Ok(())
    }

    fn sample(&mut self, t_s: f64, values: &[f64]) -> Result<(), ObserverError> {
        if self.reason.is_some() {
            return Ok(());
        }
        let omega = values[self.cols[0]];
        self.film(t_s, omega / std::f64::consts::TAU, values);
        if self.reason.is_none() {
            self.whirl(t_s, omega, values);
        }
        Ok(())
    }

    fn halt(&self) -> Option<String> {
        self.reason.clone()
    }
}
