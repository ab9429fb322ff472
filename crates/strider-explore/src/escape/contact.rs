//! Bumper contacts with apparent obstacles: the corridor of cells the bumper touches, and one
//! contact from its first touch until the bumper has been quiet.

use super::force_predictor::ForcePrediction;
use super::haptic::HapticModel;
use super::log::ContactEvent;
use super::view::{ObstacleState, TravView, is_proud};
use std::collections::BTreeSet;
use strider_core::{Cell, Pose2};
use strider_map::ElevationMap;

/// Apparent obstacle cells in the bumper corridor: cells whose centre lies ahead of the robot
/// centre by at most `reach` and within `half_width` of its heading line, nearest first, keeping
/// only those within two cells of the nearest (the face the bumper touches).
pub fn corridor_cells(
    map: &ElevationMap,
    pose: Pose2,
    reach: f64,
    half_width: f64,
    t_trav: f64,
) -> Vec<(Cell, f64)> {
    let d = map.cell_size();
    let (s, c) = pose.yaw.sin_cos();
    let r = reach.max(half_width) + d;
    let (Some(lo), Some(hi)) = (
        Cell::containing(pose.x - r, pose.y - r, d),
        Cell::containing(pose.x + r, pose.y + r, d),
    ) else {
        return Vec::new();
    };
    let mut out = Vec::new();
    for j in lo.j..=hi.j {
        for i in lo.i..=hi.i {
            let cell = Cell::new(i, j);
            let p = cell.center(d);
            let (dx, dy) = (p.x - pose.x, p.y - pose.y);
            let along = dx * c + dy * s;
            let lat = (-dx * s + dy * c).abs();
            if along >= -d && along <= reach && lat <= half_width && is_proud(map, cell, t_trav) {
                out.push((cell, along));
            }
        }
    }
    out.sort_by(|a, b| a.1.total_cmp(&b.1));
    if let Some(&(_, first)) = out.first() {
        out.retain(|&(_, a)| a <= first + 2.0 * d);
    }
    out
}

/// An open bumper contact.
pub(super) struct ContactAcc {
    t_start: f64,
    /// Time of the latest touch, s.
    pub(super) last: f64,
    cells: BTreeSet<(i32, i32)>,
    /// What the robot believed of each touched cell before touching it.
    predicted: Vec<ForcePrediction>,
    /// Some touched cell was predicted traversable.
    predicted_traversable: bool,
}

impl ContactAcc {
    /// A contact that starts at `stamp`.
    pub(super) fn new(stamp: f64) -> Self {
        Self {
            t_start: stamp,
            last: stamp,
            cells: BTreeSet::new(),
            predicted: Vec::new(),
            predicted_traversable: false,
        }
    }

    /// The bumper touched `cells` at `stamp`; a cell touched for the first time adds what
    /// `view` predicted of it (traversable when the mean force is at most `f_trav`).
    pub(super) fn touch(
        &mut self,
        stamp: f64,
        cells: &[(Cell, f64)],
        view: Option<&TravView>,
        f_trav: f64,
    ) {
        self.last = stamp;
        for &(c, _) in cells {
            if self.cells.insert((c.i, c.j))
                && let Some(ObstacleState::Predicted(fp)) = view.and_then(|v| v.obstacle(c))
            {
                self.predicted.push(fp);
                self.predicted_traversable |= fp.mean <= f_trav;
            }
        }
    }

    /// The contact's record, times relative to `t0`: the touched cells' centroid and mean
    /// fused force, the mean prediction before the contact, and whether the contact
    /// contradicted a prediction of "traversable" (a force above `f_trav`).
    pub(super) fn close(
        self,
        haptic: &HapticModel,
        cell_size: f64,
        t0: f64,
        f_trav: f64,
    ) -> ContactEvent {
        let cells: Vec<Cell> = self.cells.iter().map(|&(i, j)| Cell::new(i, j)).collect();
        let n = cells.len().max(1) as f64;
        let (mut x, mut y, mut f) = (0.0, 0.0, 0.0);
        for c in &cells {
            let p = c.center(cell_size);
            x += p.x / n;
            y += p.y / n;
            f += haptic.get(*c).map_or(0.0, |h| h.force) / n;
        }
        let predicted = (!self.predicted.is_empty()).then(|| {
            let m = self.predicted.len() as f64;
            ForcePrediction {
                mean: self.predicted.iter().map(|p| p.mean).sum::<f64>() / m,
                variance: self.predicted.iter().map(|p| p.variance).sum::<f64>() / m,
                entropy: self.predicted.iter().map(|p| p.entropy).sum::<f64>() / m,
            }
        });
        ContactEvent {
            t_start: self.t_start - t0,
            t_end: self.last - t0,
            x,
            y,
            cells: cells.len(),
            force: f,
            predicted,
            corrected: self.predicted_traversable && f > f_trav,
        }
    }
}
