//! A mission's state at one moment, as every strategy provides it: the map layers, each learned
//! model's costs and variances, the goals, the tour, the path and the robot. Recorders, live
//! views and language bindings read this, never a strategy's own types.

use crate::geom::{Point2, Point3};
use crate::grid::CellRect;
use crate::msg::{GaitId, PoseStamped};

/// One gait of the robot.
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(deny_unknown_fields)]
pub struct GaitSpec {
    /// Gait name (e.g. `fast`, `tall`).
    pub name: String,
    /// Its maximum speed on ideal terrain, m/s.
    pub v_max: f64,
}

/// The fastest of `gaits` (ties: the lowest index; 0 when there is none).
pub fn fastest_gait(gaits: &[GaitSpec]) -> GaitId {
    GaitId(
        (0..gaits.len())
            .max_by(|&a, &b| gaits[a].v_max.total_cmp(&gaits[b].v_max).then(b.cmp(&a)))
            .unwrap_or(0) as u8,
    )
}

/// What a goal set stands for.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize)]
pub enum GoalKind {
    /// Spatial goals: where the robot expects to see unmapped terrain.
    Spatial,
    /// Cost-model goals of model `model` (an index into [`Layers::models`]): where that model
    /// expects to learn.
    Cost {
        /// The model's index.
        model: usize,
    },
}

/// A named set of goal sites.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct GoalSet {
    /// Name (e.g. `spatial_goals`, `cost_goals_fast`).
    pub name: String,
    /// What the goals stand for.
    pub kind: GoalKind,
    /// Sites, world coordinates (z: the map's elevation there, 0 where unknown), m.
    pub sites: Vec<Point3>,
}

impl GoalSet {
    /// The goal set `name` of kind `kind` at `sites`.
    pub fn new(name: impl Into<String>, kind: GoalKind, sites: Vec<Point3>) -> Self {
        Self {
            name: name.into(),
            kind,
            sites,
        }
    }
}

/// What a learned cost measures, with what a judge needs to compute it from a terrain table.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(tag = "kind", rename_all = "snake_case")]
pub enum Quantity {
    /// The inverse-velocity cost c_high · tanh((v_max / v) / c_high) of a walk at speed v,
    /// v_max the fastest gait's top speed (1: as fast as the robot goes).
    InverseVelocity {
        /// The fastest gait's top speed, m/s.
        v_max: f64,
        /// The tanh bound.
        c_high: f64,
    },
    /// The variance of the body roll over a window of walking, rad².
    RollVariance,
    /// The force needed to push through an apparent obstacle, N.
    PushForce,
}

/// One learned cost model's layers over [`Layers::rect`], row-major; NaN where the model has
/// nothing to say.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct ModelLayer {
    /// Name (the gait's name for per-gait models).
    pub name: String,
    /// What the cost measures.
    pub quantity: Quantity,
    /// The gait the model is for, if it is per gait.
    pub gait: Option<GaitId>,
    /// Planning cost.
    pub cost: Vec<f32>,
    /// Its variance.
    pub variance: Vec<f32>,
    /// The cost measured in the cell.
    pub measured: Vec<f32>,
    /// The terrain class the planner gives each cell (Prágr22's planning assignment), −1 where
    /// the cell has none; `None` for models without terrain classes.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub classes: Option<Vec<i32>>,
}

impl ModelLayer {
    /// A model's layers over `cells` cells with nothing to say yet (NaN everywhere), for the
    /// model to fill in cell by cell.
    pub fn unknown(
        name: impl Into<String>,
        quantity: Quantity,
        gait: Option<GaitId>,
        cells: usize,
    ) -> Self {
        Self {
            name: name.into(),
            quantity,
            gait,
            cost: vec![f32::NAN; cells],
            variance: vec![f32::NAN; cells],
            measured: vec![f32::NAN; cells],
            classes: None,
        }
    }

    /// Whether each of its layers has one value per cell of a rectangle of `cells` cells.
    pub fn fits(&self, cells: usize) -> bool {
        self.cost.len() == cells
            && self.variance.len() == cells
            && self.measured.len() == cells
            && self.classes.as_ref().is_none_or(|c| c.len() == cells)
    }
}

