//! The learning set L (Alg. 5): one (ta(ν), c(ν)) pair per described cell with a measured cost,
//! kept in step with the map by O(n²) changes of the GP instead of refits.

use strider_core::Cell;

use super::{CostModelError, GaitCostModel};
use crate::descriptor_field::DescriptorField;

/// Learning pairs new in an update, added to the GP together.
#[derive(Default)]
struct NewPairs {
    cells: Vec<Cell>,
    /// Descriptors, row-major.
    xs: Vec<f64>,
    ys: Vec<f64>,
}

impl GaitCostModel {
    /// Alg. 5 lines 4–6: makes L the described cells with a measured cost. Removals and
    /// replacements happen in place; new pairs join the GP in one block (one blocked solve
    /// instead of one streaming solve of L each), after every removal and replacement; targets
    /// that merely changed are applied together at the end (one solve for all of them).
    pub(super) fn refresh_learning_set(
        &mut self,
        desc: &DescriptorField,
    ) -> Result<(), CostModelError> {
        let mut new_targets: Vec<(Cell, f64)> = Vec::new();
        let mut added = NewPairs::default();
        let first = self.first_trained(desc);
        for k in 0..self.measured.len() {
            let cell = self.measured[k];
            if let Some(y) = self.sync_learning_pair(cell, desc, k >= first, &mut added)? {
                new_targets.push((cell, y));
            }
        }
        self.gp.extend(&added.xs, &added.ys)?;
        for cell in added.cells {
            self.learn_index.insert(cell, self.learn_cells.len());
            self.learn_cells.push(cell);
        }
        let changes: Vec<(usize, f64)> = new_targets
            .iter()
            .filter_map(|&(c, y)| self.learn_index.get(&c).map(|&i| (i, y)))
            .collect();
        self.gp.set_ys(&changes)?;
        Ok(())
    }

    /// Makes the learning pair of `cell` match its current cost and descriptor: add (to
    /// `added`, for one [`Gp::extend`](crate::gp::Gp::extend) at the end), replace or remove its
    /// GP training point. A pair whose descriptor is unchanged but whose target changed is not
    /// touched: its new target is returned for a batched
    /// [`Gp::set_ys`](crate::gp::Gp::set_ys).
    ///
    /// A cell outside the trained window (`trained` false) leaves the GP.
    fn sync_learning_pair(
        &mut self,
        cell: Cell,
        desc: &DescriptorField,
        trained: bool,
        added: &mut NewPairs,
    ) -> Result<Option<f64>, CostModelError> {
        let cost = self.costs.get(&cell).map(|k| k.cost).filter(|_| trained);
        let x = desc.get(cell);
        match (self.learn_index.get(&cell).copied(), cost, x) {
            (Some(i), Some(y), Some(x)) => {
                if self.gp.x(i) == x {
                    if self.gp.y(i) != y {
                        return Ok(Some(y));
                    }
                } else {
                    self.gp.replace(i, x, y)?;
                }
            }
            (None, Some(y), Some(x)) => {
                added.cells.push(cell);
                added.xs.extend_from_slice(x);
                added.ys.push(y);
            }
            (Some(i), _, _) => {
                self.gp.remove(i)?;
                self.learn_cells.remove(i);
                self.learn_index.remove(&cell);
                for (k, c) in self.learn_cells.iter().enumerate().skip(i) {
                    self.learn_index.insert(*c, k);
                }
            }
            (None, _, _) => {}
        }
        Ok(None)
    }

    /// The cells of L, the described cells with a measured cost, in the order first measured.
    pub(super) fn learning_set<'a>(
        &'a self,
        desc: &'a DescriptorField,
    ) -> impl Iterator<Item = Cell> + 'a {
        self.measured
            .iter()
            .copied()
            .filter(|&c| self.in_learning_set(c, desc))
    }

    /// Whether `c` is in L: described, with a measured cost.
    fn in_learning_set(&self, c: Cell, desc: &DescriptorField) -> bool {
        self.costs.contains_key(&c) && desc.get(c).is_some()
    }

    /// The index into the measured cells from which L's pairs train the GP: 0 unless more
    /// than [`CostModelParams::max_learning_pairs`](super::CostModelParams) are in L, else
    /// where the newest that many begin.
    fn first_trained(&self, desc: &DescriptorField) -> usize {
        let Some(max) = self.params.max_learning_pairs else {
            return 0;
        };
        let mut kept = 0;
        for (k, &c) in self.measured.iter().enumerate().rev() {
            if self.in_learning_set(c, desc) {
                if kept == max {
                    return k + 1;
                }
                kept += 1;
            }
        }
        0
    }
}
