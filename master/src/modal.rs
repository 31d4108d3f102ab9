//! `airring modal`: eigenfrequencies and mode shapes of the rotor on linear film springs
//! (paper Section 2.3), at one or more speeds (Campbell data), printed and written to modal.json.

use crate::error::{Classify, Error};
use crate::plot::{Chart, Figure, Rgb, Role};
use fmu_rotor::linear::{lateral_matrices, modes, Whirl};
use fmu_rotor::{FilmCoefficients, RotorParams};
use std::path::Path;

/// The air ring bearings of `airring modal`: ring mount, film springs, ring mass (flags' units).
#[derive(Clone, Copy, Debug)]
pub struct RingFlags {
    pub c_n_per_mm: f64,
    pub d_n_s_per_m: f64,
    pub film_n_per_mm: f64,
    pub m_r_g: f64,
}

impl RingFlags {
    /// The flags, checked by name in their units before the rotor's own checks (which name its
    /// parameters in SI: c_C = -5000). Without a mount stiffness the rotor and its rings float
    /// free: rigid-body modes at 0 Hz whose nodes lie anywhere (5e12 mm was printed).
    pub fn check(&self) -> Result<(), String> {
        let RingFlags {
            c_n_per_mm,
            d_n_s_per_m,
            film_n_per_mm,
            m_r_g,
        } = *self;
        for (name, v, unit, zero_ok) in [
            ("c", c_n_per_mm, "N/mm", false),
            ("d", d_n_s_per_m, "N s/m", true),
            ("m-r", m_r_g, "g", false),
            ("film-stiffness", film_n_per_mm, "N/mm", false),
        ] {
            if !(v.is_finite() && (v > 0.0 || (zero_ok && v == 0.0))) {
                return Err(format!(
                    "--{name} = {} {unit} must be a finite number {}",
                    crate::runup::fmt_number(v),
                    if zero_ok { ">= 0" } else { "> 0" }
                ));
            }
        }
        Ok(())
    }
}

/// `--speed`: each between 0 and the run-ups' highest speed.
pub(crate) fn check_speeds(speeds_hz: &[f64]) -> Result<(), String> {
    let top = crate::runup::MAX_SPEED_HZ;
    if let Some(f) = speeds_hz
        .iter()
        .find(|f| !(f.is_finite() && **f >= 0.0 && **f <= top))
    {
        return Err(format!(
            "--speed {} Hz must lie between 0 and {top} Hz",
            crate::runup::fmt_number(*f)
        ));
    }
    Ok(())
}

pub fn modal(
    speeds_hz: &[f64],
    rings: &RingFlags,
    out: Option<&Path>,
) -> Result<serde_json::Value, Error> {
    rings.check().flag()?;
    let RingFlags {
        c_n_per_mm,
        d_n_s_per_m,
        film_n_per_mm,
        m_r_g,
    } = *rings;
    check_speeds(speeds_hz).flag()?;
    let mut p = RotorParams::paper();
    p.c_c_n_m = c_n_per_mm * 1e3;
    p.c_t_n_m = c_n_per_mm * 1e3;
    p.d_c_n_s_m = d_n_s_per_m;
    p.d_t_n_s_m = d_n_s_per_m;
    p.m_r_c_kg = m_r_g * 1e-3;
    p.m_r_t_kg = m_r_g * 1e-3;
    p.validate().flag()?;
    let film = FilmCoefficients::isotropic(film_n_per_mm * 1e3, 0.0);
    let mut table = vec![];
    println!("modal analysis: c = {c_n_per_mm} N/mm, d = {d_n_s_per_m} N s/m, film springs {film_n_per_mm} N/mm, m_R = {m_r_g} g");
    for &f in speeds_hz {
        let lm = lateral_matrices(&p, f * std::f64::consts::TAU, &[film, film]);
        let ms = modes(&lm).run()?;
        println!("speed {f} Hz:");
        let mut rows = vec![];
        for (k, m) in ms.iter().enumerate() {
            // A pair of modes at one frequency (at standstill, without gyroscopic splitting, the
            // x and y motions of isotropic bearings) has no whirl direction: any mix of the two
            // is a mode, and the eigenvectors the solver returns labelled both "forward".
            let paired = |j: usize| {
                ms.get(j).is_some_and(|o: &_| {
                    (o.freq_hz - m.freq_hz).abs() <= 1e-9 * m.freq_hz.abs().max(1.0)
                })
            };
            let degenerate = paired(k + 1) || (k > 0 && paired(k - 1));
            let w = if degenerate {
                "none (a pair at one frequency)"
            } else if m.whirl == Whirl::Forward {
                "forward"
            } else {
                "backward"
            };
            println!(
                "  {:2}. {:8.1} Hz  {:8}  {}",
                k + 1,
                m.freq_hz,
                w,
                m.shape.describe()
            );
            rows.push(serde_json::json!({
                "freq_hz": m.freq_hz, "whirl": w, "damping_ratio": m.damping_ratio,
                "node": m.shape.node().to_string(), "rotor_node_z_mm": 1e3 * m.shape.rotor_node_z_m,
                "description": m.shape.describe(),
            }));
        }
        table.push(serde_json::json!({ "speed_hz": f, "modes": rows }));
    }
    let v = serde_json::json!({
        "settings": { "c_n_per_mm": c_n_per_mm, "d_n_s_per_m": d_n_s_per_m, "film_stiffness_n_per_mm": film_n_per_mm, "m_r_g": m_r_g },
        "campbell": table,
    });
    if let Some(dir) = out {
        write_outputs(
            dir,
            &v,
            "Campbell diagram (rotor on linear film springs, undamped)",
            None,
        )
        .output()?;
    }
    Ok(v)
}

