//! Repeated navigation that actively improves over time (`004` Alg. 1, Nardi & Stachniss).
//!
//! For each navigation task — a start and one or more goals, driven 25 times — the robot plans
//! on the current model with the rectified lower confidence bound of Eq. 7–8 ([`lcb_path`],
//! decision 26), follows the path while its proprioception (vibration or power) is averaged per
//! grid cell (`004` §VI-A: "an average filter assigns an intensity value to each cell"), then
//! refits the model on every cell visited so far (Alg. 1 lines 5–11) and predicts μ and σ² over
//! the whole grid for the next run:
//!
//! * [`ModelKind::SingleGp`] — one GP on position (`004` §III): the mixture with one component.
//! * [`ModelKind::GpMixture`] — the GP mixture with mean-shift gating learned from the
//!   observations and position only (§IV-A/B).
//! * [`ModelKind::GpMixtureAerial`] — the same with gating regressions on (x, y, r, g, b) of the
//!   aerial image (§IV-C, Eq. 6), ARD squared-exponential.
//!
//! The inputs are what the paper gives the robot: the grid map 𝓜 (which cells the robot may
//! occupy) and the aerial image 𝓘 ([`NavigationMap`]); everything about the terrain's effect
//! arrives through [`Robot`] as proprioception. The model never reads ground truth; the
//! baselines' paths (shortest, least-cost on the true field) are planned by the caller and
//! driven here by [`drive_task`], measured exactly like the learned runs.
//!
//! Measurements: a proprioceptive reading at time t covers the interval since the previous one;
//! its distance ds is the distance between the poses at the two instants and it is attributed to
//! the cell of the interval's midpoint. Vibration: the cell value is the mean of its readings
//! while moving and a run's experienced cost is ∫ v ds (m/s² · m). Energy: the cell value is
//! Σ P·dt / Σ ds over its readings (J/m; kept only once the cell saw ≥ 0.2 cell sizes of travel)
//! and a run's experienced cost is Σ P·dt (J). Both experienced costs are the functional the
//! least-cost path minimises, so they compare directly.

use std::time::Instant;

use serde::Serialize;
use strider_core::interface::{Robot, SensorSink};
use strider_core::{Cell, CellRect, Point2, PoseStamped, Proprioception, Rgb8};
use strider_learn::mixture::{FieldPrediction, MixtureError, MixtureModel, MixtureParams};
use strider_plan::grid::lcb::{LcbParams, lcb_grid, lcb_path};
use strider_plan::grid::{Dijkstra, GridError, SearchError};
use thiserror::Error;

use crate::planner::waypoints;

/// What the robot learns to avoid (`004` §VI-B).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize)]
pub enum Objective {
    /// Vertical-acceleration RMS, m/s² per cell; cost ∫ v ds.
    Vibration,
    /// Energy per metre, J/m per cell; cost = energy used, J.
    Energy,
}

impl Objective {
    /// The report name.
    pub fn name(self) -> &'static str {
        match self {
            Objective::Vibration => "vibration",
            Objective::Energy => "energy",
        }
    }

    /// Parses a report name.
    pub fn parse(s: &str) -> Option<Objective> {
        match s {
            "vibration" => Some(Objective::Vibration),
            "energy" => Some(Objective::Energy),
            _ => None,
        }
    }
}

/// The model of `004` Table I.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize)]
pub enum ModelKind {
    /// One GP on position.
    SingleGp,
    /// GP mixture, gating on position.
    GpMixture,
    /// GP mixture, gating on position and aerial colour (the paper's approach).
    GpMixtureAerial,
}

impl ModelKind {
    /// All models, in Table I order.
    pub const ALL: [ModelKind; 3] = [
        ModelKind::SingleGp,
        ModelKind::GpMixture,
        ModelKind::GpMixtureAerial,
    ];

    /// The report name.
    pub fn name(self) -> &'static str {
        match self {
            ModelKind::SingleGp => "single-gp",
            ModelKind::GpMixture => "gp-mixture",
            ModelKind::GpMixtureAerial => "gp-mixture-aerial",
        }
    }

    /// Parses a report name.
    pub fn parse(s: &str) -> Option<ModelKind> {
        ModelKind::ALL.into_iter().find(|m| m.name() == s)
    }
}

