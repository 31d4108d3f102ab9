//! An x-y chart: what a figure shows (curves in data coordinates, labels, a colour map, a legend),
//! drawn by plotters: frame, mesh, ticks, tick labels and axis names come from its chart builder.
//! Legends sit outside the frame, on the right, so they never hide data or labels.

use plotters::coord::Shift;
use plotters::element::DashedPathElement;
use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};

use super::font::{self, FAMILY};
use super::svg::{Tag, Tags};
use super::{Anchor, Rgb, Role};

const TITLE_PX: f64 = 17.0;
const TICK_PX: f64 = 13.0;
const DESC_PX: f64 = 14.0;
const LEGEND_PX: f64 = 13.0;
const TOP_PX: u32 = 38;
const RIGHT_PX: u32 = 22;
const X_LABEL_AREA_PX: u32 = 52;
const Y_LABEL_AREA_PX: u32 = 78;
/// Legend: the swatch line and the gaps around it [px].
const LEGEND_SWATCH_PX: i32 = 24;

#[derive(Debug, Clone)]
pub struct Line {
    pub pts: Vec<(f64, f64)>,
    pub color: Rgb,
    pub width: f64,
    pub dashed: bool,
    pub role: Role,
    pub name: String,
}

/// Text at a data point, moved by `offset_px`, kept inside the frame.
#[derive(Debug, Clone)]
pub struct Label {
    pub at: (f64, f64),
    pub offset_px: (i32, i32),
    pub text: String,
    pub size_px: f64,
    pub anchor: Anchor,
    pub color: Rgb,
}

/// A vertical marker across the frame (onset, threshold, critical speed) with an optional label at
/// its top, beside the line on whichever side it fits.
#[derive(Debug, Clone)]
pub struct Marker {
    pub x: f64,
    pub name: String,
    pub label: Option<String>,
}

/// A colour map over the whole frame: `cols` x `rows` RGB cells, row 0 at the top.
#[derive(Debug, Clone)]
pub struct Heatmap {
    pub cols: usize,
    pub rows: usize,
    pub rgb: Vec<u8>,
}

#[derive(Debug, Clone)]
pub struct Chart {
    pub width: u32,
    pub height: u32,
    pub title: String,
    pub x_label: String,
    pub y_label: String,
    pub x: (f64, f64),
    pub y: (f64, f64),
    /// Equal scales on both axes (orbits in the bore).
    pub square: bool,
    pub lines: Vec<Line>,
    pub markers: Vec<Marker>,
    pub labels: Vec<Label>,
    pub heatmap: Option<Heatmap>,
    pub legend: Vec<(String, Rgb)>,
}

impl Chart {
    /// A chart of `width` x `height` pixels whose axes span the data ranges `x`, `y` plus 5 % (a flat
    /// or empty range gets a sensible span).
    pub fn new(
        width: u32,
        height: u32,
        title: &str,
        x_label: &str,
        y_label: &str,
        x: (f64, f64),
        y: (f64, f64),
    ) -> Self {
        Chart {
            width,
            height,
            title: title.into(),
            x_label: x_label.into(),
            y_label: y_label.into(),
            x: widen(x),
            y: widen(y),
            square: false,
            lines: vec![],
            markers: vec![],
            labels: vec![],
            heatmap: None,
            legend: vec![],
        }
    }

    /// The frame's width [px], about: decimation keeps two points per pixel column of it.
    pub fn frame_width_px(&self) -> usize {
        self.width.saturating_sub(Y_LABEL_AREA_PX + RIGHT_PX + 150) as usize
    }

    pub fn line(
        &mut self,
        pts: impl IntoIterator<Item = (f64, f64)>,
        color: Rgb,
        width: f64,
        dashed: bool,
        role: Role,
        name: &str,
    ) {
        self.lines.push(Line {
            pts: pts.into_iter().collect(),
            color,
            width,
            dashed,
            role,
            name: name.into(),
        });
    }

    pub fn marker(&mut self, x: f64, name: &str, label: Option<String>) {
        self.markers.push(Marker {
            x,
            name: name.into(),
            label,
        });
    }

    pub fn label(&mut self, at: (f64, f64), offset_px: (i32, i32), text: &str, anchor: Anchor) {
        self.labels.push(Label {
            at,
            offset_px,
            text: text.into(),
            size_px: TICK_PX,
            anchor,
            color: Rgb::BLACK,
        });
    }

    pub fn legend(&mut self, entries: &[(&str, Rgb)]) {
        self.legend = entries.iter().map(|(n, c)| (n.to_string(), *c)).collect();
    }

