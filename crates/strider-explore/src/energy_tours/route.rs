//! Planning a tour on the learnt energy map (MartinCorke §3.2).
//!
//! * The planning grid covers the planning area at the map's cell size; cell ν costs
//!   c(ν) = max(μ(ν), 0) + P_h / v J/m: the GP mean of the motive energy per metre (clamped at
//!   zero, since a negative motive energy on flat ground is an artefact of the fit) plus the
//!   hotel load per metre (decision 12). With no hotel load an unseen cell would cost nothing,
//!   which a cost grid refuses, so costs are floored at [`MIN_COST`].
//! * Costs between waypoints: 8-connected Dijkstra from each waypoint ([`Dijkstra`], edge cost =
//!   length × cost of the source cell, decision 21). MartinCorke uses D*, which finds the same cheapest
//!   paths and only saves work when the map changes under a moving robot.
//! * Order: the exact TSP (Held–Karp in [`strider_plan::gtsp`]) from the base, closed or open,
//!   on the costs in microjoules.
//! * Path: each leg's cell path, pulled taut: from each vertex the farthest later vertex is
//!   joined by a straight segment whenever that segment costs no more under the model than
//!   the cell path it replaces (integrated along the segment). An 8-connected staircase is
//!   longer than the line it approximates and makes a skid-steered robot stop and turn at every
//!   kink, which costs energy the model does not see.

use serde::Serialize;
use strider_core::{Cell, CellRect, Point2};
use strider_plan::grid::{CostGrid, Dijkstra, segment_cost_between};
use strider_plan::tsplib::{CostMatrix, Instance};
use strider_plan::{SolverParams, solve};

use super::model::EnergyMap;
use super::{EnergyTourParams, TourError};

/// The most waypoints (base included) the exact TSP solves (the Held–Karp limit of
/// [`strider_plan::gtsp`]).
pub const MAX_WAYPOINTS: usize = 12;

/// Smallest per-metre cost of a planning cell, J/m.
pub const MIN_COST: f64 = 1e-3;

/// Joules to the TSP's integer cost unit (microjoules).
const MICROJOULES: f64 = 1e6;

/// A planned tour.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct PlannedTour {
    /// Waypoint indices in visiting order, starting at the base (0).
    pub order: Vec<usize>,
    /// The polyline to drive: from the base through every waypoint (and back to the base for a
    /// closed tour).
    pub path: Vec<Point2>,
    /// Energy of the path under the model it was planned on, J.
    pub predicted_energy_j: f64,
    /// Length of the path, metres.
    pub length_m: f64,
}

impl PlannedTour {
    /// The largest distance from a point of either path to the other path (symmetric
    /// Hausdorff distance, both paths sampled every `step` metres), metres.
    pub fn deviation_m(&self, other: &PlannedTour, step: f64) -> f64 {
        directed(&self.path, &other.path, step).max(directed(&other.path, &self.path, step))
    }
}

/// Points along a polyline every `step` metres (vertices included).
fn samples(path: &[Point2], step: f64) -> Vec<Point2> {
    let mut out = Vec::new();
    for w in path.windows(2) {
        let n = (w[0].dist(w[1]) / step).ceil().max(1.0) as usize;
        for k in 0..n {
            let f = k as f64 / n as f64;
            out.push(lerp(w[0], w[1], f));
        }
    }
    out.extend(path.last());
    out
}

fn lerp(a: Point2, b: Point2, f: f64) -> Point2 {
    Point2::new(a.x + f * (b.x - a.x), a.y + f * (b.y - a.y))
}

/// Distance from `p` to the segment `ab`.
fn point_segment(p: Point2, a: Point2, b: Point2) -> f64 {
    let (dx, dy) = (b.x - a.x, b.y - a.y);
    let l2 = dx * dx + dy * dy;
    let f = if l2 > 0.0 {
        (((p.x - a.x) * dx + (p.y - a.y) * dy) / l2).clamp(0.0, 1.0)
    } else {
        0.0
    };
    p.dist(lerp(a, b, f))
}

/// max over samples of `a` of the distance to the polyline `b`.
fn directed(a: &[Point2], b: &[Point2], step: f64) -> f64 {
    if a.is_empty() || b.is_empty() {
        return if a.is_empty() && b.is_empty() {
            0.0
        } else {
            f64::INFINITY
        };
    }
    samples(a, step)
        .into_iter()
        .map(|p| {
            if b.len() == 1 {
                p.dist(b[0])
            } else {
                b.windows(2)
                    .map(|w| point_segment(p, w[0], w[1]))
                    .fold(f64::INFINITY, f64::min)
            }
        })
        .fold(0.0, f64::max)
}