/// Why navigation could not run.
#[derive(Debug, Error)]
pub enum NavigateError {
    /// Inputs of inconsistent sizes (grid map, aerial image).
    #[error("{0}")]
    BadInput(String),
    /// A parameter out of its domain.
    #[error("bad navigation parameter: {0}")]
    Params(String),
    /// A waypoint of the task lies outside the grid or on a cell the robot may not occupy.
    #[error("waypoint {index} ({x:.2}, {y:.2}) is outside the grid map or not traversable")]
    Inadmissible {
        /// Index of the waypoint in the task.
        index: usize,
        /// Its x, metres.
        x: f64,
        /// Its y, metres.
        y: f64,
    },
    /// No traversable path joins two consecutive waypoints.
    #[error("no traversable path from waypoint {from} to waypoint {to}")]
    Unreachable {
        /// Index of the start waypoint.
        from: usize,
        /// Index of the goal waypoint.
        to: usize,
    },
    /// The model failed.
    #[error("model: {0}")]
    Model(#[from] MixtureError),
    /// The cost grid could not be built.
    #[error("cost grid: {0}")]
    Grid(#[from] GridError),
    /// The search could not start.
    #[error("planner: {0}")]
    Search(#[from] SearchError),
    /// The robot (or creating it) failed.
    #[error("robot: {0}")]
    Robot(String),
}

/// The inputs of Alg. 1: the grid map 𝓜 and, for the aerial model, the aerial image 𝓘, both
/// row-major over one rectangle of the cell lattice.
#[derive(Clone, Debug)]
pub struct NavigationMap {
    rect: CellRect,
    cell_size: f64,
    admissible: Vec<bool>,
    aerial: Option<Vec<Rgb8>>,
}

impl NavigationMap {
    /// Checks that the mask and the image (if any) hold one value per cell of `rect`.
    pub fn new(
        rect: CellRect,
        cell_size: f64,
        admissible: Vec<bool>,
        aerial: Option<Vec<Rgb8>>,
    ) -> Result<NavigationMap, NavigateError> {
        if !(cell_size.is_finite() && cell_size > 0.0) {
            return Err(NavigateError::BadInput(format!(
                "cell size {cell_size} is not a positive number"
            )));
        }
        if rect.is_empty() {
            return Err(NavigateError::BadInput("the grid map has no cells".into()));
        }
        if admissible.len() != rect.len() {
            return Err(NavigateError::BadInput(format!(
                "the grid map has {} cells but its rectangle {}×{} has {}",
                admissible.len(),
                rect.width,
                rect.height,
                rect.len()
            )));
        }
        if let Some(a) = &aerial
            && a.len() != rect.len()
        {
            return Err(NavigateError::BadInput(format!(
                "the aerial image has {} pixels but the grid map is {}×{} = {} cells",
                a.len(),
                rect.width,
                rect.height,
                rect.len()
            )));
        }
        Ok(NavigationMap {
            rect,
            cell_size,
            admissible,
            aerial,
        })
    }

    /// The rectangle of the grid.
    pub fn rect(&self) -> CellRect {
        self.rect
    }

    /// Cell size, metres.
    pub fn cell_size(&self) -> f64 {
        self.cell_size
    }

    /// Where the robot may be, row-major.
    pub fn admissible(&self) -> &[bool] {
        &self.admissible
    }

    /// The aerial image, row-major, if given.
    pub fn aerial(&self) -> Option<&[Rgb8]> {
        self.aerial.as_deref()
    }

    /// Row-major index of the cell containing `p`, if inside.
    pub fn index_of(&self, p: Point2) -> Option<usize> {
        Cell::containing(p.x, p.y, self.cell_size).and_then(|c| self.rect.index(c))
    }

    /// The gating features of every cell for `kind`, standardised per feature over the whole
    /// grid (mean 0, standard deviation 1; the image statistics, no labels), row-major, and
    /// the feature count: (x, y), or (x, y, r, g, b) for the aerial model.
    pub fn gate_features(&self, kind: ModelKind) -> Result<(Vec<f64>, usize), NavigateError> {
        let aerial = match kind {
            ModelKind::GpMixtureAerial => Some(self.aerial.as_deref().ok_or_else(|| {
                NavigateError::BadInput("the gp-mixture-aerial model needs an aerial image".into())
            })?),
            _ => None,
        };
        let dim = if aerial.is_some() { 5 } else { 2 };
        let n = self.rect.len();
        let mut f = vec![0.0; n * dim];
        for (k, row) in f.chunks_exact_mut(dim).enumerate() {
            let c = self.rect.cell(k).center(self.cell_size);
            row[0] = c.x;
            row[1] = c.y;
            if let Some(a) = aerial {
                for ch in 0..3 {
                    row[2 + ch] = a[k].0[ch] as f64 / 255.0;
                }
            }
        }
        for j in 0..dim {
            let mean = f.iter().skip(j).step_by(dim).sum::<f64>() / n as f64;
            let var = f
                .iter()
                .skip(j)
                .step_by(dim)
                .map(|v| (v - mean) * (v - mean))
                .sum::<f64>()
                / n as f64;
            // A constant feature (a one-colour image) carries nothing: leave it at 0.
            let inv = if var > 0.0 { 1.0 / var.sqrt() } else { 0.0 };
            for v in f.iter_mut().skip(j).step_by(dim) {
                *v = (*v - mean) * inv;
            }
        }
        Ok((f, dim))
    }
}

/// Parameters of [`navigate`].
#[derive(Clone, Debug, PartialEq)]
pub struct NavigateParams {
    /// The model.
    pub model: ModelKind,
    /// What to minimise.
    pub objective: Objective,
    /// λ, the rectifier and the cost floor of Eq. 7.
    pub lcb: LcbParams,
    /// Runs of the task (`004`: 25).
    pub runs: usize,
    /// The mixture's parameters (`max_components` is forced to 1 for the single GP).
    pub mixture: MixtureParams,
    /// μ before any observation (the same everywhere, so the first path is a shortest one).
    pub prior_mean: f64,
    /// σ before any observation.
    pub prior_std: f64,
    /// Control period: how much robot time passes between checks of the motion, seconds.
    pub control_dt: f64,
    /// The robot's top speed, m/s (for the per-segment time limit 60 s + 20 × the straight
    /// distance at top speed).
    pub max_speed: f64,
}

impl Default for NavigateParams {
    /// The aerial mixture minimising vibration, softplus LCB with λ = 1, 25 runs, prior μ = 0,
    /// σ = 1, control at 10 Hz, top speed 1 m/s.
    fn default() -> Self {
        NavigateParams {
            model: ModelKind::GpMixtureAerial,
            objective: Objective::Vibration,
            lcb: LcbParams::default(),
            runs: 25,
            mixture: MixtureParams::default(),
            prior_mean: 0.0,
            prior_std: 1.0,
            control_dt: 0.1,
            max_speed: 1.0,
        }
    }
}

impl NavigateParams {
    fn validate(&self) -> Result<(), NavigateError> {
        let bad = |s: String| Err(NavigateError::Params(s));
        if self.runs == 0 {
            return bad("at least one run is needed".into());
        }
        if !(self.prior_mean.is_finite() && self.prior_std.is_finite() && self.prior_std >= 0.0) {
            return bad("the prior mean and standard deviation must be finite (σ ≥ 0)".into());
        }
        if !(self.control_dt.is_finite() && self.control_dt > 0.0) {
            return bad(format!(
                "control period {} must be positive",
                self.control_dt
            ));
        }
        if !(self.max_speed.is_finite() && self.max_speed > 0.0) {
            return bad(format!("top speed {} must be positive", self.max_speed));
        }
        Ok(())
    }
}

/// Per-cell accumulator of the average filter.
#[derive(Clone, Copy, Debug, Default)]
struct CellAcc {
    /// Vibration: Σ v. Energy: Σ P·dt, J.
    sum: f64,
    /// Vibration: readings. Energy: unused.
    count: u32,
    /// Σ ds, metres.
    dist: f64,
}

/// What one drive of a task measured.
#[derive(Clone, Debug, Default, PartialEq, Serialize)]
pub struct DriveResult {
    /// The experienced cost: ∫ v ds (vibration) or Σ P·dt (energy).
    pub experienced_cost: f64,
    /// Distance driven, metres (from the pose stream).
    pub distance_m: f64,
    /// Robot time, seconds.
    pub time_s: f64,
    /// Every goal was reached.
    pub reached: bool,
    /// The trajectory at 2 Hz, (x, y).
    pub trajectory: Vec<[f64; 2]>,
}

/// Records poses and proprioception into the per-cell average filter.
struct ObservationSink<'a> {
    map: &'a NavigationMap,
    objective: Objective,
    acc: &'a mut [CellAcc],
    pose: Option<Point2>,
    /// Pose and time at the previous proprioceptive reading.
    last: Option<(f64, Point2)>,
    cost: f64,
    dist: f64,
    poses: u64,
    trajectory: Vec<[f64; 2]>,
}

impl SensorSink for ObservationSink<'_> {
    fn wants_cloud(&self, _sensor: u8) -> bool {
        false
    }

    fn on_pose(&mut self, pose: &PoseStamped) {
        let p = Point2::new(pose.position.x, pose.position.y);
        if !p.is_finite() {
            return;
        }
        self.pose = Some(p);
        // The pose stream is 20 Hz: every tenth pose is 2 Hz.
        if self.poses.is_multiple_of(10) {
            self.trajectory.push([p.x, p.y]);
        }
        self.poses += 1;
    }

    fn on_proprioception(&mut self, r: &Proprioception) {
        let Some(p) = self.pose else { return };
        let prev = self.last.replace((r.stamp, p));
        let Some((t0, p0)) = prev else { return };
        let dt = r.stamp - t0;
        let ds = p.dist(p0);
        if !(dt > 0.0 && ds.is_finite()) {
            return;
        }
        let mid = Point2::new(0.5 * (p.x + p0.x), 0.5 * (p.y + p0.y));
        let cell = self.map.index_of(mid);
        match self.objective {
            Objective::Vibration => {
                // At rest the sensor reads 0 and the reading describes no terrain.
                if ds <= 0.0 || !r.vibration.is_finite() || r.vibration < 0.0 {
                    return;
                }
                self.cost += r.vibration * ds;
                self.dist += ds;
                if let Some(k) = cell {
                    let a = &mut self.acc[k];
                    a.sum += r.vibration;
                    a.count += 1;
                    a.dist += ds;
                }
            }
            Objective::Energy => {
                if !r.power_w.is_finite() || r.power_w < 0.0 {
                    return;
                }
                let e = r.power_w * dt;
                self.cost += e;
                self.dist += ds;
                if let Some(k) = cell {
                    let a = &mut self.acc[k];
                    a.sum += e;
                    a.dist += ds;
                }
            }
        }
    }
}

/// The cell value of the average filter, if the cell has one.
fn cell_value(objective: Objective, a: &CellAcc, cell_size: f64) -> Option<f64> {
    match objective {
        Objective::Vibration => (a.count > 0).then(|| a.sum / a.count as f64),
        Objective::Energy => (a.dist >= 0.2 * cell_size).then(|| a.sum / a.dist),
    }
}

/// Drives `segments` (cell paths, each starting where the previous ended) with `robot`,
/// recording into the average filter `acc` (one entry per cell of `map`).
fn drive<R: Robot>(
    robot: &mut R,
    map: &NavigationMap,
    objective: Objective,
    acc: &mut [CellAcc],
    segments: &[Vec<Cell>],
    params: &NavigateParams,
) -> Result<DriveResult, NavigateError> {
    let d = map.cell_size;
    let t_start = robot.now();
    let mut sink = ObservationSink {
        map,
        objective,
        acc,
        pose: None,
        last: None,
        cost: 0.0,
        dist: 0.0,
        poses: 0,
        trajectory: Vec::new(),
    };
    let robot_err = |e: R::Error| NavigateError::Robot(e.to_string());
    let mut reached = true;
    for seg in segments {
        let (Some(&first), Some(&last)) = (seg.first(), seg.last()) else {
            continue;
        };
        let goal = last.center(d);
        let limit = 60.0 + 20.0 * first.center(d).dist(goal) / params.max_speed;
        let t0 = robot.now();
        robot.follow(&waypoints(seg, d));
        let mut ok = false;
        while robot.now() - t0 < limit {
            let st = robot
                .advance(params.control_dt, &mut sink)
                .map_err(robot_err)?;
            if st.idle {
                ok = sink.pose.is_some_and(|p| p.dist(goal) <= 1.5 * d);
                break;
            }
            if st.blocked {
                // The grid map said traversable but the robot refuses: the run fails here.
                break;
            }
        }
        // One more period so the last readings of the segment arrive.
        robot
            .advance(params.control_dt, &mut sink)
            .map_err(robot_err)?;
        robot.follow(&[]);
        reached &= ok;
    }
    Ok(DriveResult {
        experienced_cost: sink.cost,
        distance_m: sink.dist,
        time_s: robot.now() - t_start,
        reached,
        trajectory: sink.trajectory,
    })
}

/// Drives fixed cell paths (a baseline: the shortest or the least-cost path) and measures them
/// exactly like a learned run. The robot must stand at the start of the first segment.
pub fn drive_task<R: Robot>(
    robot: &mut R,
    map: &NavigationMap,
    objective: Objective,
    segments: &[Vec<Cell>],
    params: &NavigateParams,
) -> Result<DriveResult, NavigateError> {
    params.validate()?;
    let mut acc = vec![CellAcc::default(); map.rect.len()];
    drive(robot, map, objective, &mut acc, segments, params)
}

/// One run of [`navigate`].
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct RunRecord {
    /// Run number, from 1.
    pub run: usize,
    /// What the drive measured.
    pub drive: DriveResult,
    /// The planned cells, segment after segment.
    pub planned: Vec<Vec<Cell>>,
    /// Planned cells not visited (with an observation) before this run.
    pub new_cells: usize,
    /// Cells with an observation after this run (the training set).
    pub visited_cells: usize,
    /// The mixture's centroids after this run's update.
    pub centroids: Vec<f64>,
    /// Wall time of planning, ms.
    pub plan_ms: f64,
    /// Wall time of the model update (fit and prediction over the grid), ms.
    pub update_ms: f64,
}

/// The model's prediction over the grid, single precision to keep per-run copies small.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct ModelField {
    /// μ per cell, row-major (NaN where the robot may not be).
    pub mean: Vec<f32>,
    /// σ per cell (latent, Eq. 3), row-major (NaN where the robot may not be).
    pub std: Vec<f32>,
}

