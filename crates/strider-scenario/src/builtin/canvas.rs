//! The painter the generators draw worlds with: shapes of terrain and height on a raster whose
//! lower-left corner is the world origin, then colour and elevation texture.

use rand::{RngExt, rngs::ChaCha8Rng};
use rand_distr::{Distribution, Normal};
use strider_core::{Cell, CellRect, Point2, Rgb8};

use super::terrains::TerrainTable;
use crate::model::{ElevationEncoding, World};

/// A raster being painted: terrain index and base elevation per cell (row 0 = lowest y).
pub(crate) struct Canvas {
    pub res: f64,
    pub w: usize,
    pub h: usize,
    pub elev: Vec<f32>,
    pub terrain: Vec<u8>,
}

/// An axis-aligned rectangle `[x0, x1] × [y0, y1]`, metres.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Rect {
    pub x0: f64,
    pub y0: f64,
    pub x1: f64,
    pub y1: f64,
}

impl Rect {
    /// The rectangle of lower-left corner (`x`, `y`), `w` wide and `h` high.
    pub fn at(x: f64, y: f64, w: f64, h: f64) -> Self {
        Self {
            x0: x,
            y0: y,
            x1: x + w,
            y1: y + h,
        }
    }

    /// Euclidean distance between the closest points of `self` and `other` (0 when they
    /// overlap).
    pub fn gap(&self, other: &Rect) -> f64 {
        let dx = (other.x0 - self.x1).max(self.x0 - other.x1).max(0.0);
        let dy = (other.y0 - self.y1).max(self.y0 - other.y1).max(0.0);
        dx.hypot(dy)
    }
}

impl Canvas {
    /// A `width_m × height_m` canvas of cell size `res`, all `base` terrain at elevation 0.
    pub fn new(width_m: f64, height_m: f64, res: f64, base: u8) -> Self {
        let w = (width_m / res).round() as usize;
        let h = (height_m / res).round() as usize;
        Self {
            res,
            w,
            h,
            elev: vec![0.0; w * h],
            terrain: vec![base; w * h],
        }
    }

    pub fn width_m(&self) -> f64 {
        self.w as f64 * self.res
    }

    pub fn height_m(&self) -> f64 {
        self.h as f64 * self.res
    }

    /// Centre of cell `k`.
    pub fn center(&self, k: usize) -> Point2 {
        Point2::new(
            ((k % self.w) as f64 + 0.5) * self.res,
            ((k / self.w) as f64 + 0.5) * self.res,
        )
    }

    /// Cells whose centres lie in `[x0, x1] × [y0, y1]` (clipped to the canvas).
    pub fn cells_in(&self, x0: f64, y0: f64, x1: f64, y1: f64) -> Vec<usize> {
        let lo = |v: f64| ((v / self.res - 0.5).ceil().max(0.0)) as usize;
        let hi = |v: f64, n: usize| ((v / self.res - 0.5).floor().min(n as f64 - 1.0)) as i64;
        let (i0, j0) = (lo(x0.min(x1)), lo(y0.min(y1)));
        let (i1, j1) = (hi(x0.max(x1), self.w), hi(y0.max(y1), self.h));
        let mut out = Vec::new();
        if i1 < 0 || j1 < 0 {
            return out;
        }
        for j in j0..=j1 as usize {
            for i in i0..=i1 as usize {
                out.push(j * self.w + i);
            }
        }
        out
    }

    /// Sets terrain (and elevation, when given) of the cells in `cells` whose centre satisfies
    /// `keep`.
    pub fn paint(
        &mut self,
        cells: Vec<usize>,
        keep: impl Fn(Point2, u8) -> bool,
        terrain: u8,
        z: Option<f32>,
    ) {
        for k in cells {
            if keep(self.center(k), self.terrain[k]) {
                self.terrain[k] = terrain;
                if let Some(z) = z {
                    self.elev[k] = z;
                }
            }
        }
    }

    /// Fills the axis-aligned rectangle `[x0, x1] × [y0, y1]`.
    pub fn rect(&mut self, x0: f64, y0: f64, x1: f64, y1: f64, terrain: u8, z: Option<f32>) {
        let cells = self.cells_in(x0, y0, x1, y1);
        self.paint(cells, |_, _| true, terrain, z);
    }

    /// Fills rectangle `r`.
    pub fn fill(&mut self, r: Rect, terrain: u8, z: Option<f32>) {
        self.rect(r.x0, r.y0, r.x1, r.y1, terrain, z);
    }

