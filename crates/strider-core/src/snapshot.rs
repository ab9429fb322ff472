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

/// What a learned cost measures, with what a judge needs to compute it from a terrain table.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
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
