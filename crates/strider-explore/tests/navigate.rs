//! Nardi19 repeated navigation through the robot interface, on a small synthetic world with a
//! scripted robot: the learned runs must move from the shortest path to the cheap road, the
//! baselines are measured like the runs, and bad inputs are errors.

use std::convert::Infallible;

use strider_core::interface::{MotionState, Robot, SensorSink};
use strider_core::{Cell, CellRect, GaitId, Point2, Point3, PoseStamped, Proprioception, Rgb8};
use strider_explore::navigate::{
    ModelKind, NavigateError, NavigateParams, NavigationLog, NavigationMap, Objective, drive_task,
    navigate,
};
use strider_plan::grid::Dijkstra;
use strider_plan::grid::lcb::{LcbParams, Rectifier, lcb_grid, lcb_path};

const W: u32 = 24;
const H: u32 = 12;
const D: f64 = 0.5;

/// Rows 6–7 and columns 10–15 are paved roads (vibration 0.5), the rest grass (4.0); the
/// straight start–goal path crosses the vertical road, so the first run sees both terrains.
fn vibration(c: Cell) -> f64 {
    if (6..8).contains(&c.j) || (10..16).contains(&c.i) {
        0.5
    } else {
        4.0
    }
}

/// A robot driving its path at 1 m/s and reporting pose and vibration at 20 Hz.
struct Scripted {
    pos: Point2,
    path: Vec<Point2>,
    t: f64,
}

impl Robot for Scripted {
    type Error = Infallible;
    fn now(&self) -> f64 {
        self.t
    }
    fn follow(&mut self, path: &[Point2]) {
        self.path = path.to_vec();
        self.path.reverse();
    }
    fn set_gait(&mut self, _gait: GaitId) {}
    fn advance(&mut self, dt: f64, sink: &mut dyn SensorSink) -> Result<MotionState, Infallible> {
        let steps = (dt / 0.05).round().max(1.0) as usize;
        for _ in 0..steps {
            let mut budget = 0.05;
            let mut moved = false;
            while budget > 0.0 {
                let Some(&next) = self.path.last() else { break };
                let dist = self.pos.dist(next);
                if dist <= budget {
                    budget -= dist;
                    moved |= dist > 0.0;
                    self.pos = next;
                    self.path.pop();
                } else {
                    let f = budget / dist;
                    self.pos = Point2::new(
                        self.pos.x + f * (next.x - self.pos.x),
                        self.pos.y + f * (next.y - self.pos.y),
                    );
                    moved = true;
                    budget = 0.0;
                }
            }
            self.t += 0.05;
            sink.on_pose(&PoseStamped {
                stamp: self.t,
                position: Point3::new(self.pos.x, self.pos.y, 0.0),
                ..PoseStamped::default()
            });
            let c = Cell::containing(self.pos.x, self.pos.y, D).unwrap();
            sink.on_proprioception(&Proprioception {
                stamp: self.t,
                vibration: if moved { vibration(c) } else { 0.0 },
                power_w: if moved { vibration(c) } else { 0.0 },
                ..Proprioception::default()
            });
        }
        Ok(MotionState {
            idle: self.path.is_empty(),
            blocked: false,
        })
    }
}

fn rect() -> CellRect {
    CellRect::new(Cell::new(0, 0), W, H)
}

fn world(aerial: bool) -> NavigationMap {
    let r = rect();
    let colours = r
        .cells()
        .map(|c| {
            if vibration(c) < 1.0 {
                Rgb8::new(90, 90, 95)
            } else {
                Rgb8::new(70, 130, 50)
            }
        })
        .collect();
    NavigationMap::new(r, D, vec![true; r.len()], aerial.then_some(colours)).unwrap()
}

fn task() -> Vec<Point2> {
    vec![Cell::new(1, 3).center(D), Cell::new(22, 3).center(D)]
}

fn robot_at(p: Point2) -> Scripted {
    Scripted {
        pos: p,
        path: Vec::new(),
        t: 0.0,
    }
}

/// The least-cost path on the true field, driven like a run.
fn least_cost(map: &NavigationMap) -> f64 {
    let r = rect();
    let truth: Vec<f64> = r.cells().map(vibration).collect();
    let p = LcbParams {
        lambda: 0.0,
        rectifier: Rectifier::Relu,
        floor: 1e-6,
    };
    let grid = lcb_grid(r, D, &truth, &vec![0.0; r.len()], map.admissible(), &p).unwrap();
    let t = task();
    let (s, g) = (
        Cell::containing(t[0].x, t[0].y, D).unwrap(),
        Cell::containing(t[1].x, t[1].y, D).unwrap(),
    );
    let (path, _) = lcb_path(&mut Dijkstra::new(), &grid, s, g)
        .unwrap()
        .unwrap();
    let params = NavigateParams::default();
    drive_task(
        &mut robot_at(t[0]),
        map,
        Objective::Vibration,
        &[path],
        &params,
    )
    .unwrap()
    .experienced_cost
}

/// `navigate` on the task, a fresh robot at its start for every run.
fn run_task(map: &NavigationMap, params: &NavigateParams) -> NavigationLog {
    let t = task();
    navigate(
        map,
        &t,
        params,
        |_| Ok::<_, Infallible>(robot_at(t[0])),
        |_| {},
    )
    .unwrap()
}

