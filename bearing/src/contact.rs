//! Mixed-lubrication penalty contact (paper Section 2.2, MODEL.md section 3).
//!
//! Where h < h_con = h_con_rel C, a contact pressure p_con = c_con (h_con - h) acts on the journal.
//! It enters the force integral only (not the Reynolds equation). The gap does not depend on z,
//! so the axial integral is exact: F_con = -b r Int p_con(phi) (cos theta, sin theta) dphi over
//! the lobes (pockets are deeper than the lobes and never touch first).
//!
//! The integral runs over the contact band itself, not over the film's mesh: the band can be
//! far narrower than an element (a journal grazing the ring touches over a fraction of a degree),
//! and the rotor evaluates the same law on its own (rotor.fmu, `contact = true`), so the result
//! must not depend on the film's mesh. In a band the gap is sinusoid plus linear and convex
//! (h < h_con < C forces cos(theta - theta_d) > 0), so each band is one interval around a local
//! minimum of h; its ends are found by safeguarded Newton and the smooth integrand inside by
//! composite Gauss quadrature. The minimum itself has a closed form (the rotor evaluates this
//! inside its Newton iterations and finite-difference Jacobians, so it must be cheap).

use crate::bore::{gap_at_m, gap_m, lobe_minimum, newton_minimum, Bore};
use crate::quadrature::{GAUSS3_W, GAUSS3_X};
use crate::JournalState;
use serde::{Deserialize, Serialize};

/// The mixed-lubrication contact law: a penalty pressure c_con (h_con - h) where the gap h falls
/// below h_con = h_con_rel C.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct ContactLaw {
    /// Contact threshold h_con / C.
    pub h_con_rel: f64,
    /// Penalty stiffness of the asperity contact pressure c_con (N/m^3).
    pub c_con_n_per_m3: f64,
}

impl ContactLaw {
    /// The paper's law: h_con = 0.04 C, c_con = 1e16 N/m^3.
    pub fn paper() -> Self {
        ContactLaw {
            h_con_rel: 0.04,
            c_con_n_per_m3: 1e16,
        }
    }

    /// Contact threshold h_con (m) in a bore of clearance `c_m`.
    pub fn h_con_m(&self, c_m: f64) -> f64 {
        self.h_con_rel * c_m
    }

    /// Checks the law; the error names the offending parameter (the film's names).
    pub fn validate(&self) -> Result<(), crate::InvalidParameter> {
        let bad = |name, value, reason| {
            Err(crate::InvalidParameter {
                name,
                value,
                reason,
            })
        };
        for (name, v) in [
            ("h_con_rel", self.h_con_rel),
            ("c_con", self.c_con_n_per_m3),
        ] {
            if !v.is_finite() {
                return bad(name, v, "must be finite (NaN or infinite given)");
            }
        }
        if !(0.0..1.0).contains(&self.h_con_rel) {
            return bad("h_con_rel", self.h_con_rel, "must lie in [0, 1)");
        }
        if self.c_con_n_per_m3 < 0.0 {
            return bad("c_con", self.c_con_n_per_m3, "must be >= 0");
        }
        // 1e4 times the paper's penalty: stiffer is no closer to a rigid contact the models can
        // integrate (1e300 was taken and left the rotor's steps to fail on the rings).
        if self.c_con_n_per_m3 > MAX_C_CON_N_PER_M3 {
            return bad(
                "c_con",
                self.c_con_n_per_m3,
                "must be at most 1e20 N/m3 (paper: 1e16 N/m3)",
            );
        }
        Ok(())
    }
}

/// Stiffest contact penalty taken [N/m^3]: 1e4 times the paper's.
pub const MAX_C_CON_N_PER_M3: f64 = 1e20;

impl Default for ContactLaw {
    fn default() -> Self {
        Self::paper()
    }
}

