//! Face bounds (see "Face bounds" in the module docs of `fusion`): how high a kept return on a
//! sensor-facing cell edge must be to count as a lower bound of a wall's top.

use super::scratch::refill;
use crate::map::ElevationMap;
use strider_core::{Cell, CellRect};

/// Neighbour offsets across the cell edges a return can face the sensor on: −x, +x, −y, +y.
const FACING: [(i32, i32); 4] = [(-1, 0), (1, 0), (0, -1), (0, 1)];

impl ElevationMap {
    /// Fills `bound_floor` for every cell whose kept return sits on its sensor-facing edge, from
    /// the map as it was before this scan (so the spilled face returns of this scan in the
    /// neighbour, which ray carving is yet to remove, do not hide the step).
    pub(super) fn face_bound_floors(&mut self, rect: CellRect) {
        let gate = self.params.mahalanobis_gate as f32;
        let s = &mut self.scratch;
        refill(&mut s.bound_floor, rect.len(), f32::INFINITY);
        for (k, &bits) in s.kept.facing.iter().enumerate() {
            if bits == 0 || s.kept.z[k] == f32::NEG_INFINITY {
                continue;
            }
            let c = rect.cell(k);
            for (f, (di, dj)) in FACING.iter().enumerate() {
                let nb = Cell::new(c.i + di, c.j + dj);
                if bits & (1 << f) == 0 || !self.observed.get(nb).unwrap_or(false) {
                    continue;
                }
                if let (Some(z), Some(var)) = (self.elevation.get(nb), self.variance.get(nb)) {
                    let floor = &mut s.bound_floor[k];
                    *floor = floor.min(z + gate * var.max(0.0).sqrt());
                }
            }
        }
    }
}
