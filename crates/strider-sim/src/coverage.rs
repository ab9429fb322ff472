//! A scripted driving harness: coverage paths over the ground-truth admissible area and the
//! ground truth of which cells a sensor could see from a set of poses.
//!
//! This is a *test harness*, not an algorithm of the autonomy stack: it reads the world's true
//! elevation. `strider map build` drives the simulated robot along [`coverage_path`] to build a
//! map, and [`visible_cells`] is the reference for the map's `observed_fraction`.
//!
//! Admissibility is the map's rule, not ours: [`strider_map::passability::dense_passability`] on
//! the world's elevation with ρ_obstacle = the robot's `max_step_m`, inflated by its footprint
//! radius with [`strider_map::passability::dense_admissible`] (decision 4).

use std::cmp::Reverse;
use std::collections::BinaryHeap;

use rayon::prelude::*;
use strider_core::grid::disc_offsets;
use strider_core::{Point2, Point3, Pose2};
use strider_map::passability::{dense_admissible, dense_passability};
use strider_scenario::{RobotProfile, SensorSpec, World};

use crate::heightfield::Heightfield;
use crate::sensor::RangeSensor;

/// Ground-truth admissibility of every world cell for `robot` (row-major over `world.rect`).
pub fn admissible_cells(world: &World, robot: &RobotProfile) -> Vec<bool> {
    let (w, h) = (world.rect.width as usize, world.rect.height as usize);
    if world.elevation.len() != w * h {
        return vec![false; w * h];
    }
    let pass = dense_passability(&world.elevation, None, w, h, robot.max_step_m);
    dense_admissible(&pass, w, h, robot.footprint_radius, world.resolution)
}

/// Dense grid helper: 8-connected moves without corner cutting over a mask.
struct Grid<'a> {
    w: usize,
    h: usize,
    ok: &'a [bool],
}

/// Move costs (orthogonal, diagonal), integer so the search is exact.
const COST_ORTHO: u32 = 10;
const COST_DIAG: u32 = 14;

impl Grid<'_> {
    /// Neighbours of `k` reachable in one move, with their costs.
    fn neighbours(&self, k: usize, out: &mut Vec<(usize, u32)>) {
        out.clear();
        let (x, y) = ((k % self.w) as i64, (k / self.w) as i64);
        let at = |dx: i64, dy: i64| -> Option<usize> {
            let (nx, ny) = (x + dx, y + dy);
            (nx >= 0 && ny >= 0 && nx < self.w as i64 && ny < self.h as i64)
                .then(|| ny as usize * self.w + nx as usize)
                .filter(|&n| self.ok[n])
        };
        for (dx, dy) in [(1, 0), (-1, 0), (0, 1), (0, -1)] {
            if let Some(n) = at(dx, dy) {
                out.push((n, COST_ORTHO));
            }
        }
        for (dx, dy) in [(1, 1), (-1, 1), (-1, -1), (1, -1)] {
            if let (Some(n), Some(_), Some(_)) = (at(dx, dy), at(dx, 0), at(0, dy)) {
                out.push((n, COST_DIAG));
            }
        }
    }
}

/// A piece of the coverage plan: a straight lane run (entered at either end) or a single cell.
#[derive(Clone, Copy, Debug)]
enum Target {
    Run(usize, usize),
    Point(usize),
}

