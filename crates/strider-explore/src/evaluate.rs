//! Benchmark tours after exploration (Prágr22 §5, Tbl. 5): the robot visits a scenario's
//! waypoints in order with the map and models frozen as the exploration left them, under one of
//! three navigation modes, and each segment is timed in robot time.
//!
//! * [`NavigationMode::Flat`] — the baseline: shortest admissible paths (Eq. 5 costs) and the
//!   reactive gait (the fastest gait; the stuck reflex switches to the rough-terrain gait).
//! * [`NavigationMode::GaitSelection`] — the learned gait choice (Alg. 4) on straight paths
//!   between waypoints; where the straight segment crosses an inadmissible cell the shortest
//!   admissible path is used instead.
//! * [`NavigationMode::Learned`] — the proposed: cheapest paths on the learned, merged cost grid
//!   and the learned gait choice.

use crate::kernel::{MissionError, TrajectorySample};
use crate::params::MissionParams;
use crate::planner::{CostMode, PlanningView, nearest_where};
use crate::tour_explorer::stuck::{reflex_stuck, stuck_signals};
use serde::Serialize;
use strider_core::grid::CellRay;
use strider_core::interface::{Robot, SensorSink};
use strider_core::{Cell, GaitId, Point2, PoseStamped};
use strider_learn::cost_model::GaitCostModel;
use strider_learn::signals::{FallbackTimer, InverseVelocityCost, TurningTime};
use strider_map::ElevationMap;
use strider_plan::grid::Dijkstra;

/// How the robot navigates a benchmark tour.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
pub enum NavigationMode {
    /// Shortest paths, reactive gait.
    Flat,
    /// Straight paths, learned gait.
    GaitSelection,
    /// Learned costs and gaits.
    Learned,
}

impl NavigationMode {
    /// All modes, in report order.
    pub const ALL: [NavigationMode; 3] = [
        NavigationMode::Flat,
        NavigationMode::GaitSelection,
        NavigationMode::Learned,
    ];

    /// The report name.
    pub fn name(self) -> &'static str {
        match self {
            NavigationMode::Flat => "flat",
            NavigationMode::GaitSelection => "gait-selection",
            NavigationMode::Learned => "learned",
        }
    }
}

/// One timed segment of a tour.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct SegmentResult {
    /// Index of the waypoint the segment starts at.
    pub from: usize,
    /// Index of the waypoint it ends at.
    pub to: usize,
    /// Robot time spent, s.
    pub time_s: f64,
    /// Whether the waypoint was reached (false: the segment timed out or had no path).
    pub reached: bool,
    /// Control ticks on which the robot refused the next cell of its path.
    pub blocked_ticks: usize,
    /// Control ticks spent with the stuck reflex's rough gait.
    pub fallback_ticks: usize,
    /// Whether a path was found at the start of the segment.
    pub planned: bool,
}

/// A timed tour.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct TourResult {
    /// Navigation mode.
    pub mode: NavigationMode,
    /// Segments in order.
    pub segments: Vec<SegmentResult>,
    /// Sum of the segment times, s.
    pub total_s: f64,
    /// Every segment reached its waypoint.
    pub completed: bool,
    /// Trajectory at 2 Hz.
    pub trajectory: Vec<TrajectorySample>,
}

/// Records poses and watches for the stuck condition while a tour runs (no mapping, no
/// learning: the models are frozen).
struct TourSink {
    pose: Option<PoseStamped>,
    signal: InverseVelocityCost,
    turns: TurningTime,
    moving: bool,
    trajectory: Vec<TrajectorySample>,
    poses: u64,
}

impl TourSink {
    /// The robot's latest position, if a pose arrived.
    fn position(&self) -> Option<Point2> {
        self.pose.map(|p| Point2::new(p.position.x, p.position.y))
    }
}

impl SensorSink for TourSink {
    /// The map is frozen during a tour: no scans needed.
    fn wants_cloud(&self, _sensor: u8) -> bool {
        false
    }

