//! Symmetry and invariance of the lobed film, squeeze sign, and the paper bearing's stiffness.

use fmu_airfilm::Bore;
use fmu_airfilm::{static_stiffness, steady_state, AirFilm, BearingParams, JournalState};
use std::f64::consts::PI;

const OMEGA: f64 = 2.0 * PI * 1000.0;

fn rot(v: [f64; 2], a: f64) -> [f64; 2] {
    [
        v[0] * a.cos() - v[1] * a.sin(),
        v[0] * a.sin() + v[1] * a.cos(),
    ]
}

fn force(prm: &BearingParams, d: [f64; 2]) -> [f64; 2] {
    let s = steady_state(prm, JournalState::at(d[0], d[1], OMEGA)).unwrap();
    [s.outputs.fx_n, s.outputs.fy_n]
}

#[test]
fn centred_journal_feels_no_net_force() {
    let prm = BearingParams::paper();
    let f = force(&prm, [0.0, 0.0]);
    println!("centred journal force: {f:?} N");
    assert!(f[0].hypot(f[1]) < 1e-9);
}

#[test]
fn displacement_turned_by_lobe_pitch_turns_the_force() {
    let prm = BearingParams::paper();
    let d = [0.25 * prm.bore.c_m, -0.35 * prm.bore.c_m];
    let f0 = force(&prm, d);
    for k in 1..3 {
        let a = k as f64 * 2.0 * PI / 3.0;
        let f1 = force(&prm, rot(d, a));
        let fr = rot(f0, a);
        let err = (f1[0] - fr[0]).hypot(f1[1] - fr[1]) / f0[0].hypot(f0[1]);
        println!("turn by {k} x 120 deg: F = {f1:?}, expected {fr:?}, rel. diff {err:.2e}");
        assert!(err < 1e-9);
    }
}

#[test]
fn changing_alpha_turns_the_force() {
    let prm = BearingParams::paper();
    let d = [0.1 * prm.bore.c_m, -0.5 * prm.bore.c_m];
    let f0 = force(&prm, d);
    let da = 0.37;
    let turned = BearingParams {
        bore: Bore {
            alpha_rad: prm.bore.alpha_rad + da,
            ..prm.bore.clone()
        },
        ..prm.clone()
    };
    let f1 = force(&turned, rot(d, da));
    let fr = rot(f0, da);
    let err = (f1[0] - fr[0]).hypot(f1[1] - fr[1]) / f0[0].hypot(f0[1]);
    println!("alpha + {da} rad: F = {f1:?}, expected {fr:?}, rel. diff {err:.2e}");
    assert!(err < 1e-9);
    // Same displacement, different alpha: the force changes (the ring is not isotropic).
    let f2 = force(&turned, d);
    assert!((f2[0] - f0[0]).hypot(f2[1] - f0[1]) > 1e-2 * f0[0].hypot(f0[1]));
}

#[test]
fn pure_squeeze_opposes_the_velocity() {
    for prm in [BearingParams::paper(), BearingParams::plain_bore()] {
        let v = [0.02, -0.05]; // m/s
        let path = move |t: f64| JournalState {
            dx_m: v[0] * t,
            dy_m: v[1] * t,
            vx_m_s: v[0],
            vy_m_s: v[1],
            omega_rad_s: 0.0,
        };
        let mut film = AirFilm::new(prm.clone()).unwrap();
        for n in 0..20 {
            film.advance(n as f64 * 1e-5, 1e-5, &path).unwrap();
        }
        let o = film.outputs();
        let cosang = (o.fx_n * v[0] + o.fy_n * v[1]) / (o.fx_n.hypot(o.fy_n) * v[0].hypot(v[1]));
        println!(
            "squeeze at Omega = 0 (plain bore {}): F = ({:.4}, {:.4}) N, cos(F, v) = {cosang:.5}",
            prm.bore.plain_bore, o.fx_n, o.fy_n
        );
        assert!(cosang < -0.9);
        if prm.bore.plain_bore {
            assert!(cosang < -1.0 + 1e-9);
        }
    }
}

#[test]
fn paper_bearing_stiffness_at_1000_hz() {
    let prm = BearingParams::paper();
    for eps in [0.3, 0.5, 0.7] {
        let k = static_stiffness(&prm, JournalState::at(0.0, -eps * prm.bore.c_m, OMEGA)).unwrap();
        let f = force(&prm, [0.0, -eps * prm.bore.c_m]);
        println!(
            "eps {eps} along -y, 1000 Hz: F = ({:.3}, {:.3}) N; K [N/mm] = [[{:.0}, {:.0}], [{:.0}, {:.0}]]",
            f[0], f[1], k[0][0] * 1e-3, k[0][1] * 1e-3, k[1][0] * 1e-3, k[1][1] * 1e-3
        );
        assert!(f[1] > 0.0, "journal displaced to -y must feel +y force");
        if eps == 0.5 {
            let kyy = k[1][1] * 1e-3;
            assert!(
                kyy > 1000.0 && kyy < 4000.0,
                "radial stiffness {kyy} N/mm not of the order of 2000 N/mm"
            );
        }
    }
}
