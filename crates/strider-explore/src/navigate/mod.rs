//! Repeated navigation that actively improves over time (Nardi19 Alg. 1).
//!
//! For each navigation task — a start and one or more goals, driven 25 times — the robot plans
//! on the current model with the rectified lower confidence bound of Eq. 7–8 ([`lcb_path`](strider_plan::grid::lcb::lcb_path),
//! decision 26), follows the path while its proprioception (vibration or power) is averaged per
//! grid cell (Nardi19 §VI-A: "an average filter assigns an intensity value to each cell"), then
//! refits the model on every cell visited so far (Alg. 1 lines 5–11) and predicts μ and σ² over
//! the whole grid for the next run:
//!
//! * [`ModelKind::SingleGp`] — one GP on position (Nardi19 §III): the mixture with one component.
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

mod drive;
mod map;
mod model;
mod params;

pub use drive::{DriveResult, drive_task};
pub use map::NavigationMap;
pub use model::ModelField;
pub use params::{ModelKind, NavigateError, NavigateParams, Objective};

use crate::timing::ms_since;
use model::GridModel;
use serde::Serialize;
use std::time::Instant;
use strider_core::interface::Robot;
use strider_core::{Cell, Point2};
use strider_learn::mixture::MixtureModel;
use strider_plan::grid::Dijkstra;

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

/// Runs Alg. 1 of Nardi19: `params.runs` times, a fresh robot from `new_robot(run)` (standing at
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
    let mut model = GridModel::new(map, params)?;
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
        let planned = model.plan(&mut dij, &cells, &params.lcb)?;
        let plan_ms = ms_since(t_plan);
        let new_cells = model.unvisited(&planned);
        // Line 4: navigate.
        let mut robot = new_robot(run).map_err(|e| NavigateError::Robot(e.to_string()))?;
        let drive_result = drive::drive(
            &mut robot,
            map,
            params.objective,
            &mut model.acc,
            &planned,
            params,
        )?;
        // Lines 5–11: update the model on every visited cell.
        let t_update = Instant::now();
        let (visited_cells, centroids) = model.update()?;
        let update_ms = ms_since(t_update);
        log.fields.push(model.field());
        let record = RunRecord {
            run: run + 1,
            drive: drive_result,
            planned,
            new_cells,
            visited_cells,
            centroids,
            plan_ms,
            update_ms,
        };
        progress(&record);
        log.runs.push(record);
    }
    (log.visited, log.model) = model.finish();
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
