//! Ray casting against the world's elevation layer seen as flat-topped cell columns.
//!
//! Every world cell is a box from −∞ up to its elevation; outside the world rectangle there is no
//! surface at all (rays pass, nothing is returned). A ray is traversed exactly through the cells
//! its horizontal projection crosses (3-D Amanatides–Woo DDA, the same traversal as
//! [`strider_core::grid::CellRay`] but parametrised by distance along the 3-D ray):
//!
//! * it hits a cell's **side face** when it enters the cell below the cell's top; the hit point
//!   then lies exactly on the cell boundary it crossed;
//! * it hits a cell's **top face** when it descends to the cell's elevation while inside the cell.
//!
//! A non-finite elevation marks a cell without surface (a hole), like the outside of the world.

use strider_core::{Cell, CellRect, Point2, Point3};
use strider_scenario::World;

use crate::error::SimError;

/// Which face of a cell column a ray hit.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Face {
    /// The horizontal top surface (at the cell's elevation).
    Top,
    /// A vertical side face (the hit point lies on the cell boundary), or the ray started inside
    /// the column (range 0).
    Side,
}

/// Where a ray met the terrain.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RayHit {
    /// Hit point, world frame, metres.
    pub point: Point3,
    /// Distance from the ray origin to the hit point, metres.
    pub range: f64,
    /// The cell whose column was hit.
    pub cell: Cell,
    /// Row-major layer index of that cell in the world rectangle.
    pub index: usize,
    /// The face that was hit.
    pub face: Face,
}

/// The world's elevation layer as a field of flat-topped columns, ready for ray casting.
#[derive(Clone, Debug)]
pub struct Heightfield {
    resolution: f64,
    rect: CellRect,
    /// Elevation per cell (row-major); −∞ for cells without surface.
    elevation: Vec<f64>,
    /// Highest finite elevation (−∞ when there is none).
    max_elevation: f64,
}

/// Tolerance of [`Heightfield::visible`], metres: a blocking hit this close to the target counts
/// as the target itself.
pub const VISIBILITY_TOLERANCE_M: f64 = 1e-6;

impl Heightfield {
    /// A heightfield over `rect` (cell size `resolution`) with one elevation per cell, row-major.
    pub fn new(resolution: f64, rect: CellRect, elevation: &[f32]) -> Result<Self, SimError> {
        crate::error::check(
            "world.resolution",
            resolution,
            |v| v > 0.0,
            "must be a positive cell size",
        )?;
        if elevation.len() != rect.len() {
            return Err(SimError::LayerSize {
                layer: "elevation",
                len: elevation.len(),
                expected: rect.len(),
            });
        }
        let elevation: Vec<f64> = elevation
            .iter()
            .map(|&z| {
                if z.is_finite() {
                    z as f64
                } else {
                    f64::NEG_INFINITY
                }
            })
            .collect();
        let max_elevation = elevation.iter().copied().fold(f64::NEG_INFINITY, f64::max);
        Ok(Self {
            resolution,
            rect,
            elevation,
            max_elevation,
        })
    }

    /// The heightfield of a world's elevation layer.
    pub fn from_world(world: &World) -> Result<Self, SimError> {
        Self::new(world.resolution, world.rect, &world.elevation)
    }

    /// Cell size, metres.
    pub fn resolution(&self) -> f64 {
        self.resolution
    }

    /// The covered cells.
    pub fn rect(&self) -> CellRect {
        self.rect
    }

    /// Elevation of the column containing `p`; `None` outside the world or over a hole.
    pub fn elevation_at(&self, p: Point2) -> Option<f64> {
        let c = Cell::containing(p.x, p.y, self.resolution)?;
        self.cell_elevation(c)
    }

    /// Elevation of cell `c`; `None` outside the world or for a hole.
    pub fn cell_elevation(&self, c: Cell) -> Option<f64> {
        let z = self.elevation[self.rect.index(c)?];
        z.is_finite().then_some(z)
    }

    /// Casts a ray from `origin` along `dir` (any non-zero length; normalised here) up to
    /// `max_range` metres and returns the first surface it meets.
    pub fn cast(&self, origin: Point3, dir: [f64; 3], max_range: f64) -> Option<RayHit> {
        let n = (dir[0] * dir[0] + dir[1] * dir[1] + dir[2] * dir[2]).sqrt();
        if !(n > 0.0 && n.is_finite()) {
            return None;
        }
        self.cast_unit(origin, [dir[0] / n, dir[1] / n, dir[2] / n], max_range)
    }

