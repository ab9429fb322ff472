//! Terrain classes of one gait (Alg. 7, 8 and 10): IGNG adaptation and assignment, erosion to
//! the learning assignment, the information gain per class at its median descriptor, pruning,
//! and dilation to the planning assignment.

use rustc_hash::FxHashMap as HashMap;

use super::{CostModelError, GaitCostModel};
use crate::descriptor_field::DescriptorField;
use crate::gp::differential_entropy;
use crate::igng::ClassId;
use crate::morphology::{self, TerrainCell};

/// Terrain class with its information gain (Alg. 8).
#[derive(Clone, Debug, PartialEq)]
pub struct ClassInfo {
    /// IGNG class id.
    pub id: ClassId,
    /// IGNG prototype of the class.
    pub prototype: Vec<f64>,
    /// ta(T) where the class is predicted: the component-wise median descriptor of its cells
    /// on the eroded grid (see the module notes on Eq. 18).
    pub median: Vec<f64>,
    /// Cells assigned to the class on the eroded grid.
    pub cells: usize,
    /// Learning cells (cells of the class with a learning pair), |T ∩ L|.
    pub learning_cells: usize,
    /// Predicted cost at the median descriptor, clamped to [1, c_max].
    pub cost: f64,
    /// Latent variance at the median descriptor.
    pub variance: f64,
    /// H(σ̂²(ta(T))), Eq. 16.
    pub entropy: f64,
    /// I_C(T), Eq. 23.
    pub information_gain: f64,
}

impl GaitCostModel {
    /// Alg. 7: adapts the IGNG on a random batch, assigns every described cell its nearest
    /// class T*(ν) (Eq. 17) and erodes that into the learning assignment T (Eq. 25). Only the
    /// cells that may have changed class are classified again, and T is recomputed near the
    /// cells whose T* changed (see `class_map`).
    pub(super) fn assign_classes(&mut self, desc: &DescriptorField) -> Result<(), CostModelError> {
        self.cluster(desc)?;
        let w = self.store.width as usize;
        let steps = self.params.erode_steps;
        let r = self.raw.classify(desc, &self.igng, &self.support);
        if r.full {
            for &k in &self.prev_support {
                self.learn_class[k as usize] = TerrainCell::Unknown;
            }
            for &k in &self.support {
                self.learn_class[k as usize] = self.raw.raw[k as usize];
            }
            morphology::erode_in_place(&mut self.learn_class, w, &self.support, steps);
            self.learn_changed = None;
            self.class_touched = None;
        } else {
            let changed =
                morphology::erode_near(&self.raw.raw, &mut self.learn_class, w, &r.changed, steps);
            if let Some(t) = &mut self.class_touched {
                t.extend_from_slice(&changed);
            }
            self.learn_changed = Some(changed);
        }
        Ok(())
    }

    /// Alg. 7 lines 2–6: adapt the IGNG with a batch of n^IGNG descriptors drawn at random
    /// (by the IGNG's seeded generator) from the described cells.
    fn cluster(&mut self, desc: &DescriptorField) -> Result<(), CostModelError> {
        // The described cells in row-major order, read in place rather than copied; the field
        // stores only finite descriptors of its dimension, so the rows need no validation scan.
        let cells = desc.described_indices();
        if cells.is_empty() {
            return Ok(());
        }
        self.igng.train_valid_rows(
            cells.len(),
            |r| desc.get_stored(cells[r] as usize).unwrap_or(&[]),
            1,
        );
        Ok(())
    }

