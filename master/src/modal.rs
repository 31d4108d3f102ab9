//! `airring modal`: eigenfrequencies and mode shapes of the rotor on linear film springs
//! (paper Section 2.3), at one or more speeds (Campbell data), printed and written to modal.json.

use fmu_rotor::linear::{lateral_matrices, modes, Whirl};
use fmu_rotor::{FilmCoefficients, RotorParams};
use std::path::Path;

pub fn modal(
    speeds_hz: &[f64],
    c_n_per_mm: f64,
    d_n_s_per_m: f64,
    film_n_per_mm: f64,
    m_r_g: f64,
    out: Option<&Path>,
) -> Result<serde_json::Value, String> {
    let mut p = RotorParams::paper();
    p.c_c_n_m = c_n_per_mm * 1e3;
    p.c_t_n_m = c_n_per_mm * 1e3;
    p.d_c_n_s_m = d_n_s_per_m;
    p.d_t_n_s_m = d_n_s_per_m;
    p.m_r_c_kg = m_r_g * 1e-3;
    p.m_r_t_kg = m_r_g * 1e-3;
    p.validate().map_err(|e| e.to_string())?;
    if !(film_n_per_mm.is_finite() && film_n_per_mm > 0.0) {
        return Err(format!("--film-stiffness {film_n_per_mm} N/mm must be > 0"));
    }
    let film = FilmCoefficients::isotropic(film_n_per_mm * 1e3, 0.0);
    let mut table = vec![];
    println!("modal analysis: c = {c_n_per_mm} N/mm, d = {d_n_s_per_m} N s/m, film springs {film_n_per_mm} N/mm, m_R = {m_r_g} g");
    for &f in speeds_hz {
        if !(f.is_finite() && f >= 0.0) {
            return Err(format!("--speed {f} Hz must be >= 0"));
        }
        let lm = lateral_matrices(&p, f * std::f64::consts::TAU, &[film, film]);
        let ms = modes(&lm).map_err(|e| e.to_string())?;
        println!("speed {f} Hz:");
        let mut rows = vec![];
        for (k, m) in ms.iter().enumerate() {
            let w = if m.whirl == Whirl::Forward {
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
        std::fs::create_dir_all(dir).map_err(|e| format!("{}: {e}", dir.display()))?;
        std::fs::write(
            dir.join("modal.json"),
            serde_json::to_string_pretty(&v).unwrap(),
        )
        .map_err(|e| e.to_string())?;
        println!("wrote {}", dir.join("modal.json").display());
    }
    Ok(v)
}
