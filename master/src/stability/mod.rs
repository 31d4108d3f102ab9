//! Linear stability analysis of the rotor in air ring bearings (beyond the paper; docs/stability.md).
//!
//! Per speed: the static equilibrium under gravity (`equilibrium`), the films linearized about it
//! with frequency-dependent coefficients (fmu_airfilm::dynamic), the whole-system eigenvalues with
//! each mode's film coefficients taken at its own whirl frequency (`campbell`). Then the threshold
//! speed of instability by bisection between the last stable and the first unstable grid speed.
//! `cli` is the `airring stability` command, `figures` its Campbell and damping diagrams.

pub mod campbell;
pub mod cli;
pub mod equilibrium;
pub mod figures;
pub mod structure;
pub mod unbalance;

use crate::fmu_params::with_units;
use crate::runup::RunupSettings;
use campbell::{system_modes, ModeResult};
use equilibrium::{solve_bearing, BearingEquilibrium, SolvedBearing};
use fmu_airfilm::BearingParams;
use fmu_rotor::RotorParams;
use serde::Serialize;
use std::f64::consts::TAU;
use structure::LinearRotor;

/// Rotor and film parameters [C, T] of a run-up setting: the parameters the run-up's system file
/// gives each FMU instance (including `--set` ones), mapped by the FMUs' own `params_from`, so the
/// linear model and the run-up cannot disagree on a parameter. One exception: the films' contact
/// force is always part of the linearized film (`contact_in_force`), because the rotor model of the
/// linearization has no contact of its own, wherever a run-up evaluates it.
pub fn params_of(s: &RunupSettings) -> Result<(RotorParams, [BearingParams; 2]), String> {
    s.checked_fmu_parameters()?;
    let rotor = s.rotor_params()?;
    let mut films = s.film_params()?;
    for f in &mut films {
        f.contact_in_force = true;
    }
    Ok((rotor, films))
}

/// Everything at one speed.
#[derive(Clone, Debug, Serialize)]
pub struct SpeedResult {
    pub speed_hz: f64,
    /// [C, T].
    pub bearings: [BearingEquilibrium; 2],
    /// Oscillating modes, sorted by frequency.
    pub modes: Vec<ModeResult>,
    /// Real eigenvalues [1/s] of the system with the static film coefficients (non-oscillating
    /// motion: overdamped modes, or a static divergence if one is > 0).
    pub real_eigenvalues_per_s: Vec<f64>,
}

impl SpeedResult {
    /// The least damped mode (largest Re(lambda)): an oscillating one, or a non-oscillating
    /// (real) eigenvalue when that is larger (a divergence once it is > 0).
    pub fn critical(&self) -> Option<ModeResult> {
        let osc = self
            .modes
            .iter()
            .max_by(|a, b| a.growth_per_s.total_cmp(&b.growth_per_s));
        let real = self.real_eigenvalues_per_s.iter().copied().reduce(f64::max);
        match (osc, real) {
            (Some(m), Some(r)) if r <= m.growth_per_s => Some(m.clone()),
            (None, None) => None,
            (Some(m), None) => Some(m.clone()),
            (_, Some(r)) => Some(campbell::real_mode(r)),
        }
    }
    pub fn max_growth_per_s(&self) -> f64 {
        self.critical()
            .map_or(f64::NEG_INFINITY, |m| m.growth_per_s)
    }
}

#[derive(Clone, Debug, Serialize)]
pub struct Threshold {
    /// Speed where the first mode's Re(lambda) crosses 0 [Hz] (bisection to `tolerance_hz`).
    pub speed_hz: f64,
    pub tolerance_hz: f64,
    /// The mode that turns unstable, just above the threshold.
    pub mode: ModeResult,
    /// Whirl frequency / speed.
    pub whirl_ratio: f64,
}

#[derive(Clone, Debug, Serialize)]
pub struct StabilityReport {
    pub speeds: Vec<SpeedResult>,
    /// None: stable over the whole speed range.
    pub threshold: Option<Threshold>,
    /// The first speed of the range is already unstable (threshold lies below the range).
    pub unstable_at_first_speed: bool,
    /// Run-up ramp rate assumed by `growth_exponent` [Hz/s] (the settings' f_max / t_ramp).
    pub ramp_hz_per_s: f64,
    /// Per grid speed: N = Int max(0, max_k Re(lambda_k)) dt along the run-up (trapezoid on the
    /// grid, dt = df / ramp): a perturbation grows by e^N between the threshold and that speed.
    pub growth_exponent: Vec<f64>,
    pub wall_time_s: f64,
}

