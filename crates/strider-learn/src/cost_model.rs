//! The per-gait traversal cost model C^g of `001` §4.3 (Alg. 5–10).
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
//! **Where a class is predicted.** `001` predicts a class at its prototype ta(T). Our IGNG
//! prototype is the running mean of every descriptor it wins, and with colour histograms the
//! cells along a terrain border are mixtures that the nearest prototype absorbs: on
//! `courtyard-small` the pavement prototype of the fast gait settled at 70 % pavement, 24 %
//! turf, where the GP interpolates between pavement (cost 1) and a stuck turf sample (20) and
//! predicted 6.5, so the learned planner walked everything in the slow gait. The erosion of
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

use crate::descriptor_field::DescriptorField;
use crate::gp::{Gp, GpError, GpParams, Kernel, KernelKind, differential_entropy};
use crate::igng::{ClassId, Igng, IgngParams};
use crate::morphology::{self, TerrainCell};
// Fx, not SipHash: the maps are keyed by cells and class ids (no untrusted keys), and their
// lookups run per cell of the map at every learning update.
use rustc_hash::FxHashMap as HashMap;
use strider_core::{Cell, CellRect, GaitId, Point2};
use strider_map::ElevationMap;
use strider_map::descriptors::Raster;

/// Parameters of a gait cost model (`001` Tbl. 3; defaults: the real/small-simulation column).
#[derive(Clone, Debug, PartialEq)]
pub struct CostModelParams {
    /// GP of the regressor R (default: SE, l = 0.4, σ_s² = 1, σ_ε² = 0.25, prior mean 1).
    pub gp: GpParams,
    /// σ_sense², variance of one cost measurement in the cell Kalman filter (Eq. 22).
    pub sigma_sense2: f64,
    /// σ_0², initial variance of a cell's cost filter.
    pub sigma0_2: f64,
    /// n_L^min, learning-set size from which the regressor exists.
    pub n_min: usize,
    /// m_T, learning cells a class needs (strictly more) to count as ground truth (Eq. 24).
    pub m_t: usize,
    /// d_S, cell size of the sampling lattice, metres.
    pub d_s: f64,
    /// c_max, the planning cost of unclassified cells and the upper clamp of predictions.
    pub c_max: f64,
    ///     /// IGNG parameters, including n^IGNG (`batch`); σ^IGNG = 2l is set from the kernel by
    /// [`CostModelParams::new`].
    pub igng: IgngParams,
    /// n_erode^steps, erosion passes (Eq. 25).
    pub erode_steps: usize,
    /// n_dilate^steps, dilation passes (Eq. 26).
    pub dilate_steps: usize,
    /// n_dilate^size, half-width of the dilation window (Eq. 26).
    pub dilate_size: usize,
}

impl Default for CostModelParams {
    fn default() -> Self {
        Self::new(GpParams {
            kernel: Kernel {
                kind: KernelKind::SquaredExponential,
                lengthscales: vec![0.4],
                signal_variance: 1.0,
            },
            noise_variance: 0.25,
            prior_mean: 1.0,
        })
    }
}

impl CostModelParams {
    /// Tbl. 3 defaults around the given GP; σ^IGNG = 2l (decision 17) from its first
    /// lengthscale.
    pub fn new(gp: GpParams) -> Self {
        let l = gp.kernel.lengthscales.first().copied().unwrap_or(0.4);
        let igng = IgngParams::from_lengthscale(l);
        Self {
            gp,
            sigma_sense2: 0.10,
            sigma0_2: 1.0,
            n_min: 25,
            m_t: 10,
            d_s: 0.44,
            c_max: 20.0,
            igng,
            erode_steps: 2,
            dilate_steps: 3,
            dilate_size: 2,
        }
    }
}

/// Errors of the cost model.
#[derive(Debug, thiserror::Error)]
pub enum CostModelError {
    /// A measured cost that is NaN or infinite.
    #[error("cost measurement {value} at cell ({i}, {j}) is not finite")]
    NonFiniteCost {
        /// The value received.
        value: f64,
        /// Cell column.
        i: i32,
        /// Cell row.
        j: i32,
    },
    /// A descriptor field of another dimension than the model's.
    #[error("descriptor dimension {got} does not match the model's {expected}")]
    Dimension {
        /// The model's dimension.
        expected: usize,
        /// The field's dimension.
        got: usize,
    },
    /// Invalid parameters.
    #[error("invalid cost model parameter: {0}")]
    Params(String),
    /// The GP refused an update.
    #[error(transparent)]
    Gp(#[from] GpError),
}

/// The Kalman cost estimate of one cell (Eq. 22).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CellCost {
    /// c(ν).
    pub cost: f64,
    /// Its variance σ_k².
    pub variance: f64,
    /// Measurements fused.
    pub count: u32,
}