/// The task on the planning grid, and reusable search buffers.
#[derive(Debug)]
pub struct TourPlanner {
    rect: CellRect,
    sites: Vec<Cell>,
    points: Vec<Point2>,
    closed: bool,
    dijkstra: Dijkstra,
}

impl TourPlanner {
    /// Checks the waypoints against the planning area: at least two, at most
    /// [`MAX_WAYPOINTS`], finite, inside the area, no two in one cell.
    pub fn new(params: &EnergyTourParams) -> Result<Self, TourError> {
        let d = params.cell_size;
        let (lo, hi) = (params.area_min, params.area_max);
        // Cells whose centre lies inside the area.
        let i0 = (lo.x / d - 0.5).ceil();
        let j0 = (lo.y / d - 0.5).ceil();
        let i1 = (hi.x / d - 0.5).floor();
        let j1 = (hi.y / d - 0.5).floor();
        let area = format!("({:.3}, {:.3})..({:.3}, {:.3})", lo.x, lo.y, hi.x, hi.y);
        if !(i1 >= i0
            && j1 >= j0
            && (i1 - i0) < 1e5
            && (j1 - j0) < 1e5
            && i0.abs() < 1e9
            && j0.abs() < 1e9)
        {
            return Err(TourError::BadParameter {
                name: "area_max",
                value: hi.x.min(hi.y),
                why: "must leave a planning area of at least one cell above area_min (and at most 100000 cells a side)",
            });
        }
        let rect = CellRect::new(
            Cell::new(i0 as i32, j0 as i32),
            (i1 - i0) as u32 + 1,
            (j1 - j0) as u32 + 1,
        );
        let w = &params.waypoints;
        if w.len() < 2 {
            return Err(TourError::TooFewWaypoints(w.len()));
        }
        if w.len() > MAX_WAYPOINTS {
            return Err(TourError::TooManyWaypoints {
                count: w.len(),
                max: MAX_WAYPOINTS,
            });
        }
        let mut sites = Vec::with_capacity(w.len());
        for (index, p) in w.iter().enumerate() {
            if !p.is_finite() {
                return Err(TourError::NonFiniteWaypoint {
                    index,
                    x: p.x,
                    y: p.y,
                });
            }
            let inside = p.x >= lo.x && p.x <= hi.x && p.y >= lo.y && p.y <= hi.y;
            let cell = Cell::containing(p.x, p.y, d).filter(|&c| inside && rect.contains(c));
            let Some(cell) = cell else {
                return Err(TourError::WaypointOutsideArea {
                    index,
                    x: p.x,
                    y: p.y,
                    area,
                });
            };
            if let Some(first) = sites.iter().position(|&c| c == cell) {
                return Err(TourError::DuplicateWaypoint {
                    first,
                    second: index,
                    x: p.x,
                    y: p.y,
                    cell: d,
                });
            }
            sites.push(cell);
        }
        Ok(Self {
            rect,
            sites,
            points: w.clone(),
            closed: params.closed,
            dijkstra: Dijkstra::new(),
        })
    }

    /// The planning cells.
    pub fn rect(&self) -> CellRect {
        self.rect
    }

    /// The planning grid of a map: c(ν) = max(μ(ν), 0) + P_h / v, at least [`MIN_COST`].
    pub fn cost_grid(
        &self,
        map: &EnergyMap,
        params: &EnergyTourParams,
    ) -> Result<CostGrid, TourError> {
        let hotel = params.hotel_per_m();
        let costs = map
            .mean
            .iter()
            .map(|&m| {
                let m = if m.is_finite() { m as f64 } else { 0.0 };
                (m.max(0.0) + hotel).max(MIN_COST) as f32
            })
            .collect();
        Ok(CostGrid::new(map.rect, map.cell_size, costs)?)
    }

