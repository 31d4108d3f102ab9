//! A free layout in pixels (the bifurcation maps: panels of coloured cells, labels, a legend), drawn
//! with plotters' rectangles and text in the embedded font. Layout code measures its text with
//! `font::text_width_px`, the same metrics the drawing uses.

use plotters::coord::Shift;
use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};

use super::chart::rgb;
use super::font::FAMILY;
use super::svg::{Tag, Tags};
use super::{Anchor, Rgb, Role};

#[derive(Debug, Clone)]
pub enum Item {
    Rect {
        x: f64,
        y: f64,
        w: f64,
        h: f64,
        fill: Option<Rgb>,
        stroke: Option<Rgb>,
        /// A panel's area: tagged `class="panel"` in the SVG (text must not cross its border).
        panel: bool,
    },
    /// Text centred vertically on `y`; `vertical` turns it to read upwards.
    Text {
        x: f64,
        y: f64,
        text: String,
        size_px: f64,
        anchor: Anchor,
        vertical: bool,
    },
}

#[derive(Debug, Clone)]
pub struct Scene {
    pub width: u32,
    pub height: u32,
    pub items: Vec<Item>,
}

impl Scene {
    pub fn new(width: u32, height: u32) -> Self {
        Scene {
            width,
            height,
            items: vec![],
        }
    }

    pub fn rect(
        &mut self,
        (x, y, w, h): (f64, f64, f64, f64),
        fill: Option<Rgb>,
        stroke: Option<Rgb>,
    ) {
        self.items.push(Item::Rect {
            x,
            y,
            w,
            h,
            fill,
            stroke,
            panel: false,
        });
    }

    pub fn panel(&mut self, (x, y, w, h): (f64, f64, f64, f64)) {
        self.items.push(Item::Rect {
            x,
            y,
            w,
            h,
            fill: None,
            stroke: None,
            panel: true,
        });
    }

    pub fn text(&mut self, x: f64, y: f64, text: &str, size_px: f64, anchor: Anchor) {
        self.items.push(Item::Text {
            x,
            y,
            text: text.into(),
            size_px,
            anchor,
            vertical: false,
        });
    }

    pub fn vtext(&mut self, x: f64, y: f64, text: &str, size_px: f64) {
        self.items.push(Item::Text {
            x,
            y,
            text: text.into(),
            size_px,
            anchor: Anchor::Middle,
            vertical: true,
        });
    }

    pub fn draw<DB: DrawingBackend>(
        &self,
        root: &DrawingArea<DB, Shift>,
        tags: &Tags,
    ) -> Result<(), String> {
        let err = |e: DrawingAreaErrorKind<DB::ErrorType>| e.to_string();
        root.fill(&WHITE).map_err(err)?;
        let px = |v: f64| v.round() as i32;
        for item in &self.items {
            match item {
                Item::Rect {
                    x,
                    y,
                    w,
                    h,
                    fill,
                    stroke,
                    panel,
                } => {
                    let corners = [(px(*x), px(*y)), (px(x + w), px(y + h))];
                    if *panel {
                        // Invisible in the picture; the SVG keeps the panel's bounds.
                        tags.set(Some(Tag {
                            role: Role::Panel,
                            name: String::new(),
                            dashed: false,
                        }));
                        let r = root.draw(&Rectangle::new(corners, TRANSPARENT.stroke_width(0)));
                        tags.set(None);
                        r.map_err(err)?;
                        continue;
                    }
                    if let Some(f) = fill {
                        root.draw(&Rectangle::new(corners, rgb(*f).filled()))
                            .map_err(err)?;
                    }
                    if let Some(s) = stroke {
                        root.draw(&Rectangle::new(corners, rgb(*s).stroke_width(1)))
                            .map_err(err)?;
                    }
                }
                Item::Text {
                    x,
                    y,
                    text,
                    size_px,
                    anchor,
                    vertical,
                } => {
                    let h = match anchor {
                        Anchor::Start => HPos::Left,
                        Anchor::Middle => HPos::Center,
                        Anchor::End => HPos::Right,
                    };
                    let mut font = (FAMILY, *size_px).into_font();
                    if *vertical {
                        font = font.transform(FontTransform::Rotate270);
                    }
                    let style = TextStyle::from(font).pos(Pos::new(h, VPos::Center));
                    root.draw(&Text::new(text.clone(), (px(*x), px(*y)), style))
                        .map_err(err)?;
                }
            }
        }
        Ok(())
    }
}
