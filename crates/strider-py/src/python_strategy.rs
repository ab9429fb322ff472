//! A strategy and a cost model written in Python, run inside the Rust mission loop.
//!
//! The kernel maps, drives and measures as for every strategy; at each decision (every
//! `decision_period` simulated seconds) the cost samples measured since the last one go to the
//! cost model's `update(descriptors, costs, gaits)`, the model's `predict(descriptors)` gives the
//! cost and variance of every observed cell, and the strategy's `decide(snapshot)` returns what
//! to do next: a goal is driven along the cheapest route on the map ([`GoalPlanner`]), a path
//! as given. A Python exception ends the mission (termination `StrategyFailed`) and is raised
//! from `run_python`.

use std::time::Instant;

use numpy::{IntoPyArray, PyArrayMethods, PyReadonlyArray1};
use pyo3::prelude::*;
use pyo3::types::PyDict;
use strider_core::PoseStamped;
use strider_core::interface::MotionState;
use strider_core::snapshot::{GoalKind, Snapshot};
use strider_core::{GaitId, Point2};
use strider_explore::kernel::{Actuators, Body, GoalCounts, map_layers, site_at};
use strider_explore::{FromParams, Mission, MissionStrategy, Termination, TourExplorer};
use strider_learn::signals::{InverseVelocityCost, InverseVelocityParams};
use strider_map::descriptors::{shape_lab_descriptor, shape_lab_descriptors};

use crate::errors::{msg, to_py};
use crate::goal_planner::GoalPlanner;
use crate::layers::{grid, to_dict};

/// The descriptor of a cost sample and of a cell: Prágr19's shape + Lab colour (5 values).
const DESC: usize = 5;

/// Cost samples measured since the last decision.
#[derive(Default)]
struct Samples {
    desc: Vec<f64>,
    cost: Vec<f64>,
    gait: Vec<u8>,
}

/// What the Python objects cost: decisions taken and the wall time spent in Python.
#[derive(Default, Clone, Copy)]
struct Calls {
    decisions: u64,
    python_s: f64,
}

struct PyStrategy {
    strategy: Py<PyAny>,
    model: Option<Py<PyAny>>,
    period_s: f64,
    next_decision: f64,
    signal: InverseVelocityCost,
    delta_desc: f64,
    gaits: usize,
    samples: Samples,
    learned: usize,
    goal: Option<Point2>,
    /// Whether the last goal had a route (`None` before the first goal).
    goal_reachable: Option<bool>,
    planner: GoalPlanner,
    calls: Calls,
    error: Option<PyErr>,
}

/// The observed cells' descriptors (rows of DESC) and their row-major indices in `rect`.
fn cell_descriptors(
    body: &Body,
    rect: strider_core::CellRect,
    delta: f64,
) -> (Vec<f64>, Vec<usize>) {
    // One view over the rectangle for all cells (what `shape_lab_descriptor` builds per cell).
    let raster = shape_lab_descriptors(body.map(), rect, delta);
    let (mut desc, mut at) = (Vec::new(), Vec::new());
    for (k, d) in raster.values.iter().enumerate() {
        if let Some(d) = d {
            desc.extend(d.iter().map(|v| *v as f64));
            at.push(k);
        }
    }
    (desc, at)
}

/// A point from a Python pair.
fn point(v: &Bound<'_, PyAny>) -> PyResult<Point2> {
    let (x, y): (f64, f64) = v.extract()?;
    if !(x.is_finite() && y.is_finite()) {
        return Err(msg(format!("decide: point ({x}, {y}) is not finite")));
    }
    Ok(Point2::new(x, y))
}

impl PyStrategy {
    /// The cost model's update with the new samples, then its predictions over the observed
    /// cells as (cost, variance) layers of `snapshot`.
    fn model_step(
        &mut self,
        py: Python<'_>,
        body: &Body,
        snap: &Bound<'_, PyDict>,
    ) -> PyResult<()> {
        let Some(model) = self.model.as_ref() else {
            return Ok(());
        };
        let s = std::mem::take(&mut self.samples);
        if !s.cost.is_empty() {
            self.learned += s.cost.len();
            let n = s.cost.len();
            let desc = s.desc.into_pyarray(py).reshape([n, DESC])?;
            model.call_method1(
                py,
                "update",
                (desc, s.cost.into_pyarray(py), s.gait.into_pyarray(py)),
            )?;
        }
        let rect = map_layers(body.map()).rect;
        let (desc, at) = cell_descriptors(body, rect, self.delta_desc);
        let n = at.len();
        let out =
            model.call_method1(py, "predict", (desc.into_pyarray(py).reshape([n, DESC])?,))?;
        let (mean, var): (PyReadonlyArray1<f64>, PyReadonlyArray1<f64>) = out.extract(py)?;
        let (mean, var) = (mean.as_slice()?, var.as_slice()?);
        if mean.len() != n || var.len() != n {
            return Err(msg(format!(
                "predict returned {} and {} values for {n} descriptors",
                mean.len(),
                var.len()
            )));
        }
        let (mut cost, mut variance) = (vec![f32::NAN; rect.len()], vec![f32::NAN; rect.len()]);
        for (k, &i) in at.iter().enumerate() {
            cost[i] = mean[k] as f32;
            variance[i] = var[k] as f32;
        }
        let (rows, cols) = (rect.height as usize, rect.width as usize);
        snap.set_item("cost", grid(py, cost, rows, cols)?)?;
        snap.set_item("cost_variance", grid(py, variance, rows, cols)?)?;
        Ok(())
    }

