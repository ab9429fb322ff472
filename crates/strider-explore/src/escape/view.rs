//! The traversability view of Prágr23 (thesis C4): the map's cells classified by C4 Eq. 4 and the planning
//! grid of C4 Eq. 20 built from them, as dense rasters over the area around the known map.
//!
//! * **Geometry** (C4 Eq. 5–6) is the map's roughness passability with t_trav = ρ_obstacle.
//!   A step is seen from both of its sides, so Eq. 5 marks the floor cells at the foot of a wall
//!   as obstacles too. An *apparent obstacle* here is a cell that stands proud of its lowest
//!   known neighbour by more than t_trav (the top of the step): only those carry an appearance of
//!   the obstacle, get force predictions, are sampled and counted in the cell-state report. A
//!   foot cell (impassable, not proud) follows the obstacle it stands next to: traversable when
//!   every proud neighbour is (a pushed-through curtain leaves its foot walkable), else not.
//! * **Eq. 4**: haptic ground truth where measured; else p_geom = 1; else the prediction μ_F ≤
//!   F_trav of a learned predictor (untraversable while none exists, or in the rigid baseline);
//!   unobserved cells are traversable.
//! * **Planning grid** (C4 Eq. 20): per-metre cost 1 + c_d(ν), where c_d decreases linearly from
//!   `c_obstacle` at an untraversable cell to 0 at `d_obstacle` from it (the obstacle-distance
//!   term of Bayer & Faigl 2019); cells within r_robot of an untraversable cell are inadmissible
//!   (the configuration space, decision 4).

use super::force_predictor::{ForcePrediction, ForcePredictor, describe};
use super::haptic::{Geometry, HapticModel, fuse_traversability};
use strider_core::grid::{NEIGHBOURS8, disc_offsets};
use strider_core::{Cell, CellRect};
use strider_map::ElevationMap;
use strider_map::descriptors::c4_histograms;
use strider_map::passability::Passability;
use strider_map::rect::WorldRect;
use strider_plan::grid::CostGrid;

/// Parameters of the view.
#[derive(Clone, Debug, PartialEq)]
pub struct ViewParams {
    /// Robot footprint radius, m (configuration-space inflation).
    pub r_robot: f64,
    /// Distance over which the obstacle-distance cost decays to 0, m.
    pub d_obstacle: f64,
    /// Obstacle-distance cost next to an obstacle (added to the per-metre cost 1).
    pub c_obstacle: f64,
    /// Unobserved margin around the known map that is planned through, m.
    pub margin: f64,
}

impl Default for ViewParams {
    fn default() -> Self {
        Self {
            r_robot: 0.28,
            d_obstacle: 0.5,
            c_obstacle: 2.0,
            margin: 1.0,
        }
    }
}

/// What Eq. 4 says about an apparent obstacle cell.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub enum ObstacleState {
    /// Haptic ground truth: the fused force, N, and p_haptic.
    Haptic {
        /// F(ν).
        force: f64,
        /// F(ν) ≤ F_trav.
        traversable: bool,
    },
    /// Predicted by P.
    Predicted(ForcePrediction),
    /// No predictor (or the rigid baseline): untraversable.
    Unpredicted,
}

/// Counts of apparent obstacle cells by certainty and traversability (C4 Figs. 11–12).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, serde::Serialize)]
pub struct CellStates {
    /// Certain (haptic, or I_predict < threshold) and traversable.
    pub certain_traversable: usize,
    /// Uncertain and traversable.
    pub uncertain_traversable: usize,
    /// Uncertain and untraversable (including cells without a prediction).
    pub uncertain_untraversable: usize,
    /// Certain and untraversable.
    pub certain_untraversable: usize,
}

/// The classified cells and the planning grid over one rectangle.
pub struct TravView {
    /// The rectangle.
    pub rect: CellRect,
    /// Cell size, m.
    pub cell_size: f64,
    /// Observed cells.
    pub observed: Vec<bool>,
    /// C4 Eq. 5 geometry.
    pub geometry: Vec<Geometry>,
    /// Apparent obstacle cells (proud, see the module docs) and what Eq. 4 says of them.
    pub obstacle: Vec<Option<ObstacleState>>,
    /// p(ν) of Eq. 4.
    pub traversable: Vec<bool>,
    /// Configuration-space admissible (p = 1 and no untraversable cell within r_robot).
    pub admissible: Vec<bool>,
    /// The planning grid (Eq. 20).
    pub grid: CostGrid,
    f_trav: f64,
    threshold: f64,
}

/// Whether `c` stands proud of its lowest observed 8-neighbour by more than `t_trav`.
pub fn is_proud(map: &ElevationMap, c: Cell, t_trav: f64) -> bool {
    let Some(z) = map.elevation(c) else {
        return false;
    };
    c.neighbours8()
        .filter_map(|n| map.elevation(n))
        .any(|zn| (z - zn) as f64 > t_trav)
}

