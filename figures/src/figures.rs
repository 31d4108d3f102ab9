//! The six run-up figures.

use super::chart::{decimate_minmax, Chart, Heatmap};
use super::{Anchor, Rgb, Role};
use bearing::Bore;
use runup_analysis::{spectrogram, Bearing, Classification, RunSeries};

const W: u32 = 900;
const H: u32 = 500;
/// Longest polyline drawn for an orbit: beyond this the orbit is thinned by a stride (it fills the same area).
const MAX_ORBIT_POINTS: usize = 20_000;
/// Waterfall: 40 ms Hann window (25 Hz bins, the paper's spectra resolve the whirl lines at this scale).
const WATERFALL_WINDOW_S: f64 = 0.04;
/// Waterfall colour scale: dB below the largest magnitude shown.
const WATERFALL_DB_RANGE: f64 = 60.0;

fn t_ms(series: &RunSeries) -> Vec<f64> {
    series.t_s.iter().map(|t| t * 1e3).collect()
}

fn range(vs: &[&[f64]]) -> (f64, f64) {
    vs.iter()
        .flat_map(|v| v.iter())
        .filter(|v| v.is_finite())
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(l, h), v| {
            (l.min(*v), h.max(*v))
        })
}

/// Two time series in one frame with the onset marked (if any).
fn two_series(
    series: &RunSeries,
    class: &Classification,
    a: (&[f64], &str),
    b: (&[f64], &str),
    title: &str,
    ylabel: &str,
) -> Chart {
    let t = t_ms(series);
    let mut c = Chart::new(
        W,
        H,
        title,
        "t [ms]",
        ylabel,
        range(&[&t]),
        range(&[a.0, b.0]),
    );
    let buckets = c.frame_width_px();
    for ((ys, name), color) in [(a, Rgb::BLUE), (b, Rgb::RED)] {
        c.line(
            decimate_minmax(&t, ys, buckets),
            color,
            1.2,
            false,
            Role::Series,
            name,
        );
    }
    if let (Some(t_on), Some(f_on)) = (class.onset_time_s, class.onset_speed_hz) {
        let label = format!(
            "onset {:.0} ms ({:.0} Hz), {}",
            t_on * 1e3,
            f_on,
            class.class.as_str()
        );
        c.marker(t_on * 1e3, "onset", Some(label));
    }
    c.legend(&[(a.1, Rgb::BLUE), (b.1, Rgb::RED)]);
    c
}

pub fn eps(series: &RunSeries, class: &Classification) -> Chart {
    let ec = series.eps(Bearing::C);
    let et = series.eps(Bearing::T);
    two_series(
        series,
        class,
        (&ec, "eps_C"),
        (&et, "eps_T"),
        "Bearing eccentricities",
        "eps = |dr| / C [-]",
    )
}

/// Friction power loss of both films and their sum against speed.
pub fn power_loss(speed_hz: &[f64], p_c_w: &[f64], p_t_w: &[f64]) -> Chart {
    let total: Vec<f64> = p_c_w.iter().zip(p_t_w).map(|(a, b)| a + b).collect();
    let mut c = Chart::new(
        W,
        H,
        "Friction power loss of the air films",
        "speed [Hz]",
        "P [W]",
        range(&[speed_hz]),
        range(&[p_c_w, p_t_w, &total]),
    );
    let buckets = c.frame_width_px();
    let lines = [
        (p_c_w, "bearing C", Rgb::BLUE),
        (p_t_w, "bearing T", Rgb::RED),
        (&total[..], "both", Rgb::BLACK),
    ];
    for (ys, name, color) in lines {
        c.line(
            decimate_minmax(speed_hz, ys, buckets),
            color,
            1.2,
            false,
            Role::Series,
            name,
        );
    }
    c.legend(&[
        ("bearing C", Rgb::BLUE),
        ("bearing T", Rgb::RED),
        ("both", Rgb::BLACK),
    ]);
    c
}

pub fn y_journal(series: &RunSeries, class: &Classification) -> Chart {
    let yc: Vec<f64> = series.y_jc_m.iter().map(|v| v * 1e6).collect();
    let yt: Vec<f64> = series.y_jt_m.iter().map(|v| v * 1e6).collect();
    two_series(
        series,
        class,
        (&yc, "y_JC"),
        (&yt, "y_JT"),
        "Vertical journal positions",
        "y [um]",
    )
}

/// Perceptually ordered dark-blue to yellow map (a 5-stop approximation of viridis).
fn colormap(v: f64) -> Rgb {
    const STOPS: [(u8, u8, u8); 5] = [
        (68, 1, 84),
        (59, 82, 139),
        (33, 145, 140),
        (94, 201, 98),
        (253, 231, 37),
    ];
    let v = v.clamp(0.0, 1.0) * 4.0;
    let i = (v.floor() as usize).min(3);
    let f = v - i as f64;
    let lerp = |a: u8, b: u8| (a as f64 + f * (b as f64 - a as f64)).round() as u8;
    let (a, b) = (STOPS[i], STOPS[i + 1]);
    Rgb(lerp(a.0, b.0), lerp(a.1, b.1), lerp(a.2, b.2))
}