/// Samples per block that locate the local minima of h (as in `min_gap_m`).
const SAMPLES: usize = 64;
/// Sub-intervals of 3-point Gauss across one contact band.
const BAND_PANELS: usize = 4;

/// What the journal-ring contact needs of one bearing: its bore and the contact law. The rotor
/// evaluates the contact with this (rotor.fmu, `contact = true`); the air film holds the same two
/// parts in its parameters.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct BoreContact {
    pub bore: Bore,
    pub law: ContactLaw,
}

impl BoreContact {
    /// The paper's bore and contact law.
    pub fn paper() -> Self {
        BoreContact {
            bore: Bore::paper(),
            law: ContactLaw::paper(),
        }
    }

    /// Contact force on the journal [N] (x, y) for journal-minus-ring displacement `dr_m`.
    pub fn force_n(&self, dr_m: [f64; 2]) -> [f64; 2] {
        let j = JournalState::at(dr_m[0], dr_m[1], 0.0);
        contact_force_at_n(&self.bore, &self.law, &j)
    }

    /// Checks bore and law; the error names the first offending parameter (the film's names).
    pub fn validate(&self) -> Result<(), crate::InvalidParameter> {
        self.bore.validate()?;
        self.law.validate()
    }
}

/// Contact force on the journal (N), [Fx, Fy]. Zero when the gap is everywhere >= h_con
/// (`h_min_m` is the minimum gap, used only to skip that case).
pub fn contact_force_n(p: &Bore, law: &ContactLaw, j: &JournalState, h_min_m: f64) -> [f64; 2] {
    let h_con = law.h_con_rel * p.c_m;
    if h_min_m >= h_con || law.c_con_n_per_m3 == 0.0 {
        return [0.0, 0.0];
    }
    let mut f = [0.0, 0.0];
    for k in 0..p.n_blocks() {
        for (a, b) in contact_bands(p, k, j, h_con).into_iter().flatten() {
            let fb = band_force(p, law.c_con_n_per_m3, k, j, h_con, a, b);
            f[0] += fb[0];
            f[1] += fb[1];
        }
    }
    f
}

/// Contact force on the journal (N) at journal state `j`, for callers that do not have the
/// minimum gap at hand (the rotor model evaluates the contact inside its own Newton iterations).
/// The gap is at least C - |d| (the step term is >= 0), so a journal inside that circle costs
/// one hypot.
pub fn contact_force_at_n(p: &Bore, law: &ContactLaw, j: &JournalState) -> [f64; 2] {
    let h_con = law.h_con_rel * p.c_m;
    if p.c_m - j.dx_m.hypot(j.dy_m) >= h_con {
        return [0.0, 0.0];
    }
    // The band search finds "no contact" itself; the minimum gap is not needed.
    contact_force_n(p, law, j, f64::NEG_INFINITY)
}

/// Contact force (N) of the band [a, b] of block `k`: composite 3-point Gauss.
fn band_force(
    p: &Bore,
    c_con_n_per_m3: f64,
    k: usize,
    j: &JournalState,
    h_con: f64,
    a: f64,
    b: f64,
) -> [f64; 2] {
    let mut f = [0.0, 0.0];
    let w_panel = (b - a) / BAND_PANELS as f64;
    // The points of a panel are the previous panel's turned by w_panel: sine and cosine of the
    // first panel's three points and of the turn, then rotations (4 sin_cos per band instead of
    // 3 per panel; the rotor evaluates this in every Newton iteration while a journal rides on
    // its ring). The rotations round differently from direct evaluation, by ~1e-16 per panel.
    let (turn_sin, turn_cos) = w_panel.sin_cos();
    let mut at: [(f64, f64); 3] = std::array::from_fn(|q| {
        p.theta_rad(k, a + 0.5 * (1.0 + GAUSS3_X[q]) * w_panel)
            .sin_cos()
    });
    for panel in 0..BAND_PANELS {
        for q in 0..3 {
            let s = a + (panel as f64 + 0.5 * (1.0 + GAUSS3_X[q])) * w_panel;
            let (sin, cos) = at[q];
            let pen = h_con - gap_at_m(p, s, j, (sin, cos));
            if pen > 0.0 {
                let w = 0.5 * w_panel * GAUSS3_W[q] * c_con_n_per_m3 * pen;
                f[0] -= w * cos;
                f[1] -= w * sin;
            }
            at[q] = (
                sin * turn_cos + cos * turn_sin,
                cos * turn_cos - sin * turn_sin,
            );
        }
    }
    let scale = p.b_m * p.r_m;
    [f[0] * scale, f[1] * scale]
}

