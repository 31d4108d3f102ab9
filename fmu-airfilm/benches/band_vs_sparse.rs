//! The air film's banded LU against faer's sparse LU on the paper mesh's Newton matrix (one lobe,
//! 533 unknowns), side by side in one process: factor and solve, medians over repeats, both on
//! one thread (the film's solves run one lobe at a time). Also checks that both solve the system
//! (relative residuals). Run: cargo bench -p fmu-airfilm --bench band_vs_sparse
//!
//! The question it answers (ARCHITECTURE issue: "the banded LU stays only if it beats faer's
//! sparse LU on the paper mesh, measured side by side").

use faer::sparse::{SparseColMat, Triplet};
use faer::Mat;
use fmu_airfilm::geometry::{GapField, Geometry};
use fmu_airfilm::linsolve::BandLu;
use fmu_airfilm::mesh::Mesh;
use fmu_airfilm::reynolds::{self, Coeffs};
use fmu_airfilm::{BearingParams, JournalState};
use std::time::Instant;

fn median(mut v: Vec<f64>) -> f64 {
    v.sort_by(|a, b| a.partial_cmp(b).unwrap());
    v[v.len() / 2]
}

fn main() {
    faer::set_global_parallelism(faer::Par::Seq);
    let prm = BearingParams::paper();
    let mesh = Mesh::new(&prm);
    let geom = Geometry::new(&prm, &mesh);
    let mut gap = GapField::default();
    let c = prm.bore.c_m;
    // A whirling journal at eps 0.5, 1000 Hz: a typical Newton matrix of a run-up sub-step.
    let j = JournalState {
        dx_m: 0.3 * c,
        dy_m: -0.4 * c,
        vx_m_s: 0.01,
        vy_m_s: 0.02,
        omega_rad_s: 2.0 * std::f64::consts::PI * 1000.0,
    };
    geom.update(&j, c, &mut gap);
    let n = mesh.npb;
    let p = vec![1.0; n];
    let co = Coeffs {
        lambda: prm.bearing_number(j.omega_rad_s),
        tau_s: prm.squeeze_time_s(),
        c0_per_s: 1.0 / 1e-5,
    };
    let mut band = BandLu::new(n, mesh.kl, mesh.ku);
    reynolds::jacobian(&mesh, &gap, 0, co, &p, &mut band);
    // The same matrix as triplets (every entry of the band that is non-zero).
    let mut trip = Vec::new();
    for col in 0..n {
        for row in col.saturating_sub(mesh.ku)..(col + mesh.kl + 1).min(n) {
            let v = band.get(row, col);
            if v != 0.0 {
                trip.push(Triplet::new(row, col, v));
            }
        }
    }
    let a = SparseColMat::<usize, f64>::try_new_from_triplets(n, n, &trip).unwrap();
    let b: Vec<f64> = (0..n)
        .map(|i| ((i * 7919) % 101) as f64 / 101.0 - 0.5)
        .collect();
    println!(
        "paper mesh, one lobe: n = {n}, bandwidths kl = {}, ku = {}, {} non-zeros ({:.1} % of the band)",
        mesh.kl,
        mesh.ku,
        trip.len(),
        100.0 * trip.len() as f64 / (n * (mesh.kl + mesh.ku + 1)) as f64
    );

    let residual = |x: &[f64]| -> f64 {
        let mut r = b.clone();
        for t in &trip {
            r[t.row] -= t.val * x[t.col];
        }
        let rn = r.iter().fold(0.0f64, |m, v| m.max(v.abs()));
        let xn = x.iter().fold(0.0f64, |m, v| m.max(v.abs()));
        let an = trip.iter().fold(0.0f64, |m, t| m.max(t.val.abs()));
        rn / (an * xn)
    };

    let symbolic = faer::sparse::linalg::solvers::SymbolicLu::try_new(a.symbolic()).unwrap();
    let (mut band_f, mut band_s, mut sp_f, mut sp_s, mut sp_sym) =
        (vec![], vec![], vec![], vec![], vec![]);
    let (mut x_band, mut x_sparse) = (vec![], vec![]);
    for _ in 0..41 {
        // A: banded (copy of the assembled matrix, factor, solve).
        let mut lu = band.clone();
        let t = Instant::now();
        lu.factor().unwrap();
        band_f.push(t.elapsed().as_secs_f64());
        let mut x = b.clone();
        let t = Instant::now();
        lu.solve(&mut x);
        band_s.push(t.elapsed().as_secs_f64());
        x_band = x;
        // B: faer sparse (symbolic analysis once per pattern, numeric factor, solve).
        let t = Instant::now();
        let _ = faer::sparse::linalg::solvers::SymbolicLu::try_new(a.symbolic()).unwrap();
        sp_sym.push(t.elapsed().as_secs_f64());
        let t = Instant::now();
        let f =
            faer::sparse::linalg::solvers::Lu::try_new_with_symbolic(symbolic.clone(), a.as_ref())
                .unwrap();
        sp_f.push(t.elapsed().as_secs_f64());
        let mut x = Mat::<f64>::from_fn(n, 1, |i, _| b[i]);
        let t = Instant::now();
        use faer::linalg::solvers::SolveCore;
        f.solve_in_place_with_conj(faer::Conj::No, x.as_mut());
        sp_s.push(t.elapsed().as_secs_f64());
        x_sparse = (0..n).map(|i| x[(i, 0)]).collect();
    }
    let us = |v: Vec<f64>| median(v) * 1e6;
    println!("| | factor [us] | solve [us] | residual |");
    println!("|---|---|---|---|");
    println!(
        "| banded LU (hand-written, LAPACK dgbtf2/dgbtrs) | {:.1} | {:.1} | {:.1e} |",
        us(band_f),
        us(band_s),
        residual(&x_band)
    );
    println!(
        "| faer sparse LU (numeric; symbolic once: {:.1} us) | {:.1} | {:.1} | {:.1e} |",
        us(sp_sym),
        us(sp_f),
        us(sp_s),
        residual(&x_sparse)
    );
}
