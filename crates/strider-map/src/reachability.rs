//! Cells reachable from the robot: an 8-connected flood fill over admissible cells (decision 4;
//! Prágr19 "reachable cells", Prágr22 candidates of Eq. 11).

use crate::map::ElevationMap;
use std::collections::VecDeque;
use strider_core::{Cell, CellRect};

/// The set of cells reachable from a start cell, as a bitmap over the map's known bounds.
/// Reusable: [`Reachability::recompute`] keeps the buffers.
#[derive(Clone, Debug)]
pub struct Reachability {
    rect: CellRect,
    start: Option<Cell>,
    reach: Vec<bool>,
    admissible: Vec<bool>,
    queue: VecDeque<usize>,
    count: usize,
    /// The revision of the map's admissibility changes that `admissible` matches, when it was
    /// read from the map by [`Reachability::follow`] or [`Reachability::recompute`].
    seen: Option<u64>,
}

impl Default for Reachability {
    fn default() -> Self {
        Self {
            rect: CellRect::new(Cell::default(), 0, 0),
            start: None,
            reach: Vec::new(),
            admissible: Vec::new(),
            queue: VecDeque::new(),
            count: 0,
            seen: None,
        }
    }
}

impl Reachability {
    /// The cells reachable from `start` over admissible cells (8-connected). The start cell
    /// itself is included whenever it is observed, even when not admissible (the robot may stand
    /// close to an obstacle); the fill continues only through admissible cells.
    pub fn compute(map: &ElevationMap, start: Cell) -> Self {
        let mut r = Self::default();
        r.recompute(map, start);
        r
    }

    /// The cells reachable from `start` over the cells of a caller's admissibility raster
    /// (`admissible`, row-major over `rect`) instead of the map's own layer: Prágr23 Eq. 4
    /// admits apparent obstacles that were learnt to be traversable. The start cell is included
    /// whenever it is observed, as in [`Reachability::compute`]. A raster of the wrong size
    /// gives an empty set.
    pub fn from_admissible(
        map: &ElevationMap,
        start: Cell,
        rect: CellRect,
        admissible: &[bool],
    ) -> Self {
        let mut r = Self {
            rect,
            start: Some(start),
            ..Self::default()
        };
        if admissible.len() == rect.len() {
            r.admissible = admissible.to_vec();
            r.fill(map, start);
        } else {
            r.admissible = vec![false; rect.len()];
            r.reach = vec![false; rect.len()];
        }
        r
    }

    /// Recomputes in place, reusing the buffers.
    pub fn recompute(&mut self, map: &ElevationMap, start: Cell) {
        self.rect = map.known_bounds().unwrap_or(CellRect::new(start, 0, 0));
        self.start = Some(start);
        map.admissible_layer()
            .read_rect(self.rect, &mut self.admissible);
        self.seen = Some(map.admissible_changes().revision());
        self.fill(map, start);
    }

    /// [`Reachability::recompute`] for a set that follows one map through its updates: the
    /// same cells, but when the known bounds and the start's component are unchanged it reads
    /// only the admissibility the map rewrote since the last call and grows the set from the
    /// cells that became admissible beside it. A reached cell that became inadmissible may
    /// split the set, and a new start may lie in another component: both start over.
    ///
    /// The caller passes the map this set was last computed from (the same map, changed only
    /// through its own methods); another map needs [`Reachability::recompute`].
    pub fn follow(&mut self, map: &ElevationMap, start: Cell) {
        let rect = map.known_bounds().unwrap_or(CellRect::new(start, 0, 0));
        let log = map.admissible_changes();
        let seen = self
            .seen
            .filter(|&s| s <= log.revision() && rect == self.rect)
            .filter(|_| self.same_component(start));
        let Some(seen) = seen else {
            return self.recompute(map, start);
        };
        let grown = self.apply_admissibility_changes(map, seen);
        self.seen = Some(log.revision());
        match grown {
            Some(seeds) => {
                self.start = Some(start);
                self.queue.extend(seeds);
                self.fill_from_queue();
            }
            None => self.recompute(map, start),
        }
    }

