//! The rotor side of the linear analysis, behind one trait: the paper's rigid rotor
//! (`fmu_rotor::RotorParams`) or a flexible rotor (`FlexibleRotor`, shaft elements from a ROSS
//! file) in the same two air ring bearings. The equilibrium needs each journal's load and each
//! ring's mount; the Campbell iteration needs the modes with given film coefficients.

use fmu_rotor::linear::{lateral_matrices, Whirl};
use fmu_rotor::{FilmCoefficients, RotorParams};
use shaft::{Matrices, Ring, ShaftModel};
use std::f64::consts::TAU;

/// A rotor in two air ring bearings [C, T], linearized.
pub trait LinearRotor: Sync {
    /// A mode as the rotor's model gives it.
    type Mode: Clone;
    /// Film forces on the journals [N] that hold the rotor's weight [C, T], each (x, y).
    fn journal_loads_n(&self) -> [[f64; 2]; 2];
    /// Ring mount stiffness [N/m] and ring mass [kg] of bearing `i` (0 = C, 1 = T).
    fn mount(&self, i: usize) -> (f64, f64);
    fn g_m_s2(&self) -> f64;
    /// Oscillating modes (Im > 0) by frequency, the films [C, T] at the given coefficients.
    fn modes(
        &self,
        omega_rad_s: f64,
        films: &[FilmCoefficients; 2],
    ) -> Result<Vec<Self::Mode>, String>;
    /// Real eigenvalues [1/s] with the given film coefficients.
    fn real_eigenvalues(
        &self,
        omega_rad_s: f64,
        films: &[FilmCoefficients; 2],
    ) -> Result<Vec<f64>, String>;
    fn freq_hz(m: &Self::Mode) -> f64;
    /// (Re, Im) of the eigenvalue [1/s].
    fn eigenvalue(m: &Self::Mode) -> (f64, f64);
    fn damping_ratio(m: &Self::Mode) -> f64;
    fn forward(m: &Self::Mode) -> bool;
    /// What moves in the mode, in words.
    fn describe(m: &Self::Mode) -> String;
    /// Modes above this frequency at the start of the iteration [Hz] are left out (a flexible
    /// rotor's high bending modes, far above any whirl of interest); None: all.
    fn mode_cap_hz(&self) -> Option<f64> {
        None
    }
}

impl LinearRotor for RotorParams {
    type Mode = fmu_rotor::linear::Mode;
    fn journal_loads_n(&self) -> [[f64; 2]; 2] {
        super::equilibrium::journal_loads_n(self)
    }
    fn mount(&self, i: usize) -> (f64, f64) {
        if i == 0 {
            (self.c_c_n_m, self.m_r_c_kg)
        } else {
            (self.c_t_n_m, self.m_r_t_kg)
        }
    }
    fn g_m_s2(&self) -> f64 {
        self.g_m_s2
    }
    fn modes(
        &self,
        omega_rad_s: f64,
        films: &[FilmCoefficients; 2],
    ) -> Result<Vec<Self::Mode>, String> {
        let lm = lateral_matrices(self, omega_rad_s, films);
        fmu_rotor::linear::modes(&lm).map_err(|e| e.to_string())
    }
    fn real_eigenvalues(
        &self,
        omega_rad_s: f64,
        films: &[FilmCoefficients; 2],
    ) -> Result<Vec<f64>, String> {
        fmu_rotor::linear::real_eigenvalues(&lateral_matrices(self, omega_rad_s, films))
            .map_err(|e| e.to_string())
    }
    fn freq_hz(m: &Self::Mode) -> f64 {
        m.freq_hz
    }
    fn eigenvalue(m: &Self::Mode) -> (f64, f64) {
        (m.eigenvalue.re, m.eigenvalue.im)
    }
    fn damping_ratio(m: &Self::Mode) -> f64 {
        m.damping_ratio
    }
    fn forward(m: &Self::Mode) -> bool {
        m.whirl == Whirl::Forward
    }
    fn describe(m: &Self::Mode) -> String {
        m.shape.describe()
    }
}

/// A flexible rotor in two air ring bearings: the shaft model with a ring at each bearing node,
/// its matrices assembled once without the films; each evaluation adds the films' coefficients
/// between journal node and ring.
pub struct FlexibleRotor {
    pub model: ShaftModel,
    base: Matrices,
    /// First coordinate (x) of each journal node and each ring [C, T].
    journal: [usize; 2],
    ring: [usize; 2],
    loads: [[f64; 2]; 2],
    mounts: [(f64, f64); 2],
    g_m_s2: f64,
    /// See `LinearRotor::mode_cap_hz`.
    pub cap_hz: f64,
}

/// A mode of the flexible rotor with its description (what moves).
#[derive(Clone, Debug)]
pub struct FlexibleMode {
    pub mode: shaft::Mode,
    pub description: String,
}

