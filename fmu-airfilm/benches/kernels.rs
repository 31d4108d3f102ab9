//! The film's two hot kernels alone (hand-written, harness = false): the Galerkin residual of one
//! lobe and the banded triangular solves of one lobe, on the paper mesh (533 nodes per lobe), at a
//! pressure field taken from a whirl orbit (eps 0.3, whirl 400 Hz, Omega 1000 Hz). Medians of 41
//! repeats of 200 calls each. In a run-up the two take ~2/3 of the films' time (residual ~36 %,
//! solves ~31 % of all CPU samples of a path-1 run-up). Run: cargo bench -p fmu-airfilm --bench kernels
//! (AIRFILM_MESH=20x3 before it: another mesh per lobe, e.g. a run-up's own; AIRFILM_GRADING=0.8 grades it).

mod common;

use common::{film_warmed_up, median, whirl_orbit};
use fmu_airfilm::geometry::{GapField, Geometry};
use fmu_airfilm::linsolve::BandLu;
use fmu_airfilm::mesh::Mesh;
use fmu_airfilm::reynolds::{self, Coeffs};
use fmu_airfilm::BearingParams;
use std::f64::consts::PI;
use std::time::Instant;

fn time_per_call(mut f: impl FnMut()) -> f64 {
    let reps = 200;
    let mut t_rep = Vec::new();
    for _ in 0..41 {
        let t = Instant::now();
        for _ in 0..reps {
            f();
        }
        t_rep.push(t.elapsed().as_secs_f64() / reps as f64);
    }
    median(t_rep)
}

fn main() {
    let mut prm = BearingParams::paper();
    // Another mesh per lobe, e.g. AIRFILM_MESH=20x3 (a run-up's at the Section 3 presets).
    if let Ok(mesh) = std::env::var("AIRFILM_MESH") {
        let (phi, z) = mesh.split_once('x').expect("AIRFILM_MESH: e.g. 20x3");
        prm.n_elem_phi = phi.parse().expect("AIRFILM_MESH: elements along the lobe");
        prm.n_elem_z = z
            .parse()
            .expect("AIRFILM_MESH: elements across the half width");
    }
    // A graded mesh, e.g. AIRFILM_MESH=10x3 AIRFILM_GRADING=0.8 (as the run-ups use).
    if let Ok(g) = std::env::var("AIRFILM_GRADING") {
        prm.mesh_grading = g.parse().expect("AIRFILM_GRADING: e.g. 0.8");
    }
    let om = 2.0 * PI * 1000.0;
    let orbit = whirl_orbit(&prm, 0.3, 400.0, 1000.0);
    let h = 10e-6;
    let (film, _) = film_warmed_up(&prm, &orbit, h, 5e-3);
    let mesh = Mesh::new(&prm);
    let geom = Geometry::new(&prm, &mesh);
    let mut gap = GapField::default();
    geom.update(&film.journal(), prm.bore.c_m, &mut gap);
    let co = Coeffs {
        lambda: prm.bearing_number(om),
        tau_s: prm.squeeze_time_s(),
        c0_per_s: 1.0 / h,
    };
    let npb = mesh.npb;
    let p = &film.pressures_rel()[..npb];
    let hist: Vec<f64> = p.iter().map(|v| v / h).collect();
    let mut res = vec![0.0; npb];
    let t_res = time_per_call(|| {
        reynolds::residual(&mesh, &gap, 0, co, p, &hist, None, &mut res);
        std::hint::black_box(&mut res);
    });
    let mut lu = BandLu::new(npb, mesh.kl, mesh.ku);
    reynolds::jacobian(&mesh, &gap, 0, co, p, &mut lu);
    let t_jac = time_per_call(|| {
        reynolds::jacobian(&mesh, &gap, 0, co, p, &mut lu);
        std::hint::black_box(&mut lu);
    });
    println!(
        "one lobe ({npb} nodes): residual median {:.2} us, Jacobian assembly {:.2} us",
        t_res * 1e6,
        t_jac * 1e6,
    );
    // Factor and solve with partial pivoting and without (the film's default):
    // the factorization of a copy of the assembled matrix, the copy timed apart and subtracted.
    // Without interchanges also with the factors rounded to f32 for the solves (as the film's
    // Newton matrices are; the factorization includes the rounding).
    for (pivoting, single) in [(true, false), (false, false), (false, true)] {
        lu.set_pivoting(pivoting);
        lu.set_single_precision_solves(single);
        reynolds::jacobian(&mesh, &gap, 0, co, p, &mut lu);
        let assembled = lu.clone();
        let mut work = lu.clone();
        let t_copy = time_per_call(|| {
            work.clone_from(&assembled);
            std::hint::black_box(&mut work);
        });
        let t_factor_and_copy = time_per_call(|| {
            work.clone_from(&assembled);
            work.factor().unwrap();
            std::hint::black_box(&mut work);
        });
        lu.factor().unwrap();
        let mut b = res.clone();
        let t_solve = time_per_call(|| {
            b.copy_from_slice(&res);
            lu.solve(&mut b);
            std::hint::black_box(&mut b);
        });
        println!(
            "  {}: factorization median {:.2} us, triangular solves {:.2} us",
            match (pivoting, single) {
                (true, _) => "partial pivoting",
                (false, false) => "no interchanges",
                (false, true) => "no interchanges, f32 factors in the solves",
            },
            (t_factor_and_copy - t_copy) * 1e6,
            t_solve * 1e6
        );
        if !pivoting {
            // Two films' Newton matrices in turn, as in a run-up with serial films (six lobes,
            // 1.5 MB of f64 factors: more than this machine's 1 MB of L2 per core).
            let six: Vec<BandLu> = (0..6).map(|_| lu.clone()).collect();
            let mut k = 0;
            let t_six = time_per_call(|| {
                b.copy_from_slice(&res);
                six[k % 6].solve(&mut b);
                k += 1;
                std::hint::black_box(&mut b);
            });
            println!(
                "    six lobes' matrices in turn: triangular solves {:.2} us",
                t_six * 1e6
            );
        }
    }
}