impl TravView {
    /// Builds the view around the known map (grown by `margin`, clipped to `bounds` grown by
    /// the obstacle-distance reach).
    /// `predictor` is `None` in the rigid baseline. Returns `None` while nothing is known.
    pub fn build(
        map: &ElevationMap,
        haptic: &HapticModel,
        predictor: Option<&ForcePredictor>,
        bounds: Option<&WorldRect>,
        p: &ViewParams,
    ) -> Option<TravView> {
        let d = map.cell_size();
        let rect = view_rect(map, bounds, p)?;
        let t_trav = map.params().rho_obstacle;
        let observed = map.observed_raster(rect);
        let geometry = geometry(&map.passability_raster(rect), &observed);
        let proud: Vec<bool> = (0..rect.len())
            .map(|k| geometry[k] == Geometry::Obstacle && is_proud(map, rect.cell(k), t_trav))
            .collect();
        let obstacle = obstacle_states(map, rect, &proud, haptic, predictor);
        let traversable = traversability(rect, &geometry, &obstacle, &proud, haptic);
        let (admissible, cost) = configuration_space(rect, &traversable, p, d);
        let grid = CostGrid::new(rect, d, cost).ok()?;
        Some(TravView {
            rect,
            cell_size: d,
            observed,
            geometry,
            obstacle,
            traversable,
            admissible,
            grid,
            f_trav: haptic.params().f_trav,
            threshold: predictor.map_or(f64::INFINITY, |p| p.params().entropy_threshold),
        })
    }

    /// The Eq. 4 state of apparent obstacle `c`.
    pub fn obstacle(&self, c: Cell) -> Option<ObstacleState> {
        self.rect.index(c).and_then(|k| self.obstacle[k])
    }

    /// p(ν) (cells outside the view: untraversable).
    pub fn is_traversable(&self, c: Cell) -> bool {
        self.rect.index(c).is_some_and(|k| self.traversable[k])
    }

    /// Observed, admissible: a cell the robot's centre may be sent to.
    pub fn is_goal_cell(&self, c: Cell) -> bool {
        self.rect
            .index(c)
            .is_some_and(|k| self.observed[k] && self.admissible[k])
    }

    /// The admissibility raster restricted to observed cells (for reachability and Eq. 8).
    pub fn goal_admissible(&self) -> Vec<bool> {
        self.admissible
            .iter()
            .zip(&self.observed)
            .map(|(&a, &o)| a && o)
            .collect()
    }

    /// The planning grid with the disc of radius `r` around `goal` cleared as traversable (C4
    /// §4.5: "the area in the vicinity of the prediction goal is temporarily cleared").
    pub fn cleared_grid(&self, goal: Cell, r: f64) -> Option<CostGrid> {
        let mut cost = self.grid.costs().to_vec();
        for (di, dj) in disc_offsets(r, self.cell_size) {
            if let Some(k) = self.rect.index(Cell::new(goal.i + di, goal.j + dj)) {
                cost[k] = 1.0;
            }
        }
        CostGrid::new(self.rect, self.cell_size, cost).ok()
    }

    /// Counts of apparent obstacles by state. In the rigid baseline (no predictor) every
    /// apparent obstacle is assumed untraversable with certainty.
    pub fn cell_states(&self, rigid: bool) -> CellStates {
        let mut s = CellStates::default();
        for o in self.obstacle.iter().flatten() {
            let (certain, trav) = match *o {
                ObstacleState::Haptic { traversable, .. } => (true, traversable),
                ObstacleState::Predicted(fp) => {
                    (fp.entropy < self.threshold, fp.mean <= self.f_trav)
                }
                ObstacleState::Unpredicted => (rigid, false),
            };
            match (certain, trav) {
                (true, true) => s.certain_traversable += 1,
                (false, true) => s.uncertain_traversable += 1,
                (false, false) => s.uncertain_untraversable += 1,
                (true, false) => s.certain_untraversable += 1,
            }
        }
        s
    }
}

/// The view's rectangle: the known map grown by `margin`, clipped to `bounds` grown by the
/// obstacle-distance reach (obstacles just outside the bounds, the arena's walls, still shape
/// the configuration space and the obstacle-distance cost inside).
fn view_rect(map: &ElevationMap, bounds: Option<&WorldRect>, p: &ViewParams) -> Option<CellRect> {
    let d = map.cell_size();
    let known = map.known_bounds()?;
    let mut rect = strider_map::rect::expand(known, (p.margin / d).ceil() as u32);
    if let Some(b) = bounds {
        let m = p.r_robot.max(p.d_obstacle) + d;
        let lo = Cell::containing(b.min.x - m, b.min.y - m, d)?;
        let hi = Cell::containing(b.max.x + m, b.max.y + m, d)?;
        rect = strider_map::rect::intersection(rect, strider_map::rect::from_corners(lo, hi))?;
    }
    (!rect.is_empty()).then_some(rect)
}

