//! The cells an azimuth column's horizontal line crosses ("stations"), each with the highest
//! column near it, for bounding where the column's rays may first meet the terrain.
//!
//! The rays of a column follow the line up to rounding, far less than a cell, so a ray is over
//! a cell of the 3 × 3 neighbourhood of the line's cell at the same horizontal distance: the
//! highest column of that neighbourhood bounds what the ray can meet there. Along the line,
//! 8 × 8 blocks of cells with their highest neighbourhood are skipped in one step when a ray
//! passes above them, as the walk of a single ray skips blocks.

use super::{BLOCK, BLOCK_SHIFT, Heightfield, clip_to_rect, start_index_at};

/// The neighbourhood maxima of a heightfield, on the world rectangle grown by one cell on every
/// side (so that a ray passing just outside the world is covered too).
#[derive(Clone, Debug)]
pub(super) struct Near {
    /// Highest elevation of each cell's 3 × 3 neighbourhood (row-major, `(W + 2) × (H + 2)`,
    /// −∞ where there is no surface). `f32` holds the elevations exactly (they come from `f32`)
    /// in half the memory.
    cells: Vec<f32>,
    /// The highest of those per [`BLOCK`] × [`BLOCK`] block of the grown grid (row-major).
    blocks: Vec<f32>,
    /// Cells and blocks per row of the grown grid.
    width: usize,
    blocks_w: usize,
}

impl Near {
    /// The neighbourhood maxima of `hf` (at least one cell wide and high).
    pub(super) fn new(hf: &Heightfield) -> Self {
        let (w, h) = (hf.rect.width as usize, hf.rect.height as usize);
        let width = w + 2;
        // Maximum over three columns, then over three rows.
        let mut rows = vec![f32::NEG_INFINITY; width * h];
        for (src, dst) in hf
            .elevation
            .chunks_exact(w.max(1))
            .zip(rows.chunks_exact_mut(width))
        {
            for (i, &z) in src.iter().enumerate() {
                for m in &mut dst[i..i + 3] {
                    *m = m.max(z as f32);
                }
            }
        }
        let mut cells = vec![f32::NEG_INFINITY; width * (h + 2)];
        for (j, src) in rows.chunks_exact(width).enumerate() {
            for dst in cells.chunks_exact_mut(width).skip(j).take(3) {
                for (m, &z) in dst.iter_mut().zip(src) {
                    *m = m.max(z);
                }
            }
        }
        let b = BLOCK as usize;
        let blocks_w = width.div_ceil(b);
        let mut blocks = vec![f32::NEG_INFINITY; blocks_w * (h + 2).div_ceil(b)];
        for (k, &z) in cells.iter().enumerate() {
            let m = &mut blocks[(k / width) / b * blocks_w + (k % width) / b];
            *m = m.max(z);
        }
        Self {
            cells,
            blocks,
            width,
            blocks_w,
        }
    }
}

/// A stretch of the line, from horizontal distance `a` to `b`, with the highest column near it.
#[derive(Clone, Copy)]
pub(super) struct Stretch {
    pub(super) a: f64,
    pub(super) b: f64,
    pub(super) top: f64,
}

/// The walk along the line through the grown grid (2-D DDA). Its distances accumulate; their
/// rounding stays far below the margins of the column's tests (see `columns`).
#[derive(Clone)]
pub(super) struct Stations<'a> {
    near: &'a Near,
    d: f64,
    /// Cells of the grown grid per row and column.
    n: [i64; 2],
    /// Origin and unit direction of the line, reciprocals of the direction, step per axis and
    /// distance between boundary crossings.
    o: [f64; 2],
    g: [f64; 2],
    r: [f64; 2],
    s: [i64; 2],
    dt: [f64; 2],
    /// Where the line leaves the grid or the rays' reach.
    end: f64,
    /// The current cell, where the line entered it (through a boundary across `entry`, or
    /// `None` at the line's start) and its next boundary crossings.
    i: [i64; 2],
    a: f64,
    entry: Option<usize>,
    next: [f64; 2],
    /// Whether the current cell is the first of its block on the line.
    block_start: bool,
    done: bool,
}

impl<'a> Stations<'a> {
    /// The line from `o` (grown-grid frame) along unit `g`, up to `reach`.
    pub(super) fn new(
        near: &'a Near,
        d: f64,
        n: [i64; 2],
        o: [f64; 2],
        g: [f64; 2],
        reach: f64,
    ) -> Self {
        let r = [1.0 / g[0], 1.0 / g[1]];
        let extent = [n[0] as f64 * d, n[1] as f64 * d];
        let clipped = clip_to_rect(o, g, r, extent, reach);
        let (a, end) = clipped.map_or((0.0, -1.0), |(t0, t1, _)| (t0, t1));
        let mut stations = Self {
            near,
            d,
            n,
            o,
            g,
            r,
            s: [
                if g[0] > 0.0 { 1 } else { -1 },
                if g[1] > 0.0 { 1 } else { -1 },
            ],
            dt: [d * r[0].abs(), d * r[1].abs()],
            end,
            i: [
                start_index_at(o[0], g[0], a, d, n[0]),
                start_index_at(o[1], g[1], a, d, n[1]),
            ],
            a,
            entry: None,
            next: [0.0; 2],
            block_start: true,
            done: a.partial_cmp(&end).is_none_or(|o| o.is_gt()),
        };
        stations.aim();
        stations
    }

