//! Rendering of grid layers to PNG: colour, scalar fields with a colormap, class indices with a
//! palette, and overlays (tours, paths, points). Rasters are row-major with row 0 the lowest y
//! (the global lattice); images are written north-up, so rows are flipped here and only here.

use std::path::Path;

use anyhow::{Context, Result};
use image::{Rgb, RgbImage};
use strider_core::{Cell, CellRect, Point2, Rgb8};

/// An RGB canvas over a cell rectangle, north up.
pub struct Canvas {
    img: RgbImage,
    rect: CellRect,
    resolution: f64,
    scale: u32,
}

/// Colour used for unknown/NaN cells.
pub const UNKNOWN: [u8; 3] = [40, 40, 48];

impl Canvas {
    /// A canvas over `rect` (cell size `resolution`), each cell drawn as `scale × scale` pixels.
    pub fn new(rect: CellRect, resolution: f64, scale: u32) -> Self {
        let scale = scale.max(1);
        Self {
            img: RgbImage::from_pixel(rect.width * scale, rect.height * scale, Rgb(UNKNOWN)),
            rect,
            resolution,
            scale,
        }
    }

    /// A scale that makes the longer side about `target` pixels (at least 1 pixel per cell).
    pub fn auto_scale(rect: CellRect, target: u32) -> u32 {
        (target / rect.width.max(rect.height).max(1)).clamp(1, 16)
    }

    fn put_cell(&mut self, k: usize, c: [u8; 3]) {
        let w = self.rect.width as usize;
        let (x, y) = ((k % w) as u32, (k / w) as u32);
        let y_img = self.rect.height - 1 - y;
        for dy in 0..self.scale {
            for dx in 0..self.scale {
                self.img
                    .put_pixel(x * self.scale + dx, y_img * self.scale + dy, Rgb(c));
            }
        }
    }

    /// Fills every cell from a per-cell colour function (`None`: unknown colour).
    pub fn fill(&mut self, mut f: impl FnMut(usize) -> Option<[u8; 3]>) {
        for k in 0..self.rect.len() {
            let c = f(k).unwrap_or(UNKNOWN);
            self.put_cell(k, c);
        }
    }

    /// World point to pixel coordinates (may lie outside).
    fn to_px(&self, p: Point2) -> (f64, f64) {
        let s = self.scale as f64;
        let x = (p.x / self.resolution - self.rect.min.i as f64) * s;
        let y = (p.y / self.resolution - self.rect.min.j as f64) * s;
        (x, self.rect.height as f64 * s - y)
    }

    fn plot(&mut self, x: i64, y: i64, c: [u8; 3]) {
        if x >= 0 && y >= 0 && (x as u32) < self.img.width() && (y as u32) < self.img.height() {
            self.img.put_pixel(x as u32, y as u32, Rgb(c));
        }
    }

    /// Draws a polyline through world points.
    pub fn polyline(&mut self, pts: &[Point2], c: [u8; 3], width: i64) {
        for w in pts.windows(2) {
            let (a, b) = (self.to_px(w[0]), self.to_px(w[1]));
            let n = ((b.0 - a.0).abs().max((b.1 - a.1).abs()).ceil() as usize).max(1);
            for s in 0..=n {
                let t = s as f64 / n as f64;
                let (x, y) = (a.0 + t * (b.0 - a.0), a.1 + t * (b.1 - a.1));
                for dy in -(width / 2)..=(width / 2) {
                    for dx in -(width / 2)..=(width / 2) {
                        self.plot(x as i64 + dx, y as i64 + dy, c);
                    }
                }
            }
        }
    }

    /// Draws a filled square marker of half-size `r` pixels at a world point.
    pub fn marker(&mut self, p: Point2, c: [u8; 3], r: i64) {
        let (x, y) = self.to_px(p);
        for dy in -r..=r {
            for dx in -r..=r {
                self.plot(x as i64 + dx, y as i64 + dy, c);
            }
        }
    }

    /// Writes the PNG (atomically, see [`crate::io`]).
    pub fn save(&self, path: &Path) -> Result<()> {
        let mut png = Vec::new();
        self.img
            .write_to(&mut std::io::Cursor::new(&mut png), image::ImageFormat::Png)
            .with_context(|| format!("{}: cannot encode PNG", path.display()))?;
        crate::io::write_bytes(path, &png)
    }
}

