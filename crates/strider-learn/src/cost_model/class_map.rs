//! The nearest-prototype classes T* (Alg. 7 line 8) kept from one learning update to the next,
//! and the erosion and dilation redone only near the cells whose class changed.
//!
//! **Which cells can change class.** A cell's class is the nearest prototype. If a prototype
//! moves by δ, every distance to it changes by at most δ (triangle inequality). So a cell at
//! distance d₁ from its prototype and d₂ from the next nearest keeps its class while the sum
//! of the largest prototype moves since it was classified stays below (d₂ − d₁) / 2. Each
//! cell keeps that budget; an update reclassifies the cells whose budget the moves used up,
//! the cells whose descriptor changed or that are new, and the cells of classes that are gone.
//! A new prototype could be nearer than any budget says, so a new class (rare once the terrain
//! families have been seen) reclassifies every cell.
//!
//! **Where erosion and dilation can change.** Both are local: after s steps a cell depends on
//! the cells within s (erosion) or s·n_size (dilation) of it. So the maps are recomputed in
//! blocks around the changed cells, each block on a window grown by that reach, where the
//! window's own edge can only disturb the margin that is not copied back. The results are the
//! whole-map operations' (a property test compares them).

use strider_core::CellRect;

use super::budget_queue::BudgetQueue;

use crate::descriptor_field::{DescriptorField, FieldVersion};
use crate::igng::{ClassId, Igng};
use crate::morphology::TerrainCell;

/// Side of the blocks the maps are recomputed in, cells.
const BLOCK: usize = 32;

/// T* over the storage rectangle with each cell's budget, and what they were computed with.
#[derive(Debug, Default)]
pub(super) struct RawClasses {
    /// Per storage cell: T*, `Unknown` where not described.
    pub(super) raw: Vec<TerrainCell>,
    /// Per storage cell: the value of `drift` at which the class may change (rounded down).
    budget: Vec<f32>,
    /// Sum over updates of the largest prototype move, since the last full classification.
    drift: f64,
    /// The prototypes the cells were last classified against.
    prototypes: Vec<(ClassId, Vec<f64>)>,
    /// The descriptor field's version at the last classification; `None`: classify all.
    seen: Option<FieldVersion>,
    /// The classified cells by budget, so that an update finds the cells whose budget the
    /// drift used up without reading every cell.
    by_budget: BudgetQueue,
    /// What the classifications so far did.
    pub(super) counts: ClassificationCounts,
}

/// How the class maps were brought up to date, over the model's life.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct ClassificationCounts {
    /// Updates that classified every described cell.
    pub full: u64,
    /// Updates that classified only the cells that may have changed class.
    pub partial: u64,
    /// Cells classified, over all updates.
    pub cells: u64,
}

/// What one classification did.
#[derive(Debug, Default)]
pub(super) struct Reclassified {
    /// Every cell was classified (the maps must be recomputed everywhere).
    pub(super) full: bool,
    /// Storage cells whose T* changed (with `full`: empty).
    pub(super) changed: Vec<u32>,
    /// Cells classified.
    pub(super) classified: usize,
}

impl RawClasses {
    /// Forgets everything: the next classification is a full one over `cells` storage cells.
    pub(super) fn reset(&mut self, cells: usize) {
        self.raw.clear();
        self.raw.resize(cells, TerrainCell::Unknown);
        self.budget.clear();
        self.budget.resize(cells, f32::NEG_INFINITY);
        self.by_budget.clear();
        self.seen = None;
    }

    /// Marks the classes stale without touching the rasters (the next classification is full).
    pub(super) fn invalidate(&mut self) {
        self.seen = None;
    }

