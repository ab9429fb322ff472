//! Cost-grid transforms used before planning (Prágr22 §4.3, decisions 4, 21, 22):
//!
//! * [`best_gait`] — Eq. 13, ĉ(ν) = min_g ĉ_{C^g}(ν), with the arg-min gait per cell;
//! * [`distance_transform`] — decision 21, ĉ'(ν) = max(ĉ(ν), max_ν' [ĉ(ν') − c_loss·‖ν − ν'‖]),
//!   discouraging paths near terrain boundaries where gait changes are likely;
//! * [`footprint_max`] — Eq. 12, the maximum over the robot's disc footprint δ(r_robot, ν);
//! * [`choose_gait`] — Alg. 4 line 6, argmin_g max_{ν' ∈ δ(r_robot, ν)} ĉ_{C^g}(ν');
//! * [`planning_grid`] — the chain of decision 21: distance transform, then footprint max.
//!
//! Inadmissible cells (`+∞`) stay inadmissible through the distance transform and are not cone
//! sources (an infinite cone would swamp the whole grid). Through the footprint max an
//! inadmissible cell makes every cell within r_robot inadmissible: this is exactly the
//! configuration-space inflation of decision 4. Cells outside the grid are ignored (unknown).

use super::cost_grid::{CostGrid, GridError};
use rayon::prelude::*;
use strider_core::Cell;
use strider_core::grid::disc_offsets;

/// Result of Eq. 13: the best-gait cost grid and, per cell, the index of the gait achieving it
/// (`None` where every gait is inadmissible). Ties go to the lowest gait index.
#[derive(Clone, Debug, PartialEq)]
pub struct BestGait {
    /// ĉ(ν) = min_g ĉ_{C^g}(ν).
    pub cost: CostGrid,
    /// Row-major arg-min gait index.
    pub gait: Vec<Option<u16>>,
}

/// Rows per task of the transforms' per-row parallel passes.
const ROWS_PER_TASK: usize = 32;

fn check_shapes(grids: &[CostGrid]) -> Result<&CostGrid, GridError> {
    let first = grids.first().ok_or(GridError::Empty)?;
    if grids.iter().any(|g| !g.same_shape(first)) {
        return Err(GridError::ShapeMismatch);
    }
    Ok(first)
}

/// Eq. 13: per-cell minimum (and arg-min) over per-gait cost grids, which must share rectangle
/// and cell size. At most `u16::MAX` gaits.
pub fn best_gait(grids: &[CostGrid]) -> Result<BestGait, GridError> {
    let first = check_shapes(grids)?;
    if grids.len() > u16::MAX as usize {
        return Err(GridError::BadParameter {
            name: "gait count",
            value: grids.len() as f64,
        });
    }
    let n = first.len();
    let mut cost = vec![f32::INFINITY; n];
    let mut gait = vec![None; n];
    // Rows of cells side by side: each cell's minimum is its own.
    let chunk = first.rect().width.max(1) as usize * ROWS_PER_TASK;
    cost.par_chunks_mut(chunk)
        .zip(gait.par_chunks_mut(chunk))
        .enumerate()
        .for_each(|(b, (cost, gait))| {
            let at = b * chunk;
            for (g, grid) in grids.iter().enumerate() {
                let costs = &grid.costs()[at..at + cost.len()];
                for ((best, arg), &c) in cost.iter_mut().zip(gait.iter_mut()).zip(costs) {
                    if c < *best {
                        *best = c;
                        *arg = Some(g as u16);
                    }
                }
            }
        });
    Ok(BestGait {
        cost: CostGrid::new(first.rect(), first.cell_size(), cost)?,
        gait,
    })
}

