//! Moving a walk on without looking at the cells it crosses, in the very state the full walk
//! would reach.
//!
//! A walk's boundary distances accumulate: the next x crossing is the last one plus a constant,
//! rounded at every step, so the state in a cell depends on every step since the walk last
//! computed them afresh (at its start and after a block pass), and no fresh start mid-way
//! reproduces their last bits. Within a block the walk merges two such chains, the x and the y
//! crossings, taking the earlier (x on a tie); up to a distance it takes exactly the
//! crossings of either chain that come by then, so the chains can be run on their own
//! (additions only, no branch per cell) and the walk set where the merged walk would be.

use super::{BLOCK, Entry, Walk};

/// Where [`Walk::coast_in_block`] left a walk.
enum InBlock {
    /// In the first cell it does not leave by the distance.
    Stopped,
    /// In the first cell of another block.
    Left,
    /// It meets nothing any more (it left the world or its range).
    Miss,
}

/// The crossings of one axis a walk takes within its block: `at[..n]` are the distances of the
/// crossings taken (the first `steps` stay in the block, crossing `steps` leaves it), `next`
/// the distance of the first one not taken.
struct Chain {
    at: [f64; BLOCK as usize + 1],
    n: usize,
    next: f64,
}

impl Chain {
    /// The crossings from `first` on, `delta` apart (accumulated as the walk does), up to the
    /// one leaving the block after `steps` crossings within it, taken while `take` holds.
    #[inline(always)]
    fn run(first: f64, delta: f64, steps: usize, take: impl Fn(f64) -> bool) -> Self {
        let mut chain = Self {
            at: [0.0; BLOCK as usize + 1],
            n: 0,
            next: first,
        };
        while chain.n <= steps && take(chain.next) {
            chain.at[chain.n] = chain.next;
            chain.n += 1;
            chain.next += delta;
        }
        chain
    }

    /// Whether the crossing that leaves the block is taken.
    #[inline(always)]
    fn leaves(&self, steps: usize) -> bool {
        self.n > steps
    }

    /// How many of the taken crossings come before `t` (or at `t`, with `at_tie`).
    #[inline(always)]
    fn before(&self, t: f64, at_tie: bool) -> usize {
        self.at[..self.n]
            .iter()
            .take_while(|&&c| c < t || (at_tie && c == t))
            .count()
    }

    /// The distance of crossing `k` (`k <= n`).
    #[inline(always)]
    fn distance(&self, k: usize) -> f64 {
        if k < self.n { self.at[k] } else { self.next }
    }
}

impl Walk<'_> {
    /// Walks on without looking at the cells it leaves by distance `t_stop`, which the caller
    /// knows the ray to pass above: the same crossings and block passes as [`Walk::run`], so
    /// the walk stops in the first cell it does not leave by `t_stop`, in the very state `run`
    /// would reach it in. `None` when the ray meets nothing any more.
    #[inline(always)]
    pub(super) fn coast(&mut self, t_stop: f64) -> Option<()> {
        loop {
            self.enter_block()?;
            match self.coast_in_block(t_stop) {
                InBlock::Stopped => return Some(()),
                InBlock::Left => {}
                InBlock::Miss => return None,
            }
        }
    }

    /// [`Walk::coast`] within the current block: takes every crossing the cell-by-cell walk
    /// would take by `t_stop` (and before the range's end `t1`), up to the one that leaves
    /// the block.
    #[inline(always)]
    fn coast_in_block(&mut self, t_stop: f64) -> InBlock {
        let t1 = self.t1;
        let take = |t: f64| t <= t_stop && t < t1;
        let (kx, ky) = (self.steps_in_block_x(), self.steps_in_block_y());
        let x = Chain::run(self.tx, self.tdx, kx, take);
        let y = Chain::run(self.ty, self.tdy, ky, take);
        let (nx, ny, left) = match (x.leaves(kx), y.leaves(ky)) {
            // The walk leaves the block at the earlier of the leaving crossings (x on a tie),
            // after the crossings of the other axis that come before it.
            (true, yl) if !yl || x.at[kx] <= y.at[ky] => (kx + 1, y.before(x.at[kx], false), true),
            (_, true) => (x.before(y.at[ky], true), ky + 1, true),
            _ => (x.n, y.n, false),
        };
        self.take_crossings(&x, nx, &y, ny);
        if left {
            let inside = (0..self.w).contains(&self.ix) && (0..self.h).contains(&self.iy);
            return if inside { InBlock::Left } else { InBlock::Miss };
        }
        // Every crossing by `t_stop` is taken: the walk stops here unless its range ends first.
        if self.tx.min(self.ty).min(t1) <= t_stop {
            InBlock::Miss
        } else {
            InBlock::Stopped
        }
    }

    /// Moves the walk over the first `nx` crossings of chain `x` and `ny` of chain `y`: into
    /// the cell they lead to, entered through the last of them (the y one on a tie, taken
    /// after the x one).
    #[inline(always)]
    fn take_crossings(&mut self, x: &Chain, nx: usize, y: &Chain, ny: usize) {
        if nx + ny == 0 {
            return;
        }
        self.ix += self.sx * nx as i64;
        self.iy += self.sy * ny as i64;
        let last_x = nx > 0 && (ny == 0 || x.at[nx - 1] > y.at[ny - 1]);
        if last_x {
            self.t_in = x.at[nx - 1];
            self.entry = Entry::X(self.boundary(self.ix - self.sx, self.sx));
        } else {
            self.t_in = y.at[ny - 1];
            self.entry = Entry::Y(self.boundary(self.iy - self.sy, self.sy));
        }
        self.tx = x.distance(nx);
        self.ty = y.distance(ny);
    }

    /// How many x crossings the walk can take from the current cell within its block.
    #[inline(always)]
    fn steps_in_block_x(&self) -> usize {
        let first = self.block.0 * BLOCK;
        let last = (first + BLOCK).min(self.w) - 1;
        (if self.sx > 0 {
            last - self.ix
        } else {
            self.ix - first
        }) as usize
    }

    /// How many y crossings the walk can take from the current cell within its block.
    #[inline(always)]
    fn steps_in_block_y(&self) -> usize {
        let first = self.block.1 * BLOCK;
        let last = (first + BLOCK).min(self.h) - 1;
        (if self.sy > 0 {
            last - self.iy
        } else {
            self.iy - first
        }) as usize
    }
}

