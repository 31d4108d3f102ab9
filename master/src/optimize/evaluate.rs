//! One candidate design evaluated at its tolerance corners, cheapest stage first.
//!
//! 1. **Linear** (`crate::stability`, in-process, a fraction of a second per corner): the static
//!    equilibria over the speed range (their film thickness and friction power) and the linear
//!    threshold speed. A corner whose static film is already below the limit fails here; a corner
//!    stable over the whole range (no threshold up to [`LINEAR_MARGIN`] above it) is decided
//!    here: no self-excited whirl, its film thickness the equilibria's.
//! 2. **Nonlinear**: the corners the linear stage leaves open (unstable somewhere in the range)
//!    run up to f_max and down again (`profile 0:0, T:f_max, 2T:0`: the run-down catches
//!    hysteresis and whirls that coexist with the stable equilibrium) as run-ups of a study,
//!    through the sweep machinery (`crate::sweep`, `--jobs` at a time, resumable). Their film
//!    thickness, whirl amplitude and class are read from the run folders.
//!
//! A candidate is feasible when every corner meets the requirement; each corner records the stage
//! that decided it and why.

use super::problem::{Objective, Problem, Quantity};
use crate::analysis::{Bearing, RunSeries};
use crate::summary::{RunStatus, RunSummary};
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;
use std::path::Path;

/// The linear stage calls a corner stable only if no threshold lies below the top of the
/// range times (1 + this): a margin for the linear stage's coarse film mesh, whose thresholds
/// lie within a few percent of the paper mesh's (docs/stability.md).
pub const LINEAR_MARGIN: f64 = 0.10;

/// serde_json writes a NaN (a quantity not measured) as null: read back as NaN.
fn nan_if_null<'de, D: serde::Deserializer<'de>>(d: D) -> Result<f64, D::Error> {
    Ok(Option::<f64>::deserialize(d)?.unwrap_or(f64::NAN))
}

fn nans_if_null<'de, D: serde::Deserializer<'de>>(d: D) -> Result<Vec<f64>, D::Error> {
    Ok(Vec::<Option<f64>>::deserialize(d)?
        .into_iter()
        .map(|v| v.unwrap_or(f64::NAN))
        .collect())
}

#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Stage {
    Linear,
    Nonlinear,
}

/// The linear stage's answer at one corner.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct LinearResult {
    /// The threshold speed [Hz], None if stable up to the grid's top.
    pub threshold_hz: Option<f64>,
    /// Unstable from the lowest speed of the range on.
    pub unstable_from_start: bool,
    /// The smallest static film thickness over the range, both bearings [um].
    #[serde(deserialize_with = "nan_if_null")]
    pub static_film_um: f64,
    /// Friction power of both films at the operating speed [W].
    #[serde(deserialize_with = "nan_if_null")]
    pub power_loss_w: f64,
    pub error: Option<String>,
}

/// The nonlinear stage's answer at one corner (a run-up and run-down).
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct NonlinearResult {
    /// The run folder's name (under `nonlinear/runs/`).
    pub run: String,
    pub class: Option<String>,
    pub onset_hz: Option<f64>,
    /// The smallest film thickness within the speed range, run-up and run-down [um].
    #[serde(deserialize_with = "nan_if_null")]
    pub min_film_um: f64,
    /// The largest whirl amplitude within the speed range [um].
    #[serde(deserialize_with = "nan_if_null")]
    pub whirl_um: f64,
    /// The run-up halted at its film or whirl limit (`runup --halt-film`, `--halt-whirl`):
    /// where. Its film thickness, whirl amplitude and class are those up to there.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub halted: Option<String>,
    pub error: Option<String>,
}

#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Corner {
    /// "nominal" or the toleranced keys at their low (-) or high (+) ends, e.g. "C- c+".
    pub label: String,
    pub args: BTreeMap<String, String>,
    pub linear: LinearResult,
    pub nonlinear: Option<NonlinearResult>,
    pub stage: Stage,
    #[serde(deserialize_with = "nan_if_null")]
    pub min_film_um: f64,
    #[serde(deserialize_with = "nan_if_null")]
    pub whirl_um: f64,
    pub class: Option<String>,
    pub ok: bool,
    /// Why it passes or fails, in the engineer's terms.
    pub reason: String,
}

