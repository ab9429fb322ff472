//! observable(ν, ν') of Prágr22 Eq. 11 by ray casting in the elevation map (decision 5).
//!
//! The sensor sits `h_sensor` above the centre of ν at ν's elevation; the target point is the
//! centre of ν' at its elevation (at ν's elevation when ν' is unknown: the ground is assumed
//! level with the robot). The straight 3-D segment between them is blocked iff some *known*
//! intermediate cell (neither ν nor ν') rises above the segment somewhere over that cell; unknown
//! cells are transparent.
//!
//! The test is exact per cell: the segment's height is linear in its parameter t, so its minimum
//! over a cell is attained at the cell's entry or exit parameter. The Amanatides–Woo traversal
//! ([`CellRay`]) yields both (the previous cell's exit is this cell's entry): the slab interval
//! of [`cell_interval`], up to rounding, without a division per cell.
//!
//! Centre-to-centre rays often pass exactly through a cell corner (every 45° ray does). The
//! traversal then reports one of the two side cells with a zero-length interval. Such a grazing
//! contact blocks only when *both* side cells rise above the ray at the corner: a ray slips
//! between a wall cell and a floor cell, but not through a diagonal wall.

use crate::map::ElevationMap;
use strider_core::grid::CellRay;
use strider_core::{Cell, CellRect, Point2};

/// The parameter interval `[t_in, t_out]` ⊂ [0, 1] of the segment `a + t·(dx, dy)` inside cell
/// `c` (cell size `d`). A segment merely touching the cell yields a single point.
#[inline]
pub fn cell_interval(c: Cell, a: Point2, dx: f64, dy: f64, d: f64) -> (f64, f64) {
    let lo = Point2::new(c.i as f64 * d, c.j as f64 * d);
    let hi = Point2::new(lo.x + d, lo.y + d);
    let (t_in, t_out) = box_interval(a, dx, dy, lo, hi);
    if t_in <= t_out {
        (t_in, t_out)
    } else {
        let m = 0.5 * (t_in + t_out);
        (m, m)
    }
}

/// The slab method: the parameter interval, clipped to [0, 1], of the segment `a + t·(dx, dy)`
/// inside the closed box `[lo, hi]`; `t_in > t_out` when they do not meet.
#[inline]
pub(crate) fn box_interval(a: Point2, dx: f64, dy: f64, lo: Point2, hi: Point2) -> (f64, f64) {
    let slab = |lo: f64, hi: f64, p: f64, dp: f64| -> (f64, f64) {
        if dp == 0.0 {
            // Parallel to the slab: inside for every t, or for none.
            if lo <= p && p <= hi {
                (f64::NEG_INFINITY, f64::INFINITY)
            } else {
                (f64::INFINITY, f64::NEG_INFINITY)
            }
        } else {
            let t0 = (lo - p) / dp;
            let t1 = (hi - p) / dp;
            (t0.min(t1), t0.max(t1))
        }
    };
    let (x0, x1) = slab(lo.x, hi.x, a.x, dx);
    let (y0, y1) = slab(lo.y, hi.y, a.y, dy);
    (x0.max(y0).max(0.0), x1.min(y1).min(1.0))
}

/// True when the segment from `(centre of from, sensor_z)` to `(centre of to, target_z)` is not
/// blocked by any known intermediate cell; `elev` gives a cell's elevation (`None` = unknown,
/// transparent). This is the exact core of [`observable`].
pub fn ray_clear(
    from: Cell,
    to: Cell,
    sensor_z: f64,
    target_z: f64,
    d: f64,
    elev: impl Fn(Cell) -> Option<f32>,
) -> bool {
    from == to || Segment::new(from, to, sensor_z, target_z, d).clear(elev)
}