    /// The cheapest tour on `grid` (a grid over [`Self::rect`]).
    pub fn plan(&mut self, grid: &CostGrid) -> Result<PlannedTour, TourError> {
        let n = self.sites.len();
        let mut cost = vec![0.0; n * n];
        for a in 0..n {
            let row = self
                .dijkstra
                .run_to_targets(grid, self.sites[a], &self.sites)?;
            for (b, &c) in row.iter().enumerate() {
                if a != b && !c.is_finite() {
                    return Err(TourError::Unreachable { from: a, to: b });
                }
                cost[a * n + b] = c;
            }
        }
        let matrix = CostMatrix::from_fn(n, |a, b| (cost[a * n + b] * MICROJOULES).round() as i64);
        let params = SolverParams {
            fixed_start: Some(0),
            open: (!self.closed).then_some(0),
            use_exact: true,
            ..SolverParams::default()
        };
        let sol = solve(&Instance::tsp("energy-tour", matrix), &params)?;
        if !sol.optimal {
            return Err(TourError::TooManyWaypoints {
                count: n,
                max: MAX_WAYPOINTS,
            });
        }
        let order = sol.tour;
        let mut legs: Vec<(usize, usize)> = order.windows(2).map(|w| (w[0], w[1])).collect();
        if self.closed {
            legs.push((order[n - 1], order[0]));
        }
        let mut path = vec![self.points[order[0]]];
        let mut predicted = 0.0;
        for (a, b) in legs {
            self.dijkstra
                .run_to_targets(grid, self.sites[a], &[self.sites[b]])?;
            let cells = self
                .dijkstra
                .path_to(self.sites[b])
                .ok_or(TourError::Unreachable { from: a, to: b })?;
            let leg = pull(grid, &cells, self.points[a], self.points[b]);
            let mut scratch = Vec::new();
            for w in leg.windows(2) {
                predicted +=
                    segment_cost_between(grid, w[0], w[1], &mut scratch).unwrap_or(f64::INFINITY);
            }
            path.extend_from_slice(&leg[1..]);
        }
        let length_m = path.windows(2).map(|w| w[0].dist(w[1])).sum();
        Ok(PlannedTour {
            order,
            path,
            predicted_energy_j: predicted,
            length_m,
        })
    }
}

