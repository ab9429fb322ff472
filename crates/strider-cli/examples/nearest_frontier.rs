//! A method added from outside the kernel: nearest-frontier exploration (Yamauchi's classic
//! baseline) as a [`Strategy`], compared with the registry's strategies by `bench compare`'s
//! library. Run it with
//! `cargo run --release -p strider-cli --example nearest_frontier -- [TRIALS] [TIME_LIMIT_S]`.

use anyhow::Result;
use strider_core::interface::MotionState;
use strider_core::snapshot::{GoalKind, GoalSet, Snapshot};
use strider_core::{Cell, Point2, Point3};
use strider_experiments::compare::{self, CompareOptions, Entrant};
use strider_explore::kernel::{
    Actuators, Body, BodyParams, Every, GoalCounts, Strategy, Termination, site,
};
use strider_explore::rbcm_greedy::goals::frontier_representatives;
use strider_map::Reachability;
use strider_plan::grid::{CostGrid, Dijkstra};

/// Drives to the nearest reachable frontier (by path length over admissible cells), replanning
/// every second and whenever the robot stops; ends when no frontier is reachable.
#[derive(Default)]
pub struct NearestFrontier {
    plan: Option<Every>,
    frontiers: Vec<Point2>,
    goal: Option<Cell>,
    dij: Dijkstra,
}

impl NearestFrontier {
    /// The nearest reachable frontier and the waypoints to it.
    fn nearest(&mut self, body: &mut Body) -> Option<(Cell, Vec<Point2>)> {
        body.map_mut().update_passability();
        let here = body.anchor_cell()?;
        let map = body.map();
        let reach = Reachability::compute(map, here);
        self.frontiers = frontier_representatives(map, &reach, here, body.bounds(), &[], 0.0);
        let rect = map.known_bounds()?;
        let cost = map
            .admissible_raster(rect)
            .into_iter()
            .map(|a| if a { 1.0 } else { f32::INFINITY })
            .collect();
        let grid = CostGrid::new(rect, map.cell_size(), cost).ok()?;
        self.dij.run(&grid, here).ok()?;
        let (goal, _) = self
            .frontiers
            .iter()
            .filter_map(|p| map.cell_at(p.x, p.y))
            .map(|c| (c, self.dij.distance(c)))
            .filter(|(_, d)| d.is_finite() && *d > 1.5)
            .min_by(|a, b| a.1.total_cmp(&b.1))?;
        let d = map.cell_size();
        let path = self.dij.path_to(goal)?;
        Some((goal, path.iter().skip(1).map(|c| c.center(d)).collect()))
    }
}

impl Strategy for NearestFrontier {
    fn name(&self) -> &'static str {
        "nearest-frontier"
    }

    fn control_hz(&self) -> f64 {
        10.0
    }

    fn start(&mut self, _body: &mut Body, t0: f64) {
        self.plan = Some(Every::new(1.0, t0));
    }

    fn tick(
        &mut self,
        body: &mut Body,
        robot: &mut dyn Actuators,
        state: &mut MotionState,
        t: f64,
    ) -> Option<Termination> {
        let mut plan = self.plan?;
        if !(plan.due(t) || state.idle || state.blocked) {
            return None;
        }
        self.plan = Some(plan);
        if body.map().scan_count() == 0 {
            return None;
        }
        match self.nearest(body) {
            Some((goal, waypoints)) => {
                if self.goal != Some(goal) || state.idle || state.blocked {
                    robot.follow(&waypoints);
                    self.goal = Some(goal);
                }
                *state = MotionState::default();
                None
            }
            None => Some(Termination::GoalsCleared),
        }
    }

    fn goal_counts(&self) -> GoalCounts {
        GoalCounts {
            spatial_goals: self.frontiers.len(),
            ..GoalCounts::default()
        }
    }

    fn describe(&self, body: &Body, snap: &mut Snapshot) {
        let z = |p: &Point2| Point3::new(p.x, p.y, 0.0);
        snap.goals.push(GoalSet {
            name: "frontiers".into(),
            kind: GoalKind::Spatial,
            sites: self.frontiers.iter().map(z).collect(),
        });
        snap.tour = self.goal.map(|c| site(body, c)).into_iter().collect();
    }
}

/// The example strategy as a comparison entrant: any robot with a range sensor can carry it.
pub fn entrant() -> Entrant {
    Entrant::custom("nearest-frontier", |_, robot, _| {
        let body = BodyParams {
            map: robot.map.clone(),
            sensor_hfov_deg: robot.sensor_hfov_deg.clone(),
            bounds: robot.bounds,
            time_limit_s: robot.time_limit_s,
        };
        Ok((
            body,
            Box::new(NearestFrontier::default()) as Box<dyn Strategy + Send>,
        ))
    })
}

#[allow(dead_code)] // the test includes this file for `entrant` only
fn main() -> Result<()> {
    let mut args = std::env::args().skip(1);
    let trials = args.next().map_or(Ok(3), |a| a.parse())?;
    let limit: f64 = args.next().map_or(Ok(600.0), |a| a.parse())?;
    let options = CompareOptions {
        scenarios: vec!["courtyard-small".into(), "lab-track".into()],
        trials,
        world_seeds: 3,
        jobs: std::thread::available_parallelism().map_or(1, |n| n.get()),
        time_limit: Some(limit),
        cancel: Default::default(),
        shard: None,
    };
    let entrants = vec![Entrant::registered("gtsp")?, entrant()];
    let result = compare::run(&options, &entrants, || {})?;
    print!(
        "{}",
        compare::markdown(&result, "the nearest_frontier example")
    );
    Ok(())
}
