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
//!
//! **Empty space is skipped**, exactly: a descending ray starts where it comes down to the
//! highest column of the world, and a ray that stays above the highest column of an 8 × 8 block
//! of cells until it leaves the block jumps past it (re-entering the traversal at the block's
//! far side). The hit is the one of the plain cell-by-cell traversal; a test compares the two.

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
    /// Highest finite elevation per [`BLOCK`] × [`BLOCK`] block of cells (row-major, the last
    /// row and column of blocks possibly partial), for skipping empty space.
    block_max: Vec<f64>,
    /// Blocks per row.
    blocks_w: usize,
}

/// Side of the blocks of [`Heightfield`]'s coarse maximum, cells. A ray passing above a block's
/// highest column crosses the block in one step instead of up to 2·BLOCK cell steps: over
/// open ground most of a camera's rays fly above the terrain for most of their length.
const BLOCK: i64 = 1 << BLOCK_SHIFT;
/// log2 of [`BLOCK`] (indices are never negative, so a shift is the block division).
const BLOCK_SHIFT: u32 = 3;

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
        let (w, h) = (rect.width as usize, rect.height as usize);
        let b = BLOCK as usize;
        let blocks_w = w.div_ceil(b);
        let mut block_max = vec![f64::NEG_INFINITY; blocks_w * h.div_ceil(b)];
        for (k, &z) in elevation.iter().enumerate() {
            let m = &mut block_max[(k / w) / b * blocks_w + (k % w) / b];
            *m = m.max(z);
        }
        Ok(Self {
            resolution,
            rect,
            elevation,
            max_elevation,
            block_max,
            blocks_w,
        })
    }

    /// The same heightfield with block skipping turned off: every ray then steps through every
    /// cell it crosses. A reference for tests of the skipping.
    #[doc(hidden)]
    pub fn without_block_skipping(mut self) -> Self {
        self.block_max.fill(f64::INFINITY);
        self
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
        // Reciprocals once: a camera ray is short over flat ground, so the per-ray divisions
        // cost more than its cell steps. (±∞ for a zero component, never used: every use below
        // is guarded by a `!= 0` test.)
        let (rx, ry) = (1.0 / ux, 1.0 / uy);
        let (ww, hh) = (w as f64 * d, h as f64 * d);

        // Clip the horizontal projection to the rectangle (slab method), remembering the slab
        // entry times to know which border an outside ray enters through.
        let mut t1 = max_range;
        let mut enter = [f64::NEG_INFINITY; 2];
        for (a, (o, v, r, extent)) in [(ox, ux, rx, ww), (oy, uy, ry, hh)].into_iter().enumerate() {
            if v == 0.0 {
                if o < 0.0 || o >= extent {
                    return None;
                }
            } else {
                let (ta, tb) = ((0.0 - o) * r, (extent - o) * r);
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
        let mut ix = start_index_at(ox, ux, t0, d, w);
        let mut iy = start_index_at(oy, uy, t0, d, h);
        let (sx, sy): (i64, i64) = (if ux > 0.0 { 1 } else { -1 }, if uy > 0.0 { 1 } else { -1 });
        let boundary = |k: i64, s: i64| {
            if s > 0 {
                (k + 1) as f64 * d
            } else {
                k as f64 * d
            }
        };
        let mut tx = if ux != 0.0 {
            (boundary(ix, sx) - ox) * rx
        } else {
            f64::INFINITY
        };
        let mut ty = if uy != 0.0 {
            (boundary(iy, sy) - oy) * ry
        } else {
            f64::INFINITY
        };
        let tdx = if ux != 0.0 {
            d * rx.abs()
        } else {
            f64::INFINITY
        };
        let tdy = if uy != 0.0 {
            d * ry.abs()
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
        // A ray brought down to the highest column's top by the skip above is already where
        // the terrain can begin (most of a downward camera's rays over open ground): its first
        // block is not tested, only the blocks it enters later.
        let mut block = if skipped {
            (ix >> BLOCK_SHIFT, iy >> BLOCK_SHIFT)
        } else {
            (-1, -1)
        };
        loop {
            // Entering a new block: if the ray stays above its highest column until it leaves
            // the block, jump to the first cell past the block.
            if (ix >> BLOCK_SHIFT, iy >> BLOCK_SHIFT) != block {
                block = (ix >> BLOCK_SHIFT, iy >> BLOCK_SHIFT);
                let bmax = self.block_max[block.1 as usize * self.blocks_w + block.0 as usize];
                let exit_time = |b: i64, o: f64, v: f64, r: f64| {
                    let edge = if v > 0.0 { (b + 1) * BLOCK } else { b * BLOCK };
                    if v != 0.0 {
                        (edge as f64 * d - o) * r
                    } else {
                        f64::INFINITY
                    }
                };
                let (tbx, tby) = (
                    exit_time(block.0, ox, ux, rx),
                    exit_time(block.1, oy, uy, ry),
                );
                let t_exit = tbx.min(tby).min(t1);
                let z_low = oz + uz * if uz < 0.0 { t_exit } else { t_in };
                if z_low > bmax {
                    if t_exit >= t1 || (uz >= 0.0 && oz + uz * t_in >= zmax) {
                        return None;
                    }
                    // Step out through the face the ray leaves by (x on a tie, as the cell
                    // traversal does); the other index follows the exit point.
                    t_in = t_exit;
                    // The first index past the block along the exit axis (None: the ray leaves
                    // the world), and the other axis' index at the exit point, kept in the
                    // block's span.
                    let step_out = |b: i64, s: i64, n: i64| {
                        let k = if s > 0 {
                            (b + 1) * BLOCK
                        } else {
                            b * BLOCK - 1
                        };
                        (0..n).contains(&k).then_some(k)
                    };
                    let follow = |o: f64, v: f64, b: i64, n: i64| {
                        start_index_at(o, v, t_in, d, n)
                            .clamp((b * BLOCK).min(n - 1), ((b + 1) * BLOCK - 1).min(n - 1))
                    };
                    if tbx <= tby {
                        ix = step_out(block.0, sx, w)?;
                        iy = follow(oy, uy, block.1, h);
                        entry = Entry::X(boundary(ix - sx, sx));
                    } else {
                        iy = step_out(block.1, sy, h)?;
                        ix = follow(ox, ux, block.0, w);
                        entry = Entry::Y(boundary(iy - sy, sy));
                    }
                    tx = if ux != 0.0 {
                        (boundary(ix, sx) - ox) * rx
                    } else {
                        f64::INFINITY
                    };
                    ty = if uy != 0.0 {
                        (boundary(iy, sy) - oy) * ry
                    } else {
                        f64::INFINITY
                    };
                    continue;
                }
            }
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

/// The index along one axis of the cell a ray (local coordinate `o`, direction component `v`)
/// is inside just after distance `t`, clamped to `0..n`: a point exactly on a boundary belongs
/// to the cell the ray moves into.
#[inline]
fn start_index_at(o: f64, v: f64, t: f64, d: f64, n: i64) -> i64 {
    let p = o + v * t;
    // floor() by truncation: without SSE4.1 in the baseline target, f64::floor is a libm call.
    let q = p / d;
    let mut k = q as i64;
    if k as f64 > q {
        k -= 1;
    }
    if v < 0.0 && k as f64 * d == p {
        k -= 1;
    }
    k.clamp(0, n - 1)
}
