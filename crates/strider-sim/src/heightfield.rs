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
//!
//! The rays of an omnidirectional sensor's azimuth column share one horizontal direction; they
//! are cast together by [`Heightfield::cast_column`] (module `columns`), which gives every ray
//! the hit of [`Heightfield::cast_unit`] bit for bit, for less than casting them one by one.

mod coast;
mod columns;
mod line_proof;
mod side_hit;
mod stations;

use std::sync::OnceLock;

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
    /// Highest elevation of each cell's 3 × 3 neighbourhood on the rectangle grown by one cell on
    /// every side, built by the first [`Heightfield::cast_column`].
    near_max: OnceLock<stations::Near>,
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
            near_max: OnceLock::new(),
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
        Walk::start(self, origin, u, max_range)?.run()
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

/// Which boundary the ray entered the current cell through (for exact side-face points).
#[derive(Clone, Copy)]
enum Entry {
    /// The ray starts in the cell (or was brought down into it by the top skip).
    Start,
    /// Through the boundary x = the value (local frame).
    X(f64),
    /// Through the boundary y = the value (local frame).
    Y(f64),
}

/// What a ray does in a cell.
enum Crossing {
    /// It meets the cell's column.
    Hit(RayHit),
    /// It meets nothing any more.
    Miss,
    /// It goes on to the next cell.
    Next,
}

/// What a ray does from a block it enters.
enum Block {
    /// It may meet a column of the current block (possibly after passing over blocks): walk
    /// its cells.
    Inside,
    /// It meets nothing any more (leaves the world or its range above a block, or climbs
    /// above every column).
    Miss,
}

/// A ray walking through the cell columns it crosses (3-D DDA) in the heightfield's local
/// frame, where the world rectangle spans `[0, W] × [0, H]` metres.
struct Walk<'a> {
    hf: &'a Heightfield,
    /// Cell size.
    d: f64,
    /// Columns and rows.
    w: i64,
    h: i64,
    /// World coordinates of the local origin.
    x0: f64,
    y0: f64,
    /// Ray origin, local frame.
    ox: f64,
    oy: f64,
    oz: f64,
    /// Unit direction.
    ux: f64,
    uy: f64,
    uz: f64,
    /// Reciprocals of `ux`, `uy` (±∞ for a zero component, never used: every use is guarded
    /// by a `!= 0` test).
    rx: f64,
    ry: f64,
    /// Where the ray leaves the world rectangle or its range.
    t1: f64,
    /// The current cell.
    ix: i64,
    iy: i64,
    /// Step direction per axis.
    sx: i64,
    sy: i64,
    /// Distance at which the ray crosses the next x and y cell boundary.
    tx: f64,
    ty: f64,
    /// Distance between successive x and y boundary crossings.
    tdx: f64,
    tdy: f64,
    entry: Entry,
    /// Distance at which the ray entered the current cell.
    t_in: f64,
    /// The current block (−1, −1 before the first).
    block: (i64, i64),
}

