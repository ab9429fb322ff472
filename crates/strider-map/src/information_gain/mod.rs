//! Spatial information gain of Prágr22 §4.2 (decision 5).
//!
//! * Eq. 10: I_cell(ν') = (k(ν') + 1) / 9 for an unknown cell ν', k = number of unknown cells in
//!   its 8-neighbourhood.
//! * Eq. 11: I_model(ν) = Σ over unknown ν' in δ(r_sensor, ν) with observable(ν, ν') of
//!   I_cell(ν').
//!
//! Eq. 11 is evaluated only on candidate cells: observed, admissible, reachable from the robot,
//! on the `info_gain_stride` lattice, and with an unknown cell within r_sensor (a summed-area
//! table of the unknown mask rejects the others in O(1)). "Unknown" means unobserved *and*
//! inside the exploration bounds (when given); candidates outside the bounds are dropped. All
//! work runs on a dense view of the known area grown by r_sensor, in parallel over candidates.
//!
//! The parts, in reading order:
//!
//! * `candidates`: the cells Eq. 11 is evaluated on and the result, [`InfoGain`];
//! * `disc`: the sensor disc with each offset's direction bins and shadow geometry;
//! * `sight`: the sight lines from one candidate and the tests of a cell against them;
//! * `view`: the dense view (Eq. 10) and Eq. 11 afresh at one candidate;
//! * `delta`: Eq. 11 updated from the cells that changed;
//! * `cache`: [`GainCache`], which keeps Eq. 11 up to date between calls.

mod bits;
mod cache;
mod candidates;
mod delta;
mod disc;
mod sight;
mod view;

pub use cache::GainCache;
pub use candidates::InfoGain;

use crate::map::ElevationMap;
use crate::reachability::Reachability;
use crate::rect::{self, WorldRect};
use candidates::{candidates, view_rect};
use disc::DiscTable;
use rayon::prelude::*;
use strider_core::{Cell, CellRect};
use view::{GainView, Scratch};

/// I_cell(ν') (Eq. 10): (k + 1) / 9 for an unknown cell inside `bounds`, 0 otherwise.
pub fn cell_information(map: &ElevationMap, c: Cell, bounds: Option<&WorldRect>) -> f64 {
    let v = GainView::new(map, rect::expand(CellRect::new(c, 1, 1), 1), bounds);
    v.icount[v.rect.index(c).unwrap_or(0)] as f64 / 9.0
}

/// I_model(ν) (Eq. 11) at one observed cell, without the candidate filter. 0 for an unknown
/// cell.
pub fn model_information(map: &ElevationMap, c: Cell, bounds: Option<&WorldRect>) -> f64 {
    let p = map.params();
    let d = map.cell_size();
    let view = GainView::new(map, view_rect(map, CellRect::new(c, 1, 1)), bounds);
    view.model_count(c, &DiscTable::new(p.r_sensor, d), p.sensor_height, d) as f64 / 9.0
}

/// I_model (Eq. 11) on every candidate cell: observed, admissible, reachable (`reach`), on the
/// `info_gain_stride` lattice, inside `bounds`, with an unknown cell within r_sensor. Runs in
/// parallel over candidates; the result is deterministic. [`GainCache`] gives the same result
/// incrementally.
pub fn information_gain(
    map: &ElevationMap,
    reach: &Reachability,
    bounds: Option<&WorldRect>,
) -> InfoGain {
    let Some(known) = map.known_bounds() else {
        return InfoGain::default();
    };
    let p = map.params();
    let d = map.cell_size();
    let candidates = candidates(map, reach, bounds);
    let view = GainView::new(map, view_rect(map, known), bounds);
    let disc = DiscTable::new(p.r_sensor, d);
    let counts: Vec<u32> = candidates
        .par_iter()
        .map_init(Scratch::default, |s, &c| {
            view.model_count_with(c, &disc, p.sensor_height, d, s, None)
        })
        .collect();
    InfoGain::from_counts(candidates, counts)
}

#[cfg(test)]
mod tests;
