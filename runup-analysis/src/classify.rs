//! Classification of a run-up into the paper's bifurcation paths (Sections 1 and 3).
//!
//! Decision, in this order (the thresholds are the named constants below):
//! 1. **Stable**: no onset (see [`super::onset`]) up to the end of the run.
//! 2. **UnstableLowSpeed**: onset below [`LOW_SPEED_FRACTION`] of the run's top speed: the bearings never
//!    stabilise the rotor (what plain rigid air bearings do, paper Section 1).
//! 3. After the onset, whirl windows of [`WHIRL_WINDOW_S`] every [`WHIRL_HOP_S`] give, per bearing, the whirl
//!    amplitude (RMS of the detrended relative motion) and the dominant whirl frequency (signed, forward > 0).
//!    * *large*: the largest whirl amplitude exceeds [`LARGE_WHIRL_AMP_REL`] * C, or the post-onset
//!      eccentricity exceeds [`LARGE_EPS`].
//!    * *speed-proportional frequency*: the whirl frequency's speed elasticity d ln f / d ln Omega (robust
//!      Theil-Sen slope over the whirl windows of each bearing, the larger of the two) is at least
//!      [`PROPORTIONAL_ELASTICITY`].
//!    * *two frequencies*: in at least [`TWO_FREQ_MIN_FRACTION`] of the windows where both bearings whirl,
//!      their dominant frequencies differ by more than [`FREQ_SPLIT_REL`] (and one frequency bin).
//! 4. **Path2b**: large and speed-proportional (paper 3.3: eccentricities rise to critical levels, whirl
//!    frequencies rise almost linearly with speed).
//! 5. **Path1**: large, or two frequencies (paper 3.1: very large amplitudes; turbine- and compressor-side
//!    whirls with their own frequencies until a synchronisation jump; little change with speed afterwards).
//! 6. **Path2a**: otherwise: a whirl of moderate amplitude with one common frequency (paper 3.2).

use serde::{Deserialize, Serialize};

use super::onset::{self, OscTrack};
use super::series::{Bearing, RunSeries};
use super::spectrum::WhirlFrequency;

/// An onset below 10% of the top speed (200 Hz of 2000 Hz) is "at very low speed": it lies at or below the
/// rigid-body modes (125-181 Hz, paper 2.3), far below the paper's earliest Section 3 onset (767 Hz, 38%).
pub const LOW_SPEED_FRACTION: f64 = 0.10;
/// Whirl-frequency window: 40 ms gives 25 Hz bins (refined by zero padding and peak interpolation to a few
/// Hz), enough to separate two whirl lines 5% apart at the 350-900 Hz of the paper's whirls.
pub const WHIRL_WINDOW_S: f64 = 0.04;
/// Step between whirl windows (also the time resolution of the reported whirl frequencies).
pub const WHIRL_HOP_S: f64 = 0.02;
/// Lowest whirl frequency searched; below it is what the detrending leaves of the quasi-static drift.
pub const WHIRL_F_MIN_HZ: f64 = 20.0;
/// A bearing takes part in frequency comparisons only with a whirl amplitude of at least 4% of C (twice the
/// onset threshold): a weaker line's peak frequency is not trustworthy.
pub const WHIRL_ACTIVE_REL: f64 = 0.04;
/// "Very large" whirl (path 1): an orbit radius over half the minimum clearance. With the static
/// eccentricity of a loaded journal added, such an orbit reaches eps ~ 1, i.e. the trailing edges of the
/// lobes; a "rather low" path-2a whirl stays well inside.
pub const LARGE_WHIRL_AMP_REL: f64 = 0.5;
/// "Critical" eccentricity after onset (paths 1 and 2b): eps = 1 is the minimum clearance, where the gap at a
/// lobe's trailing edge closes (eps may exceed 1 elsewhere, MODEL.md 5, but only by entering a lobe's wedge).
pub const LARGE_EPS: f64 = 1.0;
/// d ln f / d ln Omega: 1 for a whirl at a fixed fraction of the speed (path 2b), ~0 for a whirl locked to a
/// rotor/ring mode (path 1 after onset: "little influence" of speed). 0.6 splits the two.
pub const PROPORTIONAL_ELASTICITY: f64 = 0.6;
/// Two whirl frequencies are distinct when they differ by more than 5% (the paper's path-2b frequencies are
/// "almost equal" before they lock; path 1's turbine and compressor lines are clearly apart).
pub const FREQ_SPLIT_REL: f64 = 0.05;
/// Share of the jointly whirling windows with distinct frequencies that makes a path-1 two-frequency regime
/// (the paper's path 1 has it for 750 of 1850 ms after onset, ~40%).
pub const TWO_FREQ_MIN_FRACTION: f64 = 0.2;
/// Start-up (journal resting on the ring, lift-off) is left out of the reported maximum eccentricities:
/// samples below this fraction of the top speed do not count, unless the run is unstable from low speed.
pub const STARTUP_SPEED_FRACTION: f64 = 0.10;

