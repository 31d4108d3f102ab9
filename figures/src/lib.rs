//! Figures as SVG, each with a PNG twin: the paper's Fig. 6-8 panels, stability and modal diagrams,
//! bifurcation maps.
//!
//! Every figure is drawn by plotters: a `Chart` (x-y data, frame and ticks from plotters' chart
//! builder) or a `Scene` (a free layout, the maps). One drawing goes to two backends: plotters'
//! bitmap backend for the PNG, and `svg::SvgBackend` for the SVG, which tags the data curves
//! (`class="series"`, `class="lobe"`, ...). Text is set in the embedded DejaVu Sans (`font`), so PNGs
//! need no system fonts; `layout` checks that no text overlaps other text or leaves its panel.

pub mod chart;
mod figures;
pub mod font;
pub mod layout;
pub mod scene;
pub mod svg;

pub use chart::{decimate_minmax, Chart};
pub use figures::bearing_frame;
pub use scene::Scene;

use std::path::{Path, PathBuf};

use plotters::coord::Shift;
use plotters::prelude::{BitMapBackend, DrawingArea, DrawingBackend, IntoDrawingArea};

use bearing::Bore;
use runup_analysis::{Classification, RunSeries};

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Rgb(pub u8, pub u8, pub u8);

impl Rgb {
    pub const BLACK: Rgb = Rgb(0, 0, 0);
    pub const WHITE: Rgb = Rgb(255, 255, 255);
    pub const GREY: Rgb = Rgb(200, 200, 200);
    pub const BLUE: Rgb = Rgb(31, 119, 180);
    pub const RED: Rgb = Rgb(214, 39, 40);
    pub const GREEN: Rgb = Rgb(44, 160, 44);
}

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Anchor {
    Start,
    Middle,
    End,
}

/// What a curve is, written as its SVG class: tests and scripts find the data series by it.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Role {
    Series,
    Lobe,
    Reference,
    Marker,
    /// A map panel's area (invisible).
    Panel,
}

impl Role {
    pub fn class(self) -> &'static str {
        match self {
            Role::Series => "series",
            Role::Lobe => "lobe",
            Role::Reference => "ref",
            Role::Marker => "marker",
            Role::Panel => "panel",
        }
    }
}

/// A figure: its size and how to draw it on any plotters backend.
pub trait Figure {
    fn size(&self) -> (u32, u32);
    fn draw_on<DB: DrawingBackend>(
        &self,
        root: &DrawingArea<DB, Shift>,
        tags: &svg::Tags,
    ) -> Result<(), String>;

    /// The SVG text of the figure.
    fn to_svg(&self) -> Result<String, String> {
        font::register();
        let (w, h) = self.size();
        let tags = svg::Tags::for_svg();
        let sink = std::rc::Rc::new(std::cell::RefCell::new(String::new()));
        {
            let root = svg::SvgBackend::new(w, h, tags.clone(), sink.clone()).into_drawing_area();
            self.draw_on(&root, &tags)?;
            root.present().map_err(|e| e.to_string())?;
        }
        let text = sink.take();
        Ok(text)
    }

    /// The PNG bytes of the figure (RGB).
    fn to_png(&self) -> Result<Vec<u8>, String> {
        font::register();
        let (w, h) = self.size();
        let mut buf = vec![255u8; (w as usize) * (h as usize) * 3];
        {
            let root = BitMapBackend::with_buffer(&mut buf, (w, h)).into_drawing_area();
            self.draw_on(&root, &svg::Tags::default())?;
            root.present().map_err(|e| e.to_string())?;
        }
        encode_png(w, h, &buf)
    }

    /// Write `<stem>.svg` and `<stem>.png` into `dir`, each whole or not at all.
    fn save(&self, dir: &Path, stem: &str) -> std::io::Result<Vec<PathBuf>> {
        let write = |path: &Path, bytes: &[u8]| {
            cosim::files::write_whole(path, bytes)
                .map_err(|e| std::io::Error::other(format!("{}: {e}", path.display())))
        };
        let svg = dir.join(format!("{stem}.svg"));
        write(
            &svg,
            self.to_svg().map_err(std::io::Error::other)?.as_bytes(),
        )?;
        let png = dir.join(format!("{stem}.png"));
        write(&png, &self.to_png().map_err(std::io::Error::other)?)?;
        Ok(vec![svg, png])
    }
}

impl Figure for Chart {
    fn size(&self) -> (u32, u32) {
        (self.width, self.height)
    }
    fn draw_on<DB: DrawingBackend>(
        &self,
        root: &DrawingArea<DB, Shift>,
        tags: &svg::Tags,
    ) -> Result<(), String> {
        self.draw(root, tags)
    }
}