    /// [`Self::cast`] for a unit direction (not checked).
    pub fn cast_unit(&self, origin: Point3, u: [f64; 3], max_range: f64) -> Option<RayHit> {
        let valid =
            max_range > 0.0 && origin.x.is_finite() && origin.y.is_finite() && origin.z.is_finite();
        if !valid {
            return None;
        }
        let d = self.resolution;
        let (w, h) = (self.rect.width as i64, self.rect.height as i64);
        if w == 0 || h == 0 {
            return None;
        }
        let x0 = self.rect.min.i as f64 * d;
        let y0 = self.rect.min.j as f64 * d;
        // Local coordinates: the world rectangle spans [0, W] × [0, H].
        let (ox, oy, oz) = (origin.x - x0, origin.y - y0, origin.z);
        let (ux, uy, uz) = (u[0], u[1], u[2]);
        let (ww, hh) = (w as f64 * d, h as f64 * d);

        // Clip the horizontal projection to the rectangle (slab method), remembering the slab
        // entry times to know which border an outside ray enters through.
        let mut t1 = max_range;
        let mut enter = [f64::NEG_INFINITY; 2];
        for (a, (o, v, extent)) in [(ox, ux, ww), (oy, uy, hh)].into_iter().enumerate() {
            if v == 0.0 {
                if o < 0.0 || o >= extent {
                    return None;
                }
            } else {
                let (ta, tb) = ((0.0 - o) / v, (extent - o) / v);
                enter[a] = ta.min(tb);
                t1 = t1.min(ta.max(tb));
            }
        }
        let t0 = enter[0].max(enter[1]).max(0.0);
        if t0 > t1 {
            return None;
        }
        // A descending ray cannot hit anything while it is above the highest column: start
        // where it comes down to that height (exact, and most of a downward-looking camera's
        // rays over open ground).
        // (Aim 1 nm above it so rounding never puts the start below a column's top.)
        let z_top = self.max_elevation + 1e-9;
        let t_top = if uz < 0.0 && oz > z_top {
            (oz - z_top) / -uz
        } else {
            f64::NEG_INFINITY
        };
        let skipped = t_top > t0;
        let t0 = t0.max(t_top);
        if t0 > t1 {
            return None;
        }

        // The first cell: the one the ray is inside just after t0.
        let start_index = |o: f64, v: f64, n: i64| -> i64 {
            let p = o + v * t0;
            let mut k = (p / d).floor() as i64;
            if v < 0.0 && k as f64 * d == p {
                k -= 1;
            }
            k.clamp(0, n - 1)
        };
        let mut ix = start_index(ox, ux, w);
        let mut iy = start_index(oy, uy, h);
        let (sx, sy): (i64, i64) = (if ux > 0.0 { 1 } else { -1 }, if uy > 0.0 { 1 } else { -1 });
        let boundary = |k: i64, s: i64| {
            if s > 0 {
                (k + 1) as f64 * d
            } else {
                k as f64 * d
            }
        };
        let mut tx = if ux != 0.0 {
            (boundary(ix, sx) - ox) / ux
        } else {
            f64::INFINITY
        };
        let mut ty = if uy != 0.0 {
            (boundary(iy, sy) - oy) / uy
        } else {
            f64::INFINITY
        };
        let tdx = if ux != 0.0 {
            d / ux.abs()
        } else {
            f64::INFINITY
        };
        let tdy = if uy != 0.0 {
            d / uy.abs()
        } else {
            f64::INFINITY
        };

        // Which boundary the ray entered the current cell through (for exact side-face points).
        #[derive(Clone, Copy)]
        enum Entry {
            Start,
            X(f64),
            Y(f64),
        }
        let mut entry = if skipped {
            Entry::Start
        } else if t0 > 0.0 && enter[0] >= enter[1] {
            Entry::X(if ux > 0.0 { 0.0 } else { ww })
        } else if t0 > 0.0 {
            Entry::Y(if uy > 0.0 { 0.0 } else { hh })
        } else {
            Entry::Start
        };
        let mut t_in = t0;
        let zmax = self.max_elevation;
        loop {
            let k = (iy * w + ix) as usize;
            let top = self.elevation[k];
            let t_out = tx.min(ty).min(t1);
            let z_in = oz + uz * t_in;
            let cell = || Cell::new(self.rect.min.i + ix as i32, self.rect.min.j + iy as i32);
            if z_in < top {
                // Entered below the top: vertical side face (or started inside the column).
                let (px, py) = match entry {
                    Entry::X(bx) => (bx, oy + uy * t_in),
                    Entry::Y(by) => (ox + ux * t_in, by),
                    Entry::Start => (ox + ux * t_in, oy + uy * t_in),
                };
                return Some(RayHit {
                    point: Point3::new(px + x0, py + y0, z_in),
                    range: t_in,
                    cell: cell(),
                    index: k,
                    face: Face::Side,
                });
            }
            if uz < 0.0 {
                let z_out = oz + uz * t_out;
                if z_out <= top {
                    let t = ((top - oz) / uz).clamp(t_in, t_out);
                    return Some(RayHit {
                        point: Point3::new(ox + ux * t + x0, oy + uy * t + y0, top),
                        range: t,
                        cell: cell(),
                        index: k,
                        face: Face::Top,
                    });
                }
            } else if z_in >= zmax {
                // Level or rising above every column: nothing can be hit any more.
                return None;
            }
            if t_out >= t1 {
                return None;
            }
            t_in = t_out;
            if tx <= ty {
                ix += sx;
                entry = Entry::X(boundary(ix - sx, sx));
                tx += tdx;
                if ix < 0 || ix >= w {
                    return None;
                }
            } else {
                iy += sy;
                entry = Entry::Y(boundary(iy - sy, sy));
                ty += tdy;
                if iy < 0 || iy >= h {
                    return None;
                }
            }
        }
    }

    /// Line of sight: true when the straight segment from `from` to `to` meets no terrain before
    /// reaching `to` (a hit within [`VISIBILITY_TOLERANCE_M`] of `to`, e.g. the target's own top
    /// surface, does not block). Outside the world nothing blocks.
    pub fn visible(&self, from: Point3, to: Point3) -> bool {
        let dist = from.dist(to);
        if !dist.is_finite() {
            return false;
        }
        if dist <= VISIBILITY_TOLERANCE_M {
            return true;
        }
        let u = [
            (to.x - from.x) / dist,
            (to.y - from.y) / dist,
            (to.z - from.z) / dist,
        ];
        match self.cast_unit(from, u, dist) {
            None => true,
            Some(hit) => hit.range >= dist - VISIBILITY_TOLERANCE_M,
        }
    }
}