/// [`ray_clear`] in a dense elevation raster over `rect` (row-major, NaN = unknown; cells
/// outside `rect` are unknown). The same test, with the lookups written out so that the
/// information gain's millions of sight lines pay no closure call per cell.
#[inline]
pub fn ray_clear_in(
    raster: &[f32],
    rect: CellRect,
    from: Cell,
    to: Cell,
    sensor_z: f64,
    target_z: f64,
    d: f64,
) -> bool {
    debug_assert_eq!(raster.len(), rect.len());
    from == to
        || Segment::new(from, to, sensor_z, target_z, d).clear(
            #[inline(always)]
            |c: Cell| {
                rect.index(c)
                    .and_then(|k| raster.get(k).copied())
                    .filter(|e| !e.is_nan())
            },
        )
}

/// A sight line from the sensor above the centre of `from` to the target point above the
/// centre of `to`.
struct Segment {
    from: Cell,
    to: Cell,
    a: Point2,
    b: Point2,
    dx: f64,
    dy: f64,
    sensor_z: f64,
    dz: f64,
    /// The segment never dips below its lower end: lower cells cannot block.
    z_floor: f64,
    d: f64,
}

impl Segment {
    fn new(from: Cell, to: Cell, sensor_z: f64, target_z: f64, d: f64) -> Self {
        let a = from.center(d);
        let b = to.center(d);
        Self {
            from,
            to,
            a,
            b,
            dx: b.x - a.x,
            dy: b.y - a.y,
            sensor_z,
            dz: target_z - sensor_z,
            z_floor: sensor_z.min(target_z),
            d,
        }
    }

    /// Whether no known cell of the traversal blocks the segment in the map `elev`. Each
    /// cell's parameter interval `[t0, t1]` is where the traversal entered it (the previous
    /// cell's exit) and left it: the slab intervals of [`cell_interval`], without a division
    /// per cell.
    #[inline(always)]
    fn clear(&self, elev: impl Fn(Cell) -> Option<f32>) -> bool {
        let mut ray = CellRay::new(self.a, self.b, self.d);
        let mut t_in = 0.0;
        while let Some((c, t1)) = ray.next_with_exit() {
            let t0 = std::mem::replace(&mut t_in, t1);
            let Some(e) = elev(c) else {
                continue;
            };
            if e as f64 <= self.z_floor || c == self.from || c == self.to {
                continue;
            }
            // The minimum of a linear function over [t0, t1] is at one end.
            let z_min = self.sensor_z + self.dz * if self.dz < 0.0 { t1 } else { t0 };
            if e as f64 <= z_min {
                continue;
            }
            if t1 - t0 > 1e-12 {
                return false;
            }
            // Corner crossing: the other side cell must block too.
            let other = other_side_cell(c, self.a, self.dx, self.dy, t0, self.d);
            if elev(other).is_some_and(|eo| eo as f64 > z_min) {
                return false;
            }
        }
        true
    }
}

/// For a segment crossing the lattice corner at parameter `t` and the side cell `c` reported by
/// the traversal, the other side cell at that corner.
fn other_side_cell(c: Cell, a: Point2, dx: f64, dy: f64, t: f64, d: f64) -> Cell {
    let (x, y) = (((a.x + t * dx) / d).round(), ((a.y + t * dy) / d).round());
    let (x, y) = (x as i32, y as i32);
    // Cells before (p) and after (n) the corner along the segment.
    let (pi, ni) = if dx > 0.0 { (x - 1, x) } else { (x, x - 1) };
    let (pj, nj) = if dy > 0.0 { (y - 1, y) } else { (y, y - 1) };
    Cell::new(pi + ni - c.i, pj + nj - c.j)
}

/// The height of the target point for a ray to `to`: its elevation when known, else the
/// elevation of the viewing cell (level-ground assumption, decision 5).
#[inline]
pub fn target_height(to_elevation: Option<f32>, from_elevation: f32) -> f64 {
    to_elevation.unwrap_or(from_elevation) as f64
}