/// One evaluated candidate.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Candidate {
    pub index: usize,
    /// The variables' nominal values (own units, the problem's order).
    pub x: Vec<f64>,
    pub corners: Vec<Corner>,
    /// The stage that decided the candidate: the last one any corner needed.
    pub stage: Stage,
    pub feasible: bool,
    pub reason: String,
    /// Worst over the corners.
    #[serde(deserialize_with = "nan_if_null")]
    pub min_film_um: f64,
    #[serde(deserialize_with = "nan_if_null")]
    pub whirl_um: f64,
    pub threshold_hz: Option<f64>,
    #[serde(deserialize_with = "nan_if_null")]
    pub power_loss_w: f64,
    /// The normalized distance to the nearest limit (> 0 inside, < 0 violated).
    #[serde(deserialize_with = "nan_if_null")]
    pub margin: f64,
    /// The objectives' values (own sign and units).
    #[serde(deserialize_with = "nans_if_null")]
    pub objectives: Vec<f64>,
    /// The constraints the search sees (<= 0 feasible).
    #[serde(deserialize_with = "nans_if_null")]
    pub constraints: Vec<f64>,
    /// The point as the search asked for it, before `x` was rounded: what the search is given
    /// back on resume, so that it asks for what it would have asked had it run through.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub asked: Vec<f64>,
}

/// The speeds of the linear stage: the range on its step, extended by [`LINEAR_MARGIN`], and
/// the operating speed.
pub fn linear_grid(p: &Problem) -> Vec<f64> {
    let (lo, hi) = p.speed_range_hz;
    let top = hi * (1.0 + LINEAR_MARGIN);
    let n = ((top - lo) / p.linear_step_hz).ceil().max(1.0) as usize;
    let mut grid: Vec<f64> = (0..=n)
        .map(|i| lo + (top - lo) * i as f64 / n as f64)
        .collect();
    grid.push(p.operating_speed_hz);
    grid.sort_by(f64::total_cmp);
    grid.dedup_by(|a, b| (*a - *b).abs() < 1e-9);
    grid
}

/// The linear stage at one corner.
pub fn linear_stage(p: &Problem, args: &BTreeMap<String, String>) -> LinearResult {
    let mut args = args.clone();
    args.insert(
        "mesh".into(),
        format!("{}x{}", p.linear_mesh.0, p.linear_mesh.1),
    );
    let grid = linear_grid(p);
    let result = crate::sweep::linear::settings_for(&args).and_then(|s| {
        let r = crate::stability::analyse(&s, &grid)?;
        Ok(r)
    });
    let r = match result {
        Ok(r) => r,
        Err(e) => {
            return LinearResult {
                static_film_um: f64::NAN,
                power_loss_w: f64::NAN,
                error: Some(e),
                ..Default::default()
            }
        }
    };
    let (lo, hi) = p.speed_range_hz;
    let in_range = |f: f64| f >= lo - 1e-9 && f <= hi + 1e-9;
    let static_film_um = r
        .speeds
        .iter()
        .filter(|s| in_range(s.speed_hz))
        .flat_map(|s| s.bearings.iter().map(|b| b.h_min_um))
        .fold(f64::INFINITY, f64::min);
    let power_loss_w = r
        .speeds
        .iter()
        .find(|s| (s.speed_hz - p.operating_speed_hz).abs() < 1e-9)
        .map_or(f64::NAN, |s| {
            s.bearings.iter().map(|b| b.power_loss_w).sum()
        });
    LinearResult {
        threshold_hz: if r.unstable_at_first_speed {
            Some(lo)
        } else {
            r.threshold.as_ref().map(|t| t.speed_hz)
        },
        unstable_from_start: r.unstable_at_first_speed,
        static_film_um,
        power_loss_w,
        error: None,
    }
}

/// The linear stage's decision at a corner: Some(ok, reason) if it decides, None if the corner
/// needs a run-up.
pub fn linear_decision(p: &Problem, l: &LinearResult) -> Option<(bool, String)> {
    if let Some(e) = &l.error {
        return Some((false, format!("linear analysis failed: {e}")));
    }
    if l.static_film_um < p.min_film_um {
        return Some((
            false,
            format!(
                "static film {:.2} um below the limit {} um (linear stage)",
                l.static_film_um, p.min_film_um
            ),
        ));
    }
    let top = p.speed_range_hz.1 * (1.0 + LINEAR_MARGIN);
    match l.threshold_hz {
        Some(t) if t <= top => None,
        _ if !p.classes.is_empty() && !p.classes.iter().any(|c| c == "stable") => Some((
            false,
            "stable over the range, and 'stable' is not an allowed class (linear stage)".into(),
        )),
        _ => Some((
            true,
            format!(
                "linearly stable up to {top:.0} Hz, static film {:.2} um (linear stage)",
                l.static_film_um
            ),
        )),
    }
}