/// Perceptually ordered colormap (a compact viridis approximation), `t` in [0, 1].
pub fn viridis(t: f64) -> [u8; 3] {
    const STOPS: [[f64; 3]; 6] = [
        [68.0, 1.0, 84.0],
        [65.0, 68.0, 135.0],
        [42.0, 120.0, 142.0],
        [34.0, 168.0, 132.0],
        [122.0, 209.0, 81.0],
        [253.0, 231.0, 37.0],
    ];
    let t = if t.is_finite() {
        t.clamp(0.0, 1.0)
    } else {
        0.0
    };
    let x = t * (STOPS.len() - 1) as f64;
    let k = (x.floor() as usize).min(STOPS.len() - 2);
    let f = x - k as f64;
    let mut c = [0u8; 3];
    for ch in 0..3 {
        c[ch] = (STOPS[k][ch] * (1.0 - f) + STOPS[k + 1][ch] * f).round() as u8;
    }
    c
}

/// Distinct colours for class indices.
pub fn palette(k: usize) -> [u8; 3] {
    const P: [[u8; 3]; 12] = [
        [141, 160, 203],
        [230, 85, 13],
        [49, 163, 84],
        [140, 86, 75],
        [117, 107, 177],
        [222, 45, 38],
        [253, 208, 162],
        [99, 99, 99],
        [188, 189, 34],
        [23, 190, 207],
        [247, 182, 210],
        [255, 237, 111],
    ];
    P[k % P.len()]
}

/// Renders a scalar raster with [`viridis`] between its finite min and max (or the given range).
/// Returns the range used.
pub fn scalar_canvas(
    rect: CellRect,
    resolution: f64,
    scale: u32,
    values: &[f32],
    range: Option<(f32, f32)>,
) -> (Canvas, (f32, f32)) {
    let (lo, hi) = range.unwrap_or_else(|| {
        values
            .iter()
            .filter(|v| v.is_finite())
            .fold((f32::INFINITY, f32::NEG_INFINITY), |(a, b), &v| {
                (a.min(v), b.max(v))
            })
    });
    let (lo, hi) = if lo.is_finite() && hi.is_finite() {
        (lo, hi)
    } else {
        (0.0, 1.0)
    };
    let span = if hi > lo { hi - lo } else { 1.0 };
    let mut c = Canvas::new(rect, resolution, scale);
    c.fill(|k| {
        let v = values[k];
        v.is_finite().then(|| viridis(((v - lo) / span) as f64))
    });
    (c, (lo, hi))
}

/// Renders an RGB raster.
pub fn rgb_canvas(rect: CellRect, resolution: f64, scale: u32, colors: &[Option<Rgb8>]) -> Canvas {
    let mut c = Canvas::new(rect, resolution, scale);
    c.fill(|k| colors[k].map(|c| c.0));
    c
}

const WHITE: [u8; 3] = [255, 255, 255];
const BLACK: [u8; 3] = [0, 0, 0];
const GRID: [u8; 3] = [225, 225, 225];

/// 3×5 glyphs, rows top to bottom, bits left to right.
pub fn glyph(ch: char) -> [u8; 5] {
    match ch {
        '0' | 'O' => [7, 5, 5, 5, 7],
        '1' => [2, 6, 2, 2, 7],
        '2' => [7, 1, 7, 4, 7],
        '3' => [7, 1, 7, 1, 7],
        '4' => [5, 5, 7, 1, 1],
        '5' => [7, 4, 7, 1, 7],
        '6' => [7, 4, 7, 5, 7],
        '7' => [7, 1, 1, 1, 1],
        '8' => [7, 5, 7, 5, 7],
        '9' => [7, 5, 7, 1, 7],
        'J' => [1, 1, 1, 5, 7],
        'T' => [7, 2, 2, 2, 2],
        'U' => [5, 5, 5, 5, 7],
        'R' => [6, 5, 6, 5, 5],
        'N' => [5, 7, 7, 5, 5],
        'A' => [2, 5, 7, 5, 5],
        'B' => [6, 5, 6, 5, 6],
        'C' => [7, 4, 4, 4, 7],
        'D' => [6, 5, 5, 5, 6],
        'E' => [7, 4, 6, 4, 7],
        'F' => [7, 4, 6, 4, 4],
        'G' => [7, 4, 5, 5, 7],
        'H' => [5, 5, 7, 5, 5],
        'I' => [7, 2, 2, 2, 7],
        'K' => [5, 5, 6, 5, 5],
        'L' => [4, 4, 4, 4, 7],
        'M' => [5, 7, 5, 5, 5],
        'P' => [7, 5, 7, 4, 4],
        'Q' => [7, 5, 5, 7, 1],
        'S' => [7, 4, 7, 1, 7],
        'V' => [5, 5, 5, 5, 2],
        'W' => [5, 5, 5, 7, 5],
        'X' => [5, 5, 2, 5, 5],
        'Y' => [5, 5, 2, 2, 2],
        'Z' => [7, 1, 2, 4, 7],
        '-' => [0, 0, 7, 0, 0],
        '.' => [0, 0, 0, 0, 2],
        '/' => [1, 1, 2, 4, 4],
        '(' => [1, 2, 2, 2, 1],
        ')' => [4, 2, 2, 2, 4],
        _ => [0; 5],
    }
}