    fn legend_width_px(&self) -> u32 {
        let widest = self
            .legend
            .iter()
            .map(|(n, _)| font::text_width_px(n, LEGEND_PX))
            .fold(0.0, f64::max);
        if self.legend.is_empty() {
            0
        } else {
            (widest.ceil() as u32) + LEGEND_SWATCH_PX as u32 + 20
        }
    }

    /// Draw onto `root` (its size is the chart's); the SVG backend reads `tags`.
    pub fn draw<DB: DrawingBackend>(
        &self,
        root: &DrawingArea<DB, Shift>,
        tags: &Tags,
    ) -> Result<(), String> {
        let err = |e: DrawingAreaErrorKind<DB::ErrorType>| e.to_string();
        root.fill(&WHITE).map_err(err)?;
        let mut right = RIGHT_PX + self.legend_width_px();
        let mut bottom = 8;
        if self.square {
            let avail_w = self.width.saturating_sub(Y_LABEL_AREA_PX + 8 + right);
            let avail_h = self
                .height
                .saturating_sub(TOP_PX + X_LABEL_AREA_PX + bottom);
            let side = avail_w.min(avail_h);
            right += avail_w - side;
            bottom += avail_h - side;
        }
        let mut chart = ChartBuilder::on(root)
            .margin_top(TOP_PX)
            .margin_left(8)
            .margin_right(right)
            .margin_bottom(bottom)
            .x_label_area_size(X_LABEL_AREA_PX)
            .y_label_area_size(Y_LABEL_AREA_PX)
            .build_cartesian_2d(self.x.0..self.x.1, self.y.0..self.y.1)
            .map_err(err)?;
        let plot = chart.plotting_area().clone();
        let (px0, px1) = (plot.get_pixel_range().0.start, plot.get_pixel_range().0.end);
        let (py0, py1) = (plot.get_pixel_range().1.start, plot.get_pixel_range().1.end);
        if let Some(h) = &self.heatmap {
            let (w, hh) = ((px1 - px0).max(1) as u32, (py1 - py0).max(1) as u32);
            let buf = resample(h, w, hh);
            if let Some(img) = BitMapElement::with_owned_buffer((self.x.0, self.y.1), (w, hh), buf)
            {
                plot.draw(&img).map_err(err)?;
            }
        }
        let (x_range, y_range) = (self.x, self.y);
        let x_fmt = move |v: &f64| tick_label(*v, x_range);
        let y_fmt = move |v: &f64| tick_label(*v, y_range);
        let mut mesh = chart.configure_mesh();
        mesh.x_desc(&self.x_label)
            .y_desc(&self.y_label)
            .label_style((FAMILY, TICK_PX))
            .axis_desc_style((FAMILY, DESC_PX))
            .bold_line_style(RGBColor(220, 220, 220))
            .light_line_style(TRANSPARENT)
            .x_labels(9)
            .y_labels(7)
            .x_label_formatter(&x_fmt)
            .y_label_formatter(&y_fmt);
        if self.heatmap.is_some() {
            mesh.disable_mesh();
        }
        mesh.draw().map_err(err)?;
        for l in &self.lines {
            if l.pts.is_empty() {
                continue;
            }
            let style = ShapeStyle {
                color: rgb(l.color).to_rgba(),
                filled: false,
                stroke_width: l.width.round().max(1.0) as u32,
            };
            tags.set(Some(Tag {
                role: l.role,
                name: l.name.clone(),
                dashed: l.dashed,
            }));
            let drawn = if l.dashed && !tags.native_dashes {
                plot.draw(&DashedPathElement::new(l.pts.iter().copied(), 6, 4, style))
            } else {
                plot.draw(&PathElement::new(l.pts.clone(), style))
            };
            tags.set(None);
            drawn.map_err(err)?;
        }
        let frame = (px0, py0, px1, py1);
        for m in &self.markers {
            let style = ShapeStyle {
                color: BLACK.to_rgba(),
                filled: false,
                stroke_width: 1,
            };
            let pts = [(m.x, self.y.0), (m.x, self.y.1)];
            tags.set(Some(Tag {
                role: Role::Marker,
                name: m.name.clone(),
                dashed: true,
            }));
            let drawn = if tags.native_dashes {
                plot.draw(&PathElement::new(pts.to_vec(), style))
            } else {
                plot.draw(&DashedPathElement::new(pts, 6, 4, style))
            };
            tags.set(None);
            drawn.map_err(err)?;
            if let Some(text) = &m.label {
                let (mx, _) = chart.backend_coord(&(m.x, self.y.1));
                let w = font::text_width_px(text, TICK_PX).ceil() as i32;
                let (x, h) = if mx + 5 + w <= px1 - 4 {
                    (mx + 5, HPos::Left)
                } else {
                    (mx - 5, HPos::Right)
                };
                draw_text(
                    root,
                    text,
                    TICK_PX,
                    (x, py0 + 6),
                    Pos::new(h, VPos::Top),
                    frame,
                )
                .map_err(err)?;
            }
        }
        for l in &self.labels {
            let (x, y) = chart.backend_coord(&l.at);
            let pos = (x + l.offset_px.0, y + l.offset_px.1);
            let h = match l.anchor {
                Anchor::Start => HPos::Left,
                Anchor::Middle => HPos::Center,
                Anchor::End => HPos::Right,
            };
            let style = (FAMILY, l.size_px).into_font().color(&rgb(l.color));
            let pos = clamp_into(&l.text, l.size_px, pos, Pos::new(h, VPos::Center), frame);
            root.draw(&Text::new(
                l.text.clone(),
                pos,
                style.pos(Pos::new(h, VPos::Center)),
            ))
            .map_err(err)?;
        }
        // The legend: a column right of the frame.
        let lx = px1 + 14;
        for (i, (name, color)) in self.legend.iter().enumerate() {
            let y = py0 + 10 + 20 * i as i32;
            root.draw(&PathElement::new(
                vec![(lx, y), (lx + LEGEND_SWATCH_PX - 6, y)],
                ShapeStyle {
                    color: rgb(*color).to_rgba(),
                    filled: false,
                    stroke_width: 3,
                },
            ))
            .map_err(err)?;
            let style = TextStyle::from((FAMILY, LEGEND_PX).into_font())
                .pos(Pos::new(HPos::Left, VPos::Center));
            root.draw(&Text::new(name.clone(), (lx + LEGEND_SWATCH_PX, y), style))
                .map_err(err)?;
        }
        // The title: centred over the frame, or from the left edge when it is wider.
        let tw = font::text_width_px(&self.title, TITLE_PX).ceil() as i32;
        let cx = (px0 + px1) / 2;
        let (x, h) = if cx - tw / 2 >= 6 && cx + tw / 2 <= self.width as i32 - 6 {
            (cx, HPos::Center)
        } else {
            (6, HPos::Left)
        };
        let style = TextStyle::from((FAMILY, TITLE_PX).into_font()).pos(Pos::new(h, VPos::Center));
        root.draw(&Text::new(
            self.title.clone(),
            (x, TOP_PX as i32 / 2),
            style,
        ))
        .map_err(err)?;
        Ok(())
    }
}

