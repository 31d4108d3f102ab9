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

use crate::linalg::{Mat3, Vec3};
use nalgebra::{Matrix3, Vector3};
use serde::{Deserialize, Serialize};

type V3 = Vector3<f64>;
type M3 = Matrix3<f64>;

fn v3(a: &Vec3) -> V3 {
    V3::new(a[0], a[1], a[2])
}

fn arr(v: &V3) -> Vec3 {
    [v[0], v[1], v[2]]
}

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
    pub r: V3,
    pub rdot: V3,
    pub rot: M3,
    pub h: M3,
    pub omega_b: V3,
    /// H'(q, q') q'
    pub hdot_qdot: V3,
}

/// Rotation matrix Rx(a) Ry(b) Rz(c).
pub fn rotation(q: &Vec3) -> M3 {
    rotation_of(q[0].sin_cos(), q[1].sin_cos(), q[2].sin_cos())
}

/// [`rotation`] from the sines and cosines of its three angles.
fn rotation_of((sa, ca): (f64, f64), (sb, cb): (f64, f64), (sc, cc): (f64, f64)) -> M3 {
    // Rx * Ry (rows as written)
    let rxy = M3::new(cb, 0.0, sb, sa * sb, ca, -sa * cb, -ca * sb, sa, ca * cb);
    let rz = M3::new(cc, -sc, 0.0, sc, cc, 0.0, 0.0, 0.0, 1.0);
    rxy * rz
}

impl BodyKinematics {
    /// `x`, `v`: the body's 6 coordinates and 6 velocities.
    pub fn new(x: &[f64], v: &[f64]) -> Self {
        let q = [x[3], x[4], x[5]];
        // Each angle's sine and cosine once: H and the rotation share b and c (5 -> 3 sin_cos
        // per body and evaluation; libm's sincos was 5 % of a ring-riding run-up's samples).
        let (sb, cb) = q[1].sin_cos();
        let (sc, cc) = q[2].sin_cos();
        let h = M3::new(cb * cc, sc, 0.0, -cb * sc, cc, 0.0, sb, 0.0, 1.0);
        let (ad, bd, gd) = (v[3], v[4], v[5]);
        let omega_b = h * V3::new(ad, bd, gd);
        let hdot_qdot = V3::new(
            -sb * cc * ad * bd + gd * (-cb * sc * ad + cc * bd),
            sb * sc * ad * bd + gd * (-cb * cc * ad - sc * bd),
            cb * ad * bd,
        );
        BodyKinematics {
            r: V3::new(x[0], x[1], x[2]),
            rdot: V3::new(v[0], v[1], v[2]),
            rot: rotation_of(q[0].sin_cos(), (sb, cb), (sc, cc)),
            h,
            omega_b,
            hdot_qdot,
        }
    }

    /// Global position of the body-frame point s.
    pub fn point_pos(&self, s: &Vec3) -> Vec3 {
        arr(&(self.r + self.rot * v3(s)))
    }

    /// Global velocity of the body-frame point s: r' + R (omega x s).
    pub fn point_vel(&self, s: &Vec3) -> Vec3 {
        arr(&(self.rdot + self.rot * self.omega_b.cross(&v3(s))))
    }

    /// Global acceleration of point s given the coordinate accelerations `acc` (6 values):
    /// r'' + R (omega' x s + omega x (omega x s)), omega' = H q'' + H' q'.
    pub fn point_acc(&self, s: &Vec3, acc: &[f64]) -> Vec3 {
        let s = v3(s);
        let wd = self.h * V3::new(acc[3], acc[4], acc[5]) + self.hdot_qdot;
        let c_b = self.omega_b.cross(&self.omega_b.cross(&s));
        arr(&(V3::new(acc[0], acc[1], acc[2]) + self.rot * (wd.cross(&s) + c_b)))
    }

