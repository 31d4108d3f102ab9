//! The bore of the ring: lobes, clearance and step (MODEL.md section 3), and the gap between it
//! and a displaced journal.
//!
//! In lobe k (ring-fixed phi = k 2 pi / n + s, s in [0, phi_t]) the gap is
//! h = C - dx cos(theta) - dy sin(theta) + dH (1 - s / phi_t), theta = phi + alpha,
//! which equals MODEL.md's floor-function form. A plain bore is one 360-degree block without step.

use crate::{InvalidParameter, JournalState};
use serde::{Deserialize, Serialize};
use std::f64::consts::PI;

/// Geometry of one bearing's bore. Units are in the field names.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Bore {
    /// Journal radius r.
    pub r_m: f64,
    /// Bearing width b (full width).
    pub b_m: f64,
    /// Nominal clearance C (gap at each lobe's trailing edge for a centred journal).
    pub c_m: f64,
    /// Step height dH (extra gap at each lobe's leading edge). Must be 0 for a plain bore.
    pub dh_m: f64,
    /// Lobe angle phi_t, in (0, 2 pi / n_lobes). Ignored for a plain bore.
    pub phi_t_rad: f64,
    /// Ring orientation alpha: global angle theta = phi + alpha.
    pub alpha_rad: f64,
    /// Number of lobes n. Ignored for a plain bore.
    pub n_lobes: usize,
    /// Plain 360-degree bore (dH must be 0).
    pub plain_bore: bool,
}

impl Bore {
    /// The paper's three-lobe bore (MODEL.md section 3): r = 15 mm, b = 28.6 mm, C = 20 um,
    /// dH = 40 um, phi_t = 110 deg, alpha = 180 deg - phi_t.
    pub fn paper() -> Self {
        let phi_t = 110f64.to_radians();
        Bore {
            r_m: 15e-3,
            b_m: 28.6e-3,
            c_m: 20e-6,
            dh_m: 40e-6,
            phi_t_rad: phi_t,
            alpha_rad: PI - phi_t,
            n_lobes: 3,
            plain_bore: false,
        }
    }

    /// A plain 360-degree bore of the paper's radius, width and clearance.
    pub fn plain() -> Self {
        Bore {
            dh_m: 0.0,
            plain_bore: true,
            alpha_rad: 0.0,
            ..Self::paper()
        }
    }

    /// Number of blocks whose gap is continuous (lobes; 1 for a plain bore).
    pub fn n_blocks(&self) -> usize {
        if self.plain_bore {
            1
        } else {
            self.n_lobes
        }
    }

    /// Angular span of one block (lobe angle or 2 pi).
    pub fn block_span_rad(&self) -> f64 {
        if self.plain_bore {
            2.0 * PI
        } else {
            self.phi_t_rad
        }
    }

    /// Bore angle theta (rad) at block-local angle `s_rad` of block `k`.
    pub fn theta_rad(&self, k: usize, s_rad: f64) -> f64 {
        self.block_start_rad(k) + s_rad + self.alpha_rad
    }

    /// Ring-fixed start angle of block k.
    pub fn block_start_rad(&self, k: usize) -> f64 {
        if self.plain_bore {
            0.0
        } else {
            k as f64 * 2.0 * PI / self.n_lobes as f64
        }
    }

    /// The gap-closure contour of each block: the journal-centre positions (x, y) [m] at which
    /// the gap closes at angle theta, h(phi) = C + dH (1 - s / phi_t) along theta = phi + alpha
    /// (the displacement along theta at which h - dx cos(theta) - dy sin(theta) = 0 is exactly
    /// h(phi)). From each lobe's leading edge (C + dH) to its trailing edge (C); a plain bore's
    /// contour is the circle of radius C. What orbit plots draw around the journal.
    pub fn closure_contours_m(&self, points_per_block: usize) -> Vec<Vec<(f64, f64)>> {
        let n = points_per_block.max(2);
        let span = self.block_span_rad();
        (0..self.n_blocks())
            .map(|k| {
                let phi_k = self.block_start_rad(k);
                (0..n)
                    .map(|i| {
                        let s = i as f64 / (n - 1) as f64;
                        let phi = phi_k + s * span;
                        let step = if self.plain_bore {
                            0.0
                        } else {
                            self.dh_m * (1.0 - s)
                        };
                        let h = self.c_m + step;
                        let theta = phi + self.alpha_rad;
                        (h * theta.cos(), h * theta.sin())
                    })
                    .collect()
            })
            .collect()
    }

    /// d(step)/ds along a block [m/rad]: -dH / phi_t on a lobe, 0 on a plain bore.
    pub(crate) fn step_slope(&self) -> f64 {
        if self.plain_bore {
            0.0
        } else {
            -self.dh_m / self.phi_t_rad
        }
    }

