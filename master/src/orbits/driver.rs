//! `airring orbits`: the periodic whirl orbits of a rotor in its bearings at constant speeds.
//!
//! 1. At each requested speed the co-simulation runs at that constant speed from the centred
//!    start (gravity's sag is the kick) for the settle time. A whirl that is still there is
//!    either periodic (its upward crossings of the mean come at equal intervals) or not
//!    (quasi-periodic: reported as such, not forced into an orbit).
//! 2. From a settled periodic whirl the shooting finds the orbit (reduced shooting with the
//!    film pressures relaxed, see `cosim_flow.rs`); its Floquet multipliers give its stability.
//! 3. From the stable orbit at the highest such speed the branch is continued down in speed
//!    (pseudo-arclength: it passes folds) until it meets the equilibrium at its Hopf point or
//!    leaves the range; the linear threshold (`airring stability`) is what the Hopf point is
//!    compared with, and the branch's smallest orbits give the Hopf bifurcation's criticality.

use super::continuation::{
    continue_branch, criticality, hopf_estimate, Branch, BranchEnd, ContinuationOptions,
    Criticality,
};
use super::cosim_flow::RotorFilmFlow;
use super::full_state::FullStateFlow;
use super::krylov::{shoot_krylov, KrylovOptions};
use super::shooting::{shoot, Flow, PeriodicOrbit, ShootingOptions};
use crate::runup::RunupSettings;
use serde::Serialize;
use std::path::{Path, PathBuf};

#[derive(Clone, Debug)]
pub struct OrbitsRequest {
    pub settings: RunupSettings,
    pub speeds_hz: Vec<f64>,
    /// Constant-speed simulation before the whirl counts as settled [s].
    pub settle_s: f64,
    /// Continue the branch from the highest stable orbit (else only the orbits per speed).
    pub continuation: bool,
    /// Shoot on the full state by Newton-Krylov (else the reduced shooting).
    pub full_state: bool,
    pub fmu_dir: PathBuf,
    pub out_dir: PathBuf,
}

/// Leading multipliers closer than this to the unit circle leave an orbit's stability open:
/// path 2a's branch computed with steps of different size gave 0.964 and 1.035 for the orbit at
/// 488 Hz.
pub const UNDECIDED_MULTIPLIER_BAND: f64 = 0.05;

/// One periodic orbit as orbits.json lists it.
#[derive(Clone, Debug, Serialize, serde::Deserialize)]
pub struct OrbitRecord {
    pub speed_hz: f64,
    pub period_s: f64,
    pub whirl_frequency_hz: f64,
    #[serde(rename = "max_eps_C")]
    pub max_eps_c: f64,
    #[serde(rename = "max_eps_T")]
    pub max_eps_t: f64,
    /// Largest distance of the journal (relative to its ring) from its mean position, / C.
    #[serde(rename = "whirl_amplitude_C")]
    pub whirl_amplitude_c: f64,
    #[serde(rename = "whirl_amplitude_T")]
    pub whirl_amplitude_t: f64,
    #[serde(rename = "h_min_C_um")]
    pub h_min_c_um: f64,
    #[serde(rename = "h_min_T_um")]
    pub h_min_t_um: f64,
    /// [re, im] of each multiplier, largest modulus first (the trivial 1 included).
    pub floquet_multipliers: Vec<[f64; 2]>,
    /// Largest modulus without the trivial multiplier.
    pub leading_multiplier: f64,
    pub stable: bool,
    /// False when the leading multiplier is within `UNDECIDED_MULTIPLIER_BAND` of the unit
    /// circle: the finite-difference monodromy of the co-simulation does not decide stability
    /// that close (docs/orbits.md).
    pub stability_decided: bool,
    /// "settled" (shot from a settled constant-speed simulation) or "continuation".
    pub branch: String,
    pub newton_iterations: usize,
    /// Largest scaled periodicity defect.
    pub residual: f64,
}

