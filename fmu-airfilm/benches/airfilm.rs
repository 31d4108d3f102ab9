//! Hand-written benchmark (harness = false): medians over repeats on the paper mesh (1599 nodes).
//! Run: cargo bench -p fmu-airfilm

mod common;

use common::{film_warmed_up, median, whirl_orbit};
use fmu_airfilm::{steady_state, BearingParams, JournalState};
use std::f64::consts::PI;
use std::time::Instant;

/// The contact law as the rotor calls it (inside its Newton iterations and finite-difference
/// Jacobians): a journal touching lobe 2 (minimum gap 0.95 h_con) and one outside the band.
fn bench_contact(prm: &BearingParams) {
    let th = 270f64.to_radians();
    let at = |r: f64| JournalState::at(r * th.cos(), r * th.sin(), 0.0);
    // The eccentricity with a minimum gap of 0.95 h_con (bisection).
    let (mut lo, mut hi) = (0.0, 3.0 * prm.bore.c_m);
    for _ in 0..100 {
        let mid = 0.5 * (lo + hi);
        if fmu_airfilm::geometry::min_gap_m(&prm.bore, &at(mid))
            > 0.95 * prm.contact.h_con_rel * prm.bore.c_m
        {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    for (what, r) in [
        ("light contact, h_min = 0.95 h_con", lo),
        ("outside the band", 0.9 * prm.bore.c_m),
    ] {
        let j = at(r);
        let mut t_rep = Vec::new();
        for _ in 0..31 {
            let t = Instant::now();
            for _ in 0..1000 {
                std::hint::black_box(fmu_airfilm::contact::contact_force_at_n(
                    &prm.bore,
                    &prm.contact,
                    std::hint::black_box(&j),
                ));
            }
            t_rep.push(t.elapsed().as_secs_f64() / 1000.0);
        }
        let f = fmu_airfilm::contact::contact_force_at_n(&prm.bore, &prm.contact, &j);
        println!(
            "contact force, {what} (|F| = {:.2} N): median {:.3} us per call",
            f[0].hypot(f[1]),
            median(t_rep) * 1e6
        );
    }
}

fn main() {
    let prm = BearingParams::paper();
    bench_contact(&prm);
    let om = 2.0 * PI * 1000.0;
    let j = JournalState::at(0.0, -0.5 * prm.bore.c_m, om);
    let mut t_steady = Vec::new();
    for _ in 0..15 {
        let t = Instant::now();
        let s = steady_state(&prm, j).unwrap();
        t_steady.push(t.elapsed().as_secs_f64());
        std::hint::black_box(s);
    }
    println!(
        "steady state, paper mesh, eps 0.5, 1000 Hz: median {:.2} ms",
        median(t_steady) * 1e3
    );

    // Whirl orbit eps 0.3, whirl 400 Hz, Omega 1000 Hz; 10 us communication steps after 5 ms warm-up.
    let orbit = whirl_orbit(&prm, 0.3, 400.0, 1000.0);
    let h = 10e-6;
    let (mut film, mut k) = film_warmed_up(&prm, &orbit, h, 5e-3);
    let before = film.total_stats();
    let mut t_step = Vec::new();
    let n = 2000;
    for _ in 0..n {
        let t = Instant::now();
        film.advance(k as f64 * h, h, &orbit).unwrap();
        t_step.push(t.elapsed().as_secs_f64());
        k += 1;
    }
    let after = film.total_stats();
    let per = |a: usize, b: usize| (a - b) as f64 / n as f64;
    println!(
        "advance 10 us on whirl orbit: median {:.1} us, mean {:.1} us; per call: {:.2} sub-steps, {:.2} Newton iterations (block solves), {:.3} Jacobian+LU (block)",
        median(t_step.clone()) * 1e6,
        t_step.iter().sum::<f64>() / n as f64 * 1e6,
        per(after.n_steps, before.n_steps),
        per(after.n_newton_iters, before.n_newton_iters),
        per(after.n_jacobians, before.n_jacobians)
    );

    // The outputs the FMU reads after each communication step (forces, diagnostics, friction),
    // and the friction integral alone (fmu_airfilm::friction).
    let (mut t_out, mut t_fric) = (Vec::new(), Vec::new());
    let mesh = fmu_airfilm::mesh::Mesh::new(&prm);
    let geom = fmu_airfilm::geometry::Geometry::new(&prm, &mesh);
    for _ in 0..200 {
        let t = Instant::now();
        std::hint::black_box(film.outputs());
        t_out.push(t.elapsed().as_secs_f64());
        let t = Instant::now();
        std::hint::black_box(fmu_airfilm::friction::friction_torque(
            &prm,
            &mesh,
            &geom,
            &film.journal(),
            film.pressures_rel(),
        ));
        t_fric.push(t.elapsed().as_secs_f64());
    }
    println!(
        "outputs after a step: median {:.2} us, of which friction median {:.2} us",
        median(t_out) * 1e6,
        median(t_fric) * 1e6
    );

    // State save for the master's roll-back (fmi2GetFMUstate): a fresh copy, and a copy into a
    // reused state (the handle the master passes back), between two communication steps.
    let mut t_clone = Vec::new();
    let mut t_into = Vec::new();
    let mut saved = film.clone();
    for _ in 0..200 {
        film.advance(k as f64 * h, h, &orbit).unwrap();
        k += 1;
        let t = Instant::now();
        let fresh = std::hint::black_box(film.clone());
        t_clone.push(t.elapsed().as_secs_f64());
        drop(fresh);
        let t = Instant::now();
        saved.clone_from(&film);
        t_into.push(t.elapsed().as_secs_f64());
        std::hint::black_box(&saved);
    }
    println!(
        "state save: fresh copy median {:.1} us, into a reused state median {:.1} us",
        median(t_clone) * 1e6,
        median(t_into) * 1e6
    );
}