/// The outcome of a run-up.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum RunClass {
    Stable,
    Path1,
    Path2a,
    Path2b,
    UnstableLowSpeed,
    /// The run covers less than [`onset::MIN_PERSIST_S`]: no oscillation can have persisted long
    /// enough to be an onset, nor proven it would not.
    TooShort,
}

impl RunClass {
    /// The name used in `summary.json`.
    pub fn as_str(self) -> &'static str {
        match self {
            RunClass::Stable => "stable",
            RunClass::Path1 => "path1",
            RunClass::Path2a => "path2a",
            RunClass::Path2b => "path2b",
            RunClass::UnstableLowSpeed => "unstable_low_speed",
            RunClass::TooShort => "too_short",
        }
    }
}

/// Whirl amplitude and dominant frequency per bearing in one whirl window (from the onset on).
/// Frequencies are signed (forward whirl > 0) and mean something only where the amplitude is above
/// [`WHIRL_ACTIVE_REL`] * C.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct WhirlSample {
    pub t_s: f64,
    pub speed_hz: f64,
    pub f_c_hz: f64,
    pub f_t_hz: f64,
    pub amp_c_m: f64,
    pub amp_t_m: f64,
}

/// Result of [`classify`].
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Classification {
    pub class: RunClass,
    pub onset_time_s: Option<f64>,
    pub onset_speed_hz: Option<f64>,
    /// "C" or "T": the bearing whose oscillation crossed the threshold first.
    pub first_bearing: Option<String>,
    /// Maximum eccentricity ratios |dr| / C above [`STARTUP_SPEED_FRACTION`] of top speed.
    pub max_eps_c: f64,
    pub max_eps_t: f64,
    pub whirl: Vec<WhirlSample>,
    /// Why: the measured features against the thresholds, human-readable.
    pub criteria: String,
    /// Every criterion with its value, bound and relative margin (docs/classification.md).
    #[serde(default)]
    pub margins: Vec<Criterion>,
    /// A criterion that decided the class lies within [`BORDERLINE_MARGIN`] of its bound: a
    /// slightly different run (disturbance, ramp, mesh) may fall into the neighbouring class.
    #[serde(default)]
    pub borderline: bool,
}

/// A deciding criterion closer than this (relative) to its bound makes the class borderline.
pub const BORDERLINE_MARGIN: f64 = 0.10;

/// One criterion of the decision.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Criterion {
    /// What is measured, in the engineer's terms (e.g. "whirl amplitude / C").
    pub name: String,
    /// Its value in this run (None where it could not be measured, e.g. too few whirl windows).
    pub value: Option<f64>,
    /// The class boundary.
    pub bound: f64,
    /// (value - bound) / bound: positive above the bound.
    pub margin: Option<f64>,
    /// Crossing the bound alone would change the class.
    pub deciding: bool,
}

impl Criterion {
    fn new(name: &str, value: Option<f64>, bound: f64, deciding: bool) -> Self {
        Criterion {
            name: name.to_string(),
            value,
            bound,
            margin: value.map(|v| (v - bound) / bound),
            deciding: deciding && value.is_some(),
        }
    }
}

/// True if a deciding criterion lies within [`BORDERLINE_MARGIN`] of its bound.
pub fn is_borderline(margins: &[Criterion]) -> bool {
    margins
        .iter()
        .any(|c| c.deciding && c.margin.is_some_and(|m| m.abs() < BORDERLINE_MARGIN))
}

/// The bounds of the decision (the constants above by default); `classify_with` takes others for
/// the sensitivity of a study's map to each bound (`airring sweep-sensitivity`).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Bounds {
    /// Onset: oscillation amplitude / C ([`onset::ONSET_AMP_REL`]).
    pub onset_amp_rel: f64,
    pub low_speed_fraction: f64,
    pub large_whirl_amp_rel: f64,
    pub large_eps: f64,
    pub proportional_elasticity: f64,
    pub two_freq_min_fraction: f64,
}

