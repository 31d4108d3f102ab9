//! Gap geometry of the lobed ring: h, dh/dphi and dh/dt (MODEL.md section 3).
//!
//! In lobe k (ring-fixed phi = k 2 pi / n + s, s in [0, phi_t]) the gap is
//! h = C - dx cos(theta) - dy sin(theta) + dH (1 - s / phi_t), theta = phi + alpha,
//! which equals MODEL.md's floor-function form. dh/dt = -vx cos(theta) - vy sin(theta).
//!
//! Where the gap closes the Reynolds coefficients use h_r = max(h, h_floor) with
//! h_floor = max(h_con / 2, 1e-3 C): the film stays well-posed (p h^3 > 0) while the penalty
//! contact pressure (contact.rs), which starts at h_con > h_floor, carries the load there.

use crate::mesh::Mesh;
use crate::params::BearingParams;
use crate::JournalState;
use serde::{Deserialize, Serialize};

/// Angle-only data at the phi-Gauss points of every block (fixed for a given mesh).
#[derive(Clone, Debug, Serialize, Deserialize)]
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
        let step_rel = p.dh_m / p.c_m;
        let span = p.block_span_rad();
        for k in 0..mesh.n_blocks {
            for col in 0..mesh.ne_phi {
                for qa in 0..3 {
                    let s = mesh.gauss_phi(col, qa);
                    let theta = mesh.block_phi0_rad[k] + s + p.alpha_rad;
                    let i = k * nq + 3 * col + qa;
                    cos_q[i] = theta.cos();
                    sin_q[i] = theta.sin();
                    step_q[i] = step_rel * (1.0 - s / span);
                }
            }
        }
        Geometry {
            nq,
            cos_q,
            sin_q,
            step_q,
            dstep_rel: -step_rel / span,
            h_floor_rel: (0.5 * p.h_con_rel).max(1e-3),
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

/// Exact gap h (m) at block-local angle `s_rad` of block `k` (no floor).
pub fn gap_m(p: &BearingParams, k: usize, s_rad: f64, j: &JournalState) -> f64 {
    let theta = p.block_start_rad(k) + s_rad + p.alpha_rad;
    let step = if p.plain_bore {
        0.0
    } else {
        p.dh_m * (1.0 - s_rad / p.phi_t_rad)
    };
    p.c_m - j.dx_m * theta.cos() - j.dy_m * theta.sin() + step
}

/// Minimum gap (m) over all lobes, exact. A plain bore: C - |d|. A lobe narrower than pi: h is
/// C + dH (1 - s/phi_t) - |d| cos(psi) with psi = theta - theta_d; its only interior minimum is at
/// sin(psi) = dH / (phi_t |d|), cos(psi) > 0 (the other stationary point is a maximum), so the
/// lobe's minimum is there or at an end (three gap evaluations instead of a search; the film
/// evaluates this at every sub-step and the rotor inside its Newton iterations).
pub fn min_gap_m(p: &BearingParams, j: &JournalState) -> f64 {
    if p.plain_bore {
        return p.c_m - j.dx_m.hypot(j.dy_m);
    }
    if p.phi_t_rad >= std::f64::consts::PI {
        return sampled_min_gap_m(p, j);
    }
    (0..p.n_lobes)
        .map(|k| lobe_minimum(p, k, j).1)
        .fold(f64::INFINITY, f64::min)
}

/// (s, h) of the minimum gap in lobe `k` (phi_t < pi; see [`min_gap_m`]).
pub fn lobe_minimum(p: &BearingParams, k: usize, j: &JournalState) -> (f64, f64) {
    let span = p.phi_t_rad;
    let r = j.dx_m.hypot(j.dy_m);
    // Without an interior minimum h falls along the whole lobe (the step).
    let mut best = (span, gap_m(p, k, span, j));
    let q = p.dh_m / (span * r);
    if q < 1.0 {
        let theta_k = p.block_start_rad(k) + p.alpha_rad;
        let s_star =
            (j.dy_m.atan2(j.dx_m) + q.asin() - theta_k).rem_euclid(2.0 * std::f64::consts::PI);
        if s_star <= span {
            let h = gap_m(p, k, s_star, j);
            if h < best.1 {
                best = (s_star, h);
            }
        }
    }
    let h0 = gap_m(p, k, 0.0, j);
    if h0 < best.1 {
        best = (0.0, h0);
    }
    best
}

/// Minimum gap (m) by sampling plus a local Newton refinement (blocks wider than pi, and the
/// cross-check of the closed form).
pub fn sampled_min_gap_m(p: &BearingParams, j: &JournalState) -> f64 {
    let n_blocks = p.n_blocks();
    let span = p.block_span_rad();
    let ns = 64;
    let mut hmin = f64::INFINITY;
    for k in 0..n_blocks {
        let mut best = (0.0, f64::INFINITY);
        for i in 0..=ns {
            let s = span * i as f64 / ns as f64;
            let h = gap_m(p, k, s, j);
            if h < best.1 {
                best = (s, h);
            }
        }
        // Newton on dh/ds = 0 from the best sample (h'' > 0 near an interior minimum).
        let mut s = best.0;
        for _ in 0..8 {
            let theta = p.block_start_rad(k) + s + p.alpha_rad;
            let dstep = if p.plain_bore {
                0.0
            } else {
                -p.dh_m / p.phi_t_rad
            };
            let d1 = j.dx_m * theta.sin() - j.dy_m * theta.cos() + dstep;
            let d2 = j.dx_m * theta.cos() + j.dy_m * theta.sin();
            if d2 <= 0.0 {
                break;
            }
            s = (s - d1 / d2).clamp(0.0, span);
        }
        hmin = hmin.min(best.1).min(gap_m(p, k, s, j));
    }
    hmin
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn closed_form_minimum_gap_matches_the_search() {
        // Journals all around the bore, centred to far beyond contact, lobed with and without a
        // step, the paper's and a two-lobe ring, and a plain bore.
        let paper = BearingParams::paper();
        let no_step = BearingParams {
            dh_m: 0.0,
            ..paper.clone()
        };
        let two = BearingParams {
            n_lobes: 2,
            phi_t_rad: 150f64.to_radians(),
            ..paper.clone()
        };
        let plain = BearingParams::plain_bore();
        for p in [&paper, &no_step, &two, &plain] {
            for i in 0..90 {
                let th = (i as f64 + 0.21) * std::f64::consts::PI / 45.0;
                for r_rel in [0.0, 0.3, 0.9, 1.0, 1.7, 3.0] {
                    let r = r_rel * p.c_m;
                    let j = JournalState::at(r * th.cos(), r * th.sin(), 0.0);
                    let exact = min_gap_m(p, &j);
                    // Independent reference: the smallest of 4000 samples per block, never below
                    // the exact minimum.
                    let n = 4_000;
                    let dense = (0..p.n_blocks())
                        .flat_map(|k| {
                            (0..=n).map(move |i| (k, p.block_span_rad() * i as f64 / n as f64))
                        })
                        .map(|(k, s)| gap_m(p, k, s, &j))
                        .fold(f64::INFINITY, f64::min);
                    assert!(
                        exact <= dense + 1e-18,
                        "theta {th}, r {r_rel} C: {exact} > {dense}"
                    );
                    // Sampling misses the minimum by at most |d| (ds/2)^2 / 2 (the curvature).
                    let ds = p.block_span_rad() / n as f64;
                    let bound = 1.01 * r * (0.5 * ds).powi(2) / 2.0 + 1e-18;
                    assert!(
                        dense - exact <= bound,
                        "theta {th}, r {r_rel} C: {exact} vs {dense}"
                    );
                    if !p.plain_bore {
                        // The search the closed form replaced (kept for lobes wider than pi).
                        let search = sampled_min_gap_m(p, &j);
                        assert!(
                            (search - exact).abs() < 1e-12 * p.c_m,
                            "{exact} vs search {search}"
                        );
                    }
                }
            }
        }
    }
}