/// observable(ν, ν') (Eq. 11, decision 5): whether the surface of `to` is visible from a sensor
/// `h_sensor` metres above the surface of `from`. `false` when `from` is unobserved.
pub fn observable(map: &ElevationMap, from: Cell, to: Cell, h_sensor: f64) -> bool {
    let Some(ef) = map.elevation(from) else {
        return false;
    };
    ray_clear(
        from,
        to,
        ef as f64 + h_sensor,
        target_height(map.elevation(to), ef),
        map.cell_size(),
        |c| map.elevation(c),
    )
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::params::MapParams;
    use crate::testing::{block, known, lattice_map};
    use proptest::prelude::*;
    use strider_core::Rgb8;

    #[test]
    fn wall_blocks_and_unknown_is_transparent() {
        let mut m = lattice_map(0.1, MapParams::default().tile_size);
        known(&mut m, block(0, 0, 10, 1), |_| 0.0);
        let (a, b) = (Cell::new(0, 0), Cell::new(9, 0));
        assert!(observable(&m, a, b, 0.3));
        // Sensor at 0.3, target at 0: cell 5 spans x ∈ [0.5, 0.6], t ∈ [0.5, 0.6111], where the
        // ray is at ≥ 0.3 · (1 − 0.6111) = 0.1167.
        m.set_cell(Cell::new(5, 0), 0.11, 1e-4, Rgb8::default());
        assert!(observable(&m, a, b, 0.3));
        m.set_cell(Cell::new(5, 0), 0.2, 1e-4, Rgb8::default());
        assert!(!observable(&m, a, b, 0.3));
        // An unknown target behind the wall: still blocked; an unknown cell never blocks.
        assert!(!observable(&m, a, Cell::new(12, 0), 0.3));
        assert!(observable(&m, a, Cell::new(0, 12), 0.3));
        assert!(
            !observable(&m, Cell::new(-5, -5), b, 0.3),
            "unknown viewpoint"
        );
    }

    #[test]
    fn corner_crossings_block_only_between_two_walls() {
        let mut m = lattice_map(0.1, MapParams::default().tile_size);
        known(&mut m, block(0, 0, 3, 3), |_| 0.0);
        let (a, b) = (Cell::new(0, 0), Cell::new(2, 2));
        // The 45° ray crosses the corners (1,1)·d and (2,2)·d; (1,1) is on the path.
        m.set_cell(Cell::new(1, 2), 1.0, 1e-4, Rgb8::default());
        assert!(
            observable(&m, a, b, 0.3),
            "one side cell high: slips through"
        );
        m.set_cell(Cell::new(2, 1), 1.0, 1e-4, Rgb8::default());
        assert!(!observable(&m, a, b, 0.3), "diagonal wall blocks");
        // Symmetric in i and j.
        m.set_cell(Cell::new(1, 2), 0.0, 1e-4, Rgb8::default());
        assert!(observable(&m, a, b, 0.3));
    }

    /// Length of the sub-interval of cell `c` over which the segment lies strictly below `e`.
    fn blocking_length(t0: f64, t1: f64, zs: f64, dz: f64, e: f64) -> f64 {
        if dz == 0.0 {
            return if zs < e { t1 - t0 } else { 0.0 };
        }
        let ts = (e - zs) / dz;
        let (lo, hi) = if dz > 0.0 {
            (t0, t1.min(ts))
        } else {
            (t0.max(ts), t1)
        };
        (hi - lo).max(0.0)
    }

    const N: usize = 8;

    proptest! {
        /// The raster form is the same test as the closure form: equal on every ray, with
        /// rays leaving the raster (outside is unknown) and many 45° corner crossings.
        #[test]
        fn raster_form_equals_closure_form(
            heights in proptest::collection::vec(0.0f32..0.5, 144),
            known in proptest::collection::vec(proptest::bool::weighted(0.7), 144),
            rays in proptest::collection::vec((-2..14i32, -2..14i32, -2..14i32, -2..14i32), 64),
            h in 0.0f64..0.6,
        ) {
            let rect = CellRect::new(Cell::new(0, 0), 12, 12);
            let raster: Vec<f32> = heights
                .iter()
                .zip(&known)
                .map(|(&z, &k)| if k { z } else { f32::NAN })
                .collect();
            let elev = |c: Cell| rect.index(c).map(|k| raster[k]).filter(|e| !e.is_nan());
            for &(fi, fj, ti, tj) in &rays {
                // Half the rays on a diagonal, through lattice corners.
                let to = if ti % 2 == 0 { Cell::new(fi + (tj - fj), tj) } else { Cell::new(ti, tj) };
                let from = Cell::new(fi, fj);
                let zs = elev(from).unwrap_or(0.0) as f64 + h;
                let zt = elev(to).unwrap_or(0.1) as f64;
                prop_assert_eq!(
                    ray_clear_in(&raster, rect, from, to, zs, zt, 0.1),
                    ray_clear(from, to, zs, zt, 0.1, elev),
                    "{:?} -> {:?}", from, to
                );
            }
        }
    }

    proptest! {
        /// Exact per-cell test against fine sampling of the segment (`S` samples). They must
        /// agree, except that sampling may miss a blockage whose blocking sub-interval (the
        /// part of a cell's parameter interval where the segment is below the cell's surface)
        /// is shorter than 2/S in every blocking cell: the near-tangent and corner-clipping
        /// cases. Sampling never reports a blockage that the exact test misses. Samples lying on
        /// a cell edge (within 1e-9 cell) belong to two cells and are skipped as ambiguous.
        #[test]
        fn exact_test_agrees_with_sampling(
            heights in proptest::collection::vec(0.0f32..1.5, N * N),
            known in proptest::collection::vec(proptest::bool::weighted(0.7), N * N),
            fi in 0..N as i32, fj in 0..N as i32, ti in 0..N as i32, tj in 0..N as i32,
            h in 0.0f64..1.0,
        ) {
            let d = 0.2;
            let elev = |c: Cell| -> Option<f32> {
                if c.i < 0 || c.j < 0 || c.i >= N as i32 || c.j >= N as i32 { return None; }
                let k = c.j as usize * N + c.i as usize;
                known[k].then_some(heights[k])
            };
            let (from, to) = (Cell::new(fi, fj), Cell::new(ti, tj));
            let zs = heights[fj as usize * N + fi as usize] as f64 + h;
            let zt = heights[tj as usize * N + ti as usize] as f64;
            let exact = ray_clear(from, to, zs, zt, d, elev);

            const S: usize = 20_000;
            let (a, b) = (from.center(d), to.center(d));
            let mut sampled_clear = true;
            for k in 0..=S {
                let t = k as f64 / S as f64;
                let (x, y) = (a.x + t * (b.x - a.x), a.y + t * (b.y - a.y));
                let on_edge = |v: f64| ((v / d) - (v / d).round()).abs() < 1e-9;
                if on_edge(x) || on_edge(y) { continue; }
                let c = Cell::containing(x, y, d).unwrap();
                if c == from || c == to { continue; }
                if let Some(e) = elev(c) && e as f64 > zs + t * (zt - zs) {
                    sampled_clear = false;
                    break;
                }
            }
            if !sampled_clear {
                prop_assert!(!exact, "sampling found a blockage the exact test missed");
            } else if !exact {
                let (dx, dy) = (b.x - a.x, b.y - a.y);
                let mut longest: f64 = 0.0;
                for c in CellRay::new(a, b, d) {
                    if c == from || c == to { continue; }
                    if let Some(e) = elev(c) {
                        let (t0, t1) = cell_interval(c, a, dx, dy, d);
                        longest = longest.max(blocking_length(t0, t1, zs, zt - zs, e as f64));
                    }
                }
                prop_assert!(longest < 2.0 / S as f64,
                    "exact says blocked over {longest} but sampling saw nothing");
            }
        }
    }
}