impl Default for Bounds {
    fn default() -> Self {
        Bounds {
            onset_amp_rel: onset::ONSET_AMP_REL,
            low_speed_fraction: LOW_SPEED_FRACTION,
            large_whirl_amp_rel: LARGE_WHIRL_AMP_REL,
            large_eps: LARGE_EPS,
            proportional_elasticity: PROPORTIONAL_ELASTICITY,
            two_freq_min_fraction: TWO_FREQ_MIN_FRACTION,
        }
    }
}

impl Bounds {
    /// The bounds' names, as `scaled` takes them.
    pub const NAMES: [&'static str; 6] = [
        "onset_amp_rel",
        "low_speed_fraction",
        "large_whirl_amp_rel",
        "large_eps",
        "proportional_elasticity",
        "two_freq_min_fraction",
    ];

    /// A copy with bound `name` multiplied by `factor`.
    pub fn scaled(&self, name: &str, factor: f64) -> Option<Bounds> {
        let mut b = *self;
        let f = match name {
            "onset_amp_rel" => &mut b.onset_amp_rel,
            "low_speed_fraction" => &mut b.low_speed_fraction,
            "large_whirl_amp_rel" => &mut b.large_whirl_amp_rel,
            "large_eps" => &mut b.large_eps,
            "proportional_elasticity" => &mut b.proportional_elasticity,
            "two_freq_min_fraction" => &mut b.two_freq_min_fraction,
            _ => return None,
        };
        *f *= factor;
        Some(b)
    }
}

/// The class of an unstable run from its three features (module documentation, steps 4-6).
pub fn path_class(large: bool, proportional: bool, two_freq: bool) -> RunClass {
    if large && proportional {
        RunClass::Path2b
    } else if large || two_freq {
        RunClass::Path1
    } else {
        RunClass::Path2a
    }
}

/// The onset thresholds in um: one figure when both bearings share it, else C and T.
fn threshold_text(thr: [f64; 2]) -> String {
    if thr[0] == thr[1] {
        format!("{:.3} um", thr[0] * 1e6)
    } else {
        format!("C {:.3} um, T {:.3} um", thr[0] * 1e6, thr[1] * 1e6)
    }
}

/// Classify one run-up (see the module documentation for the criteria).
pub fn classify(series: &RunSeries) -> Classification {
    classify_with(series, &Bounds::default())
}

