//! Plot frames: data-to-pixel mapping, 1-2-5 ticks, labels, legend, and min/max decimation.

use super::canvas::{Anchor, Canvas, Item, Rgb, Role};

/// A rectangular plot area in pixels with its data ranges.
#[derive(Debug, Clone, Copy)]
pub struct Axes {
    pub left: f64,
    pub top: f64,
    pub width: f64,
    pub height: f64,
    pub x: (f64, f64),
    pub y: (f64, f64),
}

pub const FONT: f64 = 13.0;

impl Axes {
    /// The usual frame of a single-panel figure of `w` x `h` pixels.
    pub fn standard(w: u32, h: u32, x: (f64, f64), y: (f64, f64)) -> Self {
        Axes {
            left: 75.0,
            top: 35.0,
            width: w as f64 - 100.0,
            height: h as f64 - 90.0,
            x: widen(x),
            y: widen(y),
        }
    }

    pub fn map(&self, x: f64, y: f64) -> (f64, f64) {
        let u = (x - self.x.0) / (self.x.1 - self.x.0);
        let v = (y - self.y.0) / (self.y.1 - self.y.0);
        (
            self.left + u * self.width,
            self.top + (1.0 - v) * self.height,
        )
    }

    pub fn map_all(&self, pts: impl IntoIterator<Item = (f64, f64)>) -> Vec<(f64, f64)> {
        pts.into_iter().map(|(x, y)| self.map(x, y)).collect()
    }

    /// Frame, grid, tick labels, axis labels and title.
    pub fn draw(&self, c: &mut Canvas, title: &str, xlabel: &str, ylabel: &str) {
        let (l, t, w, h) = (self.left, self.top, self.width, self.height);
        for xt in nice_ticks(self.x.0, self.x.1, 8) {
            let (px, _) = self.map(xt, self.y.0);
            c.polyline(
                vec![(px, t), (px, t + h)],
                Rgb(235, 235, 235),
                1.0,
                false,
                Role::Axis,
                "grid",
            );
            c.polyline(
                vec![(px, t + h), (px, t + h + 5.0)],
                Rgb::BLACK,
                1.0,
                false,
                Role::Axis,
                "tick",
            );
            c.text(
                px,
                t + h + 19.0,
                &fmt_tick(xt, self.x),
                FONT - 1.0,
                Anchor::Middle,
            );
        }
        for yt in nice_ticks(self.y.0, self.y.1, 6) {
            let (_, py) = self.map(self.x.0, yt);
            c.polyline(
                vec![(l, py), (l + w, py)],
                Rgb(235, 235, 235),
                1.0,
                false,
                Role::Axis,
                "grid",
            );
            c.polyline(
                vec![(l - 5.0, py), (l, py)],
                Rgb::BLACK,
                1.0,
                false,
                Role::Axis,
                "tick",
            );
            c.text(
                l - 8.0,
                py + 4.0,
                &fmt_tick(yt, self.y),
                FONT - 1.0,
                Anchor::End,
            );
        }
        c.items.push(Item::Rect {
            x: l,
            y: t,
            w,
            h,
            fill: None,
            stroke: Some(Rgb::BLACK),
        });
        c.text(l + 0.5 * w, t + h + 40.0, xlabel, FONT, Anchor::Middle);
        c.vtext(l - 55.0, t + 0.5 * h, ylabel, FONT);
        c.text(l + 0.5 * w, t - 12.0, title, FONT + 1.0, Anchor::Middle);
    }

    /// Legend in the upper right corner of the plot area.
    pub fn legend(&self, c: &mut Canvas, entries: &[(&str, Rgb)]) {
        let x = self.left + self.width - 120.0;
        // A white box so the data underneath do not hide the names.
        c.items.push(Item::Rect {
            x: x - 8.0,
            y: self.top + 4.0,
            w: 124.0,
            h: 18.0 * entries.len() as f64 + 6.0,
            fill: Some(Rgb::WHITE),
            stroke: Some(Rgb::GREY),
        });
        for (i, (name, color)) in entries.iter().enumerate() {
            let y = self.top + 18.0 + 18.0 * i as f64;
            c.polyline(
                vec![(x, y - 4.0), (x + 25.0, y - 4.0)],
                *color,
                2.5,
                false,
                Role::Axis,
                "legend",
            );
            c.text(x + 32.0, y, name, FONT - 1.0, Anchor::Start);
        }
    }
}

/// Avoid a zero-width range (a flat signal) and add 5% margins.
fn widen((lo, hi): (f64, f64)) -> (f64, f64) {
    if !(lo.is_finite() && hi.is_finite()) {
        return (0.0, 1.0);
    }
    let span = hi - lo;
    if span <= 1e-12 * lo.abs().max(hi.abs()).max(1e-300) {
        let d = if lo == 0.0 { 1.0 } else { 0.1 * lo.abs() };
        return (lo - d, hi + d);
    }
    (lo - 0.05 * span, hi + 0.05 * span)
}

/// Ticks at 1, 2 or 5 times a power of ten, about `n` of them inside [lo, hi].
pub fn nice_ticks(lo: f64, hi: f64, n: usize) -> Vec<f64> {
    let step = tick_step(lo, hi, n);
    if !(step.is_finite() && step > 0.0) {
        return Vec::new();
    }
    let first = (lo / step).ceil() as i64;
    let last = (hi / step).floor() as i64;
    (first..=last).map(|k| k as f64 * step).collect()
}

fn tick_step(lo: f64, hi: f64, n: usize) -> f64 {
    let raw = (hi - lo) / n.max(1) as f64;
    let mag = 10f64.powf(raw.log10().floor());
    let m = raw / mag;
    mag * if m <= 1.0 {
        1.0
    } else if m <= 2.0 {
        2.0
    } else if m <= 5.0 {
        5.0
    } else {
        10.0
    }
}

fn fmt_tick(v: f64, range: (f64, f64)) -> String {
    let step = tick_step(range.0, range.1, 8);
    let decimals = (-step.log10().floor()).max(0.0) as usize;
    let s = format!("{:.*}", decimals, v);
    if s == "-0" {
        "0".to_string()
    } else {
        s
    }
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
    fn ticks_are_round_and_inside() {
        let t = nice_ticks(0.0, 3000.0, 8);
        assert_eq!(t, vec![0.0, 500.0, 1000.0, 1500.0, 2000.0, 2500.0, 3000.0]);
        let t = nice_ticks(-0.37, 1.42, 6);
        assert!(t.iter().all(|v| *v >= -0.37 && *v <= 1.42));
        assert!((t[1] - t[0] - 0.5).abs() < 1e-12);
    }

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
}
