//! A multibody system: bodies (6 coordinates each), constraints, force elements, gravity.
//! Evaluates the block-diagonal mass matrix M(x) and the force vector f_e(t, x, v, u)
//! (applied forces plus centrifugal, Coriolis and gyroscopic terms) of eq. (1).

use crate::body::{BodyKinematics, RigidBody};
use crate::constraint::Constraint;
use crate::linalg::Vec3;
use serde::{Deserialize, Serialize};

/// Force laws acting in the global x-y plane (the lateral plane of the rotor).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub enum ForceElement {
    /// Isotropic visco-elastic mount of a body's centre to the housing at `anchor_m` (x, y):
    /// F = -c (r - anchor) - d r'.
    Mount {
        body: usize,
        anchor_m: [f64; 2],
        c_n_m: f64,
        d_n_s_m: f64,
    },
    /// Input force (u[input], u[input + 1]) in x, y on body point `s_m`; the opposite force acts
    /// on the centre of `reaction_body` (the air film pushes journal and ring apart).
    InputForce {
        body: usize,
        s_m: Vec3,
        input: usize,
        reaction_body: Option<usize>,
    },
    /// Linear spring-damper between point `s_a_m` of body a and the centre of body b, general
    /// 2x2 stiffness and damping (x, y): F_a = -K (p_a - r_b) - D (p_a' - r_b'), F_b = -F_a.
    /// Stands in for a linearized air film.
    Film {
        body_a: usize,
        s_a_m: Vec3,
        body_b: usize,
        k_n_m: [[f64; 2]; 2],
        d_n_s_m: [[f64; 2]; 2],
    },
    /// Mixed-lubrication contact of the journal (point `s_a_m` of body a) on its ring (centre of
    /// body b): the `bearing` crate's penalty law on the lobed bore, evaluated on the relative
    /// displacement. F_b = -F_a. Boxed: the bearing data dwarfs the other variants.
    RingContact {
        body_a: usize,
        s_a_m: Vec3,
        body_b: usize,
        bearing: Box<bearing::BoreContact>,
    },
}

#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct MultibodySystem {
    pub bodies: Vec<RigidBody>,
    pub constraints: Vec<Constraint>,
    pub forces: Vec<ForceElement>,
    pub gravity_m_s2: Vec3,
}

impl MultibodySystem {
    pub fn n_coords(&self) -> usize {
        6 * self.bodies.len()
    }
    pub fn n_constraints(&self) -> usize {
        self.constraints.len()
    }

    /// Kinematics of every body.
    pub fn kinematics(&self, x: &[f64], v: &[f64]) -> Vec<BodyKinematics> {
        (0..self.bodies.len())
            .map(|b| BodyKinematics::new(&x[6 * b..6 * b + 6], &v[6 * b..6 * b + 6]))
            .collect()
    }

    /// The generalized forces of the [`ForceElement::InputForce`]s alone (linear in `u`).
    pub fn input_forces(&self, x: &[f64], v: &[f64], u: &[f64], f: &mut [f64]) {
        f.fill(0.0);
        let kins = self.kinematics(x, v);
        for fe in &self.forces {
            add_input_force(f, &kins, fe, u);
        }
    }

    /// Mass matrix blocks (one row-major 6x6 per body) and f_e. `u` are the input forces.
    pub fn eval(&self, x: &[f64], v: &[f64], u: &[f64], m_blocks: &mut [[f64; 36]], f: &mut [f64]) {
        self.eval_with(x, v, u, m_blocks, f, RingContacts::Evaluate)
    }

