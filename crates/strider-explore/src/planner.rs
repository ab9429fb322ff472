//! Planning on the robot's own map: the merged planning grid (Prágr22 Eq. 12–13, decision 21),
//! cheapest paths, gait choice (Alg. 4) and the exploration tour over goal sets (Alg. 1 line 17,
//! decision 23).

use crate::params::TourSolver;
use crate::timing::ms_since;
use rayon::prelude::*;
use std::borrow::Cow;
use std::sync::{Arc, Mutex, PoisonError};
use strider_core::{Cell, CellRect, GaitId, Point2};
use strider_learn::cost_model::GaitCostModel;
use strider_map::ElevationMap;
use strider_map::passability::Passability;
use strider_map::rect::WorldRect;
use strider_plan::grid::{
    CostGrid, Dijkstra, SiteCostCache, SiteCosts, site_costs, smooth_between, smooth_path,
    transform,
};
use strider_plan::gtsp::{self, Mode, SolverParams};
use strider_plan::{CostMatrix, Instance};

/// Which costs the planner uses.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum CostMode {
    /// Eq. 5: every passable cell costs 1 (path length).
    Flat,
    /// The learned per-gait planning costs (Alg. 10), best gait per cell (Eq. 13).
    Learned,
}

/// The grids a plan is made on, over the map's known rectangle.
#[derive(Clone, Debug)]
pub struct PlanningView {
    /// Per-gait cell costs ĉ_{C^g}(ν) (impassable cells +∞), before any transform.
    pub per_gait: Vec<CostGrid>,
    /// Best gait per cell (Eq. 13).
    pub best_gait: Vec<Option<u16>>,
    /// The planning grid: best-gait cost, distance transform with c_loss, footprint max (Eq. 12),
    /// +∞ where the robot's centre may not be (inadmissible or unknown cells).
    pub grid: CostGrid,
    /// Footprint offsets δ(r_robot) for the gait choice, computed once per view rather than per
    /// query (the gait is chosen at every control tick).
    footprint: Vec<(i32, i32)>,
    /// The clusters' portal costs of the site-cost graph, shared with the views that follow
    /// this one (see [`keep_site_costs_of`](Self::keep_site_costs_of)).
    site_cache: Arc<Mutex<SiteCostCache>>,
}

impl PlanningView {
    /// Builds the view from the map and the gait models. `None` while the map is empty.
    ///
    /// Cells outside the exploration `bounds` are treated as impassable, so the footprint keeps
    /// the robot's centre r_robot inside them: the robot may not leave the area it is tasked
    /// with, and the map cannot see where the ground ends (a simulated world's edge, a drop).
    pub fn build(
        map: &ElevationMap,
        models: &[GaitCostModel],
        mode: CostMode,
        c_loss: f64,
        bounds: Option<&WorldRect>,
    ) -> Option<Self> {
        Self::build_within(map, models, mode, c_loss, bounds, None)
    }