/// The map and model layers over one rectangle of cells, row-major.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct Layers {
    /// The cells covered (of the snapshot's `cell_size`).
    pub rect: CellRect,
    /// Elevation, m (NaN: unknown).
    pub elevation: Vec<f32>,
    /// Elevation variance, m².
    pub elevation_variance: Vec<f32>,
    /// Colour (black where unknown).
    pub color: Vec<[u8; 3]>,
    /// Observed cells.
    pub observed: Vec<bool>,
    /// Passability: 0 unknown, 1 passable, 2 impassable.
    pub passability: Vec<u8>,
    /// The learned models.
    pub models: Vec<ModelLayer>,
}

impl Layers {
    /// Drops the model layers whose size does not fit [`Layers::rect`] (a strategy's mistake),
    /// so that a reader may index every layer by cell.
    pub fn drop_misfit_models(&mut self) {
        let n = self.rect.len();
        self.models.retain(|m| m.fits(n));
    }
}

/// A cost measured in one cell.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct MeasuredCost {
    /// Cell centre and elevation, m.
    pub at: Point3,
    /// The cost.
    pub cost: f64,
    /// The model it trains (an index into [`Layers::models`]).
    pub model: usize,
}

/// A mission's state at one moment (see the module docs).
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct Snapshot {
    /// Robot time, s.
    pub time_s: f64,
    /// The strategy's name.
    pub strategy: String,
    /// The map's cell size, m.
    pub cell_size: f64,
    /// The latest pose.
    pub robot: Option<PoseStamped>,
    /// The gait commanded.
    pub gait: Option<GaitId>,
    /// The path commanded, world waypoints.
    pub path: Vec<Point2>,
    /// The goals.
    pub goals: Vec<GoalSet>,
    /// The sites of the planned tour in visiting order (the goal pursued first).
    pub tour: Vec<Point3>,
    /// The map and model layers, when asked for (they cost a pass over the map).
    pub layers: Option<Layers>,
    /// The costs measured so far (when the layers were asked for).
    pub measured: Vec<MeasuredCost>,
}

impl Snapshot {
    /// The state at robot time `time_s` of the strategy `strategy` on a map of `cell_size`, with
    /// nothing in it yet.
    pub fn new(time_s: f64, strategy: impl Into<String>, cell_size: f64) -> Self {
        Self {
            time_s,
            strategy: strategy.into(),
            cell_size,
            robot: None,
            gait: None,
            path: Vec::new(),
            goals: Vec::new(),
            tour: Vec::new(),
            layers: None,
            measured: Vec::new(),
        }
    }

    /// Adds the goal set `name` of kind `kind` at `sites`.
    pub fn push_goals(&mut self, name: impl Into<String>, kind: GoalKind, sites: Vec<Point3>) {
        self.goals.push(GoalSet::new(name, kind, sites));
    }

    /// Adds a cost measured at `at` for model `model`.
    pub fn push_measured(&mut self, at: Point3, cost: f64, model: usize) {
        self.measured.push(MeasuredCost { at, cost, model });
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::grid::Cell;

    #[test]
    fn unknown_model_layers_fit_and_misfits_are_dropped() {
        let rect = CellRect::new(Cell::new(-1, 2), 3, 2);
        let fits = ModelLayer::unknown("fast", Quantity::RollVariance, Some(GaitId(1)), 6);
        assert!(fits.fits(rect.len()));
        assert!(fits.cost.iter().chain(&fits.variance).all(|v| v.is_nan()));
        let mut short = fits.clone();
        short.measured.pop();
        let mut layers = Layers {
            rect,
            elevation: vec![0.0; 6],
            elevation_variance: vec![0.0; 6],
            color: vec![[0; 3]; 6],
            observed: vec![true; 6],
            passability: vec![1; 6],
            models: vec![fits, short],
        };
        layers.drop_misfit_models();
        // (NaN layers never compare equal: compare sizes.)
        assert_eq!(layers.models.len(), 1);
        assert_eq!(layers.models[0].measured.len(), 6);
    }

    #[test]
    fn goals_and_measured_costs_are_added() {
        let mut snap = Snapshot::new(1.0, "s", 0.1);
        let at = Point3::new(1.0, 2.0, 0.5);
        snap.push_goals("cost_goals_fast", GoalKind::Cost { model: 0 }, vec![at]);
        snap.push_measured(at, 2.5, 0);
        assert_eq!(snap.goals[0].name, "cost_goals_fast");
        assert_eq!(snap.goals[0].sites, vec![at]);
        assert_eq!(
            snap.measured,
            vec![MeasuredCost {
                at,
                cost: 2.5,
                model: 0
            }]
        );
    }
}
