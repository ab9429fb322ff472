//! Casting the rays of one azimuth column of an omnidirectional sensor together.
//!
//! The rays of a column leave one origin in one horizontal direction at different slopes, so in
//! plan view they cross the same cells, and a steeper-upward ray is never below a flatter one at
//! the same horizontal distance: the flatter ray meets the terrain first. One walk along the
//! column's horizontal line ([`stations`](super::stations): the cells it crosses, each with the
//! highest column of its 3 × 3 neighbourhood) finds, for the rays in order of slope, the first
//! cell each ray may not pass above; it only moves outward from ray to ray. A ray that passes
//! above every cell within its range is a miss.
//!
//! Each other ray gets exactly [`Heightfield::cast_unit`]'s result: proven from that cell on
//! when its hit holds with margins (on a top face from the line alone, [`line_proof`]; on a side
//! face with the distance its walk accumulates, [`side_hit`]), else by its own walk, which takes
//! every step (its boundary distances accumulate step by step, so it cannot be restarted from
//! scratch mid-way without changing their last bits) but does not look at the cells it leaves
//! before that cell ([`Walk::coast`]).
//!
//! [`line_proof`]: super::line_proof
//! [`side_hit`]: super::side_hit
//!
//! The rays do not share the horizontal direction exactly (each direction is rounded on its
//! own), and walks round distances; the neighbourhood maximum and a quarter-cell margin along
//! the line absorb these deviations, which the checks below keep far smaller (a ray that
//! deviates more, or is too steep to bound, is cast on its own).

use strider_core::Point3;

use super::line_proof::OnLine;
use super::stations::{Near, Stations, Stretch};
use super::{Heightfield, RayHit, Walk};

/// Margin along the column's line, in cells: the stretches a ray passes above are taken a
/// quarter cell longer on both sides.
const MARGIN_CELLS: f64 = 0.25;
/// Largest sine of the horizontal angle between a ray cast with the column and the column's
/// line, times the line's reach, in cells: such a ray stays within a tenth of a cell of the line
/// (the angle is under π/2 times its sine).
const MAX_DEVIATION_CELLS: f64 = 1.0 / 16.0;
/// Largest distance from the world's corner plus reach, in cells, of a column: below it the
/// rounding of a walk's distances (relative 1e-16 per step, one step per cell) stays far below
/// the margin.
const MAX_SPAN_CELLS: f64 = 1e7;
/// Steepest slope (vertical over horizontal) of a ray cast with the column: steeper rays cross
/// one or two cells, and their heights far from the origin would round too coarsely.
const MAX_SLOPE: f64 = 1e6;
/// Height margin relative to the heights involved (1 + |z| + range + cell): a ray passes above
/// a cell only when higher than its top by this much, far more than the rounding of the
/// heights computed along a walk or here.
const HEIGHT_MARGIN: f64 = 1e-8;

impl Heightfield {
    /// Casts rays from `origin` that share (up to rounding) one horizontal direction, such as
    /// an omnidirectional sensor's azimuth column, each along its unit direction in `dirs` up
    /// to `max_range`: `hits[k]` is exactly `self.cast_unit(origin, dirs[k], max_range)` (`hits`
    /// is cleared and refilled). Rays that do not share the direction closely enough are cast
    /// one by one.
    pub fn cast_column(
        &self,
        origin: Point3,
        dirs: &[[f64; 3]],
        max_range: f64,
        hits: &mut Vec<Option<RayHit>>,
    ) {
        hits.clear();
        hits.resize(dirs.len(), None);
        let Some(line) = Line::new(self, origin, dirs, max_range) else {
            for (hit, &u) in hits.iter_mut().zip(dirs) {
                *hit = self.cast_unit(origin, u, max_range);
            }
            return;
        };
        let beams = self.beams(&line, origin, dirs, max_range, hits);
        let mut sweep = Sweep::new(line.stations(self.near_max()));
        for beam in &beams {
            let clear_to = sweep.clear_to(&line, beam);
            if clear_to < beam.reach {
                let ray = (origin, dirs[beam.k], max_range);
                hits[beam.k] = self.resolve(&line, beam, ray, &sweep, clear_to);
            }
        }
    }

    /// The rays of `dirs` that follow `line`, in order of slope; the others are cast one by
    /// one into `hits`.
    fn beams(
        &self,
        line: &Line,
        origin: Point3,
        dirs: &[[f64; 3]],
        max_range: f64,
        hits: &mut [Option<RayHit>],
    ) -> Vec<Beam> {
        let mut beams = Vec::with_capacity(dirs.len());
        for (k, u) in dirs.iter().enumerate() {
            match line.beam(k, u, max_range) {
                Some(beam) => beams.push(beam),
                None => hits[k] = self.cast_unit(origin, *u, max_range),
            }
        }
        // A sensor's rows come in order of elevation.
        if !beams.is_sorted_by(|a, b| a.m <= b.m) {
            beams.sort_unstable_by(|a, b| a.m.total_cmp(&b.m));
        }
        beams
    }