/// Decision 21: ĉ'(ν) = max(ĉ(ν), max_ν' [ĉ(ν') − c_loss·‖ν − ν'‖]) with ‖·‖ the Euclidean distance
/// between cell centres in metres, over admissible sources ν'. Exact.
///
/// **Method.** Every admissible cell ν' is a cone source of height ĉ(ν') and slope c_loss. A cone
/// can only raise cells within R = (ĉ(ν') − min ĉ)/c_loss of its apex (elsewhere it is below the
/// grid minimum), so each source is scattered over that disc only. Sources are processed in
/// decreasing cost order; a source whose current value already exceeds its own cost has been
/// raised by a higher source ν'' with ĉ(ν'') − c_loss‖ν' − ν''‖ > ĉ(ν'), and by the triangle
/// inequality ν'''s cone then lies above ν''s everywhere, so ν' is skipped. A source whose four
/// neighbours (those inside the grid) are all admissible with costs ≥ its own is skipped too: for
/// any other cell q, the neighbour one step towards q is strictly closer to q and at least as
/// high, so its cone is above ν''s at q (and at ν' itself, out already holds ĉ(ν')). This prunes
/// the interior of every plateau, e.g. the c_max band of unclassified cells, leaving only its
/// rim. The result equals the O(n²) definition; the cost is Σ over undominated sources of their
/// disc areas. (A Dijkstra-like
/// max-propagation over the 8-neighbourhood would give octile, not Euclidean, distances and
/// overestimate the raise along off-axis directions, hence this exact scatter.)
///
/// `c_loss = 0` raises every admissible cell to the grid's maximum finite cost.
pub fn distance_transform(grid: &CostGrid, c_loss: f64) -> Result<CostGrid, GridError> {
    if !(c_loss.is_finite() && c_loss >= 0.0) {
        return Err(GridError::BadParameter {
            name: "c_loss",
            value: c_loss,
        });
    }
    let cost = grid.costs();
    let rect = grid.rect();
    let (w, h) = (rect.width as i64, rect.height as i64);
    let c_min = grid.min_cost() as f64;
    if c_loss == 0.0 {
        let c_max = cost
            .iter()
            .copied()
            .filter(|c| c.is_finite())
            .fold(f32::NEG_INFINITY, f32::max);
        let out = cost
            .iter()
            .map(|&c| if c.is_finite() { c_max } else { c })
            .collect();
        return CostGrid::new(rect, grid.cell_size(), out);
    }
    let slope = c_loss * grid.cell_size(); // per cell
    let mut out: Vec<f64> = cost.par_iter().map(|&c| c as f64).collect();
    let covered = |i: i64, j: i64, cs: f64| {
        // A missing neighbour is never the step towards an in-grid cell.
        i < 0 || i >= w || j < 0 || j >= h || {
            let c = cost[(j * w + i) as usize];
            c.is_finite() && c as f64 >= cs
        }
    };
    // The sources worth scattering, before sorting them: cones that can raise something, off
    // plateau interiors (both tests read only the input, so the order of the rest is as if
    // every cell were sorted).
    let mut order: Vec<u32> = (0..cost.len() as u32)
        .into_par_iter()
        .filter(|&k| {
            let cs = cost[k as usize] as f64;
            if !cs.is_finite() || cs <= c_min {
                return false;
            }
            let (si, sj) = ((k as i64) % w, (k as i64) / w);
            // A plateau interior: its neighbours' cones cover its own.
            !(covered(si - 1, sj, cs)
                && covered(si + 1, sj, cs)
                && covered(si, sj - 1, cs)
                && covered(si, sj + 1, cs))
        })
        .collect();
    // A total order (ties by index): the same sequence whichever sort and threads.
    order.par_sort_unstable_by(|&a, &b| {
        cost[b as usize]
            .total_cmp(&cost[a as usize])
            .then(a.cmp(&b))
    });
    let reach = order.first().map_or(0, |&s| {
        ((cost[s as usize] as f64 - c_min) / slope).floor() as i64
    });
    let cones = Cones {
        cost,
        order: &order,
        table: OffsetLengths::new(reach),
        slope,
        c_min,
        w,
    };
    // Bands of rows side by side, each scattering every cone that reaches it into its own
    // rows only: a cell's value is a maximum, whatever the order, so the result does not
    // depend on the bands.
    let rows_per_band = (h as usize)
        .div_ceil(rayon::current_num_threads().max(1))
        .max(1);
    out.par_chunks_mut((rows_per_band * w as usize).max(1))
        .enumerate()
        .for_each(|(b, band)| cones.scatter_into(band, (b * rows_per_band) as i64));
    CostGrid::new(
        rect,
        grid.cell_size(),
        out.into_par_iter().map(|v| v as f32).collect(),
    )
}