/// C4 Eq. 5 geometry of each cell from its passability and whether it was observed.
fn geometry(pass: &[Passability], observed: &[bool]) -> Vec<Geometry> {
    pass.iter()
        .zip(observed)
        .map(|(&ps, &o)| match (o, ps) {
            (true, Passability::Passable) => Geometry::Traversable,
            (true, Passability::Impassable) => Geometry::Obstacle,
            _ => Geometry::Unobserved,
        })
        .collect()
}

/// What Eq. 4 says of each apparent obstacle (`proud`) cell: haptic ground truth where
/// measured, else the learned predictor's prediction (descriptors only where one is needed).
fn obstacle_states(
    map: &ElevationMap,
    rect: CellRect,
    proud: &[bool],
    haptic: &HapticModel,
    predictor: Option<&ForcePredictor>,
) -> Vec<Option<ObstacleState>> {
    let pred = predictor.filter(|p| p.is_learned());
    let hist = pred.and_then(|pr| {
        (pr.params().descriptor == super::force_predictor::DescriptorKind::Histogram8)
            .then(|| c4_histograms(map, rect, pr.params().r_hist))
    });
    let mut obstacle: Vec<Option<ObstacleState>> = vec![None; rect.len()];
    for (k, state) in obstacle.iter_mut().enumerate() {
        if !proud[k] {
            continue;
        }
        let c = rect.cell(k);
        *state = Some(if let Some(h) = haptic.get(c) {
            ObstacleState::Haptic {
                force: h.force,
                traversable: h.force <= haptic.params().f_trav,
            }
        } else if let Some(pr) = pred {
            let x = match &hist {
                Some(r) => r
                    .get(c)
                    .copied()
                    .flatten()
                    .map(|h| h.iter().map(|&v| v as f64).collect()),
                None => describe(map, c, pr.params()),
            };
            match x.and_then(|x| pr.predict(&x)) {
                Some(fp) => ObstacleState::Predicted(fp),
                None => ObstacleState::Unpredicted,
            }
        } else {
            ObstacleState::Unpredicted
        });
    }
    obstacle
}

/// p(ν) of Eq. 4 for every cell; a foot cell (impassable, not proud, not measured) follows
/// its proud neighbours: traversable when it has one and every one is.
fn traversability(
    rect: CellRect,
    geometry: &[Geometry],
    obstacle: &[Option<ObstacleState>],
    proud: &[bool],
    haptic: &HapticModel,
) -> Vec<bool> {
    let f_trav = haptic.params().f_trav;
    let mut traversable: Vec<bool> = (0..rect.len())
        .map(|k| {
            let predicted = match obstacle[k] {
                Some(ObstacleState::Predicted(fp)) => Some(fp.mean <= f_trav),
                _ => None,
            };
            fuse_traversability(haptic.traversable(rect.cell(k)), geometry[k], predicted)
        })
        .collect();
    let (w, h) = (rect.width as i64, rect.height as i64);
    for k in 0..rect.len() {
        if geometry[k] != Geometry::Obstacle || proud[k] || haptic.get(rect.cell(k)).is_some() {
            continue;
        }
        let (x, y) = ((k as i64) % w, (k as i64) / w);
        let mut any = false;
        let mut all = true;
        for &(di, dj) in &NEIGHBOURS8 {
            let (nx, ny) = (x + di as i64, y + dj as i64);
            if nx < 0 || ny < 0 || nx >= w || ny >= h {
                continue;
            }
            let nk = (ny * w + nx) as usize;
            if proud[nk] {
                any = true;
                all &= traversable[nk];
            }
        }
        traversable[k] = any && all;
    }
    traversable
}

