//! Onset of self-excited vibration (the Hopf bifurcation of a run-up).
//!
//! The journal's equilibrium relative to the ring drifts slowly with speed (gravity sag, film stiffening):
//! quasi-static, so over a window of a few tens of milliseconds it is a straight line. A Hopf bifurcation
//! shows as an oscillation about that slowly moving mean that grows and then stays. So, per bearing:
//!
//! 1. In windows of [`AMP_WINDOW_S`] every [`AMP_HOP_S`], fit `a + b t` (the drift) and, once the rotor turns
//!    at least one revolution per window, `c cos(phi) + d sin(phi)` with phi the spin angle (a 1x
//!    imbalance response, which is forced, not self-excited) to dx and dy by least squares.
//! 2. The oscillation amplitude is the RMS length of the residual vector, `sqrt(mean(rx^2 + ry^2))`;
//!    for a circular whirl of radius A it is A.
//! 3. An episode is a stretch of windows with amplitude above [`ONSET_AMP_REL`] * C, gaps shorter than
//!    [`GAP_BRIDGE_S`] bridged. The onset is the start of the first episode that lasts at least
//!    [`MIN_PERSIST_S`] (or runs to the end of the series) and does not start in the very first window:
//!    an episode that starts at t = 0 and ends is the start-up settling (the centred journal drops under
//!    gravity onto the film) and is skipped; one that starts at t = 0 and never ends is an instability
//!    from standstill and its onset is the start of the series.
//! 4. The onset time is the threshold crossing, linearly interpolated between the window centres.

use super::series::{Bearing, RunSeries, Spin};

/// Window of the oscillation-amplitude estimate. Long against the whirl periods (whirl near the rigid-body
/// modes >= 125 Hz, paper 2.3: 2.5 periods; near 0.45x at 767 Hz: 7 periods), short against the
/// run-up (the speed changes by 13 Hz in 20 ms at 2000 Hz / 3 s), so a line fits the drift.
pub const AMP_WINDOW_S: f64 = 0.02;
/// Step between amplitude windows; sets the onset-time resolution (0.4% of the paper's 1150 ms).
pub const AMP_HOP_S: f64 = 0.005;
/// Onset threshold: oscillation amplitude 2% of C (0.4 um at C = 20 um). Far above the numerical noise of a
/// converged co-simulation (nm level) and far below every whirl the paper shows (moderate path-2a whirls are
/// a sizeable fraction of C; path 1 and 2b reach eps ~ 1), so the crossing marks the visible start of the
/// growth the paper calls the onset, a few ms after the linear threshold.
pub const ONSET_AMP_REL: f64 = 0.02;
/// An oscillation must last this long to count: a Hopf whirl in a run-up persists (paper Section 3), a
/// disturbance decays within a few film time constants (ms).
pub const MIN_PERSIST_S: f64 = 0.1;
/// Dips below the threshold shorter than this do not split an episode (beating of two whirl frequencies).
pub const GAP_BRIDGE_S: f64 = 0.02;

/// Oscillation amplitude of one bearing over time.
#[derive(Debug, Clone, Default)]
pub struct OscTrack {
    /// Window centres.
    pub t_s: Vec<f64>,
    /// RMS length of the residual (oscillating) relative displacement in each window.
    pub amp_m: Vec<f64>,
}

/// Residuals of x and y on `range` after removing a line and, if the spin advances at least one revolution
/// over the window, the 1x component. Returns (rx, ry).
pub fn detrend_window(
    t: &[f64],
    x: &[f64],
    y: &[f64],
    spin: &Spin,
    range: std::ops::Range<usize>,
) -> (Vec<f64>, Vec<f64>) {
    let (i0, i1) = (range.start, range.end);
    let n = i1 - i0;
    if n < 3 {
        return (vec![0.0; n], vec![0.0; n]);
    }
    let tc = 0.5 * (t[i0] + t[i1 - 1]);
    let half = (0.5 * (t[i1 - 1] - t[i0])).max(1e-300);
    let with_1x = spin.angle_rad[i1 - 1] - spin.angle_rad[i0] >= std::f64::consts::TAU;
    let m = if with_1x { 4 } else { 2 };
    let basis = |i: usize| -> [f64; 4] {
        let s = (t[i] - tc) / half;
        if with_1x {
            [1.0, s, spin.cos[i], spin.sin[i]]
        } else {
            [1.0, s, 0.0, 0.0]
        }
    };
    // Normal equations, shared by x and y.
    let mut a = [[0.0; 4]; 4];
    let mut bx = [0.0; 4];
    let mut by = [0.0; 4];
    for i in i0..i1 {
        let p = basis(i);
        for r in 0..m {
            for c in 0..m {
                a[r][c] += p[r] * p[c];
            }
            bx[r] += p[r] * x[i];
            by[r] += p[r] * y[i];
        }
    }
    let cx = solve_small(a, bx, m);
    let cy = solve_small(a, by, m);
    let mut rx = Vec::with_capacity(n);
    let mut ry = Vec::with_capacity(n);
    for i in i0..i1 {
        let p = basis(i);
        let (mut fx, mut fy) = (0.0, 0.0);
        for r in 0..m {
            fx += cx[r] * p[r];
            fy += cy[r] * p[r];
        }
        rx.push(x[i] - fx);
        ry.push(y[i] - fy);
    }
    (rx, ry)
}

