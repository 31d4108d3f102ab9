//! Where a run-up may take long macro steps: before the rotor comes near any instability.
//!
//! Why: a stable run-up spends 3 s of simulated time at the quiet equilibrium, and the films' own
//! error control would take 100 us steps there, but the 50 us macro step makes them take two.
//! The macro step is 50 us because of weakly damped and weakly unstable whirl modes: the explicit
//! coupling adds a small damping error (~(omega h)^3), which moves the onset of a slowly growing
//! whirl (docs/convergence.md, "A 100 us macro step"). Where every mode is well damped that
//! error is a small fraction of the mode's own damping and changes nothing that is measured.
//!
//! How: the linear stability analysis (`crate::stability`, on a coarse film mesh, ~0.1 s per 12
//! speeds) gives the least damping ratio of all modes at speeds every 50 Hz along the speed
//! profile, from the lowest speed up to where the window is decided. The run is
//! calm from the first time the speed lies on that grid with both neighbouring grid speeds
//! analysed and the interpolated least damping ratio at least [`CALM_DAMPING_RATIO`], until the
//! first time it is not. Only that first stretch: after a loss of damping the rotor may carry a
//! whirl the linear model does not see (a large whirl coexisting with a stable equilibrium, a
//! run-down through a hysteresis), so no window opens again. Speeds where the analysis fails (no
//! equilibrium) are never calm.
//!
//! The linear model can be wrong about the state the run-up is in: with dH = 0 it finds a damped
//! equilibrium at 50-100 Hz (d = 500 N s/m) while the run-up already whirls on its rings from
//! 7 Hz. There the macro-step control rejects a 100 us step within milliseconds, and the run
//! (`cosim::execution`) closes the window at the first rejected or discarded step in it.

use crate::linear_cache::LinearCache;
use crate::runup::RunupSettings;
use crate::stability::{params_of, per_speed};
use fmu_rotor::params::SpeedProfile;
use serde::Serialize;
use std::f64::consts::TAU;

/// Least damping ratio of every mode for a calm macro step. The coupling's damping error at a
/// 100 us macro step is ~0.004 (docs/convergence.md, "Calm macro steps"), a fifth of this. 0.02
/// rather than 0.05 lets a stable design run calm to the end instead of closing its window
/// where its least damped mode dips below 0.05 (C20/dH40/c1000/d500: 10.1 -> 6.6 s, every
/// time-series column within 1e-7 of its range), and moved the Section 3 presets' onsets by less
/// than 1e-5 s ("Calm threshold 0.02" there).
pub const CALM_DAMPING_RATIO: f64 = 0.02;

/// Speed grid of the analysis [Hz], from this speed up to the profile's highest.
pub const CALM_SPEED_STEP_HZ: f64 = 50.0;

/// Time resolution of the windows [s].
const TIME_STEP_S: f64 = 1e-3;

/// What the analysis found and the window it gives.
#[derive(Clone, Debug, Default, PartialEq, Serialize)]
pub struct CalmPlan {
    /// [start, end] of simulated time [s] with long macro steps (none or one).
    pub windows_s: Vec<(f64, f64)>,
    /// Per grid speed [Hz] analysed (from the lowest up to where the window is decided): the
    /// least damping ratio of all modes, None where the analysis failed.
    pub least_damping: Vec<(f64, Option<f64>)>,
    /// Why there is no window although one was asked for (the analysis could not run).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub note: Option<String>,
    pub wall_time_s: f64,
}

