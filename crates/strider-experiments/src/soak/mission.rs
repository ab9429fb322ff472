//! One soak mission: the strategy on its world with the judge watching, then its report
//! checked. Whatever happens (an error, a panic, the wall-clock bound) ends in a
//! [`MissionResult`], never in an error of the soak.

use std::panic::{AssertUnwindSafe, catch_unwind};
use std::time::{Duration, Instant};

use anyhow::{Context, Result};
use serde::Serialize;
use strider_core::snapshot::Snapshot;
use strider_explore::escape::EscapeMission;
use strider_explore::kernel::Strategy;
use strider_explore::rbcm_greedy::RbcmGreedy;
use strider_explore::registry::Configured;
use strider_explore::{FromParams, Mission, Termination, TourExplorer};
use strider_scenario::Scenario;
use strider_sim::Simulator;

use super::judge::Judge;
use super::plan::Task;
use super::reports::{self, Bounds};
use super::robot::{Counts, Judged};
use super::violation::{Findings, Kind, Violation};
use crate::run::Explored;
use crate::trial::{configure, load, robot_spec};

/// A mission's wall-clock bound: this much, plus [`WALL_PER_SIMULATED_S`] per simulated
/// second of its time limit. Missions run at 1–70× real time on a loaded machine (the slowest:
/// `rigid` on courtyard-large), so a mission past its bound is stuck, not slow.
pub const WALL_FLOOR_S: f64 = 120.0;

/// See [`WALL_FLOOR_S`]: a mission must run at least a quarter as fast as real time.
pub const WALL_PER_SIMULATED_S: f64 = 4.0;

/// The wall-clock bound of a mission with a simulated time limit of `limit_s`.
pub fn wall_bound(limit_s: f64) -> Duration {
    Duration::from_secs_f64(WALL_FLOOR_S + WALL_PER_SIMULATED_S * limit_s.clamp(0.0, 1e7))
}

/// How one mission went.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct MissionResult {
    /// The mission.
    #[serde(flatten)]
    pub task: Task,
    /// How the exploration ended (none when the mission did not run to its end).
    pub explored: Option<Explored>,
    /// True poses judged.
    pub poses_judged: u64,
    /// Of them, with the centre in a cell the map's rule on the true elevation calls
    /// inadmissible (an obstacle within the footprint radius); counted, not a violation.
    pub poses_near_obstacles: u64,
    /// Commanded paths judged.
    pub paths_judged: u64,
    /// Snapshots (goals, tour) judged.
    pub snapshots_judged: u64,
    /// Goal sites outside the exploration bounds, summed over the snapshots (counted, not a
    /// violation: the tour must not pick them).
    pub goal_sites_outside_bounds: u64,
    /// The invariants broken.
    pub violations: Vec<Violation>,
    /// Wall time, s.
    pub wall_s: f64,
}

impl MissionResult {
    /// A mission that broke `kind` as `what` says before it could be judged further.
    pub fn failed(task: &Task, kind: Kind, what: String, wall_s: f64) -> Self {
        let mut f = Findings::default();
        f.add(kind, || what);
        Self {
            task: task.clone(),
            explored: None,
            poses_judged: 0,
            poses_near_obstacles: 0,
            paths_judged: 0,
            snapshots_judged: 0,
            goal_sites_outside_bounds: 0,
            violations: f.into_sorted(),
            wall_s,
        }
    }
}

/// What a mission run gathers on its way.
#[derive(Default)]
struct Gathered {
    findings: Findings,
    counts: Counts,
    snapshots: u64,
    goal_sites_outside: u64,
    explored: Option<Explored>,
}

/// Runs `task` with the judge; advancing fails once `bound` has passed.
pub fn run(task: &Task, bound: Duration) -> MissionResult {
    let wall = Instant::now();
    let mut g = Gathered::default();
    let outcome = catch_unwind(AssertUnwindSafe(|| attempt(task, bound, &mut g)));
    match outcome {
        Ok(Ok(())) => {}
        Ok(Err(e)) => g.findings.add(Kind::Crash, || format!("{e:#}")),
        Err(panic) => {
            let msg = panic
                .downcast_ref::<&str>()
                .map(|s| s.to_string())
                .or_else(|| panic.downcast_ref::<String>().cloned())
                .unwrap_or_else(|| "a panic without a message".into());
            g.findings.add(Kind::Crash, || format!("panicked: {msg}"));
        }
    }
    MissionResult {
        task: task.clone(),
        explored: g.explored,
        poses_judged: g.counts.poses,
        poses_near_obstacles: g.counts.near_obstacles,
        paths_judged: g.counts.paths,
        snapshots_judged: g.snapshots,
        goal_sites_outside_bounds: g.goal_sites_outside,
        violations: g.findings.into_sorted(),
        wall_s: wall.elapsed().as_secs_f64(),
    }
}

