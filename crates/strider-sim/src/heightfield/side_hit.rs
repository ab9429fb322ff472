//! A descending ray's hit on a side face, at its walk's own distance, without the walk.
//!
//! A side hit lies at the distance where the walk entered the cell, which it accumulated:
//! the distance it computed afresh in the cell where it last did so (where it started, or
//! landed after a run of block passes), plus one equal step per boundary crossed since. That
//! cell is found without the walk: a descending ray passes over a block exactly when it is
//! above the block's highest column where it leaves the block, which depends on the block
//! alone, so looking back from the hit's block along the blocks the ray crosses, the nearest
//! block passed gives it. The sum is then taken as the walk takes it.

use strider_core::{Cell, Point3};

use super::{
    BLOCK, BLOCK_SHIFT, Entry, Face, Heightfield, RayHit, clip_to_rect, skip_to_top, start_entry,
    start_index_at,
};

/// Unit roundoff of `f64`.
const U: f64 = f64::EPSILON / 2.0;

impl Heightfield {
    /// The result of `self.cast_unit(origin, u, max_range)` for a descending ray known to meet
    /// nothing before it enters world cell `cell` across `axis` (0: x, 1: y), clearly below the
    /// cell's top: a hit on that side face. `span` bounds the local coordinates of the ray's
    /// path (|x| + |y| + horizontal reach), hence the rounding of its distances. `None` when a
    /// block corner lies too close to the ray to tell the blocks it crosses.
    pub(super) fn prove_side_hit(
        &self,
        origin: Point3,
        u: [f64; 3],
        max_range: f64,
        span: f64,
        (cell, axis): ([i64; 2], usize),
    ) -> Option<RayHit> {
        Ray::new(self, origin, u, max_range, span)?.side_hit(cell, axis)
    }
}

/// A descending ray in the local frame of [`super::Walk`], with its quantities as the walk has
/// them.
struct Ray<'a> {
    hf: &'a Heightfield,
    d: f64,
    n: [i64; 2],
    x0: f64,
    y0: f64,
    o: [f64; 3],
    u: [f64; 3],
    /// Reciprocals of `u[0]`, `u[1]`, distances between boundary crossings, step directions.
    r: [f64; 2],
    td: [f64; 2],
    s: [i64; 2],
    /// Slab entry distances, and where the ray starts and ends in the world (or its range).
    enter: [f64; 2],
    t0: f64,
    t1: f64,
    /// Bound on the difference between a fresh boundary distance and the walk's accumulated
    /// one, both rounded.
    slack: f64,
}

/// A cell where the walk computes its boundary distances afresh: entered at `t_in`.
struct Fresh {
    i: [i64; 2],
    t_in: f64,
    entry: Entry,
}

impl<'a> Ray<'a> {
    fn new(
        hf: &'a Heightfield,
        origin: Point3,
        u: [f64; 3],
        max_range: f64,
        span: f64,
    ) -> Option<Self> {
        let descending = u[2] < 0.0;
        if !descending {
            return None;
        }
        let d = hf.resolution;
        let n = [hf.rect.width as i64, hf.rect.height as i64];
        // The same local frame and clipping as `Walk::start`.
        let x0 = hf.rect.min.i as f64 * d;
        let y0 = hf.rect.min.j as f64 * d;
        let o = [origin.x - x0, origin.y - y0, origin.z];
        let r = [1.0 / u[0], 1.0 / u[1]];
        let extent = [n[0] as f64 * d, n[1] as f64 * d];
        let (t0, t1, enter) = clip_to_rect([o[0], o[1]], [u[0], u[1]], r, extent, max_range)?;
        // The walk rounds once per crossing (at most two per cell of the span, plus those
        // after block passes), a fresh distance a few times.
        let crossings = 2.0 * span / d + 64.0;
        let scale = |r: f64| if r.is_finite() { span * r.abs() } else { 0.0 };
        let slack = 8.0 * U * crossings * (scale(r[0]) + scale(r[1]) + max_range);
        let ray = Self {
            hf,
            d,
            n,
            x0,
            y0,
            o,
            u,
            r,
            td: [d * r[0].abs(), d * r[1].abs()],
            s: [
                if u[0] > 0.0 { 1 } else { -1 },
                if u[1] > 0.0 { 1 } else { -1 },
            ],
            enter,
            t0,
            t1,
            slack,
        };
        slack.is_finite().then_some(ray)
    }

    /// The hit on the side of `cell`, entered across `axis`: at the distance the walk has
    /// there, summed from where it last computed it afresh.
    fn side_hit(&self, cell: [i64; 2], axis: usize) -> Option<RayHit> {
        let fresh = self.last_fresh(cell)?;
        let (t, entry) = if fresh.i == cell {
            (fresh.t_in, fresh.entry)
        } else {
            // Crossings across `axis` from the fresh cell's exit to this cell's entry.
            let steps = (cell[axis] - fresh.i[axis]) * self.s[axis] - 1;
            if steps < 0 {
                return None;
            }
            let mut t = self.crossing(axis, fresh.i[axis]);
            for _ in 0..steps {
                t += self.td[axis];
            }
            // The boundary the walk entered through: the exit of the cell before.
            let b = self.boundary(axis, cell[axis] - self.s[axis]);
            (t, if axis == 0 { Entry::X(b) } else { Entry::Y(b) })
        };
        // The walk is in the cell only before its range ends, and hits its side there.
        let k = (cell[1] * self.n[0] + cell[0]) as usize;
        let (top, z) = (self.hf.elevation[k], self.o[2] + self.u[2] * t);
        if !(t < self.t1 && z < top) {
            return None;
        }
        let (o, u) = (self.o, self.u);
        let p = match entry {
            Entry::X(bx) => [bx, o[1] + u[1] * t],
            Entry::Y(by) => [o[0] + u[0] * t, by],
            Entry::Start => [o[0] + u[0] * t, o[1] + u[1] * t],
        };
        let min = self.hf.rect.min;
        Some(RayHit {
            point: Point3::new(p[0] + self.x0, p[1] + self.y0, z),
            range: t,
            cell: Cell::new(min.i + cell[0] as i32, min.j + cell[1] as i32),
            index: k,
            face: Face::Side,
        })
    }