/// Accumulated growth exponent along a linear run-up (see `StabilityReport::growth_exponent`).
pub fn growth_exponent(speeds: &[SpeedResult], ramp_hz_per_s: f64) -> Vec<f64> {
    let mut n = 0.0;
    let mut out = Vec::with_capacity(speeds.len());
    for (i, s) in speeds.iter().enumerate() {
        if i > 0 {
            let prev = &speeds[i - 1];
            let g0 = prev.max_growth_per_s().max(0.0);
            let g1 = s.max_growth_per_s().max(0.0);
            n += 0.5 * (g0 + g1) * (s.speed_hz - prev.speed_hz) / ramp_hz_per_s;
        }
        out.push(n);
    }
    out
}

/// Equilibrium of both bearings at `speed_hz`, optionally warm-started from another speed's.
fn equilibria<R: LinearRotor>(
    rotor: &R,
    films: &[BearingParams; 2],
    speed_hz: f64,
    warm: Option<&[SolvedBearing; 2]>,
) -> Result<[SolvedBearing; 2], String> {
    let loads = rotor.journal_loads_n();
    let mounts = [rotor.mount(0), rotor.mount(1)];
    let solve = |i: usize| {
        let start = match warm {
            Some(w) => {
                let j = w[i].journal;
                ([j.dx_m, j.dy_m], Some(w[i].lin.steady()))
            }
            None => ([0.0, -0.2 * films[i].bore.c_m], None),
        };
        solve_bearing(
            &films[i],
            TAU * speed_hz,
            loads[i],
            start,
            mounts[i].0,
            mounts[i].1,
            rotor.g_m_s2(),
        )
        .map_err(|e| format!("bearing {}: {e}", ["C", "T"][i]))
    };
    Ok([solve(0)?, solve(1)?])
}

fn analyse_speed<R: LinearRotor>(
    rotor: &R,
    films: &[BearingParams; 2],
    speed_hz: f64,
    warm: Option<&[SolvedBearing; 2]>,
) -> Result<(SpeedResult, [SolvedBearing; 2]), String> {
    let eq = equilibria(rotor, films, speed_hz, warm)?;
    let (modes, real_eigenvalues_per_s) = system_modes(rotor, TAU * speed_hz, &eq)?;
    let res = SpeedResult {
        speed_hz,
        bearings: [eq[0].summary.clone(), eq[1].summary.clone()],
        modes,
        real_eigenvalues_per_s,
    };
    Ok((res, eq))
}

/// One speed's analysis, or why it failed.
pub type SpeedOutcome = Result<(SpeedResult, [SolvedBearing; 2]), String>;

/// Every speed of `speeds_hz` analysed on its own (cold-started equilibria), on all cores (std
/// threads, strided split); the results keep the grid order, a failed speed fails alone.
pub fn per_speed<R: LinearRotor>(
    rotor: &R,
    films: &[BearingParams; 2],
    speeds_hz: &[f64],
) -> Vec<SpeedOutcome> {
    let n_threads = std::thread::available_parallelism()
        .map_or(1, |n| n.get())
        .min(speeds_hz.len())
        .max(1);
    let mut slots: Vec<Option<SpeedOutcome>> = (0..speeds_hz.len()).map(|_| None).collect();
    std::thread::scope(|scope| {
        let handles: Vec<_> = (0..n_threads)
            .map(|t| {
                scope.spawn(move || {
                    (t..speeds_hz.len())
                        .step_by(n_threads)
                        .map(|i| {
                            let f = speeds_hz[i];
                            let r = analyse_speed(rotor, films, f, None)
                                .map_err(|e| format!("at {f} Hz: {e}"));
                            (i, r)
                        })
                        .collect::<Vec<_>>()
                })
            })
            .collect();
        for h in handles {
            for (i, r) in h.join().expect("stability worker panicked") {
                slots[i] = Some(r);
            }
        }
    });
    slots.into_iter().flatten().collect()
}

/// Campbell data over `speeds_hz` (ascending, > 0) and the threshold speed of instability.
pub fn analyse(s: &RunupSettings, speeds_hz: &[f64]) -> Result<StabilityReport, String> {
    analyse_with_equilibria(s, speeds_hz).map(|(r, _)| r)
}

