//! Where a scan lies: its sensor origin and noise model ([`ScanFrame`]) and the cells of its
//! bounding box that the passes' rasters cover ([`ScanGrid`]).

use super::scratch::Located;
use crate::params::MapParams;
use crate::rect;
use strider_core::{Cell, CellRect, ColoredPoint, Point3};

/// What the passes need of a scan besides its returns: the sensor origin, the range limit,
/// the range noise model and the cell size.
pub(super) struct ScanFrame {
    pub(super) origin: [f32; 3],
    /// Squared `max_point_range`.
    max_r2: f32,
    /// σ_d².
    sd2: f32,
    /// k_d.
    kd: f32,
    /// Cell size, m, and its inverse.
    pub(super) d: f64,
    pub(super) inv_d: f32,
}

impl ScanFrame {
    /// The frame of a scan taken from `origin`; `None` when the origin is not finite.
    pub(super) fn new(params: &MapParams, origin: Point3) -> Option<Self> {
        let o = origin;
        if !(o.x.is_finite() && o.y.is_finite() && o.z.is_finite()) {
            return None;
        }
        let max_r = params.max_point_range.min(1e6) as f32;
        Some(Self {
            origin: [o.x as f32, o.y as f32, o.z as f32],
            max_r2: max_r * max_r,
            sd2: (params.sigma_d * params.sigma_d) as f32,
            kd: params.k_d as f32,
            d: params.cell_size,
            inv_d: (1.0 / params.cell_size) as f32,
        })
    }

    /// A return's squared range from the origin when it is usable: `Ok(range²)`, or
    /// `Err(true)` for non-finite and `Err(false)` for out of range.
    #[inline(always)]
    pub(super) fn classify(&self, p: &ColoredPoint) -> Result<f32, bool> {
        if !(p.x.is_finite() && p.y.is_finite() && p.z.is_finite()) {
            return Err(true);
        }
        let o = self.origin;
        let (dx, dy, dz) = (p.x - o[0], p.y - o[1], p.z - o[2]);
        let r2 = dx * dx + dy * dy + dz * dz;
        if r2 <= self.max_r2 {
            Ok(r2)
        } else {
            Err(false)
        }
    }

    /// σ_z² of a return at squared range `r2`: σ_d² + (k_d · range²)².
    #[inline(always)]
    pub(super) fn variance(&self, r2: f32) -> f32 {
        let kr = self.kd * r2;
        self.sd2 + kr * kr
    }
}

/// The cells of a scan's bounding box, where the passes' rasters live.
pub(super) struct ScanGrid {
    pub(super) rect: CellRect,
    pub(super) w: usize,
    pub(super) h: usize,
    /// The rectangle's corner, as cell coordinates.
    mi: f64,
    mj: f64,
}

impl ScanGrid {
    /// The cells of the box `(x0, y0, x1, y1)`; `None` when it holds no return.
    pub(super) fn covering(bbox: (f32, f32, f32, f32), d: f64) -> Option<Self> {
        let (x0, y0, x1, y1) = bbox;
        let lo = Cell::containing(x0 as f64, y0 as f64, d)?;
        let hi = Cell::containing(x1 as f64, y1 as f64, d)?;
        let rect = rect::from_corners(lo, hi);
        Some(Self {
            rect,
            w: rect.width as usize,
            h: rect.height as usize,
            mi: rect.min.i as f64,
            mj: rect.min.j as f64,
        })
    }

    /// The raster index of cell column `ci`, row `cj`.
    #[inline(always)]
    pub(super) fn index(&self, ci: usize, cj: usize) -> usize {
        cj * self.w + ci
    }

    /// Where return `p` lies (its variance left 0): cell coordinates relative to the rect,
    /// computed exactly like `Cell::containing`.
    #[inline(always)]
    pub(super) fn locate(&self, p: &ColoredPoint, d: f64) -> Located {
        let fx = p.x as f64 / d;
        let fy = p.y as f64 / d;
        let (cx, cy) = (fast_floor(fx), fast_floor(fy));
        Located {
            ci: (cx - self.mi) as u32,
            cj: (cy - self.mj) as u32,
            u: (fx - cx) as f32,
            v: (fy - cy) as f32,
            var: 0.0,
        }
    }
}

/// `v.floor()` for |v| < 2⁶², without a libm call on baseline x86-64 (no SSE4.1 `roundsd`).
#[inline(always)]
fn fast_floor(v: f64) -> f64 {
    let t = v as i64 as f64;
    if t > v { t - 1.0 } else { t }
}