    /// The boundary through which the ray leaves cell index `k` along `axis`
    /// (`Walk::boundary`).
    #[inline]
    fn boundary(&self, axis: usize, k: i64) -> f64 {
        if self.s[axis] > 0 {
            (k + 1) as f64 * self.d
        } else {
            k as f64 * self.d
        }
    }

    /// The distance at which the ray leaves cell index `k` along `axis`, computed afresh as the
    /// walk does (`Walk::aim_at_next_boundaries`).
    #[inline]
    fn crossing(&self, axis: usize, k: i64) -> f64 {
        (self.boundary(axis, k) - self.o[axis]) * self.r[axis]
    }

    /// Where the walk last computed its boundary distances afresh before it reaches cell
    /// `target`: in the cell it landed in after its last run of block passes, or at its start.
    /// Looks back along the blocks the ray crosses, from `target`'s, for the nearest one
    /// passed; `None` when the ray passes a block's corner too closely to tell which block
    /// comes before (the walk steps between blocks with its accumulated distances).
    fn last_fresh(&self, target: [i64; 2]) -> Option<Fresh> {
        let (start, skipped) = self.start();
        let first = start.i.map(|i| i >> BLOCK_SHIFT);
        let blocks = [
            self.hf.blocks_w as i64,
            (self.hf.block_max.len() / self.hf.blocks_w.max(1)) as i64,
        ];
        let mut block = target.map(|i| i >> BLOCK_SHIFT);
        for _ in 0..(self.n[0] + self.n[1]) / BLOCK + 4 {
            if block == first {
                return Some(start);
            }
            // The block before, across the face the ray entered through (the later entry),
            // clearly away from that face's ends.
            let enter = [0, 1].map(|a| self.block_edge(a, block[a], false));
            let a = if enter[0] > enter[1] { 0 } else { 1 };
            let leave_other = self.block_edge(1 - a, block[1 - a], true);
            let clear = enter[a] - enter[1 - a] > 2.0 * self.slack
                && leave_other - enter[a] > 2.0 * self.slack;
            let mut before = block;
            before[a] -= self.s[a];
            if !clear
                || !(0..blocks[0]).contains(&before[0])
                || !(0..blocks[1]).contains(&before[1])
            {
                return None;
            }
            // Passed over as the walk's block pass decides it (the walk tests every block it
            // enters but the one the top skip brings it down into).
            let leave = [0, 1].map(|a| self.block_edge(a, before[a], true));
            let t_exit = leave[0].min(leave[1]).min(self.t1);
            let bmax =
                self.hf.block_max[before[1] as usize * self.hf.blocks_w + before[0] as usize];
            let tested = !(skipped && before == first);
            if tested && self.o[2] + self.u[2] * t_exit > bmax {
                return Some(self.landing(before, a, block[a], t_exit));
            }
            block = before;
        }
        None
    }

    /// The distance at which the ray crosses the edge of block index `b` along `axis` that it
    /// leaves the block through (else enters it through), as the walk's block pass computes
    /// it.
    #[inline]
    fn block_edge(&self, axis: usize, b: i64, leaving: bool) -> f64 {
        if self.u[axis] == 0.0 {
            return if leaving {
                f64::INFINITY
            } else {
                f64::NEG_INFINITY
            };
        }
        let far = leaving == (self.u[axis] > 0.0);
        let edge = if far { (b + 1) * BLOCK } else { b * BLOCK };
        (edge as f64 * self.d - self.o[axis]) * self.r[axis]
    }

    /// Where the walk starts (`Walk::start`), and whether the top skip brought it down there.
    fn start(&self) -> (Fresh, bool) {
        let (o, u) = (self.o, self.u);
        let (t0, skipped) = skip_to_top(o[2], u[2], self.hf.max_elevation, self.t0);
        let i = [0, 1].map(|a| start_index_at(o[a], u[a], t0, self.d, self.n[a]));
        let extent = [self.n[0] as f64 * self.d, self.n[1] as f64 * self.d];
        let entry = start_entry(skipped, t0, self.enter, [u[0], u[1]], extent);
        (Fresh { i, t_in: t0, entry }, skipped)
    }

    /// The cell the walk lands in after passing over `block`, left across `axis` at distance
    /// `t` into block index `into` along that axis (`Walk::step_out`).
    fn landing(&self, block: [i64; 2], axis: usize, into: i64, t: f64) -> Fresh {
        // The first cell past the block along `axis` (`first_past_block`).
        let past = into * BLOCK + if self.s[axis] > 0 { 0 } else { BLOCK - 1 };
        let (o, u, n) = (self.o, self.u, self.n);
        let j = 1 - axis;
        let other = start_index_at(o[j], u[j], t, self.d, n[j]).clamp(
            (block[j] * BLOCK).min(n[j] - 1),
            ((block[j] + 1) * BLOCK - 1).min(n[j] - 1),
        );
        let mut i = [0; 2];
        i[axis] = past;
        i[j] = other;
        let b = self.boundary(axis, past - self.s[axis]);
        let entry = if axis == 0 { Entry::X(b) } else { Entry::Y(b) };
        Fresh { i, t_in: t, entry }
    }
}
