//! Per-class cell counts and component-wise medians of the descriptors on the eroded class map
//! (the class table of Alg. 8), kept in step with the class map and the descriptor field: an
//! update pays for the cells whose class or descriptor changed, not for every cell of the map.
//!
//! Each class keeps, per descriptor component, the multiset of its cells' values in an ordered
//! map (value → count). The median is read by walking it, which costs the number of distinct
//! values below the median, not the number of cells. The field's change log
//! ([`DescriptorField::changes_since`]) supplies the descriptors a change replaced, so that a
//! cell's old values can be taken out. When the field is another one, its log no longer
//! reaches back to the last update, or it moved its storage rectangle, everything is counted
//! again.

use std::collections::BTreeMap;

use strider_core::CellRect;

use crate::descriptor_field::{DescriptorField, FieldVersion};
use crate::igng::ClassId;
use crate::morphology::TerrainCell;

/// No class: the cell is not counted.
const NONE: u32 = u32::MAX;

/// The class table's per-class statistics, in step with one class map.
#[derive(Debug)]
pub(super) struct ClassStats {
    store: CellRect,
    dim: usize,
    /// Per storage cell: the class it is counted in, or [`NONE`].
    member: Vec<u32>,
    classes: BTreeMap<ClassId, Columns>,
    /// The field's version at the last [`sync`](Self::sync).
    seen: Option<FieldVersion>,
}

impl Default for ClassStats {
    fn default() -> Self {
        Self {
            store: CellRect::new(strider_core::Cell::new(0, 0), 0, 0),
            dim: 0,
            member: Vec::new(),
            classes: BTreeMap::new(),
            seen: None,
        }
    }
}

/// One class: its cell count and, per component, value → count.
#[derive(Debug, Default)]
struct Columns {
    count: usize,
    values: Vec<BTreeMap<u64, u32>>,
}

/// A count and the component-wise median of one class.
#[derive(Clone, Debug, PartialEq)]
pub(super) struct ClassSummary {
    pub id: ClassId,
    pub cells: usize,
    pub median: Vec<f64>,
}

impl ClassStats {
    /// Brings the statistics to the class map `classes` (eroded, laid out on the field's
    /// storage rectangle) and the descriptors of `desc`. `touched`: the storage cells whose
    /// class may have changed since the last sync (`None`: any cell), so that only those, the
    /// cells whose descriptor changed and the newly described ones are read.
    pub(super) fn sync(
        &mut self,
        desc: &DescriptorField,
        classes: &[TerrainCell],
        touched: Option<&[u32]>,
    ) {
        let store = desc.storage();
        let shaped = self.store == store
            && self.dim == desc.dim()
            && self.member.len() == store.len()
            && classes.len() == store.len();
        let Some((changes, added)) = self
            .seen
            .filter(|_| shaped)
            .and_then(|s| Some((desc.changes_since(s)?, desc.added_since(s)?)))
        else {
            self.recount(desc, classes);
            return;
        };
        // The log holds the descriptors these cells had at the last sync.
        let mut redo: Vec<u32> = Vec::new();
        for (n, old) in changes {
            if let Some(t) = self.member.get(n).copied().filter(|&t| t != NONE) {
                self.remove(t, old);
                self.member[n] = NONE;
            }
            redo.push(n as u32);
        }
        match touched {
            Some(touched) => {
                redo.extend_from_slice(added);
                redo.extend_from_slice(touched);
                for k in redo {
                    self.follow_class(desc, classes, k as usize);
                }
            }
            None => {
                for &k in desc.described_indices() {
                    self.follow_class(desc, classes, k as usize);
                }
            }
        }
        self.seen = Some(desc.version());
    }

