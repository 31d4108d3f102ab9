//! Figures of a stability report, drawn as `plot::Chart`s: Campbell and damping diagrams (one polyline per mode rank: modes sorted by
//! frequency at each speed, so a line can jump where two modes cross; whirl directions are in
//! stability.json), and the static equilibrium vs speed (journal locus in the bore, eccentricity).

use super::StabilityReport;
use crate::plot::{bearing_frame, Anchor, Chart, Figure, Rgb, Role};
use bearing::Bore;
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

/// The most oscillating modes at any speed (at low speed heavy ring damping can leave fewer).
fn n_modes(r: &StabilityReport) -> usize {
    r.speeds.iter().map(|s| s.modes.len()).max().unwrap_or(0)
}

/// Mode rank `k`'s points (speed, value) as runs of consecutive speeds that have that rank: a
/// speed with fewer oscillating modes breaks the line instead of dropping the mode everywhere.
fn rank_segments(
    r: &StabilityReport,
    k: usize,
    value: impl Fn(&super::campbell::ModeResult) -> f64,
) -> Vec<Vec<(f64, f64)>> {
    let mut out: Vec<Vec<(f64, f64)>> = vec![];
    let mut open = false;
    for s in &r.speeds {
        match s.modes.get(k) {
            Some(m) => {
                if !open {
                    out.push(vec![]);
                    open = true;
                }
                out.last_mut().expect("open").push((s.speed_hz, value(m)));
            }
            None => open = false,
        }
    }
    out
}

fn range(vals: impl Iterator<Item = f64>) -> (f64, f64) {
    vals.filter(|v| v.is_finite())
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(l, h), v| {
            (l.min(v), h.max(v))
        })
}

/// Vertical line and label at the threshold speed (if any).
fn mark_threshold(c: &mut Chart, r: &StabilityReport) {
    if let Some(t) = &r.threshold {
        let label = format!(
            "threshold {:.0} Hz: {} whirl at {:.0} Hz",
            t.speed_hz, t.mode.whirl, t.mode.freq_hz
        );
        c.marker(t.speed_hz, "threshold", Some(label));
    }
}

/// One line per mode rank of `value` vs speed (broken where a speed lacks the rank), the
/// threshold marker and the legend.
fn mode_lines(
    c: &mut Chart,
    r: &StabilityReport,
    value: impl Fn(&super::campbell::ModeResult) -> f64,
) {
    let names: Vec<String> = (0..n_modes(r)).map(|k| format!("mode {}", k + 1)).collect();
    for (k, name) in names.iter().enumerate() {
        for seg in rank_segments(r, k, &value) {
            c.line(seg, PALETTE[k % 8], 1.6, false, Role::Series, name);
        }
    }
    mark_threshold(c, r);
    let legend: Vec<(&str, Rgb)> = names
        .iter()
        .enumerate()
        .map(|(k, n)| (n.as_str(), PALETTE[k % 8]))
        .collect();
    c.legend(&legend);
}

/// Natural frequencies of the damped modes vs speed, with the 1x (synchronous) line.
pub fn campbell(r: &StabilityReport) -> Chart {
    let speeds: Vec<f64> = r.speeds.iter().map(|s| s.speed_hz).collect();
    let xr = range(speeds.iter().copied());
    let fr = range(
        r.speeds
            .iter()
            .flat_map(|s| s.modes.iter().map(|m| m.freq_hz)),
    );
    let mut c = Chart::new(
        W,
        H,
        "Campbell diagram (damped whirl frequencies)",
        "rotor speed [Hz]",
        "whirl frequency [Hz]",
        xr,
        (0.0, fr.1.max(xr.1)),
    );
    c.line(
        [(xr.0, xr.0), (xr.1, xr.1)],
        Rgb::BLACK,
        1.0,
        true,
        Role::Reference,
        "1x",
    );
    mode_lines(&mut c, r, |m| m.freq_hz);
    c
}

/// Damping ratio [%] of each mode vs speed; < 0 is unstable.
pub fn damping(r: &StabilityReport) -> Chart {
    let xr = range(r.speeds.iter().map(|s| s.speed_hz));
    let zr = range(
        r.speeds
            .iter()
            .flat_map(|s| s.modes.iter().map(|m| 100.0 * m.damping_ratio)),
    );
    // The interesting part is near zero: clip very well damped modes at 30 %.
    let zr = (zr.0.min(-1.0), zr.1.clamp(1.0, 30.0));
    let mut c = Chart::new(
        W,
        H,
        "Damping ratio of the whole-system modes",
        "rotor speed [Hz]",
        "damping ratio [%]",
        xr,
        zr,
    );
    c.line(
        [(xr.0, 0.0), (xr.1, 0.0)],
        Rgb::BLACK,
        1.0,
        false,
        Role::Reference,
        "zero",
    );
    mode_lines(&mut c, r, |m| (100.0 * m.damping_ratio).min(zr.1));
    c
}

const BEARINGS: [(&str, Rgb); 2] = [("bearing C", PALETTE[0]), ("bearing T", PALETTE[1])];

