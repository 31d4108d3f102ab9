//! `airring orbit`: the air-film library (no FMI) driven along a prescribed journal orbit read from a
//! CSV file, with exactly the input treatment of FMPy 0.3.32's `simulate_fmu` for a co-simulation
//! FMU, so that its forces can be compared with `airfilm.fmu` run by FMPy (tests/python/test_orbit.py).
//!
//! What `fmpy.simulation.simulateCS` does with an `input=` signal table (read from its source):
//! - communication points t_n = start + n * output_interval (a product, not a running sum); the last
//!   step is cut at stop_time; the loop ends when t > stop or isclose(t, stop) (math.isclose,
//!   rel_tol 1e-9);
//! - at each point t_n, *before* fmi2DoStep(t_n, t_n+1 - t_n), every input is set to the piecewise
//!   linear interpolation of the table at t_n (`Input.interpolate`: w0 = (t1 - t)/(t1 - t0),
//!   w1 = 1 - w0, v = w0 v0 + w1 v1, with t0 < t <= t1 from numpy's searchsorted; the first/last value
//!   is held outside the table); the same is done once in initialization mode at start_time;
//! - with `set_input_derivatives=True` it also sets the first derivative (v1 - v0)/(t1 - t0) of that
//!   same segment, i.e. the segment that *ends* at t_n when t_n is a sample time (the slope behind the
//!   communication point), and 0 outside the table; without it (the default) the inputs are held
//!   constant over each step;
//! - outputs are recorded after initialization and after every step.
//!
//! Here the same arithmetic feeds `AirFilm::advance`, and the input polynomial is evaluated with the
//! FMU layer's own `fmi_core::model::Inputs::real_at`, so the two results agree to the last bit.

use crate::error::{Classify, Error};
use fmi_core::model::{Inputs, Model, MAX_INPUT_DERIVATIVE_ORDER};
use fmi_core::variables::VarType;
use fmu_airfilm::shell::{params_from, vr, AirFilmFmu};
use fmu_airfilm::{AirFilm, FilmOutputs, JournalState};
use std::path::{Path, PathBuf};

/// The FMU's inputs in table order.
pub const INPUTS: [(&str, u32); 5] = [
    ("dx", vr::DX),
    ("dy", vr::DY),
    ("vx", vr::VX),
    ("vy", vr::VY),
    ("omega", vr::OMEGA),
];

#[derive(clap::Args, Clone, Debug)]
pub struct OrbitArgs {
    /// CSV: header `time,dx,dy,vx,vy,omega` (any column order after time), SI units (s, m, m/s, rad/s).
    #[arg(long)]
    pub input: PathBuf,
    /// Output CSV: time, Fx, Fy, eps, h_min, p_max, F_contact at every communication point.
    #[arg(long)]
    pub out: PathBuf,
    /// Start time [s] (FMPy: start_time).
    #[arg(long, default_value_t = 0.0)]
    pub start: f64,
    /// Stop time [s] (FMPy: stop_time; default: the last time in the table).
    #[arg(long)]
    pub stop: Option<f64>,
    /// Communication step [us] (FMPy: output_interval).
    #[arg(long, default_value_t = 10.0)]
    pub step: f64,
    /// Also set first input derivatives as FMPy's set_input_derivatives=True does.
    #[arg(long)]
    pub input_derivatives: bool,
    /// A parameter of airfilm.fmu, NAME=VALUE: SI number, "VALUE UNIT" with a display unit of the
    /// FMU (e.g. "C=25 um"), an integer, or true/false. Repeatable.
    #[arg(long = "param", value_name = "NAME=VALUE")]
    pub params: Vec<String>,
}

/// The orbit table: strictly increasing times and the five inputs per row.
#[derive(Clone, Debug, PartialEq)]
pub struct Table {
    pub t_s: Vec<f64>,
    /// `columns[k]` is input `INPUTS[k]`.
    pub columns: [Vec<f64>; 5],
}