/// The calm window of a run-up with `s`'s parameters and speed profile, its film coefficients on
/// the coarse mesh of the linear predictions (`stability::LINEAR_PREDICTION_MESH`). Speeds found in
/// `cache` are not analysed again; the ones analysed here are added to it.
pub fn plan(s: &RunupSettings, cache: Option<&LinearCache>) -> CalmPlan {
    let t0 = std::time::Instant::now();
    let mut coarse = s.clone();
    (coarse.n_elem_phi, coarse.n_elem_z) = crate::stability::LINEAR_PREDICTION_MESH;
    // The predictions' mesh is uniform: a run-up's graded one would give other film parameters,
    // whose analyses no prediction shares (and the linear analysis does not need it).
    coarse.mesh_grading = 1.0;
    let params = params_of(&coarse).and_then(|(rotor, films)| {
        if rotor.c_c_n_m > 0.0 && rotor.c_t_n_m > 0.0 {
            Ok((rotor, films))
        } else {
            Err("the linear analysis needs ring mount stiffnesses c > 0".into())
        }
    });
    let (rotor, films) = match params {
        Ok(p) => p,
        Err(e) => {
            return CalmPlan {
                note: Some(e),
                wall_time_s: t0.elapsed().as_secs_f64(),
                ..CalmPlan::default()
            }
        }
    };
    let profile = SpeedProfile::of(&rotor);
    let speed_hz = |t: f64| profile.rate_rad_s(t) / TAU;
    let n_t = (s.stop_time_s / TIME_STEP_S).ceil() as usize;
    let top_hz = (0..=n_t)
        .map(|i| speed_hz(i as f64 * TIME_STEP_S))
        .fold(0.0, f64::max);
    let n_speeds = (top_hz / CALM_SPEED_STEP_HZ).ceil() as usize;
    let speeds: Vec<f64> = (1..=n_speeds)
        .map(|i| i as f64 * CALM_SPEED_STEP_HZ)
        .collect();
    let (least_damping, windows_s) = batched_calm_window(
        &speeds,
        |chunk| {
            let known: Vec<Option<Option<f64>>> = chunk
                .iter()
                .map(|&f| cache.and_then(|c| c.get(&rotor, &films, f)))
                .collect();
            let missing: Vec<f64> = chunk
                .iter()
                .zip(&known)
                .filter(|(_, k)| k.is_none())
                .map(|(&f, _)| f)
                .collect();
            let mut analysed = per_speed(&rotor, &films, &missing).into_iter().map(|r| {
                r.ok()
                    .map(|(res, _)| crate::stability::least_damping_ratio(&res))
            });
            let mut cache_note = None;
            let ratios = chunk
                .iter()
                .zip(known)
                .map(|(&f, k)| {
                    k.unwrap_or_else(|| {
                        let z = analysed.next().expect("one result per missing speed");
                        if let Some(Err(e)) = cache.map(|c| c.put(&rotor, &films, f, z)) {
                            cache_note.get_or_insert(e);
                        }
                        z
                    })
                })
                .collect();
            if let Some(e) = cache_note {
                eprintln!("warning: linear analyses not kept for reuse: {e}");
            }
            ratios
        },
        speed_hz,
        s.stop_time_s,
    );
    CalmPlan {
        windows_s,
        least_damping,
        note: None,
        wall_time_s: t0.elapsed().as_secs_f64(),
    }
}

/// One line for the terminal: the window and what it rests on.
pub fn describe(plan: &CalmPlan, calm_macro_step_us: f64) -> String {
    let basis = format!(
        "least damping ratio >= {CALM_DAMPING_RATIO} in the linear analysis, which took {:.1} s of wall time",
        plan.wall_time_s
    );
    match (plan.windows_s.first(), &plan.note) {
        (Some(&(a, b)), _) => {
            format!(
                "calm macro steps of {calm_macro_step_us} us from {a:.3} s to {b:.3} s ({basis})"
            )
        }
        (None, Some(why)) => format!("no calm macro steps: {why}"),
        (None, None) => format!("no calm macro steps: no calm stretch ({basis})"),
    }
}

/// A grid speed [Hz] and its least damping ratio (None: the analysis failed there).
type SpeedDamping = (f64, Option<f64>);

/// Speeds analysed at a time (`plan`): two per thread on two cores.
const SPEEDS_PER_BATCH: usize = 4;