    /// Counts storage cell `k` in its class of `classes` if it is described (and in none
    /// otherwise).
    fn follow_class(&mut self, desc: &DescriptorField, classes: &[TerrainCell], k: usize) {
        let Some(x) = desc.get_stored(k) else {
            return;
        };
        let (Some(&have), Some(&c)) = (self.member.get(k), classes.get(k)) else {
            return;
        };
        let want = class_of(c);
        if have == want {
            return;
        }
        if have != NONE {
            self.remove(have, x);
        }
        if want != NONE {
            self.add(want, x);
        }
        self.member[k] = want;
    }

    /// Counts every described cell again.
    fn recount(&mut self, desc: &DescriptorField, classes: &[TerrainCell]) {
        self.store = desc.storage();
        self.dim = desc.dim();
        self.classes.clear();
        self.member.clear();
        self.member.resize(self.store.len(), NONE);
        for (k, x) in desc.described() {
            let t = classes.get(k).map_or(NONE, |&c| class_of(c));
            if t != NONE {
                self.add(t, x);
                self.member[k] = t;
            }
        }
        self.seen = Some(desc.version());
    }

    fn add(&mut self, t: u32, x: &[f64]) {
        let dim = self.dim;
        let c = self.classes.entry(ClassId(t)).or_default();
        c.values.resize_with(dim, BTreeMap::new);
        c.count += 1;
        for (column, &v) in c.values.iter_mut().zip(x) {
            *column.entry(order_key(v)).or_insert(0) += 1;
        }
    }

    fn remove(&mut self, t: u32, x: &[f64]) {
        let Some(c) = self.classes.get_mut(&ClassId(t)) else {
            return;
        };
        c.count = c.count.saturating_sub(1);
        for (column, &v) in c.values.iter_mut().zip(x) {
            let key = order_key(v);
            if let Some(n) = column.get_mut(&key) {
                *n -= 1;
                if *n == 0 {
                    column.remove(&key);
                }
            }
        }
        if c.count == 0 {
            self.classes.remove(&ClassId(t));
        }
    }

    /// The classes with at least one cell, by ascending id, with their lower medians.
    pub(super) fn summaries(&self) -> Vec<ClassSummary> {
        self.classes
            .iter()
            .filter(|(_, c)| c.count > 0)
            .map(|(&id, c)| ClassSummary {
                id,
                cells: c.count,
                median: c
                    .values
                    .iter()
                    .map(|column| lower_median(column, c.count))
                    .collect(),
            })
            .collect()
    }
}

/// The class id a class-map cell is counted in, or [`NONE`].
fn class_of(c: TerrainCell) -> u32 {
    match c {
        TerrainCell::Class(t) if t.0 != NONE => t.0,
        _ => NONE,
    }
}

/// The element of rank (count − 1) / 2 of a multiset of `count` values.
fn lower_median(column: &BTreeMap<u64, u32>, count: usize) -> f64 {
    let rank = (count.saturating_sub(1) / 2) as u64;
    let mut below = 0u64;
    for (&key, &n) in column {
        below += u64::from(n);
        if below > rank {
            return from_key(key);
        }
    }
    f64::NAN
}

/// A key whose unsigned order is [`f64::total_cmp`]'s order of the values.
fn order_key(v: f64) -> u64 {
    let b = v.to_bits();
    if b >> 63 == 1 { !b } else { b | 1 << 63 }
}