/// `classify` with other bounds.
pub fn classify_with(series: &RunSeries, b: &Bounds) -> Classification {
    series.check();
    // Thresholds scale with each bearing's own clearance.
    let cl = series.clearance_m;
    let spin = series.spin();
    let thr = cl.map(|c| b.onset_amp_rel * c);
    let tracks: Vec<OscTrack> = Bearing::BOTH
        .iter()
        .map(|b| onset::oscillation_track(series, *b, &spin, onset::AMP_WINDOW_S, onset::AMP_HOP_S))
        .collect();
    let onsets: Vec<Option<f64>> = tracks
        .iter()
        .zip(thr)
        .map(|(tr, thr)| onset::sustained_onset(tr, thr, onset::MIN_PERSIST_S, onset::GAP_BRIDGE_S))
        .collect();
    let eps = [series.eps(Bearing::C), series.eps(Bearing::T)];
    let top_hz = series.max_speed_hz();
    let speed = series.speed_hz();

    let first = match (onsets[0], onsets[1]) {
        (None, None) => None,
        (Some(tc), None) => Some((tc, Bearing::C)),
        (None, Some(tt)) => Some((tt, Bearing::T)),
        (Some(tc), Some(tt)) => {
            if (tc - tt).abs() < onset::AMP_HOP_S {
                // A tie within the time resolution: the bearing with the larger oscillation just after it.
                let after =
                    |tr: &OscTrack| mean_over(tr, tc.min(tt), tc.min(tt) + onset::MIN_PERSIST_S);
                let b = if after(&tracks[1]) > after(&tracks[0]) {
                    Bearing::T
                } else {
                    Bearing::C
                };
                Some((tc.min(tt), b))
            } else if tt < tc {
                Some((tt, Bearing::T))
            } else {
                Some((tc, Bearing::C))
            }
        }
    };

    let max_eps_from = |t_from: f64, low_speed_ok: bool| -> [f64; 2] {
        let mut m = [0.0_f64; 2];
        for i in 0..series.len() {
            if series.t_s[i] < t_from
                || (!low_speed_ok && speed[i] < STARTUP_SPEED_FRACTION * top_hz)
            {
                continue;
            }
            m[0] = m[0].max(eps[0][i]);
            m[1] = m[1].max(eps[1][i]);
        }
        m
    };

    let duration_s =
        series.t_s.last().copied().unwrap_or(0.0) - series.t_s.first().copied().unwrap_or(0.0);
    if duration_s < onset::MIN_PERSIST_S {
        let m = max_eps_from(f64::NEG_INFINITY, true);
        return Classification {
            class: RunClass::TooShort,
            onset_time_s: None,
            onset_speed_hz: None,
            first_bearing: None,
            max_eps_c: m[0],
            max_eps_t: m[1],
            whirl: Vec::new(),
            criteria: format!(
                "too short to classify: the run covers {duration_s:.4} s, less than the {} s an \
                 oscillation must persist to count as an onset (run to at least {} s)",
                onset::MIN_PERSIST_S,
                onset::MIN_PERSIST_S
            ),
            margins: vec![Criterion::new(
                "run duration [s]",
                Some(duration_s),
                onset::MIN_PERSIST_S,
                false,
            )],
            borderline: false,
        };
    }
    let Some((t_on, first_b)) = first else {
        let m = max_eps_from(f64::NEG_INFINITY, false);
        // The largest oscillation after start-up against the onset threshold: deciding (it is what
        // would make an onset; persistence comes on top).
        let largest = (max_after_startup(&tracks[0], series) / cl[0])
            .max(max_after_startup(&tracks[1], series) / cl[1]);
        let margins = vec![Criterion::new(
            "oscillation amplitude after start-up / C",
            Some(largest),
            b.onset_amp_rel,
            true,
        )];
        return Classification {
            borderline: is_borderline(&margins),
            margins,
            class: RunClass::Stable,
            onset_time_s: None,
            onset_speed_hz: None,
            first_bearing: None,
            max_eps_c: m[0],
            max_eps_t: m[1],
            whirl: Vec::new(),
            criteria: format!(
                "stable: no oscillation about the quasi-static equilibrium above {} C ({}) lasting {} s at \
                 either bearing up to {:.0} Hz (largest after start-up: C {:.4} C, T {:.4} C)",
                b.onset_amp_rel,
                threshold_text(thr),
                onset::MIN_PERSIST_S,
                top_hz,
                max_after_startup(&tracks[0], series) / cl[0],
                max_after_startup(&tracks[1], series) / cl[1],
            ),
        };
    };
    let onset_speed = series.speed_hz_at(t_on);
    let low_speed = onset_speed < b.low_speed_fraction * top_hz;
    let m = max_eps_from(f64::NEG_INFINITY, low_speed);
    let onset_text = format!(
        "onset at {:.4} s ({:.0} Hz, {:.0}% of top speed), bearing {} first (oscillation > {} C sustained >= {} s; \
         onsets C {}, T {})",
        t_on,
        onset_speed,
        100.0 * onset_speed / top_hz.max(1e-300),
        first_b.label(),
        b.onset_amp_rel,
        onset::MIN_PERSIST_S,
        fmt_opt(onsets[0]),
        fmt_opt(onsets[1]),
    );

    let whirl = whirl_samples(series, &spin, t_on);
    let feat = features(&whirl, series, &eps, t_on);
    let margins = unstable_margins(&feat, onset_speed / top_hz.max(1e-300), low_speed, b);
    let (class, why) = if low_speed {
        (
            RunClass::UnstableLowSpeed,
            format!("onset below {} of top speed", b.low_speed_fraction),
        )
    } else {
        let large = feat.max_amp_rel > b.large_whirl_amp_rel || feat.max_eps_after > b.large_eps;
        let proportional = feat
            .elasticity
            .is_some_and(|e| e >= b.proportional_elasticity);
        let two_freq = feat
            .two_freq_fraction
            .is_some_and(|f| f >= b.two_freq_min_fraction);
        let class = path_class(large, proportional, two_freq);
        let why = format!(
            "large={large} (max whirl amplitude {:.3} C vs {}, max eps after onset {:.3} vs {}); \
             speed-proportional={proportional} (whirl-frequency elasticity {} vs {}); \
             two-frequencies={two_freq} (share of joint whirl windows with frequencies > {}% apart {} vs {})",
            feat.max_amp_rel,
            b.large_whirl_amp_rel,
            feat.max_eps_after,
            b.large_eps,
            fmt_opt(feat.elasticity),
            b.proportional_elasticity,
            100.0 * FREQ_SPLIT_REL,
            fmt_opt(feat.two_freq_fraction),
            b.two_freq_min_fraction,
        );
        (class, why)
    };
    Classification {
        class,
        onset_time_s: Some(t_on),
        onset_speed_hz: Some(onset_speed),
        first_bearing: Some(first_b.label().to_string()),
        max_eps_c: m[0],
        max_eps_t: m[1],
        whirl,
        criteria: format!("{}: {onset_text}; {why}", class.as_str()),
        borderline: is_borderline(&margins),
        margins,
    }
}

