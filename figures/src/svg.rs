//! The SVG twin of a figure: a plotters drawing backend that writes SVG elements, so SVG and PNG come
//! from one drawing. Unlike plotters' own SVG backend it
//! - tags what the figure marks as data (`class="series" data-name="eps_C"`, `class="lobe"`, ...), so
//!   tests and users' scripts can find a curve by what it is, and draws dashed curves as one element;
//! - places text exactly where the PNG has it (baseline, CSS size from the embedded font's metrics), so
//!   a layout test on the SVG holds for the PNG;
//! - embeds bitmaps (the waterfall's colour map) as standard `data:image/png` URIs.

use std::cell::RefCell;
use std::fmt::Write as _;
use std::rc::Rc;

use plotters_backend::text_anchor::{HPos, VPos};
use plotters_backend::{
    BackendColor, BackendCoord, BackendStyle, BackendTextStyle, DrawingBackend, DrawingErrorKind,
    FontTransform,
};

use super::font;
use super::Role;

/// What the next drawn shapes are (set by the figure code around a draw call).
#[derive(Debug, Clone)]
pub struct Tag {
    pub role: Role,
    pub name: String,
    pub dashed: bool,
}

/// The figure's side of the tagging: a shared slot the SVG backend reads. The PNG backend ignores it,
/// so `native_dashes` tells the figure code whether to draw dashes itself.
#[derive(Clone, Default)]
pub struct Tags {
    slot: Rc<RefCell<Option<Tag>>>,
    pub native_dashes: bool,
}

impl Tags {
    /// Tags read by an SVG backend, which draws dashes itself.
    pub fn for_svg() -> Self {
        Tags {
            slot: Rc::default(),
            native_dashes: true,
        }
    }
    pub fn set(&self, tag: Option<Tag>) {
        *self.slot.borrow_mut() = tag;
    }
    fn get(&self) -> Option<Tag> {
        self.slot.borrow().clone()
    }
}

/// Writes into a shared string, because a plotters drawing area owns its backend to the end.
pub struct SvgBackend {
    width: u32,
    height: u32,
    sink: Rc<RefCell<String>>,
    out: String,
    tags: Tags,
}

#[derive(Debug)]
pub struct SvgError;

impl std::fmt::Display for SvgError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str("SVG drawing failed")
    }
}
impl std::error::Error for SvgError {}

fn color(c: BackendColor) -> String {
    format!("#{:02x}{:02x}{:02x}", c.rgb.0, c.rgb.1, c.rgb.2)
}

