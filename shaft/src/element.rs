//! The shaft element: a conical (or cylindrical) hollow Timoshenko beam between two nodes,
//! bending in two planes, with rotary inertia, shear deformation and gyroscopic terms.
//!
//! The matrices are ROSS's (`ross/shaft_element.py`, ross-rotordynamics 2.3.0: Genta and
//! Gugliotta's conical element, the shear coefficient of Cowper or Hutchinson), restricted to the
//! lateral coordinates. The same element in both tools is what makes a rotor read from a ROSS
//! file give ROSS's answers; the element itself is checked against the exact Timoshenko beam
//! (tests/timoshenko.rs), not against ROSS.
//!
//! Coordinates of an element, in this order: x0, y0, alpha0, beta0, x1, y1, alpha1, beta1. x is
//! horizontal, y vertical, alpha the rotation about x, beta the rotation about y (right-handed,
//! z along the shaft): a bent shaft's slopes are dx/dz = beta and dy/dz = -alpha.

use crate::ShaftError;
use serde::{Deserialize, Serialize};

/// An 8 x 8 element matrix over (x0, y0, alpha0, beta0, x1, y1, alpha1, beta1).
pub type Mat8 = [[f64; 8]; 8];

/// An isotropic elastic material.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Material {
    /// Name (reported in messages only).
    pub name: String,
    /// Density [kg/m^3].
    pub rho_kg_m3: f64,
    /// Young's modulus [Pa].
    pub e_pa: f64,
    /// Shear modulus [Pa].
    pub g_pa: f64,
}

impl Material {
    /// Structural steel as ROSS's examples give it (7810 kg/m^3, 211 GPa, 81.2 GPa).
    pub fn steel() -> Material {
        Material {
            name: "steel".into(),
            rho_kg_m3: 7810.0,
            e_pa: 211e9,
            g_pa: 81.2e9,
        }
    }

    /// Poisson's ratio of an isotropic material, E / (2 G) - 1.
    pub fn poisson(&self) -> f64 {
        self.e_pa / (2.0 * self.g_pa) - 1.0
    }
}

/// How the shear coefficient kappa follows from the cross-section (hollow circle) and Poisson's
/// ratio.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize, Default)]
#[serde(rename_all = "lowercase")]
pub enum ShearCoefficient {
    /// Cowper (1966), ROSS's default.
    #[default]
    Cowper,
    /// Hutchinson (2001).
    Hutchinson,
}

/// One shaft element.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct ShaftElement {
    /// Length [m].
    pub length_m: f64,
    /// Inner and outer diameters at the left (lower z) node [m].
    pub id_left_m: f64,
    pub od_left_m: f64,
    /// Inner and outer diameters at the right node [m].
    pub id_right_m: f64,
    pub od_right_m: f64,
    pub material: Material,
    /// Shear deformation (Timoshenko); without it, Euler-Bernoulli.
    pub shear_effects: bool,
    pub rotary_inertia: bool,
    pub gyroscopic: bool,
    pub shear_coefficient: ShearCoefficient,
    /// Constant axial force [N] (tension positive) and torque [N m]: their lateral stiffness.
    pub axial_force_n: f64,
    pub torque_n_m: f64,
    /// Proportional damping of the element, C = alpha M + beta K [1/s, s].
    pub alpha_1_s: f64,
    pub beta_s: f64,
}

/// The cross-section quantities an element's matrices use (ROSS's names).
struct Section {
    a_l: f64,
    a: f64,
    ie_l: f64,
    ie: f64,
    phi: f64,
    a1: f64,
    a2: f64,
    b1: f64,
    b2: f64,
    gama: f64,
    delta: f64,
}

impl ShaftElement {
    /// A cylindrical element with ROSS's defaults (Timoshenko, rotary inertia, gyroscopic,
    /// Cowper's shear coefficient, no axial load, no damping).
    pub fn cylinder(length_m: f64, id_m: f64, od_m: f64, material: Material) -> ShaftElement {
        ShaftElement {
            length_m,
            id_left_m: id_m,
            od_left_m: od_m,
            id_right_m: id_m,
            od_right_m: od_m,
            material,
            shear_effects: true,
            rotary_inertia: true,
            gyroscopic: true,
            shear_coefficient: ShearCoefficient::Cowper,
            axial_force_n: 0.0,
            torque_n_m: 0.0,
            alpha_1_s: 0.0,
            beta_s: 0.0,
        }
    }

