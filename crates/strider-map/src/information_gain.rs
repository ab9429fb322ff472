//! Spatial information gain of `001` §4.2 (decision 5).
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

use crate::map::ElevationMap;
use crate::observability::{ray_clear, target_height};
use crate::passability::disc_reach;
use crate::reachability::Reachability;
use crate::rect::{self, WorldRect, in_bounds};
use rayon::prelude::*;
use strider_core::grid::{NEIGHBOURS8, disc_offsets};
use strider_core::{Cell, CellRect};

/// I_model (Eq. 11) of the candidate cells with non-zero gain.
#[derive(Clone, Debug, Default)]
pub struct InfoGain {
    /// Candidates with I_model > 0 and their gain, in row-major order (the fixed order of
    /// Alg. 3).
    pub cells: Vec<(Cell, f64)>,
    /// Number of candidate cells evaluated.
    pub candidates: usize,
}

impl InfoGain {
    /// The gains as a dense raster over `rect` (0 elsewhere), for rendering.
    pub fn raster(&self, rect: CellRect) -> Vec<f32> {
        let mut out = vec![0.0; rect.len()];
        for &(c, g) in &self.cells {
            if let Some(k) = rect.index(c) {
                out[k] = g as f32;
            }
        }
        out
    }

    /// Total gain over all cells.
    pub fn total(&self) -> f64 {
        self.cells.iter().map(|&(_, g)| g).sum()
    }
}

/// A dense view of the map for Eq. 10–11: elevations (NaN = unknown), I_cell of every unknown
/// cell (0 for known cells and cells outside the bounds) and a summed-area table of the unknown
/// mask.
struct GainView {
    rect: CellRect,
    elev: Vec<f32>,
    i_cell: Vec<f32>,
    sat: Vec<u32>,
}

impl GainView {
    fn new(map: &ElevationMap, rect: CellRect, bounds: Option<&WorldRect>) -> Self {
        let d = map.cell_size();
        let elev = map.elevation_raster(rect);
        let (w, h) = (rect.width as usize, rect.height as usize);
        let unknown: Vec<bool> = rect
            .cells()
            .zip(&elev)
            .map(|(c, e)| e.is_nan() && in_bounds(bounds, c, d))
            .collect();
        let mut i_cell = vec![0.0f32; rect.len()];
        for y in 0..h {
            for x in 0..w {
                if !unknown[y * w + x] {
                    continue;
                }
                // k(ν'): unknown 8-neighbours; outside the view nothing is known either.
                let k = NEIGHBOURS8
                    .iter()
                    .filter(|&&(di, dj)| {
                        let (nx, ny) = (x as i64 + di as i64, y as i64 + dj as i64);
                        if nx < 0 || ny < 0 || nx >= w as i64 || ny >= h as i64 {
                            in_bounds(bounds, rect.cell(y * w + x).offset(di, dj), d)
                        } else {
                            unknown[ny as usize * w + nx as usize]
                        }
                    })
                    .count();
                i_cell[y * w + x] = (k as f32 + 1.0) / 9.0; // Eq. 10
            }
        }
        let mut sat = vec![0u32; (w + 1) * (h + 1)];
        for y in 0..h {
            let mut row = 0;
            for x in 0..w {
                row += unknown[y * w + x] as u32;
                sat[(y + 1) * (w + 1) + x + 1] = sat[y * (w + 1) + x + 1] + row;
            }
        }
        Self {
            rect,
            elev,
            i_cell,
            sat,
        }
    }

    #[inline]
    fn elevation(&self, c: Cell) -> Option<f32> {
        self.rect
            .index(c)
            .map(|k| self.elev[k])
            .filter(|e| !e.is_nan())
    }