impl<'a> Walk<'a> {
    /// The walk of a ray from `origin` along unit `u` up to `max_range`, starting in the first
    /// cell where it can meet a column; `None` when it cannot meet any.
    #[inline]
    fn start(hf: &'a Heightfield, origin: Point3, u: [f64; 3], max_range: f64) -> Option<Self> {
        let valid =
            max_range > 0.0 && origin.x.is_finite() && origin.y.is_finite() && origin.z.is_finite();
        if !valid {
            return None;
        }
        let d = hf.resolution;
        let (w, h) = (hf.rect.width as i64, hf.rect.height as i64);
        if w == 0 || h == 0 {
            return None;
        }
        let x0 = hf.rect.min.i as f64 * d;
        let y0 = hf.rect.min.j as f64 * d;
        let (ox, oy, oz) = (origin.x - x0, origin.y - y0, origin.z);
        let (ux, uy, uz) = (u[0], u[1], u[2]);
        // Reciprocals once: a camera ray is short over flat ground, so the per-ray divisions
        // cost more than its cell steps.
        let (rx, ry) = (1.0 / ux, 1.0 / uy);
        let (ww, hh) = (w as f64 * d, h as f64 * d);
        let (t0, t1, enter) = clip_to_rect([ox, oy], [ux, uy], [rx, ry], [ww, hh], max_range)?;
        let (t0, skipped) = skip_to_top(oz, uz, hf.max_elevation, t0);
        if t0 > t1 {
            return None;
        }
        // The first cell: the one the ray is inside just after t0.
        let ix = start_index_at(ox, ux, t0, d, w);
        let iy = start_index_at(oy, uy, t0, d, h);
        let entry = start_entry(skipped, t0, enter, [ux, uy], [ww, hh]);
        // A ray brought down to the highest column's top by the skip is already where the
        // terrain can begin (most of a downward camera's rays over open ground): its first
        // block is not tested, only the blocks it enters later.
        let block = if skipped {
            (ix >> BLOCK_SHIFT, iy >> BLOCK_SHIFT)
        } else {
            (-1, -1)
        };
        let mut walk = Self {
            hf,
            d,
            w,
            h,
            x0,
            y0,
            ox,
            oy,
            oz,
            ux,
            uy,
            uz,
            rx,
            ry,
            t1,
            ix,
            iy,
            sx: if ux > 0.0 { 1 } else { -1 },
            sy: if uy > 0.0 { 1 } else { -1 },
            tx: f64::INFINITY,
            ty: f64::INFINITY,
            tdx: if ux != 0.0 {
                d * rx.abs()
            } else {
                f64::INFINITY
            },
            tdy: if uy != 0.0 {
                d * ry.abs()
            } else {
                f64::INFINITY
            },
            entry,
            t_in: t0,
            block,
        };
        walk.aim_at_next_boundaries();
        Some(walk)
    }

    /// The coordinate of the boundary of cell `k` (along one axis) that a ray stepping `s`
    /// leaves it through.
    #[inline]
    fn boundary(&self, k: i64, s: i64) -> f64 {
        if s > 0 {
            (k + 1) as f64 * self.d
        } else {
            k as f64 * self.d
        }
    }

    /// Sets the distances of the next x and y boundary crossings from the current cell.
    #[inline]
    fn aim_at_next_boundaries(&mut self) {
        self.tx = if self.ux != 0.0 {
            (self.boundary(self.ix, self.sx) - self.ox) * self.rx
        } else {
            f64::INFINITY
        };
        self.ty = if self.uy != 0.0 {
            (self.boundary(self.iy, self.sy) - self.oy) * self.ry
        } else {
            f64::INFINITY
        };
    }

    /// Walks on from the current cell to the first surface met.
    #[inline(always)]
    fn run(&mut self) -> Option<RayHit> {
        loop {
            self.enter_block()?;
            match self.cross_cell() {
                Crossing::Hit(hit) => return Some(hit),
                Crossing::Miss => return None,
                Crossing::Next => {}
            }
        }
    }

    /// The block test before each cell, which may move the walk past blocks; `None` when the
    /// ray meets nothing any more.
    #[inline(always)]
    fn enter_block(&mut self) -> Option<()> {
        if self.enters_new_block() {
            match self.pass_over_blocks() {
                Block::Inside => {}
                Block::Miss => return None,
            }
        }
        Some(())
    }

    /// True (and remembers the block) when the current cell lies in another block than the
    /// previous one.
    #[inline]
    fn enters_new_block(&mut self) -> bool {
        let block = (self.ix >> BLOCK_SHIFT, self.iy >> BLOCK_SHIFT);
        let new = block != self.block;
        self.block = block;
        new
    }