impl Table {
    pub fn parse(text: &str, source: &Path) -> Result<Table, String> {
        let mut lines = text
            .lines()
            .enumerate()
            .filter(|(_, l)| !l.trim().is_empty());
        let (_, header) = lines
            .next()
            .ok_or_else(|| format!("{}: empty file", source.display()))?;
        let names: Vec<&str> = header
            .split(',')
            .map(|s| s.trim().trim_matches('"'))
            .collect();
        if names[0] != "time" {
            return Err(format!(
                "{}:1: the first column must be 'time', found '{}'",
                source.display(),
                names[0]
            ));
        }
        let mut slot = vec![usize::MAX; names.len()];
        for (c, name) in names.iter().enumerate().skip(1) {
            let k = INPUTS.iter().position(|(n, _)| n == name).ok_or_else(|| {
                format!(
                    "{}:1: column '{name}' is not an input of airfilm.fmu (dx, dy, vx, vy, omega)",
                    source.display()
                )
            })?;
            if slot.contains(&k) {
                return Err(format!(
                    "{}:1: column '{name}' appears twice",
                    source.display()
                ));
            }
            slot[c] = k;
        }
        let missing: Vec<&str> = (0..5)
            .filter(|k| !slot.contains(k))
            .map(|k| INPUTS[k].0)
            .collect();
        if !missing.is_empty() {
            return Err(format!(
                "{}:1: missing input column(s): {}",
                source.display(),
                missing.join(", ")
            ));
        }
        let mut table = Table {
            t_s: vec![],
            columns: Default::default(),
        };
        for (i, line) in lines {
            let cells: Vec<&str> = line.split(',').map(str::trim).collect();
            if cells.len() != names.len() {
                return Err(format!(
                    "{}:{}: {} values for {} columns",
                    source.display(),
                    i + 1,
                    cells.len(),
                    names.len()
                ));
            }
            for (c, cell) in cells.iter().enumerate() {
                let x: f64 = cell
                    .parse()
                    .ok()
                    .filter(|x: &f64| x.is_finite())
                    .ok_or_else(|| {
                        format!(
                            "{}:{}: {}: '{cell}' is not a finite number",
                            source.display(),
                            i + 1,
                            names[c]
                        )
                    })?;
                if c == 0 {
                    if let Some(&prev) = table.t_s.last() {
                        // FMPy treats (nearly) repeated times as input events with a different
                        // step logic; this command reproduces only the continuous case.
                        if x <= prev || is_close(x, prev) {
                            return Err(format!(
                                "{}:{}: time {x} s does not increase strictly from {prev} s (input events are not supported)",
                                source.display(),
                                i + 1
                            ));
                        }
                    }
                    table.t_s.push(x);
                } else {
                    table.columns[slot[c]].push(x);
                }
            }
        }
        if table.t_s.is_empty() {
            return Err(format!("{}: no data rows", source.display()));
        }
        Ok(table)
    }

    /// FMPy's `Input.interpolate` for continuous inputs: (value, first derivative) at `time`.
    pub fn interpolate(&self, k: usize, time: f64) -> (f64, f64) {
        let (t, v) = (&self.t_s, &self.columns[k]);
        if t.len() < 2 {
            return (v[0], 0.0);
        }
        // numpy.searchsorted(t, time), side 'left': the first index with t[i] >= time.
        let i0 = t.partition_point(|x| *x < time);
        if i0 == 0 {
            return (v[0], 0.0);
        }
        if i0 == t.len() {
            return (v[i0 - 1], 0.0);
        }
        let (i0, i1) = (i0 - 1, i0);
        let (t0, t1) = (t[i0], t[i1]);
        let w0 = (t1 - time) / (t1 - t0);
        let w1 = 1.0 - w0;
        (w0 * v[i0] + w1 * v[i1], (v[i1] - v[i0]) / (t1 - t0))
    }
}

/// Python's `math.isclose(a, b)` with its defaults (rel_tol 1e-9, abs_tol 0).
pub fn is_close(a: f64, b: f64) -> bool {
    if a == b {
        return true;
    }
    if a.is_infinite() || b.is_infinite() {
        return false;
    }
    let diff = (b - a).abs();
    diff <= (1e-9 * b).abs() || diff <= (1e-9 * a).abs()
}

/// Most communication steps of one orbit run (its rows, ~100 bytes each, are kept in memory).
pub const MAX_ORBIT_STEPS: f64 = 1e7;

/// FMPy's communication points from `start` to `stop` with `interval` (see the module doc).
pub fn communication_points(start: f64, stop: f64, interval: f64) -> Vec<f64> {
    let mut points = vec![start];
    let (mut time, mut n_steps) = (start, 0u64);
    while !(time > stop || is_close(time, stop)) {
        let next_regular = start + (n_steps + 1) as f64 * interval;
        let mut next = next_regular;
        if next > stop && !is_close(next, stop) {
            next = stop;
        }
        time = next;
        points.push(time);
        if is_close(time, next_regular) {
            n_steps += 1;
        }
    }
    points
}

