//! A flexible rotor in the two air ring bearings: the shaft as Timoshenko beam elements (the
//! `shaft` crate: elements, disks, point masses, linear supports), reduced by Craig-Bampton
//! (`reduction.rs`), the two rings on their elastomer mounts, the air films' forces and the
//! journal-ring contact at the two bearing nodes, gravity, imbalances at nodes and the random
//! journal disturbance; integrated by variable-step BDF (`bdf.rs`).
//!
//! The equations, in the reduced coordinates q (the journals' x, y first, then the shaft's
//! modal and static-correction coordinates, then ring C x, y and ring T x, y):
//!
//!   M q'' + (C + Omega(t) G) q' + K q = f_gravity + f_imbalance(t) + B (F_film(t) + F_contact(q)
//!   + F_disturbance(t))
//!
//! with Omega(t) the prescribed speed (the speed table or ramp, as for the rigid rotor). The
//! terms of the angular acceleration (dOmega/dt times the polar inertia and the tilt) are left
//! out: the drive torque acts along the deformed axis and cancels them to first order, as the
//! rigid rotor's spin constraint on its body axis does.
//!
//! The same coupling interface as the rigid rotor: forces on the journals in, the journals'
//! displacement and velocity relative to their rings out. The paper's rigid rotor is the limit
//! of a stiff shaft with its mass properties (tests/flexible_rotor.rs).

pub mod bdf;
pub mod reduction;

use crate::disturbance::DisturbanceGrid;
use crate::params::{RotorError, RotorParams, SpeedProfile};
use crate::rotor::{BearingDerivatives, BearingOutputs, OutputDerivatives, RotorOutputs};
use crate::StepStats;
use bdf::{Bdf, BdfTolerances, Ode};
use reduction::Reduced;
use serde::{Deserialize, Serialize};
use shaft::{ShaftModel, DOF_PER_NODE};

/// The name of the file in the FMU's resources that makes `rotor.fmu` a flexible rotor.
pub const RESOURCE_FILE: &str = "shaft.json";

/// The reduction's error target: the cut-off is the lowest of [`CUTOFF_LADDER`] times the top
/// speed at which no natural frequency below 1.5 times the top speed (and at least up to 2 kHz)
/// moves by more than this (relative), reduced against full.
pub const REDUCTION_TARGET: f64 = 0.001;

/// Cut-offs tried, as multiples of the top speed (at least 1 kHz), lowest first. Without 4 to 8
/// times: modes kept there (8 to 16 kHz at 2000 Hz) lie where the integrator's steps in a 50 us
/// macro step (~17 us) neither resolve them cheaply nor damp them, and the films' force
/// changes at every macro step keep them ringing: a run-up of a 20-element shaft took 7.3 s
/// with modes to 8 kHz against 2.0 s to 4 kHz and 2.5 s to 20 kHz (the rigid rotor: 1.9 s).
pub const CUTOFF_LADDER: [f64; 5] = [2.0, 3.0, 10.0, 16.0, 24.0];

/// A reduction whose error exceeds this is refused (an explicit `cutoff_hz`, or the top of the
/// ladder).
pub const MAX_REDUCTION_ERROR: f64 = 0.005;

/// A flexible rotor as the FMU reads it from its resources (JSON).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct FlexibleSpec {
    /// The shaft from the turbine end (node 0 at z = 0); no rings (the rings are the FMU's
    /// parameters m_R_C, c_C, d_C, ...).
    pub shaft: ShaftModel,
    /// The nodes of bearing C (compressor side) and bearing T (turbine side).
    pub bearing_nodes: [usize; 2],
    /// Fixed-interface modes below this frequency are kept [Hz]; none: the lowest cut-off of the
    /// ladder that meets the error target.
    #[serde(default)]
    pub cutoff_hz: Option<f64>,
}