    /// Checks the geometry; the error names the first offending parameter (the film's names).
    pub fn validate(&self) -> Result<(), InvalidParameter> {
        let bad = |name, value, reason| {
            Err(InvalidParameter {
                name,
                value,
                reason,
            })
        };
        for (name, v) in [
            ("r", self.r_m),
            ("b", self.b_m),
            ("C", self.c_m),
            ("dH", self.dh_m),
            ("phi_t", self.phi_t_rad),
            ("alpha", self.alpha_rad),
        ] {
            if !v.is_finite() {
                return bad(name, v, "must be finite (NaN or infinite given)");
            }
        }
        for (name, v) in [("r", self.r_m), ("b", self.b_m), ("C", self.c_m)] {
            if v <= 0.0 {
                return bad(name, v, "must be > 0");
            }
        }
        if self.dh_m < 0.0 {
            return bad("dH", self.dh_m, "must be >= 0");
        }
        // Sane bounds of a gas bearing, far outside any design but inside what the thin-film
        // model and f64 arithmetic carry (r = 1e300 m overflows the force integrals).
        for (name, v, lo, hi, what) in [
            (
                "r",
                self.r_m,
                1e-4,
                10.0,
                "must lie between 0.1 mm and 10 m",
            ),
            (
                "b",
                self.b_m,
                1e-4,
                10.0,
                "must lie between 0.1 mm and 10 m",
            ),
            (
                "C",
                self.c_m,
                1e-8,
                1e-2,
                "must lie between 10 nm and 10 mm",
            ),
            ("dH", self.dh_m, 0.0, 1e-2, "must lie between 0 and 10 mm"),
        ] {
            if !(lo..=hi).contains(&v) {
                return bad(name, v, what);
            }
        }
        // An orientation: one turn either way. cos and sin of 1e300 keep none of the angle's
        // digits.
        if self.alpha_rad.abs() > 2.0 * PI {
            return bad(
                "alpha",
                self.alpha_rad,
                "must lie between -2 pi and 2 pi rad (paper: pi - phi_t)",
            );
        }
        if self.c_m > 0.1 * self.r_m {
            return bad(
                "C",
                self.c_m,
                "must be at most a tenth of the radius r (a thin film: Reynolds' equation)",
            );
        }
        if self.plain_bore {
            if self.dh_m != 0.0 {
                return bad("dH", self.dh_m, "a plain bore has no step: dH must be 0");
            }
        } else {
            if self.n_lobes < 1 {
                return bad("n_lobes", self.n_lobes as f64, "must be >= 1");
            }
            let max = 2.0 * PI / self.n_lobes as f64;
            if !(self.phi_t_rad > 0.0 && self.phi_t_rad < max) {
                return bad("phi_t", self.phi_t_rad, "must lie in (0, 2 pi / n_lobes)");
            }
        }
        Ok(())
    }
}

impl Default for Bore {
    fn default() -> Self {
        Self::paper()
    }
}

/// Exact gap h (m) at block-local angle `s_rad` of block `k` (no floor).
pub fn gap_m(p: &Bore, k: usize, s_rad: f64, j: &JournalState) -> f64 {
    gap_at_m(p, s_rad, j, p.theta_rad(k, s_rad).sin_cos())
}

/// [`gap_m`] with the sine and cosine of the angle theta at `s_rad` ([`Bore::theta_rad`])
/// already at hand: the contact search needs them for the slope and the force direction too, and
/// a `sin_cos` is most of a gap's cost. The same arithmetic as `gap_m`, so the same bits.
pub(crate) fn gap_at_m(p: &Bore, s_rad: f64, j: &JournalState, (sin, cos): (f64, f64)) -> f64 {
    let step = if p.plain_bore {
        0.0
    } else {
        p.dh_m * (1.0 - s_rad / p.phi_t_rad)
    };
    p.c_m - j.dx_m * cos - j.dy_m * sin + step
}

/// Minimum gap (m) over all lobes, exact. A plain bore: C - |d|. A lobe narrower than pi: h is
/// C + dH (1 - s/phi_t) - |d| cos(psi) with psi = theta - theta_d; its only interior minimum is at
/// sin(psi) = dH / (phi_t |d|), cos(psi) > 0 (the other stationary point is a maximum), so the
/// lobe's minimum is there or at an end (three gap evaluations instead of a search; the film
/// evaluates this at every sub-step and the rotor inside its Newton iterations).
pub fn min_gap_m(p: &Bore, j: &JournalState) -> f64 {
    if p.plain_bore {
        return p.c_m - j.dx_m.hypot(j.dy_m);
    }
    if p.phi_t_rad >= PI {
        return sampled_min_gap_m(p, j);
    }
    (0..p.n_lobes)
        .map(|k| lobe_minimum(p, k, j).1)
        .fold(f64::INFINITY, f64::min)
}

