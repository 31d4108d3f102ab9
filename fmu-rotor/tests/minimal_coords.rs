//! The GGL DAE (18 coordinates, 10 constraints, multipliers) against an independent
//! minimal-coordinate formulation of the same 8-DOF system (Lagrange equations written here
//! from T = m/2 (x'^2 + y'^2) + Jt/2 (cos^2 b a'^2 + b'^2) + Jp/2 (Omega + sin b a')^2 + rings),
//! integrated with classical RK4 at a tiny fixed step, on a forced transient during a run-up.
use fmu_rotor::*;

const K_FILM: [[[f64; 2]; 2]; 2] = [
    [[2.0e6, 3.0e5], [-3.0e5, 1.8e6]],
    [[1.5e6, -2.0e5], [2.5e5, 2.2e6]],
];
const D_FILM: [[[f64; 2]; 2]; 2] = [[[150.0, 20.0], [10.0, 120.0]], [[80.0, 0.0], [0.0, 90.0]]];

fn input_forces(t: f64) -> BearingForces {
    let w = 2.0 * std::f64::consts::PI * 300.0;
    BearingForces {
        fc_x_n: 5.0 * (w * t).sin(),
        fc_y_n: 3.0 + 2.0 * (w * t).cos(),
        ft_x_n: -4.0 * (1.7 * w * t).sin(),
        ft_y_n: 2.5,
    }
}

struct Minimal {
    p: RotorParams,
}

impl Minimal {
    /// state: q = [x, y, a, b, xc, yc, xt, yt], then q'
    fn rhs(&self, t: f64, s: &[f64; 16]) -> [f64; 16] {
        let p = &self.p;
        let prof = SpeedProfile {
            f_max_hz: p.f_max_hz,
            t_ramp_s: p.t_ramp_s,
            table: None,
        };
        let (om, omd) = (prof.rate_rad_s(t), prof.accel_rad_s2(t));
        let (x, y, a, b) = (s[0], s[1], s[2], s[3]);
        let (xd, yd, ad, bd) = (s[8], s[9], s[10], s[11]);
        let (sa, ca) = a.sin_cos();
        let (sb, cb) = b.sin_cos();
        let u = input_forces(t);
        let mut fx = 0.0;
        let mut fy = -p.m_kg * p.g_m_s2;
        let (mut qa, mut qb) = (0.0, 0.0);
        let mut ring_acc = [0.0; 4];
        for (i, (zj, mr, c, d, fin)) in [
            (
                p.z_jc_m,
                p.m_r_c_kg,
                p.c_c_n_m,
                p.d_c_n_s_m,
                [u.fc_x_n, u.fc_y_n],
            ),
            (
                p.z_jt_m,
                p.m_r_t_kg,
                p.c_t_n_m,
                p.d_t_n_s_m,
                [u.ft_x_n, u.ft_y_n],
            ),
        ]
        .into_iter()
        .enumerate()
        {
            let l = zj - p.z_cm_m;
            // journal point R (0, 0, l): (l sin b, -l sin a cos b)
            let pj = [x + l * sb, y - l * sa * cb];
            let vj = [xd + l * cb * bd, yd - l * (ca * cb * ad - sa * sb * bd)];
            let (rx, ry, rxd, ryd) = (s[4 + 2 * i], s[5 + 2 * i], s[12 + 2 * i], s[13 + 2 * i]);
            let dr = [pj[0] - rx, pj[1] - ry];
            let dv = [vj[0] - rxd, vj[1] - ryd];
            let (k, dm) = (K_FILM[i], D_FILM[i]);
            let f = [
                fin[0] - k[0][0] * dr[0] - k[0][1] * dr[1] - dm[0][0] * dv[0] - dm[0][1] * dv[1],
                fin[1] - k[1][0] * dr[0] - k[1][1] * dr[1] - dm[1][0] * dv[0] - dm[1][1] * dv[1],
            ];
            fx += f[0];
            fy += f[1];
            qa += f[1] * (-l * ca * cb);
            qb += f[0] * l * cb + f[1] * l * sa * sb;
            ring_acc[2 * i] = (-c * rx - d * rxd - f[0]) / mr;
            ring_acc[2 * i + 1] = (-c * ry - d * ryd - f[1] - mr * p.g_m_s2) / mr;
        }
        let (jt, jp) = (p.j_t_kg_m2, p.j_p_kg_m2);
        let add = (qa + 2.0 * jt * cb * sb * ad * bd
            - jp * cb * bd * (om + sb * ad)
            - jp * sb * (omd + cb * ad * bd))
            / (jt * cb * cb + jp * sb * sb);
        let bdd = (qb - jt * cb * sb * ad * ad + jp * cb * ad * (om + sb * ad)) / jt;
        let mut o = [0.0; 16];
        o[..8].copy_from_slice(&s[8..]);
        o[8] = fx / p.m_kg;
        o[9] = fy / p.m_kg;
        o[10] = add;
        o[11] = bdd;
        o[12..16].copy_from_slice(&ring_acc);
        o
    }
    fn rk4(&self, t: f64, s: &mut [f64; 16], h: f64) {
        let k1 = self.rhs(t, s);
        let mut tmp = [0.0; 16];
        let stage = |k: &[f64; 16], c: f64, tmp: &mut [f64; 16]| {
            for i in 0..16 {
                tmp[i] = s[i] + c * h * k[i];
            }
        };
        stage(&k1, 0.5, &mut tmp);
        let k2 = self.rhs(t + 0.5 * h, &tmp);
        stage(&k2, 0.5, &mut tmp);
        let k3 = self.rhs(t + 0.5 * h, &tmp);
        stage(&k3, 1.0, &mut tmp);
        let k4 = self.rhs(t + h, &tmp);
        for i in 0..16 {
            s[i] += h / 6.0 * (k1[i] + 2.0 * k2[i] + 2.0 * k3[i] + k4[i]);
        }
    }
}