    fn on_pose(&mut self, pose: &PoseStamped) {
        if !(pose.position.x.is_finite() && pose.position.y.is_finite()) {
            return;
        }
        self.pose = Some(*pose);
        self.turns.push(pose.stamp, pose.yaw);
        self.poses += 1;
        if self.poses % 10 == 1 {
            self.trajectory.push(TrajectorySample {
                t: pose.stamp,
                x: pose.position.x,
                y: pose.position.y,
                gait: pose.gait.0,
            });
        }
        if self.moving {
            self.signal.push(pose, pose.gait);
        }
    }
}

/// A straight path from `a` to `b` if every cell it crosses is admissible.
fn straight_path(map: &ElevationMap, a: Point2, b: Point2) -> Option<Vec<Point2>> {
    let d = map.cell_size();
    let ok = CellRay::new(a, b, d).all(|c| map.is_observed(c) && map.is_admissible(c));
    ok.then(|| vec![a, b])
}

/// How a tour is driven under one navigation mode: the views it plans and chooses gaits on,
/// and the gait in use.
struct Navigator<'a> {
    map: &'a ElevationMap,
    mode: NavigationMode,
    /// Flat costs: the paths of the flat and gait-selection modes.
    flat: Option<PlanningView>,
    /// Learned costs: the gait choice of the gait-selection and learned modes, the paths of
    /// the learned mode.
    learned: Option<PlanningView>,
    fastest: GaitId,
    rough: GaitId,
    /// The 3·r_robot disc a waypoint's nearest admissible cell is searched in.
    near: Vec<(i32, i32)>,
    /// Control period, s.
    dt: f64,
    /// The slowest gait's speed, m/s (sizes a segment's time limit).
    v_min: f64,
    gait: GaitId,
}

impl<'a> Navigator<'a> {
    fn new(
        map: &'a ElevationMap,
        models: &[GaitCostModel],
        params: &MissionParams,
        mode: NavigationMode,
    ) -> Self {
        // Only the views the mode reads.
        let view =
            |mode| PlanningView::build(map, models, mode, params.c_loss, params.bounds.as_ref());
        let flat = (mode != NavigationMode::Learned)
            .then(|| view(CostMode::Flat))
            .flatten();
        let learned = (mode != NavigationMode::Flat)
            .then(|| view(CostMode::Learned))
            .flatten();
        let v_min = params
            .gaits
            .iter()
            .map(|g| g.v_max)
            .fold(f64::INFINITY, f64::min)
            .max(1e-6);
        Self {
            map,
            mode,
            flat,
            learned,
            fastest: params.fastest_gait(),
            rough: params.rough_gait(),
            near: strider_core::grid::disc_offsets(3.0 * map.params().r_robot, map.cell_size()),
            dt: 1.0 / params.rates.control_hz,
            v_min,
            gait: params.fastest_gait(),
        }
    }

    /// The view paths are planned on.
    fn plan_view(&self) -> Option<&PlanningView> {
        match self.mode {
            NavigationMode::Flat | NavigationMode::GaitSelection => self.flat.as_ref(),
            NavigationMode::Learned => self.learned.as_ref(),
        }
    }

    /// The view gaits are chosen on (none: the reactive gait).
    fn gait_view(&self) -> Option<&PlanningView> {
        match self.mode {
            NavigationMode::Flat => None,
            NavigationMode::GaitSelection | NavigationMode::Learned => self.learned.as_ref(),
        }
    }

    /// The waypoints from `from` to `to` under the mode.
    fn plan(&self, from: Point2, to: Point2) -> Option<Vec<Point2>> {
        let map = self.map;
        if self.mode == NavigationMode::GaitSelection
            && let Some(p) = straight_path(map, from, to)
        {
            return Some(p);
        }
        let view = self.plan_view()?;
        // Waypoints may sit next to an obstacle or the bounds, which the footprint cannot
        // approach: use the nearest cell where the planning grid lets the centre be.
        let centre_ok = |c: Cell| view.grid.is_admissible(c);
        let src = nearest_where(map.cell_at(from.x, from.y)?, &self.near, centre_ok)?;
        let dst = nearest_where(map.cell_at(to.x, to.y)?, &self.near, centre_ok)?;
        let cells = view.path(&mut Dijkstra::new(), src, dst)?;
        Some(view.drive_waypoints_between(&cells, from, to))
    }