/// The least damping ratios at `speeds` (ascending) from the lowest up, [`SPEEDS_PER_BATCH`] at
/// a time through `analyse`, until the calm window no longer depends on the speeds above (path
/// 1's window ends at 424 Hz: 12 of 40 speeds analysed); the ratios analysed and the window,
/// which is the one of all speeds.
fn batched_calm_window(
    speeds: &[f64],
    mut analyse: impl FnMut(&[f64]) -> Vec<Option<f64>>,
    speed_hz: impl Fn(f64) -> f64,
    stop_s: f64,
) -> (Vec<SpeedDamping>, Vec<(f64, f64)>) {
    let mut least_damping: Vec<(f64, Option<f64>)> = Vec::with_capacity(speeds.len());
    for (c, chunk) in speeds.chunks(SPEEDS_PER_BATCH).enumerate() {
        least_damping.extend(chunk.iter().copied().zip(analyse(chunk)));
        let last_batch = (c + 1) * SPEEDS_PER_BATCH >= speeds.len();
        let analysed_to_hz = if last_batch {
            f64::INFINITY
        } else {
            least_damping.last().map_or(0.0, |&(f, _)| f)
        };
        let (w, examined) = first_calm_window_upto(
            &least_damping,
            &speed_hz,
            stop_s,
            CALM_DAMPING_RATIO,
            analysed_to_hz,
        );
        let seen_max_hz = (0..=examined)
            .map(|i| speed_hz(grid_time(i, stop_s)))
            .fold(0.0, f64::max);
        if last_batch || seen_max_hz <= analysed_to_hz {
            return (least_damping, w);
        }
    }
    (least_damping, vec![])
}

/// Time of sample `i` of the windows' grid.
fn grid_time(i: usize, stop_s: f64) -> f64 {
    (i as f64 * TIME_STEP_S).min(stop_s)
}

/// The first stretch of time (on a 1 ms grid) in which the least damping ratio, interpolated
/// between the analysed grid speeds around the speed at that time, is at least `min_ratio`
/// ([`CALM_DAMPING_RATIO`] in a run-up); outside the grid or next to a failed speed it is not
/// calm.
#[cfg(test)]
fn first_calm_window(
    least_damping: &[(f64, Option<f64>)],
    speed_hz: impl Fn(f64) -> f64,
    stop_s: f64,
    min_ratio: f64,
) -> Vec<(f64, f64)> {
    first_calm_window_upto(least_damping, speed_hz, stop_s, min_ratio, f64::INFINITY).0
}