impl FlexibleSpec {
    pub fn validate(&self) -> Result<(), String> {
        self.shaft.validate().map_err(|e| e.to_string())?;
        if !self.shaft.rings.is_empty() {
            return Err(
                "the shaft's air ring bearings come from the FMU's parameters and its \
                        bearing_nodes: give no rings in the shaft"
                    .into(),
            );
        }
        let nodes = self.shaft.n_nodes();
        for (name, node) in ["C", "T"].iter().zip(self.bearing_nodes) {
            if node >= nodes {
                return Err(format!(
                    "bearing {name} is at node {node}, off the shaft (nodes 0 to {})",
                    nodes - 1
                ));
            }
        }
        if self.bearing_nodes[0] == self.bearing_nodes[1] {
            return Err(format!(
                "bearings C and T are both at node {}: each needs a node of its own",
                self.bearing_nodes[0]
            ));
        }
        if let Some(c) = self.cutoff_hz.filter(|c| !(c.is_finite() && *c > 0.0)) {
            return Err(format!(
                "cutoff_hz = {} must be a finite frequency > 0",
                bearing::num::Num(c)
            ));
        }
        Ok(())
    }
}

/// An imbalance at a node: the rotating force m e Omega^2 (and m e dOmega/dt) in the reduced
/// coordinates (x and y unit loads at its node).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
struct NodeImbalance {
    m_e_kg_m: f64,
    phase_rad: f64,
    /// M^-1 T^T e_x and M^-1 T^T e_y at the node.
    acc_x: Vec<f64>,
    acc_y: Vec<f64>,
    /// The centre of mass's shift [m] per newton in x and in y (the residual deflection).
    cm_per_n: [[f64; 2]; 2],
}

impl NodeImbalance {
    /// The rotating force on the shaft [N].
    fn force_n(&self, profile: &SpeedProfile, t: f64) -> [f64; 2] {
        let (omega, alpha) = (profile.rate_rad_s(t), profile.accel_rad_s2(t));
        let (s, c) = (profile.angle_rad(t) + self.phase_rad).sin_cos();
        [
            self.m_e_kg_m * (omega * omega * c + alpha * s),
            self.m_e_kg_m * (omega * omega * s - alpha * c),
        ]
    }
}

/// The reduced structure with the rings, as accelerations: a = -A_k q - (A_c + Omega A_g) v + ...
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
struct Structure {
    /// Reduced shaft coordinates (the rings follow).
    n_r: usize,
    n: usize,
    minv: Vec<f64>,
    a_k: Vec<f64>,
    a_c: Vec<f64>,
    a_g: Vec<f64>,
    /// M^-1 f_gravity.
    a_gravity: Vec<f64>,
    imbalances: Vec<NodeImbalance>,
    /// Centre of mass rows: cm_x = cm_rows[0] . q (and y), plus the residual sag under gravity.
    cm_rows: [Vec<f64>; 2],
    cm_gravity_m: [f64; 2],
    /// Axial position of the centre of mass [m] and the journals' [C, T].
    z_cm_m: f64,
    z_journal_m: [f64; 2],
}

impl Structure {
    fn ring(&self, k: usize) -> usize {
        self.n_r + 2 * k
    }
}

/// The flexible rotor simulator. Cloning or serializing and restoring it continues
/// bit-identically.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct FlexRotor {
    params: RotorParams,
    spec: FlexibleSpec,
    profile: SpeedProfile,
    st: Structure,
    integ: Bdf,
    /// What the reduction kept and its measured error.
    pub reduction: ReductionReport,
    #[serde(skip)]
    disturbance_grid: Option<DisturbanceGrid>,
}

/// What the reduction kept and how accurate it is.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct ReductionReport {
    pub full_dof: usize,
    pub reduced_dof: usize,
    pub kept_modes_hz: Vec<f64>,
    pub dropped_modes: usize,
    /// The cut-off used [Hz].
    pub cutoff_hz: f64,
    /// Largest relative error of the natural frequencies compared, and up to which frequency.
    pub frequency_error: f64,
    pub compared_up_to_hz: f64,
    pub frequencies_compared: usize,
}