    /// Brings T* to the described cells of `desc` and the prototypes of `igng`. `support` are
    /// the described cells' storage indices.
    pub(super) fn classify(
        &mut self,
        desc: &DescriptorField,
        igng: &Igng,
        support: &[u32],
    ) -> Reclassified {
        let logs = self
            .seen
            .filter(|_| self.raw.len() == desc.storage().len())
            .and_then(|s| {
                let changed: Vec<usize> = desc.changes_since(s)?.map(|(n, _)| n).collect();
                Some((changed, desc.added_since(s)?))
            });
        let moved = logs.and_then(|l| Some((l, self.largest_move(igng)?)));
        let out = match moved {
            Some(((changed, added), (step, gone))) => {
                self.drift += step;
                let logs = Logs {
                    changed: &changed,
                    added,
                    gone: &gone,
                };
                self.reclassify_stale(desc, igng, support, logs)
            }
            None => self.classify_all(desc, igng, support),
        };
        self.prototypes = igng.prototypes().map(|(c, w)| (c, w.to_vec())).collect();
        self.seen = Some(desc.version());
        if out.full {
            self.counts.full += 1;
        } else {
            self.counts.partial += 1;
        }
        self.counts.cells += out.classified as u64;
        out
    }

    /// The largest move of a prototype since the last classification and the classes gone
    /// since; `None` when a class is new.
    fn largest_move(&self, igng: &Igng) -> Option<(f64, Vec<ClassId>)> {
        let mut step = 0.0f64;
        let mut kept = 0;
        for (c, w) in igng.prototypes() {
            let (_, old) = self.prototypes.iter().find(|(o, _)| *o == c)?;
            let d2: f64 = w.iter().zip(old).map(|(a, b)| (a - b) * (a - b)).sum();
            step = step.max(d2.sqrt());
            kept += 1;
        }
        let gone = if kept == self.prototypes.len() {
            Vec::new()
        } else {
            self.prototypes
                .iter()
                .map(|(c, _)| *c)
                .filter(|c| igng.prototype(*c).is_none())
                .collect()
        };
        Some((step, gone))
    }

    fn classify_all(
        &mut self,
        desc: &DescriptorField,
        igng: &Igng,
        support: &[u32],
    ) -> Reclassified {
        let cells = desc.storage().len();
        if self.raw.len() != cells {
            self.reset(cells);
        } else {
            // Cells described at the last classification may not be now.
            self.raw.fill(TerrainCell::Unknown);
        }
        self.drift = 0.0;
        for &k in support {
            self.classify_cell(desc, igng, k as usize);
        }
        self.rebuild_budget_queue(support);
        Reclassified {
            full: true,
            changed: Vec::new(),
            classified: support.len(),
        }
    }

    /// Reclassifies the cells whose descriptor changed (storage indices from the field's log),
    /// that are new, whose budget is used up or whose class is gone.
    fn reclassify_stale(
        &mut self,
        desc: &DescriptorField,
        igng: &Igng,
        support: &[u32],
        logs: Logs,
    ) -> Reclassified {
        let mut out = Reclassified::default();
        if !logs.gone.is_empty() {
            // A class was pruned (rare): its cells are found by reading every cell.
            self.reclassify_every_stale(desc, igng, support, logs.gone, &mut out);
        } else {
            let mut stale = self.used_up_budgets();
            // As over the described cells only: the undescribed ones come with `changed`.
            stale.retain(|&k| desc.get_stored(k).is_some());
            // New cells: described now and not classified since they were described.
            stale.extend(logs.added.iter().map(|&k| k as usize).filter(|&k| {
                k < self.raw.len()
                    && self.raw[k] == TerrainCell::Unknown
                    && desc.get_stored(k).is_some()
            }));
            stale.sort_unstable();
            stale.dedup();
            for k in stale {
                self.reclassify(desc, igng, k, &mut out);
            }
        }
        for &n in logs.changed {
            if n < self.raw.len() {
                self.reclassify(desc, igng, n, &mut out);
            }
        }
        if self.by_budget.len() > 2 * support.len() + 4096 {
            self.rebuild_budget_queue(support);
        }
        out
    }

    /// The cells (described or not) whose budget the drift used up, taken off the queue
    /// (possibly repeated).
    fn used_up_budgets(&mut self) -> Vec<usize> {
        self.by_budget
            .take_used_up(self.drift, &self.raw, &self.budget)
    }