/// Text at `pos` moved so that its box stays inside `frame` (x0, y0, x1, y1).
fn clamp_into(
    text: &str,
    size: f64,
    pos: (i32, i32),
    anchor: Pos,
    (x0, y0, x1, y1): (i32, i32, i32, i32),
) -> (i32, i32) {
    let w = font::text_width_px(text, size).ceil() as i32;
    let h = (size / 1.24) as i32 + 2;
    let left = match anchor.h_pos {
        HPos::Left => pos.0,
        HPos::Center => pos.0 - w / 2,
        HPos::Right => pos.0 - w,
    };
    let dx = if left < x0 + 2 {
        x0 + 2 - left
    } else if left + w > x1 - 2 {
        x1 - 2 - (left + w)
    } else {
        0
    };
    let dy = if pos.1 - h / 2 < y0 + 2 {
        y0 + 2 - (pos.1 - h / 2)
    } else if pos.1 + h / 2 > y1 - 2 {
        y1 - 2 - (pos.1 + h / 2)
    } else {
        0
    };
    (pos.0 + dx, pos.1 + dy)
}

fn draw_text<DB: DrawingBackend>(
    root: &DrawingArea<DB, Shift>,
    text: &str,
    size: f64,
    pos: (i32, i32),
    anchor: Pos,
    frame: (i32, i32, i32, i32),
) -> Result<(), DrawingAreaErrorKind<DB::ErrorType>> {
    let pos = clamp_into(text, size, pos, anchor, frame);
    let style = TextStyle::from((FAMILY, size).into_font()).pos(anchor);
    root.draw(&Text::new(text.to_string(), pos, style))
}

