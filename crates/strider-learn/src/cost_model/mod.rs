//! The per-gait traversal cost model C^g of Prágr22 §4.3 (Alg. 5–10).
//!
//! One [`GaitCostModel`] per gait holds:
//!
//! * **Measured costs** c(ν): a 1-D Kalman filter per cell (Eq. 22) fed by the cost signals of
//!   [`crate::signals`]. A measurement is stored only if it is *novel* (§4.3.2): outside the
//!   prediction's 2σ interval (predictive variance with noise, decision 14) or on a cell whose
//!   terrain class still has information to give, I_C(T(ν)) > 0. Before a regressor exists every
//!   measurement is novel. A novel measurement updates its cell and its 8 neighbours
//!   (decision 11).
//! * **The learning set** L (Alg. 5): at most one pair (ta(ν), c(ν)) per described cell with a
//!   measured cost. It is kept in step with the map incrementally — a changed cost or
//!   descriptor *replaces* the cell's training point, a new cell *adds* one — so the GP
//!   ([`crate::gp::Gp`]) is updated in O(n²) per change instead of being refitted. The
//!   regressor R exists once |L| ≥ n_L^min; before that predictions are the prior.
//! * **Terrain classes** T (Alg. 7): IGNG prototypes ([`crate::igng`]) adapted on random batches
//!   of n^IGNG described cells, nearest-prototype assignment T*(ν) (Eq. 17), erosion to the
//!   learning assignment T (Eq. 25) and dilation to the planning assignment T̂ (Eq. 26).
//! * **Information gain** per class (Alg. 8, Eq. 23–24) from the entropy (Eq. 16) of the latent
//!   variance at the class's median descriptor (decision 14; see below), with the H^GT
//!   threshold over classes holding more than m_T learning cells (decision 19).
//! * **Goals** (Alg. 9): sampling sites on a lattice of spacing d_S, one goal per informative
//!   class; informative classes left without a site are pruned (and blacklisted in the IGNG,
//!   decision 17). While the model has no regressor it reports the bootstrap goal of decision 16.
//! * **Planning costs** (Alg. 10, Eq. 18): the class prediction at the dilated class, clamped to
//!   [1, c_max] (decision 12), c_max where no class is left.
//!
//! **Where a class is predicted.** Prágr22 predicts a class at its prototype ta(T). Our IGNG
//! prototype is the running mean of every descriptor it wins, and with colour histograms the
//! cells along a terrain border are mixtures that the nearest prototype absorbs: on
//! `courtyard-small` the pavement prototype of the fast gait settles at 70 % pavement, 24 %
//! turf, where the GP interpolates between pavement (cost 1) and a stuck turf sample (20) and
//! predicts 6.5, so the learned planner would walk everything in the slow gait. The erosion of
//! Eq. 25 exists to keep border cells out of a class, but the histogram disc (r_hist) blurs a
//! wider band than two erosion steps remove, and a mean would still lean on it. So ta(T) in
//! Eq. 18 and Eq. 23 is here the component-wise median descriptor of the class's cells on the
//! eroded grid: the terrain most of the class stands on. The prototype still decides
//! membership (Eq. 17).
//!
//! Costs are modelled as y − 1 with a zero-mean GP (decision 12): the GP's prior mean is 1, so an
//! unseen terrain is predicted as easy as ideal terrain.
//!
//! The model works on the map's layers (admissibility) and a [`DescriptorField`]; it knows
//! nothing of the simulator.
//!
//! Files: `params` (parameters and errors), `measurement` (the cell filter and the novelty
//! test), `learning_set` (L and the GP), `classes` (Alg. 7, 8 and 10), `goals` (Alg. 9 and the
//! bootstrap goal); this file holds the model and its update (Alg. 6).

mod budget_queue;
mod class_map;
mod class_stats;
mod classes;
mod goals;
mod learning_set;
mod measurement;
mod params;

pub use class_map::ClassificationCounts;
pub use classes::ClassInfo;
pub use goals::CostGoal;
pub use measurement::{CellCost, Insertion};
pub use params::{CostModelError, CostModelParams};