    /// The next boundary crossings from the current cell, from its indices.
    #[inline]
    fn aim(&mut self) {
        for k in 0..2 {
            let b = self.i[k] + (self.s[k] > 0) as i64;
            self.next[k] = if self.g[k] != 0.0 {
                (b as f64 * self.d - self.o[k]) * self.r[k]
            } else {
                f64::INFINITY
            };
        }
    }

    /// The current cell's stretch, `None` past the end of the line.
    #[inline(always)]
    pub(super) fn current(&self) -> Option<Stretch> {
        if self.done {
            return None;
        }
        let top = self.near.cells[self.i[1] as usize * self.near.width + self.i[0] as usize];
        Some(Stretch {
            a: self.a,
            b: self.next[0].min(self.next[1]).min(self.end),
            top: top as f64,
        })
    }

    /// A copy of the walk's position for looking ahead of it, `None` past the end of the line.
    #[inline(always)]
    pub(super) fn cursor(&self) -> Option<Cursor> {
        (!self.done).then_some(Cursor {
            i: self.i,
            a: self.a,
            entry: self.entry,
            next: self.next,
            s: self.s,
            dt: self.dt,
            end: self.end,
        })
    }

    /// The line's last boundary crossing across `axis` before the current cell's exit (−∞
    /// when it does not cross that axis).
    #[inline(always)]
    pub(super) fn last_crossing(&self, axis: usize) -> f64 {
        if self.g[axis] != 0.0 {
            self.next[axis] - self.dt[axis]
        } else {
            f64::NEG_INFINITY
        }
    }

    /// Moves on to the next cell.
    #[inline(always)]
    pub(super) fn advance(&mut self) {
        let k = if self.next[0] <= self.next[1] { 0 } else { 1 };
        let b = self.next[k];
        self.i[k] += self.s[k];
        self.next[k] += self.dt[k];
        self.a = b;
        self.entry = Some(k);
        // A step into another block lands on the block's near edge.
        self.block_start = self.i[k] & (BLOCK - 1) == if self.s[k] > 0 { 0 } else { BLOCK - 1 };
        self.done = b >= self.end || !(0..self.n[k]).contains(&self.i[k]);
    }

    /// When the current cell is the first of its block on the line: the stretch of the line
    /// through the block, with the block's highest neighbourhood.
    #[inline(always)]
    pub(super) fn block(&self) -> Option<Stretch> {
        if self.done || !self.block_start {
            return None;
        }
        let (bx, by) = (self.i[0] >> BLOCK_SHIFT, self.i[1] >> BLOCK_SHIFT);
        let top = self.near.blocks[by as usize * self.near.blocks_w + bx as usize];
        let (ex, ey) = self.block_exits();
        Some(Stretch {
            a: self.a,
            b: ex.min(ey).min(self.end),
            top: top as f64,
        })
    }

    /// Where the line leaves the current cell's block through its x and its y faces.
    #[inline]
    fn block_exits(&self) -> (f64, f64) {
        let exit = |k: usize| {
            let b = self.i[k] >> BLOCK_SHIFT;
            let edge = if self.s[k] > 0 {
                (b + 1) * BLOCK
            } else {
                b * BLOCK
            };
            if self.g[k] != 0.0 {
                (edge as f64 * self.d - self.o[k]) * self.r[k]
            } else {
                f64::INFINITY
            }
        };
        (exit(0), exit(1))
    }

    /// Moves on to the first cell past the current cell's block.
    pub(super) fn skip_block(&mut self) {
        let (ex, ey) = self.block_exits();
        let (k, t) = if ex <= ey { (0, ex) } else { (1, ey) };
        if t >= self.end {
            self.done = true;
            return;
        }
        let block = self.i[k] >> BLOCK_SHIFT;
        self.i[k] = if self.s[k] > 0 {
            (block + 1) * BLOCK
        } else {
            block * BLOCK - 1
        };
        if !(0..self.n[k]).contains(&self.i[k]) {
            self.done = true;
            return;
        }
        // The other index follows the exit point, kept within the block's span.
        let j = 1 - k;
        let bj = self.i[j] >> BLOCK_SHIFT;
        self.i[j] = start_index_at(self.o[j], self.g[j], t, self.d, self.n[j])
            .clamp(bj * BLOCK, ((bj + 1) * BLOCK - 1).min(self.n[j] - 1));
        self.a = t;
        self.entry = Some(k);
        self.block_start = true;
        self.aim();
    }
}

/// The line's cells ahead of the walk, one by one, without their neighbourhoods.
#[derive(Clone, Copy)]
pub(super) struct Cursor {
    /// The cell of the grown grid, where the line enters it and across which axis (`None` at
    /// the line's start).
    pub(super) i: [i64; 2],
    pub(super) a: f64,
    pub(super) entry: Option<usize>,
    next: [f64; 2],
    s: [i64; 2],
    dt: [f64; 2],
    end: f64,
}

impl Cursor {
    /// Where the line leaves the cell, and across which axis (`None`: the line ends there).
    #[inline(always)]
    pub(super) fn exit(&self) -> (f64, Option<usize>) {
        let k = if self.next[0] <= self.next[1] { 0 } else { 1 };
        let b = self.next[k];
        if b < self.end {
            (b, Some(k))
        } else {
            (self.end, None)
        }
    }

    /// Moves on to the next cell (which may lie past the grid).
    #[inline(always)]
    pub(super) fn advance(&mut self) {
        let k = if self.next[0] <= self.next[1] { 0 } else { 1 };
        self.a = self.next[k];
        self.i[k] += self.s[k];
        self.next[k] += self.dt[k];
        self.entry = Some(k);
    }
}
