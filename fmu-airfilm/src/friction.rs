//! Friction torque and power loss of the film: the wall shear stress on the journal, integrated
//! over the lobes (from the pressure field) and over the pockets (a model, below).
//!
//! Velocity across the gap (y from the journal, 0..h; the journal surface moves at U = Omega r in
//! +phi, the ring is at rest): u(y) = U (1 - y/h) + (1 / 2 eta) dp/dx (y^2 - y h). The shear
//! stress the film exerts on the journal surface, against its motion, is
//!
//!   tau = eta U / h + (h / 2) dp/dx,   dp/dx = (1/r) dp/dphi,
//!
//! the Couette part and the pressure-driven (Poiseuille) part. The friction torque on the journal
//! is T = r Int tau dA over the film, dA = r dphi dz over the full width (twice the meshed half),
//! and the power the film dissipates is P = T Omega.
//!
//! **Pockets.** Between the lobes (phi_t < phi < 2 pi / n_lobes of each block) the paper's
//! pockets supply air at ambient pressure: no pressure gradient, only Couette shear. Their depth
//! is not given; the model takes the pocket floor flush with the lobe's entry, i.e. the gap
//! h = C + dH - dx cos(theta) - dy sin(theta), the smallest depth a pocket behind a step of dH
//! can have. A deeper real pocket shears less, so the pocket part is an upper bound (with the
//! paper's geometry, 30 of 360 degrees, it is ~5 % of the total at the centre). A plain bore has
//! no pockets.
//!
//! Checked against Petroff's law T = 2 pi eta Omega r^3 b / C (concentric plain bore, exact), the
//! eccentric Couette integral 2 pi / (C sqrt(1 - eps^2)), and by mesh convergence (tests below).

use crate::geometry::Geometry;
use crate::mesh::Mesh;
use crate::node_functionals::dot;
use crate::params::BearingParams;
use crate::JournalState;

/// Friction torque of the film on the journal [N m] (positive: against the rotation), in parts.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct FrictionTorque {
    /// Couette shear over the lobes.
    pub couette_lobes_nm: f64,
    /// Pressure-driven shear over the lobes.
    pub poiseuille_lobes_nm: f64,
    /// Couette shear over the pockets (the model of the module documentation).
    pub pockets_nm: f64,
}

impl FrictionTorque {
    pub fn total_nm(&self) -> f64 {
        self.couette_lobes_nm + self.poiseuille_lobes_nm + self.pockets_nm
    }
}

/// Gauss points per pocket (composite: 4 intervals of 4 points) for the 1/h integral.
const POCKET_INTERVALS: usize = 4;
const GAUSS4_X: [f64; 4] = [
    -0.861_136_311_594_052_6,
    -0.339_981_043_584_856_3,
    0.339_981_043_584_856_3,
    0.861_136_311_594_052_6,
];
const GAUSS4_W: [f64; 4] = [
    0.347_854_845_137_453_9,
    0.652_145_154_862_546_1,
    0.652_145_154_862_546_1,
    0.347_854_845_137_453_9,
];

/// The pockets' quadrature points (composite Gauss, `POCKET_INTERVALS` x 4 per pocket): cos theta,
/// sin theta and the weight 0.5 dl w of each; none for a plain bore. Tabulated once per geometry.
pub fn pocket_points(bore: &crate::Bore) -> Vec<[f64; 3]> {
    let mut out = vec![];
    if !bore.plain_bore {
        let span = 2.0 * std::f64::consts::PI / bore.n_lobes as f64 - bore.phi_t_rad;
        let dl = span / POCKET_INTERVALS as f64;
        for k in 0..bore.n_blocks() {
            for i in 0..POCKET_INTERVALS {
                for (x, w) in GAUSS4_X.iter().zip(GAUSS4_W) {
                    let s = bore.phi_t_rad + (i as f64 + 0.5 * (1.0 + x)) * dl;
                    let theta = bore.block_start_rad(k) + s + bore.alpha_rad;
                    out.push([theta.cos(), theta.sin(), 0.5 * dl * w]);
                }
            }
        }
    }
    out
}