    /// [`build`](Self::build) over the part of the map inside `window` (the whole known
    /// rectangle for `None`): a bounded tour horizon plans on its own neighbourhood of the map
    /// rather than on all of it. `None` also when the window misses the known rectangle.
    pub fn build_within(
        map: &ElevationMap,
        models: &[GaitCostModel],
        mode: CostMode,
        c_loss: f64,
        bounds: Option<&WorldRect>,
        window: Option<CellRect>,
    ) -> Option<Self> {
        let d = map.cell_size();
        let reach = (map.params().r_robot / d).ceil() as u32 + 1;
        let known = strider_map::rect::expand(map.known_bounds()?, reach);
        let rect = match window {
            Some(w) => strider_map::rect::intersection(known, w)?,
            None => known,
        };
        let outside: Vec<bool> = match bounds {
            // Cells side by side: each test is its own.
            Some(b) => (0..rect.len())
                .into_par_iter()
                .map(|k| !b.contains_cell(rect.cell(k), d))
                .collect(),
            None => vec![false; rect.len()],
        };
        let pass = map.passability_raster(rect);
        let adm = map.admissible_raster(rect);
        let per_gait: Vec<CostGrid> = models
            .par_iter()
            .map(|m| {
                let mut c = match mode {
                    CostMode::Flat => vec![1.0f32; rect.len()],
                    CostMode::Learned => m.planning_costs(rect),
                };
                for ((v, p), &out) in c.iter_mut().zip(&pass).zip(&outside) {
                    if out {
                        *v = f32::INFINITY;
                        continue;
                    }
                    match p {
                        Passability::Impassable => *v = f32::INFINITY,
                        // Unknown cells do not raise their neighbours' footprint cost; the
                        // centre mask below keeps the robot off them.
                        Passability::Unknown => *v = 1.0,
                        Passability::Passable => *v = v.max(1.0),
                    }
                }
                CostGrid::new(rect, d, c).expect("costs are ≥ 1 or +∞")
            })
            .collect();
        let best = transform::best_gait(&per_gait).ok()?;
        let dt = transform::distance_transform(&best.cost, c_loss).ok()?;
        let fp = transform::footprint_max(&dt, map.params().r_robot).ok()?;
        let mut costs = fp.into_costs();
        costs
            .par_iter_mut()
            .zip(adm.par_iter().zip(pass.par_iter()))
            .for_each(|(v, (&admissible, &p))| {
                if !admissible || p == Passability::Unknown {
                    *v = f32::INFINITY;
                }
            });
        let grid = CostGrid::new(rect, d, costs).ok()?;
        Some(Self {
            per_gait,
            best_gait: best.gait,
            grid,
            footprint: strider_core::grid::disc_offsets(map.params().r_robot, d),
            site_cache: Arc::default(),
        })
    }

    /// Takes over `previous`'s cached cluster costs, so that [`site_costs`](Self::site_costs)
    /// on this view recomputes only the clusters whose costs changed since.
    pub fn keep_site_costs_of(&mut self, previous: &PlanningView) {
        self.site_cache = Arc::clone(&previous.site_cache);
    }

    /// Planning costs between all ordered pairs of `sites`: exact on small views, from the
    /// two-level cluster graph on large ones ([`site_costs`]).
    pub fn site_costs(&self, sites: &[Cell]) -> SiteCosts {
        let mut cache = self
            .site_cache
            .lock()
            .unwrap_or_else(PoisonError::into_inner);
        site_costs(&self.grid, sites, &mut cache)
    }

    /// The rectangle planned over.
    pub fn rect(&self) -> CellRect {
        self.grid.rect()
    }

    /// Alg. 4 line 6: argmin_g max_{ν' ∈ δ(r_robot, ν)} ĉ_{C^g}(ν') with the map's r_robot;
    /// `None` off the view.
    pub fn choose_gait(&self, cell: Cell) -> Option<GaitId> {
        transform::choose_gait_with(&self.per_gait, cell, &self.footprint)
            .map(|(g, _)| GaitId(g as u8))
    }

    /// The waypoints a robot drives along `path` (a path of this view): the cell centres of its
    /// line-of-sight smoothing on the planning grid ([`smooth_path`]), so straight stretches are
    /// driven straight instead of as 45° zig-zags.
    pub fn drive_waypoints(&self, path: &[Cell]) -> Vec<Point2> {
        waypoints(&smooth_path(&self.grid, path), self.grid.cell_size())
    }

    /// [`drive_waypoints`](Self::drive_waypoints) for a robot standing at `robot`, ending at
    /// the centre of the path's last cell.
    pub fn drive_waypoints_from(&self, path: &[Cell], robot: Point2) -> Vec<Point2> {
        let d = self.grid.cell_size();
        match path.last() {
            Some(last) => self.drive_waypoints_between(path, robot, last.center(d)),
            None => Vec::new(),
        }
    }