/// Draws `text` with its lower-left corner at pixel (x, y) (y up), 2 pixels per glyph pixel.
fn text(c: &mut Canvas, x: f64, y: f64, text: &str) {
    label(c, x, y, text, BLACK);
}

/// Draws `text` (upper case letters, digits, `- . / ( )`; see [`glyph`]) in colour `col` with its
/// lower-left corner at pixel (x, y) (y up), 2 pixels per glyph pixel.
pub fn label(c: &mut Canvas, x: f64, y: f64, text: &str, col: [u8; 3]) {
    for (i, ch) in text.chars().enumerate() {
        let g = glyph(ch.to_ascii_uppercase());
        for (row, bits) in g.iter().enumerate() {
            for bit in 0..3 {
                if bits & (4 >> bit) != 0 {
                    for (dx, dy) in [(0.0, 0.0), (1.0, 0.0), (0.0, 1.0), (1.0, 1.0)] {
                        let px = x + (i * 8 + bit * 2) as f64 + dx + 0.5;
                        let py = y + ((4 - row) * 2) as f64 + dy + 0.5;
                        c.marker(Point2::new(px, py), col, 0);
                    }
                }
            }
        }
    }
}

/// Pastes `panels` (of any sizes) into one white canvas, row by row, `cols` per row; each row is
/// as tall as its tallest panel and each column as wide as its widest.
pub fn compose(panels: &[Canvas], cols: usize) -> Canvas {
    let cols = cols.max(1);
    let rows = panels.len().div_ceil(cols).max(1);
    let mut widths = vec![0u32; cols];
    let mut heights = vec![0u32; rows];
    for (k, p) in panels.iter().enumerate() {
        widths[k % cols] = widths[k % cols].max(p.img.width());
        heights[k / cols] = heights[k / cols].max(p.img.height());
    }
    let rect = CellRect::new(
        Cell::new(0, 0),
        widths.iter().sum::<u32>().max(1),
        heights.iter().sum::<u32>().max(1),
    );
    let mut out = Canvas::new(rect, 1.0, 1);
    out.fill(|_| Some(WHITE));
    for (k, p) in panels.iter().enumerate() {
        let ox: u32 = widths[..k % cols].iter().sum();
        let oy: u32 = heights[..k / cols].iter().sum();
        for (x, y, px) in p.img.enumerate_pixels() {
            out.img.put_pixel(ox + x, oy + y, *px);
        }
    }
    out
}

/// A round step of about a fifth of `span`.
pub(crate) fn nice_step(span: f64) -> f64 {
    let raw = (span / 5.0).max(1e-9);
    let mag = 10f64.powf(raw.log10().floor());
    [1.0, 2.0, 5.0, 10.0]
        .iter()
        .map(|m| m * mag)
        .find(|s| *s >= raw)
        .unwrap_or(10.0 * mag)
}

