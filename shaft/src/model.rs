//! A flexible rotor: shaft elements end to end, rigid disks and point masses at nodes, linear
//! supports (bearings with constant stiffness, damping and mass coefficients) at nodes; its
//! global mass, stiffness, damping and gyroscopic matrices.
//!
//! Coordinates: four per node, (x, y, alpha, beta) of node 0, then node 1, ... Node 0 sits at
//! z = 0, node i + 1 one element length further. The equations of motion at spin speed Omega
//! [rad/s] are M q'' + (C + Omega G) q' + K q = f(t), as in ROSS.

use crate::element::{Mat8, ShaftElement};
use crate::ShaftError;
use serde::{Deserialize, Serialize};

/// Coordinates per node: x, y, alpha, beta.
pub const DOF_PER_NODE: usize = 4;

/// A rigid disk at a node.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Disk {
    pub node: usize,
    pub mass_kg: f64,
    /// Diametral (transverse) moment of inertia [kg m^2].
    pub id_kg_m2: f64,
    /// Polar moment of inertia [kg m^2].
    pub ip_kg_m2: f64,
    pub tag: String,
}

/// A point mass at a node (translation only).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct PointMass {
    pub node: usize,
    pub mass_kg: f64,
    pub tag: String,
}

/// A linear support between a node and the ground: force on the shaft
/// -(K [x, y] + C [x', y'] + M [x'', y'']), each 2 x 2 as [[xx, xy], [yx, yy]].
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Support {
    pub node: usize,
    pub k_n_m: [[f64; 2]; 2],
    pub c_n_s_m: [[f64; 2]; 2],
    pub m_kg: [[f64; 2]; 2],
    pub tag: String,
}

/// An air ring bearing, linearized: the ring (a mass on its elastomer mount, stiffness and
/// damping to the ground) coupled to the journal node by the air film's stiffness and damping.
/// The film's force on the journal is -(K_f (r_J - r_R) + C_f (r_J' - r_R')), the ring feels the
/// opposite. Two coordinates of its own (the ring's x, y).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Ring {
    pub node: usize,
    pub mass_kg: f64,
    pub mount_k_n_m: f64,
    pub mount_c_n_s_m: f64,
    pub film_k_n_m: [[f64; 2]; 2],
    pub film_c_n_s_m: [[f64; 2]; 2],
    pub tag: String,
}

/// The rotor.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, Default)]
pub struct ShaftModel {
    pub elements: Vec<ShaftElement>,
    pub disks: Vec<Disk>,
    pub point_masses: Vec<PointMass>,
    pub supports: Vec<Support>,
    /// Air ring bearings (their rings' coordinates follow the shaft's, x and y per ring).
    pub rings: Vec<Ring>,
}

/// Dense global matrices, row-major, n x n with n = 4 (elements + 1) + 2 rings.
#[derive(Clone, Debug, PartialEq)]
pub struct Matrices {
    pub n: usize,
    /// The (x, y) coordinate pairs of the shaft nodes: a mode's whirl direction is judged on them.
    pub whirl_pairs: Vec<[usize; 2]>,
    pub m: Vec<f64>,
    pub k: Vec<f64>,
    pub c: Vec<f64>,
    pub g: Vec<f64>,
}

impl ShaftModel {
    pub fn n_nodes(&self) -> usize {
        self.elements.len() + 1
    }

    pub fn n_dof(&self) -> usize {
        DOF_PER_NODE * self.n_nodes() + 2 * self.rings.len()
    }

    /// The first coordinate (x; y follows) of ring `r`.
    pub fn ring_dof(&self, r: usize) -> usize {
        DOF_PER_NODE * self.n_nodes() + 2 * r
    }

    /// Axial position of every node [m].
    pub fn node_z_m(&self) -> Vec<f64> {
        let mut z = Vec::with_capacity(self.n_nodes());
        z.push(0.0);
        for e in &self.elements {
            z.push(z.last().unwrap() + e.length_m);
        }
        z
    }

    /// Total mass [kg] of shaft, disks and point masses.
    pub fn mass_kg(&self) -> f64 {
        self.elements.iter().map(|e| e.mass_kg()).sum::<f64>()
            + self.disks.iter().map(|d| d.mass_kg).sum::<f64>()
            + self.point_masses.iter().map(|p| p.mass_kg).sum::<f64>()
    }

    /// Axial position of the centre of mass of shaft, disks and point masses [m].
    pub fn mass_center_m(&self) -> f64 {
        let z = self.node_z_m();
        let moment = self
            .elements
            .iter()
            .zip(&z)
            .map(|(e, z0)| e.mass_kg() * (z0 + e.mass_center_m()))
            .sum::<f64>()
            + self
                .disks
                .iter()
                .map(|d| d.mass_kg * z[d.node])
                .sum::<f64>()
            + self
                .point_masses
                .iter()
                .map(|p| p.mass_kg * z[p.node])
                .sum::<f64>();
        moment / self.mass_kg()
    }