    /// Checks the geometry and material; `index` names the element in the message.
    pub fn validate(&self, index: usize) -> Result<(), ShaftError> {
        let bad = |field: &'static str, value: f64, reason: &'static str| {
            Err(ShaftError::Element {
                index,
                field,
                value,
                reason,
            })
        };
        let positive: [(&'static str, f64); 6] = [
            ("L", self.length_m),
            ("odl", self.od_left_m),
            ("odr", self.od_right_m),
            ("rho", self.material.rho_kg_m3),
            ("E", self.material.e_pa),
            ("G_s", self.material.g_pa),
        ];
        for (field, v) in positive {
            if !(v.is_finite() && v > 0.0) {
                return bad(field, v, "must be a finite number > 0");
            }
        }
        for (field, v, od) in [
            ("idl", self.id_left_m, self.od_left_m),
            ("idr", self.id_right_m, self.od_right_m),
        ] {
            if !(v.is_finite() && v >= 0.0) {
                return bad(field, v, "must be a finite number >= 0");
            }
            if v >= od {
                return bad(
                    field,
                    v,
                    "the inner diameter must be smaller than the outer one",
                );
            }
        }
        for (field, v) in [
            ("axial_force", self.axial_force_n),
            ("torque", self.torque_n_m),
            ("alpha", self.alpha_1_s),
            ("beta", self.beta_s),
        ] {
            if !v.is_finite() {
                return bad(field, v, "must be a finite number");
            }
        }
        let nu = self.material.poisson();
        if !(nu > -1.0 && nu < 0.5) {
            return bad(
                "G_s",
                self.material.g_pa,
                "gives a Poisson ratio E/(2 G_s) - 1 outside (-1, 0.5)",
            );
        }
        Ok(())
    }

    /// Mass [kg].
    pub fn mass_kg(&self) -> f64 {
        let (ol, or, il, ir) = (
            self.od_left_m,
            self.od_right_m,
            self.id_left_m,
            self.id_right_m,
        );
        let outer = ol * ol + ol * or + or * or;
        let inner = il * il + il * ir + ir * ir;
        self.material.rho_kg_m3 * std::f64::consts::PI * (self.length_m / 12.0) * (outer - inner)
    }

    /// Axial position of the element's centre of mass from its left node [m] (ROSS's
    /// `beam_cg`; half the length for a cylinder).
    pub fn mass_center_m(&self) -> f64 {
        let (roj, rok, rij, rik) = (
            self.od_left_m / 2.0,
            self.od_right_m / 2.0,
            self.id_left_m / 2.0,
            self.id_right_m / 2.0,
        );
        let c1 = roj * roj + 2.0 * roj * rok + 3.0 * rok * rok
            - rij * rij
            - 2.0 * rij * rik
            - 3.0 * rik * rik;
        let c2 = (roj * roj + roj * rok + rok * rok) - (rij * rij + rij * rik + rik * rik);
        self.length_m * c1 / (4.0 * c2)
    }

    fn section(&self) -> Section {
        use std::f64::consts::PI;
        let (l, odl, odr, idl, idr) = (
            self.length_m,
            self.od_left_m,
            self.od_right_m,
            self.id_left_m,
            self.id_right_m,
        );
        let a_l = PI * (odl * odl - idl * idl) / 4.0;
        let ie_l = PI * (odl.powi(4) - idl.powi(4)) / 64.0;
        let (roj, rij, rok, rik) = (odl / 2.0, idl / 2.0, odr / 2.0, idr / 2.0);
        let d_ro = rok - roj;
        let d_ri = rik - rij;
        let a1 = 2.0 * PI * (roj * d_ro - rij * d_ri) / a_l;
        let a2 = PI * (roj.powi(3) * d_ro - rij.powi(3) * d_ri) / ie_l;
        let b1 = PI * (d_ro * d_ro - d_ri * d_ri) / a_l;
        let b2 = 3.0 * PI * (roj * roj * d_ro * d_ro - rij * rij * d_ri * d_ri) / (2.0 * ie_l);
        let gama = PI * (roj * d_ro.powi(3) - rij * d_ri.powi(3)) / ie_l;
        let delta = PI * (d_ro.powi(4) - d_ri.powi(4)) / (4.0 * ie_l);
        // Area and second moment at the middle of the element.
        let a = a_l * (1.0 + a1 * 0.5 + b1 * 0.25);
        let ie =
            ie_l * (1.0 + a2 * 0.5 + b2 * 0.25 + gama * 0.5f64.powi(3) + delta * 0.5f64.powi(4));
        let mut phi = 0.0;
        if self.shear_effects {
            let nu = self.material.poisson();
            let r = ((idl + idr) / 2.0) / ((odl + odr) / 2.0);
            let r2 = r * r;
            let r12 = (1.0 + r2) * (1.0 + r2);
            let kappa = match self.shear_coefficient {
                ShearCoefficient::Hutchinson => {
                    6.0 * r12
                        * ((1.0 + nu)
                            / (r12 * (7.0 + 12.0 * nu + 4.0 * nu * nu)
                                + 4.0 * r2 * (5.0 + 6.0 * nu + 2.0 * nu * nu)))
                }
                ShearCoefficient::Cowper => {
                    6.0 * r12 * ((1.0 + nu) / (r12 * (7.0 + 6.0 * nu) + r2 * (20.0 + 12.0 * nu)))
                }
            };
            phi = 12.0 * self.material.e_pa * ie / (self.material.g_pa * kappa * a * l * l);
        }
        Section {
            a_l,
            a,
            ie_l,
            ie,
            phi,
            a1,
            a2,
            b1,
            b2,
            gama,
            delta,
        }
    }

    /// Mass matrix (translational and, if set, rotary inertia).
    pub fn mass(&self) -> Mat8 {
        let s = self.section();
        let (phi, l, a1, b1) = (s.phi, self.length_m, s.a1, s.b1);
        let p2 = phi * phi;
        let m1 = (468.0 + 882.0 * phi + 420.0 * p2)
            + a1 * (108.0 + 210.0 * phi + 105.0 * p2)
            + b1 * (38.0 + 78.0 * phi + 42.0 * p2);
        let m2 = ((66.0 + 115.5 * phi + 52.5 * p2)
            + a1 * (21.0 + 40.5 * phi + 21.0 * p2)
            + b1 * (8.5 + 18.0 * phi + 10.5 * p2))
            * l;
        let m3 = (162.0 + 378.0 * phi + 210.0 * p2)
            + a1 * (81.0 + 189.0 * phi + 105.0 * p2)
            + b1 * (46.0 + 111.0 * phi + 63.0 * p2);
        let m4 = ((39.0 + 94.5 * phi + 52.5 * p2)
            + a1 * (18.0 + 40.5 * phi + 21.0 * p2)
            + b1 * (9.5 + 21.0 * phi + 10.5 * p2))
            * l;
        let m5 = ((12.0 + 21.0 * phi + 10.5 * p2)
            + a1 * (4.5 + 9.0 * phi + 5.25 * p2)
            + b1 * (2.0 + 4.5 * phi + 3.0 * p2))
            * l
            * l;
        let m6 = ((39.0 + 94.5 * phi + 52.5 * p2)
            + a1 * (21.0 + 54.0 * phi + 31.5 * p2)
            + b1 * (12.5 + 34.5 * phi + 21.0 * p2))
            * l;
        let m7 = ((9.0 + 21.0 * phi + 10.5 * p2)
            + a1 * (4.5 + 10.5 * phi + 5.25 * p2)
            + b1 * (2.5 + 6.0 * phi + 3.0 * p2))
            * l
            * l;
        let m8 = (468.0 + 882.0 * phi + 420.0 * p2)
            + a1 * (360.0 + 672.0 * phi + 315.0 * p2)
            + b1 * (290.0 + 540.0 * phi + 252.0 * p2);
        let m9 = ((66.0 + 115.5 * phi + 52.5 * p2)
            + a1 * (45.0 + 75.0 * phi + 31.5 * p2)
            + b1 * (32.5 + 52.5 * phi + 21.0 * p2))
            * l;
        let m10 = ((12.0 + 21.0 * phi + 10.5 * p2)
            + a1 * (7.5 + 12.0 * phi + 5.25 * p2)
            + b1 * (5.0 + 7.5 * phi + 3.0 * p2))
            * l
            * l;
        #[rustfmt::skip]
        let mt = [
            [m1, 0.0, 0.0, m2, m3, 0.0, 0.0, -m4],
            [0.0, m1, -m2, 0.0, 0.0, m3, m4, 0.0],
            [0.0, -m2, m5, 0.0, 0.0, -m6, -m7, 0.0],
            [m2, 0.0, 0.0, m5, m6, 0.0, 0.0, -m7],
            [m3, 0.0, 0.0, m6, m8, 0.0, 0.0, -m9],
            [0.0, m3, -m6, 0.0, 0.0, m8, m9, 0.0],
            [0.0, m4, -m7, 0.0, 0.0, m9, m10, 0.0],
            [-m4, 0.0, 0.0, -m7, -m9, 0.0, 0.0, m10],
        ];
        let rho = self.material.rho_kg_m3;
        let mut m = scaled(&mt, rho * s.a_l * l / (1260.0 * (1.0 + phi).powi(2)));
        if self.rotary_inertia {
            let (m11, m12, m13, m14, m15, m16) = rotary_terms(&s, l);
            #[rustfmt::skip]
            let mr = [
                [m11, 0.0, 0.0, m12, -m11, 0.0, 0.0, m13],
                [0.0, m11, -m12, 0.0, 0.0, -m11, -m13, 0.0],
                [0.0, -m12, m14, 0.0, 0.0, m12, -m15, 0.0],
                [m12, 0.0, 0.0, m14, -m12, 0.0, 0.0, -m15],
                [-m11, 0.0, 0.0, -m12, m11, 0.0, 0.0, -m13],
                [0.0, -m11, m12, 0.0, 0.0, m11, m13, 0.0],
                [0.0, -m13, -m15, 0.0, 0.0, m13, m16, 0.0],
                [m13, 0.0, 0.0, -m15, -m13, 0.0, 0.0, m16],
            ];
            add_scaled(
                &mut m,
                &mr,
                rho * s.ie_l / (210.0 * l * (1.0 + phi).powi(2)),
            );
        }
        m
    }

    /// Stiffness matrix (bending and shear; the axial force's and the torque's lateral terms).
    pub fn stiffness(&self) -> Mat8 {
        let s = self.section();
        let (l, phi) = (self.length_m, s.phi);
        let (a1, a2, b1, b2, gama, delta) = (s.a1, s.a2, s.b1, s.b2, s.gama, s.delta);
        let p2 = phi * phi;
        let k1 = 1260.0 + 630.0 * a2 + 504.0 * b2 + 441.0 * gama + 396.0 * delta;
        let k2 = (630.0 + 210.0 * a2 + 147.0 * b2 + 126.0 * gama + 114.0 * delta
            - phi * (105.0 * a2 + 105.0 * b2 + 94.5 * gama + 84.0 * delta))
            * l;
        let k3 = (630.0
            + 420.0 * a2
            + 357.0 * b2
            + 315.0 * gama
            + 282.0 * delta
            + phi * (105.0 * a2 + 105.0 * b2 + 94.5 * gama + 84.0 * delta))
            * l;
        let k4 = (420.0
            + 210.0 * phi
            + 105.0 * p2
            + a2 * (105.0 + 52.5 * p2)
            + b2 * (56.0 - 35.0 * phi + 35.0 * p2)
            + gama * (42.0 - 42.0 * phi + 26.25 * p2)
            + delta * (36.0 - 42.0 * phi + 21.0 * p2))
            * l
            * l;
        let k5 = (210.0 - 210.0 * phi - 105.0 * p2
            + a2 * (105.0 - 105.0 * phi - 52.5 * p2)
            + b2 * (91.0 - 70.0 * phi - 35.0 * p2)
            + gama * (84.0 - 52.5 * phi - 26.25 * p2)
            + delta * (78.0 - 42.0 * phi - 21.0 * p2))
            * l
            * l;
        let k6 = (420.0
            + 210.0 * phi
            + 105.0 * p2
            + a2 * (315.0 + 210.0 * phi + 52.5 * p2)
            + b2 * (266.0 + 175.0 * phi + 35.0 * p2)
            + gama * (231.0 + 147.0 * phi + 26.25 * p2)
            + delta * (204.0 + 126.0 * phi + 21.0 * p2))
            * l
            * l;
        let k7 = 12.0 + 6.0 * a1 + 4.0 * b1;
        let k8 = (6.0 + 3.0 * a1 + 2.0 * b1) * l;
        let k9 = (3.0 + 1.5 * a1 + b1) * l * l;
        #[rustfmt::skip]
        let kb = [
            [k1, 0.0, 0.0, k2, -k1, 0.0, 0.0, k3],
            [0.0, k1, -k2, 0.0, 0.0, -k1, -k3, 0.0],
            [0.0, -k2, k4, 0.0, 0.0, k2, k5, 0.0],
            [k2, 0.0, 0.0, k4, -k2, 0.0, 0.0, k5],
            [-k1, 0.0, 0.0, -k2, k1, 0.0, 0.0, -k3],
            [0.0, -k1, k2, 0.0, 0.0, k1, k3, 0.0],
            [0.0, -k3, k5, 0.0, 0.0, k3, k6, 0.0],
            [k3, 0.0, 0.0, k5, -k3, 0.0, 0.0, k6],
        ];
        #[rustfmt::skip]
        let ks = [
            [k7, 0.0, 0.0, k8, -k7, 0.0, 0.0, k8],
            [0.0, k7, -k8, 0.0, 0.0, -k7, -k8, 0.0],
            [0.0, -k8, k9, 0.0, 0.0, k8, k9, 0.0],
            [k8, 0.0, 0.0, k9, -k8, 0.0, 0.0, k9],
            [-k7, 0.0, 0.0, -k8, k7, 0.0, 0.0, -k8],
            [0.0, -k7, k8, 0.0, 0.0, k7, k8, 0.0],
            [0.0, -k8, k9, 0.0, 0.0, k8, k9, 0.0],
            [k8, 0.0, 0.0, k9, -k8, 0.0, 0.0, k9],
        ];
        let scale = self.material.e_pa / (l.powi(3) * (1.0 + phi).powi(2));
        let mut k = scaled(&kb, scale * s.ie_l / 105.0);
        add_scaled(&mut k, &ks, scale * s.ie * phi * s.a_l / s.a);
        if self.axial_force_n != 0.0 {
            let k10 = 36.0 + 60.0 * phi + 30.0 * p2;
            let k11 = 3.0 * l;
            let k12 = (4.0 + 5.0 * phi + 2.5 * p2) * l * l;
            let k13 = (1.0 + 5.0 * phi + 2.5 * p2) * l * l;
            #[rustfmt::skip]
            let kaf = [
                [k10, 0.0, 0.0, k11, -k10, 0.0, 0.0, k11],
                [0.0, k10, -k11, 0.0, 0.0, -k10, -k11, 0.0],
                [0.0, -k11, k12, 0.0, 0.0, k11, -k13, 0.0],
                [k11, 0.0, 0.0, k12, -k11, 0.0, 0.0, -k13],
                [-k10, 0.0, 0.0, -k11, k10, 0.0, 0.0, -k11],
                [0.0, -k10, k11, 0.0, 0.0, k10, k11, 0.0],
                [0.0, -k11, -k13, 0.0, 0.0, k11, k12, 0.0],
                [k11, 0.0, 0.0, -k13, -k11, 0.0, 0.0, k12],
            ];
            add_scaled(
                &mut k,
                &kaf,
                self.axial_force_n / (30.0 * l * (1.0 + phi).powi(2)),
            );
        }
        if self.torque_n_m != 0.0 {
            let h = l / 2.0;
            #[rustfmt::skip]
            let ktq = [
                [0.0, 0.0, 1.0, 0.0, 0.0, 0.0, -1.0, 0.0],
                [0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, -1.0],
                [1.0, 0.0, 0.0, -h, -1.0, 0.0, 0.0, h],
                [0.0, 1.0, h, 0.0, 0.0, -1.0, -h, 0.0],
                [0.0, 0.0, -1.0, 0.0, 0.0, 0.0, 1.0, 0.0],
                [0.0, 0.0, 0.0, -1.0, 0.0, 0.0, 0.0, 1.0],
                [-1.0, 0.0, 0.0, -h, 1.0, 0.0, 0.0, h],
                [0.0, -1.0, h, 0.0, 0.0, 1.0, -h, 0.0],
            ];
            add_scaled(&mut k, &ktq, self.torque_n_m / l);
        }
        k
    }

    /// Gyroscopic matrix G (the equations carry Omega G q'); skew-symmetric.
    pub fn gyroscopic(&self) -> Mat8 {
        if !self.gyroscopic {
            return [[0.0; 8]; 8];
        }
        let s = self.section();
        let l = self.length_m;
        let (g1, g2, g3, g4, g5, g6) = rotary_terms(&s, l);
        #[rustfmt::skip]
        let g = [
            [0.0, g1, -g2, 0.0, 0.0, -g1, -g3, 0.0],
            [-g1, 0.0, 0.0, -g2, g1, 0.0, 0.0, -g3],
            [g2, 0.0, 0.0, g4, -g2, 0.0, 0.0, -g5],
            [0.0, g2, -g4, 0.0, 0.0, -g2, g5, 0.0],
            [0.0, -g1, g2, 0.0, 0.0, g1, g3, 0.0],
            [g1, 0.0, 0.0, g2, -g1, 0.0, 0.0, g3],
            [g3, 0.0, 0.0, -g5, -g3, 0.0, 0.0, g6],
            [0.0, g3, g5, 0.0, 0.0, -g3, -g6, 0.0],
        ];
        scaled(
            &g,
            self.material.rho_kg_m3 * s.ie_l * 2.0 / (210.0 * l * (1.0 + s.phi).powi(2)),
        )
    }

    /// Damping matrix alpha M + beta K.
    pub fn damping(&self) -> Mat8 {
        let mut c = [[0.0; 8]; 8];
        if self.alpha_1_s != 0.0 {
            add_scaled(&mut c, &self.mass(), self.alpha_1_s);
        }
        if self.beta_s != 0.0 {
            add_scaled(&mut c, &self.stiffness(), self.beta_s);
        }
        c
    }
}

/// The rotary-inertia coefficients, shared by the rotary mass matrix and the gyroscopic matrix.
fn rotary_terms(s: &Section, l: f64) -> (f64, f64, f64, f64, f64, f64) {
    let (phi, a2, b2, gama, delta) = (s.phi, s.a2, s.b2, s.gama, s.delta);
    let p2 = phi * phi;
    let t1 = 252.0 + 126.0 * a2 + 72.0 * b2 + 45.0 * gama + 30.0 * delta;
    let t2 = (21.0 - 105.0 * phi
        + a2 * (21.0 - 42.0 * phi)
        + b2 * (15.0 - 21.0 * phi)
        + gama * (10.5 - 12.0 * phi)
        + delta * (7.5 - 7.5 * phi))
        * l;
    let t3 = (21.0
        - 105.0 * phi
        - 63.0 * a2 * phi
        - b2 * (6.0 + 42.0 * phi)
        - gama * (7.5 + 30.0 * phi)
        - delta * (7.5 + 22.5 * phi))
        * l;
    let t4 = (28.0
        + 35.0 * phi
        + 70.0 * p2
        + a2 * (7.0 - 7.0 * phi + 17.5 * p2)
        + b2 * (4.0 - 7.0 * phi + 7.0 * p2)
        + gama * (2.75 - 5.0 * phi + 3.5 * p2)
        + delta * (2.0 - 3.5 * phi + 2.0 * p2))
        * l
        * l;
    let t5 = (7.0 + 35.0 * phi - 35.0 * p2
        + a2 * (3.5 + 17.5 * phi - 17.5 * p2)
        + b2 * (3.0 + 10.5 * phi - 10.5 * p2)
        + gama * (2.75 + 7.0 * phi - 7.0 * p2)
        + delta * (2.5 + 5.0 * phi - 5.0 * p2))
        * l
        * l;
    let t6 = (28.0
        + 35.0 * phi
        + 70.0 * p2
        + a2 * (21.0 + 42.0 * phi + 52.5 * p2)
        + b2 * (18.0 + 42.0 * phi + 42.0 * p2)
        + gama * (16.25 + 40.0 * phi + 35.0 * p2)
        + delta * (15.0 + 37.5 * phi + 30.0 * p2))
        * l
        * l;
    (t1, t2, t3, t4, t5, t6)
}

fn scaled(a: &Mat8, s: f64) -> Mat8 {
    a.map(|row| row.map(|v| v * s))
}

fn add_scaled(acc: &mut Mat8, a: &Mat8, s: f64) {
    for (r, ar) in acc.iter_mut().zip(a) {
        for (v, av) in r.iter_mut().zip(ar) {
            *v += av * s;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// ROSS's own doctest values for its conical element (L = 0.5, id 0.05, od 0.1 -> 0.15,
    /// steel): the lateral entries of M, K and G.
    #[test]
    fn conical_element_matches_ross_doctests() {
        let mut e = ShaftElement::cylinder(0.5, 0.05, 0.1, Material::steel());
        e.od_right_m = 0.15;
        let (m, k, g) = (e.mass(), e.stiffness(), e.gyroscopic());
        let close = |a: f64, b: f64, tol: f64| (a - b).abs() <= tol;
        // M[:6,:6] lateral: x0 row (11.369864, beta0 0.861976), alpha0 0.086675.
        assert!(close(m[0][0], 11.369864, 1e-6), "{}", m[0][0]);
        assert!(close(m[0][3], 0.861976, 1e-6), "{}", m[0][3]);
        assert!(close(m[1][2], -0.861976, 1e-6));
        assert!(close(m[2][2], 0.086675, 1e-6));
        // K[:6,:6]/1e6: 219.9614, 41.2975, 12.2353.
        assert!(close(k[0][0] / 1e6, 219.9614, 1e-4), "{}", k[0][0] / 1e6);
        assert!(close(k[0][3] / 1e6, 41.2975, 1e-4));
        assert!(close(k[2][2] / 1e6, 12.2353, 1e-4));
        // G[:6,:6]: 0.309408, -0.010859, 0.006721.
        assert!(close(g[0][1], 0.309408, 1e-6), "{}", g[0][1]);
        assert!(close(g[0][2], -0.010859, 1e-6));
        assert!(close(g[2][3], 0.006721, 1e-6));
    }

    #[test]
    fn matrices_are_symmetric_and_gyroscopic_skew() {
        let mut e = ShaftElement::cylinder(0.3, 0.02, 0.08, Material::steel());
        e.od_right_m = 0.06;
        e.axial_force_n = 1e4;
        let (m, k, g) = (e.mass(), e.stiffness(), e.gyroscopic());
        for i in 0..8 {
            for j in 0..8 {
                let tol = |a: &Mat8| 1e-12 * a[i][i].abs().max(a[j][j].abs()).max(1e-30);
                assert!((m[i][j] - m[j][i]).abs() <= tol(&m), "M {i} {j}");
                assert!((k[i][j] - k[j][i]).abs() <= tol(&k), "K {i} {j}");
                assert!((g[i][j] + g[j][i]).abs() <= 1e-15, "G {i} {j}");
            }
        }
    }

    /// The centre of mass of a cone frustum: at h (R^2 + 2 R r + 3 r^2) / (4 (R^2 + R r + r^2))
    /// from the end of radius R; half way for a cylinder; a hollow one is the difference.
    #[test]
    fn mass_centre_of_cylinders_and_cones() {
        let c = ShaftElement::cylinder(0.4, 0.01, 0.05, Material::steel());
        assert!((c.mass_center_m() - 0.2).abs() < 1e-15);
        let mut cone = ShaftElement::cylinder(0.3, 0.0, 0.04, Material::steel());
        cone.od_right_m = 0.0;
        // A full cone from radius 0.02 to 0: its centre of mass a quarter of the way.
        assert!(
            (cone.mass_center_m() - 0.075).abs() < 1e-15,
            "{}",
            cone.mass_center_m()
        );
    }

    /// Translational mass: a rigid translation of the element in x moves its whole mass.
    #[test]
    fn rigid_translation_carries_the_element_mass() {
        let mut e = ShaftElement::cylinder(0.4, 0.01, 0.05, Material::steel());
        e.od_right_m = 0.07;
        e.rotary_inertia = false;
        let m = e.mass();
        let u = [1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0];
        let mut um = 0.0;
        for i in 0..8 {
            for j in 0..8 {
                um += u[i] * m[i][j] * u[j];
            }
        }
        assert!(
            (um - e.mass_kg()).abs() <= 1e-12 * um,
            "{um} {}",
            e.mass_kg()
        );
        // A rigid translation stores no strain energy.
        let k = e.stiffness();
        let f: Vec<f64> = (0..8)
            .map(|i| (0..8).map(|j| k[i][j] * u[j]).sum())
            .collect();
        assert!(f.iter().all(|v| v.abs() <= 1e-6 * k[0][0]), "{f:?}");
    }
}
