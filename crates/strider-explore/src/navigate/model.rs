//! The model of Nardi19 Alg. 1 over the grid: the average filter of every drive so far, the
//! mixture fitted to the visited cells (lines 5–11), its prediction where the robot may be,
//! and the paths planned on it with the rectified lower confidence bound (line 3).

use super::drive::{CellAcc, cell_value, training_set};
use super::map::NavigationMap;
use super::params::{ModelKind, NavigateError, NavigateParams, Objective};
use strider_core::Cell;
use strider_learn::mixture::{FieldPrediction, MixtureModel, MixtureParams, TrainingSet};
use strider_plan::grid::Dijkstra;
use strider_plan::grid::lcb::{LcbParams, lcb_grid, lcb_path};

/// The model's prediction over the grid, single precision to keep per-run copies small.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct ModelField {
    /// μ per cell, row-major (NaN where the robot may not be).
    pub mean: Vec<f32>,
    /// σ per cell (latent, Eq. 3), row-major (NaN where the robot may not be).
    pub std: Vec<f32>,
}

/// The model, its training data and its prediction over one grid map.
pub(super) struct GridModel<'a> {
    map: &'a NavigationMap,
    objective: Objective,
    mixture: MixtureParams,
    /// Gating features of every cell, `gate_dim` per cell.
    gate_all: Vec<f64>,
    gate_dim: usize,
    /// The cells the model is predicted on (where the robot may be), their positions and
    /// gating features.
    query: Vec<usize>,
    query_pos: Vec<f64>,
    query_gate: Vec<f64>,
    /// The average filter of every drive so far.
    pub(super) acc: Vec<CellAcc>,
    /// μ and σ per cell (NaN where the robot may not be).
    mean: Vec<f64>,
    std: Vec<f64>,
    model: Option<MixtureModel>,
    pred: FieldPrediction,
}

impl<'a> GridModel<'a> {
    /// The prior over `map`: μ and σ of `params` wherever the robot may be.
    pub(super) fn new(
        map: &'a NavigationMap,
        params: &NavigateParams,
    ) -> Result<Self, NavigateError> {
        let (gate_all, gate_dim) = map.gate_features(params.model)?;
        // The model is predicted where the robot may be (the planner reads nothing else); the
        // other cells keep NaN.
        let query: Vec<usize> = (0..map.rect.len()).filter(|&k| map.admissible[k]).collect();
        let query_pos: Vec<f64> = query
            .iter()
            .flat_map(|&k| {
                let p = map.rect.cell(k).center(map.cell_size);
                [p.x, p.y]
            })
            .collect();
        let query_gate = gather(&gate_all, gate_dim, &query);
        let mut mixture = params.mixture.clone();
        if params.model == ModelKind::SingleGp {
            mixture.max_components = 1;
        }
        let n = map.rect.len();
        let mut mean = vec![f64::NAN; n];
        let mut std = vec![f64::NAN; n];
        for &k in &query {
            mean[k] = params.prior_mean;
            std[k] = params.prior_std;
        }
        Ok(Self {
            map,
            objective: params.objective,
            mixture,
            gate_all,
            gate_dim,
            query,
            query_pos,
            query_gate,
            acc: vec![CellAcc::default(); n],
            mean,
            std,
            model: None,
            pred: FieldPrediction::default(),
        })
    }

    /// Line 3: the cheapest path between consecutive task cells under the rectified lower
    /// confidence bound of the current model.
    pub(super) fn plan(
        &self,
        dij: &mut Dijkstra,
        cells: &[Cell],
        lcb: &LcbParams,
    ) -> Result<Vec<Vec<Cell>>, NavigateError> {
        let map = self.map;
        let grid = lcb_grid(
            map.rect,
            map.cell_size,
            &self.mean,
            &self.std,
            &map.admissible,
            lcb,
        )?;
        let mut planned = Vec::with_capacity(cells.len() - 1);
        for (s, w) in cells.windows(2).enumerate() {
            let (path, _) = lcb_path(dij, &grid, w[0], w[1])?
                .ok_or(NavigateError::Unreachable { from: s, to: s + 1 })?;
            planned.push(path);
        }
        Ok(planned)
    }

    /// The planned cells without an observation yet.
    pub(super) fn unvisited(&self, planned: &[Vec<Cell>]) -> usize {
        let map = self.map;
        let mut seen: Vec<usize> = planned
            .iter()
            .flatten()
            .filter_map(|c| map.rect.index(*c))
            .filter(|&k| cell_value(self.objective, &self.acc[k], map.cell_size).is_none())
            .collect();
        seen.sort_unstable();
        seen.dedup();
        seen.len()
    }

    /// Lines 5–11: the mixture refitted on every visited cell (warm-started from the previous
    /// fit) and predicted over the grid. Returns the visited cells and the mixture's centroids.
    pub(super) fn update(&mut self) -> Result<(usize, Vec<f64>), NavigateError> {
        let (idx, pos, y) = training_set(self.map, self.objective, &self.acc);
        if y.is_empty() {
            return Ok((0, Vec::new()));
        }
        let gate_train = gather(&self.gate_all, self.gate_dim, &idx);
        let train = TrainingSet {
            positions: &pos,
            y: &y,
            gate_features: &gate_train,
            gate_dim: self.gate_dim,
        };
        let m = MixtureModel::fit(&train, &self.mixture, self.model.as_ref())?;
        m.predict(&self.query_pos, &self.query_gate, &mut self.pred)?;
        for (j, &k) in self.query.iter().enumerate() {
            self.mean[k] = self.pred.mean[j];
            self.std[k] = self.pred.variance[j].max(0.0).sqrt();
        }
        let centroids = m.components().iter().map(|c| c.centroid).collect();
        self.model = Some(m);
        Ok((y.len(), centroids))
    }

    /// The current prediction.
    pub(super) fn field(&self) -> ModelField {
        ModelField {
            mean: self.mean.iter().map(|&v| v as f32).collect(),
            std: self.std.iter().map(|&v| v as f32).collect(),
        }
    }

    /// The visited cells with their averaged observation, ascending, and the final model.
    pub(super) fn finish(self) -> (Vec<(usize, f64)>, Option<MixtureModel>) {
        let (idx, _, y) = training_set(self.map, self.objective, &self.acc);
        (idx.into_iter().zip(y).collect(), self.model)
    }
}

/// The `dim` features of each of `cells` from the row-major `features`.
fn gather(features: &[f64], dim: usize, cells: &[usize]) -> Vec<f64> {
    cells
        .iter()
        .flat_map(|&k| features[k * dim..(k + 1) * dim].iter().copied())
        .collect()
}