    /// Checks every element, disk, point mass and support; the message names the first bad one.
    pub fn validate(&self) -> Result<(), ShaftError> {
        if self.elements.is_empty() {
            return Err(ShaftError::Model("the shaft has no elements".into()));
        }
        for (i, e) in self.elements.iter().enumerate() {
            e.validate(i)?;
        }
        let nodes = self.n_nodes();
        let node_ok = |what: &str, tag: &str, node: usize| {
            if node < nodes {
                Ok(())
            } else {
                Err(ShaftError::Model(format!(
                    "{what} {tag:?} is at node {node}, off the shaft (nodes 0 to {})",
                    nodes - 1
                )))
            }
        };
        let finite = |what: &str, tag: &str, field: &str, v: f64, min_zero: bool| {
            if v.is_finite() && (!min_zero || v >= 0.0) {
                Ok(())
            } else {
                Err(ShaftError::Model(format!(
                    "{what} {tag:?}: {field} = {} must be a finite number{}",
                    bearing::num::Num(v),
                    if min_zero { " >= 0" } else { "" }
                )))
            }
        };
        for d in &self.disks {
            node_ok("disk", &d.tag, d.node)?;
            finite("disk", &d.tag, "m", d.mass_kg, true)?;
            finite("disk", &d.tag, "Id", d.id_kg_m2, true)?;
            finite("disk", &d.tag, "Ip", d.ip_kg_m2, true)?;
        }
        for p in &self.point_masses {
            node_ok("point mass", &p.tag, p.node)?;
            finite("point mass", &p.tag, "m", p.mass_kg, true)?;
        }
        for s in &self.supports {
            node_ok("bearing", &s.tag, s.node)?;
            for (field, a) in [("k", &s.k_n_m), ("c", &s.c_n_s_m), ("m", &s.m_kg)] {
                for (r, row) in a.iter().enumerate() {
                    for (c, v) in row.iter().enumerate() {
                        let name = format!("{field}{}{}", ["x", "y"][r], ["x", "y"][c]);
                        finite("bearing", &s.tag, &name, *v, false)?;
                    }
                }
            }
        }
        for r in &self.rings {
            node_ok("ring", &r.tag, r.node)?;
            if !(r.mass_kg.is_finite() && r.mass_kg > 0.0) {
                return Err(ShaftError::Model(format!(
                    "ring {:?}: mass = {} kg must be a finite number > 0",
                    r.tag,
                    bearing::num::Num(r.mass_kg)
                )));
            }
            finite("ring", &r.tag, "mount stiffness", r.mount_k_n_m, true)?;
            finite("ring", &r.tag, "mount damping", r.mount_c_n_s_m, true)?;
            for v in r.film_k_n_m.iter().chain(&r.film_c_n_s_m).flatten() {
                finite("ring", &r.tag, "film coefficient", *v, false)?;
            }
        }
        if let Some(r) = self
            .rings
            .iter()
            .enumerate()
            .find(|(i, r)| self.rings[..*i].iter().any(|o| o.node == r.node))
            .map(|(_, r)| r)
        {
            return Err(ShaftError::Model(format!(
                "two bearings at node {}: each air ring bearing needs a node of its own",
                r.node
            )));
        }
        Ok(())
    }

    /// The global matrices (call `validate` first).
    pub fn matrices(&self) -> Matrices {
        let n = self.n_dof();
        let mut out = Matrices {
            n,
            whirl_pairs: (0..self.n_nodes())
                .map(|k| [DOF_PER_NODE * k, DOF_PER_NODE * k + 1])
                .collect(),
            m: vec![0.0; n * n],
            k: vec![0.0; n * n],
            c: vec![0.0; n * n],
            g: vec![0.0; n * n],
        };
        let add8 = |a: &mut Vec<f64>, e: &Mat8, first: usize| {
            for i in 0..8 {
                for j in 0..8 {
                    a[(first + i) * n + first + j] += e[i][j];
                }
            }
        };
        for (i, e) in self.elements.iter().enumerate() {
            let first = DOF_PER_NODE * i;
            add8(&mut out.m, &e.mass(), first);
            add8(&mut out.k, &e.stiffness(), first);
            add8(&mut out.c, &e.damping(), first);
            add8(&mut out.g, &e.gyroscopic(), first);
        }
        for d in &self.disks {
            let b = DOF_PER_NODE * d.node;
            out.m[b * n + b] += d.mass_kg;
            out.m[(b + 1) * n + b + 1] += d.mass_kg;
            out.m[(b + 2) * n + b + 2] += d.id_kg_m2;
            out.m[(b + 3) * n + b + 3] += d.id_kg_m2;
            // ROSS's disk: G[alpha, beta] = Ip, G[beta, alpha] = -Ip.
            out.g[(b + 2) * n + b + 3] += d.ip_kg_m2;
            out.g[(b + 3) * n + b + 2] -= d.ip_kg_m2;
        }
        for p in &self.point_masses {
            let b = DOF_PER_NODE * p.node;
            out.m[b * n + b] += p.mass_kg;
            out.m[(b + 1) * n + b + 1] += p.mass_kg;
        }
        for s in &self.supports {
            let b = DOF_PER_NODE * s.node;
            for r in 0..2 {
                for c in 0..2 {
                    out.k[(b + r) * n + b + c] += s.k_n_m[r][c];
                    out.c[(b + r) * n + b + c] += s.c_n_s_m[r][c];
                    out.m[(b + r) * n + b + c] += s.m_kg[r][c];
                }
            }
        }
        for (ri, r) in self.rings.iter().enumerate() {
            let (j, q) = (DOF_PER_NODE * r.node, self.ring_dof(ri));
            for a in 0..2 {
                out.m[(q + a) * n + q + a] += r.mass_kg;
                out.k[(q + a) * n + q + a] += r.mount_k_n_m;
                out.c[(q + a) * n + q + a] += r.mount_c_n_s_m;
            }
            out.add_film(j, q, &r.film_k_n_m, &r.film_c_n_s_m);
        }
        out
    }
}