/// The cell path `cells` from `start` to `end` (the exact waypoints in its first and last
/// cells), pulled taut where a straight segment costs no more than the stretch of the path it
/// replaces. Both are integrated with the planner's [`segment_cost_between`] (J: each crossed
/// cell's cost times the length inside it), so a straight run of cells is never refused for a
/// discretisation difference.
fn pull(grid: &CostGrid, cells: &[Cell], start: Point2, end: Point2) -> Vec<Point2> {
    let d = grid.cell_size();
    let m = cells.len();
    if m < 2 {
        return vec![start, end];
    }
    let mut pts: Vec<Point2> = cells.iter().map(|c| c.center(d)).collect();
    pts[0] = start;
    pts[m - 1] = end;
    // Cost of the polyline through the cell centres up to each vertex.
    let mut scratch = Vec::new();
    let mut prefix = vec![0.0; m];
    for k in 1..m {
        prefix[k] = prefix[k - 1]
            + segment_cost_between(grid, pts[k - 1], pts[k], &mut scratch).unwrap_or(f64::INFINITY);
    }
    let mut out = vec![start];
    let mut i = 0;
    while i < m - 1 {
        let j = (i + 2..m)
            .rev()
            .find(|&j| {
                segment_cost_between(grid, pts[i], pts[j], &mut scratch)
                    .is_some_and(|c| c <= (prefix[j] - prefix[i]) * (1.0 + 1e-6))
            })
            .unwrap_or(i + 1);
        out.push(pts[j]);
        i = j;
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    fn params(w: Vec<Point2>) -> EnergyTourParams {
        crate::energy_tours::test_params(w)
    }

    fn flat_map(p: &TourPlanner) -> EnergyMap {
        let rect = p.rect();
        EnergyMap {
            rect,
            cell_size: 0.05,
            mean: vec![0.0; rect.len()],
            variance: vec![1.0; rect.len()],
            bins: Vec::new(),
        }
    }

    /// On uniform cost the tour is the straight-line tour in the order of least length.
    #[test]
    fn uniform_cost_gives_the_straight_shortest_tour() {
        let w = vec![
            Point2::new(0.2, 0.5),
            Point2::new(1.7, 0.9),
            Point2::new(1.7, 0.1),
            Point2::new(1.75, 0.5),
        ];
        let p = params(w.clone());
        let mut planner = TourPlanner::new(&p).unwrap();
        let grid = planner.cost_grid(&flat_map(&planner), &p).unwrap();
        let t = planner.plan(&grid).unwrap();
        // 0 → 1 → 3 → 2 → 0 or its reverse: the convex order.
        assert!(
            t.order == vec![0, 1, 3, 2] || t.order == vec![0, 2, 3, 1],
            "{:?}",
            t.order
        );
        let ideal: f64 = {
            let o: Vec<Point2> = t.order.iter().map(|&k| w[k]).chain([w[0]]).collect();
            o.windows(2).map(|s| s[0].dist(s[1])).sum()
        };
        assert!(
            (t.length_m - ideal).abs() < 1e-9,
            "{} vs {ideal}",
            t.length_m
        );
        assert_eq!(t.path.len(), 5);
        let hotel = p.hotel_per_m();
        assert!((t.predicted_energy_j - ideal * hotel).abs() < 1e-3 * ideal * hotel);
        assert!(t.deviation_m(&t, 0.01) < 1e-12);
    }

    /// A dear band across the straight line with a cheap gap at the top: the plan goes
    /// around through the gap, and it differs from the straight plan by more than the band's
    /// half-height.
    #[test]
    fn a_dear_band_is_avoided() {
        let w = vec![Point2::new(0.2, 0.3), Point2::new(1.8, 0.3)];
        let p = params(w);
        let mut planner = TourPlanner::new(&p).unwrap();
        let mut map = flat_map(&planner);
        let straight = planner.plan(&planner.cost_grid(&map, &p).unwrap()).unwrap();
        let rect = map.rect;
        for (k, m) in map.mean.iter_mut().enumerate() {
            let c = rect.cell(k).center(0.05);
            *m = if (0.9..1.1).contains(&c.x) && c.y < 0.8 {
                40.0
            } else {
                6.0
            };
        }
        let around = planner.plan(&planner.cost_grid(&map, &p).unwrap()).unwrap();
        assert!(around.length_m > straight.length_m + 0.5);
        assert!(around.deviation_m(&straight, 0.01) > 0.45);
        // Pulled taut: a handful of vertices, not one per cell.
        assert!(around.path.len() < 12, "{:?}", around.path);
    }

    #[test]
    fn bad_waypoints_are_refused() {
        let e = TourPlanner::new(&params(vec![Point2::new(0.2, 0.2)])).unwrap_err();
        assert!(matches!(e, TourError::TooFewWaypoints(1)), "{e}");
        let e = TourPlanner::new(&params(vec![
            Point2::new(0.2, 0.2),
            Point2::new(1.0, 0.5),
            Point2::new(0.21, 0.21),
        ]))
        .unwrap_err();
        assert!(
            matches!(
                e,
                TourError::DuplicateWaypoint {
                    first: 0,
                    second: 2,
                    ..
                }
            ),
            "{e}"
        );
        let e = TourPlanner::new(&params(vec![Point2::new(0.2, 0.2), Point2::new(2.5, 0.5)]))
            .unwrap_err();
        assert!(
            matches!(e, TourError::WaypointOutsideArea { index: 1, .. }),
            "{e}"
        );
        assert!(e.to_string().contains("unreachable"), "{e}");
        let e = TourPlanner::new(&params(vec![
            Point2::new(0.2, 0.2),
            Point2::new(f64::NAN, 0.5),
        ]))
        .unwrap_err();
        assert!(
            matches!(e, TourError::NonFiniteWaypoint { index: 1, .. }),
            "{e}"
        );
        let many: Vec<Point2> = (0..13)
            .map(|k| Point2::new(0.1 + 0.1 * k as f64, 0.5))
            .collect();
        let e = TourPlanner::new(&params(many)).unwrap_err();
        assert!(
            matches!(e, TourError::TooManyWaypoints { count: 13, .. }),
            "{e}"
        );
    }

    #[test]
    fn deviation_is_symmetric_hausdorff() {
        let a = PlannedTour {
            order: vec![0, 1],
            path: vec![Point2::new(0.0, 0.0), Point2::new(1.0, 0.0)],
            predicted_energy_j: 0.0,
            length_m: 1.0,
        };
        let b = PlannedTour {
            path: vec![
                Point2::new(0.0, 0.0),
                Point2::new(0.5, 0.2),
                Point2::new(1.0, 0.0),
            ],
            ..a.clone()
        };
        assert!((a.deviation_m(&b, 0.01) - 0.2).abs() < 1e-9);
        assert!((b.deviation_m(&a, 0.01) - 0.2).abs() < 1e-9);
    }
}