use crate::descriptor_field::DescriptorField;
use crate::gp::Gp;
use crate::igng::{ClassId, Igng};
use crate::morphology::TerrainCell;
// Fx, not SipHash: the maps are keyed by cells and class ids (no untrusted keys), and their
// lookups run per cell of the map at every learning update.
use rustc_hash::FxHashMap as HashMap;
use strider_core::{Cell, CellRect, GaitId};
use strider_map::ElevationMap;

/// Outcome of one [`GaitCostModel::update`] (Alg. 6).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct ModelUpdate {
    /// Classes represented on the eroded grid, by id.
    pub classes: Vec<ClassInfo>,
    /// H_C^GT (Eq. 24), `None` when no class has more than m_T learning cells.
    pub h_gt: Option<f64>,
    /// The goals Γ_C.
    pub goals: Vec<CostGoal>,
    /// Classes pruned in this update (Alg. 9 line 9).
    pub pruned: Vec<ClassId>,
}

/// The traversal cost model C^g of one gait.
#[derive(Debug)]
pub struct GaitCostModel {
    gait: GaitId,
    params: CostModelParams,
    dim: usize,
    costs: HashMap<Cell, CellCost>,
    /// Cells with a measured cost in the order they were first measured (deterministic
    /// iteration; `costs` is only used for lookups).
    measured: Vec<Cell>,
    gp: Gp,
    /// The cell of each GP training point.
    learn_cells: Vec<Cell>,
    /// The training index of each learning cell.
    learn_index: HashMap<Cell, usize>,
    igng: Igng,
    /// The descriptors' rectangle at the last update (the map's known bounds).
    rect: CellRect,
    /// The descriptors' storage rectangle: the lattice of the rasters below, which are kept
    /// from one update to the next while it stays the same, only their `support` reset.
    store: CellRect,
    /// Learning assignment T (eroded) and planning assignment T̂ of the last update.
    learn_class: Vec<TerrainCell>,
    plan_class: Vec<TerrainCell>,
    /// Storage indices of the described cells at the last update, ascending: the only cells
    /// of the class rasters that are not unknown.
    support: Vec<u32>,
    /// `support` of the update before (cells a full recomputation must reset).
    prev_support: Vec<u32>,
    /// T* kept between updates, to reclassify only the cells that may have changed class.
    raw: class_map::RawClasses,
    /// Cells of `learn_class` changed in this update, for the dilation near them; `None`
    /// after a full classification (dilate everywhere).
    learn_changed: Option<Vec<u32>>,
    /// Cells of `learn_class` changed since the class statistics last followed it; `None`:
    /// any cell may have (they read every cell).
    class_touched: Option<Vec<u32>>,
    /// Window buffer of the recomputations near changes.
    window: Vec<TerrainCell>,
    /// Per storage cell: has a measured cost; the first `mask_applied` cells of `measured`
    /// are marked.
    measured_mask: Vec<bool>,
    mask_applied: usize,
    /// Admissibility over the storage rectangle at the last update (a reused buffer).
    admissible: Vec<bool>,
    /// Counts and medians per class of the eroded class map, kept in step with it.
    stats: class_stats::ClassStats,
    /// I_C per class of the last update.
    class_gain: HashMap<ClassId, f64>,
    /// Regressor predictions (descriptor, mean, latent variance) per cell since the last
    /// update, for the novelty test; the variance is NaN until a test needed it.
    novelty_cache: HashMap<Cell, (Vec<f64>, f64, f64)>,
    /// α = K⁻¹(y − m) of the regressor since the last update (computed at the first novelty
    /// test that needs a mean), and the scaled-query scratch of [`Gp::mean_with_alpha`].
    alpha: Option<Vec<f64>>,
    query_scratch: Vec<f64>,
    /// Class predictions of the last update (clamped mean).
    class_cost: HashMap<ClassId, f64>,
    rejected_costs: usize,
    /// d_ν of the map of the last update, metres.
    cell_size: f64,
}

