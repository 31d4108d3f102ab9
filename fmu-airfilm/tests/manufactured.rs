//! Spatial convergence on a manufactured solution: L2 error order of biquadratic elements (~3).

use fmu_airfilm::verify::manufactured_l2_error;
use fmu_airfilm::{BearingParams, JournalState};
use std::f64::consts::PI;

#[test]
fn l2_error_order_is_three_on_the_lobed_geometry() {
    let last = *l2_orders(1.0).last().unwrap();
    assert!(last > 2.7 && last < 3.5, "observed order {last}");
}

/// A graded mesh (`mesh_grading` < 1: elements shrinking toward each lobe's trailing edge)
/// refined as a family of the same shape (the grading per element g^(6 / n), so the sizes
/// follow the same exponential along the lobe) keeps the order of the uniform mesh.
#[test]
fn l2_error_order_is_three_on_a_graded_mesh() {
    let last = *l2_orders(0.6).last().unwrap();
    assert!(last > 2.7 && last < 3.5, "observed order {last}");
}

/// Observed L2 orders of the manufactured solution under refinement; `grading_at_6` is the
/// grading of the 6-element mesh (1: uniform).
fn l2_orders(grading_at_6: f64) -> Vec<f64> {
    let base = BearingParams::paper();
    let (c, dh, phi_t, alpha) = (
        base.bore.c_m,
        base.bore.dh_m,
        base.bore.phi_t_rad,
        base.bore.alpha_rad,
    );
    let zb = 0.5 * base.bore.b_m / base.bore.r_m;
    let (ex, ey) = (0.2, -0.4); // journal offset / C
    let omega = 2.0 * PI * 1000.0;
    let lam = base.bearing_number(omega);
    let j = JournalState::at(ex * c, ey * c, omega);
    // Exact field with non-trivial boundary data, symmetric in zeta (dP/dzeta = 0 at zeta = 0).
    let exact = move |phi: f64, z: f64| 1.0 + 0.4 * (1.7 * phi + 0.4).cos() * (1.3 * z / zb).cos();
    let source = move |phi: f64, z: f64| {
        let k = (phi / (2.0 * PI / 3.0)).floor();
        let s = phi - k * 2.0 * PI / 3.0;
        let th = phi + alpha;
        let h = 1.0 - ex * th.cos() - ey * th.sin() + dh / c * (1.0 - s / phi_t);
        let hp = ex * th.sin() - ey * th.cos() - dh / c / phi_t;
        let (a, b) = (1.7 * phi + 0.4, 1.3 * z / zb);
        let p = 1.0 + 0.4 * a.cos() * b.cos();
        let pp = -0.4 * 1.7 * a.sin() * b.cos();
        let ppp = -0.4 * 1.7 * 1.7 * a.cos() * b.cos();
        let pz = -0.4 * (1.3 / zb) * a.cos() * b.sin();
        let pzz = -0.4 * (1.3 / zb).powi(2) * a.cos() * b.cos();
        let h3 = h * h * h;
        let dphi = pp * pp * h3 + 3.0 * p * h * h * hp * pp + p * h3 * ppp;
        let dz = h3 * (pz * pz + p * pzz);
        -dphi - dz + lam * (pp * h + p * hp)
    };
    let mut errs = Vec::new();
    let mut sizes = Vec::new();
    for m in [3usize, 6, 12, 24] {
        let prm = BearingParams {
            n_elem_phi: 2 * m,
            n_elem_z: m,
            mesh_grading: grading_at_6.powf(6.0 / (2 * m) as f64),
            ..base.clone()
        };
        let (e, n) = manufactured_l2_error(&prm, j, &exact, &source).unwrap();
        let rel = e / n;
        println!(
            "mesh {:>3} x {:>3} per lobe: relative L2 error {:.3e}",
            2 * m,
            m,
            rel
        );
        errs.push(rel);
        sizes.push(1.0 / m as f64);
    }
    let orders: Vec<f64> = (1..errs.len())
        .map(|i| (errs[i - 1] / errs[i]).ln() / 2f64.ln())
        .collect();
    println!(
        "observed L2 orders: {:?}",
        orders.iter().map(|o| format!("{o:.3}")).collect::<Vec<_>>()
    );
    orders
}