/// Journal centre relative to its ring [um] at the static equilibrium, over the speed range, in
/// the bore (clearance circle, lobe contours); the lowest and highest speeds are labelled.
pub fn locus(r: &StabilityReport, lobes: &Bore) -> Chart {
    let loci: Vec<Vec<(f64, f64)>> = (0..2)
        .map(|b| {
            r.speeds
                .iter()
                .map(|s| (s.bearings[b].dx_um, s.bearings[b].dy_um))
                .collect()
        })
        .collect();
    let all: Vec<(f64, f64)> = loci.iter().flatten().copied().collect();
    // Framed to the clearance circle (the lobes open far beyond it, to C + dH).
    let mut c = bearing_frame(
        lobes,
        &all,
        Some(1.15 * lobes.c_m * 1e6),
        "Journal locus, static equilibrium",
    );
    for (b, ((name, color), pts)) in BEARINGS.iter().zip(&loci).enumerate() {
        c.line(pts.clone(), *color, 1.8, false, Role::Series, name);
        // Speeds at the ends: bearing C's to the right, T's to the left, so they do not overlap.
        let ends = [r.speeds.first(), r.speeds.last()];
        for (s, p) in ends.into_iter().zip([pts.first(), pts.last()]) {
            if let (Some(s), Some(&(x, y))) = (s, p) {
                let label = format!("{:.0} Hz", s.speed_hz);
                match b {
                    0 => c.label((x, y), (6, 0), &label, Anchor::Start),
                    _ => c.label((x, y), (-6, 0), &label, Anchor::End),
                }
            }
        }
    }
    c.legend(&BEARINGS);
    c
}

/// Eccentricity |d| / C of each bearing's static equilibrium vs speed.
pub fn eccentricity(r: &StabilityReport) -> Chart {
    let xr = range(r.speeds.iter().map(|s| s.speed_hz));
    let er = range(
        r.speeds
            .iter()
            .flat_map(|s| s.bearings.iter().map(|b| b.eps)),
    );
    let mut c = Chart::new(
        W,
        H,
        "Static equilibrium under gravity: eccentricity",
        "rotor speed [Hz]",
        "eccentricity |d| / C [1]",
        xr,
        (0.0, er.1.max(0.1)),
    );
    for (b, (name, color)) in BEARINGS.iter().enumerate() {
        let pts = r.speeds.iter().map(|s| (s.speed_hz, s.bearings[b].eps));
        c.line(pts, *color, 1.8, false, Role::Series, name);
    }
    mark_threshold(&mut c, r);
    c.legend(&BEARINGS);
    c
}

/// Write campbell, damping, locus and eccentricity (.svg and .png each) into `dir`.
pub fn save(r: &StabilityReport, lobes: &Bore, dir: &Path) -> std::io::Result<Vec<PathBuf>> {
    let mut out = campbell(r).save(dir, "campbell")?;
    out.extend(damping(r).save(dir, "damping")?);
    out.extend(locus(r, lobes).save(dir, "locus")?);
    out.extend(eccentricity(r).save(dir, "eccentricity")?);
    Ok(out)
}

/// Bode plots of the unbalance response: the orbits' semi-major axes of the journals and rings
/// against speed (with the critical speeds marked), and the phase of the journals' x motion.
pub fn save_unbalance(
    u: &super::unbalance::UnbalanceReport,
    dir: &Path,
) -> std::io::Result<Vec<PathBuf>> {
    let f: Vec<f64> = u.points.iter().map(|p| p.speed_hz).collect();
    let xr = range(f.iter().copied());
    let series: [(&str, Rgb, Vec<f64>); 4] = [
        (
            "journal C",
            PALETTE[0],
            u.points.iter().map(|p| p.journal_c.semi_major_um).collect(),
        ),
        (
            "journal T",
            PALETTE[3],
            u.points.iter().map(|p| p.journal_t.semi_major_um).collect(),
        ),
        (
            "ring C",
            PALETTE[2],
            u.points.iter().map(|p| p.ring_c.semi_major_um).collect(),
        ),
        (
            "ring T",
            PALETTE[1],
            u.points.iter().map(|p| p.ring_t.semi_major_um).collect(),
        ),
    ];
    let yr = range(series.iter().flat_map(|s| s.2.iter().copied()));
    let mut c = Chart::new(
        W,
        H,
        "Unbalance response: orbit semi-major axis",
        "rotor speed [Hz]",
        "amplitude [um]",
        xr,
        (0.0, yr.1.max(1e-9) * 1.05),
    );
    for (name, color, a) in &series {
        let pts = f.iter().copied().zip(a.iter().copied());
        c.line(pts, *color, 1.8, false, Role::Series, name);
    }
    for cs in &u.critical_speeds {
        c.marker(cs.speed_hz, "critical speed", None);
    }
    let legend: Vec<(&str, Rgb)> = series.iter().map(|s| (s.0, s.1)).collect();
    c.legend(&legend);
    let mut out = c.save(dir, "unbalance_amplitude")?;

    let phases: [(&str, Rgb, Vec<f64>); 2] = [
        (
            "journal C",
            PALETTE[0],
            u.points.iter().map(|p| p.journal_c.x_phase_deg).collect(),
        ),
        (
            "journal T",
            PALETTE[3],
            u.points.iter().map(|p| p.journal_t.x_phase_deg).collect(),
        ),
    ];
    let mut c = Chart::new(
        W,
        H,
        "Unbalance response: phase of the journals' x motion",
        "rotor speed [Hz]",
        "phase [deg]",
        xr,
        (-180.0, 180.0),
    );
    for (name, color, a) in &phases {
        let pts = f.iter().copied().zip(a.iter().copied());
        c.line(pts, *color, 1.8, false, Role::Series, name);
    }
    let legend: Vec<(&str, Rgb)> = phases.iter().map(|s| (s.0, s.1)).collect();
    c.legend(&legend);
    out.extend(c.save(dir, "unbalance_phase")?);
    Ok(out)
}