/// modal.json and the Campbell diagram (campbell.svg, .png) in `dir`.
pub(crate) fn write_outputs(
    dir: &Path,
    v: &serde_json::Value,
    title: &str,
    cap_hz: Option<f64>,
) -> Result<(), String> {
    std::fs::create_dir_all(dir).map_err(|e| format!("{}: {e}", dir.display()))?;
    crate::output::write_whole(
        &dir.join("modal.json"),
        serde_json::to_string_pretty(v).unwrap().as_bytes(),
    )?;
    let files = campbell(v, title, cap_hz)
        .save(dir, "campbell")
        .map_err(|e| e.to_string())?;
    println!(
        "wrote {} and {}",
        dir.join("modal.json").display(),
        files
            .iter()
            .map(|f| f.display().to_string())
            .collect::<Vec<_>>()
            .join(", ")
    );
    Ok(())
}

/// Campbell diagram: one line per mode rank (sorted by frequency at each speed), each segment
/// red for forward and blue for backward whirl at its end, and the 1x line (speed = frequency:
/// its crossings are the critical speeds). With `cap_hz`, only the ranks below that frequency at
/// the first speed (a flexible rotor has modes far above any speed of interest).
fn campbell(v: &serde_json::Value, title: &str, cap_hz: Option<f64>) -> Chart {
    let table = v["campbell"].as_array().cloned().unwrap_or_default();
    let speed = |row: &serde_json::Value| row["speed_hz"].as_f64().unwrap_or(0.0);
    let freqs = |row: &serde_json::Value| -> Vec<(f64, bool)> {
        row["modes"]
            .as_array()
            .map(|m| {
                m.iter()
                    .map(|m| {
                        (
                            m["freq_hz"].as_f64().unwrap_or(0.0),
                            m["whirl"] == "forward",
                        )
                    })
                    .collect()
            })
            .unwrap_or_default()
    };
    let s_max = table.iter().map(speed).fold(0.0, f64::max);
    let s_min = table.iter().map(speed).fold(s_max, f64::min);
    let mut n = table.iter().map(|r| freqs(r).len()).min().unwrap_or(0);
    if let (Some(cap), Some(first)) = (cap_hz, table.first()) {
        n = n.min(freqs(first).iter().filter(|f| f.0 <= cap).count());
    }
    let f_max = table
        .iter()
        .flat_map(|r| freqs(r).into_iter().take(n).map(|f| f.0))
        .fold(1.0, f64::max);
    // A single speed still gets a visible short tick per mode.
    let pad = if s_max > s_min { 0.0 } else { 10.0 };
    let (w, h) = (900, 560);
    let mut c = Chart::new(
        w,
        h,
        title,
        "rotor speed [Hz]",
        "eigenfrequency [Hz]",
        (s_min - pad, s_max + pad),
        (0.0, 1.1 * f_max),
    );
    let segments: Vec<(&serde_json::Value, &serde_json::Value)> = if table.len() == 1 {
        vec![(&table[0], &table[0])]
    } else {
        table.windows(2).map(|p| (&p[0], &p[1])).collect()
    };
    for k in 0..n {
        for (a, b) in &segments {
            let (fa, fb) = (freqs(a)[k], freqs(b)[k]);
            let (xa, xb) = if a == b {
                (speed(a) - pad / 2.0, speed(a) + pad / 2.0)
            } else {
                (speed(a), speed(b))
            };
            let colour = if fb.1 { Rgb::RED } else { Rgb::BLUE };
            c.line(
                [(xa, fa.0), (xb, fb.0)],
                colour,
                1.6,
                false,
                Role::Series,
                &format!("mode {}", k + 1),
            );
        }
    }
    let top = s_max.min(1.1 * f_max);
    if top > s_min {
        c.line(
            [(s_min, s_min), (top, top)],
            Rgb::GREY,
            1.2,
            true,
            Role::Reference,
            "1x",
        );
    }
    c.legend(&[
        ("forward whirl", Rgb::RED),
        ("backward whirl", Rgb::BLUE),
        ("1x (speed)", Rgb::GREY),
    ]);
    c
}