    /// [`Self::eval`], with the ring contacts' forces (they depend on the positions alone)
    /// evaluated, left out, recorded or reused as `contacts` says.
    pub fn eval_with(
        &self,
        x: &[f64],
        v: &[f64],
        u: &[f64],
        m_blocks: &mut [[f64; 36]],
        f: &mut [f64],
        mut contacts: RingContacts<'_>,
    ) {
        let kins = self.kinematics(x, v);
        for (b, body) in self.bodies.iter().enumerate() {
            let mut m6 = [0.0; 36];
            let mut f6 = [0.0; 6];
            body.inertial_terms(&kins[b], &self.gravity_m_s2, &mut m6, &mut f6);
            m_blocks[b] = m6;
            f[6 * b..6 * b + 6].copy_from_slice(&f6);
        }
        for (e, fe) in self.forces.iter().enumerate() {
            match *fe {
                ForceElement::Mount {
                    body,
                    anchor_m,
                    c_n_m,
                    d_n_s_m,
                } => {
                    let k = &kins[body];
                    f[6 * body] += -c_n_m * (k.r[0] - anchor_m[0]) - d_n_s_m * k.rdot[0];
                    f[6 * body + 1] += -c_n_m * (k.r[1] - anchor_m[1]) - d_n_s_m * k.rdot[1];
                }
                ForceElement::InputForce { .. } => add_input_force(f, &kins, fe, u),
                ForceElement::Film {
                    body_a,
                    s_a_m,
                    body_b,
                    k_n_m,
                    d_n_s_m,
                } => {
                    let ka = &kins[body_a];
                    let kb = &kins[body_b];
                    let pa = ka.point_pos(&s_a_m);
                    let va = ka.point_vel(&s_a_m);
                    let dr = [pa[0] - kb.r[0], pa[1] - kb.r[1]];
                    let dv = [va[0] - kb.rdot[0], va[1] - kb.rdot[1]];
                    let mut fv = [0.0; 3];
                    for i in 0..2 {
                        fv[i] = -(k_n_m[i][0] * dr[0] + k_n_m[i][1] * dr[1])
                            - (d_n_s_m[i][0] * dv[0] + d_n_s_m[i][1] * dv[1]);
                    }
                    add_point_force(f, body_a, ka, &s_a_m, &fv);
                    f[6 * body_b] -= fv[0];
                    f[6 * body_b + 1] -= fv[1];
                }
                ForceElement::RingContact {
                    body_a,
                    s_a_m,
                    body_b,
                    ref bearing,
                } => {
                    if matches!(contacts, RingContacts::Omit) {
                        continue;
                    }
                    let ka = &kins[body_a];
                    let kb = &kins[body_b];
                    let pa = ka.point_pos(&s_a_m);
                    let d = [pa[0] - kb.r[0], pa[1] - kb.r[1]];
                    let fc = contacts.force_n(e, d, || bearing.force_n(d));
                    if fc != [0.0, 0.0] {
                        add_point_force(f, body_a, ka, &s_a_m, &[fc[0], fc[1], 0.0]);
                        f[6 * body_b] -= fc[0];
                        f[6 * body_b + 1] -= fc[1];
                    }
                }
            }
        }
    }

    /// Total kinetic energy [J].
    pub fn kinetic_energy(&self, x: &[f64], v: &[f64]) -> f64 {
        let kins = self.kinematics(x, v);
        self.bodies
            .iter()
            .zip(&kins)
            .map(|(b, k)| b.kinetic_energy(k))
            .sum()
    }
}

/// What an evaluation does with the ring contacts.
pub enum RingContacts<'a> {
    /// Evaluates them.
    Evaluate,
    /// Leaves them out: a difference quotient in a velocity does not need them (they cancel), and
    /// the contact is most of an evaluation while a journal rides on its ring.
    Omit,
    /// Evaluates them and records each one's relative displacement and force.
    Record(&'a mut ContactMemo),
    /// Reuses a recorded force where the relative displacement is bitwise the recorded one (a
    /// difference quotient in a coordinate that does not move that journal against its ring:
    /// the other bearing's, axial ones, the spin), evaluates the others.
    Reuse(&'a mut ContactMemo),
}

impl RingContacts<'_> {
    fn force_n(
        &mut self,
        element: usize,
        d: [f64; 2],
        eval: impl FnOnce() -> [f64; 2],
    ) -> [f64; 2] {
        match self {
            RingContacts::Record(memo) => {
                let fc = eval();
                if memo.recorded.len() <= element {
                    memo.recorded.resize(element + 1, None);
                }
                memo.recorded[element] = Some((d, fc));
                fc
            }
            RingContacts::Reuse(memo) => match memo.recorded.get(element) {
                Some(&Some((dr, fc))) if dr.map(f64::to_bits) == d.map(f64::to_bits) => {
                    memo.reused += 1;
                    fc
                }
                _ => eval(),
            },
            RingContacts::Evaluate | RingContacts::Omit => eval(),
        }
    }
}

/// The ring contacts' relative displacements and forces at one configuration, by force element.
#[derive(Clone, Debug, Default)]
pub struct ContactMemo {
    recorded: Vec<Option<([f64; 2], [f64; 2])>>,
    reused: usize,
}

impl ContactMemo {
    /// Contact forces reused so far.
    pub fn reused(&self) -> usize {
        self.reused
    }

    /// Back to the empty memo of `default()`, keeping its allocation.
    pub fn clear(&mut self) {
        self.recorded.clear();
        self.reused = 0;
    }
}

/// Adds the force of `fe` if it is an [`ForceElement::InputForce`] (its input pair on its body
/// point, the reaction on the centre of its reaction body); any other element adds nothing.
fn add_input_force(f: &mut [f64], kins: &[BodyKinematics], fe: &ForceElement, u: &[f64]) {
    let ForceElement::InputForce {
        body,
        s_m,
        input,
        reaction_body,
    } = *fe
    else {
        return;
    };
    let force_n = [u[input], u[input + 1]];
    add_point_force(f, body, &kins[body], &s_m, &[force_n[0], force_n[1], 0.0]);
    if let Some(rb) = reaction_body {
        f[6 * rb] -= force_n[0];
        f[6 * rb + 1] -= force_n[1];
    }
}

fn add_point_force(f: &mut [f64], body: usize, k: &BodyKinematics, s: &Vec3, fv: &Vec3) {
    let q = k.generalized_force(s, fv);
    for i in 0..6 {
        f[6 * body + i] += q[i];
    }
}