/// The film thickness and whirl amplitude of a finished run-up and run-down within the speed
/// range: (min film [um], max whirl [um]). The whirl amplitude is the run-up classifier's: the
/// RMS of the journal's motion relative to its ring about its slowly moving mean, in windows of
/// `WHIRL_WINDOW_S`, the larger of the two bearings.
pub fn run_metrics(dir: &Path, range_hz: (f64, f64)) -> Result<(f64, f64), String> {
    let summary =
        RunSummary::read(dir).ok_or_else(|| format!("{}: no summary.json", dir.display()))?;
    let cl = summary
        .clearance_um
        .ok_or_else(|| format!("{}: summary.json has no clearances", dir.display()))?;
    let series = crate::analysis::load_run(dir, [cl.c * 1e-6, cl.t * 1e-6])?;
    let whirl = max_whirl_m(&series, range_hz) * 1e6;
    let film = min_film_m(dir, range_hz)? * 1e6;
    Ok((film, whirl))
}

fn in_range(f: f64, (lo, hi): (f64, f64)) -> bool {
    f >= lo && f <= hi
}

/// The largest windowed oscillation amplitude of either bearing whose window centre lies in the
/// speed range [m].
pub fn max_whirl_m(series: &RunSeries, range_hz: (f64, f64)) -> f64 {
    use crate::analysis::classify::{WHIRL_HOP_S, WHIRL_WINDOW_S};
    let spin = series.spin();
    let mut worst: f64 = 0.0;
    for b in Bearing::BOTH {
        let track = crate::analysis::onset::oscillation_track(
            series,
            b,
            &spin,
            WHIRL_WINDOW_S,
            WHIRL_HOP_S,
        );
        for (t, a) in track.t_s.iter().zip(&track.amp_m) {
            if in_range(series.speed_hz_at(*t), range_hz) {
                worst = worst.max(*a);
            }
        }
    }
    worst
}

/// The smallest recorded film thickness (`film_C.h_min`, `film_T.h_min`) at speeds in the range
/// [m], from the run's timeseries.csv.
pub fn min_film_m(dir: &Path, range_hz: (f64, f64)) -> Result<f64, String> {
    let path = dir.join("timeseries.csv");
    let text = std::fs::read_to_string(&path).map_err(|e| format!("{}: {e}", path.display()))?;
    let mut lines = text.lines();
    let header: Vec<&str> = lines
        .next()
        .ok_or_else(|| format!("{}: empty", path.display()))?
        .split(',')
        .collect();
    let col = |name: &str| -> Result<usize, String> {
        header
            .iter()
            .position(|h| h.split_whitespace().next() == Some(name))
            .ok_or_else(|| format!("{}: no column {name}", path.display()))
    };
    let omega = col("rotor.omega")?;
    let films = [col("film_C.h_min")?, col("film_T.h_min")?];
    let mut worst = f64::INFINITY;
    for line in lines {
        let v: Vec<&str> = line.split(',').collect();
        let num = |i: usize| v.get(i).and_then(|s| s.trim().parse::<f64>().ok());
        let Some(w) = num(omega) else { continue };
        if !in_range(w / std::f64::consts::TAU, range_hz) {
            continue;
        }
        for &c in &films {
            if let Some(h) = num(c) {
                worst = worst.min(h);
            }
        }
    }
    if worst.is_finite() {
        Ok(worst)
    } else {
        Err(format!(
            "{}: no sample within {:.0}-{:.0} Hz",
            path.display(),
            range_hz.0,
            range_hz.1
        ))
    }
}

