//! Rigid bodies with 6 coordinates: centre-of-mass position r and Cardan angles
//! q = (alpha, beta, gamma), R = Rx(alpha) Ry(beta) Rz(gamma).
//!
//! Why Cardan "tilt-tilt-spin": the rotor spins fast about its body z axis with tilts of
//! ~1e-4 rad. With z rotated last, gamma is the spin angle itself, so the rheonomic constraint is
//! simply gamma = phi(t) (linear in x), the tilts alpha, beta are small numbers that keep full
//! relative precision, and the only singularity (beta = +-90 deg) is far outside the motion.
//! Euler angles z-x-z would be singular exactly at zero tilt; quaternions need a norm constraint
//! and a 7th coordinate. The generalized velocities are the angle rates, v = x' (so the GGL
//! kinematic equation M x' = M v - G^T mu is well defined with the same M).
//!
//! Body-frame angular velocity: omega = H(q) q', with
//! H = [[cb cc, sc, 0], [-cb sc, cc, 0], [sb, 0, 1]].
//! Rotational equations (Jourdain / projected Newton-Euler):
//! H^T J H q'' = H^T (tau - omega x J omega - J H' q').

use crate::linalg::*;
use serde::{Deserialize, Serialize};

/// A point mass rigidly attached to a body at body-frame position `s_m` (relative to the CM of
/// the body without it). Used for imbalance masses.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct PointMass {
    pub mass_kg: f64,
    pub s_m: Vec3,
}

/// A rigid body: mass, inertia tensor about its centre of mass in body axes, attached point masses.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct RigidBody {
    pub mass_kg: f64,
    pub inertia_kg_m2: Mat3,
    pub point_masses: Vec<PointMass>,
}

/// Position- and velocity-dependent quantities of one body, computed once per evaluation.
#[derive(Clone, Copy, Debug)]
pub struct BodyKinematics {
    pub r: Vec3,
    pub rdot: Vec3,
    pub rot: Mat3,
    pub h: Mat3,
    pub omega_b: Vec3,
    /// H'(q, q') q'
    pub hdot_qdot: Vec3,
}

/// Rotation matrix Rx(a) Ry(b) Rz(c).
pub fn rotation(q: &Vec3) -> Mat3 {
    let (sa, ca) = q[0].sin_cos();
    let (sb, cb) = q[1].sin_cos();
    let (sc, cc) = q[2].sin_cos();
    // Rx * Ry
    let rxy = [
        [cb, 0.0, sb],
        [sa * sb, ca, -sa * cb],
        [-ca * sb, sa, ca * cb],
    ];
    let rz = [[cc, -sc, 0.0], [sc, cc, 0.0], [0.0, 0.0, 1.0]];
    mat3_mul(&rxy, &rz)
}

impl BodyKinematics {
    /// `x`, `v`: the body's 6 coordinates and 6 velocities.
    pub fn new(x: &[f64], v: &[f64]) -> Self {
        let q = [x[3], x[4], x[5]];
        let (sb, cb) = q[1].sin_cos();
        let (sc, cc) = q[2].sin_cos();
        let h = [[cb * cc, sc, 0.0], [-cb * sc, cc, 0.0], [sb, 0.0, 1.0]];
        let (ad, bd, gd) = (v[3], v[4], v[5]);
        let omega_b = mat3_vec(&h, &[ad, bd, gd]);
        let hdot_qdot = [
            -sb * cc * ad * bd + gd * (-cb * sc * ad + cc * bd),
            sb * sc * ad * bd + gd * (-cb * cc * ad - sc * bd),
            cb * ad * bd,
        ];
        BodyKinematics {
            r: [x[0], x[1], x[2]],
            rdot: [v[0], v[1], v[2]],
            rot: rotation(&q),
            h,
            omega_b,
            hdot_qdot,
        }
    }

    /// Global position of the body-frame point s.
    pub fn point_pos(&self, s: &Vec3) -> Vec3 {
        let d = mat3_vec(&self.rot, s);
        [self.r[0] + d[0], self.r[1] + d[1], self.r[2] + d[2]]
    }

    /// Global velocity of the body-frame point s: r' + R (omega x s).
    pub fn point_vel(&self, s: &Vec3) -> Vec3 {
        let d = mat3_vec(&self.rot, &cross(&self.omega_b, s));
        [
            self.rdot[0] + d[0],
            self.rdot[1] + d[1],
            self.rdot[2] + d[2],
        ]
    }

    /// Global acceleration of point s given the coordinate accelerations `acc` (6 values).
    pub fn point_acc(&self, s: &Vec3, acc: &[f64]) -> Vec3 {
        let qdd = mat3_vec(&self.h, &[acc[3], acc[4], acc[5]]);
        let wd = [
            qdd[0] + self.hdot_qdot[0],
            qdd[1] + self.hdot_qdot[1],
            qdd[2] + self.hdot_qdot[2],
        ];
        let ws = cross(&self.omega_b, s);
        let a_b = cross(&wd, s);
        let c_b = cross(&self.omega_b, &ws);
        let d = mat3_vec(
            &self.rot,
            &[a_b[0] + c_b[0], a_b[1] + c_b[1], a_b[2] + c_b[2]],
        );
        [acc[0] + d[0], acc[1] + d[1], acc[2] + d[2]]
    }

