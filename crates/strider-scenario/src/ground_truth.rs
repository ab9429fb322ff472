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
    let (w, h) = (world.width() as i64, world.height() as i64);
    if w == 0 || h == 0 || !(p.x.is_finite() && p.y.is_finite()) {
        return None;
    }
    // Search square rings around the cell nearest to `p` (clamped into the world) outwards; a
    // ring r cells out is at least (r - 1) cells away, so the search stops once that exceeds
    // the best distance found.
    let res = world.resolution;
    let o = world.cell_center(0);
    let ci = (((p.x - o.x) / res).round() as i64).clamp(0, w - 1);
    let cj = (((p.y - o.y) / res).round() as i64).clamp(0, h - 1);
    let mut best: Option<(usize, f64)> = None;
    for r in 0..w.max(h) {
        if best.is_some_and(|(_, d)| (r as f64 - 1.0) * res > d) {
            break;
        }
        for (i, j) in ring(ci, cj, r) {
            if i < 0 || j < 0 || i >= w || j >= h {
                continue;
            }
            let k = (j * w + i) as usize;
            if !mask[k] {
                continue;
            }
            let d = world.cell_center(k).dist(p);
            if best.is_none_or(|(bk, bd)| d < bd || (d == bd && k < bk)) {
                best = Some((k, d));
            }
        }
    }
    best.map(|(k, _)| k)
}

/// The cells at Chebyshev distance `r` from (ci, cj).
fn ring(ci: i64, cj: i64, r: i64) -> impl Iterator<Item = (i64, i64)> {
    let side = (-r..=r).flat_map(move |d| [(ci + d, cj - r), (ci + d, cj + r)]);
    let ends = (-r + 1..r).flat_map(move |d| [(ci - r, cj + d), (ci + r, cj + d)]);
    let centre = (r == 0).then_some((ci, cj));
    centre
        .into_iter()
        .chain(side.filter(move |_| r > 0))
        .chain(ends)
}

/// True when `p` lies on a cell that is set in `mask`.
pub fn point_in_mask(world: &World, mask: &[bool], p: Point2) -> bool {
    world.index_at(p).is_some_and(|k| mask[k])
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;
    use strider_core::{Cell, CellRect, Rgb8};

    fn world(w: u32, h: u32, origin: (i32, i32)) -> World {
        let n = (w * h) as usize;
        World {
            resolution: 0.1,
            rect: CellRect::new(Cell::new(origin.0, origin.1), w, h),
            elevation: vec![0.0; n],
            color: vec![Rgb8::new(0, 0, 0); n],
            terrain: vec![0; n],
            terrains: Vec::new(),
        }
    }

    /// The nearest cell by brute force, ties to the lower index.
    fn brute(world: &World, mask: &[bool], p: Point2) -> Option<usize> {
        let mut best: Option<(usize, f64)> = None;
        for (k, _) in mask.iter().enumerate().filter(|(_, m)| **m) {
            let d = world.cell_center(k).dist(p);
            if best.is_none_or(|(_, bd)| d < bd) {
                best = Some((k, d));
            }
        }
        best.map(|(k, _)| k)
    }

    proptest! {
        #[test]
        fn the_ring_search_finds_the_nearest_mask_cell(
            w in 1u32..30, h in 1u32..30, origin in (-20i32..20, -20i32..20),
            bits in proptest::collection::vec(any::<u8>(), 900),
            x in -8.0f64..8.0, y in -8.0f64..8.0,
        ) {
            let wd = world(w, h, origin);
            let mask: Vec<bool> = (0..(w * h) as usize).map(|k| bits[k] < 20).collect();
            let p = Point2::new(x, y);
            let (a, b) = (nearest_in_mask(&wd, &mask, p), brute(&wd, &mask, p));
            // Equal distances may pick different cells; the distance must be the same.
            let d = |k: Option<usize>| k.map(|k| wd.cell_center(k).dist(p));
            prop_assert_eq!(a.is_some(), b.is_some());
            if let (Some(da), Some(db)) = (d(a), d(b)) {
                prop_assert!((da - db).abs() < 1e-12, "{} vs {}", da, db);
            }
        }
    }
}