/// What the constant-speed simulation at one requested speed settled into.
#[derive(Clone, Debug, Serialize, serde::Deserialize)]
pub struct SettledRecord {
    pub speed_hz: f64,
    /// "equilibrium", "periodic", "quasi-periodic" or "failed".
    pub motion: String,
    /// Largest eccentricity per bearing over the last tenth of the settle time (None: failed).
    #[serde(rename = "max_eps_C")]
    pub max_eps_c: Option<f64>,
    #[serde(rename = "max_eps_T")]
    pub max_eps_t: Option<f64>,
    pub whirl_frequency_hz: Option<f64>,
    /// Each bearing's own whirl frequency [Hz] (C, T), from the crossings of its journal's x
    /// relative to the ring: two whirl frequencies more than 5 % apart are the run-up
    /// classifier's path-1 sign. None in files of earlier versions and where a bearing has
    /// fewer than four crossings.
    #[serde(default)]
    pub bearing_whirl_frequencies_hz: Option<[f64; 2]>,
    /// RMS distance of the journal (relative to its ring) from its mean position over the last
    /// tenth of the settle time, / C: the run-up classifier's whirl amplitude (`LARGE_WHIRL_AMP_REL`
    /// is its bound). None in files of earlier versions and for a failed simulation.
    #[serde(rename = "whirl_rms_C", default)]
    pub whirl_rms_c: Option<f64>,
    #[serde(rename = "whirl_rms_T", default)]
    pub whirl_rms_t: Option<f64>,
    /// Relative spread of the intervals between the whirl's crossings of its mean.
    pub period_spread: Option<f64>,
    pub message: Option<String>,
}

#[derive(Clone, Debug, Serialize, serde::Deserialize)]
pub struct OrbitsReport {
    pub preset: String,
    pub speeds_hz: Vec<f64>,
    pub settle_s: f64,
    /// How the orbits were shot: "reduced" (the rotor's lateral state, the films relaxed onto
    /// the orbit) or "full state, Newton-Krylov".
    #[serde(default)]
    pub shooting: String,
    /// The linear threshold speed (`airring stability`) [Hz], if the equilibrium turns unstable
    /// from 100 Hz to the top speed.
    pub linear_threshold_hz: Option<f64>,
    /// Why there is no linear threshold: the analysis failed (its message) or the equilibrium
    /// stays stable up to the top speed.
    #[serde(default)]
    pub linear_note: Option<String>,
    pub settled: Vec<SettledRecord>,
    pub orbits: Vec<OrbitRecord>,
    /// Where the continued branch meets the equilibrium [Hz].
    pub hopf_estimate_hz: Option<f64>,
    /// "supercritical" or "subcritical", read off the continued branch.
    pub criticality: Option<String>,
    /// Speeds where the branch turns (folds) [Hz].
    pub folds_hz: Vec<f64>,
    /// Why the continuation ended.
    pub branch_end: Option<String>,
    /// Flows (period-map evaluations) and macro steps co-simulated.
    pub flows: usize,
    pub macro_steps: u64,
    pub wall_time_s: f64,
}

/// Intervals between upward crossings of the mean of `xs` (sampled at `ts`): the whirl period
/// and the relative spread of the intervals.
pub fn crossing_period(ts: &[f64], xs: &[f64]) -> Option<(f64, f64)> {
    let mean = xs.iter().sum::<f64>() / xs.len() as f64;
    let mut crossings = vec![];
    for i in 1..xs.len() {
        let (a, b) = (xs[i - 1] - mean, xs[i] - mean);
        if a < 0.0 && b >= 0.0 {
            crossings.push(ts[i - 1] + (ts[i] - ts[i - 1]) * (-a) / (b - a));
        }
    }
    if crossings.len() < 4 {
        return None;
    }
    let iv: Vec<f64> = crossings.windows(2).map(|w| w[1] - w[0]).collect();
    let period = iv.iter().sum::<f64>() / iv.len() as f64;
    let spread = iv.iter().map(|d| (d - period).abs()).fold(0.0, f64::max) / period;
    Some((period, spread))
}

fn record(
    speed_hz: f64,
    orbit: &PeriodicOrbit,
    measures: &[(String, f64)],
    branch: &str,
) -> OrbitRecord {
    let m = |name: &str| {
        measures
            .iter()
            .find(|(n, _)| n == name)
            .map_or(f64::NAN, |(_, v)| *v)
    };
    OrbitRecord {
        speed_hz,
        period_s: orbit.period_s,
        whirl_frequency_hz: 1.0 / orbit.period_s,
        max_eps_c: m("max_eps_C"),
        max_eps_t: m("max_eps_T"),
        whirl_amplitude_c: m("whirl_amplitude_C"),
        whirl_amplitude_t: m("whirl_amplitude_T"),
        h_min_c_um: m("h_min_C_m") * 1e6,
        h_min_t_um: m("h_min_T_m") * 1e6,
        floquet_multipliers: orbit.multipliers.iter().map(|c| [c.re, c.im]).collect(),
        leading_multiplier: orbit.leading_multiplier(),
        stable: orbit.stable(),
        stability_decided: (orbit.leading_multiplier() - 1.0).abs() > UNDECIDED_MULTIPLIER_BAND,
        branch: branch.into(),
        newton_iterations: orbit.iterations,
        residual: orbit.residual,
    }
}