/// Friction torque of the film with the relative nodal pressures `p` (p / p_a) at journal state `j`.
/// The gap at the Gauss points comes from `geom`'s precomputed angles (no trigonometry per call:
/// this runs after every communication step) and is floored like the Reynolds coefficients'
/// (`Geometry::h_floor_rel`), so a closing gap gives a large, finite Couette shear.
pub fn friction_torque(
    prm: &BearingParams,
    mesh: &Mesh,
    geom: &Geometry,
    j: &JournalState,
    p: &[f64],
) -> FrictionTorque {
    let r = prm.bore.r_m;
    let c = prm.bore.c_m;
    let eta = prm.eta_pa_s;
    let u = j.omega_rad_s * r;
    let (ex, ey) = (j.dx_m / c, j.dy_m / c);
    let cols = &geom.columns;
    // Int dphi dzeta of 1 / H and of H dP/dphi over the lobes: H is a function of phi alone, so
    // per phi-Gauss point the column's integral of 1 and of dP/dxi (dP/dphi = 2 / dphi_e of it).
    // The gap h / C at the phi-Gauss points, floored like the Reynolds coefficients'.
    let (mut couette, mut floored) = (0.0, false);
    for k in 0..mesh.n_blocks {
        for g in 0..geom.nq {
            let gi = k * geom.nq + g;
            let h = 1.0 - ex * geom.cos_q[gi] - ey * geom.sin_q[gi] + geom.step_q[gi];
            floored |= h < geom.h_floor_rel;
            couette += cols.w_one[g] / h.max(geom.h_floor_rel);
        }
    }
    let poiseuille = if floored {
        poiseuille_by_columns(mesh, geom, ex, ey, p)
    } else {
        // H linear in the eccentricity: three fixed weights per node (`node_functionals`).
        let f = &geom.nodal;
        dot(&f.dp_step, p) - ex * dot(&f.dp_cos, p) - ey * dot(&f.dp_sin, p)
    };
    // tau = eta U / h + (h / 2) dp / (r dphi), h = C H, dp = p_a dP.
    let couette = couette * eta * u / c;
    let poiseuille = poiseuille * c * prm.p_a_pa * (2.0 / mesh.dphi_e) / (2.0 * r);
    // Meshed half width, dA = r dphi r dzeta: T = 2 r^3 Int tau dphi dzeta.
    let lobes = 2.0 * r * r * r;
    let mut pockets = 0.0;
    let bore = &prm.bore;
    for &[cos, sin, w] in &geom.pockets {
        let h = bore.c_m + bore.dh_m - j.dx_m * cos - j.dy_m * sin;
        pockets += w * eta * u / h;
    }
    FrictionTorque {
        couette_lobes_nm: lobes * couette,
        poiseuille_lobes_nm: lobes * poiseuille,
        // Full width b: T = r^3 (b / r) Int tau dphi.
        pockets_nm: r * r * bore.b_m * pockets,
    }
}