    /// One decision: the snapshot to Python, its answer to the robot.
    fn decide(
        &mut self,
        py: Python<'_>,
        body: &Body,
        robot: &mut dyn Actuators,
        t: f64,
    ) -> PyResult<bool> {
        let snap = PyDict::new(py);
        snap.set_item("time_s", t)?;
        if let Some(p) = body.pose() {
            snap.set_item("pose", (p.position.x, p.position.y, p.yaw))?;
            snap.set_item("gait", p.gait.0)?;
        }
        snap.set_item("gaits", self.gaits)?;
        snap.set_item("goal_reachable", self.goal_reachable)?;
        snap.set_item(
            "layers",
            to_dict(py, map_layers(body.map()), body.map().cell_size())?,
        )?;
        self.model_step(py, body, &snap)?;
        let answer = self.strategy.call_method1(py, "decide", (snap,))?;
        let answer = answer.bind(py);
        if answer.is_none() {
            return Ok(false);
        }
        let d = answer
            .cast::<PyDict>()
            .map_err(|_| msg("decide must return a dict or None"))?;
        for key in d.keys() {
            let k: String = key.extract()?;
            if !["goal", "path", "gait", "done"].contains(&k.as_str()) {
                return Err(msg(format!(
                    "decide returned the unknown key {k:?} (known: goal, path, gait, done)"
                )));
            }
        }
        if let Some(g) = d.get_item("gait")? {
            let g: usize = g.extract()?;
            if g >= self.gaits {
                return Err(msg(format!(
                    "decide: gait {g} out of range: the robot has {}",
                    self.gaits
                )));
            }
            robot.set_gait(GaitId(g as u8));
        }
        if let Some(p) = d.get_item("path")? {
            let path: Vec<Point2> = p.try_iter()?.map(|v| point(&v?)).collect::<PyResult<_>>()?;
            self.goal = path.last().copied();
            robot.follow(&path);
        } else if let Some(g) = d.get_item("goal")? {
            let goal = point(&g)?;
            self.goal = Some(goal);
            let route = body
                .position()
                .and_then(|from| self.planner.route(body.map(), from, goal));
            self.goal_reachable = Some(route.is_some());
            // No known route: the robot stops rather than drive blind into the unknown.
            robot.follow(route.as_deref().unwrap_or(&[]));
        }
        Ok(match d.get_item("done")? {
            Some(v) => v.is_truthy()?,
            None => false,
        })
    }
}

impl MissionStrategy for PyStrategy {
    fn name(&self) -> &'static str {
        "python"
    }
    fn control_hz(&self) -> f64 {
        10.0
    }
    fn on_pose(&mut self, body: &Body, pose: &PoseStamped) {
        let Some(s) = self.signal.push(pose, pose.gait) else {
            return;
        };
        let map = body.map();
        if let Some(cell) = map.cell_at(s.position.x, s.position.y)
            && let Some(d) = shape_lab_descriptor(map, cell, self.delta_desc)
        {
            self.samples.desc.extend(d.iter().map(|v| *v as f64));
            self.samples.cost.push(s.cost);
            self.samples.gait.push(s.gait.0);
        }
    }
    fn tick(
        &mut self,
        body: &mut Body,
        robot: &mut dyn Actuators,
        state: &mut MotionState,
        t: f64,
    ) -> Option<Termination> {
        if state.idle {
            self.signal.reset();
        }
        if t < self.next_decision || self.error.is_some() {
            return None;
        }
        self.next_decision = t + self.period_s;
        let wall = Instant::now();
        let r = Python::attach(|py| self.decide(py, body, robot, t));
        self.calls.python_s += wall.elapsed().as_secs_f64();
        self.calls.decisions += 1;
        match r {
            Ok(false) => None,
            Ok(true) => Some(Termination::GoalsCleared),
            Err(e) => {
                self.error = Some(e);
                Some(Termination::StrategyFailed)
            }
        }
    }
    fn goal_counts(&self) -> GoalCounts {
        GoalCounts {
            spatial_goals: usize::from(self.goal.is_some()),
            cost_goals: 0,
            learning_set: self.learned,
        }
    }
    fn describe(&self, body: &Body, snap: &mut Snapshot) {
        if let Some(g) = self.goal {
            let site = site_at(body, g);
            snap.push_goals("python_goal", GoalKind::Spatial, vec![site]);
            snap.tour = vec![site];
        }
    }
}