/// A boustrophedon coverage path over the admissible area reachable from `start`.
///
/// Lanes `lane_spacing` apart run along the longer axis of the reachable admissible region; each
/// maximal straight run of reachable admissible cells on a lane is driven end to end. Cells not
/// within `lane_spacing / 2` of any run get a visiting waypoint of their own. The pieces are
/// chained greedily (always the one nearest by path length) and connected by shortest
/// 8-connected paths without corner cutting over admissible cells, so consecutive waypoints are
/// joined by straight segments over admissible cells only. Every reachable admissible cell lies
/// within `lane_spacing / 2` of a waypoint or lane run.
///
/// The path starts at the centre of the start cell (or of the nearest admissible cell when the
/// start is not admissible). A world without admissible cells gives just the start position.
/// Non-positive or non-finite `lane_spacing` is taken as one cell, and one wider than the
/// world's diagonal as the diagonal (one lane or point then covers everything within it, and
/// the coverage disc stays the size of the world).
pub fn coverage_path(
    world: &World,
    robot: &RobotProfile,
    start: Pose2,
    lane_spacing: f64,
) -> Vec<Point2> {
    let d = world.resolution;
    let (w, h) = (world.rect.width as usize, world.rect.height as usize);
    let adm = admissible_cells(world, robot);
    let Some(s) = nearest_admissible(world, &adm, start.position()) else {
        return vec![start.position()];
    };
    let grid = Grid { w, h, ok: &adm };
    let comp = grid.component(s);
    let spacing_ok = lane_spacing.is_finite() && lane_spacing > 0.0;
    let diagonal = (w as f64).hypot(h as f64) * d;
    let lane_spacing = lane_spacing.min(diagonal);
    let step = if spacing_ok {
        ((lane_spacing / d).round() as usize).max(1)
    } else {
        1
    };
    let lanes = Lanes::along_longer_axis(&comp, w);
    let mut targets = lanes.runs(&comp, step);
    let radius = if spacing_ok {
        lane_spacing / 2.0
    } else {
        d / 2.0
    };
    lanes.cover_the_rest(&comp, &mut targets, &disc_offsets(radius, d), h);
    let cells = grid.chain(s, &targets);
    straight_stretches_merged(cells, w)
        .into_iter()
        .map(|k| world.rect.cell(k).center(d))
        .collect()
}

impl Grid<'_> {
    /// The cells 8-connected to `s` (without corner cutting).
    fn component(&self, s: usize) -> Vec<bool> {
        let mut comp = vec![false; self.w * self.h];
        let mut stack = vec![s];
        comp[s] = true;
        let mut nb = Vec::with_capacity(8);
        while let Some(k) = stack.pop() {
            self.neighbours(k, &mut nb);
            for &(n, _) in &nb {
                if !comp[n] {
                    comp[n] = true;
                    stack.push(n);
                }
            }
        }
        comp
    }

    /// The cells of a path from `s` through every piece of `targets`, always going next to the
    /// piece nearest by path length (shortest 8-connected paths, runs driven end to end).
    fn chain(&self, s: usize, targets: &[Target]) -> Vec<usize> {
        let n = self.w * self.h;
        let mut endpoint = vec![NO_TARGET; n];
        for (i, t) in targets.iter().enumerate() {
            match *t {
                Target::Run(a, b) => {
                    endpoint[a] = i as u32;
                    endpoint[b] = i as u32;
                }
                Target::Point(k) => endpoint[k] = i as u32,
            }
        }
        let mut search = Search::new(n);
        let mut cells: Vec<usize> = vec![s];
        let mut cur = s;
        for _ in 0..targets.len() {
            let Some(entry) = search.nearest_endpoint(self, cur, &endpoint) else {
                break; // cannot happen: every piece lies in the component
            };
            cells.extend(search.path_to(entry, cur));
            cur = match targets[endpoint[entry] as usize] {
                Target::Run(a, b) => {
                    endpoint[a] = NO_TARGET;
                    endpoint[b] = NO_TARGET;
                    let exit = if entry == a { b } else { a };
                    if exit != entry {
                        cells.push(exit);
                    }
                    exit
                }
                Target::Point(k) => {
                    endpoint[k] = NO_TARGET;
                    k
                }
            };
        }
        cells
    }
}

/// No piece of the plan ends at this cell.
const NO_TARGET: u32 = u32::MAX;

/// Dijkstra state reused between searches (only the cells a search touched are reset).
struct Search {
    dist: Vec<u32>,
    parent: Vec<usize>,
    touched: Vec<usize>,
    nb: Vec<(usize, u32)>,
}

impl Search {
    fn new(n: usize) -> Self {
        Self {
            dist: vec![u32::MAX; n],
            parent: vec![usize::MAX; n],
            touched: Vec::new(),
            nb: Vec::with_capacity(8),
        }
    }