/// Spectrogram of y_J of one bearing vs time as a colour map (dB), with the 1x line.
pub fn waterfall(series: &RunSeries, b: Bearing) -> Chart {
    let y = match b {
        Bearing::C => &series.y_jc_m,
        Bearing::T => &series.y_jt_m,
    };
    let dt = series.dt_s();
    let duration =
        series.t_s.last().copied().unwrap_or(0.0) - series.t_s.first().copied().unwrap_or(0.0);
    let top_hz = series.max_speed_hz();
    let title = format!(
        "Spectrum of y_J{} (Hann {:.0} ms, dB re max)",
        b.label(),
        WATERFALL_WINDOW_S * 1e3
    );
    if dt <= 0.0 || duration < WATERFALL_WINDOW_S {
        let mut c = Chart::new(W, H, &title, "t [ms]", "f [Hz]", (0.0, 1.0), (0.0, 1.0));
        c.label(
            (0.5, 0.5),
            (0, 0),
            "run shorter than one window",
            Anchor::Middle,
        );
        return c;
    }
    // About 300 columns over the run, but no finer than a quarter window.
    let hop = (duration / 300.0).max(WATERFALL_WINDOW_S / 4.0).max(dt);
    let sg = spectrogram(y, dt, WATERFALL_WINDOW_S, hop);
    let nyq = 0.5 / dt;
    let f_hi = if top_hz > 0.0 {
        (1.1 * top_hz).min(nyq)
    } else {
        nyq
    };
    let rows = sg
        .freqs_hz
        .iter()
        .take_while(|f| **f <= f_hi)
        .count()
        .max(1);
    let cols = sg.times_s.len().max(1);
    let t0 = series.t_s[0];
    let x_lo = (sg.times_s.first().copied().unwrap_or(t0) - 0.5 * hop) * 1e3;
    let x_hi = (sg.times_s.last().copied().unwrap_or(t0) + 0.5 * hop) * 1e3;
    let df = sg.freqs_hz.get(1).copied().unwrap_or(1.0);
    let mut c = Chart::new(W, H, &title, "t [ms]", "f [Hz]", (0.0, 1.0), (0.0, 1.0));
    // The colour map fills the frame exactly: no margins around it.
    c.x = (x_lo, x_hi);
    c.y = (-0.5 * df, (rows as f64 - 0.5) * df);
    let peak = sg
        .magnitude
        .iter()
        .flat_map(|r| r[..rows].iter())
        .fold(0.0_f64, |m, v| m.max(*v))
        .max(1e-300);
    let mut rgb = Vec::with_capacity(cols * rows * 3);
    for row in (0..rows).rev() {
        for col in 0..cols {
            let m = sg.magnitude.get(col).map_or(0.0, |r| r[row]);
            let db = 20.0 * (m.max(1e-300) / peak).log10();
            let Rgb(r, g, bl) = colormap(1.0 + db / WATERFALL_DB_RANGE);
            rgb.extend_from_slice(&[r, g, bl]);
        }
    }
    if !sg.times_s.is_empty() {
        c.heatmap = Some(Heatmap { cols, rows, rgb });
    }
    // The 1x line (speed in Hz vs time) where it lies in the frame.
    let t = t_ms(series);
    let speed = series.speed_hz();
    let y_hi = c.y.1;
    let line: Vec<(f64, f64)> = decimate_minmax(&t, &speed, c.frame_width_px())
        .into_iter()
        .filter(|(x, f)| *x >= x_lo && *x <= x_hi && *f <= y_hi)
        .collect();
    c.line(line, Rgb::WHITE, 1.5, true, Role::Series, "1x");
    if let Some(&(x, f)) = sg
        .times_s
        .last()
        .map(|t| (t * 1e3, series.speed_hz_at(*t)))
        .as_ref()
    {
        if f <= c.y.1 && f > c.y.0 {
            c.labels.push(super::chart::Label {
                at: (x, f),
                offset_px: (-6, 14),
                text: "1x".into(),
                size_px: 13.0,
                anchor: Anchor::End,
                color: Rgb::WHITE,
            });
        }
    }
    c
}

/// Relative journal orbit dx, dy in um with the lobe contours and the clearance circle.
pub fn orbit(series: &RunSeries, b: Bearing, lobes: &Bore) -> Chart {
    let (dx, dy) = series.rel(b);
    let stride = dx.len().div_ceil(MAX_ORBIT_POINTS).max(1);
    let pts: Vec<(f64, f64)> = dx
        .iter()
        .zip(dy)
        .step_by(stride)
        .map(|(x, y)| (x * 1e6, y * 1e6))
        .collect();
    let mut c = bearing_frame(
        lobes,
        &pts,
        None,
        &format!("Orbit of journal in ring, bearing {}", b.label()),
    );
    c.line(
        pts,
        Rgb::BLUE,
        0.8,
        false,
        Role::Series,
        &format!("dr_{}", b.label()),
    );
    c
}