/// Shooting options for the co-simulated period map: its film and rotor step controls make it
/// smooth only to ~1e-7 of a clearance, so the finite differences step 1e-4 of a scale, the
/// defect is converged to 1e-6, and a defect below 1e-5 that no Newton step lowers any more
/// is the map's noise floor (path 2a at 520 Hz stalled at 1.04e-6 from one start point).
pub fn cosim_shooting_options() -> ShootingOptions {
    ShootingOptions {
        fd_rel: 1e-4,
        dt_rel: 1e-3,
        tol: 1e-6,
        max_iter: 12,
        noise_floor: 1e-5,
    }
}

/// Reduced shooting: shoot, move the films' start field to the orbit's end, shoot again, until
/// the orbit's start moves less than the tolerance (at most 4 passes).
pub fn shoot_relaxed(
    flow: &mut RotorFilmFlow,
    x0: &[f64],
    period_s: f64,
    opts: &ShootingOptions,
) -> Result<PeriodicOrbit, String> {
    let scale = super::shooting::Flow::scale(flow);
    let mut orbit = shoot(flow, x0, period_s, opts)?;
    for _pass in 0..3 {
        flow.rebase(&orbit.x0, orbit.period_s)?;
        let start = flow.base_lateral_state()?;
        let next = shoot(flow, &start, orbit.period_s, opts)?;
        let moved = next
            .x0
            .iter()
            .zip(&orbit.x0)
            .zip(&scale)
            .map(|((a, b), s)| ((a - b) / s).abs())
            .fold(0.0, f64::max);
        orbit = next;
        if moved < 10.0 * opts.tol {
            break;
        }
    }
    Ok(orbit)
}

/// Newton-Krylov shooting on the full state from the base point; the orbit keeps the lateral
/// part of its start state, its measures are those of the full-state orbit.
pub fn shoot_full_state(
    flow: &mut RotorFilmFlow,
    period_s: f64,
    opts: &ShootingOptions,
) -> Result<(PeriodicOrbit, Vec<(String, f64)>), String> {
    let mut full = FullStateFlow::new(flow)?;
    let x0 = full.base_state()?;
    let kopts = KrylovOptions {
        // Finite differences of 1e-3 of the scales (a thousandth of the clearance, 100 Pa): the
        // products' noise from the films' error control (atol 10 Pa) stays small beside them.
        // 1e-4 stalls (path 2a at 520 Hz: defect 1e-3 at the first Newton step).
        shooting: ShootingOptions {
            fd_rel: 1e-3,
            ..*opts
        },
        gmres_rel_tol: 1e-3,
        max_krylov: 80,
        ritz_steps: 20,
    };
    let found = shoot_krylov(&mut full, &x0, period_s, &kopts)?;
    let measures = full.measures(&found.orbit.x0, found.orbit.period_s)?;
    let mut orbit = found.orbit;
    orbit.x0.truncate(full.inner.n_lateral());
    Ok((orbit, measures))
}

