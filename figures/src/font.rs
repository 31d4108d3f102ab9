//! The one typeface of every figure: DejaVu Sans, compiled into the program (`assets/fonts`, Bitstream
//! Vera licence beside it), so a PNG looks the same on a cluster node without fonts as on a desktop.
//!
//! Sizes in this module are plotters' text sizes [px]: ab_glyph scales a font so that its ascent minus
//! descent spans `size` pixels. The SVG twin states the CSS em size that gives the same glyphs
//! (`em_px`), so a browser with any sans-serif font draws text of nearly the same width.

use ab_glyph::{Font, FontRef, PxScale, ScaleFont};
use plotters::style::FontStyle;
use std::sync::{Once, OnceLock};

/// The family name the figures ask plotters for.
pub const FAMILY: &str = "sans-serif";

static TTF: &[u8] = include_bytes!("../assets/fonts/DejaVuSans.ttf");

fn face() -> &'static FontRef<'static> {
    static FACE: OnceLock<FontRef<'static>> = OnceLock::new();
    // The file is part of the program and read by a test (`embedded_font_parses`); it cannot fail at
    // run time unless the binary itself is corrupt.
    FACE.get_or_init(|| FontRef::try_from_slice(TTF).expect("embedded DejaVu Sans parses"))
}

/// Register the embedded font with plotters (once per process; every figure calls this first).
pub fn register() {
    static ONCE: Once = Once::new();
    ONCE.call_once(|| {
        if plotters::style::register_font(FAMILY, FontStyle::Normal, TTF).is_err() {
            unreachable!("embedded DejaVu Sans parses (tested)");
        }
    });
}

/// The CSS font size [px per em] whose glyphs match plotters' text size `size_px`.
pub fn em_px(size_px: f64) -> f64 {
    let f = face();
    size_px * f64::from(f.units_per_em().unwrap_or(2048.0)) / f64::from(f.height_unscaled())
}

/// Width [px] of `text` at plotters' text size `size_px` (advances and kerning, as plotters lays it out).
pub fn text_width_px(text: &str, size_px: f64) -> f64 {
    let f = face().as_scaled(PxScale::from(size_px as f32));
    let mut w = 0.0f32;
    let mut prev = None;
    for c in text.chars() {
        let id = f.glyph_id(c);
        if let Some(p) = prev {
            w += f.kern(p, id);
        }
        w += f.h_advance(id);
        prev = Some(id);
    }
    f64::from(w)
}

/// Ascent and descent [px, both positive] of a line of text at CSS font size `em_px`: the line box
/// a browser reserves around the baseline.
pub fn line_box_px(em_px: f64) -> (f64, f64) {
    let f = face();
    let upem = f64::from(f.units_per_em().unwrap_or(2048.0));
    (
        em_px * f64::from(f.ascent_unscaled()) / upem,
        -em_px * f64::from(f.descent_unscaled()) / upem,
    )
}

/// Width [px] of `text` at CSS font size `em_px`.
pub fn text_width_em(text: &str, em_px: f64) -> f64 {
    let f = face();
    text_width_px(
        text,
        em_px * f64::from(f.height_unscaled()) / f64::from(f.units_per_em().unwrap_or(2048.0)),
    )
}

#[cfg(test)]
mod tests {
    use super::*;
    use plotters::style::IntoFont;

    #[test]
    fn embedded_font_parses_and_plotters_lays_it_out_as_we_measure() {
        register();
        assert!(face().glyph_count() > 1000);
        for (text, size) in [("1150", 12.0), ("rotor speed [Hz]", 14.0), ("W", 30.0)] {
            let ours = text_width_px(text, size);
            let font = (FAMILY, size).into_font();
            let (w, _) = font
                .box_size(text)
                .expect("plotters measures with the embedded font");
            // plotters truncates its box to whole pixels.
            assert!((ours - w as f64).abs() < 1.0, "{text}: {ours} vs {w}");
        }
        // Digits are ~0.55 em wide in DejaVu Sans (0.636 em advance): "1150" at 12 px em.
        let w = text_width_em("1150", 12.0);
        assert!((w - 4.0 * 0.636 * 12.0).abs() < 0.5, "{w}");
        let (a, d) = line_box_px(10.0);
        assert!(
            (a - 9.28).abs() < 0.05 && (d - 2.36).abs() < 0.05,
            "{a} {d}"
        );
    }
}
