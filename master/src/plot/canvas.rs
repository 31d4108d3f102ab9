//! A tiny drawing model written out twice: as SVG text and as a PNG raster (tiny-skia, with an 8x8 bitmap
//! font so the PNG needs no system fonts). Coordinates are pixels, y downwards.

use std::fmt::Write as _;
use std::path::Path;

use tiny_skia::{
    FillRule, FilterQuality, Paint, PathBuilder, Pixmap, PixmapPaint, Rect, Stroke, StrokeDash,
    Transform,
};

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Rgb(pub u8, pub u8, pub u8);

impl Rgb {
    pub const BLACK: Rgb = Rgb(0, 0, 0);
    pub const WHITE: Rgb = Rgb(255, 255, 255);
    pub const GREY: Rgb = Rgb(200, 200, 200);
    pub const BLUE: Rgb = Rgb(31, 119, 180);
    pub const RED: Rgb = Rgb(214, 39, 40);
    pub const GREEN: Rgb = Rgb(44, 160, 44);

    fn hex(self) -> String {
        format!("#{:02x}{:02x}{:02x}", self.0, self.1, self.2)
    }
}

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Anchor {
    Start,
    Middle,
    End,
}

/// What a polyline is, written as its SVG class: tests count the data series by it.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Role {
    Series,
    Lobe,
    Reference,
    Marker,
    Axis,
}

impl Role {
    fn class(self) -> &'static str {
        match self {
            Role::Series => "series",
            Role::Lobe => "lobe",
            Role::Reference => "ref",
            Role::Marker => "marker",
            Role::Axis => "axis",
        }
    }
}

#[derive(Debug, Clone)]
pub enum Item {
    Polyline {
        pts: Vec<(f64, f64)>,
        color: Rgb,
        width: f64,
        dashed: bool,
        role: Role,
        name: String,
    },
    Rect {
        x: f64,
        y: f64,
        w: f64,
        h: f64,
        fill: Option<Rgb>,
        stroke: Option<Rgb>,
    },
    Text {
        x: f64,
        y: f64,
        text: String,
        size: f64,
        anchor: Anchor,
        vertical: bool,
        color: Rgb,
    },
    /// An RGBA image of cols x rows cells stretched over the rectangle (the waterfall colour map).
    Image {
        x: f64,
        y: f64,
        w: f64,
        h: f64,
        cols: u32,
        rows: u32,
        rgba: Vec<u8>,
    },
}

#[derive(Debug, Clone)]
pub struct Canvas {
    pub width: u32,
    pub height: u32,
    pub items: Vec<Item>,
}

impl Canvas {
    pub fn new(width: u32, height: u32) -> Self {
        Canvas {
            width,
            height,
            items: Vec::new(),
        }
    }

    pub fn polyline(
        &mut self,
        pts: Vec<(f64, f64)>,
        color: Rgb,
        width: f64,
        dashed: bool,
        role: Role,
        name: &str,
    ) {
        self.items.push(Item::Polyline {
            pts,
            color,
            width,
            dashed,
            role,
            name: name.to_string(),
        });
    }

    pub fn text(&mut self, x: f64, y: f64, text: &str, size: f64, anchor: Anchor) {
        self.items.push(Item::Text {
            x,
            y,
            text: text.to_string(),
            size,
            anchor,
            vertical: false,
            color: Rgb::BLACK,
        });
    }

    pub fn vtext(&mut self, x: f64, y: f64, text: &str, size: f64) {
        self.items.push(Item::Text {
            x,
            y,
            text: text.to_string(),
            size,
            anchor: Anchor::Middle,
            vertical: true,
            color: Rgb::BLACK,
        });
    }