/// (s, h) of the minimum gap in lobe `k` (phi_t < pi; see [`min_gap_m`]).
pub fn lobe_minimum(p: &Bore, k: usize, j: &JournalState) -> (f64, f64) {
    let span = p.phi_t_rad;
    let r = j.dx_m.hypot(j.dy_m);
    // Without an interior minimum h falls along the whole lobe (the step).
    let mut best = (span, gap_m(p, k, span, j));
    let q = p.dh_m / (span * r);
    if q < 1.0 {
        let theta_k = p.block_start_rad(k) + p.alpha_rad;
        let s_star = (j.dy_m.atan2(j.dx_m) + q.asin() - theta_k).rem_euclid(2.0 * PI);
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

/// Newton on dh/ds = 0 from `s0` (h'' > 0 near an interior minimum), clamped to [0, span];
/// at most 8 steps, stops where h is not convex.
pub(crate) fn newton_minimum(p: &Bore, k: usize, j: &JournalState, s0: f64, span: f64) -> f64 {
    let dstep = p.step_slope();
    let mut s = s0;
    for _ in 0..8 {
        let theta = p.block_start_rad(k) + s + p.alpha_rad;
        let d1 = j.dx_m * theta.sin() - j.dy_m * theta.cos() + dstep;
        let d2 = j.dx_m * theta.cos() + j.dy_m * theta.sin();
        if d2 <= 0.0 {
            break;
        }
        s = (s - d1 / d2).clamp(0.0, span);
    }
    s
}

/// Minimum gap (m) by sampling plus a local Newton refinement (blocks wider than pi, and the
/// cross-check of the closed form).
pub fn sampled_min_gap_m(p: &Bore, j: &JournalState) -> f64 {
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
        let s = newton_minimum(p, k, j, best.0, span);
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
        let paper = Bore::paper();
        let no_step = Bore {
            dh_m: 0.0,
            ..paper.clone()
        };
        let two = Bore {
            n_lobes: 2,
            phi_t_rad: 150f64.to_radians(),
            ..paper.clone()
        };
        let plain = Bore::plain();
        for p in [&paper, &no_step, &two, &plain] {
            for i in 0..90 {
                let th = (i as f64 + 0.21) * PI / 45.0;
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

    #[test]
    fn gap_of_a_centred_journal_is_clearance_plus_step() {
        let p = Bore::paper();
        let j = JournalState::default();
        for k in 0..3 {
            assert_eq!(gap_m(&p, k, 0.0, &j), p.c_m + p.dh_m);
            assert!((gap_m(&p, k, p.phi_t_rad, &j) - p.c_m).abs() < 1e-21);
        }
        assert_eq!(min_gap_m(&Bore::plain(), &j), p.c_m);
    }

    #[test]
    fn closure_contours_are_where_the_gap_closes() {
        for p in [Bore::paper(), Bore::plain()] {
            let contours = p.closure_contours_m(41);
            assert_eq!(contours.len(), p.n_blocks());
            for (k, c) in contours.iter().enumerate() {
                for (i, &(x, y)) in c.iter().enumerate() {
                    // A journal centred on the contour point touches the bore exactly there.
                    let s = p.block_span_rad() * i as f64 / 40.0;
                    let h = gap_m(&p, k, s, &JournalState::at(x, y, 0.0));
                    assert!(h.abs() < 1e-18, "block {k}, point {i}: h = {h}");
                }
            }
        }
    }

    #[test]
    fn validate_names_the_offending_parameter() {
        let cases = [
            (
                Bore {
                    c_m: 0.0,
                    ..Bore::paper()
                },
                "C",
            ),
            (
                Bore {
                    dh_m: -1e-6,
                    ..Bore::paper()
                },
                "dH",
            ),
            (
                Bore {
                    r_m: f64::NAN,
                    ..Bore::paper()
                },
                "r",
            ),
            (
                Bore {
                    phi_t_rad: 2.2,
                    ..Bore::paper()
                },
                "phi_t",
            ),
            (
                Bore {
                    n_lobes: 0,
                    ..Bore::paper()
                },
                "n_lobes",
            ),
            (
                Bore {
                    dh_m: 1e-6,
                    ..Bore::plain()
                },
                "dH",
            ),
            (
                Bore {
                    alpha_rad: 1e300,
                    ..Bore::paper()
                },
                "alpha",
            ),
            (
                Bore {
                    alpha_rad: -7.0,
                    ..Bore::paper()
                },
                "alpha",
            ),
        ];
        for (bore, name) in cases {
            assert_eq!(bore.validate().unwrap_err().name, name, "{bore:?}");
        }
        assert!(Bore::paper().validate().is_ok());
        assert!(Bore::plain().validate().is_ok());
    }
}