/// Runs a mission of the Python `strategy` (and cost `model`) on `scenario`; returns the
/// report as a dict with the final layers.
#[pyfunction]
#[pyo3(signature = (scenario, strategy, model, seed, world_seed, time_limit, decision_period))]
#[allow(clippy::too_many_arguments)]
pub fn run_python<'py>(
    py: Python<'py>,
    scenario: &str,
    strategy: Py<PyAny>,
    model: Option<Py<PyAny>>,
    seed: u64,
    world_seed: u64,
    time_limit: Option<f64>,
    decision_period: f64,
) -> PyResult<Bound<'py, PyDict>> {
    if !(decision_period.is_finite() && decision_period > 0.0) {
        return Err(msg(format!(
            "decision_period {decision_period}: must be a finite number of seconds > 0"
        )));
    }
    let sc = strider_experiments::trial::load(scenario, world_seed).map_err(to_py)?;
    let mut params =
        strider_experiments::trial::mission_params(&sc, strider_explore::Strategy::Gtsp, seed)
            .map_err(to_py)?;
    if let Some(t) = time_limit {
        params.time_limit_s = strider_experiments::trial::checked_time_limit(t).map_err(to_py)?;
    }
    let iv: InverseVelocityParams = params.inverse_velocity();
    let signal = InverseVelocityCost::new(iv).map_err(|e| msg(e.to_string()))?;
    let planner = GoalPlanner::new(
        params.gaits.len(),
        params.c_loss,
        params.bounds,
        &params.map,
    )
    .map_err(msg)?;
    let strat = PyStrategy {
        strategy,
        model,
        period_s: decision_period,
        next_decision: f64::NEG_INFINITY,
        signal,
        delta_desc: params.map.delta_desc,
        gaits: params.gaits.len(),
        samples: Samples::default(),
        learned: 0,
        goal: None,
        goal_reachable: None,
        planner,
        calls: Calls::default(),
        error: None,
    };
    let body = TourExplorer::body_params(&params);
    let mut mission = Mission::new(body, strat).map_err(|e| msg(e.to_string()))?;
    let cancel = strider_experiments::cancel::Cancel::new();
    let wall = Instant::now();
    let driven = py.detach(|| {
        strider_experiments::parallel::on_worker(|| {
            strider_experiments::trial::drive(&sc, seed, &mut mission, (None, &cancel), |_, _| {})
        })
    });
    let wall_s = wall.elapsed().as_secs_f64();
    driven.map_err(to_py)?;
    let failed = mission.strategy_mut().error.take();
    let d = PyDict::new(py);
    let record = mission.record();
    d.set_item("scenario", &sc.name)?;
    d.set_item("world_seed", world_seed)?;
    d.set_item("seed", seed)?;
    d.set_item("strategy", "python")?;
    d.set_item("termination", format!("{:?}", record.termination))?;
    d.set_item("exploration_time_s", record.exploration_time_s)?;
    d.set_item("driven_m", record.driven_m)?;
    d.set_item("observed_cells", mission.body().map().observed_count())?;
    let s = mission.strategy();
    d.set_item("cost_samples", s.learned)?;
    d.set_item("decisions", s.calls.decisions)?;
    d.set_item("python_s", s.calls.python_s)?;
    d.set_item("mission_wall_s", wall_s)?;
    let last = mission.snapshot(true);
    let layers = last
        .layers
        .ok_or_else(|| msg("the mission's final state has no layers"))?;
    d.set_item("layers", to_dict(py, layers, last.cell_size)?)?;
    match failed {
        // The mission up to the failure travels with the exception (`strider_report`); an
        // exception type that takes no attributes is raised as it is.
        Some(e) => {
            let _ = e.value(py).setattr("strider_report", d);
            Err(e)
        }
        None => Ok(d),
    }
}