/// [`first_calm_window`] while the speeds above `analysed_to_hz` are not analysed yet (they
/// count as not calm; infinite: all are), and the last grid sample it looked at. The window is
/// the one of the whole grid when no speed up to that sample exceeds `analysed_to_hz`: at those
/// speeds the interpolation reads the same grid values either way.
fn first_calm_window_upto(
    least_damping: &[(f64, Option<f64>)],
    speed_hz: impl Fn(f64) -> f64,
    stop_s: f64,
    min_ratio: f64,
    analysed_to_hz: f64,
) -> (Vec<(f64, f64)>, usize) {
    let calm_at = |f: f64| -> bool {
        if f > analysed_to_hz {
            return false;
        }
        let i = least_damping.partition_point(|&(g, _)| g <= f);
        if i == 0 {
            return false;
        }
        let (f0, z0) = least_damping[i - 1];
        let (f1, z1) = least_damping.get(i).copied().unwrap_or((f0, z0));
        match (z0, z1) {
            (Some(z0), Some(z1)) => {
                let w = if f1 > f0 { (f - f0) / (f1 - f0) } else { 0.0 };
                z0 + w * (z1 - z0) >= min_ratio
            }
            _ => false,
        }
    };
    let n_t = (stop_s / TIME_STEP_S).ceil() as usize;
    let time = |i: usize| grid_time(i, stop_s);
    let Some(first) = (0..=n_t).find(|&i| calm_at(speed_hz(time(i)))) else {
        return (vec![], n_t);
    };
    let not_calm = (first..=n_t).find(|&i| !calm_at(speed_hz(time(i))));
    // The last calm sample ends the window; with none, the run ends calm.
    let end = not_calm.map_or(stop_s, |i| time(i - 1));
    let examined = not_calm.unwrap_or(n_t);
    if end > time(first) {
        (vec![(time(first), end)], examined)
    } else {
        (vec![], examined)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_window_is_the_first_calm_stretch_only() {
        // Damping falls below 0.05 between 300 and 350 Hz and recovers above 500 Hz; 450 Hz failed.
        let zeta = [
            (50.0, Some(0.2)),
            (100.0, Some(0.2)),
            (150.0, Some(0.2)),
            (200.0, Some(0.1)),
            (250.0, Some(0.08)),
            (300.0, Some(0.06)),
            (350.0, Some(0.04)),
            (400.0, Some(0.02)),
            (450.0, None),
            (500.0, Some(0.2)),
            (550.0, Some(0.3)),
        ];
        // 0 -> 600 Hz in 0.6 s: 1 Hz per ms.
        let speed = |t| 1000.0 * t;
        let w = first_calm_window(&zeta, speed, 0.6, 0.05);
        assert_eq!(w.len(), 1);
        let (a, b) = w[0];
        // Calm from 50 Hz; 0.05 is crossed at 325 Hz.
        assert!((a - 0.050).abs() < 1e-12, "{a}");
        assert!((b - 0.325).abs() < 1.5e-3, "{b}");
        // At 0.02 the window reaches 400 Hz (0.02 exactly), whose upper neighbour failed: its
        // last calm sample is 399 Hz. The window does not reopen at 500 Hz.
        let w = first_calm_window(&zeta, speed, 0.6, 0.02);
        assert_eq!(w.len(), 1);
        assert!((w[0].0 - 0.050).abs() < 1e-12, "{w:?}");
        assert!((w[0].1 - 0.399).abs() < 1e-9, "{w:?}");
        // Calm all the way (the speed stays on the grid, and constant after the ramp).
        let w = first_calm_window(&zeta[..3], |t| (100.0 * t / 0.3).min(100.0), 1.0, 0.05);
        assert_eq!(w.len(), 1);
        assert!((w[0].0 - 0.150).abs() < 1e-12 && w[0].1 == 1.0, "{w:?}");
        // Nothing calm: no window.
        let not_calm = [(50.0, Some(0.01)), (100.0, None)];
        assert!(first_calm_window(&not_calm, speed, 0.2, CALM_DAMPING_RATIO).is_empty());
    }

    /// Batches from the lowest speed up give the window of all speeds, and stop early where the
    /// window ends below the top speed: run-ups whose damping falls below the threshold early,
    /// late or never, one with a failed speed, one with no calm speed, and a run-up with a
    /// run-down (the speed comes back through the analysed range).
    #[test]
    fn batches_from_the_lowest_speed_give_the_window_of_all_speeds() {
        let speeds: Vec<f64> = (1..=40).map(|i| 50.0 * i as f64).collect();
        type Damping = Box<dyn Fn(f64) -> Option<f64>>;
        let dampings: Vec<(&str, Damping)> = vec![
            ("path-1-like", Box::new(|f| Some(0.2 - f / 2500.0))),
            ("late", Box::new(|f| Some(0.2 - f / 9000.0))),
            ("stable", Box::new(|_| Some(0.1))),
            ("never calm", Box::new(|_| Some(0.01))),
            (
                "failed at 300 Hz",
                Box::new(|f| (f != 300.0).then_some(0.1)),
            ),
        ];
        let ramp = |t: f64| 2000.0 * (t / 3.0).min(1.0);
        let up_and_down = |t: f64| 2000.0 * (1.0 - (t / 1.5 - 1.0).abs());
        let profiles: [(&str, &dyn Fn(f64) -> f64); 2] =
            [("ramp", &ramp), ("up and down", &up_and_down)];
        for (name, zeta) in &dampings {
            for (pname, speed) in profiles {
                let all: Vec<(f64, Option<f64>)> = speeds.iter().map(|&f| (f, zeta(f))).collect();
                let full = first_calm_window(&all, speed, 3.0, CALM_DAMPING_RATIO);
                let mut analysed = 0;
                let (ld, w) = batched_calm_window(
                    &speeds,
                    |chunk| {
                        analysed += chunk.len();
                        chunk.iter().map(|&f| zeta(f)).collect()
                    },
                    speed,
                    3.0,
                );
                assert_eq!(w, full, "{name}, {pname}");
                assert_eq!(ld[..], all[..ld.len()], "{name}, {pname}");
                if *name == "path-1-like" {
                    // Calm until 450 Hz: 0.2 - f / 2500 = 0.02 there.
                    assert!(
                        !w.is_empty() && analysed <= 12,
                        "{pname}: {analysed} speeds, {w:?}"
                    );
                }
                if *name == "stable" || *name == "never calm" {
                    assert_eq!(analysed, speeds.len(), "{name}, {pname}");
                }
            }
        }
    }
}