    /// The reclassification by reading every described cell: the unknown ones, those of a
    /// class in `gone` and those whose budget is used up.
    fn reclassify_every_stale(
        &mut self,
        desc: &DescriptorField,
        igng: &Igng,
        support: &[u32],
        gone: &[ClassId],
        out: &mut Reclassified,
    ) {
        let drift = self.drift;
        for &k in support {
            let k = k as usize;
            let stale = match self.raw[k] {
                TerrainCell::Unknown => true,
                TerrainCell::Class(t) => gone.contains(&t),
                TerrainCell::Eroded => false,
            } || drift >= f64::from(self.budget[k]);
            if stale {
                self.reclassify(desc, igng, k, out);
            }
        }
    }

    /// The queue of budgets from scratch: one entry per classified described cell.
    fn rebuild_budget_queue(&mut self, support: &[u32]) {
        self.by_budget.clear();
        for &k in support {
            if matches!(self.raw[k as usize], TerrainCell::Class(_)) {
                self.by_budget.push(self.budget[k as usize], k);
            }
        }
    }

    /// Classifies storage cell `k` again (unknown when not described), recording a change.
    fn reclassify(
        &mut self,
        desc: &DescriptorField,
        igng: &Igng,
        k: usize,
        out: &mut Reclassified,
    ) {
        let before = self.raw[k];
        self.classify_cell(desc, igng, k);
        if matches!(self.raw[k], TerrainCell::Class(_)) {
            self.by_budget.push(self.budget[k], k as u32);
        }
        out.classified += 1;
        if self.raw[k] != before {
            out.changed.push(k as u32);
        }
    }

    fn classify_cell(&mut self, desc: &DescriptorField, igng: &Igng, k: usize) {
        let Some(x) = desc.get_stored(k) else {
            self.raw[k] = TerrainCell::Unknown;
            self.budget[k] = f32::NEG_INFINITY;
            return;
        };
        let (class, budget) = match igng.nearest_two(x) {
            Some((c, d1, d2)) => (TerrainCell::Class(c), self.drift + margin(d1, d2)),
            // No class yet: a new one triggers a full classification anyway.
            None => (TerrainCell::Eroded, f64::INFINITY),
        };
        self.raw[k] = class;
        self.budget[k] = round_down(budget);
    }
}

/// What changed in the descriptor field and the classes since the last classification.
struct Logs<'a> {
    /// Storage cells whose descriptor was replaced or removed.
    changed: &'a [usize],
    /// Storage cells newly described.
    added: &'a [u32],
    /// Classes gone.
    gone: &'a [ClassId],
}

/// Half the gap between the two nearest distances, less a margin for the rounding of the
/// distances themselves; negative on a tie.
fn margin(d1: f64, d2: f64) -> f64 {
    0.5 * (d2 - d1) - 1e-9 * (1.0 + d1 + d2.min(1e9))
}

/// The largest `f32` not above `v`.
fn round_down(v: f64) -> f32 {
    let f = v as f32;
    if f64::from(f) > v { f.next_down() } else { f }
}

