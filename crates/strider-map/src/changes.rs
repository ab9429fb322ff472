//! Where the map changed, for consumers that keep derived layers up to date incrementally.
//!
//! Every mutation of a cell's elevation, colour or observed flag stamps the cell's *block*
//! (a square of [`CHANGE_BLOCK`] cells) with the map's revision. A consumer remembers the
//! revision it last saw and asks for the blocks stamped after it, so any number of consumers
//! can follow the same map, each at its own pace, and nothing has to be taken or reset.
//! Blocks rather than cells keep the bookkeeping to one hash entry per 256 cells, and a block
//! is fine enough that a sensor sweep over a corridor marks little beside what it saw.

use std::collections::HashMap;
use std::hash::BuildHasherDefault;

use strider_core::{Cell, CellRect};

use crate::tiles::{TileHasher, TileKey};

/// Side of a change block, in cells.
pub const CHANGE_BLOCK: i32 = 16;

/// Revision stamps of the map's blocks.
#[derive(Clone, Debug, Default)]
pub struct ChangeLog {
    revision: u64,
    /// The newest stamp of every block that ever changed.
    blocks: HashMap<TileKey, u64, BuildHasherDefault<TileHasher>>,
    /// (revision, block) for each block the first time it changes in a revision, in revision
    /// order: a query reads only the entries after the revision it has seen, so its cost
    /// follows the changes, not the map. Compacted to one entry per block (its newest stamp)
    /// when it holds more than twice as many entries as there are blocks.
    journal: Vec<(u64, TileKey)>,
    /// The block stamped last in this revision: consecutive cells of a row mostly share a
    /// block, and this skips their hash lookups.
    last: Option<TileKey>,
}

impl ChangeLog {
    /// Starts a new revision: the changes marked from now on are newer than every revision a
    /// consumer has seen so far.
    pub(crate) fn begin(&mut self) {
        self.revision += 1;
        self.last = None;
        if self.journal.len() > 2 * self.blocks.len() + 1024 {
            self.compact();
        }
    }

    /// Marks cell `c` changed in the current revision.
    #[inline]
    pub(crate) fn mark(&mut self, c: Cell) {
        let key = block_of(c);
        if self.last != Some(key) {
            if self.blocks.insert(key, self.revision) != Some(self.revision) {
                self.journal.push((self.revision, key));
            }
            self.last = Some(key);
        }
    }

    /// Marks every cell of `rect` changed in the current revision.
    pub(crate) fn mark_rect(&mut self, rect: CellRect) {
        if rect.is_empty() {
            return;
        }
        let (mi, mj) = crate::rect::max_corner(rect);
        let (lo, hi) = (block_of(rect.min), block_of(Cell::new(mi, mj)));
        for tj in lo.tj..=hi.tj {
            for ti in lo.ti..=hi.ti {
                let key = TileKey { tj, ti };
                if self.blocks.insert(key, self.revision) != Some(self.revision) {
                    self.journal.push((self.revision, key));
                }
            }
        }
        self.last = None;
    }

    /// Rewrites the journal as one entry per block at its newest stamp, in revision order.
    fn compact(&mut self) {
        self.journal = self.blocks.iter().map(|(&k, &rev)| (rev, k)).collect();
        self.journal.sort_unstable();
    }

    /// The current revision: a consumer that has caught up with the map remembers it.
    pub fn revision(&self) -> u64 {
        self.revision
    }

    /// The blocks changed after revision `seen`, as rectangles in row-major block order, runs
    /// of neighbouring changed blocks in a row merged into one rectangle.
    pub fn changed_since(&self, seen: u64) -> Vec<CellRect> {
        let first = self.journal.partition_point(|&(rev, _)| rev <= seen);
        let mut keys: Vec<TileKey> = self.journal[first..].iter().map(|&(_, k)| k).collect();
        keys.sort_unstable();
        keys.dedup();
        let mut out: Vec<CellRect> = Vec::new();
        let mut prev: Option<TileKey> = None;
        for k in keys {
            match (prev, out.last_mut()) {
                (Some(p), Some(r)) if p.tj == k.tj && p.ti + 1 == k.ti => {
                    r.width += CHANGE_BLOCK as u32;
                }
                _ => out.push(block_rect(k)),
            }
            prev = Some(k);
        }
        out
    }
}