fn mat_mul(n: usize, a: &[f64], b: &[f64]) -> Vec<f64> {
    let mut c = vec![0.0; n * n];
    for i in 0..n {
        for k in 0..n {
            let aik = a[i * n + k];
            if aik != 0.0 {
                for j in 0..n {
                    c[i * n + j] += aik * b[k * n + j];
                }
            }
        }
    }
    c
}

fn mat_vec(n: usize, a: &[f64], x: &[f64]) -> Vec<f64> {
    (0..n)
        .map(|i| (0..n).map(|j| a[i * n + j] * x[j]).sum())
        .collect()
}

fn invert(n: usize, a: &[f64]) -> Result<Vec<f64>, RotorError> {
    let lu = crate::linalg::Lu::factor(n, a.to_vec(), "the flexible rotor's mass matrix")?;
    let mut inv = vec![0.0; n * n];
    let mut col = vec![0.0; n];
    for j in 0..n {
        col.fill(0.0);
        col[j] = 1.0;
        lu.solve(&mut col);
        for i in 0..n {
            inv[i * n + j] = col[i];
        }
    }
    Ok(inv)
}

fn bad(what: String) -> RotorError {
    RotorError::InvalidInput(what)
}

impl FlexRotor {
    /// Centred, at rest, t = 0. `params` gives the rings, gravity, the speed, the imbalances
    /// (their z must be at nodes of the shaft), the contact, the disturbance and the tolerances;
    /// its rigid-body values (m, J_t, J_p, z_cm, z_JC, z_JT) are not used.
    pub fn new(params: RotorParams, spec: FlexibleSpec) -> Result<FlexRotor, RotorError> {
        params.validate()?;
        spec.validate().map_err(|e| bad(format!("shaft: {e}")))?;
        let mut shaft = spec.shaft.clone();
        let z_nodes = shaft.node_z_m();
        // The imbalance masses are point masses at their nodes (as on the rigid rotor).
        let mut imb_nodes = Vec::new();
        for (side, im) in ["C", "T"].iter().zip(&params.imbalance) {
            if im.mass_kg == 0.0 {
                continue;
            }
            let node = z_nodes
                .iter()
                .position(|z| (z - im.z_m).abs() <= 1e-6)
                .ok_or_else(|| {
                    bad(format!(
                        "z_imb_{side} = {} m is at no node of the shaft: the imbalance of a \
                         flexible rotor sits at a node (z from the shaft's first node: {} m); \
                         set z_imb_{side} to one of them",
                        bearing::num::Num(im.z_m),
                        z_nodes
                            .iter()
                            .map(|z| bearing::num::Num(*z).to_string())
                            .collect::<Vec<_>>()
                            .join(", ")
                    ))
                })?;
            shaft.point_masses.push(shaft::PointMass {
                node,
                mass_kg: im.mass_kg,
                tag: format!("imbalance {side}"),
            });
            imb_nodes.push((node, im.mass_kg * im.radius_m, im.phase_rad));
        }
        let load_nodes: Vec<usize> = imb_nodes.iter().map(|i| i.0).collect();
        let shaft_error = |e: String| bad(format!("shaft: {e}"));
        let analysis =
            reduction::analyse(&shaft, spec.bearing_nodes, &load_nodes).map_err(shaft_error)?;
        let top_hz = match params.speed_table.is_empty() {
            true => params.f_max_hz,
            false => params.speed_table.iter().map(|p| p.1).fold(0.0, f64::max),
        };
        let up_to = (1.5 * top_hz).max(2000.0);
        let k_ref = params.c_c_n_m.max(params.c_t_n_m).max(1e5);
        let full = reduction::full_frequencies_hz(&shaft, spec.bearing_nodes, k_ref)
            .map_err(shaft_error)?;
        let cutoffs: Vec<f64> = match spec.cutoff_hz {
            Some(c) => vec![c],
            None => CUTOFF_LADDER
                .iter()
                .map(|k| k * top_hz.max(1000.0))
                .collect(),
        };
        let mut chosen = None;
        for (i, &cutoff) in cutoffs.iter().enumerate() {
            let red = analysis.reduce(cutoff);
            let (err, compared) = red
                .frequency_error(&full, k_ref, up_to)
                .map_err(shaft_error)?;
            let last = i + 1 == cutoffs.len();
            if err <= REDUCTION_TARGET || (last && err <= MAX_REDUCTION_ERROR) {
                chosen = Some((cutoff, red, err, compared));
                break;
            }
            if last {
                return Err(bad(format!(
                    "shaft: the reduction to {} coordinates (modes below {} Hz) moves a natural \
                     frequency below {} Hz by {:.2} %, more than {:.1} %: {}",
                    red.n,
                    bearing::num::Num(cutoff),
                    bearing::num::Num(up_to),
                    100.0 * err,
                    100.0 * MAX_REDUCTION_ERROR,
                    if spec.cutoff_hz.is_some() {
                        "raise cutoff_hz"
                    } else {
                        "the shaft's modes converge too slowly; give a cutoff_hz"
                    }
                )));
            }
        }
        let (cutoff, red, err, compared) = chosen.expect("the last cut-off decides");
        let st = Self::structure(&params, &shaft, &spec, &red, &imb_nodes)?;
        let n = st.n;
        // Tolerances: a reduced coordinate's weight is its largest physical translation.
        let scale: Vec<f64> = (0..red.n)
            .map(|j| {
                (0..red.n_full)
                    .filter(|i| i % DOF_PER_NODE < 2)
                    .map(|i| red.basis[i * red.n + j].abs())
                    .fold(0.0, f64::max)
                    .max(1e-300)
            })
            .chain([1.0; 4])
            .collect();
        let atol: Vec<f64> = scale
            .iter()
            .map(|s| params.atol / s)
            .chain(scale.iter().map(|s| params.atol_vel / s))
            .collect();
        let tol = BdfTolerances {
            rtol: params.rtol,
            h_max_s: params.h_max_s,
            h_min_s: 1e-14,
            max_steps_per_call: params.max_steps_per_call,
        };
        let integ = Bdf::new(
            tol,
            atol,
            0.0,
            vec![0.0; 2 * n],
            1e-6_f64.min(params.h_max_s),
        );
        let reduction = ReductionReport {
            full_dof: red.n_full,
            reduced_dof: red.n,
            kept_modes_hz: red.kept_modes_hz.clone(),
            dropped_modes: red.dropped_modes,
            cutoff_hz: cutoff,
            frequency_error: err,
            compared_up_to_hz: up_to,
            frequencies_compared: compared,
        };
        Ok(FlexRotor {
            profile: SpeedProfile::of(&params),
            params,
            spec,
            st,
            integ,
            reduction,
            disturbance_grid: None,
        })
    }