/// The cone sources of [`distance_transform`], highest first, and what scattering them needs.
struct Cones<'a> {
    cost: &'a [f32],
    order: &'a [u32],
    table: OffsetLengths,
    /// c_loss per cell.
    slope: f64,
    c_min: f64,
    w: i64,
}

impl Cones<'_> {
    /// Raises `band`, the rows of the output from `j0` on, by every cone that reaches them. A
    /// source in the band that already stands above its own cost was raised by a higher cone,
    /// which lies above its cone everywhere, and is skipped; a source outside the band is
    /// scattered anyway (when dominated, it changes nothing).
    fn scatter_into(&self, band: &mut [f64], j0: i64) {
        let w = self.w;
        let j1 = j0 + band.len() as i64 / w;
        for &s in self.order {
            let s = s as usize;
            let cs = self.cost[s] as f64;
            let (si, sj) = ((s as i64) % w, (s as i64) / w);
            let r = (cs - self.c_min) / self.slope;
            let rc = r.floor() as i64;
            if sj + rc < j0 || sj - rc >= j1 {
                continue;
            }
            if (j0..j1).contains(&sj) && band[s - (j0 * w) as usize] > cs {
                continue; // dominated
            }
            for j in (sj - rc).max(j0)..=(sj + rc).min(j1 - 1) {
                let dj = j - sj;
                let half = (r * r - (dj * dj) as f64).max(0.0).sqrt().floor() as i64;
                let row = ((j - j0) * w) as usize;
                let (i0, i1) = ((si - half).max(0), (si + half).min(w - 1));
                let cells = &mut band[row + i0 as usize..=row + i1 as usize];
                match self.table.row(dj) {
                    Some(lengths) => {
                        let from = (i0 - si + lengths.reach) as usize;
                        for (o, &len) in cells.iter_mut().zip(&lengths.row[from..]) {
                            // Inadmissible cells hold +∞ and are never lowered.
                            *o = o.max(cs - self.slope * len);
                        }
                    }
                    None => {
                        for (o, di) in cells.iter_mut().zip(i0 - si..) {
                            *o = o.max(cs - self.slope * ((di * di + dj * dj) as f64).sqrt());
                        }
                    }
                }
            }
        }
    }
}

/// √(di² + dj²) for every offset of a cone's reach, computed once per transform instead of once
/// per cell a cone covers (the same values, so the same result).
struct OffsetLengths {
    reach: i64,
    /// Row dj + reach holds the lengths for di = −reach..=reach; empty when the reach is too
    /// large for a table (a tiny c_loss), and then lengths are computed where needed.
    lengths: Vec<f64>,
}

/// One row of [`OffsetLengths`].
struct LengthRow<'a> {
    reach: i64,
    row: &'a [f64],
}

impl OffsetLengths {
    /// Largest reach with a table (a 1025 × 1025 table of 8 MB).
    const MAX_REACH: i64 = 512;

    fn new(reach: i64) -> Self {
        if !(0..=Self::MAX_REACH).contains(&reach) {
            return Self {
                reach,
                lengths: Vec::new(),
            };
        }
        let side = 2 * reach + 1;
        let mut lengths = Vec::with_capacity((side * side) as usize);
        for dj in -reach..=reach {
            lengths.extend((-reach..=reach).map(|di| ((di * di + dj * dj) as f64).sqrt()));
        }
        Self { reach, lengths }
    }

    /// The lengths of row `dj` (|dj| ≤ the reach), if tabled.
    fn row(&self, dj: i64) -> Option<LengthRow<'_>> {
        if self.lengths.is_empty() {
            return None;
        }
        let side = (2 * self.reach + 1) as usize;
        let at = (dj + self.reach) as usize * side;
        Some(LengthRow {
            reach: self.reach,
            row: &self.lengths[at..at + side],
        })
    }
}

