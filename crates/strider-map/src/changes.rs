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
    blocks: HashMap<TileKey, u64, BuildHasherDefault<TileHasher>>,
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
    }

    /// Marks cell `c` changed in the current revision.
    #[inline]
    pub(crate) fn mark(&mut self, c: Cell) {
        let key = block_of(c);
        if self.last != Some(key) {
            self.blocks.insert(key, self.revision);
            self.last = Some(key);
        }
    }

    /// The current revision: a consumer that has caught up with the map remembers it.
    pub fn revision(&self) -> u64 {
        self.revision
    }

    /// The blocks changed after revision `seen`, as rectangles in row-major block order, runs
    /// of neighbouring changed blocks in a row merged into one rectangle.
    pub fn changed_since(&self, seen: u64) -> Vec<CellRect> {
        let mut keys: Vec<TileKey> = self
            .blocks
            .iter()
            .filter(|&(_, &rev)| rev > seen)
            .map(|(&k, _)| k)
            .collect();
        keys.sort_unstable();
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
    fn extreme_cells_have_blocks() {
        let mut log = ChangeLog::default();
        log.begin();
        log.mark(Cell::new(i32::MIN, i32::MAX));
        let r = log.changed_since(0);
        assert_eq!(r.len(), 1);
        assert!(r[0].contains(Cell::new(i32::MIN, i32::MAX)));
    }
}
