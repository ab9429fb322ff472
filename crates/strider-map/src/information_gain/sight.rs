//! The sight lines from one candidate cell of Eq. 11 and the tests of a cell against them.

use super::disc::{DiscEntry, shadow_interval};
use crate::observability::{box_interval, ray_clear_in, target_height};
use strider_core::{Cell, CellRect, Point2};

/// The sight lines from one candidate: its cell and elevation, the sensor height above it,
/// the height of its targets and the cell size.
#[derive(Clone, Copy)]
pub(super) struct Sight {
    c: Cell,
    ef: f32,
    zs: f64,
    zt: f64,
    d: f64,
}

impl Sight {
    /// The sight lines from cell `c` at elevation `ef` with the sensor `h` above it, on cells
    /// of size `d`.
    pub(super) fn new(c: Cell, ef: f32, h: f64, d: f64) -> Self {
        Self {
            c,
            ef,
            zs: ef as f64 + h,
            zt: target_height(None, ef),
            d,
        }
    }

    /// The candidate's cell.
    #[inline]
    pub(super) fn cell(&self) -> Cell {
        self.c
    }

    /// The target at disc entry `e`.
    #[inline]
    pub(super) fn target(&self, e: &DiscEntry) -> Cell {
        self.c.offset(e.di, e.dj)
    }

    /// `z` when a known cell of that height rises above the candidate, so that it may block a
    /// sight line (only such cells can); `None` otherwise (and for NaN, unknown: transparent).
    #[inline]
    pub(super) fn blocking(&self, z: f32) -> Option<f32> {
        (z > self.ef).then_some(z)
    }

    /// Whether height `z` is above the sensor.
    #[inline]
    pub(super) fn above_sensor(&self, z: f32) -> bool {
        z as f64 > self.zs
    }

    /// The target distances a cell of height `z` at centre distance `r` can shadow (see
    /// [`shadow_interval`]).
    #[inline]
    pub(super) fn shadow(&self, r: f32, z: f32) -> (f32, f32) {
        shadow_interval(r, z, self.zs, self.zt)
    }

    /// Whether the sight line to `t` is clear in the elevations `elev` over `rect`.
    #[inline]
    pub(super) fn clear_in(&self, elev: &[f32], rect: CellRect, t: Cell) -> bool {
        ray_clear_in(elev, rect, self.c, t, self.zs, self.zt, self.d)
    }

    /// Whether a cell of height `z` at disc entry `x` can take part in blocking the sight line
    /// to the target at entry `t` ([`touches_sight_line`]).
    #[inline]
    pub(super) fn touched_by(&self, x: &DiscEntry, t: &DiscEntry, z: f32) -> bool {
        touches_sight_line(x.di, x.dj, t.di, t.dj, z as f64, self.zs, self.zt)
    }

    /// Whether a cell of height `z` at disc entry `x` certainly blocks the sight line to the
    /// target at entry `t` ([`crosses_below`]).
    #[inline]
    pub(super) fn blocked_by(&self, x: &DiscEntry, t: &DiscEntry, z: f32) -> bool {
        crosses_below(x.di, x.dj, t.di, t.dj, z as f64, self.zs, self.zt)
    }
}

/// Whether a cell of height `z` at offset `(xi, xj)` from the sensor cell can take part in
/// blocking the sight line to the target at offset `(ti, tj)` (sensor at `zs`, target at
/// `zt`, both above cell centres): the closed cell meets the segment where the segment is
/// below `z`. This is the condition under which [`ray_clear_in`] looks at a cell (as a
/// traversed cell or as the other side of a corner crossing), widened by 1e-6 cell and 1e-9 m
/// against rounding, so a `false` is safe: the cell cannot change that sight line.
#[inline]
pub(super) fn touches_sight_line(
    xi: i32,
    xj: i32,
    ti: i32,
    tj: i32,
    z: f64,
    zs: f64,
    zt: f64,
) -> bool {
    let (t0, t1) = cell_span(xi, xj, ti, tj, 1e-6);
    t0 <= t1 && z > lowest_on(t0, t1, zs, zt) - 1e-9
}

/// Whether a cell of height `z` at offset `(xi, xj)` from the sensor cell certainly blocks the
/// sight line to the target at offset `(ti, tj)` (see [`touches_sight_line`]): the segment
/// crosses the cell's interior over more than 1e-6 of its length and dips more than 1e-9 m
/// below `z` there. [`ray_clear_in`] then reports the line blocked, whatever the rounding of
/// its traversal. The cell must be neither the sensor's nor the target's.
#[inline]
pub(super) fn crosses_below(xi: i32, xj: i32, ti: i32, tj: i32, z: f64, zs: f64, zt: f64) -> bool {
    let (t0, t1) = cell_span(xi, xj, ti, tj, 0.0);
    t1 - t0 > 1e-6 && z > lowest_on(t0, t1, zs, zt) + 1e-9
}

/// The parameter interval `[t0, t1]` ⊂ [0, 1] of the segment from the sensor cell's centre
/// (0, 0) to the target's centre `(ti, tj)` (cell units) inside the cell at `(xi, xj)` grown by
/// `grow` cells on every side; `t0 > t1` when they do not meet.
#[inline]
fn cell_span(xi: i32, xj: i32, ti: i32, tj: i32, grow: f64) -> (f64, f64) {
    let h = 0.5 + grow;
    let (x, y) = (xi as f64, xj as f64);
    box_interval(
        Point2::new(0.0, 0.0),
        ti as f64,
        tj as f64,
        Point2::new(x - h, y - h),
        Point2::new(x + h, y + h),
    )
}

/// The segment's lowest height over `[t0, t1]` (heights `zs` at 0 and `zt` at 1): linear, so
/// at an end of the interval.
#[inline]
fn lowest_on(t0: f64, t1: f64, zs: f64, zt: f64) -> f64 {
    zs + (zt - zs) * if zt < zs { t1 } else { t0 }
}
