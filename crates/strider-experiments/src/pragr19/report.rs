//! The typed `report.json` of a Prágr19 `rbcm-greedy` mission.

use std::time::Instant;

use serde::Serialize;
use strider_explore::Mission;
use strider_explore::kernel::{Termination, TrajectorySample};
use strider_explore::rbcm_greedy::{CostRecord, PlanRecord, RbcmGreedy};
use strider_scenario::Scenario;

use crate::pragr22::report::MedianMax;
use crate::run::{Explored, MissionId, RunRequest};

/// Planning-time figures are reported over cycles with at least this many traversable cells
/// (the paper's 23.2 s was at 910).
pub const LARGE_MAP_CELLS: usize = 900;

/// One terrain's prediction against the terrain table.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct TerrainRow {
    /// Terrain name.
    pub terrain: String,
    /// Traversable Mcost cells on it.
    pub cells: usize,
    /// Mean predicted μ over them.
    pub predicted_mean: Option<f64>,
    /// Mean predicted σ over them.
    pub predicted_std: Option<f64>,
    /// The terrain table's roll variance for the gait.
    pub roll_variance_truth: Option<f64>,
}

/// One RBCM expert at the end.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct ExpertReport {
    /// Training points.
    pub points: usize,
    /// Kernel lengthscale.
    pub lengthscale: Option<f64>,
    /// Signal variance.
    pub signal_variance: f64,
    /// Noise variance.
    pub noise_variance: f64,
}

/// Median, maximum and count of planning-cycle timings, ms.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct CycleStats {
    /// Median and maximum.
    #[serde(flatten)]
    pub ms: MedianMax,
    /// Cycles.
    pub cycles: usize,
}

impl CycleStats {
    fn of(v: &[f64]) -> Self {
        Self {
            ms: MedianMax::of(v),
            cycles: v.len(),
        }
    }
}

/// Planning-cycle timings, ms.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct PlanningMs {
    /// Every cycle.
    pub all: CycleStats,
    /// Cycles on maps of at least [`LARGE_MAP_CELLS`] traversable cells.
    pub large_map: CycleStats,
    /// [`LARGE_MAP_CELLS`].
    pub large_map_min_cells: usize,
    /// The largest map, traversable cells.
    pub max_traversable_cells: usize,
    /// Traversability.
    pub traversability: CycleStats,
    /// RBCM inference.
    pub inference: CycleStats,
    /// Goals.
    pub goals: CycleStats,
    /// Path.
    pub path: CycleStats,
}

/// `report.json` of `strider run --strategy rbcm-greedy`.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct RbcmReport {
    /// Which mission (strategy `rbcm-greedy`).
    #[serde(flatten)]
    pub id: MissionId,
    /// The gait walked.
    pub gait: String,
    /// The goal-score threshold of the gait.
    pub lambda_score: f64,
    /// How the exploration ended.
    #[serde(flatten)]
    pub explored: Explored,
    /// Whether it stopped by Eq. 16 (no goal left).
    pub terminated: bool,
    /// Easy terrains all predicted cheaper than hard ones.
    pub terrains_learned: bool,
    /// Per terrain.
    pub terrains: Vec<TerrainRow>,
    /// Learning pairs stored.
    pub learning_pairs: usize,
    /// Cost windows without a descriptor.
    pub undescribed_windows: usize,
    /// The experts.
    pub experts: Vec<ExpertReport>,
    /// Learning updates.
    pub learning_ms: MedianMax,
    /// Cost goals reached.
    pub cost_goals_reached: usize,
    /// Spatial goals reached.
    pub spatial_goals_reached: usize,
    /// Planning timings.
    pub planning_ms: PlanningMs,
    /// Every planning cycle.
    pub plans: Vec<PlanRecord>,
    /// Every learning pair.
    pub samples: Vec<CostRecord>,
    /// The trajectory.
    pub trajectory: Vec<TrajectorySample>,
    /// Wall time of the mission, s.
    pub mission_wall_s: f64,
    /// Wall time of the command, s.
    pub wall_s: f64,
    /// The strategy's parameters.
    pub parameters: toml::Table,
    /// Warnings about the scenario.
    pub warnings: Vec<String>,
}

fn planning(plans: &[PlanRecord]) -> PlanningMs {
    let part = |f: fn(&PlanRecord) -> f64| {
        let v: Vec<f64> = plans.iter().map(f).collect();
        CycleStats::of(&v)
    };
    let large: Vec<f64> = plans
        .iter()
        .filter(|p| p.traversable_cells >= LARGE_MAP_CELLS)
        .map(|p| p.total_ms)
        .collect();
    PlanningMs {
        all: part(|p| p.total_ms),
        large_map: CycleStats::of(&large),
        large_map_min_cells: LARGE_MAP_CELLS,
        max_traversable_cells: plans.iter().map(|p| p.traversable_cells).max().unwrap_or(0),
        traversability: part(|p| p.trv_ms),
        inference: part(|p| p.inference_ms),
        goals: part(|p| p.goals_ms),
        path: part(|p| p.path_ms),
    }
}

/// The report of a finished mission (parameters and warnings empty).
pub(crate) fn report(
    sc: &Scenario,
    req: &RunRequest,
    mission: &Mission<RbcmGreedy>,
    terrains: Vec<TerrainRow>,
    learned: bool,
    wall: Instant,
) -> RbcmReport {
    let ex = mission.strategy();
    let log = ex.log();
    let record = mission.record();
    RbcmReport {
        id: MissionId::of(sc, req, "rbcm-greedy"),
        gait: sc.robot.gaits[ex.params().gait.0 as usize].name.clone(),
        lambda_score: ex.params().lambda_score,
        explored: Explored::of(mission),
        terminated: record.termination == Termination::GoalsCleared,
        terrains_learned: learned,
        terrains,
        learning_pairs: ex.rbcm().len(),
        undescribed_windows: log.undescribed_samples,
        experts: ex
            .rbcm()
            .experts()
            .iter()
            .map(|e| ExpertReport {
                points: e.len(),
                lengthscale: e.params().kernel.lengthscales.first().copied(),
                signal_variance: e.params().kernel.signal_variance,
                noise_variance: e.params().noise_variance,
            })
            .collect(),
        learning_ms: MedianMax::of(&log.learning_ms),
        cost_goals_reached: log.cost_goals_reached,
        spatial_goals_reached: log.spatial_goals_reached,
        planning_ms: planning(&log.plans),
        plans: log.plans.clone(),
        samples: log.samples.clone(),
        trajectory: record.trajectory.clone(),
        mission_wall_s: record.wall_s,
        wall_s: wall.elapsed().as_secs_f64(),
        parameters: toml::Table::new(),
        warnings: Vec::new(),
    }
}
