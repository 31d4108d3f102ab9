//! Cost of one 10 us `advance` during a run-up (hand-written timing, medians).
//! The film forces come from a linear spring-damper law (2000 N/mm, 100 N s/m) evaluated at the
//! start of each communication step and extrapolated with order 0 (held) or order 1 (line
//! through the last two values), as the master feeds them.
use fmu_rotor::*;
use std::time::Instant;

fn median(v: &mut [f64]) -> f64 {
    v.sort_by(|a, b| a.total_cmp(b));
    v[v.len() / 2]
}

fn film(dx: f64, dy: f64, vx: f64, vy: f64) -> (f64, f64) {
    (-2e6 * dx - 100.0 * vx, -2e6 * dy - 100.0 * vy)
}

fn bench(label: &str, mut p: RotorParams, t_start: f64, n: usize, order: usize) {
    p.imbalance[0] = Imbalance {
        mass_kg: 1e-4,
        radius_m: 0.01,
        z_m: 0.230,
        phase_rad: 0.0,
    };
    let mut r = Rotor::new(p).unwrap();
    let h = 1e-5;
    let mut t = 0.0;
    let mut times = Vec::with_capacity(n);
    let mut stats = StepStats::default();
    let total = (t_start / h) as usize + n;
    let mut f_prev = BearingForces::default();
    for i in 0..total {
        let o = r.outputs();
        let (fcx, fcy) = film(
            o.bearing_c.dx_m,
            o.bearing_c.dy_m,
            o.bearing_c.vx_m_s,
            o.bearing_c.vy_m_s,
        );
        let (ftx, fty) = film(
            o.bearing_t.dx_m,
            o.bearing_t.dy_m,
            o.bearing_t.vx_m_s,
            o.bearing_t.vy_m_s,
        );
        let f = BearingForces {
            fc_x_n: fcx,
            fc_y_n: fcy,
            ft_x_n: ftx,
            ft_y_n: fty,
        };
        let fp = if order == 0 || i == 0 { f } else { f_prev };
        let tn = t;
        let extrap = move |tt: f64| {
            let s = (tt - tn) / h;
            BearingForces {
                fc_x_n: f.fc_x_n + s * (f.fc_x_n - fp.fc_x_n),
                fc_y_n: f.fc_y_n + s * (f.fc_y_n - fp.fc_y_n),
                ft_x_n: f.ft_x_n + s * (f.ft_x_n - fp.ft_x_n),
                ft_y_n: f.ft_y_n + s * (f.ft_y_n - fp.ft_y_n),
            }
        };
        f_prev = f;
        let t0 = Instant::now();
        let s = r.advance(t, h, &extrap).unwrap();
        let dt = t0.elapsed().as_secs_f64();
        t += h;
        if i + n >= total {
            times.push(dt * 1e6);
            stats.accumulate(&s);
        }
    }
    let mut sorted = times.clone();
    let med = median(&mut sorted);
    let p90 = sorted[sorted.len() * 9 / 10];
    let mean = times.iter().sum::<f64>() / times.len() as f64;
    println!(
        "{label}, order-{order} forces: one 10 us advance: median {med:.2} us, p90 {p90:.2} us, mean {mean:.2} us over {n} advances \
         (steps {}, rejected {}, Newton its {}, Jacobians {}, LU {})",
        stats.steps, stats.rejected_steps, stats.newton_iterations, stats.jacobian_evaluations, stats.factorizations
    );
}

fn main() {
    let mut fast = RotorParams::paper();
    fast.t_ramp_s = 0.3; // reach high speed quickly
    let mut tight = RotorParams::paper();
    tight.rtol = 1e-7;
    tight.atol = 1e-11;
    tight.atol_vel = 1e-8;
    // The run-ups' disturbance (1 uN rms per component on a 100 us grid, `airring runup`'s
    // default): its forces are evaluated at every rotor step.
    let mut disturbed = RotorParams::paper();
    disturbed.disturbance = Disturbance {
        force_rms_n: 1e-6,
        interval_s: 1e-4,
        seed: 1,
    };
    bench(
        "paper run-up at t = 0.2 s (133 Hz), with the run-ups' disturbance",
        disturbed,
        0.2,
        20000,
        1,
    );
    for order in [1, 0] {
        // Default tolerances (rtol 1e-4, atol 1e-8 m, 1e-5 m/s) during the paper's 3 s run-up.
        bench(
            "paper run-up at t = 0.2 s (133 Hz)",
            RotorParams::paper(),
            0.2,
            20000,
            order,
        );
        bench(
            "fast run-up (t_ramp 0.3 s) at t = 0.2 s (1333 Hz)",
            fast.clone(),
            0.2,
            20000,
            order,
        );
        bench(
            "paper run-up, tight tolerances (rtol 1e-7)",
            tight.clone(),
            0.2,
            20000,
            order,
        );
    }
}