/// Recomputes `dst` = `op(src)` near the storage cells `changed` of a `w`-wide map, for an
/// operation that reads no farther than `reach` cells: in blocks of [`BLOCK`] cells within
/// `reach` of a change, each computed on its window grown by `reach` (in `scratch`). `op`
/// gets the window, its width and its cells that are not unknown. Returns the cells of `dst`
/// that changed, ascending.
pub(super) fn recompute_near(
    src: &[TerrainCell],
    dst: &mut [TerrainCell],
    w: usize,
    changed: &[u32],
    reach: usize,
    scratch: &mut Vec<TerrainCell>,
    mut op: impl FnMut(&mut [TerrainCell], usize, &[u32]),
) -> Vec<u32> {
    let mut out = Vec::new();
    if w == 0 || src.len() != dst.len() {
        return out;
    }
    let h = src.len() / w;
    let mut support = Vec::new();
    for (bx, by) in touched_blocks(changed, w, h, reach) {
        let block = CellRect::new(
            strider_core::Cell::new((bx * BLOCK) as i32, (by * BLOCK) as i32),
            BLOCK.min(w - bx * BLOCK) as u32,
            BLOCK.min(h - by * BLOCK) as u32,
        );
        let (x0, y0) = (block.min.i as usize, block.min.j as usize);
        let (x1, y1) = (x0 + block.width as usize, y0 + block.height as usize);
        let (wx0, wy0) = (x0.saturating_sub(reach), y0.saturating_sub(reach));
        let (wx1, wy1) = ((x1 + reach).min(w), (y1 + reach).min(h));
        let ww = wx1 - wx0;
        scratch.clear();
        for y in wy0..wy1 {
            scratch.extend_from_slice(&src[y * w + wx0..y * w + wx1]);
        }
        support.clear();
        support.extend(
            (0..scratch.len() as u32).filter(|&k| scratch[k as usize] != TerrainCell::Unknown),
        );
        op(scratch, ww, &support);
        for y in y0..y1 {
            for x in x0..x1 {
                let v = scratch[(y - wy0) * ww + (x - wx0)];
                let k = y * w + x;
                if dst[k] != v {
                    dst[k] = v;
                    out.push(k as u32);
                }
            }
        }
    }
    out.sort_unstable();
    out
}