fn opacity(c: BackendColor) -> String {
    if c.alpha >= 1.0 {
        String::new()
    } else {
        format!(r#" opacity="{:.3}""#, c.alpha)
    }
}

pub fn xml_escape(s: &str) -> String {
    s.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
        .replace('"', "&quot;")
}

impl SvgBackend {
    /// A page of `width` x `height` pixels whose SVG text goes to `sink` (whole when the backend is
    /// dropped); `tags` is the slot the figure code sets.
    pub fn new(width: u32, height: u32, tags: Tags, sink: Rc<RefCell<String>>) -> Self {
        let mut out = String::new();
        let _ = writeln!(
            out,
            r#"<svg xmlns="http://www.w3.org/2000/svg" width="{width}" height="{height}" viewBox="0 0 {width} {height}" font-family="DejaVu Sans, Verdana, sans-serif">"#
        );
        SvgBackend {
            width,
            height,
            sink,
            out,
            tags,
        }
    }

    fn tag_attrs(&self) -> (String, bool) {
        match self.tags.get() {
            Some(t) => (
                format!(
                    r#" class="{}" data-name="{}""#,
                    t.role.class(),
                    xml_escape(&t.name)
                ),
                t.dashed,
            ),
            None => (String::new(), false),
        }
    }
}

impl Drop for SvgBackend {
    fn drop(&mut self) {
        self.out.push_str("</svg>\n");
        *self.sink.borrow_mut() = std::mem::take(&mut self.out);
    }
}

type Result<T> = std::result::Result<T, DrawingErrorKind<SvgError>>;

impl DrawingBackend for SvgBackend {
    type ErrorType = SvgError;

    fn get_size(&self) -> (u32, u32) {
        (self.width, self.height)
    }

    fn ensure_prepared(&mut self) -> Result<()> {
        Ok(())
    }

    fn present(&mut self) -> Result<()> {
        Ok(())
    }

    fn draw_pixel(&mut self, p: BackendCoord, c: BackendColor) -> Result<()> {
        if c.alpha > 0.0 {
            let _ = writeln!(
                self.out,
                r#"<rect x="{}" y="{}" width="1" height="1" fill="{}"{}/>"#,
                p.0,
                p.1,
                color(c),
                opacity(c)
            );
        }
        Ok(())
    }

    fn draw_line<S: BackendStyle>(
        &mut self,
        a: BackendCoord,
        b: BackendCoord,
        s: &S,
    ) -> Result<()> {
        self.draw_path([a, b], s)
    }

    fn draw_rect<S: BackendStyle>(
        &mut self,
        a: BackendCoord,
        b: BackendCoord,
        s: &S,
        fill: bool,
    ) -> Result<()> {
        let c = s.color();
        let panel = matches!(
            self.tags.get(),
            Some(Tag {
                role: Role::Panel,
                ..
            })
        );
        if panel {
            // Invisible; it keeps a panel's bounds for layout checks.
            let _ = writeln!(
                self.out,
                r#"<rect class="panel" x="{}" y="{}" width="{}" height="{}" fill="none" stroke="none"/>"#,
                a.0.min(b.0),
                a.1.min(b.1),
                (b.0 - a.0).abs(),
                (b.1 - a.1).abs()
            );
            return Ok(());
        }
        if c.alpha == 0.0 {
            return Ok(());
        }
        let (tag, _) = self.tag_attrs();
        let paint = if fill {
            format!(r#"fill="{}" stroke="none""#, color(c))
        } else {
            format!(
                r#"fill="none" stroke="{}" stroke-width="{}""#,
                color(c),
                s.stroke_width()
            )
        };
        let _ = writeln!(
            self.out,
            r#"<rect{tag} x="{}" y="{}" width="{}" height="{}" {paint}{}/>"#,
            a.0.min(b.0),
            a.1.min(b.1),
            (b.0 - a.0).abs(),
            (b.1 - a.1).abs(),
            opacity(c)
        );
        Ok(())
    }

    fn draw_path<S: BackendStyle, I: IntoIterator<Item = BackendCoord>>(
        &mut self,
        path: I,
        s: &S,
    ) -> Result<()> {
        let c = s.color();
        if c.alpha == 0.0 {
            return Ok(());
        }
        let (tag, dashed) = self.tag_attrs();
        let dash = if dashed {
            r#" stroke-dasharray="6 4""#
        } else {
            ""
        };
        let _ = write!(
            self.out,
            r#"<polyline{tag} fill="none" stroke="{}" stroke-width="{}"{dash}{} points=""#,
            color(c),
            s.stroke_width(),
            opacity(c)
        );
        for (i, (x, y)) in path.into_iter().enumerate() {
            let sep = if i > 0 { " " } else { "" };
            let _ = write!(self.out, "{sep}{x},{y}");
        }
        self.out.push_str("\"/>\n");
        Ok(())
    }

    fn fill_polygon<S: BackendStyle, I: IntoIterator<Item = BackendCoord>>(
        &mut self,
        vert: I,
        s: &S,
    ) -> Result<()> {
        let c = s.color();
        if c.alpha == 0.0 {
            return Ok(());
        }
        let pts: Vec<String> = vert.into_iter().map(|(x, y)| format!("{x},{y}")).collect();
        let _ = writeln!(
            self.out,
            r#"<polygon fill="{}" stroke="none"{} points="{}"/>"#,
            color(c),
            opacity(c),
            pts.join(" ")
        );
        Ok(())
    }

    fn draw_circle<S: BackendStyle>(
        &mut self,
        center: BackendCoord,
        radius: u32,
        s: &S,
        fill: bool,
    ) -> Result<()> {
        let c = s.color();
        if c.alpha == 0.0 {
            return Ok(());
        }
        let paint = if fill {
            format!(r#"fill="{}""#, color(c))
        } else {
            format!(r#"fill="none" stroke="{}""#, color(c))
        };
        let _ = writeln!(
            self.out,
            r#"<circle cx="{}" cy="{}" r="{radius}" {paint}{}/>"#,
            center.0,
            center.1,
            opacity(c)
        );
        Ok(())
    }

    /// The text where plotters' raster puts it: the layout box (width from the font's advances, height
    /// size / 1.24) is offset by the anchor in the text's own frame, the baseline sits size / 2 below
    /// the box's top (plotters' ab_glyph rasterizer), and the frame turns about `pos`.
    fn draw_text<S: BackendTextStyle>(
        &mut self,
        text: &str,
        s: &S,
        pos: BackendCoord,
    ) -> Result<()> {
        let c = s.color();
        if c.alpha == 0.0 {
            return Ok(());
        }
        let size = s.size();
        let ((min_x, min_y), (max_x, max_y)) = s
            .layout_box(text)
            .map_err(|e| DrawingErrorKind::FontError(Box::new(e)))?;
        let (w, h) = (max_x - min_x, max_y - min_y);
        let dx = match s.anchor().h_pos {
            HPos::Left => 0,
            HPos::Right => -w,
            HPos::Center => -w / 2,
        };
        let dy = match s.anchor().v_pos {
            VPos::Top => 0,
            VPos::Center => -h / 2,
            VPos::Bottom => -h,
        };
        let x = pos.0 + dx - min_x;
        let y = f64::from(pos.1 + dy - min_y) + (size / 2.0).trunc();
        let rotate = match s.transform() {
            FontTransform::None => String::new(),
            FontTransform::Rotate90 => format!(r#" transform="rotate(90 {} {})""#, pos.0, pos.1),
            FontTransform::Rotate180 => format!(r#" transform="rotate(180 {} {})""#, pos.0, pos.1),
            FontTransform::Rotate270 => format!(r#" transform="rotate(270 {} {})""#, pos.0, pos.1),
        };
        let _ = writeln!(
            self.out,
            r#"<text x="{x}" y="{y}" font-size="{:.2}" fill="{}"{}{rotate}>{}</text>"#,
            font::em_px(size),
            color(c),
            opacity(c),
            xml_escape(text)
        );
        Ok(())
    }

    fn blit_bitmap(&mut self, pos: BackendCoord, (w, h): (u32, u32), src: &[u8]) -> Result<()> {
        let png =
            super::encode_png(w, h, src).map_err(|_| DrawingErrorKind::DrawingError(SvgError))?;
        let _ = writeln!(
            self.out,
            r#"<image x="{}" y="{}" width="{w}" height="{h}" style="image-rendering:pixelated" href="data:image/png;base64,{}"/>"#,
            pos.0,
            pos.1,
            super::base64(&png)
        );
        Ok(())
    }
}