pub fn find_orbits(
    req: &OrbitsRequest,
    progress: &mut dyn FnMut(&str),
) -> Result<OrbitsReport, String> {
    let t0 = std::time::Instant::now();
    check_speeds(&req.speeds_hz, &req.settings)?;
    super::cosim_flow::check_autonomous(&req.settings)?;
    if !(req.settle_s.is_finite() && req.settle_s > 0.0) {
        return Err(format!(
            "--settle {} s: must be a positive time",
            req.settle_s
        ));
    }
    std::fs::create_dir_all(&req.out_dir).map_err(|e| format!("{}: {e}", req.out_dir.display()))?;
    let (linear, whirl_hz, linear_note) = linear_threshold_and_whirl(&req.settings);
    if let Some(note) = &linear_note {
        progress(&format!("linear threshold: {note}"));
    }
    if let Some(f) = whirl_hz {
        check_settle_holds_whirl(req.settle_s, f)?;
    }
    let opts = cosim_shooting_options();
    let mut report = OrbitsReport {
        preset: req.settings.preset.clone(),
        speeds_hz: req.speeds_hz.clone(),
        settle_s: req.settle_s,
        shooting: if req.full_state {
            "full state, Newton-Krylov".into()
        } else {
            "reduced".into()
        },
        linear_threshold_hz: linear,
        linear_note,
        settled: vec![],
        orbits: vec![],
        hopf_estimate_hz: None,
        criticality: None,
        folds_hz: vec![],
        branch_end: None,
        flows: 0,
        macro_steps: 0,
        wall_time_s: 0.0,
    };
    let mut top: Option<(RotorFilmFlow, PeriodicOrbit)> = None;
    for &speed in &req.speeds_hz {
        progress(&format!("{speed:.1} Hz: settling for {} s", req.settle_s));
        let system_file = req.out_dir.join(format!("system-{speed}Hz.toml"));
        let mut flow = RotorFilmFlow::new(&req.settings, &req.fmu_dir, speed, &system_file)?;
        let settled = settle_and_shoot(&mut flow, req.settle_s, &opts, req.full_state);
        report.flows += flow.flows;
        report.macro_steps += flow.macro_steps;
        match settled {
            Ok((mut rec, orbit)) => {
                if let (Some(t), "equilibrium" | "decaying") = (linear, rec.motion.as_str()) {
                    if speed < t {
                        rec.message = Some(format!(
                            "{speed} Hz is below the linear threshold {t:.1} Hz: the equilibrium is stable, no whirl to find{}",
                            rec.message.as_ref().map_or(String::new(), |m| format!(" ({m})"))
                        ));
                    } else if crate::stability::analyse(&req.settings, &[speed])
                        .is_ok_and(|r| r.unstable_at_first_speed)
                    {
                        // The equilibrium is unstable at this speed (an unstable band may close
                        // again below the top speed: checked here, not from the threshold):
                        // what looked settled or dying is the start-up transient, before the
                        // whirl has grown.
                        rec.message = Some(format!(
                            "{speed} Hz is above the linear threshold {t:.1} Hz, so the equilibrium \
                             is unstable, but no whirl grew within --settle {} s (the motion \
                             looked {}): settle longer",
                            req.settle_s, rec.motion
                        ));
                        rec.motion = "not settled".into();
                    }
                }
                if let Some((orbit, measures)) = orbit {
                    let r = record(speed, &orbit, &measures, "settled");
                    progress(&format!(
                        "{speed:.1} Hz: orbit T = {:.4} ms, max eps C {:.3} T {:.3}, leading multiplier {:.4} ({})",
                        orbit.period_s * 1e3,
                        r.max_eps_c,
                        r.max_eps_t,
                        r.leading_multiplier,
                        if r.stable { "stable" } else { "unstable" }
                    ));
                    report.orbits.push(r);
                    if orbit.stable() {
                        top = Some((flow, orbit));
                    }
                } else {
                    progress(&format!(
                        "{speed:.1} Hz: {}{}",
                        rec.motion,
                        rec.message
                            .as_ref()
                            .map_or(String::new(), |m| format!(": {m}"))
                    ));
                }
                report.settled.push(rec);
            }
            Err(e) => {
                progress(&format!("{speed:.1} Hz: {e}"));
                report.settled.push(SettledRecord {
                    speed_hz: speed,
                    motion: "failed".into(),
                    max_eps_c: None,
                    max_eps_t: None,
                    whirl_frequency_hz: None,
                    bearing_whirl_frequencies_hz: None,
                    whirl_rms_c: None,
                    whirl_rms_t: None,
                    period_spread: None,
                    message: Some(e),
                });
            }
        }
        write_report(&req.out_dir, &report)?;
    }
    if let (true, Some((mut flow, orbit))) = (req.continuation, top) {
        progress(&format!(
            "continuing the branch down from {:.1} Hz",
            flow.speed_hz()
        ));
        let (lo, hi) = (req.speeds_hz[0], req.speeds_hz[req.speeds_hz.len() - 1]);
        let copts = ContinuationOptions {
            ds: 0.02,
            ds_min: 1e-3,
            ds_max: 0.1,
            max_points: 60,
            param_min: lo,
            param_max: hi,
            min_size: 0.02,
            max_corrector: 5,
            shooting: opts,
            fd_param_rel: 1e-4,
        };
        let flows_before = flow.flows;
        let steps_before = flow.macro_steps;
        let out_dir = req.out_dir.clone();
        let mut partial = report.clone();
        let branch = continue_branch(&mut flow, &orbit, false, &copts, &mut |p| {
            let r = record(p.param, &p.orbit, &p.measures, "continuation");
            progress(&format!(
                "branch: {:.2} Hz, T = {:.4} ms, max eps C {:.3} T {:.3}, leading multiplier {:.4} ({})",
                p.param,
                p.orbit.period_s * 1e3,
                r.max_eps_c,
                r.max_eps_t,
                r.leading_multiplier,
                if r.stable { "stable" } else { "unstable" }
            ));
            // Written as it grows: a branch cut short by a failure or Ctrl-C is not lost.
            partial.orbits.push(r);
            let _ = write_report(&out_dir, &partial);
        });
        let branch = match branch {
            Ok(b) => b,
            Err(e) => {
                report.orbits = partial.orbits;
                report.branch_end = Some(format!("failed: {e}"));
                write_report(&req.out_dir, &report)?;
                return Err(e);
            }
        };
        report.flows += flow.flows - flows_before;
        report.macro_steps += flow.macro_steps - steps_before;
        add_branch(&mut report, &branch);
        write_report(&req.out_dir, &report)?;
    }
    report.wall_time_s = t0.elapsed().as_secs_f64();
    write_report(&req.out_dir, &report)?;
    Ok(report)
}