    /// The hit of `beam`, ray `(origin, u, max_range)`, which passes above the line before
    /// horizontal distance `clear_to` (the sweep's current cell): proven from there, else by
    /// its own walk, which does not look at the cells before.
    fn resolve(
        &self,
        line: &Line,
        beam: &Beam,
        (origin, u, max_range): (Point3, [f64; 3], f64),
        sweep: &Sweep,
        clear_to: f64,
    ) -> Option<RayHit> {
        let proven = match line.prove_on_line(self, beam, u, max_range, &sweep.stations) {
            OnLine::Top(hit) => Some(hit),
            OnLine::Side { cell, axis } => {
                self.prove_side_hit(origin, u, max_range, line.span, (cell, axis))
            }
            OnLine::Unsure => None,
        };
        proven.or_else(|| {
            let t_stop = if sweep.cleared {
                clear_to / beam.c
            } else {
                f64::NEG_INFINITY
            };
            self.cast_coasting(origin, u, max_range, t_stop)
        })
    }

    /// [`Self::cast_unit`] for a ray known to pass above every column it crosses before
    /// distance `t_stop`.
    fn cast_coasting(
        &self,
        origin: Point3,
        u: [f64; 3],
        max_range: f64,
        t_stop: f64,
    ) -> Option<RayHit> {
        let mut walk = Walk::start(self, origin, u, max_range)?;
        walk.coast(t_stop)?;
        walk.run()
    }

    /// The neighbourhood maxima, built by the first column cast.
    fn near_max(&self) -> &Near {
        self.near_max.get_or_init(|| Near::new(self))
    }
}

/// The walk along the line for the rays in order of slope: it stops at the first cell the
/// current ray may not pass above, and goes on from there for the next ray.
struct Sweep<'a> {
    stations: Stations<'a>,
    /// Whether the line before the current cell is known to be passed above (nothing is known
    /// before the first cell when the line starts in the grown grid, not even of a cell a ray
    /// leaves at distance 0; before a later first cell, nothing is near).
    cleared: bool,
}

impl<'a> Sweep<'a> {
    fn new(stations: Stations<'a>) -> Self {
        let cleared = stations.current().is_none_or(|s| s.a > 0.0);
        Self { stations, cleared }
    }

    /// Moves on past the cells `beam` passes above (whole blocks where it can) and returns
    /// where the line enters the first one it may not (∞ past the line's end). The cells
    /// before were passed above by a flatter ray, hence by this one.
    fn clear_to(&mut self, line: &Line, beam: &Beam) -> f64 {
        loop {
            if let Some(block) = self.stations.block()
                && block.a < beam.reach
                && line.passes_above(beam, &block)
            {
                self.stations.skip_block();
                self.cleared = true;
                continue;
            }
            let Some(s) = self.stations.current() else {
                return f64::INFINITY;
            };
            if s.a >= beam.reach || !line.passes_above(beam, &s) {
                return s.a;
            }
            self.stations.advance();
            self.cleared = true;
        }
    }
}

/// A ray of the column: its index in the caller's slice, horizontal length of its unit
/// direction, slope, horizontal reach and sine of its horizontal angle to the line.
pub(super) struct Beam {
    k: usize,
    pub(super) c: f64,
    pub(super) m: f64,
    reach: f64,
    pub(super) deviation: f64,
}

/// The column's horizontal line in the local frame of the grid grown by one cell (the world
/// rectangle spans `[d, W + d] × [d, H + d]`), with the margins of the test.
pub(super) struct Line {
    pub(super) d: f64,
    /// Columns and rows of the grown grid.
    n: [i64; 2],
    /// Origin and unit horizontal direction, and the reciprocals of the direction's components'
    /// magnitudes.
    pub(super) o: [f64; 2],
    pub(super) oz: f64,
    g: [f64; 2],
    pub(super) inv_g: [f64; 2],
    /// The origin in the walk's local frame, and that frame's offset from the world's.
    pub(super) walk_origin: [f64; 2],
    pub(super) walk_shift: [f64; 2],
    /// How far along the line stations are needed: the longest horizontal reach of a ray.
    reach: f64,
    /// Bound on the local coordinates along the rays' paths (|x| + |y| + reach).
    span: f64,
    /// Largest sine of the angle between a ray's horizontal direction and the line's.
    max_deviation: f64,
    /// Margins along the line and in height.
    margin: f64,
    pub(super) height_margin: f64,
    /// Bounds on the rounding of a boundary crossing's distance across each axis (the line's
    /// and a ray walk's).
    pub(super) rounding: [f64; 2],
    /// Whether the origin lies in the grown grid, inside its cell farther from the boundaries
    /// than rounding can move it: then the line's cells are the rays' (up to crossings).
    pub(super) starts_inside: bool,
}