/// Gaussian elimination with partial pivoting on the leading m x m block; a singular pivot gives 0 for
/// that coefficient (the fit then simply does without that basis function).
fn solve_small(mut a: [[f64; 4]; 4], mut b: [f64; 4], m: usize) -> [f64; 4] {
    let scale = (0..m)
        .map(|i| a[i][i].abs())
        .fold(0.0, f64::max)
        .max(1e-300);
    for col in 0..m {
        let piv = (col..m)
            .max_by(|&i, &j| a[i][col].abs().total_cmp(&a[j][col].abs()))
            .unwrap_or(col);
        a.swap(col, piv);
        b.swap(col, piv);
        if a[col][col].abs() < 1e-12 * scale {
            continue;
        }
        for r in col + 1..m {
            let f = a[r][col] / a[col][col];
            for c in col..m {
                a[r][c] -= f * a[col][c];
            }
            b[r] -= f * b[col];
        }
    }
    let mut x = [0.0; 4];
    for r in (0..m).rev() {
        if a[r][r].abs() < 1e-12 * scale {
            continue;
        }
        let mut s = b[r];
        for c in r + 1..m {
            s -= a[r][c] * x[c];
        }
        x[r] = s / a[r][r];
    }
    x
}

/// Samples per window and per hop for a series (at least 3 and 1).
pub fn window_samples(series: &RunSeries, window_s: f64, hop_s: f64) -> (usize, usize) {
    let dt = series.dt_s().max(1e-300);
    (
        ((window_s / dt).round() as usize).max(3),
        ((hop_s / dt).round() as usize).max(1),
    )
}

/// Windowed oscillation amplitude of one bearing (steps 1-2 of the module doc).
pub fn oscillation_track(
    series: &RunSeries,
    bearing: Bearing,
    spin: &Spin,
    window_s: f64,
    hop_s: f64,
) -> OscTrack {
    let (x, y) = series.rel(bearing);
    let (n_win, hop) = window_samples(series, window_s, hop_s);
    let mut track = OscTrack::default();
    let mut start = 0;
    while start + n_win <= series.len() {
        let (rx, ry) = detrend_window(&series.t_s, x, y, spin, start..start + n_win);
        let ms = rx.iter().zip(&ry).map(|(a, b)| a * a + b * b).sum::<f64>() / n_win as f64;
        track
            .t_s
            .push(0.5 * (series.t_s[start] + series.t_s[start + n_win - 1]));
        track.amp_m.push(ms.sqrt());
        start += hop;
    }
    track
}

/// Onset time from an amplitude track (steps 3-4 of the module doc), or None.
pub fn sustained_onset(
    track: &OscTrack,
    threshold_m: f64,
    min_persist_s: f64,
    gap_s: f64,
) -> Option<f64> {
    let n = track.amp_m.len();
    let above: Vec<bool> = track.amp_m.iter().map(|a| *a > threshold_m).collect();
    let mut i = 0;
    while i < n {
        if !above[i] {
            i += 1;
            continue;
        }
        // Episode from i; extend over short gaps.
        let start = i;
        let mut end = i; // last index above threshold
        let mut j = i + 1;
        while j < n {
            if above[j] {
                end = j;
            } else if track.t_s[j] - track.t_s[end] > gap_s {
                break;
            }
            j += 1;
        }
        let reaches_end = end + 1 >= n || (j >= n && track.t_s[n - 1] - track.t_s[end] <= gap_s);
        let long = track.t_s[end] - track.t_s[start] >= min_persist_s;
        let startup = start == 0;
        if startup && reaches_end {
            return Some(track.t_s[0]);
        }
        if !startup && (long || (reaches_end && end - start >= 2)) {
            let (t0, t1) = (track.t_s[start - 1], track.t_s[start]);
            let (a0, a1) = (track.amp_m[start - 1], track.amp_m[start]);
            let w = if a1 > a0 {
                ((threshold_m - a0) / (a1 - a0)).clamp(0.0, 1.0)
            } else {
                1.0
            };
            return Some(t0 + w * (t1 - t0));
        }
        i = end + 1;
    }
    None
}
