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
use bearing::Bore;

/// Write the run-up figures into `out_dir` (which must exist): `eps`, `y_journal`, `waterfall_C`,
/// `waterfall_T`, `orbit_C`, `orbit_T`, each as `.svg` and `.png`. Returns the written paths.
pub fn plot_runup(
    series: &RunSeries,
    class: &Classification,
    bores: &[Bore; 2],
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
        out.extend(
            figures::orbit(series, b, &bores[b as usize])
                .save(out_dir, &format!("orbit_{name}"))?,
        );
    }
    Ok(out)
}

/// Write the friction power-loss figure (`power_loss.svg`, `.png`) into `out_dir`.
pub fn plot_power_loss(
    speed_hz: &[f64],
    p_c_w: &[f64],
    p_t_w: &[f64],
    out_dir: &Path,
) -> std::io::Result<Vec<PathBuf>> {
    figures::power_loss(speed_hz, p_c_w, p_t_w).save(out_dir, "power_loss")
}

#[cfg(test)]
mod tests;
