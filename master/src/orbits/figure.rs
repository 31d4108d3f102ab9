//! The bifurcation diagram of `airring orbits`: each orbit's largest eccentricity per bearing
//! against speed, stable stretches of the branch solid, unstable ones dashed, the orbits shot
//! from settled simulations as short crosses, the linear threshold and the branch's Hopf point
//! marked; beside it, when given, a run-up's eccentricity envelope (light) for comparison.

use super::driver::{OrbitRecord, OrbitsReport};
use crate::analysis::{Bearing, RunSeries};
use crate::plot::{decimate_minmax, Chart, Figure, Rgb, Role};
use std::path::{Path, PathBuf};

fn eps_of(o: &OrbitRecord, b: usize) -> f64 {
    if b == 0 {
        o.max_eps_c
    } else {
        o.max_eps_t
    }
}

fn lighter(Rgb(r, g, b): Rgb) -> Rgb {
    Rgb(r / 3 + 170, g / 3 + 170, b / 3 + 170)
}

pub fn bifurcation_diagram(report: &OrbitsReport, runup: Option<&RunSeries>) -> Chart {
    let mut xs: Vec<f64> = report.orbits.iter().map(|o| o.speed_hz).collect();
    xs.extend(report.speeds_hz.iter().copied());
    let mut ys: Vec<f64> = report
        .orbits
        .iter()
        .flat_map(|o| [o.max_eps_c, o.max_eps_t])
        .collect();
    ys.push(0.0);
    let env = runup.map(|s| {
        let lo = xs.iter().copied().fold(f64::INFINITY, f64::min);
        let hi = xs.iter().copied().fold(f64::NEG_INFINITY, f64::max);
        let speed = s.speed_hz();
        let keep: Vec<usize> = (0..speed.len())
            .filter(|&i| speed[i] >= lo && speed[i] <= hi)
            .collect();
        let pick = |v: Vec<f64>| keep.iter().map(|&i| v[i]).collect::<Vec<f64>>();
        (
            pick(speed.clone()),
            pick(s.eps(Bearing::C)),
            pick(s.eps(Bearing::T)),
        )
    });
    if let Some((_, c, t)) = &env {
        ys.extend(c.iter().chain(t.iter()).copied());
    }
    let finite = |v: &[f64]| {
        v.iter()
            .filter(|x| x.is_finite())
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(l, h), x| {
                (l.min(*x), h.max(*x))
            })
    };
    let mut chart = Chart::new(
        900,
        500,
        "Whirl orbits: largest eccentricity against speed",
        "rotor speed [Hz]",
        "max eps = max |dr| / C [-]",
        finite(&xs),
        finite(&ys),
    );
    let buckets = chart.frame_width_px();
    if let Some((speed, c, t)) = &env {
        for (eps, name, color) in [(c, "C", Rgb::BLUE), (t, "T", Rgb::RED)] {
            chart.line(
                decimate_minmax(speed, eps, buckets),
                lighter(color),
                1.0,
                false,
                Role::Series,
                &format!("run-up eps_{name}"),
            );
        }
    }
    // The continued branch in its order, cut where its stability changes.
    let branch: Vec<&OrbitRecord> = report
        .orbits
        .iter()
        .filter(|o| o.branch == "continuation")
        .collect();
    let start = report
        .orbits
        .iter()
        .filter(|o| o.branch == "settled" && o.stable)
        .max_by(|a, b| a.speed_hz.total_cmp(&b.speed_hz));
    let path: Vec<&OrbitRecord> = start.into_iter().chain(branch).collect();
    for (b, name, color) in [(0, "C", Rgb::BLUE), (1, "T", Rgb::RED)] {
        let mut i = 0;
        while i + 1 < path.len() {
            let stable = path[i + 1].stable;
            let mut j = i + 1;
            while j + 1 < path.len() && path[j + 1].stable == stable {
                j += 1;
            }
            chart.line(
                path[i..=j].iter().map(|o| (o.speed_hz, eps_of(o, b))),
                color,
                2.0,
                !stable,
                Role::Series,
                &format!(
                    "orbit max eps_{name} ({})",
                    if stable { "stable" } else { "unstable" }
                ),
            );
            i = j;
        }
        // Orbits shot from settled simulations: a cross each.
        let dx = 0.004 * (chart.x.1 - chart.x.0);
        let dy = 0.015 * (chart.y.1 - chart.y.0);
        for o in report.orbits.iter().filter(|o| o.branch == "settled") {
            let (x, y) = (o.speed_hz, eps_of(o, b));
            for seg in [
                [(x - dx, y - dy), (x + dx, y + dy)],
                [(x - dx, y + dy), (x + dx, y - dy)],
            ] {
                chart.line(
                    seg,
                    color,
                    1.5,
                    false,
                    Role::Series,
                    &format!("settled orbit eps_{name}"),
                );
            }
        }
    }
    if let Some(f) = report.linear_threshold_hz {
        chart.marker(
            f,
            "linear threshold",
            Some(format!("linear threshold {f:.0} Hz")),
        );
    }
    // The Hopf point is usually within a few Hz of the threshold: its line is unlabelled and
    // its value goes into the legend, where the two texts cannot collide.
    let hopf = report.hopf_estimate_hz.map(|f| {
        chart.marker(f, "Hopf point", None);
        format!(
            "branch from {f:.0} Hz{}",
            report
                .criticality
                .as_ref()
                .map_or(String::new(), |c| format!(" ({c})"))
        )
    });
    let mut legend = vec![
        ("eps_C (dashed: unstable)".to_string(), Rgb::BLUE),
        ("eps_T (dashed: unstable)".to_string(), Rgb::RED),
    ];
    if env.is_some() {
        legend.push(("run-up eps_C".into(), lighter(Rgb::BLUE)));
        legend.push(("run-up eps_T".into(), lighter(Rgb::RED)));
    }
    if let Some(h) = hopf {
        legend.push((h, Rgb::BLACK));
    }
    let legend: Vec<(&str, Rgb)> = legend.iter().map(|(t, c)| (t.as_str(), *c)).collect();
    chart.legend(&legend);
    chart
}

/// Writes `bifurcation.svg` and `.png` into `out_dir`.
pub fn write_bifurcation_diagram(
    report: &OrbitsReport,
    runup: Option<&RunSeries>,
    out_dir: &Path,
) -> std::io::Result<Vec<PathBuf>> {
    bifurcation_diagram(report, runup).save(out_dir, "bifurcation")
}