/// The intervals [a, b] of block-local angle where h < h_con in block `k` (at most two pieces:
/// a plain bore's band may wrap around s = 0). Closed forms for a plain bore and for lobes
/// narrower than pi (every real bearing); sampling otherwise.
fn contact_bands(p: &Bore, k: usize, j: &JournalState, h_con: f64) -> [Option<(f64, f64)>; 2] {
    if p.plain_bore {
        plain_bore_bands(p, j, h_con)
    } else if p.phi_t_rad < std::f64::consts::PI {
        [lobe_band(p, k, j, h_con), None]
    } else {
        sampled_bands(p, k, j, h_con)
    }
}

/// Plain bore: h = C - |d| cos(theta - theta_d), so the band is |theta - theta_d| < acos((C - h_con) / |d|).
fn plain_bore_bands(p: &Bore, j: &JournalState, h_con: f64) -> [Option<(f64, f64)>; 2] {
    let tau = 2.0 * std::f64::consts::PI;
    let r = j.dx_m.hypot(j.dy_m);
    let q = (p.c_m - h_con) / r;
    if q.is_nan() || q >= 1.0 {
        return [None, None];
    }
    let half = q.max(-1.0).acos();
    let centre = (j.dy_m.atan2(j.dx_m) - p.alpha_rad).rem_euclid(tau);
    let (a, b) = (centre - half, centre + half);
    if a < 0.0 {
        [Some((0.0, b.min(tau))), Some((a + tau, tau))]
    } else if b > tau {
        [Some((a, tau)), Some((0.0, b - tau))]
    } else {
        [Some((a, b)), None]
    }
}

/// One lobe (phi_t < pi): the band around the lobe's minimum (closed form, `lobe_minimum`) ends
/// where h = h_con (safeguarded Newton).
fn lobe_band(p: &Bore, k: usize, j: &JournalState, h_con: f64) -> Option<(f64, f64)> {
    let span = p.phi_t_rad;
    let (s_min, h_min) = lobe_minimum(p, k, j);
    if h_min >= h_con {
        return None;
    }
    // Newton starts where the parabola through the minimum with the gap's curvature there,
    // h'' = dx cos(theta) + dy sin(theta) (the step is linear), reaches h_con: a band is a small
    // fraction of the lobe, so that is close to the crossing (4-5 iterations to full precision
    // instead of ~10 from the lobe's end, which took 40 % of a contact evaluation).
    let (sin, cos) = p.theta_rad(k, s_min).sin_cos();
    let curvature = j.dx_m * cos + j.dy_m * sin;
    let half_width = (2.0 * (h_con - h_min) / curvature).sqrt();
    let a = if gap_m(p, k, 0.0, j) < h_con {
        0.0
    } else {
        crossing(p, k, j, h_con, 0.0, s_min, s_min - half_width)
    };
    let b = if gap_m(p, k, span, j) < h_con {
        span
    } else {
        crossing(p, k, j, h_con, span, s_min, s_min + half_width)
    };
    Some((a, b))
}