/// Int H dP/dxi over the lobes with the floored gap, point by point through the column
/// functionals (where some point is at the gap floor, and in the tests).
pub(crate) fn poiseuille_by_columns(
    mesh: &Mesh,
    geom: &Geometry,
    ex: f64,
    ey: f64,
    p: &[f64],
) -> f64 {
    let mut poiseuille = 0.0;
    for k in 0..mesh.n_blocks {
        let pb = &p[k * mesh.npb..(k + 1) * mesh.npb];
        geom.columns.each_dp(pb, |g, dp_int| {
            let gi = k * geom.nq + g;
            let h = 1.0 - ex * geom.cos_q[gi] - ey * geom.sin_q[gi] + geom.step_q[gi];
            poiseuille += h.max(geom.h_floor_rel) * dp_int;
        });
    }
    poiseuille
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::Mesh;
    use std::f64::consts::PI;

    fn plain(ne_phi: usize, ne_z: usize) -> (BearingParams, Mesh) {
        let prm = BearingParams {
            bore: crate::Bore::plain(),
            n_elem_phi: ne_phi,
            n_elem_z: ne_z,
            ..BearingParams::default()
        };
        let mesh = Mesh::new(&prm);
        (prm, mesh)
    }

    fn at(dx: f64, dy: f64, omega: f64) -> JournalState {
        JournalState {
            dx_m: dx,
            dy_m: dy,
            vx_m_s: 0.0,
            vy_m_s: 0.0,
            omega_rad_s: omega,
        }
    }

    /// Concentric plain bore, ambient pressure: Petroff's law T = 2 pi eta Omega r^3 b / C.
    #[test]
    fn petroff_in_the_concentric_plain_bore() {
        let (prm, mesh) = plain(16, 4);
        let omega = 2.0 * PI * 1000.0;
        let p = vec![1.0; mesh.n_blocks * mesh.npb];
        let geom = Geometry::new(&prm, &mesh);
        let t = friction_torque(&prm, &mesh, &geom, &at(0.0, 0.0, omega), &p);
        let b = &prm.bore;
        let petroff = 2.0 * PI * prm.eta_pa_s * omega * b.r_m.powi(3) * b.b_m / b.c_m;
        assert!(
            (t.total_nm() - petroff).abs() <= 1e-12 * petroff,
            "{t:?} vs {petroff}"
        );
        // No pressure gradient: the pressure part is round-off of the shape-function derivatives.
        assert!(t.poiseuille_lobes_nm.abs() <= 1e-15 * petroff, "{t:?}");
        assert_eq!(t.pockets_nm, 0.0);
    }

    /// Eccentric plain bore, Couette part: Int dphi / (C (1 + eps cos phi)) = 2 pi / (C sqrt(1 -
    /// eps^2)); the Gauss quadrature converges fast (error / 2^k much more than 2^6 per doubling).
    #[test]
    fn eccentric_couette_integral_converges_to_the_closed_form() {
        let omega = 2.0 * PI * 500.0;
        let eps = 0.6;
        let mut errors = vec![];
        for ne in [8, 16, 32] {
            let (prm, mesh) = plain(ne, 2);
            let b = &prm.bore;
            let p = vec![1.0; mesh.n_blocks * mesh.npb];
            let geom = Geometry::new(&prm, &mesh);
            let t = friction_torque(&prm, &mesh, &geom, &at(eps * b.c_m, 0.0, omega), &p);
            let exact = prm.eta_pa_s * omega * b.r_m.powi(3) * b.b_m * 2.0 * PI
                / (b.c_m * (1.0 - eps * eps).sqrt());
            errors.push((t.couette_lobes_nm - exact).abs() / exact);
        }
        assert!(errors[0] < 1e-4, "{errors:?}");
        assert!(
            errors[1] < errors[0] / 50.0 && errors[2] < 1e-9,
            "{errors:?}"
        );
    }

    /// The three-lobe bearing at a steady state at speed: the torque converges with the mesh
    /// (successive differences shrink at least fourfold), the pressure part is not negligible, and
    /// the pockets' share is the few per cent the documentation states.
    #[test]
    fn lobed_bearing_torque_converges_with_the_mesh() {
        let omega = 2.0 * PI * 1000.0;
        let j = at(3e-6, -6e-6, omega);
        let mut totals = vec![];
        let mut last = FrictionTorque::default();
        for (ne_phi, ne_z) in [(8, 2), (16, 4), (32, 8)] {
            let prm = BearingParams {
                n_elem_phi: ne_phi,
                n_elem_z: ne_z,
                ..BearingParams::default()
            };
            let s = crate::steady_state(&prm, j).expect("steady state");
            let geom = Geometry::new(&prm, &s.mesh);
            last = friction_torque(&prm, &s.mesh, &geom, &j, &s.p_rel);
            totals.push(last.total_nm());
        }
        println!("friction torque at 1000 Hz on meshes 8x2, 16x4, 32x8: {totals:?} N m; {last:?}");
        let d1 = (totals[1] - totals[0]).abs();
        let d2 = (totals[2] - totals[1]).abs();
        assert!(d2 < d1 / 4.0, "{totals:?}");
        assert!(d2 < 1e-3 * totals[2].abs(), "{totals:?}");
        let share = last.pockets_nm / last.total_nm();
        assert!((0.01..0.10).contains(&share), "{last:?}");
        assert!(
            last.poiseuille_lobes_nm.abs() > 1e-3 * last.total_nm(),
            "{last:?}"
        );
    }
}