    /// Number of unknown cells in the square of half-size `n` around `c` (clipped to the view).
    fn unknown_in_square(&self, c: Cell, n: u32) -> u32 {
        let w = self.rect.width as i64;
        let h = self.rect.height as i64;
        let (x, y) = (
            (c.i - self.rect.min.i) as i64,
            (c.j - self.rect.min.j) as i64,
        );
        let (x0, y0) = ((x - n as i64).clamp(0, w), (y - n as i64).clamp(0, h));
        let (x1, y1) = (
            (x + n as i64 + 1).clamp(0, w),
            (y + n as i64 + 1).clamp(0, h),
        );
        let at = |xx: i64, yy: i64| self.sat[(yy * (w + 1) + xx) as usize];
        at(x1, y1) + at(x0, y0) - at(x0, y1) - at(x1, y0)
    }

    /// I_model(ν) (Eq. 11).
    fn model_gain(&self, c: Cell, disc: &[(i32, i32)], reach: u32, h: f64, d: f64) -> f64 {
        self.model_gain_with(c, disc, reach, h, d, &mut Vec::new())
    }

    /// [`GainView::model_gain`] with a reusable buffer for the unknown targets.
    ///
    /// The targets (unknown cells of the disc) are gathered first. When casting a ray to each
    /// of them costs less than a pass over the disc (few targets, late in exploration), each is
    /// cast directly; otherwise raised cells mark shadow intervals first and only targets inside
    /// one are cast. Both give the exact Eq. 11 sum.
    fn model_gain_with(
        &self,
        c: Cell,
        disc: &[(i32, i32)],
        reach: u32,
        h: f64,
        d: f64,
        targets: &mut Vec<(i32, i32, f32)>,
    ) -> f64 {
        let Some(ef) = self.elevation(c) else {
            return 0.0;
        };
        if self.unknown_in_square(c, reach) == 0 {
            return 0.0;
        }
        let zs = ef as f64 + h;
        let zt = target_height(None, ef);
        targets.clear();
        let mut ray_work = 0.0f64;
        for &(di, dj) in disc {
            let Some(k) = self.rect.index(c.offset(di, dj)) else {
                continue;
            };
            let g = self.i_cell[k];
            if g > 0.0 {
                targets.push((di, dj, g));
                ray_work += (di.abs().max(dj.abs()) + 1) as f64;
            }
        }
        if targets.is_empty() {
            return 0.0;
        }
        if ray_work < disc.len() as f64 {
            return targets
                .iter()
                .filter(|&&(di, dj, _)| {
                    ray_clear(c, c.offset(di, dj), zs, zt, d, |x| self.elevation(x))
                })
                .map(|&(_, _, g)| g as f64)
                .sum();
        }
        // Only known cells above min(sensor, target) = ef can block a ray to an unknown
        // target, and only over a range of target distances: the sight line to a target at
        // distance R (cells) passes a cell at centre distance r no lower than
        // zs − (zs − zt)·(r + ½√2)/R, so a cell of elevation e < zs can block only targets with
        // R < (zs − zt)·(r + ½√2)/(zs − e), and none nearer than its near side r − ½√2. Each
        // such cell marks the direction bins it subtends with that distance interval (kept as
        // the hull per bin); targets outside every interval of their direction are clear
        // without casting (exact: a ray meets a cell only within its angular extent, and a
        // slightly raised cell shadows only the targets just behind it).
        const HALF_DIAG: f64 = std::f64::consts::FRAC_1_SQRT_2;
        let mut shadow = [(f32::INFINITY, f32::NEG_INFINITY); ANGLE_BINS];
        let mut any_tall = false;
        for &(di, dj) in disc {
            if (di, dj) == (0, 0) {
                continue;
            }
            let Some(e) = self.elevation(c.offset(di, dj)) else {
                continue;
            };
            if e <= ef {
                continue;
            }
            let r = ((di * di + dj * dj) as f64).sqrt();
            let start = (r - HALF_DIAG) as f32;
            let end = if (e as f64) < zs {
                ((zs - zt) * (r + HALF_DIAG) / (zs - e as f64)) as f32
            } else {
                f32::INFINITY
            };
            mark_cell_directions(&mut shadow, di, dj, start, end);
            any_tall = true;
        }
        let mut sum = 0.0;
        for &(di, dj, g) in targets.iter() {
            let t = c.offset(di, dj);
            let maybe_blocked = any_tall && {
                let (lo, hi) = shadow[angle_bin(di as f64, dj as f64)];
                let rt = ((di * di + dj * dj) as f32).sqrt();
                rt >= lo && rt <= hi
            };
            if !maybe_blocked || ray_clear(c, t, zs, zt, d, |x| self.elevation(x)) {
                sum += g as f64;
            }
        }
        sum
    }
}