    /// True when the set computed from the last start is also the set of `start`: the same
    /// start, or both admissible with `start` reached (the component of an admissible start
    /// is the same from any of its cells).
    fn same_component(&self, start: Cell) -> bool {
        let (Some(old), Some(k)) = (self.start, self.rect.index(start)) else {
            return false;
        };
        let Some(o) = self.rect.index(old) else {
            return false;
        };
        if !self.reach[o] {
            return false;
        }
        old == start || (self.admissible[o] && self.admissible[k] && self.reach[k])
    }

    /// Reads the admissibility the map rewrote after revision `seen` into `admissible`: the
    /// cells that became admissible beside a reached cell (seeds of the fill), or `None` when
    /// a reached cell became inadmissible.
    fn apply_admissibility_changes(&mut self, map: &ElevationMap, seen: u64) -> Option<Vec<usize>> {
        let layer = map.admissible_layer();
        let mut added = Vec::new();
        let mut lost = false;
        // One tile read per changed block rather than a tile lookup per cell.
        let mut block_now = Vec::new();
        for block in map.admissible_changes().changed_since(seen) {
            let Some(r) = crate::rect::intersection(block, self.rect) else {
                continue;
            };
            layer.read_rect(r, &mut block_now);
            for (n, &now) in block_now.iter().enumerate() {
                let Some(k) = self.rect.index(r.cell(n)) else {
                    continue;
                };
                if now == self.admissible[k] {
                    continue;
                }
                self.admissible[k] = now;
                if self.reach[k] && !now {
                    lost = true;
                } else if now && !self.reach[k] {
                    added.push(k);
                }
            }
        }
        if lost {
            return None;
        }
        let (w, h) = (self.rect.width as usize, self.rect.height as usize);
        added.retain(|&k| self.touches_reached(k, w, h));
        Some(added)
    }

    /// True when an 8-neighbour of cell `k` is reached.
    fn touches_reached(&self, k: usize, w: usize, h: usize) -> bool {
        let (x, y) = (k % w, k / w);
        let (x0, x1) = (x.saturating_sub(1), (x + 1).min(w - 1));
        let (y0, y1) = (y.saturating_sub(1), (y + 1).min(h - 1));
        (y0..=y1).any(|yy| self.reach[yy * w + x0..=yy * w + x1].iter().any(|&r| r))
    }

    /// The flood fill from `start` over `self.admissible`, by row spans: each span of
    /// admissible cells is marked in one sweep and seeds the spans it touches (diagonals
    /// included) in the rows above and below. The same cells as a cell-by-cell search, with
    /// sequential memory access and no division per cell.
    fn fill(&mut self, map: &ElevationMap, start: Cell) {
        self.reach.clear();
        self.reach.resize(self.rect.len(), false);
        self.queue.clear();
        self.count = 0;
        let Some(s) = self.rect.index(start) else {
            return;
        };
        if !map.is_observed(start) {
            return;
        }
        let (w, h) = (self.rect.width as usize, self.rect.height as usize);
        let (sx, sy) = (s % w, s / w);
        if self.admissible[s] {
            self.queue.push_back(s);
        } else {
            // The start itself need not be admissible; the fill goes on from its neighbours.
            self.reach[s] = true;
            self.count = 1;
            self.seed_row(sx, sx, sy, -1, w, h);
            self.seed_row(sx, sx, sy, 1, w, h);
            self.seed_row(sx.saturating_sub(1), (sx + 1).min(w - 1), sy, 0, w, h);
        }
        self.fill_from_queue();
    }