    /// The cell nearest to `from` by path length where a remaining piece ends.
    fn nearest_endpoint(
        &mut self,
        grid: &Grid<'_>,
        from: usize,
        endpoint: &[u32],
    ) -> Option<usize> {
        for &k in &self.touched {
            self.dist[k] = u32::MAX;
            self.parent[k] = usize::MAX;
        }
        self.touched.clear();
        let mut heap = BinaryHeap::new();
        self.dist[from] = 0;
        self.touched.push(from);
        heap.push(Reverse((0u32, from)));
        while let Some(Reverse((dk, k))) = heap.pop() {
            if dk > self.dist[k] {
                continue;
            }
            if endpoint[k] != NO_TARGET {
                return Some(k);
            }
            grid.neighbours(k, &mut self.nb);
            for &(n, c) in &self.nb {
                let nd = dk + c;
                if nd < self.dist[n] {
                    if self.dist[n] == u32::MAX {
                        self.touched.push(n);
                    }
                    self.dist[n] = nd;
                    self.parent[n] = k;
                    heap.push(Reverse((nd, n)));
                }
            }
        }
        None
    }

    /// The cells of the last search's path from `from` to `to`, without `from`.
    fn path_to(&self, to: usize, from: usize) -> impl Iterator<Item = usize> + use<> {
        let mut back = vec![to];
        while let Some(&k) = back.last() {
            if k == from {
                break;
            }
            back.push(self.parent[k]);
        }
        back.pop(); // `from` is already on the path
        back.into_iter().rev()
    }
}

/// Boustrophedon lanes over a component: lanes run along `pos`, one every `step` along `lane`.
struct Lanes {
    along_x: bool,
    w: usize,
    lane_lo: usize,
    lane_hi: usize,
    pos_lo: usize,
    pos_hi: usize,
}

impl Lanes {
    /// Lanes along the longer axis of the component's bounding box.
    fn along_longer_axis(comp: &[bool], w: usize) -> Self {
        let (mut x0, mut x1, mut y0, mut y1) = (usize::MAX, 0, usize::MAX, 0);
        for k in (0..comp.len()).filter(|&k| comp[k]) {
            let (x, y) = (k % w, k / w);
            (x0, x1, y0, y1) = (x0.min(x), x1.max(x), y0.min(y), y1.max(y));
        }
        let along_x = x1 - x0 >= y1 - y0;
        let (lane_lo, lane_hi, pos_lo, pos_hi) = if along_x {
            (y0, y1, x0, x1)
        } else {
            (x0, x1, y0, y1)
        };
        Self {
            along_x,
            w,
            lane_lo,
            lane_hi,
            pos_lo,
            pos_hi,
        }
    }

    /// Layer index of position `pos` on lane `lane`.
    fn index(&self, lane: usize, pos: usize) -> usize {
        if self.along_x {
            lane * self.w + pos
        } else {
            pos * self.w + lane
        }
    }

    /// (lane, position) of layer index `k`.
    fn lane_pos(&self, k: usize) -> (usize, usize) {
        if self.along_x {
            (k / self.w, k % self.w)
        } else {
            (k % self.w, k / self.w)
        }
    }

    /// Every maximal straight run of component cells on every `step`-th lane.
    fn runs(&self, comp: &[bool], step: usize) -> Vec<Target> {
        let mut targets = Vec::new();
        let mut lane = self.lane_lo + step / 2;
        while lane <= self.lane_hi {
            let mut pos = self.pos_lo;
            while pos <= self.pos_hi {
                if comp[self.index(lane, pos)] {
                    let a = pos;
                    while pos < self.pos_hi && comp[self.index(lane, pos + 1)] {
                        pos += 1;
                    }
                    targets.push(Target::Run(self.index(lane, a), self.index(lane, pos)));
                }
                pos += 1;
            }
            lane += step;
        }
        targets
    }

    /// Adds a visiting point for every component cell not within `disc` of a lane run or of an
    /// earlier point (`h`: rows of the layer).
    fn cover_the_rest(
        &self,
        comp: &[bool],
        targets: &mut Vec<Target>,
        disc: &[(i32, i32)],
        h: usize,
    ) {
        let w = self.w;
        let mut covered = vec![false; w * h];
        let stamp = |covered: &mut [bool], k: usize| {
            let (x, y) = ((k % w) as i64, (k / w) as i64);
            for &(dx, dy) in disc {
                let (nx, ny) = (x + dx as i64, y + dy as i64);
                if nx >= 0 && ny >= 0 && nx < w as i64 && ny < h as i64 {
                    covered[ny as usize * w + nx as usize] = true;
                }
            }
        };
        for t in targets.iter() {
            if let Target::Run(a, b) = *t {
                let ((lane, la), (_, lb)) = (self.lane_pos(a), self.lane_pos(b));
                for p in la..=lb {
                    stamp(&mut covered, self.index(lane, p));
                }
            }
        }
        for k in 0..w * h {
            if comp[k] && !covered[k] {
                targets.push(Target::Point(k));
                stamp(&mut covered, k);
            }
        }
    }
}