fn block_of(c: Cell) -> TileKey {
    TileKey {
        tj: c.j.div_euclid(CHANGE_BLOCK),
        ti: c.i.div_euclid(CHANGE_BLOCK),
    }
}

fn block_rect(k: TileKey) -> CellRect {
    // Block indices come from `div_euclid` of an i32, so the corner fits an i32 again.
    CellRect::new(
        Cell::new(k.ti * CHANGE_BLOCK, k.tj * CHANGE_BLOCK),
        CHANGE_BLOCK as u32,
        CHANGE_BLOCK as u32,
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn consumers_see_only_newer_blocks_and_runs_merge() {
        let mut log = ChangeLog::default();
        log.begin();
        log.mark(Cell::new(0, 0));
        let seen = log.revision();
        assert_eq!(log.changed_since(0).len(), 1);
        assert!(log.changed_since(seen).is_empty());
        log.begin();
        log.mark(Cell::new(-1, 0)); // block (-1, 0)
        log.mark(Cell::new(16, 0)); // block (1, 0)
        log.mark(Cell::new(0, 17)); // block (0, 1)
        let r = log.changed_since(seen);
        assert_eq!(
            r,
            vec![
                CellRect::new(Cell::new(-16, 0), 16, 16),
                CellRect::new(Cell::new(16, 0), 16, 16),
                CellRect::new(Cell::new(0, 16), 16, 16),
            ]
        );
        // Block (0, 0) changes again: the row -1, 0, 1 becomes one run.
        log.begin();
        log.mark(Cell::new(3, 3));
        assert_eq!(
            log.changed_since(seen)[0],
            CellRect::new(Cell::new(-16, 0), 48, 16)
        );
    }

    #[test]
    fn queries_equal_the_newest_stamps_across_compactions() {
        let mut log = ChangeLog::default();
        let mut stamps: HashMap<TileKey, u64, BuildHasherDefault<TileHasher>> = Default::default();
        let mut x: u64 = 7;
        for _ in 0..3000 {
            log.begin();
            for _ in 0..(x % 5) {
                x = x
                    .wrapping_mul(6364136223846793005)
                    .wrapping_add(1442695040888963407);
                let c = Cell::new((x >> 40) as i32 % 200 - 100, (x >> 20) as i32 % 120 - 60);
                log.mark(c);
                stamps.insert(block_of(c), log.revision());
            }
            let seen = log.revision().saturating_sub(x % 40);
            let mut want: Vec<TileKey> = stamps
                .iter()
                .filter(|&(_, &rev)| rev > seen)
                .map(|(&k, _)| k)
                .collect();
            want.sort_unstable();
            let got: Vec<TileKey> = log
                .changed_since(seen)
                .iter()
                .flat_map(|r| {
                    (0..r.width as i32 / CHANGE_BLOCK)
                        .map(move |n| block_of(Cell::new(r.min.i + n * CHANGE_BLOCK, r.min.j)))
                })
                .collect();
            assert_eq!(got, want);
        }
        assert!(log.journal.len() <= 2 * log.blocks.len() + 1024 + 5);
    }

    #[test]
    fn extreme_cells_have_blocks() {
        let mut log = ChangeLog::default();
        log.begin();
        log.mark(Cell::new(i32::MIN, i32::MAX));
        let r = log.changed_since(0);
        assert_eq!(r.len(), 1);
        assert!(r[0].contains(Cell::new(i32::MIN, i32::MAX)));
    }
}
