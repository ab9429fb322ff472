//! The classified cells ordered by class budget, so that an update finds the cells whose budget
//! the prototypes' drift used up without reading every cell.
//!
//! Cells sit in buckets of nearby budgets (the top bits of an order-preserving key of the
//! `f32` budget, about 128 buckets per doubling). The drift only grows between full
//! classifications, so an update empties the buckets wholly below it and checks the entries of
//! the one it falls in. A binary heap over millions of cells did the same at one cache miss per
//! level of every pop, and that grew to a third of the learning update on `campus`.

use crate::morphology::TerrainCell;

/// Key bits dropped to make a bucket: 2¹⁶ buckets over the `f32` order, 7 bits of mantissa.
const SHIFT: u32 = 16;

/// The classified cells by budget. Entries are storage indices; an entry is stale when its cell
/// has been classified again since (its current budget has its own entry), and is dropped when
/// its bucket is read.
#[derive(Debug, Default)]
pub(super) struct BudgetQueue {
    /// Per bucket, the cells whose budget fell in it when they were classified. Empty until
    /// the first entry.
    buckets: Vec<Vec<u32>>,
    /// No bucket below this one holds an entry.
    lowest: usize,
    /// Entries held, stale ones included.
    len: usize,
}

impl BudgetQueue {
    /// Removes every entry (and frees the buckets' memory).
    pub(super) fn clear(&mut self) {
        for b in &mut self.buckets {
            *b = Vec::new();
        }
        self.lowest = self.buckets.len();
        self.len = 0;
    }

    /// Entries held, stale ones included.
    pub(super) fn len(&self) -> usize {
        self.len
    }

    /// Entries the buckets have room for.
    #[cfg(test)]
    fn capacity(&self) -> usize {
        self.buckets.iter().map(Vec::capacity).sum()
    }

    /// Adds cell `k` with budget `budget`.
    pub(super) fn push(&mut self, budget: f32, k: u32) {
        if self.buckets.is_empty() {
            self.buckets.resize_with(1 << (32 - SHIFT), Vec::new);
            self.lowest = self.buckets.len();
        }
        let b = bucket_of(budget);
        self.buckets[b].push(k);
        self.lowest = self.lowest.min(b);
        self.len += 1;
    }

    /// Takes off the classified cells whose budget `drift` reached (`drift ≥ budget[k]`), in no
    /// particular order and possibly repeated; drops the stale entries read on the way. `raw`
    /// and `budget` are the cells' current classes and budgets.
    pub(super) fn take_used_up(
        &mut self,
        drift: f64,
        raw: &[TerrainCell],
        budget: &[f32],
    ) -> Vec<usize> {
        let mut used_up = Vec::new();
        let mut b = self.lowest;
        while b < self.buckets.len() && f64::from(lowest_budget(b)) <= drift {
            let mut entries = std::mem::take(&mut self.buckets[b]);
            self.len -= entries.len();
            entries.retain(|&k| {
                let k = k as usize;
                if !matches!(raw[k], TerrainCell::Class(_)) {
                    return false;
                }
                if drift >= f64::from(budget[k]) {
                    used_up.push(k);
                    return false;
                }
                // Kept only as the cell's current entry.
                bucket_of(budget[k]) == b
            });
            self.len += entries.len();
            // The drift passes each bucket once between full classifications: a bucket it
            // emptied keeps no memory, or over a long mission every bucket the drift swept
            // would hold on to the most entries it ever had.
            if entries.is_empty() {
                entries = Vec::new();
            } else if entries.capacity() > 2 * entries.len() + 16 {
                entries.shrink_to_fit();
            }
            self.buckets[b] = entries;
            b += 1;
        }
        // Every bucket wholly below the drift is empty now.
        while self.lowest < b && self.buckets[self.lowest].is_empty() {
            self.lowest += 1;
        }
        used_up
    }
}

/// The bucket of a budget.
fn bucket_of(budget: f32) -> usize {
    (order_key(budget) >> SHIFT) as usize
}

/// The lowest budget bucket `b` can hold.
fn lowest_budget(b: usize) -> f32 {
    from_order_key((b as u32) << SHIFT)
}

/// A key of `v` whose unsigned order is the order of the floats (−∞ lowest, NaN above +∞).
fn order_key(v: f32) -> u32 {
    let b = v.to_bits();
    if b & 0x8000_0000 != 0 {
        !b
    } else {
        b | 0x8000_0000
    }
}