    fn structure(
        p: &RotorParams,
        shaft: &ShaftModel,
        spec: &FlexibleSpec,
        red: &Reduced,
        imb_nodes: &[(usize, f64, f64)],
    ) -> Result<Structure, RotorError> {
        let (nr, n) = (red.n, red.n + 4);
        let embed = |a: &[f64]| {
            let mut out = vec![0.0; n * n];
            for i in 0..nr {
                out[i * n..i * n + nr].copy_from_slice(&a[i * nr..(i + 1) * nr]);
            }
            out
        };
        let (mut m, mut k, mut c) = (embed(&red.m), embed(&red.k), embed(&red.c));
        let g = embed(&red.g);
        for (ring, (m_r, c_r, d_r)) in [
            (p.m_r_c_kg, p.c_c_n_m, p.d_c_n_s_m),
            (p.m_r_t_kg, p.c_t_n_m, p.d_t_n_s_m),
        ]
        .into_iter()
        .enumerate()
        {
            for a in 0..2 {
                let i = nr + 2 * ring + a;
                m[i * n + i] = m_r;
                k[i * n + i] = c_r;
                c[i * n + i] = d_r;
            }
        }
        let minv = invert(n, &m)?;
        let nf = red.n_full;
        let nodes = shaft.n_nodes();
        // Gravity: -g in y on the shaft (consistent mass) and on the rings.
        let mut e_y = vec![0.0; nf];
        for node in 0..nodes {
            e_y[DOF_PER_NODE * node + 1] = 1.0;
        }
        let mm = shaft.matrices();
        let f_full: Vec<f64> = (0..nf)
            .map(|i| -p.g_m_s2 * (0..nf).map(|j| mm.m[i * nf + j] * e_y[j]).sum::<f64>())
            .collect();
        let mut f_g = red.load(&f_full);
        f_g.extend([0.0, -p.g_m_s2 * p.m_r_c_kg, 0.0, -p.g_m_s2 * p.m_r_t_kg]);
        let a_gravity = mat_vec(n, &minv, &f_g);
        let unit_acc = |node: usize, dir: usize| {
            let mut f = vec![0.0; nf];
            f[DOF_PER_NODE * node + dir] = 1.0;
            let mut fr = red.load(&f);
            fr.extend([0.0; 4]);
            mat_vec(n, &minv, &fr)
        };
        // Centre of mass: the momentum of a rigid translation, r^T M u / m.
        let total = shaft.mass_kg();
        let cm_of = |u: &[f64]| {
            [0, 1].map(|dir| {
                let mut s = 0.0;
                for i in (dir..nf).step_by(DOF_PER_NODE) {
                    s += (0..nf).map(|l| mm.m[i * nf + l] * u[l]).sum::<f64>();
                }
                s / total
            })
        };
        // Residuals: gravity x, y, then x, y at each load node in `imb_nodes`' order.
        let sag = cm_of(&red.residuals[1]);
        let cm_gravity_m = [-p.g_m_s2 * sag[0], -p.g_m_s2 * sag[1]];
        let imbalances = imb_nodes
            .iter()
            .enumerate()
            .map(|(k, &(node, m_e, phase))| NodeImbalance {
                m_e_kg_m: m_e,
                phase_rad: phase,
                acc_x: unit_acc(node, 0),
                acc_y: unit_acc(node, 1),
                cm_per_n: [
                    cm_of(&red.residuals[2 + 2 * k]),
                    cm_of(&red.residuals[3 + 2 * k]),
                ],
            })
            .collect();
        let cm_rows = [0, 1].map(|dir| {
            let mut row = vec![0.0; n];
            for j in 0..nr {
                let mut s = 0.0;
                for i in 0..nf {
                    if i % DOF_PER_NODE == dir && i < DOF_PER_NODE * nodes {
                        for l in 0..nf {
                            s += mm.m[i * nf + l] * red.basis[l * nr + j];
                        }
                    }
                }
                row[j] = s / total;
            }
            row
        });
        let z = shaft.node_z_m();
        Ok(Structure {
            n_r: nr,
            n,
            a_k: mat_mul(n, &minv, &k),
            a_c: mat_mul(n, &minv, &c),
            a_g: mat_mul(n, &minv, &g),
            minv,
            a_gravity,
            imbalances,
            cm_rows,
            cm_gravity_m,
            z_cm_m: shaft.mass_center_m(),
            z_journal_m: spec.bearing_nodes.map(|k| z[k]),
        })
    }