    /// The waypoints a robot standing at `from` drives along `path` (a path of this view) to
    /// the point `to`: [`smooth_between`] on the planning grid, without the robot's own
    /// position. Shortcuts start at the robot and end at `to` themselves: a robot standing past
    /// the centre of its own cell does not turn back to it (which would turn it on the spot, up
    /// to half a turn and back, at every replan), and a straight cheapest route is driven
    /// straight, not through the cell centres beside it.
    pub fn drive_waypoints_between(&self, path: &[Cell], from: Point2, to: Point2) -> Vec<Point2> {
        let mut pts = smooth_between(&self.grid, from, path, to);
        pts.remove(0);
        pts
    }

    /// The cheapest path from `from` to `to` on the planning grid, as cell centres; `None` if
    /// unreachable.
    pub fn path(&self, dij: &mut Dijkstra, from: Cell, to: Cell) -> Option<Vec<Cell>> {
        let cost = dij.astar(&self.grid, from, to).ok()?;
        if !cost.is_finite() {
            return None;
        }
        dij.path_to(to)
    }
}

/// A goal as the tour sees it: a set of alternative sites, any one of which clears it.
#[derive(Clone, Debug, PartialEq)]
pub struct TourGoal {
    /// Caller's identifier of the goal.
    pub key: GoalKey,
    /// Its sites.
    pub sites: Vec<Cell>,
}

/// Identity of a goal across replans (decision 23: replan when the goal set changes by
/// identity).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum GoalKey {
    /// A spatial goal Γ_P, by its representative cell.
    Spatial(Cell),
    /// A cost-model goal γ_C(T) of gait `gait`, by class (`u32::MAX` for the bootstrap goal).
    Cost {
        /// Gait index.
        gait: u8,
        /// Class id.
        class: u32,
    },
}

/// The result of ordering goals.
#[derive(Clone, Debug, PartialEq)]
pub struct Tour {
    /// Goals in visiting order with the chosen site of each.
    pub order: Vec<(GoalKey, Cell)>,
    /// Planning cost of the open tour from the robot.
    pub cost: f64,
    /// Vertices of the instance (the robot and every reachable site).
    pub vertices: usize,
    /// Wall time of the all-pairs site costs, ms.
    pub all_pairs_ms: f64,
    /// Wall time of the GTSP solve (0 for the greedy choice), ms.
    pub gtsp_ms: f64,
}

/// Farthest-point subsample of `sites` down to `k` (decision 23), deterministic: start from
/// the first site, repeatedly add the site farthest from those chosen (ties: lowest index).
pub fn farthest_point_subsample(sites: &[Cell], k: usize) -> Vec<Cell> {
    if sites.len() <= k {
        return sites.to_vec();
    }
    let mut chosen = vec![sites[0]];
    let mut dmin: Vec<f64> = sites.iter().map(|s| s.dist_cells(sites[0])).collect();
    while chosen.len() < k {
        let (mut bi, mut bd) = (0, -1.0);
        for (i, &d) in dmin.iter().enumerate() {
            if d > bd {
                (bi, bd) = (i, d);
            }
        }
        let c = sites[bi];
        chosen.push(c);
        for (i, s) in sites.iter().enumerate() {
            dmin[i] = dmin[i].min(s.dist_cells(c));
        }
    }
    chosen
}

/// How a tour orders its goals.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum TourOrder<'a> {
    /// An open GTSP over the robot vertex and every site (decision 23), solved within this
    /// budget.
    Gtsp(&'a TourSolver),
    /// The cheapest goal next (the myopic baseline).
    CheapestNext,
}