/// The float of an [`order_key`].
fn from_order_key(key: u32) -> f32 {
    if key & 0x8000_0000 != 0 {
        f32::from_bits(key & 0x7fff_ffff)
    } else {
        f32::from_bits(!key)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::igng::ClassId;
    use proptest::prelude::*;

    proptest! {
        /// The order keys sort as the floats do (−0 below +0), and give the floats back.
        #[test]
        fn order_keys_sort_as_the_floats(a in proptest::num::f32::ANY, b in proptest::num::f32::ANY) {
            prop_assert_eq!(from_order_key(order_key(a)).to_bits(), a.to_bits());
            if let Some(o) = a.partial_cmp(&b).filter(|_| a != 0.0 || b != 0.0) {
                prop_assert_eq!(order_key(a).cmp(&order_key(b)), o);
            }
        }

        /// Against the definition: after any pushes, reclassifications and growing drifts, the
        /// cells taken are exactly the classified cells whose current budget the drift reached.
        #[test]
        fn the_cells_taken_are_those_whose_budget_is_used_up(
            budgets in proptest::collection::vec(-4.0f32..40.0, 1..60),
            steps in proptest::collection::vec(
                (0.0f64..3.0, proptest::collection::vec((0usize..60, -4.0f32..40.0, any::<bool>()), 0..8)),
                1..12,
            ),
        ) {
            let n = budgets.len();
            let mut budget = budgets.clone();
            let mut raw: Vec<TerrainCell> = (0..n).map(|k| TerrainCell::Class(ClassId(k as u32 % 3))).collect();
            let mut q = BudgetQueue::default();
            for (k, &b) in budget.iter().enumerate() {
                q.push(b, k as u32);
            }
            let mut drift = -5.0;
            for (step, changes) in steps {
                drift += step;
                let mut taken = q.take_used_up(drift, &raw, &budget);
                taken.sort_unstable();
                taken.dedup();
                let expected: Vec<usize> = (0..n)
                    .filter(|&k| matches!(raw[k], TerrainCell::Class(_)) && drift >= f64::from(budget[k]))
                    .collect();
                prop_assert_eq!(&taken, &expected);
                // The taken cells are classified again, as are a few others.
                for &k in &taken {
                    budget[k] = (drift as f32 + 1.0).max(budget[k]);
                    q.push(budget[k], k as u32);
                }
                for (k, b, classified) in changes {
                    let k = k % n;
                    budget[k] = b.max(drift as f32);
                    raw[k] = if classified { TerrainCell::Class(ClassId(1)) } else { TerrainCell::Eroded };
                    if classified {
                        q.push(budget[k], k as u32);
                    }
                }
            }
        }
    }

    /// A drift sweeping through many buckets leaves none holding memory behind it.
    #[test]
    fn swept_buckets_free_their_memory() {
        let n = 4096;
        let raw = vec![TerrainCell::Class(ClassId(0)); n];
        let mut budget = vec![0.0f32; n];
        let mut q = BudgetQueue::default();
        let mut drift = 0.0f64;
        for _ in 0..200 {
            // Every cell used up and classified again just above the drift.
            for (k, b) in budget.iter_mut().enumerate() {
                *b = (drift + 0.01 + k as f64 * 1e-6) as f32;
                q.push(*b, k as u32);
            }
            drift += 0.05;
            let taken = q.take_used_up(drift, &raw, &budget);
            assert_eq!(taken.len(), n);
        }
        assert_eq!(q.len(), 0);
        assert!(
            q.capacity() <= 4 * n,
            "{} entries of room for none",
            q.capacity()
        );
        q.push(1e9, 0);
        q.clear();
        assert_eq!(q.capacity(), 0);
    }

    #[test]
    fn stale_entries_are_dropped_and_counted_out() {
        let raw = vec![TerrainCell::Class(ClassId(0)); 2];
        let mut budget = vec![1.0f32, 2.0];
        let mut q = BudgetQueue::default();
        q.push(1.0, 0);
        q.push(2.0, 1);
        // Cell 0 classified again with a larger budget: its first entry is stale.
        budget[0] = 5.0;
        q.push(5.0, 0);
        assert_eq!(q.len(), 3);
        assert_eq!(q.take_used_up(1.5, &raw, &budget), Vec::<usize>::new());
        assert_eq!(q.len(), 2);
        assert_eq!(q.take_used_up(2.0, &raw, &budget), vec![1]);
        assert_eq!(q.take_used_up(5.0, &raw, &budget), vec![0]);
        assert_eq!(q.len(), 0);
        q.clear();
        assert_eq!(q.take_used_up(100.0, &raw, &budget), Vec::<usize>::new());
    }
}