impl Figure for Scene {
    fn size(&self) -> (u32, u32) {
        (self.width, self.height)
    }
    fn draw_on<DB: DrawingBackend>(
        &self,
        root: &DrawingArea<DB, Shift>,
        tags: &svg::Tags,
    ) -> Result<(), String> {
        self.draw(root, tags)
    }
}

/// PNG of an RGB raster.
pub fn encode_png(w: u32, h: u32, rgb: &[u8]) -> Result<Vec<u8>, String> {
    let mut out = Vec::new();
    {
        let mut enc = png::Encoder::new(&mut out, w, h);
        enc.set_color(png::ColorType::Rgb);
        enc.set_depth(png::BitDepth::Eight);
        let mut writer = enc.write_header().map_err(|e| e.to_string())?;
        writer.write_image_data(rgb).map_err(|e| e.to_string())?;
    }
    Ok(out)
}

/// Standard base64 (RFC 4648) for data URIs.
pub fn base64(data: &[u8]) -> String {
    const A: &[u8; 64] = b"ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    let mut out = String::with_capacity(data.len().div_ceil(3) * 4);
    for chunk in data.chunks(3) {
        let b = [
            chunk[0],
            *chunk.get(1).unwrap_or(&0),
            *chunk.get(2).unwrap_or(&0),
        ];
        let v = (b[0] as u32) << 16 | (b[1] as u32) << 8 | b[2] as u32;
        for k in 0..4 {
            if k <= chunk.len() {
                out.push(A[(v >> (18 - 6 * k) & 63) as usize] as char);
            } else {
                out.push('=');
            }
        }
    }
    out
}

/// Write the run-up figures into `out_dir` (which must exist): `eps`, `y_journal`, `waterfall_C`,
/// `orbit_C`, `waterfall_T`, `orbit_T`, each as `.svg` and `.png`. Returns the written paths, in
/// that order. The figures are drawn on two threads (each figure's spectrogram, raster and PNG
/// are its own): ~55 ms of path 1's ~110 ms after the co-simulation were figures, one after the
/// other, while the second core waited.
pub fn plot_runup(
    series: &RunSeries,
    class: &Classification,
    bores: &[Bore; 2],
    out_dir: &Path,
) -> std::io::Result<Vec<PathBuf>> {
    use runup_analysis::Bearing;
    series.check();
    let figure = |k: usize| -> std::io::Result<Vec<PathBuf>> {
        match k {
            0 => figures::eps(series, class).save(out_dir, "eps"),
            1 => figures::y_journal(series, class).save(out_dir, "y_journal"),
            2 => figures::waterfall(series, Bearing::C).save(out_dir, "waterfall_C"),
            3 => figures::orbit(series, Bearing::C, &bores[0]).save(out_dir, "orbit_C"),
            4 => figures::waterfall(series, Bearing::T).save(out_dir, "waterfall_T"),
            _ => figures::orbit(series, Bearing::T, &bores[1]).save(out_dir, "orbit_T"),
        }
    };
    let mut out = Vec::new();
    for files in on_two_threads(6, figure) {
        out.extend(files?);
    }
    Ok(out)
}

/// `job(0..n)` on the caller's thread and one more, each taking the next index when it is free;
/// the results in index order. A panic in a job is re-raised on the caller's thread with its own
/// message (the scope alone would report a helper's as "a scoped thread panicked").
fn on_two_threads<T: Send>(n: usize, job: impl Fn(usize) -> T + Sync) -> Vec<T> {
    use std::sync::atomic::{AtomicUsize, Ordering};
    use std::sync::Mutex;
    let next = AtomicUsize::new(0);
    let results: Mutex<Vec<Option<T>>> = Mutex::new((0..n).map(|_| None).collect());
    let work = || loop {
        let k = next.fetch_add(1, Ordering::Relaxed);
        if k >= n {
            break;
        }
        let r = job(k);
        results.lock().unwrap_or_else(|p| p.into_inner())[k] = Some(r);
    };
    std::thread::scope(|s| {
        let helper = s.spawn(work);
        work();
        if let Err(panic) = helper.join() {
            std::panic::resume_unwind(panic);
        }
    });
    results
        .into_inner()
        .unwrap_or_else(|p| p.into_inner())
        .into_iter()
        .map(|r| r.expect("every index was taken by a thread that finished"))
        .collect()
}

/// Write the hysteresis figure (`hysteresis.svg`, `.png`) of a run with a run-down into `out_dir`.
pub fn plot_hysteresis(
    series: &RunSeries,
    h: &runup_analysis::Hysteresis,
    out_dir: &Path,
) -> std::io::Result<Vec<PathBuf>> {
    figures::hysteresis(series, h).save(out_dir, "hysteresis")
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