/// Everything [`navigate`] did.
#[derive(Clone, Debug)]
pub struct NavigationLog {
    /// One record per run.
    pub runs: Vec<RunRecord>,
    /// The model after each run (entry r: after run r + 1).
    pub fields: Vec<ModelField>,
    /// The visited cells (row-major indices) with their averaged observation, ascending.
    pub visited: Vec<(usize, f64)>,
    /// The final model.
    pub model: Option<MixtureModel>,
}

/// The training set of the visited cells: indices, positions, values.
fn training_set(
    map: &NavigationMap,
    objective: Objective,
    acc: &[CellAcc],
) -> (Vec<usize>, Vec<f64>, Vec<f64>) {
    let mut idx = Vec::new();
    let mut pos = Vec::new();
    let mut y = Vec::new();
    for (k, a) in acc.iter().enumerate() {
        if let Some(v) = cell_value(objective, a, map.cell_size) {
            let c = map.rect.cell(k).center(map.cell_size);
            idx.push(k);
            pos.extend([c.x, c.y]);
            y.push(v);
        }
    }
    (idx, pos, y)
}

/// Runs Alg. 1 of `004`: `params.runs` times, a fresh robot from `new_robot(run)` (standing at
/// `task[0]`) drives the task `task[0] → task[1] → …` on paths planned with Eq. 7 on the
/// current model, and the model is refitted on every cell observed so far.
pub fn navigate<R: Robot, E: std::fmt::Display>(
    map: &NavigationMap,
    task: &[Point2],
    params: &NavigateParams,
    mut new_robot: impl FnMut(usize) -> Result<R, E>,
    mut progress: impl FnMut(&RunRecord),
) -> Result<NavigationLog, NavigateError> {
    params.validate()?;
    if task.len() < 2 {
        return Err(NavigateError::Params(
            "a task needs a start and at least one goal".into(),
        ));
    }
    let cells = task_cells(map, task)?;
    let (gate_all, gate_dim) = map.gate_features(params.model)?;
    // The model is predicted where the robot may be (the planner reads nothing else); the
    // other cells keep NaN.
    let query: Vec<usize> = (0..map.rect.len()).filter(|&k| map.admissible[k]).collect();
    let query_pos: Vec<f64> = query
        .iter()
        .flat_map(|&k| {
            let p = map.rect.cell(k).center(map.cell_size);
            [p.x, p.y]
        })
        .collect();
    let query_gate: Vec<f64> = query
        .iter()
        .flat_map(|&k| gate_all[k * gate_dim..(k + 1) * gate_dim].iter().copied())
        .collect();
    let mut mixture = params.mixture.clone();
    if params.model == ModelKind::SingleGp {
        mixture.max_components = 1;
    }
    let n = map.rect.len();
    let mut acc = vec![CellAcc::default(); n];
    let mut mean = vec![f64::NAN; n];
    let mut std = vec![f64::NAN; n];
    for &k in &query {
        mean[k] = params.prior_mean;
        std[k] = params.prior_std;
    }
    let mut model: Option<MixtureModel> = None;
    let mut pred = FieldPrediction::default();
    let mut dij = Dijkstra::new();
    let mut log = NavigationLog {
        runs: Vec::with_capacity(params.runs),
        fields: Vec::with_capacity(params.runs),
        visited: Vec::new(),
        model: None,
    };
    for run in 0..params.runs {
        // Line 3: plan on the current model.
        let t_plan = Instant::now();
        let grid = lcb_grid(
            map.rect,
            map.cell_size,
            &mean,
            &std,
            &map.admissible,
            &params.lcb,
        )?;
        let mut planned = Vec::with_capacity(cells.len() - 1);
        for (s, w) in cells.windows(2).enumerate() {
            let (path, _) = lcb_path(&mut dij, &grid, w[0], w[1])?
                .ok_or(NavigateError::Unreachable { from: s, to: s + 1 })?;
            planned.push(path);
        }
        let plan_ms = t_plan.elapsed().as_secs_f64() * 1e3;
        let new_cells = {
            let mut seen: Vec<usize> = planned
                .iter()
                .flatten()
                .filter_map(|c| map.rect.index(*c))
                .filter(|&k| cell_value(params.objective, &acc[k], map.cell_size).is_none())
                .collect();
            seen.sort_unstable();
            seen.dedup();
            seen.len()
        };
        // Line 4: navigate.
        let mut robot = new_robot(run).map_err(|e| NavigateError::Robot(e.to_string()))?;
        let drive_result = drive(
            &mut robot,
            map,
            params.objective,
            &mut acc,
            &planned,
            params,
        )?;
        // Lines 5–11: update the model on every visited cell.
        let t_update = Instant::now();
        let (idx, pos, y) = training_set(map, params.objective, &acc);
        let mut centroids = Vec::new();
        if !y.is_empty() {
            let gate_train: Vec<f64> = idx
                .iter()
                .flat_map(|&k| gate_all[k * gate_dim..(k + 1) * gate_dim].iter().copied())
                .collect();
            let train = strider_learn::mixture::TrainingSet {
                positions: &pos,
                y: &y,
                gate_features: &gate_train,
                gate_dim,
            };
            let m = MixtureModel::fit(&train, &mixture, model.as_ref())?;
            m.predict(&query_pos, &query_gate, &mut pred)?;
            for (j, &k) in query.iter().enumerate() {
                mean[k] = pred.mean[j];
                std[k] = pred.variance[j].max(0.0).sqrt();
            }
            centroids = m.components().iter().map(|c| c.centroid).collect();
            model = Some(m);
        }
        let update_ms = t_update.elapsed().as_secs_f64() * 1e3;
        log.fields.push(ModelField {
            mean: mean.iter().map(|&v| v as f32).collect(),
            std: std.iter().map(|&v| v as f32).collect(),
        });
        let record = RunRecord {
            run: run + 1,
            drive: drive_result,
            planned,
            new_cells,
            visited_cells: y.len(),
            centroids,
            plan_ms,
            update_ms,
        };
        progress(&record);
        log.runs.push(record);
    }
    let (idx, _, y) = training_set(map, params.objective, &acc);
    log.visited = idx.into_iter().zip(y).collect();
    log.model = model;
    Ok(log)
}

/// The cells of the task's waypoints, each admissible.
pub fn task_cells(map: &NavigationMap, task: &[Point2]) -> Result<Vec<Cell>, NavigateError> {
    task.iter()
        .enumerate()
        .map(|(index, p)| {
            map.index_of(*p)
                .filter(|&k| map.admissible[k])
                .map(|k| map.rect.cell(k))
                .ok_or(NavigateError::Inadmissible {
                    index,
                    x: p.x,
                    y: p.y,
                })
        })
        .collect()
}