    /// Generalized force (6) of a global force `f` acting at body point `s`:
    /// [f; H^T (s x R^T f)].
    pub fn generalized_force(&self, s: &Vec3, f: &Vec3) -> [f64; 6] {
        let fb = self.rot.tr_mul(&v3(f));
        let tq = self.h.tr_mul(&v3(s).cross(&fb));
        [f[0], f[1], f[2], tq[0], tq[1], tq[2]]
    }
}

impl RigidBody {
    fn inertia(&self) -> M3 {
        let j = &self.inertia_kg_m2;
        M3::new(
            j[0][0], j[0][1], j[0][2], j[1][0], j[1][1], j[1][2], j[2][0], j[2][1], j[2][2],
        )
    }

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
        let j = self.inertia();
        // H^T J H
        let mrot = k.h.transpose() * (j * k.h);
        for i in 0..3 {
            for l in 0..3 {
                m6[(3 + i) * 6 + 3 + l] += mrot[(i, l)];
            }
        }
        // H^T (-omega x J omega - J H' q')
        let wjw = k.omega_b.cross(&(j * k.omega_b));
        let tq = k.h.transpose() * (-wjw - j * k.hdot_qdot);
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
        let jw = self.inertia() * k.omega_b;
        let mut e = 0.5 * self.mass_kg * k.rdot.dot(&k.rdot) + 0.5 * k.omega_b.dot(&jw);
        for pm in &self.point_masses {
            let vp = v3(&k.point_vel(&pm.s_m));
            e += 0.5 * pm.mass_kg * vp.dot(&vp);
        }
        e
    }

    /// Angular momentum about the global origin [kg m^2/s] (global axes).
    pub fn angular_momentum(&self, k: &BodyKinematics) -> Vec3 {
        let l_cm = k.rot * (self.inertia() * k.omega_b);
        let mut l = l_cm + self.mass_kg * k.r.cross(&k.rdot);
        for pm in &self.point_masses {
            let rp = v3(&k.point_pos(&pm.s_m));
            let vp = v3(&k.point_vel(&pm.s_m));
            l += pm.mass_kg * rp.cross(&vp);
        }
        arr(&l)
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
    let s = v3(&pm.s_m);
    // B columns: B e_j = -R (s x H e_j) = R ((H e_j) x s)
    let b = M3::from_columns(&[0, 1, 2].map(|jc| k.rot * k.h.column(jc).cross(&s)));
    let btb = b.transpose() * b;
    for i in 0..3 {
        m6[i * 6 + i] += m;
        for jc in 0..3 {
            m6[i * 6 + 3 + jc] += m * b[(i, jc)];
            m6[(3 + jc) * 6 + i] += m * b[(i, jc)];
            m6[(3 + i) * 6 + 3 + jc] += m * btb[(i, jc)];
        }
    }
    let aq = k.rot * (k.hdot_qdot.cross(&s) + k.omega_b.cross(&k.omega_b.cross(&s)));
    let fp = m * (v3(gravity) - aq);
    let bt = b.tr_mul(&fp);
    for i in 0..3 {
        f6[i] += fp[i];
        f6[3 + i] += bt[i];
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::{Rotation3, Unit};

    /// R = Rx(a) Ry(b) Rz(c), checked against nalgebra's axis rotations; orthonormal.
    #[test]
    fn rotation_is_the_cardan_sequence() {
        for q in [[0.1, -0.2, 0.3], [1e-4, 2e-4, 5.0], [-1.0, 0.7, -2.5]] {
            let r = rotation(&q);
            let axis = |v: V3| Unit::new_normalize(v);
            let expect = Rotation3::from_axis_angle(&axis(V3::x()), q[0])
                * Rotation3::from_axis_angle(&axis(V3::y()), q[1])
                * Rotation3::from_axis_angle(&axis(V3::z()), q[2]);
            assert!((r - expect.matrix()).abs().max() < 1e-15, "{q:?}");
            assert!((r.transpose() * r - M3::identity()).abs().max() < 1e-15);
        }
    }
}