/// Orders `goals` from the robot's cell: an open GTSP over the robot vertex and every site
/// (decision 23), or the cheapest goal next. Goals none of whose sites is
/// reachable are left out. Deterministic for a seed (iteration limits, no wall-clock limit
/// decides the result unless the instance is huge).
///
/// `previous` is the last tour's order: its (goal, site) pairs still in the instance warm-start
/// the solver in that order (goals that are gone are dropped, new ones inserted at their
/// cheapest places), so a replan refines the standing plan instead of starting over, and the
/// robot does not switch between near-equal tours from one replan to the next.
///
/// `first`, an index into `goals`, is the goal the robot has committed to: when it is reachable
/// the tour starts with it (the cheapest tour among those that do) and the greedy choice is
/// its cheapest site; otherwise it is ignored.
pub fn plan_tour(
    view: &PlanningView,
    robot: Cell,
    goals: &[TourGoal],
    order: TourOrder,
    seed: u64,
    previous: &[(GoalKey, Cell)],
    first: Option<usize>,
) -> Option<Tour> {
    let w = std::time::Instant::now();
    let inst = TourInstance::new(view, robot, goals)?;
    let all_pairs_ms = ms_since(w);
    // The set that must come first, if that goal is still reachable.
    let first_set = first.and_then(|g| inst.set_goal.iter().position(|&x| x == g));
    let TourOrder::Gtsp(budget) = order else {
        let (cost, v) = inst.cheapest_next(first_set)?;
        return Some(Tour {
            order: vec![inst.stop(goals, v)],
            cost,
            vertices: inst.len(),
            all_pairs_ms,
            gtsp_ms: 0.0,
        });
    };
    let gtsp = Instance::new("exploration", inst.all_sets(), inst.matrix(first_set)).ok()?;
    let warm = inst.warm_start(goals, previous);
    let params = SolverParams {
        mode: Mode::Fast,
        time_limit_s: budget.time_limit_s,
        seed,
        open: Some(0),
        warm_start: (warm.len() > 1).then_some(warm),
        max_trials: Some(budget.max_trials),
        max_iterations: Some(budget.max_iterations as u64),
        stall_iterations: Some(300),
        ..SolverParams::default()
    };
    let w = std::time::Instant::now();
    let sol = gtsp::solve(&gtsp, &params).ok()?;
    let gtsp_ms = ms_since(w);
    let order = sol
        .tour
        .iter()
        .skip_while(|&&v| v != 0)
        .skip(1)
        .map(|&v| inst.stop(goals, v))
        .collect();
    Some(Tour {
        order,
        cost: sol.cost as f64 / 1000.0,
        vertices: inst.len(),
        all_pairs_ms,
        gtsp_ms,
    })
}

/// The planning window around `robot` and the sites of `goals`, grown by `margin` cells on
/// every side: where a tour over a bounded horizon ([`horizon`]) is planned.
pub fn window_around(robot: Cell, goals: &[TourGoal], margin: u32) -> CellRect {
    let mut rect = strider_map::rect::include(None, robot);
    for &s in goals.iter().flat_map(|g| &g.sites) {
        rect = strider_map::rect::include(Some(rect), s);
    }
    strider_map::rect::expand(rect, margin)
}

/// The goals within the tour's horizon and the committed goal's index among them: all of
/// `goals` when their sites number at most `max_sites` (or there is no bound); else the
/// `max_sites` sites nearest to `robot` in a straight line (ties by goal, then site index),
/// the committed goal `first`'s sites before all, grouped by their goal (at least one site).
/// A goal keeps only its sites within the horizon: the tour visits one site per goal, and a
/// goal's far sites would spread the planning window over the map. A goal without a site
/// within the horizon waits until the robot comes nearer; the next replan's horizon moves
/// with it. The goals keep their order; the result borrows `goals` exactly when it holds all
/// of them.
pub fn horizon(
    goals: &[TourGoal],
    robot: Cell,
    first: Option<usize>,
    max_sites: Option<usize>,
) -> (Cow<'_, [TourGoal]>, Option<usize>) {
    let total: usize = goals.iter().map(|g| g.sites.len()).sum();
    let Some(max_sites) = max_sites.filter(|&m| total > m) else {
        return (Cow::Borrowed(goals), first);
    };
    // (not the committed goal, distance, goal, site) of every site, nearest first.
    let mut by_distance: Vec<(bool, f64, usize, usize)> = goals
        .iter()
        .enumerate()
        .flat_map(|(g, goal)| {
            goal.sites
                .iter()
                .enumerate()
                .map(move |(k, &s)| (first != Some(g), s.dist_cells(robot), g, k))
        })
        .collect();
    by_distance.sort_by(|a, b| {
        a.0.cmp(&b.0)
            .then(a.1.total_cmp(&b.1))
            .then(a.2.cmp(&b.2))
            .then(a.3.cmp(&b.3))
    });
    let mut kept: Vec<Vec<bool>> = goals.iter().map(|g| vec![false; g.sites.len()]).collect();
    for &(_, _, g, k) in by_distance.iter().take(max_sites.max(1)) {
        kept[g][k] = true;
    }
    let (near, near_first) = retain_sites(goals, first, |g, k, _| kept[g][k]);
    (Cow::Owned(near), near_first)
}