    pub fn params(&self) -> &RotorParams {
        &self.params
    }
    pub fn spec(&self) -> &FlexibleSpec {
        &self.spec
    }
    pub fn time_s(&self) -> f64 {
        self.integ.t()
    }
    pub fn totals(&self) -> &StepStats {
        &self.integ.totals
    }
    /// Coordinates of the structure (reduced shaft, then the rings' x, y).
    pub fn dof(&self) -> usize {
        self.st.n
    }

    /// Each coordinate's largest translation of a shaft node or ring per unit [m per unit]: the
    /// journals' and rings' 1, a mode's its largest node displacement (the error weights use
    /// it; so does a periodic-orbit search, for its typical magnitudes).
    pub fn coordinate_scales(&self) -> Vec<f64> {
        self.integ.atol[..self.st.n]
            .iter()
            .map(|a| self.params.atol / a)
            .collect()
    }

    /// The state a periodic-orbit search varies: the coordinates, then their rates.
    pub fn lateral_state(&self) -> Vec<f64> {
        self.integ.y().to_vec()
    }

    /// Starts again at the current time from `state` (as [`FlexRotor::lateral_state`] gives it),
    /// spinning at a constant `speed_hz` from t = 0 on; the integrator restarts at order 1.
    pub fn restart_constant_speed(
        &mut self,
        state: &[f64],
        speed_hz: f64,
    ) -> Result<(), RotorError> {
        if state.len() != 2 * self.st.n || state.iter().any(|v| !v.is_finite()) {
            return Err(bad(format!(
                "the state must be {} finite numbers",
                2 * self.st.n
            )));
        }
        let mut params = self.params.clone();
        let t = self.integ.t();
        params.speed_table = vec![(0.0, speed_hz), (t.max(0.0) + 1.0, speed_hz)];
        params.validate()?;
        self.profile = SpeedProfile::of(&params);
        self.params = params;
        self.integ.restart(state.to_vec());
        Ok(())
    }

