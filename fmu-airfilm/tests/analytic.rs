//! Plain bore against closed forms: the incompressible short-bearing limit and the
//! small-eccentricity compressible (Ausman) result.

use fmu_airfilm::Bore;
use fmu_airfilm::{steady_state, BearingParams, JournalState};
use std::f64::consts::PI;

/// Radial (restoring) and tangential (leading, in the sense of rotation) load for a journal
/// displaced along +x: W_r = -Fx, W_t = +Fy.
fn loads(prm: &BearingParams, eps: f64, omega: f64) -> (f64, f64) {
    let s = steady_state(prm, JournalState::at(eps * prm.bore.c_m, 0.0, omega)).unwrap();
    (-s.outputs.fx_n, s.outputs.fy_n)
}

#[test]
fn short_bearing_incompressible_limit() {
    // L/D = 0.1, Lambda = 1e-3: the compressible film is incompressible to O(Lambda).
    let prm = BearingParams {
        bore: Bore {
            b_m: 3e-3,
            ..BearingParams::plain_bore().bore
        },
        n_elem_phi: 48,
        n_elem_z: 4,
        ..BearingParams::plain_bore()
    };
    let lam_target = 1e-3;
    let omega = lam_target * prm.p_a_pa * prm.bore.c_m.powi(2)
        / (6.0 * prm.eta_pa_s * prm.bore.r_m.powi(2));
    for eps in [0.2, 0.5] {
        let (wr, wt) = loads(&prm, eps, omega);
        let u = omega * prm.bore.r_m;
        let l = prm.bore.b_m;
        let ocvirk = PI * prm.eta_pa_s * u * l.powi(3) * eps
            / (2.0 * prm.bore.c_m.powi(2) * (1.0 - eps * eps).powf(1.5));
        let rel = (wt - ocvirk) / ocvirk;
        println!(
            "short bearing eps {eps}: W_t = {wt:.6e} N, Ocvirk full film {ocvirk:.6e} N, rel. diff {rel:+.3e}; W_r/W_t = {:.2e}",
            wr / wt
        );
        assert!(rel.abs() < 0.02, "short-bearing mismatch {rel}");
        assert!((wr / wt).abs() < 0.01);
    }
}

#[derive(Clone, Copy)]
struct C(f64, f64);
impl C {
    fn mul(self, o: C) -> C {
        C(self.0 * o.0 - self.1 * o.1, self.0 * o.1 + self.1 * o.0)
    }
    fn div(self, o: C) -> C {
        let d = o.0 * o.0 + o.1 * o.1;
        C(
            (self.0 * o.0 + self.1 * o.1) / d,
            (self.1 * o.0 - self.0 * o.1) / d,
        )
    }
    fn sqrt(self) -> C {
        let r = self.0.hypot(self.1).sqrt();
        let a = 0.5 * self.1.atan2(self.0);
        C(r * a.cos(), r * a.sin())
    }
    fn exp(self) -> C {
        let m = self.0.exp();
        C(m * self.1.cos(), m * self.1.sin())
    }
    fn tanh(self) -> C {
        let e = C(2.0 * self.0, 2.0 * self.1).exp();
        C(e.0 - 1.0, e.1).div(C(e.0 + 1.0, e.1))
    }
}

#[test]
fn small_eccentricity_compressible_ausman() {
    let prm = BearingParams {
        n_elem_phi: 40,
        n_elem_z: 8,
        ..BearingParams::plain_bore()
    };
    let l_over_d = prm.bore.b_m / (2.0 * prm.bore.r_m);
    let eps = 0.01;
    for lambda in [0.3, 1.0, 3.0, 10.0] {
        let omega = lambda * prm.p_a_pa * prm.bore.c_m.powi(2)
            / (6.0 * prm.eta_pa_s * prm.bore.r_m.powi(2));
        let (wr, wt) = loads(&prm, eps, omega);
        let scale = prm.p_a_pa * prm.bore.b_m * 2.0 * prm.bore.r_m * eps;
        let num = wr.hypot(wt) / scale;
        let att = wt.atan2(wr);
        // Ausman: load/(p_a L D eps) = (pi/(2 lam)) |Lambda/(1+i Lambda) (lam - tanh(kappa lam)/kappa)|.
        let kappa = C(1.0, lambda).sqrt();
        let t = kappa.mul(C(l_over_d, 0.0)).tanh().div(kappa);
        let z = C(lambda, 0.0)
            .div(C(1.0, lambda))
            .mul(C(l_over_d - t.0, -t.1));
        let ana = PI / (2.0 * l_over_d) * z.0.hypot(z.1);
        // arg(z) is the force angle measured from the tangential direction: attitude = pi/2 + arg.
        let att_ana = 0.5 * PI + z.1.atan2(z.0);
        let rel = num / ana - 1.0;
        println!(
            "Lambda {lambda:>5}: load/(p_a L D eps) FE {num:.5} Ausman {ana:.5} (rel {rel:+.2e}); attitude FE {:.3} deg Ausman {:.3} deg",
            att.to_degrees(),
            att_ana.to_degrees()
        );
        assert!(rel.abs() < 5e-3, "load mismatch {rel}");
        assert!((att - att_ana).abs().to_degrees() < 0.5);
    }
}

/// Without rotation a journal at rest in any position carries no load: the steady pressure is
/// ambient everywhere (no wedge, no squeeze). The steady solver must return that at once, also
/// for a displaced journal and in the stiffness it differentiates (libcosim reads the outputs of
/// a `start_steady` film before any input is set, at omega = 0).
#[test]
fn no_rotation_no_load_at_any_position() {
    let prm = BearingParams::paper();
    for (ex, ey) in [(0.0, 0.0), (0.3, -0.5), (-0.7, 0.1)] {
        let j = JournalState::at(ex * prm.bore.c_m, ey * prm.bore.c_m, 0.0);
        let s = steady_state(&prm, j).unwrap_or_else(|e| panic!("({ex}, {ey}): {e}"));
        let dev = s.p_rel.iter().fold(0.0f64, |m, p| m.max((p - 1.0).abs()));
        assert!(dev < 1e-12, "({ex}, {ey}): max |P - 1| = {dev}");
        let f = s.outputs.fx_n.hypot(s.outputs.fy_n);
        assert!(f < 1e-9, "({ex}, {ey}): load {f} N");
    }
    let k = fmu_airfilm::static_stiffness(&prm, JournalState::at(0.0, -0.3 * prm.bore.c_m, 0.0))
        .unwrap();
    for row in k {
        for kij in row {
            assert!(kij.abs() < 1e-3, "{k:?} N/m");
        }
    }
    // With rotation the same start is not steady: the solver iterates and the film carries load.
    let j = JournalState::at(0.0, -0.3 * prm.bore.c_m, 2.0 * PI * 500.0);
    let s = steady_state(&prm, j).unwrap();
    assert!(s.iterations > 1 && s.outputs.fy_n > 1.0, "{:?}", s.outputs);
}