    /// The gait at `p`: the stuck reflex's rough gait, the learned choice, or the fastest.
    fn choose_gait(&self, p: Point2, stuck: bool) -> GaitId {
        if stuck {
            self.rough
        } else if let (Some(v), Some(c)) = (self.gait_view(), self.map.cell_at(p.x, p.y)) {
            v.choose_gait(c).unwrap_or(self.gait)
        } else {
            self.fastest
        }
    }

    /// Drives segment `index` from `a` to `b`, timed, replanning when the robot refuses its
    /// path (at most five times).
    fn drive_segment<R: Robot>(
        &mut self,
        robot: &mut R,
        sink: &mut TourSink,
        fallback: &mut FallbackTimer,
        index: usize,
        (a, b): (Point2, Point2),
    ) -> Result<SegmentResult, MissionError> {
        let d = self.map.cell_size();
        let r_robot = self.map.params().r_robot;
        let t_start = robot.now();
        let limit = 60.0 + 20.0 * a.dist(b) / self.v_min;
        let mut path = sink.position().and_then(|p| self.plan(p, b));
        let mut reached = false;
        if let Some(p) = &path {
            robot.follow(p);
        }
        let mut replans = 0;
        let (mut blocked_ticks, mut fallback_ticks) = (0usize, 0usize);
        let planned = path.is_some();
        while path.is_some() && robot.now() - t_start < limit {
            sink.moving = true;
            let st = robot.advance(self.dt, sink).map_err(MissionError::robot)?;
            let t = robot.now();
            let Some(p) = sink.position() else { continue };
            if p.dist(b) <= 1.5 * d || st.idle {
                reached = p.dist(b) <= 3.0 * d.max(r_robot);
                break;
            }
            blocked_ticks += st.blocked as usize;
            if st.blocked && replans < 5 {
                replans += 1;
                path = self.plan(p, b);
                if let Some(q) = &path {
                    robot.follow(q);
                }
            }
            fallback.update(t, reflex_stuck(&sink.signal, &sink.turns));
            let stuck = fallback.is_active(t);
            fallback_ticks += stuck as usize;
            let g = self.choose_gait(p, stuck);
            if g != self.gait {
                self.gait = g;
                robot.set_gait(g);
            }
        }
        sink.moving = false;
        sink.signal.reset();
        robot.follow(&[]);
        Ok(SegmentResult {
            from: index,
            to: index + 1,
            time_s: robot.now() - t_start,
            reached,
            blocked_ticks,
            fallback_ticks,
            planned,
        })
    }
}

/// Runs the tour `waypoints` (the robot standing at the first one) under `mode`.
pub fn run_tour<R: Robot>(
    robot: &mut R,
    map: &ElevationMap,
    models: &[GaitCostModel],
    params: &MissionParams,
    tour: &[Point2],
    mode: NavigationMode,
) -> Result<TourResult, MissionError> {
    let (signal, turns, mut fallback) = stuck_signals(params, params.inverse_velocity().window_s)?;
    let mut sink = TourSink {
        pose: None,
        signal,
        turns,
        moving: false,
        trajectory: Vec::new(),
        poses: 0,
    };
    let mut nav = Navigator::new(map, models, params, mode);
    robot.set_gait(nav.gait);
    // Let one pose arrive.
    robot
        .advance(nav.dt, &mut sink)
        .map_err(MissionError::robot)?;
    let mut segments = Vec::new();
    for (i, w) in tour.windows(2).enumerate() {
        segments.push(nav.drive_segment(robot, &mut sink, &mut fallback, i, (w[0], w[1]))?);
    }
    let total_s = segments.iter().map(|s| s.time_s).sum();
    let completed = segments.iter().all(|s| s.reached);
    Ok(TourResult {
        mode,
        segments,
        total_s,
        completed,
        trajectory: sink.trajectory,
    })
}