    /// In a block just entered: while the ray stays above the highest column of the block it
    /// is in until it leaves it, moves on to the next block (one step per block), then sets
    /// the walk in the first cell past the last block passed. The cell is only needed there:
    /// a block passed is left through a face, so the next block follows from the block alone.
    #[inline]
    fn pass_over_blocks(&mut self) -> Block {
        let mut last_pass = None;
        loop {
            let block = self.block;
            let bmax = self.hf.block_max[block.1 as usize * self.hf.blocks_w + block.0 as usize];
            let exit_time = |b: i64, o: f64, v: f64, r: f64| {
                let edge = if v > 0.0 { (b + 1) * BLOCK } else { b * BLOCK };
                if v != 0.0 {
                    (edge as f64 * self.d - o) * r
                } else {
                    f64::INFINITY
                }
            };
            let (tbx, tby) = (
                exit_time(block.0, self.ox, self.ux, self.rx),
                exit_time(block.1, self.oy, self.uy, self.ry),
            );
            let t_exit = tbx.min(tby).min(self.t1);
            let (oz, uz) = (self.oz, self.uz);
            let z_low = oz + uz * if uz < 0.0 { t_exit } else { self.t_in };
            let above = z_low > bmax;
            if !above {
                break;
            }
            if t_exit >= self.t1 || (uz >= 0.0 && oz + uz * self.t_in >= self.hf.max_elevation) {
                return Block::Miss;
            }
            // Out through the face the ray leaves by (x on a tie, as the cell traversal does).
            self.t_in = t_exit;
            let through_x = tbx <= tby;
            let past = if through_x {
                first_past_block(block.0, self.sx, self.w)
            } else {
                first_past_block(block.1, self.sy, self.h)
            };
            let Some(past) = past else {
                return Block::Miss;
            };
            self.block = if through_x {
                (past >> BLOCK_SHIFT, block.1)
            } else {
                (block.0, past >> BLOCK_SHIFT)
            };
            last_pass = Some((block, through_x, past));
        }
        if let Some((block, through_x, past)) = last_pass {
            self.step_out(block, through_x, past);
        }
        Block::Inside
    }

    /// Sets the walk in cell `past` (along the exit axis) past block `block`, left through its
    /// x face (else its y face) at distance `t_in`: the other index follows the exit point.
    #[inline]
    fn step_out(&mut self, block: (i64, i64), through_x: bool, past: i64) {
        if through_x {
            self.ix = past;
            self.iy = self.index_in_block(self.oy, self.uy, block.1, self.h);
            self.entry = Entry::X(self.boundary(past - self.sx, self.sx));
        } else {
            self.iy = past;
            self.ix = self.index_in_block(self.ox, self.ux, block.0, self.w);
            self.entry = Entry::Y(self.boundary(past - self.sy, self.sy));
        }
        self.aim_at_next_boundaries();
    }

    /// The index along one axis at the exit point (distance `t_in`), kept in block `b`'s span.
    #[inline]
    fn index_in_block(&self, o: f64, v: f64, b: i64, n: i64) -> i64 {
        start_index_at(o, v, self.t_in, self.d, n)
            .clamp((b * BLOCK).min(n - 1), ((b + 1) * BLOCK - 1).min(n - 1))
    }

    /// Crosses the current cell: the ray hits its side face when it entered below the top
    /// (or started inside the column), its top when it descends to it before leaving the cell;
    /// else it moves on to the next cell unless nothing can be hit any more (it is level or
    /// rising above every column, or leaves its range or the world).
    #[inline]
    fn cross_cell(&mut self) -> Crossing {
        let k = (self.iy * self.w + self.ix) as usize;
        let top = self.hf.elevation[k];
        let t_out = self.tx.min(self.ty).min(self.t1);
        let z_in = self.oz + self.uz * self.t_in;
        if z_in < top {
            return Crossing::Hit(self.side_hit(k, z_in));
        }
        if self.uz < 0.0 {
            let z_out = self.oz + self.uz * t_out;
            if z_out <= top {
                let t = ((top - self.oz) / self.uz).clamp(self.t_in, t_out);
                let (px, py) = (self.ox + self.ux * t, self.oy + self.uy * t);
                return Crossing::Hit(self.hit(k, Point3::new(px, py, top), t, Face::Top));
            }
        } else if z_in >= self.hf.max_elevation {
            return Crossing::Miss;
        }
        if self.advance(t_out) {
            Crossing::Next
        } else {
            Crossing::Miss
        }
    }

    /// Leaves the current cell at distance `t_out` for the next one; false when the ray leaves
    /// its range or the world instead.
    #[inline(always)]
    fn advance(&mut self, t_out: f64) -> bool {
        if t_out >= self.t1 {
            return false;
        }
        self.t_in = t_out;
        if self.tx <= self.ty {
            self.ix += self.sx;
            self.entry = Entry::X(self.boundary(self.ix - self.sx, self.sx));
            self.tx += self.tdx;
            self.ix >= 0 && self.ix < self.w
        } else {
            self.iy += self.sy;
            self.entry = Entry::Y(self.boundary(self.iy - self.sy, self.sy));
            self.ty += self.tdy;
            self.iy >= 0 && self.iy < self.h
        }
    }