impl GaitCostModel {
    /// An empty model for `gait` over `dim`-dimensional descriptors; `seed` drives the IGNG
    /// batches.
    pub fn new(
        gait: GaitId,
        dim: usize,
        params: CostModelParams,
        seed: u64,
    ) -> Result<Self, CostModelError> {
        if !(params.c_max >= 1.0 && params.c_max.is_finite()) {
            return Err(CostModelError::Params(format!(
                "c_max must be a finite value ≥ 1, got {}",
                params.c_max
            )));
        }
        if !(params.d_s > 0.0 && params.d_s.is_finite()) {
            return Err(CostModelError::Params(format!(
                "d_S must be positive, got {}",
                params.d_s
            )));
        }
        if !(params.sigma_sense2 > 0.0 && params.sigma0_2 > 0.0) {
            return Err(CostModelError::Params(
                "σ_sense² and σ_0² must be positive".into(),
            ));
        }
        let gp = Gp::new(dim, params.gp.clone())?;
        let igng = Igng::new(dim, params.igng.clone(), seed ^ (gait.0 as u64) << 56)
            .map_err(|e| CostModelError::Params(e.to_string()))?;
        Ok(Self {
            gait,
            dim,
            costs: HashMap::default(),
            measured: Vec::new(),
            gp,
            learn_cells: Vec::new(),
            learn_index: HashMap::default(),
            igng,
            rect: CellRect::new(Cell::new(0, 0), 0, 0),
            store: CellRect::new(Cell::new(0, 0), 0, 0),
            learn_class: Vec::new(),
            plan_class: Vec::new(),
            support: Vec::new(),
            prev_support: Vec::new(),
            raw: class_map::RawClasses::default(),
            learn_changed: None,
            class_touched: None,
            window: Vec::new(),
            measured_mask: Vec::new(),
            mask_applied: 0,
            admissible: Vec::new(),
            stats: class_stats::ClassStats::default(),
            class_gain: HashMap::default(),
            novelty_cache: HashMap::default(),
            alpha: None,
            query_scratch: Vec::new(),
            class_cost: HashMap::default(),
            rejected_costs: 0,
            cell_size: 0.05,
            params,
        })
    }

    /// The gait g of this model.
    pub fn gait(&self) -> GaitId {
        self.gait
    }

    /// The parameters.
    pub fn params(&self) -> &CostModelParams {
        &self.params
    }

    /// True once the regressor R exists (|L| ≥ n_L^min).
    pub fn has_regressor(&self) -> bool {
        self.gp.len() >= self.params.n_min.max(1)
    }

    /// The learning pairs the regressor trains on: |L|, or the newest
    /// [`CostModelParams::max_learning_pairs`] of L when L holds more.
    pub fn learning_set_len(&self) -> usize {
        self.gp.len()
    }

    /// Cells of the pairs the regressor trains on, in training order.
    pub fn learning_cells(&self) -> &[Cell] {
        &self.learn_cells
    }

    /// Cells with a measured cost, in the order first measured.
    pub fn measured_cells(&self) -> &[Cell] {
        &self.measured
    }

    /// The Kalman cost estimate c(ν), if measured.
    pub fn cell_cost(&self, c: Cell) -> Option<CellCost> {
        self.costs.get(&c).copied()
    }

    /// Non-finite cost measurements refused so far.
    pub fn rejected_costs(&self) -> usize {
        self.rejected_costs
    }

    /// The regressor's GP (its training set is L).
    pub fn gp(&self) -> &Gp {
        &self.gp
    }

    /// The IGNG terrain classes.
    pub fn igng(&self) -> &Igng {
        &self.igng
    }

    /// [`GaitCostModel::predict`] at many descriptors (`xs`: q × dim, row-major), blocked and
    /// in parallel ([`Gp::predict_batch`]); the prior where there is no regressor or the input
    /// does not fit.
    pub fn predict_many(&self, xs: &[f64]) -> Vec<(f64, f64)> {
        let q = xs.len().checked_div(self.dim).unwrap_or(0);
        let prior = (
            self.clamp(self.params.gp.prior_mean),
            self.params.gp.kernel.prior_variance(),
        );
        if !self.has_regressor() || xs.len() != q * self.dim {
            return vec![prior; q];
        }
        let (mut mean, mut var) = (vec![0.0; q], vec![0.0; q]);
        if self.gp.predict_batch(xs, &mut mean, &mut var).is_err() {
            return vec![prior; q];
        }
        mean.into_iter()
            .zip(var)
            .map(|(m, v)| (self.clamp(m), v.max(0.0)))
            .collect()
    }