impl Matrices {
    /// Adds a film's stiffness `k` and damping `c` (2 x 2, row = force, column = displacement)
    /// between the coordinates (x, y) starting at `journal` and at `ring`: [[K, -K], [-K, K]]
    /// (the film pushes journal and ring apart alike).
    pub fn add_film(&mut self, journal: usize, ring: usize, k: &[[f64; 2]; 2], c: &[[f64; 2]; 2]) {
        let n = self.n;
        let (j, q) = (journal, ring);
        for a in 0..2 {
            for b in 0..2 {
                for (mat, v) in [(&mut self.k, k[a][b]), (&mut self.c, c[a][b])] {
                    mat[(j + a) * n + j + b] += v;
                    mat[(j + a) * n + q + b] -= v;
                    mat[(q + a) * n + j + b] -= v;
                    mat[(q + a) * n + q + b] += v;
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::element::Material;

    fn two_element_shaft() -> ShaftModel {
        let e = ShaftElement::cylinder(0.2, 0.0, 0.04, Material::steel());
        ShaftModel {
            elements: vec![e.clone(), e],
            disks: vec![Disk {
                node: 1,
                mass_kg: 3.0,
                id_kg_m2: 0.01,
                ip_kg_m2: 0.02,
                tag: "wheel".into(),
            }],
            point_masses: vec![PointMass {
                node: 2,
                mass_kg: 0.5,
                tag: "collar".into(),
            }],
            supports: vec![],
            rings: vec![],
        }
    }

    /// Rigid translation: the kinetic energy of unit velocity in x is the total mass.
    #[test]
    fn global_mass_of_a_rigid_translation_is_the_rotor_mass() {
        let s = two_element_shaft();
        let mm = s.matrices();
        let n = mm.n;
        let u: Vec<f64> = (0..n).map(|i| if i % 4 == 0 { 1.0 } else { 0.0 }).collect();
        let mut e = 0.0;
        for i in 0..n {
            for j in 0..n {
                e += u[i] * mm.m[i * n + j] * u[j];
            }
        }
        assert!((e - s.mass_kg()).abs() <= 1e-12 * e, "{e} {}", s.mass_kg());
    }

    #[test]
    fn a_bearing_off_the_shaft_is_named() {
        let mut s = two_element_shaft();
        s.supports.push(Support {
            node: 7,
            k_n_m: [[1e6, 0.0], [0.0, 1e6]],
            c_n_s_m: [[0.0; 2]; 2],
            m_kg: [[0.0; 2]; 2],
            tag: "B1".into(),
        });
        let e = s.validate().unwrap_err().to_string();
        assert!(
            e.contains("\"B1\"") && e.contains("node 7") && e.contains("0 to 2"),
            "{e}"
        );
        s.supports[0].node = 2;
        s.supports[0].k_n_m[0][1] = f64::NAN;
        let e = s.validate().unwrap_err().to_string();
        assert!(e.contains("kxy"), "{e}");
    }

    #[test]
    fn bad_elements_are_named_by_index_and_field() {
        let mut s = two_element_shaft();
        s.elements[1].id_left_m = 0.05;
        let e = s.validate().unwrap_err().to_string();
        assert!(e.contains("element 1") && e.contains("idl"), "{e}");
        s.elements[1].id_left_m = 0.0;
        s.elements[0].length_m = -0.1;
        let e = s.validate().unwrap_err().to_string();
        assert!(e.contains("element 0") && e.contains("L = -0.1"), "{e}");
    }
}