    /// Fills a wobbly ellipse: centre `c`, semi-axes `rx`, `ry`, rotated by `angle`, radius
    /// modulated by `1 + Σ a·sin(m·θ + φ)` over `wobble` = [(m, a, φ)].
    #[allow(clippy::too_many_arguments)]
    pub fn blob(
        &mut self,
        c: Point2,
        rx: f64,
        ry: f64,
        angle: f64,
        wobble: &[(f64, f64, f64)],
        terrain: u8,
        only_on: Option<&[u8]>,
    ) {
        let r = rx.max(ry) * 1.5;
        let cells = self.cells_in(c.x - r, c.y - r, c.x + r, c.y + r);
        let (s, co) = angle.sin_cos();
        self.paint(
            cells,
            |p, t| {
                if only_on.is_some_and(|o| !o.contains(&t)) {
                    return false;
                }
                let (dx, dy) = (p.x - c.x, p.y - c.y);
                let (u, v) = (co * dx + s * dy, -s * dx + co * dy);
                let th = v.atan2(u);
                let m: f64 = 1.0
                    + wobble
                        .iter()
                        .map(|&(k, a, ph)| a * (k * th + ph).sin())
                        .sum::<f64>();
                (u / rx).powi(2) + (v / ry).powi(2) <= m * m
            },
            terrain,
            None,
        );
    }

    /// Paints a thick segment: cells within `half_width` of the segment `a`–`b`.
    #[allow(clippy::too_many_arguments)]
    pub fn segment(
        &mut self,
        a: Point2,
        b: Point2,
        half_width: f64,
        terrain: u8,
        z: Option<f32>,
        only_on: Option<&[u8]>,
    ) {
        let m = half_width + self.res;
        let cells = self.cells_in(
            a.x.min(b.x) - m,
            a.y.min(b.y) - m,
            a.x.max(b.x) + m,
            a.y.max(b.y) + m,
        );
        self.paint(
            cells,
            |p, t| only_on.is_none_or(|o| o.contains(&t)) && dist_to_segment(p, a, b) <= half_width,
            terrain,
            z,
        );
    }

    /// A wall of `thickness` metres around the edge of the canvas.
    pub fn border(&mut self, thickness: f64, terrain: u8, z: f32) {
        let (wm, hm) = (self.width_m(), self.height_m());
        self.rect(0.0, 0.0, thickness, hm, terrain, Some(z));
        self.rect(wm - thickness, 0.0, wm, hm, terrain, Some(z));
        self.rect(0.0, 0.0, wm, thickness, terrain, Some(z));
        self.rect(0.0, hm - thickness, wm, hm, terrain, Some(z));
    }

    /// Fraction of cells whose terrain is in `set`.
    pub fn fraction(&self, set: &[u8]) -> f64 {
        self.terrain.iter().filter(|t| set.contains(t)).count() as f64 / self.terrain.len() as f64
    }

    /// Colours and textures the canvas into a [`World`] with origin (0, 0): each cell's colour is
    /// one of its terrain's bases plus Gaussian noise (a shared lightness shift and a smaller
    /// per-channel one), its elevation the painted one plus uniform texture noise, snapped to the
    /// default 16-bit encoding ([`ElevationEncoding::default`]).
    pub fn finish(&self, terrains: &TerrainTable, rng: &mut ChaCha8Rng) -> World {
        let enc = ElevationEncoding::default();
        let unit = Normal::new(0.0, 1.0).expect("unit normal");
        let mut color = Vec::with_capacity(self.terrain.len());
        let mut elevation = Vec::with_capacity(self.terrain.len());
        for (k, &t) in self.terrain.iter().enumerate() {
            let look = terrains.look(t);
            let (c, tex) = match look {
                Some(l) => {
                    let base = l.bases[rng.random_range(0..l.bases.len())];
                    let shift = l.sigma * unit.sample(rng);
                    let ch = |v: u8, rng: &mut ChaCha8Rng| {
                        let n = v as f64 + shift + 0.5 * l.sigma * unit.sample(rng);
                        n.round().clamp(0.0, 255.0) as u8
                    };
                    let c = Rgb8::new(ch(base.0[0], rng), ch(base.0[1], rng), ch(base.0[2], rng));
                    (c, l.texture)
                }
                None => (Rgb8::new(128, 128, 128), 0.0),
            };
            let noise = if tex > 0.0 {
                rng.random_range(-tex..tex)
            } else {
                0.0
            };
            color.push(c);
            elevation.push(enc.quantize(self.elev[k] + noise));
        }
        World {
            resolution: self.res,
            rect: CellRect::new(Cell::new(0, 0), self.w as u32, self.h as u32),
            elevation,
            color,
            terrain: self.terrain.clone(),
            terrains: terrains.types(),
        }
    }
}

/// Distance from `p` to the segment `a`–`b`.
pub(crate) fn dist_to_segment(p: Point2, a: Point2, b: Point2) -> f64 {
    let (dx, dy) = (b.x - a.x, b.y - a.y);
    let l2 = dx * dx + dy * dy;
    let t = if l2 > 0.0 {
        (((p.x - a.x) * dx + (p.y - a.y) * dy) / l2).clamp(0.0, 1.0)
    } else {
        0.0
    };
    p.dist(Point2::new(a.x + t * dx, a.y + t * dy))
}