/// `analyse`, also returning the equilibria of the grid speeds (in the report's order), which
/// the unbalance response linearizes about.
pub fn analyse_with_equilibria(
    s: &RunupSettings,
    speeds_hz: &[f64],
) -> Result<(StabilityReport, Vec<[SolvedBearing; 2]>), String> {
    // A design's flexible rotor is analysed as such wherever the settings go (an optimisation's
    // linear stage, a study's prediction), never as the rigid rotor it replaces.
    if let Some(shaft) = &s.shaft {
        return analyse_flexible(s, shaft.model.clone(), shaft.bearing_nodes, speeds_hz)
            .map(|(r, solved, _)| (r, solved));
    }
    let t0 = std::time::Instant::now();
    let (rotor, films) = checked_params(s, speeds_hz)?;
    analyse_rotor(&rotor, &films, s, speeds_hz, t0)
}

/// The rotor and film parameters of `s`, checked for the linear analysis, and the speeds.
fn checked_params(
    s: &RunupSettings,
    speeds_hz: &[f64],
) -> Result<(RotorParams, [BearingParams; 2]), String> {
    let (rotor, films) = params_of(s)?;
    rotor
        .validate()
        .map_err(|e| with_units("rotor", format!("rotor: {e}")))?;
    if !(rotor.c_c_n_m > 0.0 && rotor.c_t_n_m > 0.0) {
        // Without a mount stiffness the rings have no static position to linearize about.
        return Err(format!(
            "the linear analysis needs ring mount stiffnesses c > 0 (c_C = {} N/m, c_T = {} N/m)",
            rotor.c_c_n_m, rotor.c_t_n_m
        ));
    }
    for (f, side) in films.iter().zip(["C", "T"]) {
        f.validate()
            .map_err(|e| with_units("film", format!("film_{side}: {e}")))?;
    }
    if speeds_hz.is_empty() || speeds_hz.iter().any(|f| !(f.is_finite() && *f > 0.0)) {
        return Err("speeds must be finite and > 0 Hz".into());
    }
    Ok((rotor, films))
}

/// `analyse_with_equilibria` for a flexible rotor: `model` (no bearings of its own) on the air
/// ring bearings of `s` (films, ring masses, mounts, gravity) at the nodes `bearing_nodes` [C, T].
/// The modes followed are those below twice the highest speed (at least 1 kHz).
pub fn analyse_flexible(
    s: &RunupSettings,
    model: shaft::ShaftModel,
    bearing_nodes: [usize; 2],
    speeds_hz: &[f64],
) -> Result<
    (
        StabilityReport,
        Vec<[SolvedBearing; 2]>,
        structure::FlexibleRotor,
    ),
    String,
> {
    let t0 = std::time::Instant::now();
    let (p, films) = checked_params(s, speeds_hz)?;
    let mut rotor = structure::FlexibleRotor::new(
        model,
        bearing_nodes,
        [
            (p.m_r_c_kg, p.c_c_n_m, p.d_c_n_s_m),
            (p.m_r_t_kg, p.c_t_n_m, p.d_t_n_s_m),
        ],
        p.g_m_s2,
    )?;
    rotor.cap_hz = crate::flexible::campbell_cap_hz(speeds_hz);
    let (report, solved) = analyse_rotor(&rotor, &films, s, speeds_hz, t0)?;
    Ok((report, solved, rotor))
}

