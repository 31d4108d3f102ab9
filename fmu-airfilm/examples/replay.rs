//! Replays the journal motion of a run-up (a run folder's timeseries.csv, bearing C or T) through
//! the air-film library alone and prints the solver work per phase: the film's cost along a real
//! trajectory without the master. Used to profile (perf record) and to compare solver policies.
//!
//! cargo run --release -p fmu-airfilm --example replay -- RUN_DIR/timeseries.csv C [t_end_s [t_start_s [h_us]]]
//!
//! AIRFILM_MESH=20x3 and AIRFILM_TOL=1e-3,100 give the film a run-up's mesh and tolerances (the
//! paper's 20 x 6 and the FMU's own tolerances without them), AIRFILM_GRADING=0.8 a graded mesh
//! (the run-ups' 10 x 3 is `AIRFILM_MESH=10x3 AIRFILM_GRADING=0.8`), AIRFILM_HMAX_US=1000 another
//! largest sub-step (its own 100 us without).
//!
//! With a start time the film starts there from ambient pressure; the first 2 ms (its start-up
//! transient) are not counted.

use fmu_airfilm::{AirFilm, BearingParams, JournalState};
use std::time::Instant;

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let path = args
        .get(1)
        .expect("usage: replay timeseries.csv C|T [t_end_s]");
    let side = args.get(2).map(String::as_str).unwrap_or("C");
    let t_end: f64 = args
        .get(3)
        .map(|s| s.parse().unwrap())
        .unwrap_or(f64::INFINITY);
    let t_start: f64 = args.get(4).map(|s| s.parse().unwrap()).unwrap_or(0.0);
    let text = std::fs::read_to_string(path).unwrap();
    let mut lines = text.lines();
    let header: Vec<&str> = lines.next().unwrap().split(',').collect();
    let col = |name: &str| {
        header
            .iter()
            .position(|h| h.split(" [").next() == Some(name))
            .unwrap_or_else(|| panic!("no column {name}"))
    };
    let idx = [
        col(&format!("rotor.dx_{side}")),
        col(&format!("rotor.dy_{side}")),
        col(&format!("rotor.vx_{side}")),
        col(&format!("rotor.vy_{side}")),
        col("rotor.omega"),
    ];
    let mut t = vec![];
    let mut rows: Vec<[f64; 5]> = vec![];
    for l in lines {
        let v: Vec<f64> = l.split(',').map(|x| x.parse().unwrap()).collect();
        if v[0] > t_end {
            break;
        }
        if v[0] < t_start - 1e-3 {
            continue;
        }
        t.push(v[0]);
        rows.push(idx.map(|i| v[i]));
    }
    let journal = |tt: f64| {
        let k = t.partition_point(|x| *x <= tt).clamp(1, t.len() - 1);
        let w = ((tt - t[k - 1]) / (t[k] - t[k - 1])).clamp(0.0, 1.0);
        let r: [f64; 5] =
            std::array::from_fn(|i| rows[k - 1][i] + w * (rows[k][i] - rows[k - 1][i]));
        JournalState {
            dx_m: r[0],
            dy_m: r[1],
            vx_m_s: r[2],
            vy_m_s: r[3],
            omega_rad_s: r[4],
        }
    };
    let mut params = BearingParams::paper();
    // The run-up's film settings, e.g. AIRFILM_MESH=20x3 AIRFILM_TOL=1e-3,100 (the paper's 20 x 6
    // and the FMU's own tolerances without them).
    if let Ok(mesh) = std::env::var("AIRFILM_MESH") {
        let (phi, z) = mesh.split_once('x').expect("AIRFILM_MESH: e.g. 20x3");
        params.n_elem_phi = phi.parse().unwrap();
        params.n_elem_z = z.parse().unwrap();
    }
    if let Ok(grading) = std::env::var("AIRFILM_GRADING") {
        params.mesh_grading = grading.parse().expect("AIRFILM_GRADING: e.g. 0.8");
    }
    if let Ok(tol) = std::env::var("AIRFILM_TOL") {
        let (rtol, atol) = tol.split_once(',').expect("AIRFILM_TOL: e.g. 1e-3,100");
        params.rtol = rtol.parse().unwrap();
        params.atol_pa = atol.parse().unwrap();
    }
    if let Ok(h_max_us) = std::env::var("AIRFILM_HMAX_US") {
        params.h_max_s = h_max_us
            .parse::<f64>()
            .expect("AIRFILM_HMAX_US: microseconds")
            * 1e-6;
    }
    let mut film = AirFilm::new(params).unwrap();
    // Macro step [s]: the run-up default (20 us) unless given.
    let h: f64 = args
        .get(5)
        .map(|s| s.parse::<f64>().unwrap() * 1e-6)
        .unwrap_or(20e-6);
    let t0 = t_start.max(t[0]);
    let n = ((t[t.len() - 1] - t0) / h).floor() as usize;
    let phase = (0.1 / h).round() as usize; // 100 ms phases
    let warm = if t_start > 0.0 { 200 } else { 0 };
    for k in 0..warm {
        film.advance(t0 + k as f64 * h, h, &journal).unwrap();
    }
    let t0 = t0 + warm as f64 * h;
    let n = n - warm;
    let start = Instant::now();
    let mut last = (film.total_stats(), Instant::now());
    println!("phase end [s]  speed [Hz]  us/step  substeps  newton  jacobians  rejected (per macro step)");
    for k in 0..n {
        film.advance(t0 + k as f64 * h, h, &journal).unwrap();
        if (k + 1) % phase == 0 || k + 1 == n {
            let s = film.total_stats();
            let m = ((k + 1) % phase).max(if (k + 1) % phase == 0 { phase } else { 0 }) as f64;
            let per = |a: usize, b: usize| (a - b) as f64 / m;
            println!(
                "{:10.3} {:10.1} {:9.1} {:9.2} {:7.2} {:10.3} {:9.3}",
                t0 + (k + 1) as f64 * h,
                journal(t0 + (k + 1) as f64 * h).omega_rad_s / std::f64::consts::TAU,
                last.1.elapsed().as_secs_f64() / m * 1e6,
                per(s.n_steps, last.0.n_steps),
                per(s.n_newton_iters, last.0.n_newton_iters),
                per(s.n_jacobians, last.0.n_jacobians),
                per(s.n_rejected, last.0.n_rejected),
            );
            last = (s, Instant::now());
        }
    }
    println!(
        "total {:.1} s for {n} macro steps",
        start.elapsed().as_secs_f64()
    );
}