/// Parses `NAME=VALUE` and writes the value into `store` as airfilm.fmu would receive it.
pub fn set_param(store: &mut fmi_core::model::Store, spec: &str) -> Result<(), String> {
    let info = AirFilmFmu::info();
    let (name, value) = spec
        .split_once('=')
        .ok_or_else(|| format!("--param '{spec}': expected NAME=VALUE"))?;
    let (name, value) = (name.trim(), value.trim());
    let var = info
        .by_name(name)
        .filter(|v| v.causality == fmi_core::variables::Causality::Parameter)
        .ok_or_else(|| format!("--param '{spec}': airfilm.fmu has no parameter '{name}'"))?;
    let bad = |what: &str| format!("--param '{spec}': {name} expects {what}");
    match var.var_type {
        VarType::Boolean => {
            store.booleans[var.vr as usize] = match value {
                "true" => true,
                "false" => false,
                _ => return Err(bad("true or false")),
            }
        }
        VarType::Integer => {
            store.integers[var.vr as usize] = value.parse().map_err(|_| bad("an integer"))?
        }
        VarType::Real => {
            let (num, unit) = cosim::system::split_quantity(value)
                .ok_or_else(|| bad("a number, optionally with a unit"))?;
            let si = if unit.is_empty() || Some(unit) == var.unit {
                num
            } else {
                let u = var.unit.and_then(fmi_core::units::unit);
                let (_, factor, offset) = u
                    .and_then(|u| u.display_units.iter().find(|d| d.0 == unit))
                    .ok_or_else(|| {
                        bad(&format!(
                            "SI ({}) or one of its display units",
                            var.unit.unwrap_or("1")
                        ))
                    })?;
                // The master's conversion (cosim/setup.rs): divide by the exact power of ten.
                (num - offset) / factor
            };
            if !si.is_finite() {
                return Err(bad("a finite value"));
            }
            store.reals[var.vr as usize] = si;
        }
    }
    Ok(())
}

use cosim::number::short as n;

/// One output row: the time and the film's outputs after the step ending there.
pub type Row = (f64, FilmOutputs);

/// Runs the film along the table; `params` are `NAME=VALUE` specs (see [`set_param`]).
pub fn run_orbit(
    table: &Table,
    params: &[String],
    start_s: f64,
    stop_s: f64,
    interval_s: f64,
    input_derivatives: bool,
) -> Result<Vec<Row>, String> {
    if !(start_s.is_finite() && stop_s.is_finite()) {
        return Err(format!(
            "start time {} s and stop time {} s must be finite numbers",
            n(start_s),
            n(stop_s)
        ));
    }
    if stop_s <= start_s {
        return Err(format!(
            "stop time {} s must be after the start time {} s",
            n(stop_s),
            n(start_s)
        ));
    }
    if !(interval_s.is_finite() && interval_s > 0.0) {
        return Err(format!(
            "the communication step {} s must be > 0",
            n(interval_s)
        ));
    }
    let steps = (stop_s - start_s) / interval_s;
    if steps > MAX_ORBIT_STEPS {
        return Err(format!(
            "a communication step of {} s gives {steps:.3e} steps from {} s to {} s (at most \
             {MAX_ORBIT_STEPS:e}: the rows are kept in memory)",
            n(interval_s),
            n(start_s),
            n(stop_s)
        ));
    }
    let info = AirFilmFmu::info();
    let mut store = fmi_core::model::Store::from_info(&info);
    for p in params {
        set_param(&mut store, p)?;
    }
    let film_params = params_from(&store);
    film_params
        .validate()
        .map_err(|e| crate::fmu_params::with_units("film", e.to_string()))?;
    let mut film = AirFilm::new(film_params.clone()).map_err(|e| e.to_string())?;

    // The inputs as the FMU layer holds them: all Reals by value reference, plus derivatives.
    let mut inputs = Inputs {
        t0: start_s,
        values: store.reals.clone(),
        derivatives: vec![[0.0; MAX_INPUT_DERIVATIVE_ORDER]; store.reals.len()],
    };
    let apply = |inputs: &mut Inputs, time: f64| {
        inputs.t0 = time;
        for (k, (_, r)) in INPUTS.iter().enumerate() {
            let (v, d) = table.interpolate(k, time);
            inputs.values[*r as usize] = v;
            inputs.derivatives[*r as usize][0] = if input_derivatives { d } else { 0.0 };
        }
    };
    let journal_at = |inputs: &Inputs, t: f64| JournalState {
        dx_m: inputs.real_at(vr::DX, t),
        dy_m: inputs.real_at(vr::DY, t),
        vx_m_s: inputs.real_at(vr::VX, t),
        vy_m_s: inputs.real_at(vr::VY, t),
        omega_rad_s: inputs.real_at(vr::OMEGA, t),
    };

    // Initialization mode: inputs at the start time; the FMU builds its film from their values.
    apply(&mut inputs, start_s);
    let journal0 = JournalState {
        dx_m: inputs.values[vr::DX as usize],
        dy_m: inputs.values[vr::DY as usize],
        vx_m_s: inputs.values[vr::VX as usize],
        vy_m_s: inputs.values[vr::VY as usize],
        omega_rad_s: inputs.values[vr::OMEGA as usize],
    };
    let p_rel = if store.boolean(vr::START_STEADY) {
        fmu_airfilm::steady_state(&film_params, journal0)
            .map_err(|e| format!("steady start: {e}"))?
            .p_rel
    } else {
        vec![1.0; film.pressures_rel().len()]
    };
    film.set_pressures_rel(start_s, journal0, &p_rel)
        .map_err(|e| e.to_string())?;

    let points = communication_points(start_s, stop_s, interval_s);
    let mut rows = Vec::with_capacity(points.len());
    rows.push((start_s, film.outputs()));
    for w in points.windows(2) {
        let (time, next) = (w[0], w[1]);
        apply(&mut inputs, time);
        let step_inputs = inputs.clone();
        film.advance(time, next - time, &|t| journal_at(&step_inputs, t))
            .map_err(|e| format!("film step [{time} s, {next} s]: {e}"))?;
        rows.push((next, film.outputs()));
    }
    Ok(rows)
}

