//! Reading a run folder's `timeseries.csv` back into a [`RunSeries`], so that a finished run
//! (from `airring runup`, `airring run`, or another tool writing the same columns) can be
//! classified again without re-running it (`airring classify DIR`). The films' own `eps`
//! columns are used when the run recorded them.

use super::RunSeries;
use std::path::Path;

/// Columns a run-up classification needs (names without the " [unit]" suffix).
const NEEDED: [&str; 7] = [
    "rotor.omega",
    "rotor.dx_C",
    "rotor.dy_C",
    "rotor.dx_T",
    "rotor.dy_T",
    "rotor.y_JC",
    "rotor.y_JT",
];

/// Parses `timeseries.csv` text (first column time [s]); `clearance_m` is each bearing's C [C, T].
pub fn series_from_csv(text: &str, clearance_m: [f64; 2]) -> Result<RunSeries, String> {
    if !clearance_m.iter().all(|c| c.is_finite() && *c > 0.0) {
        return Err(format!("clearances {clearance_m:?} m must be positive"));
    }
    let mut lines = text.lines();
    let header: Vec<&str> = lines
        .next()
        .ok_or("empty file")?
        .split(',')
        .map(|h| h.split(" [").next().unwrap_or(h).trim())
        .collect();
    let mut idx = [0usize; 7];
    for (k, name) in NEEDED.iter().enumerate() {
        idx[k] = header
            .iter()
            .position(|h| h == name)
            .ok_or_else(|| format!("column '{name}' is missing"))?;
    }
    // The films' own eccentricities, if recorded (an older airring's folders have none).
    let eps_idx: Option<[usize; 2]> = ["film_C.eps", "film_T.eps"]
        .map(|name| header.iter().position(|h| *h == name))
        .into_iter()
        .collect::<Option<Vec<usize>>>()
        .map(|v| [v[0], v[1]]);
    let mut eps_cols: [Vec<f64>; 2] = Default::default();
    let mut cols: [Vec<f64>; 8] = Default::default();
    for (n, line) in lines.enumerate() {
        if line.trim().is_empty() {
            continue;
        }
        let v: Vec<f64> = line
            .split(',')
            .map(|x| x.trim().parse::<f64>())
            .collect::<Result<_, _>>()
            .map_err(|e| format!("line {}: {e}", n + 2))?;
        if v.len() != header.len() {
            return Err(format!(
                "line {}: {} values, header has {}",
                n + 2,
                v.len(),
                header.len()
            ));
        }
        if v.iter().any(|x| !x.is_finite()) {
            return Err(format!("line {}: non-finite value", n + 2));
        }
        cols[0].push(v[0]);
        for k in 0..7 {
            cols[k + 1].push(v[idx[k]]);
        }
        if let Some(e) = eps_idx {
            eps_cols[0].push(v[e[0]]);
            eps_cols[1].push(v[e[1]]);
        }
    }
    if cols[0].len() < 16 {
        return Err(format!(
            "only {} samples: too short to classify",
            cols[0].len()
        ));
    }
    let [t_s, omega_rad_s, dx_c_m, dy_c_m, dx_t_m, dy_t_m, y_jc_m, y_jt_m] = cols;
    Ok(RunSeries {
        t_s,
        omega_rad_s,
        dx_c_m,
        dy_c_m,
        dx_t_m,
        dy_t_m,
        y_jc_m,
        y_jt_m,
        clearance_m,
        eps_films: eps_idx.map(|_| eps_cols),
    })
}

/// Reads `DIR/timeseries.csv`.
pub fn load_run(dir: &Path, clearance_m: [f64; 2]) -> Result<RunSeries, String> {
    let p = dir.join("timeseries.csv");
    let text = std::fs::read_to_string(&p).map_err(|e| format!("{}: {e}", p.display()))?;
    series_from_csv(&text, clearance_m).map_err(|e| format!("{}: {e}", p.display()))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn csv(rows: usize) -> String {
        let mut s = String::from("time [s],rotor.omega [rad/s],rotor.dx_C [m],rotor.dy_C [m],rotor.dx_T [m],rotor.dy_T [m],rotor.y_JC [m],rotor.y_JT [m],film_C.Fx [N]\n");
        for k in 0..rows {
            let t = k as f64 * 1e-3;
            s += &format!(
                "{t},{},{},{},{},{},{},{},0\n",
                100.0 * t,
                1e-6,
                -2e-6,
                3e-6,
                -4e-6,
                -5e-6,
                -6e-6
            );
        }
        s
    }

    #[test]
    fn reads_columns_by_name_whatever_their_order() {
        let r = series_from_csv(&csv(20), [20e-6; 2]).unwrap();
        assert_eq!(r.t_s.len(), 20);
        assert_eq!(r.dy_t_m[3], -4e-6);
        assert_eq!(r.y_jt_m[0], -6e-6);
        assert_eq!(r.omega_rad_s[10], 100.0 * 10.0 * 1e-3);
    }

    /// With the films' eps columns the analysis takes them (the eccentricity each film computed
    /// with); without them (folders of earlier versions) |dr| / C from the rotor's outputs.
    #[test]
    fn the_films_own_eccentricities_are_used_when_recorded() {
        let without = series_from_csv(&csv(20), [20e-6; 2]).unwrap();
        assert!(without.eps_films.is_none());
        let e = without.eps(crate::Bearing::C)[0];
        assert!((e - 1e-6f64.hypot(2e-6) / 20e-6).abs() < 1e-15);
        let with = csv(20)
            .replace(
                "film_C.Fx [N]\n",
                "film_C.Fx [N],film_T.eps [1],film_C.eps [1]\n",
            )
            .replace(",0\n", ",0,0.25,0.125\n");
        let r = series_from_csv(&with, [20e-6; 2]).unwrap();
        assert_eq!(r.eps(crate::Bearing::C), vec![0.125; 20]);
        assert_eq!(r.eps(crate::Bearing::T), vec![0.25; 20]);
    }

    #[test]
    fn bad_files_are_clear_errors() {
        assert!(series_from_csv(&csv(5), [20e-6; 2])
            .unwrap_err()
            .contains("too short"));
        let missing = csv(20).replace("rotor.y_JT [m]", "other [m]");
        assert!(series_from_csv(&missing, [20e-6; 2])
            .unwrap_err()
            .contains("rotor.y_JT"));
        let nan = csv(20).replacen("0.001,", "NaN,", 1);
        assert!(series_from_csv(&nan, [20e-6; 2]).is_err());
        assert!(series_from_csv(&csv(20), [20e-6, 0.0]).is_err());
    }
}