    /// Fills the spans of admissible, unreached cells from the queued cells and every span
    /// they touch.
    fn fill_from_queue(&mut self) {
        let (w, h) = (self.rect.width as usize, self.rect.height as usize);
        while let Some(k) = self.queue.pop_back() {
            if self.reach[k] {
                continue;
            }
            let (x, y) = (k % w, k / w);
            let row = y * w;
            let mut x0 = x;
            while x0 > 0 && self.admissible[row + x0 - 1] && !self.reach[row + x0 - 1] {
                x0 -= 1;
            }
            let mut x1 = x;
            while x1 + 1 < w && self.admissible[row + x1 + 1] && !self.reach[row + x1 + 1] {
                x1 += 1;
            }
            self.reach[row + x0..=row + x1].fill(true);
            self.count += x1 - x0 + 1;
            self.seed_row(x0, x1, y, -1, w, h);
            self.seed_row(x0, x1, y, 1, w, h);
        }
    }

    /// Queues the first cell of every run of admissible, unreached cells in row `y + dy`
    /// between columns `x0 − 1` and `x1 + 1` (the 8-neighbours of the span `x0..=x1` of row
    /// `y`; `dy = 0` scans row `y` itself over `x0..=x1`).
    fn seed_row(&mut self, x0: usize, x1: usize, y: usize, dy: i64, w: usize, h: usize) {
        let ny = y as i64 + dy;
        if ny < 0 || ny >= h as i64 {
            return;
        }
        let row = ny as usize * w;
        let (from, to) = if dy == 0 {
            (x0, x1)
        } else {
            (x0.saturating_sub(1), (x1 + 1).min(w - 1))
        };
        let mut in_run = false;
        for x in from..=to {
            let k = row + x;
            let open = self.admissible[k] && !self.reach[k];
            if open && !in_run {
                self.queue.push_back(k);
            }
            in_run = open;
        }
    }

    /// The start cell of the last computation.
    pub fn start(&self) -> Option<Cell> {
        self.start
    }

    /// The rectangle the bitmap covers.
    pub fn rect(&self) -> CellRect {
        self.rect
    }

    /// True when `c` is reachable.
    #[inline]
    pub fn contains(&self, c: Cell) -> bool {
        self.rect.index(c).is_some_and(|k| self.reach[k])
    }

    /// True when `c` is reachable and admissible (a cell the robot's centre may be sent to).
    #[inline]
    pub fn is_goal_cell(&self, c: Cell) -> bool {
        self.rect
            .index(c)
            .is_some_and(|k| self.reach[k] && self.admissible[k])
    }

    /// The bitmap over [`Reachability::rect`], row-major.
    pub fn bitmap(&self) -> &[bool] {
        &self.reach
    }

    /// Which cells of [`Reachability::rect`] are admissible, row-major (a goal cell is
    /// reachable and admissible).
    pub fn admissible_bitmap(&self) -> &[bool] {
        &self.admissible
    }

    /// Number of reachable cells.
    pub fn count(&self) -> usize {
        self.count
    }