/// Sampling for blocks wider than pi (one lobe wider than a half circle): one band per local
/// minimum of 64 samples.
fn sampled_bands(p: &Bore, k: usize, j: &JournalState, h_con: f64) -> [Option<(f64, f64)>; 2] {
    let span = p.block_span_rad();
    let s_at = |i: usize| span * i as f64 / SAMPLES as f64;
    let h: Vec<f64> = (0..=SAMPLES).map(|i| gap_m(p, k, s_at(i), j)).collect();
    let mut bands = [None, None];
    let mut n = 0;
    for i in 0..=SAMPLES {
        let left_higher = i == 0 || h[i] < h[i - 1];
        let right_not_lower = i == SAMPLES || h[i] <= h[i + 1];
        if !(left_higher && right_not_lower) || n == bands.len() {
            continue;
        }
        let s_min = refine_minimum(p, k, j, s_at(i), span);
        if gap_m(p, k, s_min, j) >= h_con {
            continue;
        }
        // Walk out to the first sample at or above h_con (or the block end), then bisect.
        let mut lo = i;
        while lo > 0 && h[lo] < h_con && s_at(lo) > 0.0 {
            lo -= 1;
        }
        let mut hi = i;
        while hi < SAMPLES && h[hi] < h_con {
            hi += 1;
        }
        let a = if h[lo] < h_con {
            0.0
        } else {
            crossing(p, k, j, h_con, s_at(lo), s_min, s_at(lo))
        };
        let b = if h[hi] < h_con {
            span
        } else {
            crossing(p, k, j, h_con, s_at(hi), s_min, s_at(hi))
        };
        let (a, b) = (a.min(s_min), b.max(s_min));
        if bands[..n]
            .iter()
            .flatten()
            .any(|&(a0, b0)| a < b0 && b > a0)
        {
            continue; // the same band seen from a second sample
        }
        bands[n] = Some((a, b));
        n += 1;
    }
    bands
}

/// Newton on dh/ds = 0 from a sample (h'' > 0 near a minimum), clamped to the block.
fn refine_minimum(p: &Bore, k: usize, j: &JournalState, s0: f64, span: f64) -> f64 {
    let s = newton_minimum(p, k, j, s0, span);
    // Keep the sample if Newton went astray.
    if gap_m(p, k, s, j) <= gap_m(p, k, s0, j) {
        s
    } else {
        s0
    }
}