/// Learning pairs new in an update, added to the GP together.
#[derive(Default)]
struct NewPairs {
    cells: Vec<Cell>,
    /// Descriptors, row-major.
    xs: Vec<f64>,
    ys: Vec<f64>,
}

/// What [`GaitCostModel::insert_measurement`] did.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Insertion {
    /// The measurement was novel and updated the cell and its neighbours.
    Stored,
    /// The model already predicts it well and the cell's class is certain.
    NotNovel,
}

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

/// A cost-model goal γ_C(T): sampling sites of one terrain class (Alg. 9).
#[derive(Clone, Debug, PartialEq)]
pub struct CostGoal {
    /// The class to sample; `None` for the bootstrap goal of decision 16.
    pub class: Option<ClassId>,
    /// I_C of the class (for the bootstrap goal: the prior's entropy).
    pub information_gain: f64,
    /// Sampling sites, in lattice order.
    pub sites: Vec<Cell>,
}

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
    /// Rasters of the last update: learning assignment T (eroded) and planning assignment T̂.
    rect: CellRect,
    learn_class: Vec<TerrainCell>,
    plan_class: Vec<TerrainCell>,
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
            learn_class: Vec::new(),
            plan_class: Vec::new(),
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

    /// |L|, the learning-set size.
    pub fn learning_set_len(&self) -> usize {
        self.gp.len()
    }

    /// Cells of the learning set, in training order.
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

    /// The eroded class T(ν) of the last update.
    pub fn learning_class(&self, c: Cell) -> Option<ClassId> {
        match self.rect.index(c).map(|k| self.learn_class[k]) {
            Some(TerrainCell::Class(t)) => Some(t),
            _ => None,
        }
    }

    /// The dilated class T̂(ν) of the last update.
    pub fn planning_class(&self, c: Cell) -> Option<ClassId> {
        match self.rect.index(c).map(|k| self.plan_class[k]) {
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

    /// Alg. 5 line 3, `insertIfNovel`: fuses a cost measurement `z` experienced with this
    /// model's gait at cell `c` into `c` and its 8 neighbours (Eq. 22, decision 11) when it is
    /// novel, then brings the learning set up to date for the touched cells. `desc` supplies
    /// ta(ν). Non-finite costs are refused (error, counted, nothing stored).
    pub fn insert_measurement(
        &mut self,
        c: Cell,
        z: f64,
        desc: &DescriptorField,
    ) -> Result<Insertion, CostModelError> {
        if !z.is_finite() {
            self.rejected_costs += 1;
            return Err(CostModelError::NonFiniteCost {
                value: z,
                i: c.i,
                j: c.j,
            });
        }
        self.check_dim(desc)?;
        if !self.is_novel(c, z, desc) {
            return Ok(Insertion::NotNovel);
        }
        let (s2, s0) = (self.params.sigma_sense2, self.params.sigma0_2);
        for cell in std::iter::once(c).chain(c.neighbours8()) {
            match self.costs.get_mut(&cell) {
                Some(k) => {
                    let sum = s2 + k.variance;
                    k.cost = (s2 * k.cost + k.variance * z) / sum;
                    k.variance = s2 * k.variance / sum;
                    k.count += 1;
                }
                None => {
                    self.costs.insert(
                        cell,
                        CellCost {
                            cost: z,
                            variance: s0,
                            count: 1,
                        },
                    );
                    self.measured.push(cell);
                }
            }
        }
        // The learning set follows at the next update (Alg. 5 relearns the regressor at the
        // learning rate; the novelty test uses the latest learned one).
        Ok(Insertion::Stored)
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

    /// Novelty (§4.3.2): no regressor yet, or outside the 2σ predictive interval, or the cell's
    /// class can still give information.
    ///
    /// The regressor changes only at updates, so its prediction at a cell is cached until the
    /// next update (keyed by the cell and checked against its descriptor): the robot measures
    /// the same cells many times at 20 Hz, and a prediction costs O(n²).
    fn is_novel(&mut self, c: Cell, z: f64, desc: &DescriptorField) -> bool {
        if !self.has_regressor() || self.cell_information_gain(c) > 0.0 {
            return true;
        }
        let Some(x) = desc.get(c) else {
            // Without a descriptor the prediction is unknown: keep the measurement, it joins
            // the learning set once the cell is described.
            return true;
        };
        let (mean, latent) = match self.novelty_cache.get(&c) {
            Some((xc, m, v)) if xc[..] == x[..] => (*m, *v),
            _ => {
                let alpha = match &self.alpha {
                    Some(a) => a,
                    None => self.alpha.insert(self.gp.alpha()),
                };
                let mean = self.gp.mean_with_alpha(alpha, x, &mut self.query_scratch);
                self.novelty_cache.insert(c, (x.to_vec(), mean, f64::NAN));
                (mean, f64::NAN)
            }
        };
        // The latent variance lies in [0, σ_f²]: outside the band those bounds leave open the
        // test is decided by the O(n·dim) mean alone, and only inside it is the O(n²)
        // variance computed (then cached too).
        let sn2 = self.params.gp.noise_variance;
        let deviation = (mean - z).abs();
        if deviation > 2.0 * (self.gp.params().kernel.prior_variance() + sn2).sqrt() {
            return true;
        }
        if deviation <= 2.0 * sn2.sqrt() {
            return false;
        }
        let latent = if latent.is_nan() {
            let v = self.gp.predict(x).latent_variance;
            self.novelty_cache.insert(c, (x.to_vec(), mean, v));
            v
        } else {
            latent
        };
        deviation > 2.0 * (latent.max(0.0) + sn2).sqrt()
    }

    /// Makes the learning pair of `cell` match its current cost and descriptor: add (to `added`,
    /// for one [`Gp::extend`] at the end), replace or remove its GP training point. A pair
    /// whose descriptor is unchanged but whose target changed is not touched: its new target is
    /// returned for a batched [`Gp::set_ys`].
    fn sync_learning_pair(
        &mut self,
        cell: Cell,
        desc: &DescriptorField,
        added: &mut NewPairs,
    ) -> Result<Option<f64>, CostModelError> {
        let cost = self.costs.get(&cell).map(|k| k.cost);
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
        self.check_dim(desc)?;
        // Alg. 5 lines 4–6: L = described cells with a measured cost. Targets that merely
        // changed are applied together at the end (one solve for all of them).
        self.novelty_cache.clear();
        self.alpha = None;
        let mut new_targets: Vec<(Cell, f64)> = Vec::new();
        let mut added = NewPairs::default();
        for k in 0..self.measured.len() {
            let cell = self.measured[k];
            if let Some(y) = self.sync_learning_pair(cell, desc, &mut added)? {
                new_targets.push((cell, y));
            }
        }
        // New pairs join the GP in one block (one blocked solve instead of one streaming
        // solve of L each), after every removal and replacement of this update.
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
        self.rect = desc.rect();
        self.cell_size = map.cell_size();
        let n = self.rect.len();
        self.learn_class = vec![TerrainCell::Unknown; n];
        self.plan_class = vec![TerrainCell::Unknown; n];
        self.class_gain.clear();
        self.class_cost.clear();
        let admissible = map.admissible_raster(self.rect);

        if !self.has_regressor() {
            // Decision 16: one bootstrap goal over described admissible cells with no cost.
            for k in 0..n {
                if desc.get_index(k).is_some() {
                    self.learn_class[k] = TerrainCell::Eroded;
                    self.plan_class[k] = TerrainCell::Eroded;
                }
            }
            let sites = self.lattice_sites(desc, |m, k| {
                admissible[k] && !m.costs.contains_key(&m.rect.cell(k))
            });
            let goals = if sites.is_empty() {
                Vec::new()
            } else {
                vec![CostGoal {
                    class: None,
                    information_gain: differential_entropy(self.params.gp.kernel.prior_variance()),
                    sites,
                }]
            };
            return Ok(ModelUpdate {
                goals,
                ..ModelUpdate::default()
            });
        }

        // Alg. 7: adapt the IGNG on a random batch, assign, erode.
        self.cluster(desc)?;
        let mut star = vec![TerrainCell::Unknown; n];
        for (k, s) in star.iter_mut().enumerate() {
            if let Some(x) = desc.get_index(k) {
                *s = self
                    .igng
                    .classify(x)
                    .map_or(TerrainCell::Eroded, TerrainCell::Class);
            }
        }
        self.learn_class = morphology::erode(
            &Raster {
                rect: self.rect,
                values: star,
            },
            self.params.erode_steps,
        )
        .map_err(|e| CostModelError::Params(e.to_string()))?
        .values;

        // Alg. 8: information gain per class represented on the eroded grid.
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

        // Alg. 9: sampling sites on the lattice; prune informative classes without a site.
        let sites = self.lattice_sites(desc, |m, k| {
            admissible[k]
                && !m.costs.contains_key(&m.rect.cell(k))
                && match m.learn_class[k] {
                    TerrainCell::Class(t) => m.class_gain.get(&t).copied().unwrap_or(0.0) > 0.0,
                    _ => false,
                }
        });
        let mut goals: Vec<CostGoal> = Vec::new();
        for c in &classes {
            if c.information_gain > 0.0 {
                goals.push(CostGoal {
                    class: Some(c.id),
                    information_gain: c.information_gain,
                    sites: Vec::new(),
                });
            }
        }
        for s in sites {
            if let Some(TerrainCell::Class(t)) = self.rect.index(s).map(|k| self.learn_class[k])
                && let Some(g) = goals.iter_mut().find(|g| g.class == Some(t))
            {
                g.sites.push(s);
            }
        }
        let mut pruned = Vec::new();
        goals.retain(|g| {
            if g.sites.is_empty() {
                pruned.extend(g.class);
                false
            } else {
                true
            }
        });
        for &t in &pruned {
            self.igng
                .prune(t)
                .map_err(|e| CostModelError::Params(e.to_string()))?;
            self.class_gain.insert(t, 0.0);
            for s in &mut self.learn_class {
                if *s == TerrainCell::Class(t) {
                    *s = TerrainCell::Eroded;
                }
            }
        }
        classes.retain(|c| !pruned.contains(&c.id));

        // Alg. 10: dilate the learning assignment into the planning assignment.
        self.plan_class = morphology::dilate(
            &Raster {
                rect: self.rect,
                values: self.learn_class.clone(),
            },
            self.params.dilate_size,
            self.params.dilate_steps,
        )
        .map_err(|e| CostModelError::Params(e.to_string()))?
        .values;
        Ok(ModelUpdate {
            classes,
            h_gt,
            goals,
            pruned,
        })
    }

    /// Alg. 7 lines 2–6: adapt the IGNG with a batch of n^IGNG descriptors drawn at random
    /// (by the IGNG's seeded generator) from the described cells.
    fn cluster(&mut self, desc: &DescriptorField) -> Result<(), CostModelError> {
        let mut rows = Vec::with_capacity(desc.described_count() * self.dim);
        for k in 0..desc.rect().len() {
            if let Some(x) = desc.get_index(k) {
                rows.extend_from_slice(x);
            }
        }
        if rows.is_empty() {
            return Ok(());
        }
        self.igng
            .train(&rows, 1)
            .map_err(|e| CostModelError::Params(e.to_string()))?;
        Ok(())
    }

    /// One [`ClassInfo`] per class represented on the eroded grid, by ascending id, with the
    /// prediction at its median descriptor (information gain filled in by the caller).
    fn class_table(&self, desc: &DescriptorField) -> Vec<ClassInfo> {
        // Per class: eroded cells, learning cells, and the descriptors of its cells.
        let mut cells: HashMap<ClassId, (usize, usize, Vec<f64>)> = HashMap::default();
        for (k, s) in self.learn_class.iter().enumerate() {
            if let TerrainCell::Class(t) = *s {
                let e = cells.entry(t).or_default();
                e.0 += 1;
                e.1 += self.learn_index.contains_key(&self.rect.cell(k)) as usize;
                if let Some(x) = desc.get_index(k) {
                    e.2.extend_from_slice(x);
                }
            }
        }
        let mut ids: Vec<ClassId> = cells.keys().copied().collect();
        ids.sort_unstable();
        let mut column = Vec::new();
        ids.into_iter()
            .filter_map(|id| {
                let prototype = self.igng.prototype(id)?.to_vec();
                let (n, l, rows) = &cells[&id];
                // Never `None`: a cell gets a class only by classifying its descriptor.
                let median = component_median(rows, self.dim, &mut column)?;
                let (cost, variance) = self.predict(&median);
                let (n, l) = (*n, *l);
                Some(ClassInfo {
                    id,
                    prototype,
                    median,
                    cells: n,
                    learning_cells: l,
                    cost,
                    variance,
                    entropy: differential_entropy(variance),
                    information_gain: 0.0,
                })
            })
            .collect()
    }

    /// Alg. 9 lines 4–7: for each point p_S of the global lattice of spacing d_S inside the
    /// rectangle, the closest cell within √2/2·d_S of p_S that satisfies `ok(self, index)`.
    /// Lattice order (rows, then columns); ties go to the lower row-major index.
    fn lattice_sites(
        &self,
        desc: &DescriptorField,
        ok: impl Fn(&Self, usize) -> bool,
    ) -> Vec<Cell> {
        let rect = desc.rect();
        if rect.is_empty() {
            return Vec::new();
        }
        let d = self.cell_size;
        let ds = self.params.d_s;
        let r = std::f64::consts::FRAC_1_SQRT_2 * ds;
        let lo = rect.min.center(d);
        let hi = Cell::new(
            rect.min.i + rect.width as i32 - 1,
            rect.min.j + rect.height as i32 - 1,
        )
        .center(d);
        let (a0, a1) = ((lo.x / ds).ceil() as i64, (hi.x / ds).floor() as i64);
        let (b0, b1) = ((lo.y / ds).ceil() as i64, (hi.y / ds).floor() as i64);
        let reach = (r / d).ceil() as i32 + 1;
        let mut out = Vec::new();
        for b in b0..=b1 {
            for a in a0..=a1 {
                let p = Point2::new(a as f64 * ds, b as f64 * ds);
                let Some(pc) = Cell::containing(p.x, p.y, d) else {
                    continue;
                };
                let mut best: Option<(f64, usize)> = None;
                for dj in -reach..=reach {
                    for di in -reach..=reach {
                        let c = Cell::new(pc.i + di, pc.j + dj);
                        let Some(k) = rect.index(c) else { continue };
                        let cc = c.center(d);
                        let dist = ((cc.x - p.x).powi(2) + (cc.y - p.y).powi(2)).sqrt();
                        if dist >= r || !ok(self, k) {
                            continue;
                        }
                        if best.is_none_or(|(bd, bk)| dist < bd || (dist == bd && k < bk)) {
                            best = Some((dist, k));
                        }
                    }
                }
                if let Some((_, k)) = best {
                    let c = rect.cell(k);
                    if out.last() != Some(&c) {
                        out.push(c);
                    }
                }
            }
        }
        out
    }

    /// Planning cost ĉ_{C^g}(ν) over `rect` (Alg. 10, Eq. 18), row-major: the dilated class's
    /// prediction clamped to [1, c_max]; c_max for cells left without a class by erosion and
    /// dilation (Eq. 18's ∅). Cells without a descriptor (too little of their r_hist disc is
    /// known yet, or outside the last update) have no prediction at all; they get the prior cost
    /// (decision 12: unseen terrain is as easy as ideal terrain), as does every cell before the
    /// regressor exists (flat costs).
    pub fn planning_costs(&self, rect: CellRect) -> Vec<f32> {
        if !self.has_regressor() {
            return vec![self.clamp(self.params.gp.prior_mean) as f32; rect.len()];
        }
        rect.cells()
            .map(|c| {
                let prior = self.clamp(self.params.gp.prior_mean);
                let cost = match self.rect.index(c).map(|k| self.plan_class[k]) {
                    Some(TerrainCell::Class(t)) => self
                        .class_cost
                        .get(&t)
                        .copied()
                        .unwrap_or(self.params.c_max),
                    Some(TerrainCell::Eroded) => self.params.c_max,
                    Some(TerrainCell::Unknown) | None => prior,
                };
                cost as f32
            })
            .collect()
    }
}

/// Component-wise median of `rows` (row-major, `dim` values per row; the lower median for an
/// even count); `None` without rows. `column` is scratch space.
fn component_median(rows: &[f64], dim: usize, column: &mut Vec<f64>) -> Option<Vec<f64>> {
    let n = rows.len().checked_div(dim)?;
    if n == 0 {
        return None;
    }
    Some(
        (0..dim)
            .map(|k| {
                column.clear();
                column.extend(rows.iter().skip(k).step_by(dim));
                *column.select_nth_unstable_by((n - 1) / 2, f64::total_cmp).1
            })
            .collect(),
    )
}