#[cfg(test)]
mod tests {
    use super::*;

    fn flags(c: f64, d: f64, film: f64, m_r: f64) -> RingFlags {
        RingFlags {
            c_n_per_mm: c,
            d_n_s_per_m: d,
            film_n_per_mm: film,
            m_r_g: m_r,
        }
    }

    /// At standstill the modes come in pairs at one frequency (no gyroscopic splitting): no whirl
    /// direction (the solver's eigenvectors were labelled "forward" and "forward"); running, each
    /// pair splits into a backward and a forward mode.
    #[test]
    fn a_pair_at_one_frequency_has_no_whirl_direction() {
        let v = modal(&[0.0, 500.0], &flags(500.0, 0.0, 2000.0, 50.0), None).unwrap();
        let whirls = |k: usize| -> Vec<String> {
            v["campbell"][k]["modes"]
                .as_array()
                .unwrap()
                .iter()
                .map(|m| m["whirl"].as_str().unwrap().to_string())
                .collect()
        };
        let standstill = whirls(0);
        assert_eq!(standstill.len(), 8);
        assert!(
            standstill
                .iter()
                .all(|w| w == "none (a pair at one frequency)"),
            "{standstill:?}"
        );
        let running = whirls(1);
        assert_eq!(
            running.iter().filter(|w| *w == "forward").count(),
            4,
            "{running:?}"
        );
        assert_eq!(
            running.iter().filter(|w| *w == "backward").count(),
            4,
            "{running:?}"
        );
    }

    /// The Campbell figure of three speeds and four modes: a segment per mode and speed interval,
    /// coloured by whirl direction, and clean text.
    #[test]
    fn campbell_figure_has_a_segment_per_mode_and_interval_and_clean_text() {
        let row = |s: f64| {
            serde_json::json!({"speed_hz": s, "modes": [
                {"freq_hz": 150.0 - 0.01 * s, "whirl": "backward"},
                {"freq_hz": 160.0 + 0.01 * s, "whirl": "forward"},
                {"freq_hz": 400.0 - 0.05 * s, "whirl": "backward"},
                {"freq_hz": 420.0 + 0.05 * s, "whirl": "forward"}]})
        };
        let v = serde_json::json!({"campbell": [row(100.0), row(1000.0), row(2000.0)]});
        let svg = campbell(&v, "Campbell diagram", None).to_svg().unwrap();
        let doc = roxmltree::Document::parse(&svg).unwrap();
        let series: Vec<_> = doc
            .descendants()
            .filter(|n| n.attribute("class") == Some("series"))
            .collect();
        assert_eq!(series.len(), 4 * 2);
        let red = series
            .iter()
            .filter(|n| n.attribute("stroke") == Some("#d62728"))
            .count();
        assert_eq!(red, 4, "forward whirl segments");
        let bad = crate::plot::layout::problems(&svg);
        assert!(bad.is_empty(), "{bad:#?}");
    }

    /// Flags are refused by their names, in their units, before anything is printed.
    #[test]
    fn bad_flags_are_refused_by_name_in_their_units() {
        for (args, why) in [
            (
                (vec![100.0], -5.0, 50.0, 1000.0, 50.0),
                "--c = -5 N/mm must be a finite number > 0",
            ),
            (
                (vec![100.0], 0.0, 50.0, 1000.0, 50.0),
                "--c = 0 N/mm must be a finite number > 0",
            ),
            (
                (vec![100.0], 1000.0, f64::NAN, 1000.0, 50.0),
                "--d = NaN N s/m must be",
            ),
            (
                (vec![100.0], 1000.0, 50.0, 1000.0, 0.0),
                "--m-r = 0 g must be a finite number > 0",
            ),
            (
                (vec![100.0], 1000.0, 50.0, 0.0, 50.0),
                "--film-stiffness = 0 N/mm must be",
            ),
            (
                (vec![100.0, 1e12], 1000.0, 50.0, 1000.0, 50.0),
                "--speed 1e12 Hz must lie between 0 and 20000 Hz",
            ),
            (
                (vec![-1.0], 1000.0, 50.0, 1000.0, 50.0),
                "--speed -1 Hz must lie",
            ),
        ] {
            let (speeds, c, d, film, m_r) = args;
            let e = modal(&speeds, &flags(c, d, film, m_r), None).unwrap_err();
            assert!(matches!(&e, Error::Flag(m) if m.starts_with(why)), "{e:?}");
        }
    }
}