/// The value of an [`order_key`].
fn from_key(k: u64) -> f64 {
    f64::from_bits(if k >> 63 == 1 { k & !(1 << 63) } else { !k })
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;
    use strider_core::Cell;

    /// The table computed from scratch: per class, its count and component-wise lower median.
    fn fresh(desc: &DescriptorField, classes: &[TerrainCell]) -> Vec<ClassSummary> {
        let mut members: BTreeMap<ClassId, Vec<&[f64]>> = BTreeMap::new();
        for (k, x) in desc.described() {
            if let TerrainCell::Class(t) = classes[k] {
                members.entry(t).or_default().push(x);
            }
        }
        members
            .into_iter()
            .map(|(id, rows)| ClassSummary {
                id,
                cells: rows.len(),
                median: (0..desc.dim())
                    .map(|k| {
                        let mut col: Vec<f64> = rows.iter().map(|r| r[k]).collect();
                        let n = col.len();
                        *col.select_nth_unstable_by((n - 1) / 2, f64::total_cmp).1
                    })
                    .collect(),
            })
            .collect()
    }

    #[test]
    fn keys_order_as_total_cmp() {
        let vs = [
            -1.5,
            -0.0,
            0.0,
            1e-300,
            0.25,
            7.0,
            f64::INFINITY,
            -f64::INFINITY,
        ];
        for &a in &vs {
            assert_eq!(from_key(order_key(a)).to_bits(), a.to_bits());
            for &b in &vs {
                assert_eq!(order_key(a).cmp(&order_key(b)), a.total_cmp(&b));
            }
        }
    }

    /// One step of a random history: set a cell's descriptor, or give it a class.
    #[derive(Clone, Debug)]
    enum Step {
        Describe(usize, [i8; 2]),
        Classify(usize, u8),
    }

    fn step() -> impl Strategy<Value = Step> {
        prop_oneof![
            (0usize..48, [-3i8..3, -3i8..3]).prop_map(|(k, v)| Step::Describe(k, v)),
            (0usize..48, 0u8..4).prop_map(|(k, c)| Step::Classify(k, c)),
        ]
    }

    proptest! {
        /// Kept in step over a history of descriptor and class changes, synced after each
        /// batch, the statistics equal the table computed from scratch.
        #[test]
        fn kept_in_step_equals_fresh(
            batches in proptest::collection::vec(proptest::collection::vec(step(), 0..12), 1..8),
        ) {
            let rect = CellRect::new(Cell::new(0, 0), 8, 6);
            let mut desc = DescriptorField::empty(rect, 2);
            let store = desc.storage();
            let mut classes = vec![TerrainCell::Unknown; store.len()];
            let mut stats = ClassStats::default();
            for (b, batch) in batches.into_iter().enumerate() {
                let mut touched = Vec::new();
                for s in batch {
                    match s {
                        Step::Describe(k, v) => {
                            let c = rect.cell(k);
                            desc.set(c, &[f64::from(v[0]) * 0.5, f64::from(v[1])]);
                        }
                        Step::Classify(k, t) => {
                            let k = store.index(rect.cell(k)).unwrap();
                            touched.push(k as u32);
                            classes[k] = if t == 0 {
                                TerrainCell::Eroded
                            } else {
                                TerrainCell::Class(ClassId(u32::from(t)))
                            };
                        }
                    }
                }
                // Every other sync is told which cells changed class.
                stats.sync(&desc, &classes, (b % 2 == 0).then_some(&touched[..]));
                prop_assert_eq!(stats.summaries(), fresh(&desc, &classes));
            }
        }

        /// With one field change between syncs (the learning update's rhythm).
        #[test]
        fn one_change_per_sync_equals_fresh(
            changes in proptest::collection::vec((0usize..48, -3i8..3, 0u8..4), 1..40),
        ) {
            let rect = CellRect::new(Cell::new(0, 0), 8, 6);
            let mut desc = DescriptorField::empty(rect, 2);
            let store = desc.storage();
            let mut classes = vec![TerrainCell::Unknown; store.len()];
            let mut stats = ClassStats::default();
            for (k, v, t) in changes {
                let c = rect.cell(k);
                // -3 clears the cell (a non-finite descriptor is refused and removes it).
                let x = if v == -3 { f64::NAN } else { f64::from(v) };
                desc.set(c, &[x, -f64::from(v) * 0.25]);
                let k = store.index(c).unwrap();
                classes[k] = TerrainCell::Class(ClassId(u32::from(t)));
                stats.sync(&desc, &classes, Some(&[k as u32]));
                prop_assert_eq!(stats.summaries(), fresh(&desc, &classes));
            }
        }
    }
}