/// The speed where the branch turns near its fold at index `i` (the tangent turned between
/// points i and i + 1): the extreme speed of the few points around it, the lowest if the branch
/// was running down in speed, the highest if up.
fn fold_speed(branch: &Branch, i: usize) -> f64 {
    let p = &branch.points;
    let running_down = i > 0 && p[i].param < p[i - 1].param;
    let near = p[i.saturating_sub(1)..(i + 4).min(p.len())]
        .iter()
        .map(|q| q.param);
    if running_down {
        near.fold(f64::INFINITY, f64::min)
    } else {
        near.fold(f64::NEG_INFINITY, f64::max)
    }
}

fn add_branch(report: &mut OrbitsReport, branch: &Branch) {
    for p in branch.points.iter().skip(1) {
        report
            .orbits
            .push(record(p.param, &p.orbit, &p.measures, "continuation"));
    }
    report.folds_hz = branch
        .folds
        .iter()
        .map(|&i| fold_speed(branch, i))
        .collect();
    report.branch_end = Some(match &branch.end {
        BranchEnd::ReachedHopf => "reached the equilibrium (Hopf point)".into(),
        BranchEnd::LeftRange => "left the speed range".into(),
        BranchEnd::MaxPoints => "point limit".into(),
        BranchEnd::Failed(e) => format!("failed: {e}"),
    });
    report.hopf_estimate_hz = hopf_estimate(branch);
    if let Some(h) = report.hopf_estimate_hz {
        report.criticality = criticality(branch, h, true).map(|c| match c {
            Criticality::Supercritical => "supercritical".into(),
            Criticality::Subcritical => "subcritical".into(),
        });
    }
}

/// The share of `--settle` at its end whose samples are classified and shot from.
const SAMPLE_WINDOW_FRACTION: f64 = 0.1;
/// Whirl periods the sample window must hold at least.
const MIN_WINDOW_PERIODS: f64 = 5.0;

/// Refuses a `--settle` whose sample window cannot hold `MIN_WINDOW_PERIODS` periods of the whirl
/// at `whirl_hz` (the one that turns unstable at the linear threshold, the slowest above it
/// along a run-up's whirl-speed ratio): with fewer, the motion's class and period come from a
/// fraction of an orbit.
pub fn check_settle_holds_whirl(settle_s: f64, whirl_hz: f64) -> Result<(), String> {
    let needed_s = MIN_WINDOW_PERIODS / (SAMPLE_WINDOW_FRACTION * whirl_hz);
    if whirl_hz > 0.0 && settle_s < needed_s {
        return Err(format!(
            "--settle {} s is too short: its last tenth ({} ms), where the motion is classified \
             and its orbit shot from, must hold {MIN_WINDOW_PERIODS} periods of the whirl the \
             linear analysis finds at its threshold ({whirl_hz:.1} Hz, {:.1} ms each); give \
             --settle {:.2} s or more",
            bearing::num::Num(settle_s),
            bearing::num::Num(SAMPLE_WINDOW_FRACTION * settle_s * 1e3),
            1e3 / whirl_hz,
            (needed_s * 100.0).ceil() / 100.0,
        ));
    }
    Ok(())
}