/// `goals` with only the sites `keep(goal, site index, site)` accepts, the goals left without a
/// site dropped, and the index of goal `first` among them (`None` when it was dropped).
pub fn retain_sites(
    goals: &[TourGoal],
    first: Option<usize>,
    keep: impl Fn(usize, usize, Cell) -> bool,
) -> (Vec<TourGoal>, Option<usize>) {
    let mut out = Vec::with_capacity(goals.len());
    let mut out_first = None;
    for (g, goal) in goals.iter().enumerate() {
        let sites: Vec<Cell> = goal
            .sites
            .iter()
            .enumerate()
            .filter(|&(k, &s)| keep(g, k, s))
            .map(|(_, &s)| s)
            .collect();
        if sites.is_empty() {
            continue;
        }
        if first == Some(g) {
            out_first = Some(out.len());
        }
        out.push(TourGoal {
            key: goal.key,
            sites,
        });
    }
    (out, out_first)
}

/// The tour's vertices: the robot (vertex 0) and the sites reachable from it, grouped by goal.
struct TourInstance {
    /// The robot's cell, then every site of every goal.
    sites: Vec<Cell>,
    /// The goal of each of `sites` (`usize::MAX` for the robot).
    owner: Vec<usize>,
    /// Planning costs between all of `sites`.
    costs: SiteCosts,
    /// The vertices: indices into `sites` of the robot and every site reachable from it.
    reachable: Vec<usize>,
    /// Per goal with a reachable site, its vertices.
    sets: Vec<Vec<usize>>,
    /// The goal of each of `sets`.
    set_goal: Vec<usize>,
}

impl TourInstance {
    /// The instance of `goals` from the robot's cell; `None` when no goal is reachable.
    fn new(view: &PlanningView, robot: Cell, goals: &[TourGoal]) -> Option<Self> {
        let mut sites = vec![robot];
        let mut owner = vec![usize::MAX];
        for (g, goal) in goals.iter().enumerate() {
            for &s in &goal.sites {
                sites.push(s);
                owner.push(g);
            }
        }
        let costs = view.site_costs(&sites);
        let reachable: Vec<usize> = (0..sites.len())
            .filter(|&v| v == 0 || costs.get(0, v).is_finite())
            .collect();
        let mut sets: Vec<Vec<usize>> = Vec::new();
        let mut set_goal: Vec<usize> = Vec::new();
        for g in 0..goals.len() {
            let vs: Vec<usize> = reachable
                .iter()
                .enumerate()
                .filter(|&(_, &v)| owner[v] == g)
                .map(|(i, _)| i)
                .collect();
            if !vs.is_empty() {
                sets.push(vs);
                set_goal.push(g);
            }
        }
        (!sets.is_empty()).then_some(Self {
            sites,
            owner,
            costs,
            reachable,
            sets,
            set_goal,
        })
    }

    /// Vertices.
    fn len(&self) -> usize {
        self.reachable.len()
    }

    /// The planning cost from vertex `a` to vertex `b`.
    fn cost(&self, a: usize, b: usize) -> f64 {
        self.costs.get(self.reachable[a], self.reachable[b])
    }