impl Line {
    /// The line of the rays in `dirs` from `origin`; `None` when the column cannot bound its
    /// rays (they are then cast one by one).
    fn new(hf: &Heightfield, origin: Point3, dirs: &[[f64; 3]], max_range: f64) -> Option<Self> {
        let d = hf.resolution;
        let (w, h) = (hf.rect.width as i64, hf.rect.height as i64);
        let finite = origin.x.is_finite() && origin.y.is_finite() && origin.z.is_finite();
        if !(finite && max_range > 0.0 && max_range.is_finite() && w > 0 && h > 0) {
            return None;
        }
        let walk_shift = [hf.rect.min.i as f64 * d, hf.rect.min.j as f64 * d];
        let walk_origin = [origin.x - walk_shift[0], origin.y - walk_shift[1]];
        let o = [walk_origin[0] + d, walk_origin[1] + d];
        // The flattest ray, whose horizontal direction is the most accurate, gives the line.
        let (g, c_max) = dirs
            .iter()
            .map(|u| (u, horizontal(u)))
            .filter(|(_, c)| c.is_finite())
            .max_by(|a, b| a.1.total_cmp(&b.1))
            .map(|(u, c)| ([u[0] / c, u[1] / c], c))?;
        if !(c_max > 0.0 && g[0].is_finite() && g[1].is_finite()) {
            return None;
        }
        let reach = c_max * max_range + d;
        let span = o[0].abs() + o[1].abs() + reach + d;
        let bounded = span / d <= MAX_SPAN_CELLS;
        if !bounded {
            return None;
        }
        let inv_g = [1.0 / g[0].abs(), 1.0 / g[1].abs()];
        // One rounding per crossing along a walk (at most two per cell of the span, plus the
        // re-entries after block passes), relative to the distances involved, generously.
        let crossings = 2.0 * span / d + 64.0;
        let rounding_pos = 16.0 * f64::EPSILON * crossings * span;
        let inside = |o: f64, n: i64| {
            let frac = o / d - (o / d).floor();
            o >= 0.0 && o < n as f64 * d && frac * d > rounding_pos && d - frac * d > rounding_pos
        };
        let starts_inside = inside(o[0], w + 2) && inside(o[1], h + 2);
        let rounding = inv_g.map(|r| 16.0 * f64::EPSILON * crossings * (span * r + max_range));
        Some(Self {
            d,
            n: [w + 2, h + 2],
            o,
            oz: origin.z,
            g,
            inv_g,
            walk_origin,
            walk_shift,
            reach,
            span,
            max_deviation: MAX_DEVIATION_CELLS * d / reach,
            margin: MARGIN_CELLS * d,
            height_margin: HEIGHT_MARGIN * (1.0 + origin.z.abs() + max_range + d),
            rounding,
            starts_inside,
        })
    }

    /// Ray `k` along unit `u` up to `max_range` as a beam of the column, if it follows the
    /// line closely enough and is not too steep.
    fn beam(&self, k: usize, u: &[f64; 3], max_range: f64) -> Option<Beam> {
        let c = horizontal(u);
        if !(c > 0.0 && u[2].abs() <= MAX_SLOPE * c) {
            return None;
        }
        // Sine of the angle to the line (and the same way along it), times c.
        let across = u[0] * self.g[1] - u[1] * self.g[0];
        let along = u[0] * self.g[0] + u[1] * self.g[1];
        let follows = along > 0.0 && across.abs() <= self.max_deviation * c;
        follows.then(|| Beam {
            k,
            c,
            m: u[2] / c,
            reach: c * max_range,
            deviation: across.abs() / c,
        })
    }

    /// True when `beam` stays higher than the stretch's top (with the margins) all along the
    /// stretch, grown by the margin on both sides.
    #[inline(always)]
    fn passes_above(&self, beam: &Beam, s: &Stretch) -> bool {
        // The lowest point of a straight ray over an interval is at one of its ends.
        let at = if beam.m < 0.0 {
            s.b + self.margin
        } else {
            (s.a - self.margin).max(0.0)
        };
        self.oz + beam.m * at > s.top + self.height_margin
    }

    /// The walk along the line, on the grown grid with its neighbourhood maxima `near`.
    fn stations<'a>(&self, near: &'a Near) -> Stations<'a> {
        Stations::new(near, self.d, self.n, self.o, self.g, self.reach)
    }
}

/// The horizontal length of a unit direction.
#[inline]
fn horizontal(u: &[f64; 3]) -> f64 {
    (u[0] * u[0] + u[1] * u[1]).sqrt()
}