/// The criteria of a run with an onset: the onset speed against the low-speed bound, then the
/// features of the whirl against theirs; each marked deciding if crossing its bound alone would
/// change the class.
fn unstable_margins(
    feat: &Features,
    onset_fraction: f64,
    low_speed: bool,
    b: &Bounds,
) -> Vec<Criterion> {
    let amp = feat.max_amp_rel > b.large_whirl_amp_rel;
    let eps = feat.max_eps_after > b.large_eps;
    let prop = feat
        .elasticity
        .is_some_and(|e| e >= b.proportional_elasticity);
    let two = feat
        .two_freq_fraction
        .is_some_and(|f| f >= b.two_freq_min_fraction);
    let class = path_class(amp || eps, prop, two);
    // The class with one criterion's outcome flipped (and the low-speed step passed).
    let flips =
        |a: bool, e: bool, p: bool, t: bool| !low_speed && path_class(a || e, p, t) != class;
    vec![
        Criterion::new(
            "onset speed / top speed",
            Some(onset_fraction),
            b.low_speed_fraction,
            true,
        ),
        Criterion::new(
            "whirl amplitude / C",
            Some(feat.max_amp_rel),
            b.large_whirl_amp_rel,
            flips(!amp, eps, prop, two),
        ),
        Criterion::new(
            "eccentricity after onset (1 - h_min / C at the lobe trailing edge)",
            Some(feat.max_eps_after),
            b.large_eps,
            flips(amp, !eps, prop, two),
        ),
        Criterion::new(
            "whirl-frequency elasticity d ln f / d ln Omega",
            feat.elasticity,
            b.proportional_elasticity,
            flips(amp, eps, !prop, two),
        ),
        Criterion::new(
            "share of whirl windows with two frequencies",
            feat.two_freq_fraction,
            b.two_freq_min_fraction,
            flips(amp, eps, prop, !two),
        ),
    ]
}

fn fmt_opt(v: Option<f64>) -> String {
    v.map_or_else(|| "n/a".to_string(), |v| format!("{v:.3}"))
}

fn mean_over(tr: &OscTrack, t0: f64, t1: f64) -> f64 {
    let v: Vec<f64> = tr
        .t_s
        .iter()
        .zip(&tr.amp_m)
        .filter(|(t, _)| **t >= t0 && **t <= t1)
        .map(|(_, a)| *a)
        .collect();
    if v.is_empty() {
        0.0
    } else {
        v.iter().sum::<f64>() / v.len() as f64
    }
}

/// Largest windowed oscillation amplitude once the rotor is past start-up speed (for the "stable" reason).
fn max_after_startup(tr: &OscTrack, series: &RunSeries) -> f64 {
    let top = series.max_speed_hz();
    tr.t_s
        .iter()
        .zip(&tr.amp_m)
        .filter(|(t, _)| series.speed_hz_at(**t) >= STARTUP_SPEED_FRACTION * top)
        .fold(0.0, |m, (_, a)| m.max(*a))
}