/// The configuration space (no untraversable cell within r_robot) and the Eq. 20 per-metre
/// cost with the obstacle-distance term (+∞ where inadmissible), for cell size `d`.
fn configuration_space(
    rect: CellRect,
    traversable: &[bool],
    p: &ViewParams,
    d: f64,
) -> (Vec<bool>, Vec<f32>) {
    let (w, h) = (rect.width as i64, rect.height as i64);
    let inflate = disc_offsets(p.r_robot, d);
    let decay = disc_offsets(p.d_obstacle.max(p.r_robot), d);
    let mut admissible = traversable.to_vec();
    let mut cost = vec![1.0f32; rect.len()];
    for (k, _) in traversable.iter().enumerate().filter(|&(_, &t)| !t) {
        let (x, y) = ((k as i64) % w, (k as i64) / w);
        for &(di, dj) in &inflate {
            let (nx, ny) = (x + di as i64, y + dj as i64);
            if nx >= 0 && ny >= 0 && nx < w && ny < h {
                admissible[(ny * w + nx) as usize] = false;
            }
        }
        for &(di, dj) in &decay {
            let (nx, ny) = (x + di as i64, y + dj as i64);
            if nx >= 0 && ny >= 0 && nx < w && ny < h {
                let dist = ((di * di + dj * dj) as f64).sqrt() * d;
                let c = 1.0 + p.c_obstacle * (1.0 - dist / p.d_obstacle).max(0.0);
                let q = (ny * w + nx) as usize;
                cost[q] = cost[q].max(c as f32);
            }
        }
    }
    for (c, &a) in cost.iter_mut().zip(&admissible) {
        if !a {
            *c = f32::INFINITY;
        }
    }
    (admissible, cost)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::escape::goals::{GoalInputs, GoalKind, select_goal};
    use crate::escape::haptic::HapticParams;
    use strider_core::Rgb8;
    use strider_map::MapParams;

    /// A 2 × 2 m floor (0.05 m cells) with a 1 m high purple wall two cells thick at x ≈ 1 m.
    fn map() -> ElevationMap {
        let mut m = ElevationMap::new(MapParams {
            rho_obstacle: 0.12,
            r_robot: 0.28,
            ..MapParams::default()
        });
        for j in 0..40 {
            for i in 0..40 {
                let wall = i == 20 || i == 21;
                let (z, c) = if wall {
                    (1.0, Rgb8::new(170, 60, 170))
                } else {
                    (0.0, Rgb8::new(120, 120, 125))
                };
                m.set_cell(Cell::new(i, j), z, 1e-4, c);
            }
        }
        m.update_passability();
        m
    }

    #[test]
    fn eq4_without_and_with_haptic_ground_truth() {
        let m = map();
        let mut h = HapticModel::new(HapticParams::default());
        let p = ViewParams::default();
        let v = TravView::build(&m, &h, None, None, &p).unwrap();
        let wall = Cell::new(20, 20);
        let foot = Cell::new(19, 20);
        assert!(matches!(v.obstacle(wall), Some(ObstacleState::Unpredicted)));
        assert!(
            v.obstacle(foot).is_none(),
            "the foot of the step is not an apparent obstacle"
        );
        assert!(!v.is_traversable(wall) && !v.is_traversable(foot));
        assert!(v.is_traversable(Cell::new(5, 5)));
        // The wall cannot be crossed: the two halves are disconnected in the planning grid.
        assert!(!v.grid.is_admissible(Cell::new(17, 20)));
        // Haptic ground truth below F_trav on the whole wall opens it, foot cells included.
        for j in 0..40 {
            for i in [20, 21] {
                h.fuse(Cell::new(i, j), 0.7);
            }
        }
        let v = TravView::build(&m, &h, None, None, &p).unwrap();
        assert!(v.is_traversable(wall) && v.is_traversable(foot));
        assert!(v.grid.is_admissible(Cell::new(20, 20)));
        assert_eq!(
            v.cell_states(false).certain_traversable,
            v.obstacle.iter().flatten().count()
        );
    }

    #[test]
    fn alg2_spatial_first_then_closest_obstacle_then_uncertain() {
        let m = map();
        let h = HapticModel::new(HapticParams::default());
        let v = TravView::build(&m, &h, None, None, &ViewParams::default()).unwrap();
        let mut dij = strider_plan::grid::Dijkstra::new();
        dij.run(&v.grid, Cell::new(5, 20)).unwrap();
        let spatial = vec![strider_map::SpatialGoal {
            cell: Cell::new(5, 30),
            centroid: Cell::new(5, 30).center(0.05),
            information: 1.0,
            members: 20,
        }];
        let mut inp = GoalInputs {
            dist: dij.distances(),
            spatial: &spatial,
            learn: true,
            predictor_learned: false,
            entropy_threshold: 0.26,
            r_robot: 0.28,
            reach: 0.1,
            excluded: &[],
            exclusion_cells: 3.0,
            bounds: None,
        };
        assert_eq!(select_goal(&v, &inp).unwrap().kind, GoalKind::Spatial);
        inp.spatial = &[];
        let g = select_goal(&v, &inp).unwrap();
        assert_eq!(g.kind, GoalKind::ClosestObstacle);
        // The nearest apparent obstacle cell is on the wall's west face, level with the robot
        // (up to ties of the approach cost).
        assert_eq!(g.cell.i, 20);
        assert!((g.cell.j - 20).abs() <= 3, "{g:?}");
        // The rigid baseline has no obstacle goals.
        inp.learn = false;
        assert!(select_goal(&v, &inp).is_none());
        // A learned predictor with every obstacle below the threshold: no goal.
        inp.learn = true;
        inp.predictor_learned = true;
        assert!(
            select_goal(&v, &inp).is_none(),
            "unpredicted cells carry no entropy"
        );
    }
}