/// A line chart of `series` over 1..n (x, one point per entry; non-finite entries skipped) on a y
/// range that includes 0, with tick labels, the axis names `x_label` and `y_label` (drawn with
/// [`glyph`]'s characters) and horizontal reference lines `hlines` (value, colour).
pub fn line_chart(
    series: &[(Vec<f64>, [u8; 3])],
    hlines: &[(f64, [u8; 3])],
    x_label: &str,
    y_label: &str,
) -> Canvas {
    const W: u32 = 720;
    const H: u32 = 420;
    const L: f64 = 70.0;
    const B: f64 = 45.0;
    const R: f64 = 20.0;
    const T: f64 = 20.0;
    let n = series.iter().map(|s| s.0.len()).max().unwrap_or(0).max(2);
    let (lo_data, hi_data) = series
        .iter()
        .flat_map(|s| s.0.iter())
        .chain(hlines.iter().map(|h| &h.0))
        .filter(|v| v.is_finite())
        .fold((0.0f64, 0.0f64), |(a, b), &v| (a.min(v), b.max(v)));
    let step = nice_step((hi_data - lo_data).max(1e-6));
    let ymin = (lo_data / step).floor() * step;
    let ymax = ((hi_data / step).ceil() * step).max(ymin + step);
    let rect = CellRect::new(Cell::new(0, 0), W, H);
    let mut c = Canvas::new(rect, 1.0, 1);
    c.fill(|_| Some(WHITE));
    // Whole pixels plus a half: the canvas truncates coordinates, and a line along a pixel
    // edge would lose pixels to rounding.
    let px = |k: f64| (L + (k - 1.0) / (n as f64 - 1.0) * (W as f64 - L - R)).round() + 0.5;
    let py = |v: f64| (B + (v - ymin) / (ymax - ymin) * (H as f64 - B - T)).round() + 0.5;
    let ticks = ((ymax - ymin) / step).round() as i64;
    for i in 0..=ticks {
        let v = ymin + i as f64 * step;
        let col = if v.abs() < 1e-9 * step { BLACK } else { GRID };
        c.polyline(
            &[
                Point2::new(L + 0.5, py(v)),
                Point2::new(W as f64 - R, py(v)),
            ],
            col,
            1,
        );
        // As many decimals as the step needs (0.1 → 1, 0.002 → 3).
        let decimals = (-step.log10().floor()).max(0.0) as usize;
        let label = format!("{v:.decimals$}");
        text(
            &mut c,
            L - 8.0 - 8.0 * label.len() as f64,
            py(v) - 5.0,
            &label,
        );
    }
    // Tick every point up to 10, every 5 up to 50, then a round step for about ten labels.
    let xstep = if n <= 10 {
        1
    } else if n <= 50 {
        5
    } else {
        nice_step(n as f64 / 2.0) as usize
    };
    for k in 1..=n {
        if k == 1 || k.is_multiple_of(xstep) {
            let x = px(k as f64);
            c.polyline(
                &[Point2::new(x, B + 0.5), Point2::new(x, B - 4.5)],
                BLACK,
                1,
            );
            let label = k.to_string();
            text(&mut c, x - 4.0 * label.len() as f64, B - 20.0, &label);
        }
    }
    let (x0, y0) = (L + 0.5, B + 0.5);
    c.polyline(
        &[Point2::new(x0, y0), Point2::new(W as f64 - R, y0)],
        BLACK,
        1,
    );
    c.polyline(
        &[Point2::new(x0, y0), Point2::new(x0, H as f64 - T)],
        BLACK,
        1,
    );
    text(&mut c, 8.0, H as f64 - T - 10.0, y_label);
    text(
        &mut c,
        W as f64 - R - 10.0 * x_label.len() as f64,
        6.0,
        x_label,
    );
    for &(v, col) in hlines.iter().filter(|h| h.0.is_finite()) {
        c.polyline(
            &[Point2::new(x0, py(v)), Point2::new(W as f64 - R, py(v))],
            col,
            1,
        );
    }
    for (ys, col) in series {
        let pts: Vec<Point2> = ys
            .iter()
            .enumerate()
            .filter(|(_, v)| v.is_finite())
            .map(|(k, &v)| Point2::new(px(k as f64 + 1.0), py(v)))
            .collect();
        c.polyline(&pts, *col, 2);
        // Markers only where they stay apart (long series are lines).
        if pts.len() <= 50 {
            for p in &pts {
                c.marker(*p, *col, 3);
            }
        }
    }
    c
}

#[cfg(test)]
mod tests {
    use super::*;
    use strider_core::Cell;

    #[test]
    fn rows_are_flipped_north_up() {
        let rect = CellRect::new(Cell::new(0, 0), 2, 2);
        let mut c = Canvas::new(rect, 1.0, 1);
        c.fill(|k| (k == 0).then_some([255, 0, 0]));
        // Cell (0,0) is the lowest row: bottom-left pixel.
        assert_eq!(c.img.get_pixel(0, 1).0, [255, 0, 0]);
        assert_eq!(c.img.get_pixel(0, 0).0, UNKNOWN);
    }

    #[test]
    fn line_chart_draws_series_and_reference_lines_with_zero_in_range() {
        let red = [200, 0, 0];
        let ref_line = [0, 0, 200];
        let c = line_chart(
            &[(vec![10.0, f64::NAN, 30.0], red)],
            &[(20.0, ref_line)],
            "RUN",
            "J",
        );
        let count = |col: [u8; 3]| c.img.pixels().filter(|p| p.0 == col).count();
        assert!(count(red) > 100, "series drawn");
        assert!(count(ref_line) > 100, "reference line drawn");
        // The reference line is one horizontal row of pixels.
        let rows: std::collections::BTreeSet<u32> = c
            .img
            .enumerate_pixels()
            .filter(|(_, _, p)| p.0 == ref_line)
            .map(|(_, y, _)| y)
            .collect();
        assert_eq!(rows.len(), 1);
        // All-negative data still get a range that includes 0: nothing panics, the curve shows.
        let c = line_chart(&[(vec![-5.0, -1.0], red)], &[], "TOUR", "J");
        assert!(c.img.pixels().any(|p| p.0 == red));
    }

    #[test]
    fn viridis_ends() {
        assert_eq!(viridis(0.0), [68, 1, 84]);
        assert_eq!(viridis(1.0), [253, 231, 37]);
        assert_eq!(viridis(f64::NAN), [68, 1, 84]);
    }
}
