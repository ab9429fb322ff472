//! A ray's hit found along the column's line, without any walk of the ray.
//!
//! Beyond the stretch of the line a ray is known to pass above, the ray crosses the same cells
//! as the line, in the same order, where the line's boundary crossings are farther apart than
//! the ray's crossings can differ from them (its small angle to the line, and rounding); this
//! holds when the line starts clearly inside a cell. Over those cells a straight ray's height
//! is known at both ends, so its walk's tests come out as here when they hold with a margin:
//! above a cell's top throughout (the walk moves on), or entering above the top and leaving
//! below it, at `(top − z0) / u_z` clearly inside the cell (the walk's hit, which its clamp to
//! the cell's distances leaves alone): one division per ray instead of a walk. A ray clearly
//! entering a cell below its top hits the side face it crossed, at its walk's accumulated
//! distance, which [`Heightfield::prove_side_hit`] sums. Anything closer to call is left to
//! the ray's own walk.

use strider_core::{Cell, Point3};

use super::columns::{Beam, Line};
use super::stations::Stations;
use super::{Face, Heightfield, RayHit};

/// Cells of the line a proof looks at before it gives up.
const MAX_CELLS: usize = 32;

/// What [`Line::prove_on_line`] found.
pub(super) enum OnLine {
    /// The walk's hit, on a top face.
    Top(RayHit),
    /// The walk hits the side of world cell `cell`, entered across `axis` (0: x, 1: y).
    Side { cell: [i64; 2], axis: usize },
    /// Too close to call.
    Unsure,
}

impl Line {
    /// The hit of descending `beam` (unit direction `u`, range `max_range`) when it lies within
    /// [`MAX_CELLS`] cells from the line's current cell `at` (before which the ray passes above
    /// every column) and every test holds with a margin.
    pub(super) fn prove_on_line(
        &self,
        hf: &Heightfield,
        beam: &Beam,
        u: [f64; 3],
        max_range: f64,
        at: &Stations,
    ) -> OnLine {
        match self.walk_line(hf, beam, u, max_range, at) {
            Some(found) => found,
            None => OnLine::Unsure,
        }
    }

    /// [`Self::prove_on_line`], `None` when unsure.
    fn walk_line(
        &self,
        hf: &Heightfield,
        beam: &Beam,
        u: [f64; 3],
        max_range: f64,
        at: &Stations,
    ) -> Option<OnLine> {
        if !(beam.m < 0.0 && self.starts_inside) {
            return None;
        }
        let mut cell = at.cursor()?;
        let (w, h) = (hf.rect.width as i64, hf.rect.height as i64);
        // The first cell's entry must also lie clearly after the last crossing across the
        // other axis (later cells' entries are checked as the exits of the cells before).
        let mut ea = 0.0;
        if let Some(k) = cell.entry {
            let before = at.last_crossing(1 - k);
            ea = self.crossing_slack(beam, k, cell.a);
            let after = cell.a - ea > before + self.crossing_slack(beam, 1 - k, before.max(0.0));
            if !after {
                return None;
            }
        }
        for _ in 0..MAX_CELLS {
            // The world cell under this cell of the grown grid; off the world, unsure.
            let [i, j] = cell.i.map(|i| i - 1);
            if !(0..w).contains(&i) || !(0..h).contains(&j) {
                return None;
            }
            // The ray enters and leaves the cell within `ea`, `eb` of the line.
            let (sb, exit) = cell.exit();
            let eb = self.crossing_slack(beam, exit?, sb);
            let (a, b) = (cell.a + ea, sb - eb);
            let ordered = a < b;
            if !ordered {
                return None;
            }
            let k = (j * w + i) as usize;
            let top = hf.elevation[k];
            if top != f64::NEG_INFINITY {
                let margin = self.height_margin + 8.0 * f64::EPSILON * top.abs();
                let z = |s: f64| self.oz + beam.m * s;
                let above = z(sb + eb) > top + margin;
                if !above {
                    // Into the side: entered across `entry` below the top.
                    if let Some(axis) = cell.entry
                        && z(cell.a - ea) < top - margin
                    {
                        return Some(OnLine::Side { cell: [i, j], axis });
                    }
                    // In at `a` above the top, out at `b` below it: the hit lies inside.
                    if !(z(a) > top + margin && z(b) < top - margin) {
                        return None;
                    }
                    let t = (top - self.oz) / u[2];
                    let inside = beam.c * t > a && beam.c * t < b && t < max_range;
                    if !inside {
                        return None;
                    }
                    // As the walk computes it: in its local frame, then shifted.
                    let (o, x0) = (self.walk_origin, self.walk_shift);
                    let p = [o[0] + u[0] * t + x0[0], o[1] + u[1] * t + x0[1]];
                    let point = Point3::new(p[0], p[1], top);
                    return Some(OnLine::Top(hit(hf, [i, j], k, point, t)));
                }
            }
            cell.advance();
            ea = eb;
        }
        None
    }

    /// How far (horizontally) the ray's crossing of a boundary across `axis` at distance `s`
    /// along the line may lie from the line's: its angle to the line stretched by the
    /// crossing's obliqueness, plus rounding.
    #[inline]
    fn crossing_slack(&self, beam: &Beam, axis: usize, s: f64) -> f64 {
        // The ray's direction component across `axis` differs from the line's by at most its
        // angle (under π/2 times its sine); while that is under a fifth of the line's
        // component, the crossing moves by under twice `s` times sine over component.
        let stretch = beam.deviation * self.inv_g[axis];
        if stretch <= 0.125 {
            self.rounding[axis] + 2.0 * s * stretch
        } else {
            f64::INFINITY
        }
    }
}

/// A top-face hit at world point `p` and distance `range` in world cell `[i, j]` (layer index
/// `k`), as the walk reports it.
fn hit(hf: &Heightfield, [i, j]: [i64; 2], k: usize, p: Point3, range: f64) -> RayHit {
    let min = hf.rect.min;
    RayHit {
        point: p,
        range,
        cell: Cell::new(min.i + i as i32, min.j + j as i32),
        index: k,
        face: Face::Top,
    }
}