/// A tick value with the decimals its axis needs ("500", "0.25", "-0.1"), never "500.0" or "-0".
fn tick_label(v: f64, (lo, hi): (f64, f64)) -> String {
    let span = (hi - lo).abs().max(f64::MIN_POSITIVE);
    // Ticks are at least span / 20 apart: two decimals below that step's leading digit suffice.
    let decimals = (2.0 - (span / 20.0).log10().floor()).clamp(0.0, 12.0) as usize;
    let s = format!("{v:.decimals$}");
    let s = if s.contains('.') {
        s.trim_end_matches('0').trim_end_matches('.').to_string()
    } else {
        s
    };
    if s == "-0" {
        "0".into()
    } else {
        s
    }
}

pub fn rgb(c: Rgb) -> RGBColor {
    RGBColor(c.0, c.1, c.2)
}

/// Nearest-neighbour resampling of the colour map's cells onto `w` x `h` pixels (RGB).
fn resample(h: &Heatmap, w: u32, hh: u32) -> Vec<u8> {
    let mut out = Vec::with_capacity((w * hh * 3) as usize);
    for py in 0..hh as usize {
        let row = (py * h.rows / hh as usize).min(h.rows.saturating_sub(1));
        for px in 0..w as usize {
            let col = (px * h.cols / w as usize).min(h.cols.saturating_sub(1));
            let i = 3 * (row * h.cols + col);
            out.extend_from_slice(h.rgb.get(i..i + 3).unwrap_or(&[255, 255, 255]));
        }
    }
    out
}

/// Avoid a zero-width range (a flat signal) and add 5% margins.
pub fn widen((lo, hi): (f64, f64)) -> (f64, f64) {
    if !(lo.is_finite() && hi.is_finite()) || hi < lo {
        return (0.0, 1.0);
    }
    let span = hi - lo;
    if span <= 1e-12 * lo.abs().max(hi.abs()).max(1e-300) {
        let d = if lo == 0.0 { 1.0 } else { 0.1 * lo.abs() };
        return (lo - d, hi + d);
    }
    (lo - 0.05 * span, hi + 0.05 * span)
}

/// Keep the envelope of a long time series: for each of `buckets` equal slices of x, the minimum and the
/// maximum in the order they occur. A 3 s run at 10 us output has 300 000 samples; 2 per pixel column
/// draw the same picture.
pub fn decimate_minmax(xs: &[f64], ys: &[f64], buckets: usize) -> Vec<(f64, f64)> {
    let n = xs.len().min(ys.len());
    if n <= 2 * buckets.max(1) {
        return xs.iter().zip(ys).map(|(x, y)| (*x, *y)).collect();
    }
    let mut out = Vec::with_capacity(2 * buckets);
    for b in 0..buckets {
        let (i0, i1) = (b * n / buckets, ((b + 1) * n / buckets).min(n));
        if i0 >= i1 {
            continue;
        }
        let (mut imin, mut imax) = (i0, i0);
        for i in i0..i1 {
            if ys[i] < ys[imin] {
                imin = i;
            }
            if ys[i] > ys[imax] {
                imax = i;
            }
        }
        let (a, b) = if imin <= imax {
            (imin, imax)
        } else {
            (imax, imin)
        };
        out.push((xs[a], ys[a]));
        if b != a {
            out.push((xs[b], ys[b]));
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn decimation_keeps_extremes() {
        let xs: Vec<f64> = (0..10_000).map(|i| i as f64).collect();
        let ys: Vec<f64> = xs
            .iter()
            .map(|x| (x * 0.37).sin() + if *x == 5003.0 { 7.0 } else { 0.0 })
            .collect();
        let d = decimate_minmax(&xs, &ys, 100);
        assert!(d.len() <= 200);
        assert!(d.iter().any(|p| p.0 == 5003.0 && p.1 > 6.0));
        assert!(d.windows(2).all(|w| w[0].0 < w[1].0));
    }

    #[test]
    fn tick_labels_are_short_and_exact() {
        assert_eq!(tick_label(500.0, (0.0, 3000.0)), "500");
        assert_eq!(tick_label(0.25, (0.0, 1.0)), "0.25");
        assert_eq!(tick_label(-1e-17, (-1.0, 1.0)), "0");
        assert_eq!(tick_label(0.0005, (0.0, 0.002)), "0.0005");
        assert_eq!(tick_label(1150.0, (1000.0, 1200.0)), "1150");
    }

    #[test]
    fn flat_empty_and_reversed_ranges_get_a_span() {
        assert_eq!(widen((0.0, 0.0)), (-1.0, 1.0));
        assert_eq!(widen((f64::INFINITY, f64::NEG_INFINITY)), (0.0, 1.0));
        let (lo, hi) = widen((2.0, 2.0));
        assert!(lo < 2.0 && hi > 2.0);
        assert_eq!(widen((0.0, 10.0)), (-0.5, 10.5));
    }
}
