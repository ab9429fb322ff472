//! What every strategy puts into a [`Snapshot`](strider_core::snapshot::Snapshot) the same way: the map's layers, goal sites at
//! the map's elevation, and the spatial goals.

use super::body::Body;
use strider_core::snapshot::{GoalKind, GoalSet, Layers};
use strider_core::{Cell, CellRect, Point2, Point3};
use strider_map::{ElevationMap, SpatialGoal};

/// The map's layers over its known part (an empty rectangle before anything is mapped, so a
/// recorder still knows the layers were due), without model layers.
pub fn map_layers(map: &ElevationMap) -> Layers {
    let rect = map
        .known_bounds()
        .unwrap_or(CellRect::new(Cell::new(0, 0), 0, 0));
    Layers {
        rect,
        elevation: map.elevation_raster(rect),
        elevation_variance: map.variance_raster(rect),
        color: map
            .color_raster(rect)
            .into_iter()
            .map(|c| c.map_or([0, 0, 0], |c| c.0))
            .collect(),
        observed: map.observed_raster(rect),
        passability: map
            .passability_raster(rect)
            .into_iter()
            .map(|p| p as u8)
            .collect(),
        models: Vec::new(),
    }
}

/// The centre of `cell` at the map's elevation there (0 where unknown), for snapshots.
pub fn site(body: &Body, cell: Cell) -> Point3 {
    let map = body.map();
    with_elevation(cell.center(map.cell_size()), map.elevation(cell))
}

/// The point `p` at the map's elevation of its cell (0 where unknown), for snapshots.
pub fn site_at(body: &Body, p: Point2) -> Point3 {
    let map = body.map();
    with_elevation(p, map.cell_at(p.x, p.y).and_then(|c| map.elevation(c)))
}

fn with_elevation(p: Point2, z: Option<f32>) -> Point3 {
    let z = z.filter(|z| z.is_finite()).unwrap_or(0.0) as f64;
    Point3::new(p.x, p.y, z)
}

/// The goal set `spatial_goals` of a strategy's spatial goals.
pub fn spatial_goal_set(body: &Body, goals: &[SpatialGoal]) -> GoalSet {
    GoalSet::new(
        "spatial_goals",
        GoalKind::Spatial,
        goals.iter().map(|g| site(body, g.cell)).collect(),
    )
}