/// The blocks (column, row) within `reach` of the cells `changed`, each once, in order.
fn touched_blocks(changed: &[u32], w: usize, h: usize, reach: usize) -> Vec<(usize, usize)> {
    let bw = w.div_ceil(BLOCK);
    let mut blocks: Vec<usize> = Vec::new();
    for &k in changed {
        let (x, y) = (k as usize % w, k as usize / w);
        if y >= h {
            continue;
        }
        let (bx0, bx1) = (
            x.saturating_sub(reach) / BLOCK,
            (x + reach).min(w - 1) / BLOCK,
        );
        let (by0, by1) = (
            y.saturating_sub(reach) / BLOCK,
            (y + reach).min(h - 1) / BLOCK,
        );
        for by in by0..=by1 {
            blocks.extend((bx0..=bx1).map(|bx| by * bw + bx));
        }
    }
    blocks.sort_unstable();
    blocks.dedup();
    blocks.into_iter().map(|b| (b % bw, b / bw)).collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::morphology::{dilate_in_place, erode_in_place};
    use proptest::prelude::*;

    fn cell_of(code: u8) -> TerrainCell {
        match code {
            0 => TerrainCell::Unknown,
            1 => TerrainCell::Eroded,
            c => TerrainCell::Class(ClassId(u32::from(c - 2))),
        }
    }

    fn known(values: &[TerrainCell]) -> Vec<u32> {
        (0..values.len() as u32)
            .filter(|&k| values[k as usize] != TerrainCell::Unknown)
            .collect()
    }

    proptest! {
        /// After changes to the source, erosion and dilation redone near them equal the
        /// whole-map operations.
        #[test]
        fn recomputed_near_changes_equals_whole_map(
            w in 1usize..80,
            h in 1usize..80,
            seed_codes in proptest::collection::vec(2u8..5, 1..64),
            edits in proptest::collection::vec((0usize..6400, 0u8..5), 0..30),
            steps in 1usize..4,
            size in 1usize..3,
        ) {
            // Patches of classes (so that erosion keeps some), some unknown and eroded.
            let before: Vec<TerrainCell> = (0..w * h)
                .map(|k| {
                    let (x, y) = (k % w, k / w);
                    cell_of(seed_codes[(x / 7 + 3 * (y / 5)) % seed_codes.len()])
                })
                .collect();
            let erode_all = |v: &[TerrainCell]| {
                let mut v = v.to_vec();
                let s = known(&v);
                erode_in_place(&mut v, w, &s, steps);
                v
            };
            let dilate_all = |v: &[TerrainCell]| {
                let mut v = v.to_vec();
                let s = known(&v);
                dilate_in_place(&mut v, w, &s, size, steps);
                v
            };
            let mut eroded = erode_all(&before);
            let mut dilated = dilate_all(&eroded);
            let mut after = before.clone();
            let mut changed = Vec::new();
            for (k, c) in edits {
                let k = k % (w * h);
                if after[k] != cell_of(c) {
                    after[k] = cell_of(c);
                    changed.push(k as u32);
                }
            }
            changed.sort_unstable();
            changed.dedup();
            let mut scratch = Vec::new();
            let t_changed = recompute_near(&after, &mut eroded, w, &changed, steps, &mut scratch,
                |v, ww, s| erode_in_place(v, ww, s, steps));
            prop_assert_eq!(&eroded, &erode_all(&after));
            let src = eroded.clone();
            recompute_near(&src, &mut dilated, w, &t_changed, steps * size, &mut scratch,
                |v, ww, s| dilate_in_place(v, ww, s, size, steps));
            prop_assert_eq!(dilated, dilate_all(&eroded));
        }
    }

    proptest! {
        /// Classes kept between classifications, while the prototypes move (so that budgets
        /// run out), descriptors change, cells lose their descriptor and new cells are
        /// described, are the nearest prototype of every described cell.
        #[test]
        fn kept_classes_are_the_nearest_prototypes(
            seed in 0u64..1000,
            steps in proptest::collection::vec(
                (proptest::collection::vec((0usize..40, 0.0f64..1.0, 0.0f64..1.0), 0..6),
                 proptest::collection::vec((0.0f64..1.0, 0.0f64..1.0), 1..30)),
                1..10,
            ),
        ) {
            use crate::igng::IgngParams;
            use strider_core::Cell;
            let rect = CellRect::new(Cell::new(0, 0), 8, 5);
            let mut desc = DescriptorField::empty(rect, 2);
            let mut state = seed;
            let mut next = || {
                state = state.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
                (state >> 11) as f64 / (1u64 << 53) as f64
            };
            // The first half described now, the rest as the steps go.
            for k in 0..20 {
                desc.set(rect.cell(k), &[next(), next()]);
            }
            let mut params = IgngParams::with_sigma(0.25);
            params.eps_winner = 0.3;
            params.eps_neighbour = 0.05;
            let mut igng = Igng::new(2, params, seed).unwrap();
            let corners = [0.1, 0.1, 0.9, 0.1, 0.1, 0.9, 0.9, 0.9, 0.5, 0.5];
            igng.train(&corners[..], 1).unwrap();
            let mut raw = RawClasses::default();
            raw.reset(desc.storage().len());
            for (n, (edits, samples)) in steps.into_iter().enumerate() {
                for (k, x, y) in edits {
                    let v = if x < 0.1 { [f64::NAN, 0.0] } else { [x, y] };
                    desc.set(rect.cell(k), &v);
                }
                for k in 20 + 2 * n..(22 + 2 * n).min(40) {
                    desc.set(rect.cell(k), &[next(), next()]);
                }
                let support = desc.described_indices().to_vec();
                raw.classify(&desc, &igng, &support);
                for &k in &support {
                    let x = desc.get_stored(k as usize).unwrap();
                    let (c, d1, d2) = igng.nearest_two(x).unwrap();
                    if d2 - d1 > 1e-6 {
                        prop_assert_eq!(raw.raw[k as usize], TerrainCell::Class(c));
                    }
                }
                // Move the prototypes: samples near them, within σ (no new class).
                for (x, y) in samples {
                    let protos: Vec<Vec<f64>> = igng.prototypes().map(|(_, w)| w.to_vec()).collect();
                    let w = &protos[(x * protos.len() as f64) as usize % protos.len()];
                    let _ = igng.adapt(&[w[0] + 0.2 * (y - 0.5), w[1] + 0.2 * (x - 0.5)]);
                }
            }
        }
    }

    #[test]
    fn budgets_round_down() {
        for v in [0.1, 1.0 / 3.0, 1e-12, 7.25, -0.3] {
            assert!(f64::from(round_down(v)) <= v);
        }
        assert!(margin(1.0, 1.0) < 0.0);
        assert!(margin(0.2, 0.6) > 0.19 && margin(0.2, 0.6) < 0.2);
    }
}