fn attempt(task: &Task, bound: Duration, g: &mut Gathered) -> Result<()> {
    let wall = Instant::now();
    let sc = load(task.scenario, task.world_seed)?;
    let (_, configured) = configure(&sc, task.strategy, &[])?;
    let judge = Judge::new(&sc).context("ground truth")?;
    let robot = robot_spec(&sc);
    let sim = Simulator::new(&sc, task.seed)?;
    let mut judged = Judged::new(sim, &sc, &judge, bound);
    let limit = task.time_limit_s;
    match &configured {
        Configured::Tour(..) => {
            let mut p = configured
                .tour_mission(&robot, task.seed)
                .context("not a Prágr22 strategy")?;
            p.time_limit_s = limit;
            let mut mission = TourExplorer::mission(p)?;
            let b = drive(&sc, task, &mut mission, &mut judged, g)?;
            let r = reports::tour(&sc, task, &configured, &mission, wall);
            reports::check(&r, &r.explored, &r.trajectory, &b, &mut g.findings);
            reports::tour_counts(&r, &mut g.findings);
        }
        Configured::Rbcm(table) => {
            let mut p = table.explorer_params(&robot)?;
            p.time_limit_s = limit;
            let mut mission = RbcmGreedy::mission(p)?;
            let b = drive(&sc, task, &mut mission, &mut judged, g)?;
            let r = reports::rbcm(&sc, task, table, &mission, wall);
            reports::check(&r, &r.explored, &r.trajectory, &b, &mut g.findings);
            reports::rbcm_counts(&r, &mut g.findings);
        }
        Configured::Escape(mode, table) => {
            let mut p = table.escape_params(&robot, *mode)?;
            p.time_limit_s = limit;
            let mut mission = EscapeMission::mission(p)?;
            let b = drive(&sc, task, &mut mission, &mut judged, g)?;
            let r = reports::escape(&sc, task, table, &mission, wall);
            reports::check(&r, &r.explored, &r.trajectory, &b, &mut g.findings);
            reports::escape_counts(&r, &mut g.findings);
        }
    }
    Ok(())
}

/// Runs `mission` on the judged robot, judging its snapshot about once per simulated second
/// and at the end, and how it ended; returns what its report is checked against.
fn drive<S: Strategy>(
    sc: &Scenario,
    task: &Task,
    mission: &mut Mission<S>,
    judged: &mut Judged,
    g: &mut Gathered,
) -> Result<Bounds> {
    let judge = judged.judge();
    let mut seen = Findings::default();
    let (mut snapshots, mut outside) = (0, 0);
    let ran = mission
        .run_watched(judged, |m, _| {
            snapshots += 1;
            outside += judge_snapshot(&m.snapshot(false), judge, &mut seen);
        })
        .map(|_| ());
    g.findings.merge(std::mem::take(&mut judged.findings));
    g.findings.merge(seen);
    g.counts = judged.counts;
    g.snapshots = snapshots + 1;
    g.goal_sites_outside = outside;
    if let Err(e) = ran {
        if judged.timed_out() {
            g.findings.add(Kind::Termination, || format!("{e}"));
            return Err(anyhow::anyhow!("{e}")).context("stopped by the soak");
        }
        return Err(e.into());
    }
    let last = mission.snapshot(true);
    let mut f = Findings::default();
    g.goal_sites_outside += judge_snapshot(&last, judge, &mut f);
    if let Some(m) = last.measured.iter().find(|m| !m.cost.is_finite()) {
        f.add(Kind::Report, || {
            format!("a measured cost of {} for model {}", m.cost, m.model)
        });
    }
    g.findings.merge(f);
    g.explored = Some(Explored::of(mission));
    let step = 1.0 / mission.strategy().control_hz();
    let rec = mission.record();
    let t = rec.exploration_time_s;
    if t.is_nan() || t > task.time_limit_s + step + 1e-6 {
        g.findings.add(Kind::Termination, || {
            format!(
                "explored for {t} s, past the time limit of {} s plus one control step of {step} s",
                task.time_limit_s
            )
        });
    }
    if rec.termination == Termination::TimeLimit && t < task.time_limit_s - 1e-6 {
        g.findings.add(Kind::Termination, || {
            format!(
                "stopped for the time limit after {t} s of {} s",
                task.time_limit_s
            )
        });
    }
    Ok(Bounds::of(sc, task.time_limit_s, step))
}

/// Judges what a snapshot shows: tour sites (the goals the robot is driving to) inside the
/// exploration bounds, goal sites finite, the gait one the robot has, the pose and time
/// finite. Returns the goal sites outside the exploration bounds (counted only: a strategy may
/// list sites it cannot reach, e.g. cost-model goals on every map cell of a terrain class; the
/// tour must not pick them).
fn judge_snapshot(snap: &Snapshot, judge: &Judge, f: &mut Findings) -> u64 {
    let t = snap.time_s;
    let at = |e: String| move || format!("t {t:.2} s: {e}");
    let mut outside = 0;
    for set in &snap.goals {
        for &p in &set.sites {
            if !(p.x.is_finite() && p.y.is_finite() && p.z.is_finite()) {
                f.add(
                    Kind::Plan,
                    at(format!("goal set {} site {p:?} not finite", set.name)),
                );
            } else if judge.site("goal", p).is_err() {
                outside += 1;
            }
        }
    }
    for &p in &snap.tour {
        if let Err(e) = judge.site("tour", p) {
            f.add(Kind::Plan, at(e));
        }
    }
    if let Some(g) = snap.gait.filter(|g| g.0 as usize >= judge.gaits()) {
        f.add(
            Kind::Plan,
            at(format!("snapshot gait {} of {}", g.0, judge.gaits())),
        );
    }
    let pose_ok = snap
        .robot
        .is_none_or(|r| r.position.x.is_finite() && r.position.y.is_finite() && r.yaw.is_finite());
    if !(t.is_finite() && pose_ok) {
        f.add(
            Kind::Report,
            at(format!(
                "snapshot time {t} or pose {:?} not finite",
                snap.robot
            )),
        );
    }
    outside
}