/// The nonlinear stage's result from a finished run folder.
pub fn nonlinear_result(dir: &Path, run: &str, range_hz: (f64, f64)) -> NonlinearResult {
    let summary = RunSummary::read(dir);
    let mut r = NonlinearResult {
        run: run.into(),
        min_film_um: f64::NAN,
        whirl_um: f64::NAN,
        ..Default::default()
    };
    match summary {
        Some(s) if s.status == RunStatus::Completed => {
            // A halted run-up's class is that of its part before the halt (a whirl halted at
            // its limit has not grown into its path yet): said so wherever it is shown.
            r.class = match (&s.classification, &s.halted) {
                (Some(c), Some(_)) => Some(format!("{c} (up to the halt)")),
                (c, None) => c.clone(),
                (None, Some(_)) => None,
            };
            r.onset_hz = s.onset_speed_hz;
            r.halted = s.halted.clone();
            match run_metrics(dir, range_hz) {
                Ok((film, whirl)) => {
                    r.min_film_um = film;
                    r.whirl_um = whirl;
                }
                Err(e) => r.error = Some(e),
            }
        }
        Some(s) => {
            r.error = Some(
                s.error
                    .unwrap_or_else(|| format!("the run-up ended {}", s.status.as_str())),
            )
        }
        None => r.error = Some(format!("{}: no summary.json", dir.display())),
    }
    r
}

/// The nonlinear stage's decision at a corner.
pub fn nonlinear_decision(p: &Problem, n: &NonlinearResult) -> (bool, String) {
    if let Some(e) = &n.error {
        return (false, format!("run-up failed: {e}"));
    }
    let mut why = vec![];
    if n.min_film_um < p.min_film_um {
        why.push(format!(
            "film {:.2} um below {} um",
            n.min_film_um, p.min_film_um
        ));
    }
    if let Some(lim) = p.max_whirl_um {
        if n.whirl_um > lim {
            why.push(format!("whirl {:.2} um above {lim} um", n.whirl_um));
        }
    }
    let class = n.class.as_deref().unwrap_or("unclassified");
    if !p.classes.is_empty() && n.halted.is_none() && !p.classes.iter().any(|c| c == class) {
        why.push(format!("class {class} not allowed"));
    }
    // A run that halted crossed the film or whirl limit, even where its series cannot show it
    // (a film thickness that is not a number): never feasible on the part of a run.
    if let (Some(h), true) = (&n.halted, why.is_empty()) {
        why.push(format!("halted: {h}"));
    }
    if why.is_empty() {
        (
            true,
            format!(
                "{class}, film {:.2} um, whirl {:.2} um (run-up and run-down)",
                n.min_film_um, n.whirl_um
            ),
        )
    } else if n.halted.is_some() {
        (
            false,
            format!("{} (the run-up halted at a limit)", why.join(", ")),
        )
    } else {
        (false, format!("{} (run-up and run-down)", why.join(", ")))
    }
}

/// The reason of a corner the linear stage left open and that was not run: another corner of
/// its candidate already fails.
pub const NOT_RUN: &str = "not run: another corner already fails";

/// A corner's final values from its stages.
pub fn decide_corner(p: &Problem, c: &mut Corner) {
    match (&c.nonlinear, linear_decision(p, &c.linear)) {
        (Some(n), _) => {
            let (ok, reason) = nonlinear_decision(p, n);
            c.stage = Stage::Nonlinear;
            c.min_film_um = n.min_film_um;
            c.whirl_um = n.whirl_um;
            c.class = n.class.clone();
            c.ok = ok;
            c.reason = reason;
        }
        (None, Some((ok, reason))) => {
            c.stage = Stage::Linear;
            c.min_film_um = c.linear.static_film_um;
            // Stable: no self-excited whirl. Statically too thin: not measured.
            c.whirl_um = if ok { 0.0 } else { f64::NAN };
            c.class = ok.then(|| "stable".into());
            c.ok = ok;
            c.reason = reason;
        }
        (None, None) => {
            c.stage = Stage::Linear;
            c.ok = false;
            c.reason = NOT_RUN.into();
        }
    }
}