impl FlexibleRotor {
    /// The model `model` (no supports of its own: two air ring bearings carry it) with rings at
    /// `nodes` [C, T]; ring mass, mount stiffness and damping of each from `rings` [C, T]
    /// as (m_R [kg], c [N/m], d [N s/m]); gravity `g_m_s2` downwards.
    pub fn new(
        mut model: ShaftModel,
        nodes: [usize; 2],
        rings: [(f64, f64, f64); 2],
        g_m_s2: f64,
    ) -> Result<Self, String> {
        if let Some(s) = model.supports.first() {
            return Err(format!(
                "the rotor file has linear bearings away from the air ring bearings ({:?} at node \
                 {}, {} in all): the stability analysis carries the rotor on its two air ring \
                 bearings only; remove them from the file",
                s.tag,
                s.node,
                model.supports.len()
            ));
        }
        if nodes[0] == nodes[1] {
            return Err(format!(
                "--bearing-nodes names node {} twice: bearings C and T need nodes of their own",
                nodes[0]
            ));
        }
        for (&node, side) in nodes.iter().zip(["C", "T"]) {
            if node >= model.n_nodes() {
                return Err(format!(
                    "--bearing-nodes: bearing {side} at node {node}, off the shaft (nodes 0 to {})",
                    model.n_nodes() - 1
                ));
            }
        }
        model.rings = nodes
            .iter()
            .zip(rings)
            .zip(["C", "T"])
            .map(|((&node, (m, c, d)), side)| Ring {
                node,
                mass_kg: m,
                mount_k_n_m: c,
                mount_c_n_s_m: d,
                film_k_n_m: [[0.0; 2]; 2],
                film_c_n_s_m: [[0.0; 2]; 2],
                tag: side.into(),
            })
            .collect();
        model.validate().map_err(|e| e.to_string())?;
        let z = model.node_z_m();
        let (zc, zt) = (z[nodes[0]], z[nodes[1]]);
        let z_cm = model.mass_center_m();
        let w = model.mass_kg() * g_m_s2;
        // Two supports: force and moment balance give each journal's share of the weight.
        let (a_c, a_t) = (zc - z_cm, zt - z_cm);
        let loads = [[0.0, -a_t * w / (a_c - a_t)], [0.0, a_c * w / (a_c - a_t)]];
        let base = model.matrices();
        Ok(FlexibleRotor {
            journal: nodes.map(|n| shaft::DOF_PER_NODE * n),
            ring: [model.ring_dof(0), model.ring_dof(1)],
            base,
            model,
            loads,
            mounts: [(rings[0].1, rings[0].0), (rings[1].1, rings[1].0)],
            g_m_s2,
            cap_hz: f64::INFINITY,
        })
    }

    fn matrices(&self, films: &[FilmCoefficients; 2]) -> Matrices {
        let mut mm = self.base.clone();
        for (i, f) in films.iter().enumerate() {
            mm.add_film(self.journal[i], self.ring[i], &f.k_n_m, &f.d_n_s_m);
        }
        mm
    }

    /// The synchronous response to an imbalance `me_kg_m` at `node` (phase `phase_rad`) spinning at
    /// `omega_rad_s`, the films at the given coefficients: the complex amplitudes (x, y) of the
    /// journals and rings [C, T].
    pub fn synchronous_response(
        &self,
        omega_rad_s: f64,
        films: &[FilmCoefficients; 2],
        node: usize,
        me_kg_m: f64,
        phase_rad: f64,
    ) -> Result<[[shaft::eigen::C64; 2]; 4], String> {
        let q = shaft::modal::unbalance_response_of(
            &self.matrices(films),
            node,
            me_kg_m,
            phase_rad,
            omega_rad_s,
        )
        .map_err(|e| e.to_string())?;
        let at = |i: usize| [q[i], q[i + 1]];
        Ok([
            at(self.journal[0]),
            at(self.journal[1]),
            at(self.ring[0]),
            at(self.ring[1]),
        ])
    }

    fn describe(&self, m: &shaft::Mode) -> String {
        let size = |x: usize| fmu_rotor::forced::semi_major_axis(&[m.shape[x], m.shape[x + 1]]);
        let nodes: Vec<f64> = (0..self.model.n_nodes())
            .map(|k| size(shaft::DOF_PER_NODE * k))
            .collect();
        let rings = [size(self.ring[0]), size(self.ring[1])];
        let big = nodes
            .iter()
            .chain(&rings)
            .copied()
            .fold(0.0, f64::max)
            .max(1e-300);
        let (k_max, _) =
            nodes.iter().enumerate().fold(
                (0, 0.0),
                |acc, (k, v)| if *v > acc.1 { (k, *v) } else { acc },
            );
        let z = self.model.node_z_m();
        let jc = nodes[self.journal[0] / shaft::DOF_PER_NODE] / big;
        let jt = nodes[self.journal[1] / shaft::DOF_PER_NODE] / big;
        format!(
            "|J_C|={jc:.3} |J_T|={jt:.3} |R_C|={:.3} |R_T|={:.3}: {} mode, largest shaft orbit \
             at node {k_max} (z = {:.0} mm)",
            rings[0] / big,
            rings[1] / big,
            if rings[0].max(rings[1]) > jc.max(jt) * big {
                "ring"
            } else {
                "rotor"
            },
            1e3 * z[k_max]
        )
    }
}