/// The output CSV, units in the header.
pub fn write_csv(path: &Path, rows: &[Row]) -> Result<(), String> {
    let mut s = String::from("time [s],Fx [N],Fy [N],eps [1],h_min [m],p_max [Pa],F_contact [N]\n");
    for (t, o) in rows {
        s.push_str(&format!(
            "{t:?},{:?},{:?},{:?},{:?},{:?},{:?}\n",
            o.fx_n, o.fy_n, o.eps, o.h_min_m, o.p_max_pa, o.f_contact_n
        ));
    }
    crate::output::write_whole(path, s.as_bytes())
}

/// The command: read, run, write, report.
pub fn run_cli(a: &OrbitArgs) -> Result<(), Error> {
    let text = std::fs::read_to_string(&a.input)
        .map_err(|e| Error::Input(format!("{}: {e}", a.input.display())))?;
    let table = Table::parse(&text, &a.input).input()?;
    let stop = a
        .stop
        .unwrap_or(*table.t_s.last().expect("at least one row"));
    if !(a.step.is_finite() && a.step > 0.0) {
        return Err(Error::Flag(format!("--step {} us must be > 0", n(a.step))));
    }
    // Checked before the note on the table's range, which a non-finite time would only confuse.
    for (flag, t) in [("--start", a.start), ("--stop", stop)] {
        if !t.is_finite() {
            return Err(Error::Flag(format!(
                "{flag} = {} s must be a finite number",
                n(t)
            )));
        }
    }
    let (first, last) = (table.t_s[0], *table.t_s.last().expect("at least one row"));
    if a.start < first || stop > last {
        // FMPy holds the inputs outside the table too; said, since it is rarely meant.
        eprintln!(
            "note: the run ({} s to {} s) reaches outside the input table ({} s to {} s); the \
             inputs are held at the table's end values there, as FMPy holds them",
            n(a.start),
            n(stop),
            n(first),
            n(last)
        );
    }
    // "10" us -> the double nearest 1e-5 s, as FMPy's output_interval=1e-5.
    let interval_s = a.step / 1e6;
    let wall = std::time::Instant::now();
    let rows = run_orbit(
        &table,
        &a.params,
        a.start,
        stop,
        interval_s,
        a.input_derivatives,
    )
    .run()?;
    write_csv(&a.out, &rows).output()?;
    eprintln!(
        "orbit: {} communication steps to t = {} s in {:.2} s wall -> {}",
        rows.len() - 1,
        rows.last().map_or(a.start, |r| r.0),
        wall.elapsed().as_secs_f64(),
        a.out.display()
    );
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn table(text: &str) -> Result<Table, String> {
        Table::parse(text, Path::new("orbit.csv"))
    }

    #[test]
    fn interpolation_is_fmpys() {
        let t = table("time,omega,dx,dy,vx,vy\n0,0,1,0,0,0\n1,10,3,0,0,0\n3,30,3,0,0,0\n").unwrap();
        // dx (k = 0) and omega (k = 4) before, at and after the table; at a sample the slope is
        // the one *behind* it.
        assert_eq!(t.interpolate(0, -1.0), (1.0, 0.0));
        assert_eq!(t.interpolate(0, 0.0), (1.0, 0.0));
        assert_eq!(t.interpolate(0, 0.5), (2.0, 2.0));
        assert_eq!(t.interpolate(0, 1.0), (3.0, 2.0));
        assert_eq!(t.interpolate(0, 2.0), (3.0, 0.0));
        assert_eq!(t.interpolate(4, 2.0), (20.0, 10.0));
        assert_eq!(t.interpolate(4, 4.0), (30.0, 0.0));
    }

    #[test]
    fn communication_points_are_products_cut_at_stop() {
        let p = communication_points(0.0, 0.35, 0.1);
        assert_eq!(p.len(), 5);
        assert_eq!(p[3], 3.0 * 0.1); // 0.30000000000000004, not 0.1 + 0.1 + 0.1 summed otherwise
        assert_eq!(p[4], 0.35);
        // A stop within isclose of a grid point is reached on the grid.
        let p = communication_points(0.0, 0.3, 0.1);
        assert_eq!(p.last(), Some(&(3.0 * 0.1)));
        assert!(is_close(1.0, 1.0 + 1e-10) && !is_close(1.0, 1.0 + 1e-8));
    }

    #[test]
    fn bad_tables_and_parameters_are_refused_clearly() {
        let e = table("t,dx\n").unwrap_err();
        assert!(e.contains("first column must be 'time'"), "{e}");
        let e = table("time,dx,dy,vx,vy\n0,0,0,0,0\n").unwrap_err();
        assert!(e.ends_with("missing input column(s): omega"), "{e}");
        let e = table("time,dx,dy,vx,vy,omega,Fx\n").unwrap_err();
        assert!(e.contains("'Fx' is not an input"), "{e}");
        let e = table("time,dx,dy,vx,vy,omega\n0,0,0,0,0,0\n0,1,0,0,0,0\n").unwrap_err();
        assert!(
            e.starts_with("orbit.csv:3:") && e.contains("input events"),
            "{e}"
        );
        let e = table("time,dx,dy,vx,vy,omega\n0,0,0,x,0,0\n").unwrap_err();
        assert!(
            e.contains("orbit.csv:2: vx: 'x' is not a finite number"),
            "{e}"
        );

        let mut store = fmi_core::model::Store::from_info(&AirFilmFmu::info());
        set_param(&mut store, "C=25 um").unwrap();
        assert_eq!(store.real(vr::C), 25.0 / 1e6);
        set_param(&mut store, "n_elem_phi=10").unwrap();
        set_param(&mut store, "start_steady=true").unwrap();
        assert!(store.boolean(vr::START_STEADY) && store.integer(vr::N_ELEM_PHI) == 10);
        let e = set_param(&mut store, "C=25 parsecs").unwrap_err();
        assert!(e.contains("SI (m) or one of its display units"), "{e}");
        assert!(set_param(&mut store, "dx=1")
            .unwrap_err()
            .contains("no parameter 'dx'"));
        // The film's refusal gives the value in the unit the user wrote it in, too.
        let t = table("time,dx,dy,vx,vy,omega\n0,0,0,0,0,0\n").unwrap();
        let e = run_orbit(&t, &["C=-25 um".into()], 0.0, 1e-5, 1e-5, false).unwrap_err();
        assert_eq!(
            e,
            "invalid air-film parameter C = -2.5e-5 m (-25 um): must be > 0"
        );
        // A time that is not finite is called so (it read "must be after the start time").
        for stop in [f64::INFINITY, f64::NAN] {
            let e = run_orbit(&t, &[], 0.0, stop, 1e-5, false).unwrap_err();
            assert!(e.ends_with("must be finite numbers"), "{e}");
        }
        let e = run_orbit(&t, &[], 1e-3, 1e-3, 1e-5, false).unwrap_err();
        assert!(e.contains("must be after the start time"), "{e}");
    }

    #[test]
    fn centred_journal_at_rest_feels_no_force() {
        let t = table("time,dx,dy,vx,vy,omega\n0,0,0,0,0,0\n").unwrap();
        let rows = run_orbit(
            &t,
            &["n_elem_phi=4".into(), "n_elem_z=2".into()],
            0.0,
            5e-5,
            1e-5,
            false,
        )
        .unwrap();
        assert_eq!(rows.len(), 6);
        assert!(rows
            .iter()
            .all(|(_, o)| o.fx_n.abs() < 1e-9 && o.fy_n.abs() < 1e-9));
    }
}