/// The path's cells without repeats and without the cells in the middle of straight stretches.
fn straight_stretches_merged(mut cells: Vec<usize>, w: usize) -> Vec<usize> {
    cells.dedup();
    let xy: Vec<(i64, i64)> = cells
        .iter()
        .map(|&k| ((k % w) as i64, (k / w) as i64))
        .collect();
    let dir = |a: (i64, i64), b: (i64, i64)| {
        let (dx, dy) = (b.0 - a.0, b.1 - a.1);
        let g = gcd(dx.unsigned_abs(), dy.unsigned_abs()) as i64;
        (dx / g, dy / g)
    };
    (0..cells.len())
        .filter(|&i| {
            i == 0 || i + 1 == cells.len() || dir(xy[i - 1], xy[i]) != dir(xy[i], xy[i + 1])
        })
        .map(|i| cells[i])
        .collect()
}

fn gcd(a: u64, b: u64) -> u64 {
    if b == 0 { a.max(1) } else { gcd(b, a % b) }
}

/// Layer index of the admissible cell nearest to `p` (the cell containing it when admissible).
fn nearest_admissible(world: &World, adm: &[bool], p: Point2) -> Option<usize> {
    if let Some(k) = world.index_at(p).filter(|&k| adm[k]) {
        return Some(k);
    }
    let d = world.resolution;
    (0..adm.len()).filter(|&k| adm[k]).min_by(|&a, &b| {
        let da = world.rect.cell(a).center(d).dist(p);
        let db = world.rect.cell(b).center(d).dist(p);
        da.total_cmp(&db)
    })
}

/// Smallest angle (degrees) between a line of sight and a top surface for that surface to count
/// as seen (incidence at most 89° from its normal).
pub const MIN_GRAZING_DEG: f64 = 1.0;
const MIN_GRAZING_SIN: f64 = 0.017_452_406_437_283_51; // sin(1°)

/// Per world cell (row-major): true when some pose in `poses` sees the centre of the cell's top
/// surface with `sensor`: from above, at least [`MIN_GRAZING_DEG`] above the surface's plane (a
/// top at sensor height shows only its edge),
/// within its range (3-D distance from the sensor), inside its field of view, and with a clear
/// line of sight through the heightfield
/// ([`Heightfield::visible`]). The sensor stands `sensor.height` above the terrain under each
/// pose; poses outside the world are ignored. An invalid world or sensor sees nothing.
///
/// Cost grows with cells × poses (cells never seen are tested against every pose in range):
/// pass the scan poses, not the 20 Hz pose stream.
pub fn visible_cells(world: &World, sensor: &SensorSpec, poses: &[Pose2]) -> Vec<bool> {
    let n = world.rect.len();
    let (Ok(hf), Ok(model)) = (
        Heightfield::from_world(world),
        RangeSensor::new(sensor, "sensor"),
    ) else {
        return vec![false; n];
    };
    let range = sensor.range;
    let origins: Vec<(Point3, f64)> = poses
        .iter()
        .filter_map(|p| {
            let z = hf.elevation_at(p.position())?;
            Some((model.origin(*p, z), p.yaw))
        })
        .collect();
    let d = world.resolution;
    (0..n)
        .into_par_iter()
        .map(|k| {
            let Some(z) = hf.cell_elevation(world.rect.cell(k)) else {
                return false;
            };
            let c = world.rect.cell(k).center(d);
            let target = Point3::new(c.x, c.y, z);
            origins.iter().any(|&(o, yaw)| {
                let v = [target.x - o.x, target.y - o.y, target.z - o.z];
                // A horizontal top surface is seen only from above, and only when the line of
                // sight meets it at least MIN_GRAZING_DEG above its plane: a top at sensor height
                // shows just its edge (and the face beneath it).
                let l2 = v[0] * v[0] + v[1] * v[1] + v[2] * v[2];
                -v[2] >= MIN_GRAZING_SIN * l2.sqrt()
                    && l2 <= range * range
                    && model.in_fov(yaw, v)
                    && hf.visible(o, target)
            })
        })
        .collect()
}
