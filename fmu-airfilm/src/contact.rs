//! Mixed-lubrication penalty contact (paper Section 2.2, MODEL.md section 3).
//!
//! Where h < h_con = h_con_rel C, a contact pressure p_con = c_con (h_con - h) acts on the journal.
//! It enters the force integral only (not the Reynolds equation). The gap does not depend on z,
//! so the axial integral is exact: F_con = -b r Int p_con(phi) (cos theta, sin theta) dphi over
//! the lobes (pockets are deeper than the lobes and never touch first). The kink of p_con at
//! h = h_con is resolved by 8 sub-intervals of 3-point Gauss per element column.

use crate::geometry::gap_m;
use crate::mesh::{GAUSS3_W, GAUSS3_X};
use crate::params::BearingParams;
use crate::JournalState;

const SUB: usize = 8;

/// Contact force on the journal (N), [Fx, Fy]. Zero when the gap is everywhere >= h_con.
pub fn contact_force_n(p: &BearingParams, j: &JournalState, h_min_m: f64) -> [f64; 2] {
    let h_con = p.h_con_rel * p.c_m;
    if h_min_m >= h_con || p.c_con_n_per_m3 == 0.0 {
        return [0.0, 0.0];
    }
    let span = p.block_span_rad();
    let n_int = p.n_elem_phi * SUB;
    let ds = span / n_int as f64;
    let mut f = [0.0, 0.0];
    for k in 0..p.n_blocks() {
        for i in 0..n_int {
            for q in 0..3 {
                let s = (i as f64 + 0.5 * (1.0 + GAUSS3_X[q])) * ds;
                let h = gap_m(p, k, s, j);
                if h < h_con {
                    let pc = p.c_con_n_per_m3 * (h_con - h);
                    let theta = p.block_start_rad(k) + s + p.alpha_rad;
                    let w = 0.5 * ds * GAUSS3_W[q] * pc;
                    f[0] -= w * theta.cos();
                    f[1] -= w * theta.sin();
                }
            }
        }
    }
    let scale = p.b_m * p.r_m;
    [f[0] * scale, f[1] * scale]
}