    /// Vertex `v` as a stop of the tour: its goal's key and its site.
    fn stop(&self, goals: &[TourGoal], v: usize) -> (GoalKey, Cell) {
        let o = self.reachable[v];
        (goals[self.owner[o]].key, self.sites[o])
    }

    /// The cheapest site of any goal from the robot (of set `first` only, when given): its
    /// cost and vertex.
    fn cheapest_next(&self, first: Option<usize>) -> Option<(f64, usize)> {
        let mut best: Option<(f64, usize)> = None;
        for (s, vs) in self.sets.iter().enumerate() {
            if first.is_some_and(|f| f != s) {
                continue;
            }
            for &v in vs {
                let c = self.cost(0, v);
                if best.is_none_or(|(bc, _)| c < bc) {
                    best = Some((c, v));
                }
            }
        }
        best
    }

    /// The GTSP's sets: the robot alone, then each goal's vertices.
    fn all_sets(&self) -> Vec<Vec<usize>> {
        let mut all = vec![vec![0]];
        all.extend(self.sets.iter().cloned());
        all
    }

    /// Integer costs in millimetre-cost units; unreachable pairs get a large finite penalty,
    /// and so does leaving the robot for any set but the committed `first`.
    fn matrix(&self, first: Option<usize>) -> CostMatrix {
        let n = self.len();
        let finite_max = (0..n)
            .flat_map(|a| (0..n).map(move |b| (a, b)))
            .map(|(a, b)| self.cost(a, b))
            .filter(|c| c.is_finite())
            .fold(0.0, f64::max);
        // A tour sums n + 1 edges of at most 2·big: capped so that the sum stays an i64.
        let cap = i64::MAX / 4 / (n as i64 + 1);
        let big = ((finite_max * 1000.0).ceil() as i64)
            .saturating_add(1)
            .saturating_mul(n as i64)
            .min(cap);
        let mut in_first = vec![false; n];
        if let Some(f) = first {
            for &v in &self.sets[f] {
                in_first[v] = true;
            }
        }
        CostMatrix::from_fn(n, |a, b| {
            if a == b || b == 0 {
                0 // the diagonal, and the open tour's free return to the robot
            } else {
                let c = self.cost(a, b);
                // Leaving the robot for any set but the committed one costs more than any tour.
                let detour = if a == 0 && first.is_some() && !in_first[b] {
                    big
                } else {
                    0
                };
                if c.is_finite() {
                    ((c * 1000.0).round() as i64).min(cap) + detour
                } else {
                    big + detour
                }
            }
        })
    }

    /// The warm start: the robot, then the (goal, site) pairs of `previous` still in the
    /// instance, in that order.
    fn warm_start(&self, goals: &[TourGoal], previous: &[(GoalKey, Cell)]) -> Vec<usize> {
        let mut warm = vec![0];
        for &(key, cell) in previous {
            let found = (1..self.len()).find(|&v| {
                let o = self.reachable[v];
                self.sites[o] == cell && goals[self.owner[o]].key == key
            });
            if let Some(v) = found {
                warm.push(v);
            }
        }
        warm
    }
}

/// The first cell of `c` + `offsets` (sorted by distance, as [`disc_offsets`] gives them)
/// that satisfies `ok`: the nearest place near `c` where the robot's centre may be. Both the
/// mission (its anchor cell) and the tours (their waypoints) use it with a 3·r_robot disc.
///
/// [`disc_offsets`]: strider_core::grid::disc_offsets
pub fn nearest_where(c: Cell, offsets: &[(i32, i32)], ok: impl Fn(Cell) -> bool) -> Option<Cell> {
    offsets
        .iter()
        .map(|&(di, dj)| Cell::new(c.i + di, c.j + dj))
        .find(|&x| ok(x))
}

/// Cell centres of a cell path as world waypoints.
pub fn waypoints(path: &[Cell], d: f64) -> Vec<Point2> {
    path.iter().map(|c| c.center(d)).collect()
}