/// Eq. 12: ĉ(ν) ← max over the disc δ(r_robot, ν) (cells whose centres lie within r_robot of
/// ν's centre, [`disc_offsets`]) of ĉ(ν'); cells outside the grid are ignored.
///
/// The disc is a stack of centred row spans: row dj covers di ∈ [−a(dj), a(dj)]. So the grid is
/// first reduced along rows, H_a(i) = max(H_{a−1}(i), ĉ(i − a), ĉ(i + a)) for every half-width a
/// up to the radius, and each cell then takes the maximum of H_{a(dj)} over the 2R + 1 rows of
/// its disc: O(R) per cell instead of O(R²).
pub fn footprint_max(grid: &CostGrid, r_robot: f64) -> Result<CostGrid, GridError> {
    if !(r_robot.is_finite() && r_robot >= 0.0) {
        return Err(GridError::BadParameter {
            name: "r_robot",
            value: r_robot,
        });
    }
    let offsets = disc_offsets(r_robot, grid.cell_size());
    // Half-width per row offset dj ∈ [−R, R].
    let radius = offsets
        .iter()
        .map(|&(_, dj)| dj.unsigned_abs())
        .max()
        .unwrap_or(0) as i64;
    let mut half = vec![0usize; 2 * radius as usize + 1];
    for &(di, dj) in &offsets {
        let k = (dj as i64 + radius) as usize;
        half[k] = half[k].max(di.unsigned_abs() as usize);
    }
    debug_assert_eq!(
        half.iter().map(|&a| 2 * a + 1).sum::<usize>(),
        offsets.len(),
        "disc rows are centred spans"
    );
    let rect = grid.rect();
    let cost = grid.costs();
    let (w, h) = (rect.width as usize, rect.height as usize);
    let widest = half.iter().copied().max().unwrap_or(0);
    // rows[a] = H_a, row-major like the grid.
    let mut rows: Vec<Vec<f32>> = Vec::with_capacity(widest + 1);
    rows.push(cost.to_vec());
    let band = w.max(1) * ROWS_PER_TASK;
    for a in 1..=widest {
        let prev = &rows[a - 1];
        let mut next = prev.clone();
        // H_a(i) = max(H_{a−1}(i), c(i − a), c(i + a)) where those exist, as two shifted
        // passes over each row (no bounds test per cell, so they vectorise); bands of rows
        // side by side.
        if a < w {
            next.par_chunks_mut(band)
                .zip(cost.par_chunks(band))
                .for_each(|(next, cost)| {
                    for (row, out) in cost.chunks_exact(w).zip(next.chunks_exact_mut(w)) {
                        for (o, &c) in out[a..].iter_mut().zip(&row[..w - a]) {
                            *o = o.max(c);
                        }
                        for (o, &c) in out[..w - a].iter_mut().zip(&row[a..]) {
                            *o = o.max(c);
                        }
                    }
                });
        }
        rows.push(next);
    }
    let mut out = vec![f32::NEG_INFINITY; cost.len()];
    out.par_chunks_mut(w.max(1)).enumerate().for_each(|(j, o)| {
        for (k, &a) in half.iter().enumerate() {
            let y = j as i64 + k as i64 - radius;
            if y < 0 || y >= h as i64 {
                continue;
            }
            let src = &rows[a][y as usize * w..(y as usize + 1) * w];
            for (v, &s) in o.iter_mut().zip(src) {
                *v = v.max(s);
            }
        }
    });
    CostGrid::new(rect, grid.cell_size(), out)
}

/// Decision 21 chain on a best-gait grid: [`distance_transform`] with `c_loss`, then
/// [`footprint_max`] over `r_robot`. The result is what the planner searches.
pub fn planning_grid(best: &CostGrid, c_loss: f64, r_robot: f64) -> Result<CostGrid, GridError> {
    footprint_max(&distance_transform(best, c_loss)?, r_robot)
}