/// Direction bins of the shadow mask in [`GainView::model_gain`].
const ANGLE_BINS: usize = 2048;

/// Pseudo-angle of the direction (x, y) ≠ 0 in [0, 4): monotone in atan2, no trigonometry.
#[inline]
fn pseudo_angle(x: f64, y: f64) -> f64 {
    if y >= 0.0 {
        if x >= 0.0 {
            y / (x + y)
        } else {
            1.0 - x / (-x + y)
        }
    } else if x < 0.0 {
        2.0 - y / (-x - y)
    } else {
        3.0 + x / (x - y)
    }
}

#[inline]
fn angle_bin(x: f64, y: f64) -> usize {
    ((pseudo_angle(x, y) * (ANGLE_BINS as f64 / 4.0)) as usize).min(ANGLE_BINS - 1)
}

/// Widens the shadow interval of the direction bins subtended by the cell at offset
/// `(di, dj)` ≠ 0 from the viewpoint (its four corners, plus one bin on each side against
/// rounding) to include target distances `start..=end` (cells).
fn mark_cell_directions(
    mask: &mut [(f32, f32); ANGLE_BINS],
    di: i32,
    dj: i32,
    start: f32,
    end: f32,
) {
    let (x, y) = (di as f64, dj as f64);
    let bins = [(-0.5, -0.5), (0.5, -0.5), (-0.5, 0.5), (0.5, 0.5)]
        .map(|(ox, oy)| angle_bin(x + ox, y + oy) as i64);
    let lo = bins.iter().copied().min().unwrap_or(0);
    let hi = bins.iter().copied().max().unwrap_or(0);
    let n = ANGLE_BINS as i64;
    let mut mark = |a: i64, b: i64| {
        for k in a - 1..=b + 1 {
            let m = &mut mask[k.rem_euclid(n) as usize];
            m.0 = m.0.min(start);
            m.1 = m.1.max(end);
        }
    };
    if hi - lo > n / 2 {
        // The cell straddles direction 0 (the +x axis): wrap around.
        let lo_w = bins
            .iter()
            .copied()
            .filter(|&b| b >= n / 2)
            .min()
            .unwrap_or(n);
        let hi_w = bins
            .iter()
            .copied()
            .filter(|&b| b < n / 2)
            .max()
            .unwrap_or(0);
        mark(lo_w, n - 1);
        mark(0, hi_w);
    } else {
        mark(lo, hi);
    }
}

/// The view rectangle: the known area grown by the sensor reach plus the neighbourhood of
/// Eq. 10.
fn view_rect(map: &ElevationMap, around: CellRect) -> CellRect {
    let reach = disc_reach(map.params().r_sensor, map.cell_size());
    rect::expand(around, reach + 2)
}

/// I_cell(ν') (Eq. 10): (k + 1) / 9 for an unknown cell inside `bounds`, 0 otherwise.
pub fn cell_information(map: &ElevationMap, c: Cell, bounds: Option<&WorldRect>) -> f64 {
    let v = GainView::new(map, rect::expand(CellRect::new(c, 1, 1), 1), bounds);
    v.i_cell[v.rect.index(c).unwrap_or(0)] as f64
}

