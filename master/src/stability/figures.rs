//! Campbell and damping diagrams of a stability report, drawn with the run-up plot helpers
//! (`plot::axes`, `plot::canvas`): one polyline per mode rank (modes sorted by frequency at each
//! speed, so a line can jump where two modes cross); whirl directions are in stability.json.

use super::StabilityReport;
use crate::plot::axes::Axes;
use crate::plot::canvas::{Anchor, Canvas, Rgb, Role};
use std::path::{Path, PathBuf};

const W: u32 = 900;
const H: u32 = 560;
const PALETTE: [Rgb; 8] = [
    Rgb(31, 119, 180),
    Rgb(255, 127, 14),
    Rgb(44, 160, 44),
    Rgb(214, 39, 40),
    Rgb(148, 103, 189),
    Rgb(140, 86, 75),
    Rgb(227, 119, 194),
    Rgb(127, 127, 127),
];

fn n_modes(r: &StabilityReport) -> usize {
    r.speeds.iter().map(|s| s.modes.len()).min().unwrap_or(0)
}

fn range(vals: impl Iterator<Item = f64>) -> (f64, f64) {
    vals.filter(|v| v.is_finite())
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(l, h), v| {
            (l.min(v), h.max(v))
        })
}

/// Vertical line and label at the threshold speed (if any).
fn mark_threshold(c: &mut Canvas, ax: &Axes, r: &StabilityReport) {
    if let Some(t) = &r.threshold {
        let (px, _) = ax.map(t.speed_hz, ax.y.0);
        c.polyline(
            vec![(px, ax.top), (px, ax.top + ax.height)],
            Rgb::BLACK,
            1.0,
            true,
            Role::Marker,
            "threshold",
        );
        let label = format!(
            "threshold {:.0} Hz: {} whirl at {:.0} Hz",
            t.speed_hz, t.mode.whirl, t.mode.freq_hz
        );
        c.text(px + 4.0, ax.top + 14.0, &label, 12.0, Anchor::Start);
    }
}

/// Natural frequencies of the damped modes vs speed, with the 1x (synchronous) line.
pub fn campbell(r: &StabilityReport) -> Canvas {
    let speeds: Vec<f64> = r.speeds.iter().map(|s| s.speed_hz).collect();
    let xr = range(speeds.iter().copied());
    let fr = range(
        r.speeds
            .iter()
            .flat_map(|s| s.modes.iter().map(|m| m.freq_hz)),
    );
    let mut c = Canvas::new(W, H);
    let ax = Axes::standard(W, H, xr, (0.0, fr.1.max(xr.1)));
    ax.draw(
        &mut c,
        "Campbell diagram (damped whirl frequencies)",
        "rotor speed [Hz]",
        "whirl frequency [Hz]",
    );
    c.polyline(
        ax.map_all([(xr.0, xr.0), (xr.1, xr.1)]),
        Rgb::BLACK,
        1.0,
        true,
        Role::Reference,
        "1x",
    );
    let mut legend = vec![];
    let names: Vec<String> = (0..n_modes(r)).map(|k| format!("mode {}", k + 1)).collect();
    for k in 0..n_modes(r) {
        let pts = r.speeds.iter().map(|s| (s.speed_hz, s.modes[k].freq_hz));
        c.polyline(
            ax.map_all(pts),
            PALETTE[k % 8],
            1.6,
            false,
            Role::Series,
            &names[k],
        );
        legend.push((names[k].as_str(), PALETTE[k % 8]));
    }
    mark_threshold(&mut c, &ax, r);
    ax.legend(&mut c, &legend);
    c
}

/// Damping ratio [%] of each mode vs speed; < 0 is unstable.
pub fn damping(r: &StabilityReport) -> Canvas {
    let xr = range(r.speeds.iter().map(|s| s.speed_hz));
    let zr = range(
        r.speeds
            .iter()
            .flat_map(|s| s.modes.iter().map(|m| 100.0 * m.damping_ratio)),
    );
    // The interesting part is near zero: clip very well damped modes at 30 %.
    let zr = (zr.0.min(-1.0), zr.1.clamp(1.0, 30.0));
    let mut c = Canvas::new(W, H);
    let ax = Axes::standard(W, H, xr, zr);
    ax.draw(
        &mut c,
        "Damping ratio of the whole-system modes",
        "rotor speed [Hz]",
        "damping ratio [%]",
    );
    c.polyline(
        ax.map_all([(xr.0, 0.0), (xr.1, 0.0)]),
        Rgb::BLACK,
        1.0,
        false,
        Role::Reference,
        "zero",
    );
    let mut legend = vec![];
    let names: Vec<String> = (0..n_modes(r)).map(|k| format!("mode {}", k + 1)).collect();
    for k in 0..n_modes(r) {
        let pts = r
            .speeds
            .iter()
            .map(|s| (s.speed_hz, (100.0 * s.modes[k].damping_ratio).min(zr.1)));
        c.polyline(
            ax.map_all(pts),
            PALETTE[k % 8],
            1.6,
            false,
            Role::Series,
            &names[k],
        );
        legend.push((names[k].as_str(), PALETTE[k % 8]));
    }
    mark_threshold(&mut c, &ax, r);
    ax.legend(&mut c, &legend);
    c
}

/// Write campbell.svg/.png and damping.svg/.png into `dir`.
pub fn save(r: &StabilityReport, dir: &Path) -> std::io::Result<Vec<PathBuf>> {
    let mut out = campbell(r).save(dir, "campbell")?;
    out.extend(damping(r).save(dir, "damping")?);
    Ok(out)
}
