//! Layout check of a written SVG figure: every text's box (its width from the embedded font's advances,
//! its height the font's ascent and descent around the baseline, turned with its `transform`) lies
//! inside the figure, overlaps no other text, and, where it touches a map panel (`class="panel"`),
//! lies inside that panel. Tests run it on every figure kind.

use super::font;

#[derive(Debug, Clone, Copy)]
pub struct BoxPx {
    pub x0: f64,
    pub y0: f64,
    pub x1: f64,
    pub y1: f64,
}

impl BoxPx {
    fn overlap(&self, o: &BoxPx, tol: f64) -> bool {
        self.x0 + tol < o.x1 && o.x0 + tol < self.x1 && self.y0 + tol < o.y1 && o.y0 + tol < self.y1
    }
    fn inside(&self, o: &BoxPx, tol: f64) -> bool {
        self.x0 >= o.x0 - tol
            && self.x1 <= o.x1 + tol
            && self.y0 >= o.y0 - tol
            && self.y1 <= o.y1 + tol
    }
}

fn num(n: roxmltree::Node, a: &str) -> f64 {
    n.attribute(a).and_then(|v| v.parse().ok()).unwrap_or(0.0)
}

/// The boxes of all texts in `svg`, with their strings.
pub fn text_boxes(svg: &str) -> Result<Vec<(String, BoxPx)>, String> {
    let doc = roxmltree::Document::parse(svg).map_err(|e| e.to_string())?;
    let mut out = vec![];
    for n in doc.descendants().filter(|n| n.has_tag_name("text")) {
        let text = n.text().unwrap_or("").to_string();
        let (x, y, em) = (num(n, "x"), num(n, "y"), num(n, "font-size"));
        let anchor = n.attribute("text-anchor").unwrap_or("start");
        let w = font::text_width_em(&text, em);
        let x0 = match anchor {
            "middle" => x - w / 2.0,
            "end" => x - w,
            _ => x,
        };
        let (asc, desc) = font::line_box_px(em);
        let mut corners = [
            (x0, y - asc),
            (x0 + w, y - asc),
            (x0, y + desc),
            (x0 + w, y + desc),
        ];
        if let Some(t) = n.attribute("transform") {
            let args: Vec<f64> = t
                .trim_start_matches("rotate(")
                .trim_end_matches(')')
                .split([' ', ','])
                .filter(|s| !s.is_empty())
                .filter_map(|s| s.parse().ok())
                .collect();
            let [a, cx, cy] = args[..] else {
                return Err(format!("unsupported transform {t:?}"));
            };
            let (s, c) = a.to_radians().sin_cos();
            for p in &mut corners {
                let (dx, dy) = (p.0 - cx, p.1 - cy);
                *p = (cx + c * dx - s * dy, cy + s * dx + c * dy);
            }
        }
        let b = BoxPx {
            x0: corners.iter().map(|p| p.0).fold(f64::INFINITY, f64::min),
            x1: corners
                .iter()
                .map(|p| p.0)
                .fold(f64::NEG_INFINITY, f64::max),
            y0: corners.iter().map(|p| p.1).fold(f64::INFINITY, f64::min),
            y1: corners
                .iter()
                .map(|p| p.1)
                .fold(f64::NEG_INFINITY, f64::max),
        };
        out.push((text, b));
    }
    Ok(out)
}

/// Everything wrong with the text layout of `svg` (empty when it is clean).
pub fn problems(svg: &str) -> Vec<String> {
    let doc = match roxmltree::Document::parse(svg) {
        Ok(d) => d,
        Err(e) => return vec![e.to_string()],
    };
    let root = doc.root_element();
    let page = BoxPx {
        x0: 0.0,
        y0: 0.0,
        x1: num(root, "width"),
        y1: num(root, "height"),
    };
    let panels: Vec<BoxPx> = doc
        .descendants()
        .filter(|n| n.has_tag_name("rect") && n.attribute("class") == Some("panel"))
        .map(|n| BoxPx {
            x0: num(n, "x"),
            y0: num(n, "y"),
            x1: num(n, "x") + num(n, "width"),
            y1: num(n, "y") + num(n, "height"),
        })
        .collect();
    let boxes = match text_boxes(svg) {
        Ok(b) => b,
        Err(e) => return vec![e],
    };
    // Half a pixel: rounding of positions to whole pixels.
    const TOL: f64 = 0.5;
    let mut out = vec![];
    for (i, (t, b)) in boxes.iter().enumerate() {
        if !b.inside(&page, TOL) {
            out.push(format!("{t:?} leaves the figure: {b:?}"));
        }
        let touched: Vec<&BoxPx> = panels.iter().filter(|p| b.overlap(p, TOL)).collect();
        if !touched.is_empty() && !touched.iter().any(|p| b.inside(p, TOL)) {
            out.push(format!("{t:?} crosses a panel's border: {b:?}"));
        }
        for (u, c) in &boxes[i + 1..] {
            if b.overlap(c, TOL) {
                out.push(format!("{t:?} overlaps {u:?}: {b:?} {c:?}"));
            }
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    fn svg(body: &str) -> String {
        format!(r#"<svg xmlns="http://www.w3.org/2000/svg" width="200" height="100">{body}</svg>"#)
    }

    #[test]
    fn finds_overlaps_escapes_and_panel_crossings() {
        let clean = svg(
            r#"<text x="10" y="20" font-size="11">one</text><text x="10" y="40" font-size="11">two</text>"#,
        );
        assert!(problems(&clean).is_empty(), "{:?}", problems(&clean));
        // Same line, the second starting inside the first ("one" is ~21 px wide at 11 px em).
        let overlap = svg(
            r#"<text x="10" y="20" font-size="11">one</text><text x="25" y="20" font-size="11">two</text>"#,
        );
        assert_eq!(problems(&overlap).len(), 1);
        let out = svg(r#"<text x="190" y="20" font-size="11">outside</text>"#);
        assert_eq!(problems(&out).len(), 1);
        // A vertical label turned about its anchor: 100 px tall text in a 100 px figure at y = 50
        // sticks out; at y = 90 upwards it does too.
        let turned = svg(
            r#"<text x="20" y="95" font-size="11" transform="rotate(270 20 95)">a rather long vertical label</text>"#,
        );
        assert_eq!(problems(&turned).len(), 1, "{:?}", problems(&turned));
        let panel = svg(
            r#"<rect class="panel" x="0" y="0" width="60" height="100"/><text x="50" y="20" font-size="11">crossing</text>"#,
        );
        assert_eq!(problems(&panel).len(), 1, "{:?}", problems(&panel));
    }
}