    /// The reachable cells in row-major order.
    pub fn cells(&self) -> impl Iterator<Item = Cell> + '_ {
        self.reach
            .iter()
            .enumerate()
            .filter(|&(_, &r)| r)
            .map(|(k, _)| self.rect.cell(k))
    }

    /// The reachable admissible cell nearest to `target` (Euclidean, ties in row-major order),
    /// optionally restricted by `accept`; `None` when there is none. Searches square rings
    /// outward from `target` and stops once no farther ring can hold a nearer cell.
    pub fn nearest_goal_cell(&self, target: Cell, accept: impl Fn(Cell) -> bool) -> Option<Cell> {
        let rect = self.rect;
        if rect.is_empty() {
            return None;
        }
        let ok = |c: Cell| {
            rect.index(c)
                .is_some_and(|k| self.reach[k] && self.admissible[k])
                && accept(c)
        };
        // The farthest ring that still meets the rectangle.
        let (x0, y0) = (rect.min.i as i64, rect.min.j as i64);
        let (x1, y1) = (x0 + rect.width as i64 - 1, y0 + rect.height as i64 - 1);
        let (tx, ty) = (target.i as i64, target.j as i64);
        let max_r = [tx - x0, tx - x1, ty - y0, ty - y1]
            .into_iter()
            .map(i64::abs)
            .max()
            .unwrap_or(0);
        let mut best: Option<(i64, usize, Cell)> = None;
        for r in 0..=max_r {
            if best.is_some_and(|(b, _, _)| r * r > b) {
                break;
            }
            // Ring r: rows ty ± r in full, columns tx ± r between them.
            let mut visit = |x: i64, y: i64| {
                if x < x0 || x > x1 || y < y0 || y > y1 {
                    return;
                }
                let c = Cell::new(x as i32, y as i32);
                if !ok(c) {
                    return;
                }
                let d2 = (x - tx).pow(2) + (y - ty).pow(2);
                let k = rect.index(c).unwrap_or(usize::MAX);
                if best.is_none_or(|(b, bk, _)| d2 < b || (d2 == b && k < bk)) {
                    best = Some((d2, k, c));
                }
            };
            if r == 0 {
                visit(tx, ty);
                continue;
            }
            for x in tx - r..=tx + r {
                visit(x, ty - r);
                visit(x, ty + r);
            }
            for y in ty - r + 1..ty + r {
                visit(tx - r, y);
                visit(tx + r, y);
            }
        }
        best.map(|(_, _, c)| c)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::params::MapParams;
    use crate::testing::{block, known};
    use strider_core::Rgb8;
    use strider_core::grid::NEIGHBOURS8;

    #[test]
    fn wall_splits_reachable_region() {
        let p = MapParams {
            cell_size: 0.1,
            tile_size: 4,
            r_robot: 0.0,
            rho_obstacle: 0.1,
            ..MapParams::default()
        };
        let mut m = ElevationMap::new(p);
        known(&mut m, block(0, 0, 10, 10), |c| {
            if c.i == 5 { 1.0 } else { 0.0 }
        });
        m.update_passability();
        let r = Reachability::compute(&m, Cell::new(1, 1));
        // Columns 4..=6 are impassable (the wall and the cells beside it).
        assert_eq!(r.count(), 4 * 10);
        assert!(r.contains(Cell::new(3, 9)));
        assert!(!r.contains(Cell::new(7, 1)));
        assert_eq!(
            r.nearest_goal_cell(Cell::new(8, 2), |_| true),
            Some(Cell::new(3, 2))
        );
        let r = Reachability::compute(&m, Cell::new(50, 50));
        assert_eq!(r.count(), 0);
    }

    /// The cells an 8-connected breadth-first search reaches over `adm` (w × h) from `s`,
    /// which is reached even when not admissible: the reference of the span fill.
    fn reached_by_search(adm: &[bool], w: usize, h: usize, s: usize) -> Vec<bool> {
        let mut reach = vec![false; adm.len()];
        reach[s] = true;
        let mut queue = VecDeque::from([s]);
        while let Some(k) = queue.pop_front() {
            let (x, y) = ((k % w) as i64, (k / w) as i64);
            for &(di, dj) in &NEIGHBOURS8 {
                let (nx, ny) = (x + di as i64, y + dj as i64);
                if nx < 0 || ny < 0 || nx >= w as i64 || ny >= h as i64 {
                    continue;
                }
                let nk = ny as usize * w + nx as usize;
                if adm[nk] && !reach[nk] {
                    reach[nk] = true;
                    queue.push_back(nk);
                }
            }
        }
        reach
    }

    proptest::proptest! {
        /// The span fill reaches the cells a cell-by-cell search reaches, from admissible and
        /// inadmissible starts, through diagonal gaps and around concave walls.
        #[test]
        fn span_fill_equals_a_breadth_first_search(
            adm in proptest::collection::vec(proptest::bool::weighted(0.6), 13 * 11),
            start in 0usize..13 * 11,
        ) {
            let (w, h) = (13usize, 11usize);
            let mut m = ElevationMap::new(MapParams { cell_size: 0.1, ..MapParams::default() });
            for k in 0..w * h {
                m.set_cell(Cell::new((k % w) as i32, (k / w) as i32), 0.0, 1e-4, Rgb8::default());
            }
            let rect = CellRect::new(Cell::new(0, 0), w as u32, h as u32);
            let start_cell = Cell::new((start % w) as i32, (start / w) as i32);
            let r = Reachability::from_admissible(&m, start_cell, rect, &adm);
            let want = reached_by_search(&adm, w, h, start);
            proptest::prop_assert_eq!(r.bitmap(), &want[..]);
            proptest::prop_assert_eq!(r.count(), want.iter().filter(|&&b| b).count());
        }

        /// A set that follows a map through edits (walls raised and removed, the known area
        /// grown, the start moved) equals the set computed afresh after each edit: the
        /// incremental growth, the restarts on a lost cell or a new component, and the
        /// admissibility read from the map's change log.
        #[test]
        fn following_a_map_equals_computing_afresh(
            edits in proptest::collection::vec(
                (proptest::collection::vec((0..24i32, 0..20i32, proptest::bool::weighted(0.5)), 1..12),
                 0..6usize, proptest::bool::weighted(0.15)),
                1..12,
            ),
            r_robot in proptest::sample::select(vec![0.0, 0.1, 0.25]),
        ) {
            let mut m = ElevationMap::new(MapParams {
                cell_size: 0.1,
                tile_size: 4,
                r_robot,
                rho_obstacle: 0.1,
                ..MapParams::default()
            });
            known(&mut m, block(0, 0, 16, 14), |_| 0.0);
            m.update_passability();
            let starts = [
                Cell::new(1, 1),
                Cell::new(2, 1),
                Cell::new(12, 10),
                Cell::new(8, 3),
                Cell::new(1, 1),
                Cell::new(20, 18),
            ];
            let mut followed = Reachability::default();
            for (cells, s, grow) in edits {
                for (i, j, wall) in cells {
                    // Cells beyond the first block grow the known bounds.
                    if grow || (i < 16 && j < 14) {
                        m.set_cell(Cell::new(i, j), if wall { 1.0 } else { 0.0 }, 1e-4, Rgb8::default());
                    }
                }
                m.update_passability();
                followed.follow(&m, starts[s]);
                let fresh = Reachability::compute(&m, starts[s]);
                proptest::prop_assert_eq!(followed.rect(), fresh.rect());
                proptest::prop_assert_eq!(followed.bitmap(), fresh.bitmap());
                proptest::prop_assert_eq!(followed.count(), fresh.count());
                for c in fresh.rect().cells() {
                    proptest::prop_assert_eq!(followed.is_goal_cell(c), fresh.is_goal_cell(c));
                }
            }
        }

        /// The ring search finds what a scan of every cell finds (nearest, ties row-major).
        #[test]
        fn ring_search_equals_a_full_scan(
            known in proptest::collection::vec(proptest::bool::weighted(0.7), 144),
            walls in proptest::collection::vec(proptest::bool::weighted(0.1), 144),
            ti in -6..18i32, tj in -6..18i32,
            parity in 0..3i32,
        ) {
            let mut m = ElevationMap::new(MapParams {
                cell_size: 0.1,
                tile_size: 4,
                r_robot: 0.0,
                rho_obstacle: 0.1,
                ..MapParams::default()
            });
            for k in 0..144 {
                if known[k] || k == 0 {
                    let z = if walls[k] && k != 0 { 1.0 } else { 0.0 };
                    m.set_cell(Cell::new(k as i32 % 12, k as i32 / 12), z, 1e-4, Rgb8::default());
                }
            }
            m.update_passability();
            let r = Reachability::compute(&m, Cell::new(0, 0));
            let accept = |c: Cell| (c.i + c.j).rem_euclid(3) != parity;
            let target = Cell::new(ti, tj);
            let mut brute: Option<(i64, Cell)> = None;
            for c in r.rect().cells() {
                if r.is_goal_cell(c) && accept(c) {
                    let d2 = ((c.i - ti) as i64).pow(2) + ((c.j - tj) as i64).pow(2);
                    if brute.is_none_or(|(b, _)| d2 < b) {
                        brute = Some((d2, c));
                    }
                }
            }
            proptest::prop_assert_eq!(r.nearest_goal_cell(target, accept), brute.map(|b| b.1));
        }
    }
}