/// The angle between `s_out` (h >= h_con) and `s_in` (h < h_con) where h = h_con. Between them
/// the points with h < h_con form one interval ending at `s_in` (they lie where h is convex), so
/// the crossing is unique. Newton from `s_start` (from `s_out` if that is not strictly between
/// the two, or not a number), safeguarded by bisection when a step leaves the bracket.
fn crossing(
    p: &Bore,
    k: usize,
    j: &JournalState,
    h_con: f64,
    s_out: f64,
    s_in: f64,
    s_start: f64,
) -> f64 {
    let dstep = p.step_slope();
    let (mut out, mut inside) = (s_out, s_in);
    let mut s = if (s_start - s_out) * (s_start - s_in) < 0.0 {
        s_start
    } else {
        s_out
    };
    for _ in 0..100 {
        let (sin, cos) = p.theta_rad(k, s).sin_cos();
        let f = gap_at_m(p, s, j, (sin, cos)) - h_con;
        if f >= 0.0 {
            out = s;
        } else {
            inside = s;
        }
        let slope = j.dx_m * sin - j.dy_m * cos + dstep;
        let newton = s - f / slope;
        let next = if newton.is_finite() && (newton - out) * (newton - inside) < 0.0 {
            newton
        } else {
            0.5 * (out + inside)
        };
        if (next - s).abs() <= 1e-15 * (1.0 + s.abs()) || (out - inside).abs() <= 1e-15 {
            return next;
        }
        s = next;
    }
    s
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::bore::min_gap_m;

    /// The law's checks name the parameter; the paper's law and the stiffest one taken pass.
    #[test]
    fn the_contact_law_refuses_values_no_contact_can_mean() {
        let law = |h_con_rel, c_con_n_per_m3| ContactLaw {
            h_con_rel,
            c_con_n_per_m3,
        };
        assert!(ContactLaw::paper().validate().is_ok());
        assert!(law(0.04, MAX_C_CON_N_PER_M3).validate().is_ok());
        assert!(law(0.04, 0.0).validate().is_ok());
        for (l, name) in [
            (law(0.04, 1e300), "c_con"),
            (law(0.04, -1.0), "c_con"),
            (law(0.04, f64::NAN), "c_con"),
            (law(1.0, 1e16), "h_con_rel"),
        ] {
            let e = l.validate().unwrap_err();
            assert_eq!(e.name, name, "{l:?}");
        }
        assert!(law(0.04, 1e300)
            .validate()
            .unwrap_err()
            .reason
            .contains("1e20 N/m3"));
    }

    #[test]
    fn shortcut_agrees_with_the_full_evaluation_inside_and_beyond_the_bound() {
        let (p, law) = (Bore::paper(), ContactLaw::paper());
        let c = p.c_m;
        // Inside C - h_con (no contact possible), on the bound, and beyond it in several
        // directions (the lobes' trailing edges and the pockets).
        for r_rel in [0.0, 0.5, 0.95, 0.96, 0.97, 1.0, 1.02, 1.3] {
            for k in 0..12 {
                let th = k as f64 * std::f64::consts::PI / 6.0 + 0.1;
                let j = JournalState::at(r_rel * c * th.cos(), r_rel * c * th.sin(), 0.0);
                let full = contact_force_n(&p, &law, &j, min_gap_m(&p, &j));
                assert_eq!(
                    contact_force_at_n(&p, &law, &j),
                    full,
                    "r = {r_rel} C, theta = {th}"
                );
            }
        }
        // Beyond the bound towards a lobe's trailing edge the force is non-zero and pushes back.
        let th = p.phi_t_rad + p.alpha_rad - 0.005;
        let j = JournalState::at(0.99 * c * th.cos(), 0.99 * c * th.sin(), 0.0);
        let f = contact_force_at_n(&p, &law, &j);
        assert!(f[0] * th.cos() + f[1] * th.sin() < -1.0, "{f:?}");
    }

    /// Brute force: midpoint rule with `n` points per block over the whole block.
    fn reference(p: &Bore, law: &ContactLaw, j: &JournalState, n: usize) -> [f64; 2] {
        let h_con = law.h_con_rel * p.c_m;
        let span = p.block_span_rad();
        let mut f = [0.0, 0.0];
        for k in 0..p.n_blocks() {
            for i in 0..n {
                let s = span * (i as f64 + 0.5) / n as f64;
                let pen = h_con - gap_m(p, k, s, j);
                if pen > 0.0 {
                    let th = p.block_start_rad(k) + s + p.alpha_rad;
                    let w = law.c_con_n_per_m3 * pen * span / n as f64 * p.b_m * p.r_m;
                    f[0] -= w * th.cos();
                    f[1] -= w * th.sin();
                }
            }
        }
        f
    }

    /// `band_force` as it was before its points were rotated: sine and cosine per point.
    fn band_force_direct(
        p: &Bore,
        c_con_n_per_m3: f64,
        k: usize,
        j: &JournalState,
        h_con: f64,
        a: f64,
        b: f64,
    ) -> [f64; 2] {
        let mut f = [0.0, 0.0];
        let w_panel = (b - a) / BAND_PANELS as f64;
        for panel in 0..BAND_PANELS {
            for q in 0..3 {
                let s = a + (panel as f64 + 0.5 * (1.0 + GAUSS3_X[q])) * w_panel;
                let (sin, cos) = p.theta_rad(k, s).sin_cos();
                let pen = h_con - gap_at_m(p, s, j, (sin, cos));
                if pen > 0.0 {
                    let w = 0.5 * w_panel * GAUSS3_W[q] * c_con_n_per_m3 * pen;
                    f[0] -= w * cos;
                    f[1] -= w * sin;
                }
            }
        }
        [f[0] * p.b_m * p.r_m, f[1] * p.b_m * p.r_m]
    }

    /// The rotated points give the per-point evaluation's force to rounding, on every block
    /// and band of a journal pressed into the ring in many directions (lobed and plain bores).
    #[test]
    fn rotated_band_points_equal_the_direct_evaluation() {
        let law = ContactLaw::paper();
        let mut compared = 0;
        for p in [Bore::paper(), Bore::plain()] {
            let h_con = law.h_con_rel * p.c_m;
            for i in 0..72 {
                let th = i as f64 * std::f64::consts::PI / 36.0 + 0.01;
                for r_rel in [1.0, 1.1, 1.5] {
                    let r = r_rel * p.c_m;
                    let j = JournalState::at(r * th.cos(), r * th.sin(), 0.0);
                    for k in 0..p.n_blocks() {
                        for (a, b) in contact_bands(&p, k, &j, h_con).into_iter().flatten() {
                            let f = band_force(&p, law.c_con_n_per_m3, k, &j, h_con, a, b);
                            let g = band_force_direct(&p, law.c_con_n_per_m3, k, &j, h_con, a, b);
                            let mag = g[0].hypot(g[1]);
                            let err = (f[0] - g[0]).hypot(f[1] - g[1]);
                            assert!(err <= 1e-13 * mag, "{f:?} vs {g:?}");
                            compared += usize::from(mag > 0.0);
                        }
                    }
                }
            }
        }
        assert!(compared > 100, "{compared} bands with contact");
    }

    #[test]
    fn a_grazing_journal_gets_the_band_integral_on_any_mesh() {
        // A journal that just touches a lobe: the band is ~1 degree wide, narrower than an
        // element of the paper's mesh (5.5 degrees). Also bands at a lobe's end and in the middle.
        let (p, law) = (Bore::paper(), ContactLaw::paper());
        let c = p.c_m;
        // Directions: lobe 2 past its middle (theta = 260 deg), near lobe 1's trailing edge, and
        // the bottom; minimum gaps 0.9 h_con (grazing), 0.5 h_con and -2 h_con (deep).
        let deg = std::f64::consts::PI / 180.0;
        let h_con = law.h_con_rel * c;
        let cases = [
            (260.0 * deg, 0.9 * h_con),
            (178.0 * deg, 0.5 * h_con),
            (270.0 * deg, -2.0 * h_con),
        ];
        for (th, h_min) in cases {
            // The eccentricity that gives this minimum gap (bisection; h_min falls with it).
            let at = |r: f64| JournalState::at(r * th.cos(), r * th.sin(), 0.0);
            let (mut lo, mut hi) = (0.0, 3.0 * c);
            for _ in 0..100 {
                let mid = 0.5 * (lo + hi);
                if min_gap_m(&p, &at(mid)) > h_min {
                    lo = mid;
                } else {
                    hi = mid;
                }
            }
            let (j, r_rel) = (at(lo), lo / c);
            let f = contact_force_at_n(&p, &law, &j);
            let fr = reference(&p, &law, &j, 2_000_000);
            let mag = fr[0].hypot(fr[1]);
            assert!(mag > 0.0, "no contact at theta = {th}, r = {r_rel} C");
            let err = (f[0] - fr[0]).hypot(f[1] - fr[1]) / mag;
            assert!(
                err < 1e-6,
                "theta {th}, r {r_rel} C: {f:?} vs {fr:?} (rel. error {err:.2e})"
            );
        }
        // A plain bore whose band wraps around s = 0 (journal towards theta = 0).
        let pb = Bore::plain();
        let j = JournalState::at(0.99 * pb.c_m, 1e-3 * pb.c_m, 0.0);
        let (f, fr) = (
            contact_force_at_n(&pb, &law, &j),
            reference(&pb, &law, &j, 2_000_000),
        );
        assert!(
            fr[0] < -1.0 && ((f[0] - fr[0]) / fr[0]).abs() < 1e-6,
            "{f:?} vs {fr:?}"
        );
    }

    #[test]
    fn band_ends_from_the_parabola_start_are_the_crossings() {
        // Newton started near the crossing (lobe_band) and started at the lobe's end (the
        // bracket's outer side, as before) find the same angle, where h = h_con.
        let law = ContactLaw::paper();
        for p in [
            Bore::paper(),
            Bore {
                dh_m: 0.0,
                c_m: 15e-6,
                ..Bore::paper()
            },
        ] {
            let h_con = law.h_con_rel * p.c_m;
            let mut n_ends = 0;
            for i in 0..720 {
                let th = (i as f64 + 0.37) * std::f64::consts::PI / 360.0;
                for r_rel in [0.9601, 0.961, 0.965, 0.99, 1.0, 1.05, 1.2, 1.5] {
                    let r = r_rel * p.c_m;
                    let j = JournalState::at(r * th.cos(), r * th.sin(), 0.0);
                    for k in 0..p.n_blocks() {
                        let Some((a, b)) = lobe_band(&p, k, &j, h_con) else {
                            continue;
                        };
                        let (s_min, _) = lobe_minimum(&p, k, &j);
                        for (end, s_out) in [(a, 0.0), (b, p.phi_t_rad)] {
                            if end == s_out {
                                continue;
                            }
                            let old = crossing(&p, k, &j, h_con, s_out, s_min, s_out);
                            assert!(
                                (end - old).abs() <= 1e-13,
                                "lobe {k}, theta {th}, r {r_rel} C: {end} vs {old}"
                            );
                            let h = gap_m(&p, k, end, &j);
                            assert!((h - h_con).abs() <= 1e-12 * p.c_m, "{h} vs {h_con}");
                            n_ends += 1;
                        }
                    }
                }
            }
            assert!(n_ends > 1000, "only {n_ends} band ends");
        }
    }

    #[test]
    fn closed_form_bands_agree_with_sampled_bands() {
        // Journals all around the bore at eccentricities from the contact edge to deep
        // penetration, lobed (with and without a step) and plain: the closed forms give the bands
        // that sampling plus bisection finds.
        let law = ContactLaw::paper();
        let lobed = Bore::paper();
        let no_step = Bore {
            dh_m: 0.0,
            ..Bore::paper()
        };
        let plain = Bore::plain();
        let mut n_contact = 0;
        for p in [&lobed, &no_step, &plain] {
            let h_con = law.h_con_rel * p.c_m;
            for i in 0..360 {
                let th = (i as f64 + 0.37) * std::f64::consts::PI / 180.0;
                for r_rel in [0.965, 0.99, 1.0, 1.05, 1.5, 2.5] {
                    let r = r_rel * p.c_m;
                    let j = JournalState::at(r * th.cos(), r * th.sin(), 0.0);
                    let fast = contact_force_at_n(p, &law, &j);
                    let mut slow = [0.0, 0.0];
                    for k in 0..p.n_blocks() {
                        for (a, b) in sampled_bands(p, k, &j, h_con).into_iter().flatten() {
                            let f = band_force(p, law.c_con_n_per_m3, k, &j, h_con, a, b);
                            slow[0] += f[0];
                            slow[1] += f[1];
                        }
                    }
                    let mag = slow[0].hypot(slow[1]);
                    n_contact += usize::from(mag > 0.0);
                    let err = (fast[0] - slow[0]).hypot(fast[1] - slow[1]);
                    assert!(
                        err <= 1e-9 * mag + 1e-12,
                        "theta {th}, r {r_rel} C: {fast:?} vs {slow:?}"
                    );
                }
            }
        }
        assert!(n_contact > 2000, "only {n_contact} states in contact");
    }
}