/// The settled motion at the flow's speed, and the orbit shot from it when it is periodic.
#[allow(clippy::type_complexity)]
fn settle_and_shoot(
    flow: &mut RotorFilmFlow,
    settle_s: f64,
    opts: &ShootingOptions,
    full_state: bool,
) -> Result<(SettledRecord, Option<(PeriodicOrbit, Vec<(String, f64)>)>), String> {
    let speed = flow.speed_hz();
    let window = SAMPLE_WINDOW_FRACTION * settle_s;
    let n = ((window / 20e-6).round() as usize).max(50);
    let simulated = flow
        .settle(settle_s - window)
        .and_then(|()| flow.sample(window, n));
    let samples = simulated.map_err(|e| {
        // Where it failed says what it was doing: a journal deep in its ring (a large whirl in
        // hard contact the rotor's step control gives up on) or not.
        let at = flow.max_eps_now().map_or(String::new(), |eps| {
            format!(" (largest film eccentricity {eps:.3} when it failed)")
        });
        format!("{e}{at}")
    })?;
    let ts: Vec<f64> = samples.iter().map(|s| s.0).collect();
    let clearance = flow.clearance_m();
    let eps = |b: usize| {
        samples
            .iter()
            .map(|s| s.1[2 * b].hypot(s.1[2 * b + 1]) / clearance[b])
            .fold(0.0, f64::max)
    };
    let (max_eps_c, max_eps_t) = (eps(0), eps(1));
    let rms = |b: usize| {
        let n = samples.len() as f64;
        let mx = samples.iter().map(|s| s.1[2 * b]).sum::<f64>() / n;
        let my = samples.iter().map(|s| s.1[2 * b + 1]).sum::<f64>() / n;
        let ms = samples
            .iter()
            .map(|s| (s.1[2 * b] - mx).powi(2) + (s.1[2 * b + 1] - my).powi(2))
            .sum::<f64>()
            / n;
        ms.sqrt() / clearance[b]
    };
    let xs: Vec<f64> = samples.iter().map(|s| s.1[0]).collect();
    let lo = xs.iter().copied().fold(f64::INFINITY, f64::min);
    let hi = xs.iter().copied().fold(f64::NEG_INFINITY, f64::max);
    let mut rec = SettledRecord {
        speed_hz: speed,
        motion: "equilibrium".into(),
        max_eps_c: Some(max_eps_c),
        max_eps_t: Some(max_eps_t),
        whirl_frequency_hz: None,
        bearing_whirl_frequencies_hz: None,
        whirl_rms_c: Some(rms(0)),
        whirl_rms_t: Some(rms(1)),
        period_spread: None,
        message: None,
    };
    // Below a thousandth of the clearance the journal sits in its equilibrium.
    if hi - lo < 2e-3 * clearance[0] {
        return Ok((rec, None));
    }
    // A whirl still dying out (near the threshold the equilibrium is only weakly damped): no
    // orbit to shoot for.
    let half = xs.len() / 2;
    let span = |v: &[f64]| {
        v.iter().copied().fold(f64::NEG_INFINITY, f64::max)
            - v.iter().copied().fold(f64::INFINITY, f64::min)
    };
    let decay = span(&xs[half..]) / span(&xs[..half]);
    if decay < 0.97 {
        rec.motion = "decaying".into();
        rec.message = Some(format!(
            "the whirl shrinks by {:.0} % within the last {:.3} s: the equilibrium is stable here, no orbit to find",
            (1.0 - decay) * 100.0,
            window / 2.0
        ));
        return Ok((rec, None));
    }
    let Some((period, spread)) = crossing_period(&ts, &xs) else {
        rec.motion = "not settled".into();
        rec.message = Some(format!("fewer than 4 whirl periods in the last {window} s"));
        return Ok((rec, None));
    };
    rec.whirl_frequency_hz = Some(1.0 / period);
    let xt: Vec<f64> = samples.iter().map(|s| s.1[2]).collect();
    if let Some((period_t, _)) = crossing_period(&ts, &xt) {
        rec.bearing_whirl_frequencies_hz = Some([1.0 / period, 1.0 / period_t]);
    }
    rec.period_spread = Some(spread);
    if spread > 0.05 {
        rec.motion = "quasi-periodic".into();
        rec.message = Some(format!(
            "the intervals between whirl periods vary by {:.0} %: not one periodic orbit",
            spread * 100.0
        ));
        return Ok((rec, None));
    }
    rec.motion = "periodic".into();
    flow.move_base_to_quietest(period)?;
    let x0 = flow.base_lateral_state()?;
    // A shooting that fails keeps what the simulation showed, with the reason.
    let shot = if full_state {
        shoot_full_state(flow, period, opts)
    } else {
        shoot_relaxed(flow, &x0, period, opts).and_then(|orbit| {
            let measures = super::shooting::Flow::measures(flow, &orbit.x0, orbit.period_s)?;
            Ok((orbit, measures))
        })
    };
    match shot {
        Ok(found) => Ok((rec, Some(found))),
        Err(e) => {
            rec.message = Some(format!("no orbit found: {e}"));
            Ok((rec, None))
        }
    }
}