/// Alg. 4 line 6 with precomputed footprint offsets (see [`disc_offsets`]): the gait minimising
/// the footprint maximum of its cost grid at `cell`, with that maximum. Ties go to the lowest
/// index; footprint cells outside a grid are ignored. `None` when `cell` is outside the grids or
/// every gait's footprint touches an inadmissible cell.
pub fn choose_gait_with(
    grids: &[CostGrid],
    cell: Cell,
    offsets: &[(i32, i32)],
) -> Option<(usize, f32)> {
    let first = check_shapes(grids).ok()?;
    first.index(cell)?;
    let mut best: Option<(usize, f32)> = None;
    for (g, grid) in grids.iter().enumerate() {
        let m = offsets
            .iter()
            .filter_map(|&(di, dj)| grid.cost(cell.offset(di, dj)))
            .fold(f32::NEG_INFINITY, f32::max);
        if m.is_finite() && best.is_none_or(|(_, b)| m < b) {
            best = Some((g, m));
        }
    }
    best
}

/// Alg. 4 line 6: g_best = argmin_g max_{ν' ∈ δ(r_robot, ν)} ĉ_{C^g}(ν') at `cell`; see
/// [`choose_gait_with`].
pub fn choose_gait(grids: &[CostGrid], cell: Cell, r_robot: f64) -> Option<(usize, f32)> {
    let d = grids.first()?.cell_size();
    choose_gait_with(grids, cell, &disc_offsets(r_robot, d))
}

#[cfg(test)]
mod tests {
    use super::*;
    use strider_core::CellRect;

    #[test]
    fn single_peak_cone() {
        let rect = CellRect::new(Cell::new(0, 0), 7, 1);
        let mut c = vec![1.0f32; 7];
        c[0] = 5.0;
        let g = CostGrid::new(rect, 0.5, c).unwrap();
        let t = distance_transform(&g, 2.0).unwrap();
        // slope per cell = 1.0
        assert_eq!(t.costs(), &[5.0, 4.0, 3.0, 2.0, 1.0, 1.0, 1.0]);
        assert!(distance_transform(&g, -1.0).is_err());
        let z = distance_transform(&g, 0.0).unwrap();
        assert!(z.costs().iter().all(|&v| v == 5.0));
    }

    #[test]
    fn best_gait_and_choice() {
        let rect = CellRect::new(Cell::new(0, 0), 3, 1);
        let inf = f32::INFINITY;
        let a = CostGrid::new(rect, 1.0, vec![1.0, 4.0, inf]).unwrap();
        let b = CostGrid::new(rect, 1.0, vec![2.0, 3.0, inf]).unwrap();
        let bg = best_gait(&[a.clone(), b.clone()]).unwrap();
        assert_eq!(bg.cost.costs()[..2], [1.0, 3.0]);
        assert_eq!(bg.gait, vec![Some(0), Some(1), None]);
        // Footprint radius 1 at cell 0: gait a max 4, gait b max 3 → b.
        assert_eq!(
            choose_gait(&[a.clone(), b.clone()], Cell::new(0, 0), 1.0),
            Some((1, 3.0))
        );
        assert_eq!(
            choose_gait(&[a.clone(), b.clone()], Cell::new(0, 0), 0.0),
            Some((0, 1.0))
        );
        assert_eq!(
            choose_gait(&[a.clone(), b.clone()], Cell::new(1, 0), 1.0),
            None
        );
        let other = CostGrid::filled(CellRect::new(Cell::new(0, 0), 2, 1), 1.0, 1.0).unwrap();
        assert_eq!(best_gait(&[a, other]), Err(GridError::ShapeMismatch));
        assert_eq!(best_gait(&[]), Err(GridError::Empty));
    }

    #[test]
    fn footprint_inflates_obstacles() {
        let rect = CellRect::new(Cell::new(0, 0), 5, 1);
        let g = CostGrid::new(rect, 1.0, vec![1.0, 1.0, 1.0, 1.0, f32::INFINITY]).unwrap();
        let f = footprint_max(&g, 1.0).unwrap();
        assert_eq!(f.costs(), &[1.0, 1.0, 1.0, f32::INFINITY, f32::INFINITY]);
    }
}