    /// Integrate t0 -> t0 + h with the film forces `forces(t)` (as the rigid rotor's `advance`).
    pub fn advance(
        &mut self,
        t0_s: f64,
        h_s: f64,
        forces: &dyn Fn(f64) -> crate::BearingForces,
    ) -> Result<StepStats, RotorError> {
        let t = self.integ.t();
        if !t0_s.is_finite() || (t0_s - t).abs() > 1e-9 * t.abs().max(1e-3) {
            return Err(bad(format!(
                "advance from t0 = {t0_s} s but the rotor is at t = {t} s"
            )));
        }
        if !(h_s.is_finite() && h_s > 0.0) {
            return Err(bad(format!(
                "step size h = {h_s} s must be positive and finite"
            )));
        }
        let disturbance = match self.disturbance_grid.take() {
            Some(g) if g.disturbance() == self.params.disturbance => g,
            _ => DisturbanceGrid::new(self.params.disturbance),
        };
        let mut ode = FlexOde {
            st: &self.st,
            profile: &self.profile,
            contact: self.params.contact.as_ref(),
            forces,
            disturbance,
        };
        let r = self.integ.advance_to(&mut ode, t0_s + h_s);
        self.disturbance_grid = Some(ode.disturbance);
        r
    }

    fn bearing(&self, k: usize) -> BearingOutputs {
        let (y, n) = (self.integ.y(), self.st.n);
        let (j, r) = (2 * k, self.st.ring(k));
        let d = [y[j] - y[r], y[j + 1] - y[r + 1]];
        BearingOutputs {
            dx_m: d[0],
            dy_m: d[1],
            vx_m_s: y[n + j] - y[n + r],
            vy_m_s: y[n + j + 1] - y[n + r + 1],
            journal_m: [y[j], y[j + 1]],
            ring_m: [y[r], y[r + 1]],
            contact_n: match &self.params.contact {
                Some(b) => b[k].force_n(d),
                None => [0.0, 0.0],
            },
        }
    }

    pub fn outputs(&self) -> RotorOutputs {
        let (y, t) = (self.integ.y(), self.integ.t());
        let [zc, zt] = self.st.z_journal_m;
        let dz = zc - zt;
        let mut cm = [0, 1].map(|d| {
            let row = &self.st.cm_rows[d];
            row.iter().zip(y).map(|(a, b)| a * b).sum::<f64>() + self.st.cm_gravity_m[d]
        });
        for im in &self.st.imbalances {
            let f = im.force_n(&self.profile, t);
            for d in 0..2 {
                cm[d] += im.cm_per_n[0][d] * f[0] + im.cm_per_n[1][d] * f[1];
            }
        }
        RotorOutputs {
            t_s: t,
            bearing_c: self.bearing(0),
            bearing_t: self.bearing(1),
            omega_rad_s: self.profile.rate_rad_s(t),
            spin_angle_rad: self.profile.angle_rad(t),
            // The line through the journals: slope dx/dz is the Cardan beta, dy/dz is -alpha.
            tilt_x_rad: -(y[1] - y[3]) / dz,
            tilt_y_rad: (y[0] - y[2]) / dz,
            cm_m: [cm[0], cm[1], self.st.z_cm_m],
            drift_pos: 0.0,
            drift_vel: 0.0,
        }
    }