    /// Predicted cost distribution N(μ̂_c, σ̂_c²) at a descriptor (Eq. 14): the mean clamped to
    /// [1, c_max] and the latent variance; the prior (1, σ_s²) while there is no regressor.
    pub fn predict(&self, x: &[f64]) -> (f64, f64) {
        if !self.has_regressor() || x.len() != self.dim {
            return (
                self.clamp(self.params.gp.prior_mean),
                self.params.gp.kernel.prior_variance(),
            );
        }
        let p = self.gp.predict(x);
        (self.clamp(p.mean), p.latent_variance.max(0.0))
    }

    fn clamp(&self, c: f64) -> f64 {
        if c.is_finite() {
            c.clamp(1.0, self.params.c_max)
        } else {
            self.params.c_max
        }
    }

    /// Makes the next [`update`](Self::update) classify, erode and dilate every cell again
    /// instead of only near what changed. The result is the same; this exists to check that
    /// and to measure the difference.
    pub fn forget_class_maps(&mut self) {
        self.raw.invalidate();
    }

    /// How the class maps were brought up to date so far (see [`ClassificationCounts`]).
    pub fn classification_counts(&self) -> ClassificationCounts {
        self.raw.counts
    }

    /// The eroded class T(ν) of the last update.
    pub fn learning_class(&self, c: Cell) -> Option<ClassId> {
        match self.store.index(c).map(|k| self.learn_class[k]) {
            Some(TerrainCell::Class(t)) => Some(t),
            _ => None,
        }
    }

    /// The dilated class T̂(ν) of the last update.
    pub fn planning_class(&self, c: Cell) -> Option<ClassId> {
        match self.store.index(c).map(|k| self.plan_class[k]) {
            Some(TerrainCell::Class(t)) => Some(t),
            _ => None,
        }
    }

    /// I_C(T(ν)) of the cell's eroded class in the last update; 0 for eroded cells.
    pub fn cell_information_gain(&self, c: Cell) -> f64 {
        self.learning_class(c)
            .and_then(|t| self.class_gain.get(&t).copied())
            .unwrap_or(0.0)
    }

    fn check_dim(&self, desc: &DescriptorField) -> Result<(), CostModelError> {
        if desc.dim() != self.dim {
            return Err(CostModelError::Dimension {
                expected: self.dim,
                got: desc.dim(),
            });
        }
        Ok(())
    }

    /// Alg. 6 for this gait: refreshes the learning set against the current descriptors,
    /// adapts the terrain classes (Alg. 7), computes the information gain per class (Alg. 8),
    /// identifies the goals (Alg. 9, or the bootstrap goal of decision 16) and the planning
    /// class assignment (Alg. 10). `map` supplies admissibility: goal sites are admissible
    /// cells (the robot's centre must be able to stand there).
    pub fn update(
        &mut self,
        map: &ElevationMap,
        desc: &DescriptorField,
    ) -> Result<ModelUpdate, CostModelError> {
        let out = self.update_models(map, desc);
        if out.is_err() {
            // The class maps may be half done: the next update starts them over.
            self.raw.invalidate();
            self.class_touched = None;
        }
        out
    }

    fn update_models(
        &mut self,
        map: &ElevationMap,
        desc: &DescriptorField,
    ) -> Result<ModelUpdate, CostModelError> {
        self.check_dim(desc)?;
        self.novelty_cache.clear();
        self.alpha = None;
        self.refresh_learning_set(desc)?;
        self.reset_classes(map, desc);
        if !self.has_regressor() {
            return Ok(self.bootstrap_update());
        }
        self.assign_classes(desc)?;
        let (mut classes, h_gt) = self.rate_classes(desc);
        let (goals, pruned) = self.class_goals(&classes);
        self.prune_classes(&pruned)?;
        classes.retain(|c| !pruned.contains(&c.id));
        self.dilate_classes();
        Ok(ModelUpdate {
            classes,
            h_gt,
            goals,
            pruned,
        })
    }