    pub fn to_svg(&self) -> String {
        let mut s = String::new();
        let _ = writeln!(
            s,
            r#"<svg xmlns="http://www.w3.org/2000/svg" width="{w}" height="{h}" viewBox="0 0 {w} {h}" font-family="sans-serif">"#,
            w = self.width,
            h = self.height
        );
        let _ = writeln!(s, r#"<rect width="100%" height="100%" fill="white"/>"#);
        for item in &self.items {
            match item {
                Item::Polyline {
                    pts,
                    color,
                    width,
                    dashed,
                    role,
                    name,
                } => {
                    let _ = write!(
                        s,
                        r#"<polyline class="{}" data-name="{}" fill="none" stroke="{}" stroke-width="{width}"{} points=""#,
                        role.class(),
                        xml_escape(name),
                        color.hex(),
                        if *dashed {
                            r#" stroke-dasharray="6 4""#
                        } else {
                            ""
                        }
                    );
                    for (i, (x, y)) in pts.iter().enumerate() {
                        let _ = write!(s, "{}{:.1},{:.1}", if i > 0 { " " } else { "" }, x, y);
                    }
                    let _ = writeln!(s, r#""/>"#);
                }
                Item::Rect {
                    x,
                    y,
                    w,
                    h,
                    fill,
                    stroke,
                } => {
                    let _ = writeln!(
                        s,
                        r#"<rect x="{x:.1}" y="{y:.1}" width="{w:.1}" height="{h:.1}" fill="{}" stroke="{}"/>"#,
                        fill.map_or("none".to_string(), Rgb::hex),
                        stroke.map_or("none".to_string(), Rgb::hex)
                    );
                }
                Item::Text {
                    x,
                    y,
                    text,
                    size,
                    anchor,
                    vertical,
                    color,
                } => {
                    let a = match anchor {
                        Anchor::Start => "start",
                        Anchor::Middle => "middle",
                        Anchor::End => "end",
                    };
                    let rot = if *vertical {
                        format!(r#" transform="rotate(-90 {x:.1} {y:.1})""#)
                    } else {
                        String::new()
                    };
                    let _ = writeln!(
                        s,
                        r#"<text x="{x:.1}" y="{y:.1}" font-size="{size}" text-anchor="{a}" fill="{}"{rot}>{}</text>"#,
                        color.hex(),
                        xml_escape(text)
                    );
                }
                Item::Image {
                    x,
                    y,
                    w,
                    h,
                    cols,
                    rows,
                    rgba,
                } => {
                    let png = cells_pixmap(*cols, *rows, rgba)
                        .and_then(|p| p.encode_png().ok())
                        .unwrap_or_default();
                    let _ = writeln!(
                        s,
                        r#"<image x="{x:.1}" y="{y:.1}" width="{w:.1}" height="{h:.1}" preserveAspectRatio="none" style="image-rendering:pixelated" href="data:image/png;base64,{}"/>"#,
                        base64(&png)
                    );
                }
            }
        }
        s.push_str("</svg>\n");
        s
    }

    /// Rasterize to a pixmap (white background).
    pub fn to_pixmap(&self) -> Option<Pixmap> {
        let mut pm = Pixmap::new(self.width, self.height)?;
        pm.fill(tiny_skia::Color::WHITE);
        for item in &self.items {
            match item {
                Item::Polyline {
                    pts,
                    color,
                    width,
                    dashed,
                    ..
                } => {
                    if pts.len() < 2 {
                        continue;
                    }
                    let mut pb = PathBuilder::new();
                    pb.move_to(pts[0].0 as f32, pts[0].1 as f32);
                    for p in &pts[1..] {
                        pb.line_to(p.0 as f32, p.1 as f32);
                    }
                    let Some(path) = pb.finish() else { continue };
                    let mut stroke = Stroke {
                        width: *width as f32,
                        ..Stroke::default()
                    };
                    if *dashed {
                        stroke.dash = StrokeDash::new(vec![6.0, 4.0], 0.0);
                    }
                    pm.stroke_path(&path, &paint(*color), &stroke, Transform::identity(), None);
                }
                Item::Rect {
                    x,
                    y,
                    w,
                    h,
                    fill,
                    stroke,
                } => {
                    let Some(r) = Rect::from_xywh(*x as f32, *y as f32, *w as f32, *h as f32)
                    else {
                        continue;
                    };
                    if let Some(f) = fill {
                        pm.fill_rect(r, &paint(*f), Transform::identity(), None);
                    }
                    if let Some(sc) = stroke {
                        let path = PathBuilder::from_rect(r);
                        pm.stroke_path(
                            &path,
                            &paint(*sc),
                            &Stroke::default(),
                            Transform::identity(),
                            None,
                        );
                    }
                }
                Item::Text {
                    x,
                    y,
                    text,
                    size,
                    anchor,
                    vertical,
                    color,
                } => {
                    draw_text(&mut pm, *x, *y, text, *size, *anchor, *vertical, *color);
                }
                Item::Image {
                    x,
                    y,
                    w,
                    h,
                    cols,
                    rows,
                    rgba,
                } => {
                    let Some(cells) = cells_pixmap(*cols, *rows, rgba) else {
                        continue;
                    };
                    let t = Transform::from_row(
                        (*w / *cols as f64) as f32,
                        0.0,
                        0.0,
                        (*h / *rows as f64) as f32,
                        *x as f32,
                        *y as f32,
                    );
                    let pp = PixmapPaint {
                        quality: FilterQuality::Nearest,
                        ..PixmapPaint::default()
                    };
                    pm.draw_pixmap(0, 0, cells.as_ref(), &pp, t, None);
                }
            }
        }
        Some(pm)
    }

    /// Write `<stem>.svg` and `<stem>.png` into `dir`; returns both paths.
    pub fn save(&self, dir: &Path, stem: &str) -> std::io::Result<Vec<std::path::PathBuf>> {
        // Whole files or none (a full disk must not leave empty figures behind).
        let write = |path: &Path, bytes: &[u8]| {
            crate::output::write_whole(path, bytes).map_err(std::io::Error::other)
        };
        let svg = dir.join(format!("{stem}.svg"));
        write(&svg, self.to_svg().as_bytes())?;
        let png = dir.join(format!("{stem}.png"));
        let pm = self
            .to_pixmap()
            .ok_or_else(|| std::io::Error::other("plot: cannot allocate the raster"))?;
        let bytes = pm.encode_png().map_err(std::io::Error::other)?;
        write(&png, &bytes)?;
        Ok(vec![svg, png])
    }
}

fn paint(c: Rgb) -> Paint<'static> {
    let mut p = Paint::default();
    p.set_color_rgba8(c.0, c.1, c.2, 255);
    p.anti_alias = true;
    p
}

fn cells_pixmap(cols: u32, rows: u32, rgba: &[u8]) -> Option<Pixmap> {
    if rgba.len() != (cols * rows * 4) as usize {
        return None;
    }
    Pixmap::from_vec(rgba.to_vec(), tiny_skia::IntSize::from_wh(cols, rows)?)
}

/// Text in the PNG: 8x8 bitmap glyphs (font8x8, public domain) scaled to `size`. The glyphs are drawn
/// pixel by pixel as small squares, so any scale and the vertical orientation are one transform.
fn draw_text(
    pm: &mut Pixmap,
    x: f64,
    y: f64,
    text: &str,
    size: f64,
    anchor: Anchor,
    vertical: bool,
    color: Rgb,
) {
    let scale = (size / 8.0 * 0.85) as f32; // the glyph cell is 8 units; SVG font sizes run a bit larger
    let n = text.chars().count() as f32;
    let width = n * 8.0 * scale;
    let dx = match anchor {
        Anchor::Start => 0.0,
        Anchor::Middle => -0.5 * width,
        Anchor::End => -width,
    };
    // Baseline at y: the glyph cell's bottom row sits one unit below it.
    let base = Transform::from_translate(x as f32, y as f32);
    let rot = if vertical {
        Transform::from_rotate(-90.0)
    } else {
        Transform::identity()
    };
    let t = base
        .pre_concat(rot)
        .pre_translate(dx, -7.0 * scale)
        .pre_scale(scale, scale);
    let p = paint(color);
    let mut pb = PathBuilder::new();
    for (ci, ch) in text.chars().enumerate() {
        let code = ch as usize;
        let glyph = if code < 128 {
            font8x8::legacy::BASIC_LEGACY[code]
        } else {
            font8x8::legacy::BASIC_LEGACY[b'?' as usize]
        };
        for (row, bits) in glyph.iter().enumerate() {
            for col in 0..8 {
                if bits & (1 << col) != 0 {
                    if let Some(r) = Rect::from_xywh((ci * 8 + col) as f32, row as f32, 1.0, 1.0) {
                        pb.push_rect(r);
                    }
                }
            }
        }
    }
    if let Some(path) = pb.finish() {
        pm.fill_path(&path, &p, FillRule::Winding, t, None);
    }
}

fn xml_escape(s: &str) -> String {
    s.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
        .replace('"', "&quot;")
}

/// Standard base64 (RFC 4648) for the data URI of the embedded colour map.
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

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn base64_known_vectors() {
        assert_eq!(base64(b""), "");
        assert_eq!(base64(b"f"), "Zg==");
        assert_eq!(base64(b"fo"), "Zm8=");
        assert_eq!(base64(b"foo"), "Zm9v");
        assert_eq!(base64(b"foobar"), "Zm9vYmFy");
    }

    #[test]
    fn text_is_rasterized_without_system_fonts() {
        let mut c = Canvas::new(60, 20);
        c.text(2.0, 14.0, "1150", 12.0, Anchor::Start);
        let pm = c.to_pixmap().unwrap();
        let dark = pm.pixels().iter().filter(|p| p.red() < 128).count();
        assert!(dark > 20, "only {dark} dark pixels");
    }
}
