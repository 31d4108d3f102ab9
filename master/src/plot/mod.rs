//! Plots of a run-up as SVG, each with a PNG twin: the paper's Fig. 6-8 panels.
//!
//! Hand-written SVG (axes, ticks, labels, polylines; the waterfall colour map is an embedded PNG image) and
//! the same drawing rasterized with tiny-skia; PNG text uses a built-in 8x8 bitmap font, so no system fonts
//! are needed. Data polylines carry `class="series"`, lobe contours `class="lobe"`.

pub mod axes;
pub mod canvas;
mod figures;

pub use figures::bearing_frame;

use std::path::{Path, PathBuf};

use crate::analysis::{Classification, RunSeries};

/// The ring bore geometry needed to draw the lobe contours around an orbit (MODEL.md 3).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LobeGeometry {
    pub n_lobes: usize,
    /// Angular extent of each lobe.
    pub phi_t_rad: f64,
    /// Ring orientation: global angle theta = phi + alpha.
    pub alpha_rad: f64,
    /// Nominal (minimum) clearance C, at each lobe's trailing edge.
    pub c_m: f64,
    /// Step height dH: the gap is C + dH at each lobe's leading edge.
    pub dh_m: f64,
}

impl LobeGeometry {
    /// The paper's Section 3 bearing: three lobes of 110 deg, alpha = pi - phi_t, C = 20 um, dH = 40 um.
    pub fn paper() -> Self {
        let phi_t = 110f64.to_radians();
        LobeGeometry {
            n_lobes: 3,
            phi_t_rad: phi_t,
            alpha_rad: std::f64::consts::PI - phi_t,
            c_m: 20e-6,
            dh_m: 40e-6,
        }
    }

    /// The bore of an air-film parameter set (its lobe count, extent, orientation, C and dH).
    pub fn of_bearing(b: &fmu_airfilm::BearingParams) -> Self {
        LobeGeometry {
            n_lobes: b.n_lobes,
            phi_t_rad: b.phi_t_rad,
            alpha_rad: b.alpha_rad,
            c_m: b.c_m,
            dh_m: b.dh_m,
        }
    }

    /// For each lobe k (phi_k = 2 pi k / n), the points (x, y) in m where the gap closes when the journal centre
    /// is there: radius h(phi) = C + dH (1 - (phi - phi_k) / phi_t) at global angle theta = phi + alpha, from
    /// the leading edge (C + dH) to the trailing edge (C). The journal-centre displacement along theta at which
    /// h - dx cos(theta) - dy sin(theta) = 0 is exactly h(phi).
    pub fn contours_m(&self, points_per_lobe: usize) -> Vec<Vec<(f64, f64)>> {
        let n = points_per_lobe.max(2);
        (0..self.n_lobes)
            .map(|k| {
                let phi_k = std::f64::consts::TAU * k as f64 / self.n_lobes as f64;
                (0..n)
                    .map(|i| {
                        let s = i as f64 / (n - 1) as f64;
                        let phi = phi_k + s * self.phi_t_rad;
                        let h = self.c_m + self.dh_m * (1.0 - s);
                        let theta = phi + self.alpha_rad;
                        (h * theta.cos(), h * theta.sin())
                    })
                    .collect()
            })
            .collect()
    }
}

/// Write the run-up figures into `out_dir` (which must exist): `eps`, `y_journal`, `waterfall_C`,
/// `waterfall_T`, `orbit_C`, `orbit_T`, each as `.svg` and `.png`. Returns the written paths.
pub fn plot_runup(
    series: &RunSeries,
    class: &Classification,
    lobes: &LobeGeometry,
    out_dir: &Path,
) -> std::io::Result<Vec<PathBuf>> {
    series.check();
    let mut out = Vec::new();
    out.extend(figures::eps(series, class).save(out_dir, "eps")?);
    out.extend(figures::y_journal(series, class).save(out_dir, "y_journal")?);
    for (b, name) in [
        (crate::analysis::Bearing::C, "C"),
        (crate::analysis::Bearing::T, "T"),
    ] {
        out.extend(figures::waterfall(series, b).save(out_dir, &format!("waterfall_{name}"))?);
        out.extend(figures::orbit(series, b, lobes).save(out_dir, &format!("orbit_{name}"))?);
    }
    Ok(out)
}

#[cfg(test)]
mod tests;