/// A square frame (equal scales) of journal-in-ring displacements dx, dy [um] with the clearance
/// circle C and the lobe contours (where the gap closes). The frame holds `pts` [um] and either the
/// whole contours (radius up to C + dH) or, with `half_width_um`, that half width (the contours cut
/// at the frame). The caller adds its data to the returned chart.
pub fn bearing_frame(
    lobes: &Bore,
    pts: &[(f64, f64)],
    half_width_um: Option<f64>,
    title: &str,
) -> Chart {
    let contours: Vec<Vec<(f64, f64)>> = lobes
        .closure_contours_m(60)
        .into_iter()
        .map(|l| l.into_iter().map(|(x, y)| (x * 1e6, y * 1e6)).collect())
        .collect();
    let reach = |v: &mut dyn Iterator<Item = &(f64, f64)>| {
        v.fold(0.0_f64, |m, (x, y)| m.max(x.abs()).max(y.abs()))
    };
    let r = match half_width_um {
        Some(h) => h.max(reach(&mut pts.iter()) * 1.05),
        None => reach(&mut pts.iter().chain(contours.iter().flatten())) * 1.05,
    };
    // Contour pieces inside the frame (all of them without a half width).
    let inside = |p: &(f64, f64)| p.0.abs() <= r && p.1.abs() <= r;
    let contours: Vec<Vec<(f64, f64)>> = contours
        .iter()
        .flat_map(|l| {
            l.split(|p| !inside(p))
                .filter(|seg| seg.len() > 1)
                .map(<[(f64, f64)]>::to_vec)
                .collect::<Vec<_>>()
        })
        .collect();
    let mut c = Chart::new(640, 580, title, "dx [um]", "dy [um]", (-r, r), (-r, r));
    c.x = (-r, r);
    c.y = (-r, r);
    c.square = true;
    let circle: Vec<(f64, f64)> = (0..=120)
        .map(|i| {
            let a = std::f64::consts::TAU * i as f64 / 120.0;
            (lobes.c_m * 1e6 * a.cos(), lobes.c_m * 1e6 * a.sin())
        })
        .collect();
    c.line(circle, Rgb::GREY, 1.0, true, Role::Reference, "C");
    for (k, l) in contours.into_iter().enumerate() {
        c.line(
            l,
            Rgb::GREEN,
            2.0,
            false,
            Role::Lobe,
            &format!("lobe {}", k + 1),
        );
    }
    c
}

/// Eccentricity against speed with the speed going up and coming down (a profile with a run-down):
/// the whirl's hysteresis, with the speeds where it starts and stops marked.
pub fn hysteresis(series: &RunSeries, h: &runup_analysis::Hysteresis) -> Chart {
    let speed = series.speed_hz();
    let ec = series.eps(Bearing::C);
    let et = series.eps(Bearing::T);
    let mut c = Chart::new(
        W,
        H,
        "Whirl hysteresis: eccentricity against speed, up and down",
        "rotor speed [Hz]",
        "eps = |dr| / C [-]",
        range(&[&speed]),
        range(&[&ec, &et]),
    );
    let split = series
        .t_s
        .iter()
        .position(|t| *t >= h.run_down_from_s)
        .unwrap_or(series.len());
    let buckets = c.frame_width_px();
    let lighter = |Rgb(r, g, b): Rgb| Rgb(r / 2 + 128, g / 2 + 128, b / 2 + 128);
    for (eps, name, color) in [(&ec, "C", Rgb::BLUE), (&et, "T", Rgb::RED)] {
        for (part, dir, col) in [
            (0..split, "up", color),
            (split..series.len(), "down", lighter(color)),
        ] {
            c.line(
                decimate_minmax(&speed[part.clone()], &eps[part], buckets),
                col,
                1.0,
                false,
                Role::Series,
                &format!("eps_{name} {dir}"),
            );
        }
    }
    if let Some(f) = h.whirl_start_speed_hz {
        c.marker(
            f,
            "whirl start",
            Some(format!("whirl starts {f:.0} Hz (up)")),
        );
    }
    if let Some(f) = h.whirl_stop_speed_hz {
        c.marker(
            f,
            "whirl stop",
            Some(format!("whirl stops {f:.0} Hz (down)")),
        );
    }
    c.legend(&[
        ("eps_C up", Rgb::BLUE),
        ("eps_C down", lighter(Rgb::BLUE)),
        ("eps_T up", Rgb::RED),
        ("eps_T down", lighter(Rgb::RED)),
    ]);
    c
}