#[cfg(test)]
mod tests {
    use strider_core::{Cell, CellRect, Point3};

    use super::super::{Entry, Heightfield, Walk};

    /// The walk's state, bit for bit.
    fn state(w: &Walk) -> ([i64; 2], [u64; 3], Option<u64>, (i64, i64)) {
        let entry = match w.entry {
            Entry::Start => None,
            Entry::X(b) => Some(b.to_bits()),
            Entry::Y(b) => Some(!b.to_bits()),
        };
        let t = [w.tx, w.ty, w.t_in].map(f64::to_bits);
        ([w.ix, w.iy], t, entry, w.block)
    }

    /// The reference: the walk's own steps, cell by cell, without looking at the cells.
    fn coast_cell_by_cell(w: &mut Walk, t_stop: f64) -> Option<()> {
        loop {
            w.enter_block()?;
            let t_out = w.tx.min(w.ty).min(w.t1);
            let skipped = t_out <= t_stop;
            if !skipped {
                return Some(());
            }
            if !w.advance(t_out) {
                return None;
            }
        }
    }

    /// Coasting block by block leaves the walk in the very state of coasting cell by cell, for
    /// rays through cell corners (exact ties between x and y crossings, at block edges too)
    /// and in general directions, over low ground (block passes) and higher (none).
    #[test]
    fn coasting_by_blocks_equals_coasting_by_cells() {
        let (w, h) = (61, 53);
        let mut elevation = vec![0.0f32; w * h];
        for (k, z) in elevation.iter_mut().enumerate() {
            *z = if k % 7 == 0 {
                0.3
            } else {
                (k % 5) as f32 * 0.01
            };
        }
        let rect = CellRect::new(Cell::new(-3, 2), w as u32, h as u32);
        let hf = Heightfield::new(0.125, rect, &elevation).unwrap();
        let s = std::f64::consts::FRAC_1_SQRT_2;
        let mut compared = 0;
        // Cell corners on and off block corners, and general points.
        for (x, y) in [
            (0.0, 1.0),
            (0.0, 1.375),
            (1.0, 2.0),
            (0.5, 3.25),
            (0.3, 1.7),
            (-1.0, 0.5),
        ] {
            for g in [
                [s, s],
                [-s, s],
                [s, -s],
                [1.0, 0.0],
                [0.0, 1.0],
                [0.6, 0.8],
                [-0.8, 0.6],
            ] {
                for e in [-0.02f64, -0.2, 0.0, 0.1] {
                    let u = [e.cos() * g[0], e.cos() * g[1], e.sin()];
                    for z in [0.02, 0.5] {
                        let origin = Point3::new(x, y, z);
                        for t_stop in [0.0, 0.3, 1.0, 1.5, 2.75, 4.0, 20.0] {
                            let Some(mut a) = Walk::start(&hf, origin, u, 6.0) else {
                                continue;
                            };
                            let mut b = Walk::start(&hf, origin, u, 6.0).unwrap();
                            let (ra, rb) = (a.coast(t_stop), coast_cell_by_cell(&mut b, t_stop));
                            assert_eq!(ra, rb, "{origin:?} {u:?} {t_stop}");
                            if ra.is_some() {
                                assert_eq!(state(&a), state(&b), "{origin:?} {u:?} {t_stop}");
                            }
                            compared += 1;
                        }
                    }
                }
            }
        }
        assert!(compared > 1200, "{compared}");
    }
}