    /// Forgets the gains and costs of the last update, lays the class rasters out on the
    /// descriptors' storage rectangle (kept when it is unchanged: the class maps are then
    /// brought up to date near what changed), and reads admissibility and the measured cells
    /// onto it.
    fn reset_classes(&mut self, map: &ElevationMap, desc: &DescriptorField) {
        self.rect = desc.rect();
        self.cell_size = map.cell_size();
        let store = desc.storage();
        if store != self.store || self.learn_class.len() != store.len() {
            self.store = store;
            self.learn_class = vec![TerrainCell::Unknown; store.len()];
            self.plan_class = vec![TerrainCell::Unknown; store.len()];
            self.measured_mask = vec![false; store.len()];
            self.mask_applied = 0;
            self.raw.reset(store.len());
            self.class_touched = None;
            self.support.clear();
        }
        std::mem::swap(&mut self.prev_support, &mut self.support);
        self.support.clear();
        self.support.extend_from_slice(desc.described_indices());
        for c in &self.measured[self.mask_applied..] {
            if let Some(k) = store.index(*c) {
                self.measured_mask[k] = true;
            }
        }
        self.mask_applied = self.measured.len();
        map.admissible_layer()
            .read_rect(store, &mut self.admissible);
        self.class_gain.clear();
        self.class_cost.clear();
    }

    /// Planning cost ĉ_{C^g}(ν) over `rect` (Alg. 10, Eq. 18), row-major: the dilated class's
    /// prediction clamped to [1, c_max]; c_max for cells left without a class by erosion and
    /// dilation (Eq. 18's ∅). Cells without a descriptor (too little of their r_hist disc is
    /// known yet, or outside the last update) have no prediction at all; they get the prior cost
    /// (decision 12: unseen terrain is as easy as ideal terrain), as does every cell before the
    /// regressor exists (flat costs).
    pub fn planning_costs(&self, rect: CellRect) -> Vec<f32> {
        let prior = self.clamp(self.params.gp.prior_mean) as f32;
        if !self.has_regressor() {
            return vec![prior; rect.len()];
        }
        // The classes' costs by id, looked up per cell of the view: a dense table (ids are
        // small and never reused) instead of a hash lookup on every cell.
        let c_max = self.params.c_max as f32;
        let table = self.class_cost_table();
        let class_cost = |t: ClassId| match &table {
            Some(v) => v.get(t.0 as usize).copied().unwrap_or(c_max),
            None => self.class_cost.get(&t).map_or(c_max, |&c| c as f32),
        };
        let mut out = Vec::with_capacity(rect.len());
        for j in rect.min.j..rect.min.j + rect.height as i32 {
            for i in rect.min.i..rect.min.i + rect.width as i32 {
                out.push(
                    match self
                        .store
                        .index(Cell::new(i, j))
                        .map(|k| self.plan_class[k])
                    {
                        Some(TerrainCell::Class(t)) => class_cost(t),
                        Some(TerrainCell::Eroded) => c_max,
                        Some(TerrainCell::Unknown) | None => prior,
                    },
                );
            }
        }
        out
    }

    /// The classes' planning costs indexed by class id (c_max where a class has none), or
    /// `None` when the largest id would make the table unreasonably large.
    fn class_cost_table(&self) -> Option<Vec<f32>> {
        const MAX_DENSE_IDS: u32 = 1 << 20;
        let top = self.class_cost.keys().map(|t| t.0).max().unwrap_or(0);
        if top >= MAX_DENSE_IDS {
            return None;
        }
        let mut v = vec![self.params.c_max as f32; top as usize + 1];
        for (t, &c) in &self.class_cost {
            v[t.0 as usize] = c as f32;
        }
        Some(v)
    }
}