    pub fn output_derivatives(&self) -> OutputDerivatives {
        let (y, yd, n) = (self.integ.y(), self.integ.ydot(), self.st.n);
        let der = |k: usize| {
            let (j, r) = (2 * k, self.st.ring(k));
            BearingDerivatives {
                ddx_m_s: y[n + j] - y[n + r],
                ddy_m_s: y[n + j + 1] - y[n + r + 1],
                dvx_m_s2: yd[n + j] - yd[n + r],
                dvy_m_s2: yd[n + j + 1] - yd[n + r + 1],
            }
        };
        OutputDerivatives {
            bearing_c: der(0),
            bearing_t: der(1),
            domega_rad_s2: self.profile.accel_rad_s2(self.integ.t()),
        }
    }
}

/// The equations of one `advance` call.
struct FlexOde<'a> {
    st: &'a Structure,
    profile: &'a SpeedProfile,
    contact: Option<&'a [bearing::BoreContact; 2]>,
    forces: &'a dyn Fn(f64) -> crate::BearingForces,
    disturbance: DisturbanceGrid,
}

impl FlexOde<'_> {
    /// Adds M^-1 f for a force f at coordinates (i, i + 1).
    fn add_force(&self, acc: &mut [f64], i: usize, f: [f64; 2]) {
        let n = self.st.n;
        for (row, a) in acc.iter_mut().enumerate() {
            *a += self.st.minv[row * n + i] * f[0] + self.st.minv[row * n + i + 1] * f[1];
        }
    }
}

