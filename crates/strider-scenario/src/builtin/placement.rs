//! Placing start and waypoints on a generated world and checking a layout's promises, all on the
//! ground-truth admissibility mask (`World::gt_admissible`).

use rand::{RngExt, rngs::ChaCha8Rng};
use strider_core::Point2;

use strider_map::passability::{Passability, dense_admissible};

use crate::ground_truth::{flood_fill, nearest_in_mask};
use crate::model::World;

/// The centre of the `mask` cell nearest to `p`.
pub(crate) fn snap(world: &World, mask: &[bool], p: Point2) -> Option<Point2> {
    nearest_in_mask(world, mask, p).map(|k| world.cell_center(k))
}

/// `n` distinct centres of `mask` cells drawn uniformly, each at least `min_sep` from the
/// previous one.
pub(crate) fn sample_cells(
    world: &World,
    mask: &[bool],
    n: usize,
    min_sep: f64,
    rng: &mut ChaCha8Rng,
) -> Vec<Point2> {
    let cells: Vec<usize> = (0..mask.len()).filter(|&k| mask[k]).collect();
    let mut out: Vec<Point2> = Vec::with_capacity(n);
    if cells.is_empty() {
        return out;
    }
    let mut tries = 0;
    while out.len() < n && tries < 100 * n {
        tries += 1;
        let p = world.cell_center(cells[rng.random_range(0..cells.len())]);
        if out.iter().any(|q| q.dist(p) < 1e-9) || out.last().is_some_and(|q| q.dist(p) < min_sep) {
            continue;
        }
        out.push(p);
    }
    out
}

/// The `mask` cells 8-connected to the cell under `p` (`None` when `p` is off the world).
pub(crate) fn reach_from(world: &World, mask: &[bool], p: Point2) -> Option<Vec<bool>> {
    let k = world.index_at(p)?;
    Some(flood_fill(mask, world.width(), world.height(), k))
}

/// True when every `mask` cell is reachable from the cell under `p`.
pub(crate) fn connected_from(world: &World, mask: &[bool], p: Point2) -> bool {
    reach_from(world, mask, p).is_some_and(|reach| reach == mask)
}

/// True when the cell under `p` has a terrain in `set`.
pub(crate) fn on_terrain(world: &World, p: Point2, set: &[u8]) -> bool {
    world
        .index_at(p)
        .is_some_and(|k| set.contains(&world.terrain[k]))
}

/// True when the straight segment `a`–`b`, sampled at 101 points, touches a terrain in `set`.
pub(crate) fn crosses(world: &World, a: Point2, b: Point2, set: &[u8]) -> bool {
    (0..=100).any(|s| {
        let f = s as f64 / 100.0;
        let p = Point2::new(a.x + f * (b.x - a.x), a.y + f * (b.y - a.y));
        on_terrain(world, p, set)
    })
}

/// The `mask` cells whose terrain is in `set`.
pub(crate) fn restrict_to(world: &World, mask: &[bool], set: &[u8]) -> Vec<bool> {
    (0..mask.len())
        .map(|k| mask[k] && set.contains(&world.terrain[k]))
        .collect()
}

/// The `mask` cells where a footprint of radius `r_robot` touches no cell whose terrain is in
/// `set`: the admissibility rule (decision 4) with those terrains as obstacles.
pub(crate) fn footprint_clear_of(
    world: &World,
    mask: &[bool],
    set: &[u8],
    r_robot: f64,
) -> Vec<bool> {
    let pass: Vec<Passability> = world
        .terrain
        .iter()
        .map(|t| {
            if set.contains(t) {
                Passability::Impassable
            } else {
                Passability::Passable
            }
        })
        .collect();
    let clear = dense_admissible(
        &pass,
        world.width(),
        world.height(),
        r_robot,
        world.resolution,
    );
    clear.iter().zip(mask).map(|(&c, &m)| c && m).collect()
}
