//! The GGL iteration matrix's LU: factorization and one solve, on the paper rotor's 56 x 56
//! matrices with the journals free and pressed into their rings (hand-written timing, medians
//! of rounds).
use bearing::{Bore, BoreContact};
use fmu_rotor::ggl::{assemble_iteration_matrix, constraint_jacobian, force_jacobians, Work};
use fmu_rotor::linalg::Lu;
use fmu_rotor::rotor::{build_system, initial_state, N_INPUTS};
use fmu_rotor::RotorParams;
use std::hint::black_box;
use std::time::Instant;

fn median(v: &mut [f64]) -> f64 {
    v.sort_by(|a, b| a.total_cmp(b));
    v[v.len() / 2]
}

fn matrix(pressed: bool, beta_h: f64) -> Vec<f64> {
    let p = RotorParams {
        contact: Some([BoreContact::paper(), BoreContact::paper()]),
        ..RotorParams::paper()
    };
    let sys = build_system(&p, None);
    let (mut x, mut v) = initial_state(&p);
    if pressed {
        x[1] -= 3.0 * Bore::paper().c_m;
    }
    for (i, vi) in v.iter_mut().enumerate() {
        *vi += 1e-3 * (i as f64 + 1.0).sin();
    }
    let mut work = Work::new(sys.bodies.len());
    let (fx, fv, m) = force_jacobians(&sys, &x, &v, &[0.0; N_INPUTS], &mut work);
    let m_flat: Vec<f64> = m.iter().flatten().copied().collect();
    let g = constraint_jacobian(&sys);
    assemble_iteration_matrix(
        sys.n_coords(),
        sys.n_constraints(),
        &g,
        &m_flat,
        &fx,
        &fv,
        beta_h,
    )
}

fn main() {
    const ROUNDS: usize = 15;
    const REPS: usize = 2000;
    for (label, pressed) in [("journals free", false), ("journals on their rings", true)] {
        let a = matrix(pressed, 2e-6);
        let n = 56;
        let (mut fac, mut sol) = (Vec::new(), Vec::new());
        let lu = Lu::factor(n, a.clone(), "bench").unwrap();
        let mut b = vec![1.0; n];
        for _ in 0..ROUNDS {
            let t = Instant::now();
            for _ in 0..REPS {
                black_box(Lu::factor(n, black_box(a.clone()), "bench").unwrap());
            }
            fac.push(t.elapsed().as_secs_f64() / REPS as f64 * 1e6);
            let t = Instant::now();
            for _ in 0..REPS {
                lu.solve(black_box(&mut b));
            }
            sol.push(t.elapsed().as_secs_f64() / REPS as f64 * 1e6);
        }
        let (nl, nu) = lu.off_diagonal_nonzeros();
        println!(
            "GGL 56 x 56, {label} ({nl} + {nu} nonzeros off the diagonal): factorization (with \
             the matrix's copy) median {:.2} us, solve {:.2} us",
            median(&mut fac),
            median(&mut sol)
        );
    }
}
