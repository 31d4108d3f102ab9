//! Gap of the lobed ring at the film's Gauss points: h, dh/dphi and dh/dt (MODEL.md section 3).
//!
//! The bore and its exact gap live in the `bearing` crate (`bearing::gap_m`); this is the same
//! h = C - dx cos(theta) - dy sin(theta) + dH (1 - s / phi_t), theta = phi + alpha, tabulated on
//! the mesh. dh/dt = -vx cos(theta) - vy sin(theta).
//!
//! Where the gap closes the Reynolds coefficients use h_r = max(h, h_floor) with
//! h_floor = max(h_con / 2, 1e-3 C): the film stays well-posed (p h^3 > 0) while the penalty
//! contact pressure (contact.rs), which starts at h_con > h_floor, carries the load there.

use crate::column_integrals::ColumnIntegrals;
use crate::mesh::Mesh;
use crate::node_functionals::NodeFunctionals;
use crate::params::BearingParams;
use crate::JournalState;
use serde::{Deserialize, Serialize};

/// Angle-only data at the phi-Gauss points of every block (fixed for a given mesh).
#[derive(Clone, Debug, Serialize, Deserialize)]
#[serde(from = "GeometryData", into = "GeometryData")]
pub struct Geometry {
    /// Gauss points along phi per block: 3 per element column.
    pub nq: usize,
    pub cos_q: Vec<f64>,
    pub sin_q: Vec<f64>,
    /// Step term dH/C (1 - s/phi_t) and its phi derivative.
    pub step_q: Vec<f64>,
    pub dstep_rel: f64,
    /// Floor of h/C used in the Reynolds coefficients.
    pub h_floor_rel: f64,
    /// The output integrals' functionals per phi-Gauss point (`column_integrals`).
    pub columns: ColumnIntegrals,
    /// The friction's pocket quadrature (`friction`): cos theta, sin theta and the weight of each
    /// point, so a call needs no trigonometry. Empty for a plain bore.
    pub pockets: Vec<[f64; 3]>,
    /// The force and the friction's pressure part as weights per node (`node_functionals`),
    /// derived from the tables above (not serialized: rebuilt when a state is read).
    pub nodal: NodeFunctionals,
}

/// The serialized form of [`Geometry`]: its fields before the node functionals, so saved states
/// read as before.
#[derive(Clone, Debug, Serialize, Deserialize)]
struct GeometryData {
    nq: usize,
    cos_q: Vec<f64>,
    sin_q: Vec<f64>,
    step_q: Vec<f64>,
    dstep_rel: f64,
    h_floor_rel: f64,
    columns: ColumnIntegrals,
    pockets: Vec<[f64; 3]>,
}

impl From<GeometryData> for Geometry {
    fn from(d: GeometryData) -> Geometry {
        let GeometryData {
            nq,
            cos_q,
            sin_q,
            step_q,
            dstep_rel,
            h_floor_rel,
            columns,
            pockets,
        } = d;
        // A state whose tables do not agree gets no node functionals; `AirFilm::check_layout`
        // then refuses it (never an index out of bounds here).
        let n = cos_q.len();
        let consistent = nq > 0
            && nq == columns.nq()
            && n % nq == 0
            && sin_q.len() == n
            && step_q.len() == n
            && columns.fits(nq, columns.nodes_per_block());
        let nodal = if consistent {
            NodeFunctionals::new(
                &columns,
                n / nq,
                columns.nodes_per_block(),
                &cos_q,
                &sin_q,
                &step_q,
            )
        } else {
            NodeFunctionals::default()
        };
        Geometry {
            nq,
            cos_q,
            sin_q,
            step_q,
            dstep_rel,
            h_floor_rel,
            columns,
            pockets,
            nodal,
        }
    }
}

impl From<Geometry> for GeometryData {
    fn from(g: Geometry) -> GeometryData {
        let Geometry {
            nq,
            cos_q,
            sin_q,
            step_q,
            dstep_rel,
            h_floor_rel,
            columns,
            pockets,
            nodal: _,
        } = g;
        GeometryData {
            nq,
            cos_q,
            sin_q,
            step_q,
            dstep_rel,
            h_floor_rel,
            columns,
            pockets,
        }
    }
}

/// Dimensionless gap H = h/C, dH/dphi and the time derivative dH/dt (1/s) at the phi-Gauss points.
#[derive(Clone, Debug, Default)]
pub struct GapField {
    pub h: Vec<f64>,
    pub h_phi: Vec<f64>,
    pub h_t: Vec<f64>,
}

impl Geometry {
    pub fn new(p: &BearingParams, mesh: &Mesh) -> Self {
        let nq = 3 * mesh.ne_phi;
        let n = mesh.n_blocks * nq;
        let (mut cos_q, mut sin_q, mut step_q) = (vec![0.0; n], vec![0.0; n], vec![0.0; n]);
        let step_rel = p.bore.dh_m / p.bore.c_m;
        let span = p.bore.block_span_rad();
        for k in 0..mesh.n_blocks {
            for col in 0..mesh.ne_phi {
                for qa in 0..3 {
                    let s = mesh.gauss_phi(col, qa);
                    let theta = mesh.block_phi0_rad[k] + s + p.bore.alpha_rad;
                    let i = k * nq + 3 * col + qa;
                    cos_q[i] = theta.cos();
                    sin_q[i] = theta.sin();
                    step_q[i] = step_rel * (1.0 - s / span);
                }
            }
        }
        let columns = ColumnIntegrals::new(mesh);
        let nodal =
            NodeFunctionals::new(&columns, mesh.n_blocks, mesh.npb, &cos_q, &sin_q, &step_q);
        Geometry {
            nq,
            cos_q,
            sin_q,
            step_q,
            dstep_rel: -step_rel / span,
            h_floor_rel: (0.5 * p.contact.h_con_rel).max(1e-3),
            columns,
            pockets: crate::friction::pocket_points(&p.bore),
            nodal,
        }
    }

    /// Fills `g` for the journal state `j`; `c_m` is the clearance.
    pub fn update(&self, j: &JournalState, c_m: f64, g: &mut GapField) {
        let n = self.cos_q.len();
        g.h.resize(n, 0.0);
        g.h_phi.resize(n, 0.0);
        g.h_t.resize(n, 0.0);
        let (ex, ey) = (j.dx_m / c_m, j.dy_m / c_m);
        let (ux, uy) = (j.vx_m_s / c_m, j.vy_m_s / c_m);
        for i in 0..n {
            let (c, s) = (self.cos_q[i], self.sin_q[i]);
            let h = 1.0 - ex * c - ey * s + self.step_q[i];
            if h > self.h_floor_rel {
                g.h[i] = h;
                g.h_phi[i] = ex * s - ey * c + self.dstep_rel;
                g.h_t[i] = -ux * c - uy * s;
            } else {
                g.h[i] = self.h_floor_rel;
                g.h_phi[i] = 0.0;
                g.h_t[i] = 0.0;
            }
        }
    }
}

pub use bearing::bore::{gap_m, lobe_minimum, min_gap_m, sampled_min_gap_m};