/// The candidate's worst values, objectives and constraints from its decided corners.
pub fn summarize(p: &Problem, index: usize, x: Vec<f64>, corners: Vec<Corner>) -> Candidate {
    let feasible = corners.iter().all(|c| c.ok);
    let stage = if corners.iter().any(|c| c.stage == Stage::Nonlinear) {
        Stage::Nonlinear
    } else {
        Stage::Linear
    };
    // The first corner that decided the candidate (not one left unrun because of it).
    let failed = corners
        .iter()
        .find(|c| !c.ok && c.reason != NOT_RUN)
        .or_else(|| corners.iter().find(|c| !c.ok));
    let reason = match failed {
        Some(c) => format!("{}: {}", c.label, c.reason),
        None => format!(
            "all {} corners meet the requirement ({})",
            corners.len(),
            if stage == Stage::Linear {
                "decided by the linear stage"
            } else {
                "run-ups where the linear stage found an instability"
            }
        ),
    };
    // Worst over the corners measured: a candidate that failed at one corner has the others
    // unrun, and a statically too thin corner no whirl amplitude; NaN if none was measured.
    let worst = |f: &dyn Fn(&Corner) -> f64, max: bool| -> f64 {
        let vals: Vec<f64> = corners.iter().map(f).filter(|v| !v.is_nan()).collect();
        if vals.is_empty() {
            return f64::NAN;
        }
        if max {
            vals.into_iter().fold(f64::NEG_INFINITY, f64::max)
        } else {
            vals.into_iter().fold(f64::INFINITY, f64::min)
        }
    };
    let min_film_um = worst(&|c| c.min_film_um, false);
    let whirl_um = worst(&|c| c.whirl_um, true);
    let top = p.speed_range_hz.1 * (1.0 + LINEAR_MARGIN);
    let threshold_hz = corners
        .iter()
        .map(|c| c.linear.threshold_hz.unwrap_or(top).min(top))
        .reduce(f64::min);
    let power_loss_w = corners.first().map_or(f64::NAN, |c| c.linear.power_loss_w);
    let film_c = 1.0 - min_film_um / p.min_film_um;
    let whirl_c = p.max_whirl_um.map(|lim| whirl_um / lim - 1.0);
    let class_c = (!p.classes.is_empty()).then(|| {
        let allowed = corners
            .iter()
            .all(|c| c.class.as_ref().is_some_and(|k| p.classes.contains(k)));
        if allowed {
            -1.0
        } else {
            1.0
        }
    });
    let mut constraints = vec![film_c];
    constraints.extend(whirl_c);
    constraints.extend(class_c);
    // The margin: how far the worst limit is from being reached (the film's and the whirl's
    // normalized distances; the class is a yes or no).
    let margin = -film_c.max(whirl_c.unwrap_or(f64::NEG_INFINITY));
    let margin = if feasible || margin.is_nan() {
        margin
    } else {
        margin.min(0.0)
    };
    let mut c = Candidate {
        asked: vec![],
        index,
        x,
        corners,
        stage,
        feasible,
        reason,
        min_film_um,
        whirl_um,
        threshold_hz,
        power_loss_w,
        margin,
        objectives: vec![],
        constraints,
    };
    c.objectives = p.objectives.iter().map(|o| quantity(&c, o)).collect();
    c
}

/// An objective's value for a candidate (own sign and unit).
pub fn quantity(c: &Candidate, o: &Objective) -> f64 {
    match o.quantity {
        Quantity::Variable(i) => c.x[i],
        Quantity::ThresholdHz => c.threshold_hz.unwrap_or(f64::NAN),
        Quantity::PowerLossW => c.power_loss_w,
        Quantity::MinFilmUm => c.min_film_um,
        Quantity::Margin => c.margin,
    }
}

