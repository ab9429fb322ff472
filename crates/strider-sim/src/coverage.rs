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
/// Non-positive or non-finite `lane_spacing` is taken as one cell.
pub fn coverage_path(
    world: &World,
    robot: &RobotProfile,
    start: Pose2,
    lane_spacing: f64,
) -> Vec<Point2> {
    let d = world.resolution;
    let (w, h) = (world.rect.width as usize, world.rect.height as usize);
    let adm = admissible_cells(world, robot);
    let centre = |k: usize| world.rect.cell(k).center(d);
    let Some(s) = nearest_admissible(world, &adm, start.position()) else {
        return vec![start.position()];
    };

    // The reachable component.
    let grid = Grid { w, h, ok: &adm };
    let mut comp = vec![false; w * h];
    let mut stack = vec![s];
    comp[s] = true;
    let mut nb = Vec::with_capacity(8);
    while let Some(k) = stack.pop() {
        grid.neighbours(k, &mut nb);
        for &(n, _) in &nb {
            if !comp[n] {
                comp[n] = true;
                stack.push(n);
            }
        }
    }

    // Lanes along the longer axis of the component's bounding box.
    let (mut x0, mut x1, mut y0, mut y1) = (usize::MAX, 0, usize::MAX, 0);
    for k in (0..w * h).filter(|&k| comp[k]) {
        let (x, y) = (k % w, k / w);
        (x0, x1, y0, y1) = (x0.min(x), x1.max(x), y0.min(y), y1.max(y));
    }
    let along_x = x1 - x0 >= y1 - y0;
    let step = if lane_spacing.is_finite() && lane_spacing > 0.0 {
        ((lane_spacing / d).round() as usize).max(1)
    } else {
        1
    };
    let (lane_lo, lane_hi, pos_lo, pos_hi) = if along_x {
        (y0, y1, x0, x1)
    } else {
        (x0, x1, y0, y1)
    };
    let index = |lane: usize, pos: usize| {
        if along_x {
            lane * w + pos
        } else {
            pos * w + lane
        }
    };
    let mut targets = Vec::new();
    let mut lane = lane_lo + step / 2;
    while lane <= lane_hi {
        let mut pos = pos_lo;
        while pos <= pos_hi {
            if comp[index(lane, pos)] {
                let a = pos;
                while pos < pos_hi && comp[index(lane, pos + 1)] {
                    pos += 1;
                }
                targets.push(Target::Run(index(lane, a), index(lane, pos)));
            }
            pos += 1;
        }
        lane += step;
    }

    // Cells left uncovered by the lanes get waypoints of their own.
    let radius = if lane_spacing.is_finite() && lane_spacing > 0.0 {
        lane_spacing / 2.0
    } else {
        d / 2.0
    };
    let disc = disc_offsets(radius, d);
    let mut covered = vec![false; w * h];
    let stamp = |covered: &mut [bool], k: usize| {
        let (x, y) = ((k % w) as i64, (k / w) as i64);
        for &(dx, dy) in &disc {
            let (nx, ny) = (x + dx as i64, y + dy as i64);
            if nx >= 0 && ny >= 0 && nx < w as i64 && ny < h as i64 {
                covered[ny as usize * w + nx as usize] = true;
            }
        }
    };
    for t in &targets {
        if let Target::Run(a, b) = *t {
            let (la, lb) = (
                if along_x { a % w } else { a / w },
                if along_x { b % w } else { b / w },
            );
            let lane = if along_x { a / w } else { a % w };
            for p in la..=lb {
                stamp(&mut covered, index(lane, p));
            }
        }
    }
    for k in 0..w * h {
        if comp[k] && !covered[k] {
            targets.push(Target::Point(k));
            stamp(&mut covered, k);
        }
    }

    // Chain the pieces greedily by path length.
    const NONE: u32 = u32::MAX;
    let mut endpoint = vec![NONE; w * h];
    for (i, t) in targets.iter().enumerate() {
        match *t {
            Target::Run(a, b) => {
                endpoint[a] = i as u32;
                endpoint[b] = i as u32;
            }
            Target::Point(k) => endpoint[k] = i as u32,
        }
    }
    let mut cells: Vec<usize> = vec![s];
    let mut cur = s;
    let mut left = targets.len();
    let mut dist = vec![u32::MAX; w * h];
    let mut parent = vec![usize::MAX; w * h];
    let mut touched: Vec<usize> = Vec::new();
    while left > 0 {
        // Dijkstra from `cur` until the nearest endpoint of a remaining piece.
        for &k in &touched {
            dist[k] = u32::MAX;
            parent[k] = usize::MAX;
        }
        touched.clear();
        let mut heap = BinaryHeap::new();
        dist[cur] = 0;
        touched.push(cur);
        heap.push(Reverse((0u32, cur)));
        let mut found = None;
        while let Some(Reverse((dk, k))) = heap.pop() {
            if dk > dist[k] {
                continue;
            }
            if endpoint[k] != NONE {
                found = Some(k);
                break;
            }
            grid.neighbours(k, &mut nb);
            for &(n, c) in &nb {
                let nd = dk + c;
                if nd < dist[n] {
                    if dist[n] == u32::MAX {
                        touched.push(n);
                    }
                    dist[n] = nd;
                    parent[n] = k;
                    heap.push(Reverse((nd, n)));
                }
            }
        }
        let Some(entry) = found else {
            break; // cannot happen: every piece lies in the component
        };
        let mut back = vec![entry];
        while let Some(&k) = back.last() {
            if k == cur {
                break;
            }
            back.push(parent[k]);
        }
        back.pop(); // `cur` is already on the path
        cells.extend(back.into_iter().rev());
        let t = endpoint[entry] as usize;
        cur = match targets[t] {
            Target::Run(a, b) => {
                endpoint[a] = NONE;
                endpoint[b] = NONE;
                let exit = if entry == a { b } else { a };
                if exit != entry {
                    cells.push(exit);
                }
                exit
            }
            Target::Point(k) => {
                endpoint[k] = NONE;
                k
            }
        };
        left -= 1;
    }

    // Cells → waypoints, dropping points in the middle of straight stretches.
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
        .map(|i| centre(cells[i]))
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