/// The linear threshold speed [Hz] on `airring stability`'s default grid (100 Hz to the top
/// speed in 50 Hz steps, the crossing refined to 0.5 Hz), or why there is none. The grid starts
/// at 100 Hz because at 10 Hz the static equilibrium of a large clearance is not found
/// (C = 30 um, c = 1000 N/mm: "static equilibrium not found in 40 Newton steps at 10.0 Hz"),
/// which once left the threshold silently empty.
pub fn linear_threshold(s: &RunupSettings) -> (Option<f64>, Option<String>) {
    let (threshold, _, note) = linear_threshold_and_whirl(s);
    (threshold, note)
}

/// `linear_threshold` and the frequency of the whirl that turns unstable there [Hz] (none where
/// there is no threshold inside the speed range).
pub fn linear_threshold_and_whirl(s: &RunupSettings) -> (Option<f64>, Option<f64>, Option<String>) {
    let top = top_speed_hz(s);
    let mut grid: Vec<f64> = (2..)
        .map(|k| 50.0 * k as f64)
        .take_while(|f| *f < top)
        .collect();
    grid.push(top);
    match crate::stability::analyse(s, &grid) {
        // Unstable from the first speed on: the threshold lies below it, and its upper bound is
        // what a class can use (a rotor unstable at 100 Hz is unstable at low speed).
        Ok(r) if r.unstable_at_first_speed => (
            Some(grid[0]),
            None,
            Some(format!(
                "unstable already at {} Hz, the first speed analysed: the threshold lies below it",
                grid[0]
            )),
        ),
        Ok(r) => match r.threshold {
            Some(t) => (Some(t.speed_hz), Some(t.mode.freq_hz), None),
            None => (
                None,
                None,
                Some(format!(
                    "the equilibrium stays stable from 100 to {top} Hz (linear analysis)"
                )),
            ),
        },
        Err(e) => (None, None, Some(format!("the linear analysis failed: {e}"))),
    }
}

/// The highest speed of the run-up (its ramp's end, or the profile's top).
pub fn top_speed_hz(s: &RunupSettings) -> f64 {
    if s.speed_profile.is_empty() {
        s.f_max_hz
    } else {
        s.speed_profile.iter().map(|p| p.1).fold(0.0, f64::max)
    }
}

/// Speeds: increasing, positive, within the run-up's range (0, f_max].
pub fn check_speeds(speeds: &[f64], s: &RunupSettings) -> Result<(), String> {
    if speeds.is_empty() {
        return Err("no speeds given".into());
    }
    let top = top_speed_hz(s);
    for &f in speeds {
        if !(f.is_finite() && f > 0.0 && f <= top) {
            return Err(format!(
                "speed {f} Hz is outside the run-up's range (0, {top}] Hz"
            ));
        }
    }
    Ok(())
}

fn write_report(dir: &Path, r: &OrbitsReport) -> Result<(), String> {
    let text = serde_json::to_string_pretty(r).map_err(|e| e.to_string())?;
    let path = dir.join("orbits.json");
    cosim::files::write_whole(&path, text.as_bytes())
        .map_err(|e| format!("{}: {e}", path.display()))
}