/// The value the search minimises for an objective.
pub fn to_minimise(o: &Objective, value: f64) -> f64 {
    if o.maximize {
        -value
    } else {
        value
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::optimize::problem::Problem;

    fn problem() -> Problem {
        Problem::parse(
            r#"
            [variables]
            clearance = [10, 30]
            [requirement]
            min_film_um = 2.0
            max_whirl_um = 1.0
            speed_range_hz = [500, 2000]
            [objective]
            maximize = "clearance"
            "#,
            Path::new("t.toml"),
        )
        .unwrap()
    }

    fn corner(label: &str, linear: LinearResult, nonlinear: Option<NonlinearResult>) -> Corner {
        let mut c = Corner {
            label: label.into(),
            args: BTreeMap::new(),
            linear,
            nonlinear,
            stage: Stage::Linear,
            min_film_um: f64::NAN,
            whirl_um: f64::NAN,
            class: None,
            ok: false,
            reason: String::new(),
        };
        decide_corner(&problem(), &mut c);
        c
    }

    fn linear(threshold_hz: Option<f64>, film: f64) -> LinearResult {
        LinearResult {
            threshold_hz,
            static_film_um: film,
            power_loss_w: 10.0,
            ..Default::default()
        }
    }

    #[test]
    fn the_linear_stage_decides_stable_and_statically_too_thin_corners_only() {
        let stable = corner("nominal", linear(None, 5.0), None);
        assert!(stable.ok && stable.stage == Stage::Linear, "{stable:?}");
        assert_eq!(stable.min_film_um, 5.0);
        // A threshold just above the range is inside the linear stage's margin: undecided.
        let near = corner("nominal", linear(Some(2150.0), 5.0), None);
        assert!(!near.ok && near.reason == NOT_RUN, "{near:?}");
        let beyond = corner("nominal", linear(Some(2300.0), 5.0), None);
        assert!(beyond.ok);
        let thin = corner("nominal", linear(Some(900.0), 1.5), None);
        assert!(
            !thin.ok && thin.reason.contains("static film 1.50 um"),
            "{thin:?}"
        );
    }

    #[test]
    fn run_ups_decide_by_film_whirl_and_class_and_the_worst_corner_counts() {
        let p = problem();
        let run = |film: f64, whirl: f64| NonlinearResult {
            run: "r".into(),
            class: Some("path2a".into()),
            onset_hz: Some(1200.0),
            min_film_um: film,
            whirl_um: whirl,
            halted: None,
            error: None,
        };
        let good = corner("nominal", linear(Some(1100.0), 5.0), Some(run(3.0, 0.5)));
        assert!(good.ok && good.stage == Stage::Nonlinear, "{good:?}");
        let bad = corner("C- c+", linear(Some(1000.0), 5.0), Some(run(3.0, 1.6)));
        assert!(
            !bad.ok && bad.reason.contains("whirl 1.60 um above 1 um"),
            "{bad:?}"
        );
        let c = summarize(&p, 0, vec![20.0], vec![good.clone(), bad]);
        assert!(
            !c.feasible && c.reason.starts_with("C- c+: whirl"),
            "{}",
            c.reason
        );
        assert_eq!((c.min_film_um, c.whirl_um), (3.0, 1.6));
        // Film 1 - 3/2 = -0.5 (met), whirl 1.6/1 - 1 = 0.6 (violated).
        assert!((c.constraints[0] + 0.5).abs() < 1e-12 && (c.constraints[1] - 0.6).abs() < 1e-12);
        assert!(c.margin < 0.0);
        assert_eq!(c.threshold_hz, Some(1000.0));
        assert_eq!(c.objectives, vec![20.0]);
        let ok = summarize(&p, 1, vec![20.0], vec![good]);
        assert!(ok.feasible);
        // Margin: the nearer limit is the whirl (0.5 of 1 um) before the film (3 of 2 um).
        assert!((ok.margin - 0.5).abs() < 1e-12, "{}", ok.margin);
        // A halted run-up is never a pass: its film crossed the limit, even where its series
        // cannot show it (a film thickness that is not a number).
        let halted = |film: f64| NonlinearResult {
            halted: Some("film_T.h_min = NaN um < 2 um at 900 Hz (t = 1.3 s)".into()),
            ..run(film, 0.5)
        };
        let (pass, why) = nonlinear_decision(&p, &halted(1.5));
        assert!(
            !pass && why == "film 1.50 um below 2 um (the run-up halted at a limit)",
            "{why}"
        );
        let (pass, why) = nonlinear_decision(&p, &halted(3.0));
        assert!(
            !pass && why.starts_with("halted: film_T.h_min = NaN um"),
            "{why}"
        );
    }

    #[test]
    fn candidates_with_unmeasured_quantities_are_read_back() {
        let p = problem();
        // Statically too thin: its film is measured, its whirl is not.
        let thin = corner("C-", linear(Some(900.0), 1.5), None);
        let c = summarize(&p, 3, vec![20.0], vec![thin]);
        assert!(c.min_film_um.is_finite() && c.whirl_um.is_nan());
        let back: Candidate = serde_json::from_str(&serde_json::to_string(&c).unwrap()).unwrap();
        assert!(back.whirl_um.is_nan() && back.constraints[1].is_nan());
        assert_eq!(back.min_film_um, c.min_film_um);
    }

    #[test]
    fn the_linear_grid_covers_the_range_its_margin_and_the_operating_speed() {
        let mut p = problem();
        p.operating_speed_hz = 1234.0;
        let g = linear_grid(&p);
        assert_eq!(g[0], 500.0);
        assert!((g.last().unwrap() - 2200.0).abs() < 1e-9);
        assert!(g.contains(&1234.0));
        assert!(g.windows(2).all(|w| w[0] < w[1]));
    }
}