#[test]
fn learned_runs_leave_the_shortest_path_for_the_road() {
    for model in [ModelKind::GpMixtureAerial, ModelKind::SingleGp] {
        let map = world(true);
        let lc = least_cost(&map);
        let params = NavigateParams {
            model,
            runs: 6,
            ..NavigateParams::default()
        };
        let log = run_task(&map, &params);
        assert_eq!(log.runs.len(), 6);
        let first = &log.runs[0];
        // Run 1: no observation yet, so the straight path: 7.5 m of grass at 4.0 and 3 m of
        // road at 0.5.
        assert!(first.drive.reached);
        assert!(first.planned[0].iter().all(|c| c.j == 3), "{model:?}");
        assert!((first.drive.experienced_cost - 31.5).abs() < 1.5);
        assert!(log.runs.iter().all(|r| r.drive.reached));
        let best_later = log.runs[1..]
            .iter()
            .map(|r| r.drive.experienced_cost)
            .fold(f64::INFINITY, f64::min);
        if model == ModelKind::GpMixtureAerial {
            // The colour tells where the road is after one crossing: the road from run 3 on.
            for r in &log.runs[2..] {
                assert!(
                    r.drive.experienced_cost <= 1.1 * lc,
                    "run {}: {} vs least-cost {lc}",
                    r.run,
                    r.drive.experienced_cost
                );
            }
        } else {
            // Position alone: it explores, and some later run is much cheaper than the first.
            assert!(
                best_later < 0.8 * first.drive.experienced_cost,
                "{best_later}"
            );
        }
        // The model knows the visited cells and the road.
        assert_eq!(log.fields.len(), 6);
        assert!(!log.visited.is_empty());
        let f = log.fields.last().unwrap();
        let road = rect().index(Cell::new(12, 6)).unwrap();
        assert!(
            (f.mean[road] - 0.5).abs() < 0.5,
            "{model:?}: {}",
            f.mean[road]
        );
    }
}

#[test]
fn energy_cells_average_power_over_distance() {
    let map = world(false);
    let params = NavigateParams {
        model: ModelKind::GpMixture,
        objective: Objective::Energy,
        runs: 1,
        ..NavigateParams::default()
    };
    let log = run_task(&map, &params);
    // Power = vibration × 1 m/s, so energy per metre is the cell's vibration value.
    for &(k, v) in &log.visited {
        let truth = vibration(rect().cell(k));
        assert!((v - truth).abs() < 0.05, "{v} vs {truth}");
    }
    assert_eq!(log.visited.len(), 22);
    // Energy = 7.5 m × 4 J/m + 3 m × 0.5 J/m.
    assert!((log.runs[0].drive.experienced_cost - 31.5).abs() < 1.5);
}

#[test]
fn bad_inputs_are_errors() {
    let r = rect();
    let e = NavigationMap::new(
        r,
        D,
        vec![true; r.len()],
        Some(vec![Rgb8::new(0, 0, 0); 10]),
    )
    .unwrap_err();
    assert!(matches!(e, NavigateError::BadInput(_)));
    assert!(e.to_string().contains("aerial image has 10 pixels"), "{e}");
    assert!(NavigationMap::new(r, D, vec![true; 3], None).is_err());
    assert!(NavigationMap::new(r, 0.0, vec![true; r.len()], None).is_err());

    let t = task();
    let never = |_| -> Result<Scripted, String> { unreachable!("no run may start") };
    // The aerial model without an image.
    let no_image = world(false);
    let e = navigate(&no_image, &t, &NavigateParams::default(), never, |_| {}).unwrap_err();
    assert!(e.to_string().contains("aerial image"), "{e}");
    // A goal outside the grid, and one on an impassable cell.
    let map = world(true);
    let outside = vec![t[0], Point2::new(100.0, 1.0)];
    let e = navigate(&map, &outside, &NavigateParams::default(), never, |_| {}).unwrap_err();
    assert!(
        matches!(e, NavigateError::Inadmissible { index: 1, .. }),
        "{e}"
    );
    let mut adm = vec![true; r.len()];
    // A wall across the world at column 12: the goal cannot be reached.
    for j in 0..H as i32 {
        adm[r.index(Cell::new(12, j)).unwrap()] = false;
    }
    let walled = NavigationMap::new(r, D, adm, None).unwrap();
    let params = NavigateParams {
        model: ModelKind::SingleGp,
        ..NavigateParams::default()
    };
    let e = navigate(&walled, &t, &params, never, |_| {}).unwrap_err();
    assert!(
        matches!(e, NavigateError::Unreachable { from: 0, to: 1 }),
        "{e}"
    );
    // No runs, a task without a goal, a robot that cannot be made.
    let zero = NavigateParams {
        runs: 0,
        ..params.clone()
    };
    assert!(navigate(&walled, &t, &zero, never, |_| {}).is_err());
    assert!(navigate(&map, &t[..1], &params, never, |_| {}).is_err());
    let e = navigate(
        &map,
        &t,
        &params,
        |_| Err::<Scripted, _>("no robot"),
        |_| {},
    )
    .unwrap_err();
    assert!(matches!(e, NavigateError::Robot(_)), "{e}");
}