/// Whirl windows from the onset to the end of the run.
fn whirl_samples(series: &RunSeries, spin: &super::series::Spin, t_on: f64) -> Vec<WhirlSample> {
    let (n_win, hop) = onset::window_samples(series, WHIRL_WINDOW_S, WHIRL_HOP_S);
    let dt = series.dt_s();
    let mut out = Vec::new();
    let mut start = series.t_s.partition_point(|t| *t < t_on);
    // Zero padding to 8x the window for a peak interpolation accurate to a fraction of a bin.
    let mut whirl_hz = WhirlFrequency::new(8 * n_win);
    while start + n_win <= series.len() {
        let mut amp = [0.0; 2];
        let mut f = [0.0; 2];
        for (k, b) in Bearing::BOTH.iter().enumerate() {
            let (x, y) = series.rel(*b);
            let (rx, ry) = onset::detrend_window(&series.t_s, x, y, spin, start..start + n_win);
            amp[k] =
                (rx.iter().zip(&ry).map(|(a, b)| a * a + b * b).sum::<f64>() / n_win as f64).sqrt();
            f[k] = whirl_hz.dominant_hz(&rx, &ry, dt, WHIRL_F_MIN_HZ);
        }
        let t = 0.5 * (series.t_s[start] + series.t_s[start + n_win - 1]);
        out.push(WhirlSample {
            t_s: t,
            speed_hz: series.speed_hz_at(t),
            f_c_hz: f[0],
            f_t_hz: f[1],
            amp_c_m: amp[0],
            amp_t_m: amp[1],
        });
        start += hop;
    }
    out
}

/// The measured features of step 3 of the module documentation.
#[derive(Debug, Clone, Default)]
struct Features {
    max_amp_rel: f64,
    max_eps_after: f64,
    elasticity: Option<f64>,
    two_freq_fraction: Option<f64>,
}

fn features(whirl: &[WhirlSample], series: &RunSeries, eps: &[Vec<f64>; 2], t_on: f64) -> Features {
    let cl = series.clearance_m;
    let active = cl.map(|c| WHIRL_ACTIVE_REL * c);
    let mut feat = Features::default();
    for w in whirl {
        feat.max_amp_rel = feat
            .max_amp_rel
            .max(w.amp_c_m / cl[0])
            .max(w.amp_t_m / cl[1]);
    }
    for i in series.t_s.partition_point(|t| *t < t_on)..series.len() {
        feat.max_eps_after = feat.max_eps_after.max(eps[0][i]).max(eps[1][i]);
    }
    // Speed elasticity per bearing over its active windows.
    let mut best: Option<f64> = None;
    for k in 0..2 {
        let pts: Vec<(f64, f64)> = whirl
            .iter()
            .filter_map(|w| {
                let (f, a) = if k == 0 {
                    (w.f_c_hz, w.amp_c_m)
                } else {
                    (w.f_t_hz, w.amp_t_m)
                };
                (a > active[k] && f.abs() > 0.0 && w.speed_hz > 0.0)
                    .then(|| (w.speed_hz.ln(), f.abs().ln()))
            })
            .collect();
        if pts.len() < 5 {
            continue;
        }
        let (lo, hi) = pts
            .iter()
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(l, h), p| {
                (l.min(p.0), h.max(p.0))
            });
        // Needs a speed span of 10% to say anything about a slope.
        if hi - lo < 1.1_f64.ln() {
            continue;
        }
        if let Some(e) = theil_sen(&pts) {
            best = Some(best.map_or(e, |b: f64| b.max(e)));
        }
    }
    feat.elasticity = best;
    // Two distinct frequencies where both bearings whirl.
    let bin_hz = 1.0 / WHIRL_WINDOW_S;
    let joint: Vec<&WhirlSample> = whirl
        .iter()
        .filter(|w| w.amp_c_m > active[0] && w.amp_t_m > active[1])
        .collect();
    if !joint.is_empty() {
        let split = joint
            .iter()
            .filter(|w| {
                let df = (w.f_c_hz - w.f_t_hz).abs();
                df > (FREQ_SPLIT_REL * w.f_c_hz.abs().max(w.f_t_hz.abs())).max(bin_hz)
            })
            .count();
        feat.two_freq_fraction = Some(split as f64 / joint.len() as f64);
    }
    feat
}

/// Theil-Sen slope: the median of all pairwise slopes (robust against the frequency jumps of a
/// synchronisation and against the growth phase right after onset).
fn theil_sen(pts: &[(f64, f64)]) -> Option<f64> {
    let mut slopes = Vec::new();
    for i in 0..pts.len() {
        for j in i + 1..pts.len() {
            let dx = pts[j].0 - pts[i].0;
            if dx.abs() > 1e-12 {
                slopes.push((pts[j].1 - pts[i].1) / dx);
            }
        }
    }
    if slopes.is_empty() {
        return None;
    }
    slopes.sort_by(f64::total_cmp);
    Some(slopes[slopes.len() / 2])
}
