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
//! The erosion and dilation that follow the class changes are `morphology::erode_near` and
//! `morphology::dilate_near`.

use super::budget_queue::BudgetQueue;

use crate::descriptor_field::{DescriptorField, FieldVersion};
use crate::igng::{ClassId, Igng};
use crate::morphology::TerrainCell;

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

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

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
            use strider_core::{Cell, CellRect};
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