/// I_model(ν) (Eq. 11) at one observed cell, without the candidate filter. 0 for an unknown
/// cell.
pub fn model_information(map: &ElevationMap, c: Cell, bounds: Option<&WorldRect>) -> f64 {
    let p = map.params();
    let d = map.cell_size();
    let view = GainView::new(map, view_rect(map, CellRect::new(c, 1, 1)), bounds);
    let disc = disc_offsets(p.r_sensor, d);
    view.model_gain(c, &disc, disc_reach(p.r_sensor, d), p.sensor_height, d)
}

/// I_model (Eq. 11) on every candidate cell: observed, admissible, reachable (`reach`), on the
/// `info_gain_stride` lattice, inside `bounds`, with an unknown cell within r_sensor. Runs in
/// parallel over candidates; the result is deterministic.
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
    let stride = p.info_gain_stride.max(1) as i32;
    let candidates: Vec<Cell> = reach
        .cells()
        .filter(|&c| {
            c.i.rem_euclid(stride) == 0
                && c.j.rem_euclid(stride) == 0
                && reach.is_goal_cell(c)
                && in_bounds(bounds, c, d)
        })
        .collect();
    let view = GainView::new(map, view_rect(map, known), bounds);
    let disc = disc_offsets(p.r_sensor, d);
    let r = disc_reach(p.r_sensor, d);
    let gains: Vec<f64> = candidates
        .par_iter()
        .map_init(Vec::new, |buf, &c| {
            view.model_gain_with(c, &disc, r, p.sensor_height, d, buf)
        })
        .collect();
    InfoGain {
        candidates: candidates.len(),
        cells: candidates
            .into_iter()
            .zip(gains)
            .filter(|&(_, g)| g > 0.0)
            .collect(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::params::MapParams;
    use approx::assert_abs_diff_eq;
    use strider_core::{Point2, Rgb8};

    fn params() -> MapParams {
        MapParams {
            cell_size: 0.1,
            tile_size: 8,
            r_sensor: 0.2, // disc of 13 cells
            r_robot: 0.0,
            sensor_height: 0.3,
            ..MapParams::default()
        }
    }

    fn flat(m: &mut ElevationMap, cells: impl IntoIterator<Item = Cell>) {
        for c in cells {
            m.set_cell(c, 0.0, 1e-4, Rgb8::default());
        }
        m.update_passability();
    }

    #[test]
    fn cell_information_counts_unknown_neighbours() {
        let mut m = ElevationMap::new(params());
        assert_abs_diff_eq!(
            cell_information(&m, Cell::new(0, 0), None),
            1.0,
            epsilon = 1e-6
        );
        flat(&mut m, [Cell::new(1, 0), Cell::new(1, 1)]);
        assert_abs_diff_eq!(
            cell_information(&m, Cell::new(0, 0), None),
            7.0 / 9.0,
            epsilon = 1e-6
        );
        assert_abs_diff_eq!(
            cell_information(&m, Cell::new(1, 0), None),
            0.0,
            epsilon = 1e-6
        );
        // Bounds: the cell itself outside gives nothing; neighbours outside do not count.
        let b = WorldRect::new(Point2::new(-0.1, -0.1), Point2::new(0.1, 1.0));
        assert_abs_diff_eq!(
            cell_information(&m, Cell::new(0, 0), Some(&b)),
            6.0 / 9.0,
            epsilon = 1e-6
        );
        assert_abs_diff_eq!(
            cell_information(&m, Cell::new(2, 0), Some(&b)),
            0.0,
            epsilon = 1e-6
        );
    }

    #[test]
    fn model_information_on_a_strip() {
        // A known 1-cell-wide strip j = 0, i ∈ [-5, 5]; the disc of radius 2 cells around (0, 0)
        // holds 13 cells: 5 known (the strip), 8 unknown. Unknown (0, ±1), (±1, ±1): neighbours
        // include 3 known strip cells → k = 5, I = 6/9; (0, ±2): k = 8 → 1; and (±1, ±1) → k = 5.
        let mut m = ElevationMap::new(params());
        flat(&mut m, (-5..=5).map(|i| Cell::new(i, 0)));
        let expected = 2.0 * (6.0 / 9.0 * 3.0) + 2.0 * 1.0;
        assert_abs_diff_eq!(
            model_information(&m, Cell::new(0, 0), None),
            expected,
            epsilon = 1e-6
        );
        // A tall known wall cell between the robot and (0, 2) hides it.
        m.set_cell(Cell::new(0, 1), 2.0, 1e-4, Rgb8::default());
        let hidden = expected - 6.0 / 9.0 - 1.0 - 2.0 * (1.0 / 9.0);
        // (0,1) became known: it no longer counts, (0,2) is hidden behind it and the unknown
        // cells (±1, 1) lost one unknown neighbour each.
        assert_abs_diff_eq!(
            model_information(&m, Cell::new(0, 0), None),
            hidden,
            epsilon = 1e-6
        );
    }

    #[test]
    fn information_gain_on_candidates() {
        let mut m = ElevationMap::new(params());
        // Known 11 × 11 square: interior cells see no unknown cell within 2 cells.
        flat(
            &mut m,
            (-5..=5).flat_map(|j| (-5..=5).map(move |i| Cell::new(i, j))),
        );
        let reach = Reachability::compute(&m, Cell::new(0, 0));
        let g = information_gain(&m, &reach, None);
        // Candidates: every cell except the border ring (no known neighbour on all sides is
        // fine; the border ring is passable too) → 121 evaluated.
        assert_eq!(g.candidates, 121);
        // Cells with an unknown cell within 2 cells: the outer two rings (121 − 7·7).
        assert_eq!(g.cells.len(), 121 - 49);
        let corner = g
            .cells
            .iter()
            .find(|&&(c, _)| c == Cell::new(5, 5))
            .unwrap()
            .1;
        assert_abs_diff_eq!(corner, model_information(&m, Cell::new(5, 5), None));
        // With a stride of 2 only even lattice cells are evaluated.
        let mut m2 = m.clone();
        m2.set_info_gain_stride(2);
        let g2 = information_gain(&m2, &reach, None);
        assert_eq!(g2.candidates, 25);
        // Bounds that exclude everything beyond the square leave nothing to gain.
        let b = WorldRect::new(Point2::new(-0.5, -0.5), Point2::new(0.6, 0.6));
        assert!(information_gain(&m, &reach, Some(&b)).cells.is_empty());
    }

    proptest::proptest! {
        #![proptest_config(proptest::prelude::ProptestConfig::with_cases(64))]
        /// The shadow-direction shortcut is exact: I_model equals the sum over every unknown
        /// target of I_cell when its ray (cast unconditionally) is clear.
        #[test]
        fn shadow_pruning_is_exact(
            heights in proptest::collection::vec(0.0f32..0.6, 144),
            known in proptest::collection::vec(proptest::bool::weighted(0.6), 144),
            ci in 0..12i32, cj in 0..12i32,
        ) {
            let mut m = ElevationMap::new(MapParams { r_sensor: 0.5, ..params() });
            for k in 0..144 {
                if known[k] || k == (cj * 12 + ci) as usize {
                    m.set_cell(Cell::new(k as i32 % 12, k as i32 / 12), heights[k], 1e-4, Rgb8::default());
                }
            }
            let c = Cell::new(ci, cj);
            let ef = m.elevation(c).unwrap();
            let mut brute = 0.0;
            for (di, dj) in disc_offsets(0.5, 0.1) {
                let t = c.offset(di, dj);
                if m.is_observed(t) {
                    continue;
                }
                let clear = ray_clear(c, t, ef as f64 + 0.3, ef as f64, 0.1, |x| m.elevation(x));
                if clear {
                    brute += cell_information(&m, t, None);
                }
            }
            let fast = model_information(&m, c, None);
            proptest::prop_assert!((fast - brute).abs() < 1e-4, "fast {fast} brute {brute}");
        }
    }
}