    /// Alg. 8: the classes represented on the eroded grid with their information gain I_C
    /// (Eq. 23) against the threshold H_C^GT (Eq. 24, returned; `None` when no class has more
    /// than m_T learning cells). Records each class's gain and cost for the novelty test and the
    /// planning costs.
    pub(super) fn rate_classes(&mut self, desc: &DescriptorField) -> (Vec<ClassInfo>, Option<f64>) {
        let mut classes = self.class_table(desc);
        let h_gt = classes
            .iter()
            .filter(|c| c.learning_cells > self.params.m_t)
            .map(|c| c.entropy)
            .fold(None, |a: Option<f64>, h| Some(a.map_or(h, |a| a.max(h))));
        for c in &mut classes {
            c.information_gain = match h_gt {
                Some(h) => (c.entropy - h).max(0.0),
                // Eq. 24 over an empty set is −∞, so every class is informative; its gain is
                // reported relative to the noise entropy so it stays finite and ordered.
                None => (c.entropy - differential_entropy(self.params.gp.noise_variance))
                    .max(f64::MIN_POSITIVE),
            };
            self.class_gain.insert(c.id, c.information_gain);
            self.class_cost.insert(c.id, c.cost);
        }
        (classes, h_gt)
    }

    /// One [`ClassInfo`] per class represented on the eroded grid, by ascending id, with the
    /// prediction at its median descriptor (information gain filled in by the caller). The
    /// counts and medians come from the statistics kept in step with the class map.
    fn class_table(&mut self, desc: &DescriptorField) -> Vec<ClassInfo> {
        self.stats
            .sync(desc, &self.learn_class, self.class_touched.as_deref());
        self.class_touched = Some(Vec::new());
        let mut learning: HashMap<ClassId, usize> = HashMap::default();
        // All of L, also the pairs a bounded regressor no longer trains on.
        for c in self.learning_set(desc) {
            if let Some(TerrainCell::Class(t)) = self.store.index(c).map(|k| self.learn_class[k]) {
                *learning.entry(t).or_default() += 1;
            }
        }
        self.stats
            .summaries()
            .into_iter()
            .filter_map(|s| {
                let prototype = self.igng.prototype(s.id)?.to_vec();
                let (cost, variance) = self.predict(&s.median);
                Some(ClassInfo {
                    id: s.id,
                    prototype,
                    cells: s.cells,
                    learning_cells: learning.get(&s.id).copied().unwrap_or(0),
                    median: s.median,
                    cost,
                    variance,
                    entropy: differential_entropy(variance),
                    information_gain: 0.0,
                })
            })
            .collect()
    }

    /// Alg. 9 line 9: removes the classes `pruned` from the IGNG (blacklisting them, decision
    /// 17), zeroes their gain and relabels their cells as eroded.
    pub(super) fn prune_classes(&mut self, pruned: &[ClassId]) -> Result<(), CostModelError> {
        for &t in pruned {
            self.igng
                .prune(t)
                .map_err(|e| CostModelError::Params(e.to_string()))?;
            self.class_gain.insert(t, 0.0);
            for &k in &self.support {
                let s = &mut self.learn_class[k as usize];
                if *s == TerrainCell::Class(t) {
                    *s = TerrainCell::Eroded;
                    if let Some(changed) = &mut self.learn_changed {
                        changed.push(k);
                    }
                    if let Some(t) = &mut self.class_touched {
                        t.push(k);
                    }
                }
            }
        }
        Ok(())
    }

    /// Alg. 10: dilates the learning assignment into the planning assignment T̂ (Eq. 26),
    /// everywhere after a full classification, else near the cells whose T changed.
    pub(super) fn dilate_classes(&mut self) {
        let w = self.store.width as usize;
        let (size, steps) = (self.params.dilate_size, self.params.dilate_steps);
        match self.learn_changed.take() {
            None => {
                for &k in &self.prev_support {
                    self.plan_class[k as usize] = TerrainCell::Unknown;
                }
                for &k in &self.support {
                    self.plan_class[k as usize] = self.learn_class[k as usize];
                }
                morphology::dilate_in_place(&mut self.plan_class, w, &self.support, size, steps);
            }
            Some(mut changed) => {
                changed.sort_unstable();
                changed.dedup();
                morphology::dilate_near(
                    &self.learn_class,
                    &mut self.plan_class,
                    w,
                    &changed,
                    size,
                    steps,
                    &mut self.window,
                );
            }
        }
    }
}
