//! Ground-truth queries over a world's admissibility mask that tests, generators and the CLI
//! share: 8-connected flood fill and nearest admissible cell. (The passability rule itself lives
//! in `strider_map::passability`; see [`crate::World::gt_admissible`].)

use strider_core::Point2;

use crate::model::World;

/// Cells 8-connected to `start` within `mask` (`width × height`, row-major). Empty (all false)
/// when `start` is out of range or not in the mask.
pub fn flood_fill(mask: &[bool], width: usize, height: usize, start: usize) -> Vec<bool> {
    let mut seen = vec![false; mask.len()];
    if start >= mask.len() || !mask[start] || mask.len() != width * height {
        return seen;
    }
    let mut stack = vec![start];
    seen[start] = true;
    while let Some(k) = stack.pop() {
        let (x, y) = ((k % width) as i64, (k / width) as i64);
        for dy in -1..=1i64 {
            for dx in -1..=1i64 {
                let (nx, ny) = (x + dx, y + dy);
                if nx < 0 || ny < 0 || nx >= width as i64 || ny >= height as i64 {
                    continue;
                }
                let n = ny as usize * width + nx as usize;
                if mask[n] && !seen[n] {
                    seen[n] = true;
                    stack.push(n);
                }
            }
        }
    }
    seen
}

/// Layer index of the `mask` cell whose centre is nearest to `p` (ties: lowest index), or
/// `None` when the mask is empty.
pub fn nearest_in_mask(world: &World, mask: &[bool], p: Point2) -> Option<usize> {
    let mut best: Option<(usize, f64)> = None;
    for (k, _) in mask.iter().enumerate().filter(|(_, m)| **m) {
        let d = world.cell_center(k).dist(p);
        if best.is_none_or(|(_, bd)| d < bd) {
            best = Some((k, d));
        }
    }
    best.map(|(k, _)| k)
}

/// True when `p` lies on a cell that is set in `mask`.
pub fn point_in_mask(world: &World, mask: &[bool], p: Point2) -> bool {
    world.index_at(p).is_some_and(|k| mask[k])
}