impl Ode for FlexOde<'_> {
    fn dim(&self) -> usize {
        2 * self.st.n
    }

    fn jacobian_parameter(&self, t: f64) -> f64 {
        self.profile.rate_rad_s(t)
    }

    fn rhs(&mut self, t: f64, y: &[f64], ydot: &mut [f64]) -> Result<(), RotorError> {
        let st = self.st;
        let n = st.n;
        let (q, v) = y.split_at(n);
        let omega = self.profile.rate_rad_s(t);
        ydot[..n].copy_from_slice(v);
        let acc = &mut ydot[n..];
        acc.copy_from_slice(&st.a_gravity);
        for i in 0..n {
            let (ak, ac, ag) = (
                &st.a_k[i * n..(i + 1) * n],
                &st.a_c[i * n..(i + 1) * n],
                &st.a_g[i * n..(i + 1) * n],
            );
            let mut s = 0.0;
            for j in 0..n {
                s += ak[j] * q[j] + (ac[j] + omega * ag[j]) * v[j];
            }
            acc[i] -= s;
        }
        for im in &st.imbalances {
            let [fx, fy] = im.force_n(self.profile, t);
            for i in 0..n {
                acc[i] += im.acc_x[i] * fx + im.acc_y[i] * fy;
            }
        }
        let f = (self.forces)(t);
        if !f.is_finite() {
            return Err(bad(format!("non-finite bearing force at t = {t} s: {f:?}")));
        }
        let dist = self.disturbance.forces_n(t);
        for (k, film) in [[f.fc_x_n, f.fc_y_n], [f.ft_x_n, f.ft_y_n]]
            .into_iter()
            .enumerate()
        {
            let (j, r) = (2 * k, st.ring(k));
            let mut on_journal = film;
            if let Some(b) = self.contact {
                let fc = b[k].force_n([q[j] - q[r], q[j + 1] - q[r + 1]]);
                on_journal = [film[0] + fc[0], film[1] + fc[1]];
            }
            self.add_force(acc, r, [-on_journal[0], -on_journal[1]]);
            let d = [dist[2 * k], dist[2 * k + 1]];
            self.add_force(acc, j, [on_journal[0] + d[0], on_journal[1] + d[1]]);
        }
        Ok(())
    }

    fn jacobian(&mut self, t: f64, y: &[f64], jac: &mut [f64]) -> Result<(), RotorError> {
        let st = self.st;
        let (n, nn) = (st.n, 2 * st.n);
        let omega = self.profile.rate_rad_s(t);
        jac.fill(0.0);
        for i in 0..n {
            jac[i * nn + n + i] = 1.0;
            for j in 0..n {
                jac[(n + i) * nn + j] = -st.a_k[i * n + j];
                jac[(n + i) * nn + n + j] = -(st.a_c[i * n + j] + omega * st.a_g[i * n + j]);
            }
        }
        if let Some(b) = self.contact {
            let q = &y[..n];
            for k in 0..2 {
                let (j, r) = (2 * k, st.ring(k));
                let d = [q[j] - q[r], q[j + 1] - q[r + 1]];
                let f0 = b[k].force_n(d);
                if f0 == [0.0, 0.0] {
                    let probe = b[k].force_n([d[0] * 1.001, d[1] * 1.001]);
                    if probe == [0.0, 0.0] {
                        continue;
                    }
                }
                // dF/dd by differences (the law depends on the relative displacement alone).
                let delta = 1e-9;
                let mut kc = [[0.0; 2]; 2];
                for c in 0..2 {
                    let mut dd = d;
                    dd[c] += delta;
                    let f1 = b[k].force_n(dd);
                    for a in 0..2 {
                        kc[a][c] = (f1[a] - f0[a]) / delta;
                    }
                }
                // Force on the journal +F, on the ring -F; d = q_j - q_r.
                for row in 0..n {
                    for c in 0..2 {
                        let dacc = st.minv[row * n + j] * kc[0][c]
                            + st.minv[row * n + j + 1] * kc[1][c]
                            - st.minv[row * n + r] * kc[0][c]
                            - st.minv[row * n + r + 1] * kc[1][c];
                        jac[(n + row) * nn + j + c] += dacc;
                        jac[(n + row) * nn + r + c] -= dacc;
                    }
                }
            }
        }
        Ok(())
    }
}

/// The rigid rotor `p` as a flexible one, for checks of the rigid limit: a light, very stiff
/// two-element shaft through the turbine journal (node 0), the centre of mass (node 1) and the
/// compressor journal (node 2), the rotor's mass and inertias as a disk at the centre of mass.
/// The shaft weighs 4e-5 of the rotor (density 1 kg/m^3) and is 1000 times as stiff as steel:
/// its own bending modes lie above 20 kHz. Node 0 sits at z_JT, so an imbalance's z is
/// measured from there.
pub fn stiff_shaft_of(p: &RotorParams) -> FlexibleSpec {
    let mut stiff = shaft::Material::steel();
    stiff.rho_kg_m3 = 1.0;
    stiff.e_pa *= 1e3;
    stiff.g_pa *= 1e3;
    FlexibleSpec {
        shaft: ShaftModel {
            elements: vec![
                shaft::ShaftElement::cylinder(p.z_cm_m - p.z_jt_m, 0.0, 0.02, stiff.clone()),
                shaft::ShaftElement::cylinder(p.z_jc_m - p.z_cm_m, 0.0, 0.02, stiff),
            ],
            disks: vec![shaft::Disk {
                node: 1,
                mass_kg: p.m_kg,
                id_kg_m2: p.j_t_kg_m2,
                ip_kg_m2: p.j_p_kg_m2,
                tag: "rotor".into(),
            }],
            ..Default::default()
        },
        bearing_nodes: [2, 0],
        cutoff_hz: None,
    }
}