    /// The hit on the side face of cell `k` the ray entered at height `z_in`: on the boundary
    /// it crossed.
    #[inline]
    fn side_hit(&self, k: usize, z_in: f64) -> RayHit {
        let t = self.t_in;
        let (px, py) = match self.entry {
            Entry::X(bx) => (bx, self.oy + self.uy * t),
            Entry::Y(by) => (self.ox + self.ux * t, by),
            Entry::Start => (self.ox + self.ux * t, self.oy + self.uy * t),
        };
        self.hit(k, Point3::new(px, py, z_in), t, Face::Side)
    }

    /// A hit at local point `p`, distance `range`, in cell `k`.
    #[inline]
    fn hit(&self, k: usize, p: Point3, range: f64, face: Face) -> RayHit {
        let min = self.hf.rect.min;
        RayHit {
            point: Point3::new(p.x + self.x0, p.y + self.y0, p.z),
            range,
            cell: Cell::new(min.i + self.ix as i32, min.j + self.iy as i32),
            index: k,
            face,
        }
    }
}

/// Clips the horizontal projection of a ray (local origin `o`, direction `u`, reciprocals `r`)
/// to the rectangle `[0, extent[0]] × [0, extent[1]]` and to `max_range` (slab method):
/// `(t0, t1, enter)`, where `enter` holds the slab entry times (to know which border an
/// outside ray enters through). `None` when the ray misses the rectangle.
#[inline]
fn clip_to_rect(
    o: [f64; 2],
    u: [f64; 2],
    r: [f64; 2],
    extent: [f64; 2],
    max_range: f64,
) -> Option<(f64, f64, [f64; 2])> {
    let mut t1 = max_range;
    let mut enter = [f64::NEG_INFINITY; 2];
    for a in 0..2 {
        if u[a] == 0.0 {
            if o[a] < 0.0 || o[a] >= extent[a] {
                return None;
            }
        } else {
            let (ta, tb) = ((0.0 - o[a]) * r[a], (extent[a] - o[a]) * r[a]);
            enter[a] = ta.min(tb);
            t1 = t1.min(ta.max(tb));
        }
    }
    let t0 = enter[0].max(enter[1]).max(0.0);
    if t0 > t1 {
        return None;
    }
    Some((t0, t1, enter))
}

/// A descending ray cannot hit anything while it is above the highest column (`z_max`): the
/// distance where it comes down to that height (exact, and most of a downward-looking camera's
/// rays over open ground) if later than `t0`, and whether that skip applies. It aims 1 nm above
/// the top so that rounding never puts the start below a column's top.
#[inline]
fn skip_to_top(oz: f64, uz: f64, z_max: f64, t0: f64) -> (f64, bool) {
    let z_top = z_max + 1e-9;
    let t_top = if uz < 0.0 && oz > z_top {
        (oz - z_top) / -uz
    } else {
        f64::NEG_INFINITY
    };
    (t0.max(t_top), t_top > t0)
}

/// How a ray enters the cell its walk starts in at distance `t0`: through the world's border
/// it enters by (slab entry times `enter`, direction `u`, world extent `extent`), or not at all
/// when it starts inside the world or was brought down by the top skip.
#[inline]
fn start_entry(skipped: bool, t0: f64, enter: [f64; 2], u: [f64; 2], extent: [f64; 2]) -> Entry {
    if skipped {
        Entry::Start
    } else if t0 > 0.0 && enter[0] >= enter[1] {
        Entry::X(if u[0] > 0.0 { 0.0 } else { extent[0] })
    } else if t0 > 0.0 {
        Entry::Y(if u[1] > 0.0 { 0.0 } else { extent[1] })
    } else {
        Entry::Start
    }
}

/// The first index along one axis past block `b` for a ray stepping `s`, if inside `0..n`.
#[inline]
fn first_past_block(b: i64, s: i64, n: i64) -> Option<i64> {
    let k = if s > 0 {
        (b + 1) * BLOCK
    } else {
        b * BLOCK - 1
    };
    (0..n).contains(&k).then_some(k)
}