#[test]
fn ggl_matches_minimal_coordinates() {
    let mut p = RotorParams::paper();
    p.t_ramp_s = 0.05; // 2000 Hz at 50 ms: 800 Hz at the end of this 20 ms transient
    p.rtol = 1e-11;
    p.atol = 1e-16;
    p.atol_vel = 1e-13;
    // These tolerances need ~2500 internal steps per 100 us communication step.
    p.max_steps_per_call = 20_000;
    let films = [0, 1].map(|i| FilmCoefficients {
        k_n_m: K_FILM[i],
        d_n_s_m: D_FILM[i],
    });
    let mut r = Rotor::with_linear_films(p.clone(), films).unwrap();
    let mm = Minimal { p };
    let mut s = [0.0; 16];
    let macro_h = 1e-4;
    let n_sub = 500; // RK4 at 0.2 us
    let mut max_diff = 0.0f64;
    let mut max_amp = 0.0f64;
    let mut tot = StepStats::default();
    for n in 0..200 {
        let t0 = n as f64 * macro_h;
        tot.accumulate(&r.advance(t0, macro_h, &input_forces).unwrap());
        for k in 0..n_sub {
            mm.rk4(
                t0 + k as f64 * macro_h / n_sub as f64,
                &mut s,
                macro_h / n_sub as f64,
            );
        }
        let o = r.outputs();
        let (sa, ca) = (s[2].sin(), s[2].cos());
        let (sb, cb) = (s[3].sin(), s[3].cos());
        let jc = [
            s[0] + (0.170 - 0.125) * sb,
            s[1] - (0.170 - 0.125) * sa * cb,
        ];
        let jt = [
            s[0] + (0.060 - 0.125) * sb,
            s[1] - (0.060 - 0.125) * sa * cb,
        ];
        let _ = ca;
        let pairs = [
            (o.bearing_c.journal_m[0], jc[0]),
            (o.bearing_c.journal_m[1], jc[1]),
            (o.bearing_t.journal_m[0], jt[0]),
            (o.bearing_t.journal_m[1], jt[1]),
            (o.bearing_c.ring_m[0], s[4]),
            (o.bearing_c.ring_m[1], s[5]),
            (o.bearing_t.ring_m[0], s[6]),
            (o.bearing_t.ring_m[1], s[7]),
            (o.tilt_x_rad * 0.1, s[2] * 0.1),
            (o.tilt_y_rad * 0.1, s[3] * 0.1),
        ];
        for (a, b) in pairs {
            max_diff = max_diff.max((a - b).abs());
            max_amp = max_amp.max(b.abs());
        }
    }
    println!(
        "GGL vs minimal coordinates, 20 ms forced run-up: max |diff| {:.3e} m, max amplitude {:.3e} m, relative {:.2e}; GGL steps {}, rejected {}, jacobians {}, LU {}",
        max_diff,
        max_amp,
        max_diff / max_amp,
        tot.steps,
        tot.rejected_steps,
        tot.jacobian_evaluations,
        tot.factorizations
    );
    assert!(max_amp > 1e-6);
    assert!(
        max_diff / max_amp < 2e-7,
        "relative difference {}",
        max_diff / max_amp
    );
}