impl LinearRotor for FlexibleRotor {
    type Mode = FlexibleMode;
    fn journal_loads_n(&self) -> [[f64; 2]; 2] {
        self.loads
    }
    fn mount(&self, i: usize) -> (f64, f64) {
        self.mounts[i]
    }
    fn g_m_s2(&self) -> f64 {
        self.g_m_s2
    }
    fn modes(
        &self,
        omega_rad_s: f64,
        films: &[FilmCoefficients; 2],
    ) -> Result<Vec<Self::Mode>, String> {
        let ms = shaft::modal::modes_of(&self.matrices(films), omega_rad_s)
            .map_err(|e| e.to_string())?;
        Ok(ms
            .into_iter()
            .map(|mode| FlexibleMode {
                description: self.describe(&mode),
                mode,
            })
            .collect())
    }
    fn real_eigenvalues(
        &self,
        omega_rad_s: f64,
        films: &[FilmCoefficients; 2],
    ) -> Result<Vec<f64>, String> {
        shaft::modal::real_eigenvalues_of(&self.matrices(films), omega_rad_s)
            .map_err(|e| e.to_string())
    }
    fn freq_hz(m: &Self::Mode) -> f64 {
        m.mode.wd_rad_s / TAU
    }
    fn eigenvalue(m: &Self::Mode) -> (f64, f64) {
        (m.mode.eigenvalue.re, m.mode.eigenvalue.im)
    }
    fn damping_ratio(m: &Self::Mode) -> f64 {
        m.mode.damping_ratio
    }
    fn forward(m: &Self::Mode) -> bool {
        m.mode.whirl == shaft::Whirl::Forward
    }
    fn describe(m: &Self::Mode) -> String {
        m.description.clone()
    }
    fn mode_cap_hz(&self) -> Option<f64> {
        Some(self.cap_hz)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn rings() -> [(f64, f64, f64); 2] {
        [(0.05, 1e6, 50.0); 2]
    }

    /// The weight is shared by force and moment balance about the two bearing nodes.
    #[test]
    fn journal_loads_balance_the_weight_of_the_shaft_and_disks() {
        let p = RotorParams::paper();
        let mut model = crate::flexible::stiff_shaft_of(&p);
        model.elements[0].material.rho_kg_m3 = 7810.0;
        let r = FlexibleRotor::new(model.clone(), [2, 0], rings(), 9.81).unwrap();
        let [c, t] = r.journal_loads_n();
        let w = model.mass_kg() * 9.81;
        assert!((c[1] + t[1] - w).abs() < 1e-12 * w);
        let z = model.node_z_m();
        let zcm = model.mass_center_m();
        assert!((c[1] * (z[2] - zcm) + t[1] * (z[0] - zcm)).abs() < 1e-12 * w);
        // The heavier first element pulls the centre of mass towards T (node 0).
        assert!(t[1] > c[1] * (p.z_jc_m - p.z_cm_m) / (p.z_cm_m - p.z_jt_m));
    }

    #[test]
    fn bearings_of_the_file_and_bad_nodes_are_refused() {
        let p = RotorParams::paper();
        let mut model = crate::flexible::stiff_shaft_of(&p);
        let e = FlexibleRotor::new(model.clone(), [1, 1], rings(), 9.81)
            .err()
            .unwrap();
        assert!(e.contains("node 1 twice"), "{e}");
        let e = FlexibleRotor::new(model.clone(), [2, 3], rings(), 9.81)
            .err()
            .unwrap();
        assert!(
            e.contains("bearing T at node 3") && e.contains("0 to 2"),
            "{e}"
        );
        model.supports.push(shaft::Support {
            node: 1,
            k_n_m: [[1e6, 0.0], [0.0, 1e6]],
            c_n_s_m: [[0.0; 2]; 2],
            m_kg: [[0.0; 2]; 2],
            tag: "B".into(),
        });
        let e = FlexibleRotor::new(model, [2, 0], rings(), 9.81)
            .err()
            .unwrap();
        assert!(
            e.contains("\"B\" at node 1") && e.contains("remove them"),
            "{e}"
        );
    }
}