    /// Generalized force (6) of a global force `f` acting at body point `s`:
    /// [f; H^T (s x R^T f)].
    pub fn generalized_force(&self, s: &Vec3, f: &Vec3) -> [f64; 6] {
        let fb = mat3t_vec(&self.rot, f);
        let tq = mat3t_vec(&self.h, &cross(s, &fb));
        [f[0], f[1], f[2], tq[0], tq[1], tq[2]]
    }
}

impl RigidBody {
    /// Adds the body's 6x6 mass matrix (row-major) to `m6` and its gravity plus
    /// centrifugal/gyroscopic generalized forces to `f6`.
    pub fn inertial_terms(
        &self,
        k: &BodyKinematics,
        gravity: &Vec3,
        m6: &mut [f64; 36],
        f6: &mut [f64; 6],
    ) {
        let m = self.mass_kg;
        for i in 0..3 {
            m6[i * 6 + i] += m;
            f6[i] += m * gravity[i];
        }
        let j = &self.inertia_kg_m2;
        let jh = mat3_mul(j, &k.h);
        let ht = transpose3(&k.h);
        let mrot = mat3_mul(&ht, &jh);
        for i in 0..3 {
            for l in 0..3 {
                m6[(3 + i) * 6 + 3 + l] += mrot[i][l];
            }
        }
        let jw = mat3_vec(j, &k.omega_b);
        let wjw = cross(&k.omega_b, &jw);
        let jhq = mat3_vec(j, &k.hdot_qdot);
        let tq = mat3_vec(&ht, &[-wjw[0] - jhq[0], -wjw[1] - jhq[1], -wjw[2] - jhq[2]]);
        for i in 0..3 {
            f6[3 + i] += tq[i];
        }
        for pm in &self.point_masses {
            if pm.mass_kg != 0.0 {
                point_mass_terms(pm, k, gravity, m6, f6);
            }
        }
    }

    /// Kinetic energy [J].
    pub fn kinetic_energy(&self, k: &BodyKinematics) -> f64 {
        let jw = mat3_vec(&self.inertia_kg_m2, &k.omega_b);
        let mut e = 0.5 * self.mass_kg * dot(&k.rdot, &k.rdot) + 0.5 * dot(&k.omega_b, &jw);
        for pm in &self.point_masses {
            let vp = k.point_vel(&pm.s_m);
            e += 0.5 * pm.mass_kg * dot(&vp, &vp);
        }
        e
    }

    /// Angular momentum about the global origin [kg m^2/s] (global axes).
    pub fn angular_momentum(&self, k: &BodyKinematics) -> Vec3 {
        let jw = mat3_vec(&self.inertia_kg_m2, &k.omega_b);
        let l_cm = mat3_vec(&k.rot, &jw);
        let p = cross(&k.r, &k.rdot);
        let mut l = [
            l_cm[0] + self.mass_kg * p[0],
            l_cm[1] + self.mass_kg * p[1],
            l_cm[2] + self.mass_kg * p[2],
        ];
        for pm in &self.point_masses {
            let rp = k.point_pos(&pm.s_m);
            let vp = k.point_vel(&pm.s_m);
            let c = cross(&rp, &vp);
            for i in 0..3 {
                l[i] += pm.mass_kg * c[i];
            }
        }
        l
    }
}

/// Point mass at body point s: velocity r' + B q' with B = -R [s]x H.
/// Mass matrix += m [[I, B], [B^T, B^T B]]; forces += m [I; B^T] (g - a_quad),
/// a_quad = R (H'q' x s + omega x (omega x s)).
fn point_mass_terms(
    pm: &PointMass,
    k: &BodyKinematics,
    gravity: &Vec3,
    m6: &mut [f64; 36],
    f6: &mut [f64; 6],
) {
    let m = pm.mass_kg;
    let s = &pm.s_m;
    // B columns: B e_j = -R (s x H e_j) = R ((H e_j) x s)
    let mut b = [[0.0; 3]; 3];
    for jc in 0..3 {
        let hj = [k.h[0][jc], k.h[1][jc], k.h[2][jc]];
        let col = mat3_vec(&k.rot, &cross(&hj, s));
        for i in 0..3 {
            b[i][jc] = col[i];
        }
    }
    let btb = mat3_mul(&transpose3(&b), &b);
    for i in 0..3 {
        m6[i * 6 + i] += m;
        for jc in 0..3 {
            m6[i * 6 + 3 + jc] += m * b[i][jc];
            m6[(3 + jc) * 6 + i] += m * b[i][jc];
            m6[(3 + i) * 6 + 3 + jc] += m * btb[i][jc];
        }
    }
    let ws = cross(&k.omega_b, s);
    let t1 = cross(&k.hdot_qdot, s);
    let t2 = cross(&k.omega_b, &ws);
    let aq = mat3_vec(&k.rot, &[t1[0] + t2[0], t1[1] + t2[1], t1[2] + t2[2]]);
    let fp = [
        m * (gravity[0] - aq[0]),
        m * (gravity[1] - aq[1]),
        m * (gravity[2] - aq[2]),
    ];
    let bt = mat3t_vec(&b, &fp);
    for i in 0..3 {
        f6[i] += fp[i];
        f6[3 + i] += bt[i];
    }
}