fn analyse_rotor<R: LinearRotor>(
    rotor: &R,
    films: &[BearingParams; 2],
    s: &RunupSettings,
    speeds_hz: &[f64],
    t0: std::time::Instant,
) -> Result<(StabilityReport, Vec<[SolvedBearing; 2]>), String> {
    let results = per_speed(rotor, films, speeds_hz).into_iter();
    let mut speeds = Vec::with_capacity(speeds_hz.len());
    let mut solved = Vec::with_capacity(speeds_hz.len());
    for r in results {
        let (res, eq) = r?;
        speeds.push(res);
        solved.push(eq);
    }
    let first_unstable = speeds.iter().position(|r| r.max_growth_per_s() > 0.0);
    let mut threshold = None;
    let unstable_at_first_speed = first_unstable == Some(0);
    if let Some(i) = first_unstable.filter(|&i| i > 0) {
        let tolerance_hz = 0.5;
        let (mut lo, mut hi) = (speeds_hz[i - 1], speeds_hz[i]);
        // Warm start from the last stable speed: equilibria move little over the bracket.
        let mut warm: Option<[SolvedBearing; 2]> = None;
        let mut hi_mode = speeds[i].critical();
        while hi - lo > tolerance_hz {
            let mid = 0.5 * (lo + hi);
            let w = warm.as_ref().unwrap_or(&solved[i - 1]);
            let (r, eq) = analyse_speed(rotor, films, mid, Some(w))?;
            if r.max_growth_per_s() > 0.0 {
                hi = mid;
                hi_mode = r.critical();
            } else {
                lo = mid;
                warm = Some(eq);
            }
        }
        if let Some(mode) = hi_mode {
            let speed_hz = 0.5 * (lo + hi);
            threshold = Some(Threshold {
                speed_hz,
                tolerance_hz,
                whirl_ratio: mode.freq_hz / speed_hz,
                mode,
            });
        }
    }
    let ramp_hz_per_s = s.f_max_hz / s.t_ramp_s;
    let report = StabilityReport {
        growth_exponent: growth_exponent(&speeds, ramp_hz_per_s),
        ramp_hz_per_s,
        speeds,
        threshold,
        unstable_at_first_speed,
        wall_time_s: t0.elapsed().as_secs_f64(),
    };
    Ok((report, solved))
}

/// Most speeds one `--speeds` grid may give: each is an analysis of its own (an equilibrium and
/// an eigenvalue problem, or an orbit); 10 001 were taken before and ran for minutes without a
/// line of output.
pub const MAX_SPEEDS: usize = 1000;

/// "from:to:step" [Hz] -> the speed grid (inclusive of `to` within rounding); a single "F" is the
/// one speed F. Each way a grid can be wrong is named.
pub fn parse_speeds(spec: &str) -> Result<Vec<f64>, String> {
    let head = format!("--speeds '{spec}'");
    let parts: Vec<&str> = spec.split(':').collect();
    if !(parts.len() == 1 || parts.len() == 3) {
        return Err(format!(
            "{head}: expected from:to:step in Hz (e.g. 100:2000:50) or one speed"
        ));
    }
    let mut v = Vec::with_capacity(3);
    for (part, what) in parts.iter().zip(["from", "to", "step"]) {
        let x: f64 = part
            .trim()
            .parse()
            .map_err(|_| format!("{head}: {what} '{}' is not a number (Hz)", part.trim()))?;
        if !x.is_finite() {
            return Err(format!("{head}: {what} must be a finite number of Hz"));
        }
        v.push(x);
    }
    let max_hz = crate::runup::MAX_SPEED_HZ;
    let (from, to, step) = match v[..] {
        [f] => (f, f, 1.0),
        [from, to, step] => (from, to, step),
        _ => unreachable!("one or three parts"),
    };
    if from <= 0.0 {
        return Err(format!("{head}: the speeds must be > 0 Hz (from = {from})"));
    }
    if to > max_hz {
        return Err(format!(
            "{head}: the speeds must be at most {max_hz} Hz (to = {to}), as a run-up's"
        ));
    }
    if to < from {
        return Err(format!("{head}: to = {to} Hz lies below from = {from} Hz"));
    }
    if step <= 0.0 {
        return Err(format!("{head}: the step must be > 0 Hz (step = {step})"));
    }
    let count = (to - from) / step + 1.0;
    if count > MAX_SPEEDS as f64 + 1e-9 {
        return Err(format!(
            "{head}: {count:.0} speeds, at most {MAX_SPEEDS} (each is an analysis of its own): \
             take a larger step"
        ));
    }
    let n = ((to - from) / step + 1e-9).floor() as usize;
    Ok((0..=n).map(|k| from + step * k as f64).collect())
}

/// Film mesh per lobe of the linear predictions (a study's `--linear` map, the run-ups' calm
/// plans) where none is given: on the path-1 parameters it gives the paper mesh's threshold
/// within 0.15 % and its growth exponents within 1 % at a tenth of the time (docs/stability.md).
pub const LINEAR_PREDICTION_MESH: (u32, u32) = (8, 2);

/// Least damping ratio over the oscillating modes; -1 for a static divergence (a positive real
/// eigenvalue).
pub fn least_damping_ratio(r: &SpeedResult) -> f64 {
    if r.real_eigenvalues_per_s.iter().any(|&re| re > 0.0) {
        return -1.0;
    }
    r.modes
        .iter()
        .map(|m| m.damping_ratio)
        .fold(f64::INFINITY, f64::min)
        .min(1.0)
}
