//! The typed `report.json` of a Prágr22 mission (`strider run` with `gtsp`, `greedy` or
//! `spatial-only`), and the per-gait model summaries it shares with `strider replay`.

use serde::Serialize;
use strider_explore::evaluate::{SegmentResult, TourResult};
use strider_explore::kernel::TrajectorySample;
use strider_explore::tour_explorer::ReplanParts;
use strider_explore::{Activity, Mission, MissionLog, PhaseWall, TourExplorer};

use crate::run::{Explored, MissionId};
use crate::stats::median_max;

/// Median and maximum of a latency series, ms.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct MedianMax {
    /// Median.
    pub median: f64,
    /// Maximum.
    pub max: f64,
}

impl MedianMax {
    /// Of the series `v` ((0, 0) when empty).
    pub fn of(v: &[f64]) -> Self {
        let (median, max) = median_max(v);
        Self { median, max }
    }
}

/// Information-gain evaluations of the mission.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct GainEvaluations {
    /// Evaluated from scratch.
    pub fresh: usize,
    /// Updated incrementally.
    pub incremental: usize,
}

/// Latency of the parts of a replan, ms (`vertices`: GTSP vertices).
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct ReplanPartsMs {
    /// Building the planning view.
    pub view: MedianMax,
    /// All-pairs site costs.
    pub all_pairs: MedianMax,
    /// The GTSP solve.
    pub gtsp: MedianMax,
    /// GTSP vertices (a count, not ms).
    pub vertices: MedianMax,
}

/// Latency of goal identification, ms.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct GoalIdentificationMs {
    /// Spatial goals.
    pub spatial: MedianMax,
    /// Learning updates.
    pub learning: MedianMax,
}

/// One class of a gait's model.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct ClassReport {
    /// IGNG class id.
    pub id: u32,
    /// The colour bin that dominates the descriptor the class is predicted at (its cells'
    /// median).
    pub dominant_colour_bin: Option<usize>,
    /// Cells of the class.
    pub cells: usize,
    /// Cells of the class with a learning pair.
    pub learning_cells: usize,
    /// Predicted cost.
    pub cost: f64,
    /// Latent variance of the prediction.
    pub variance: f64,
    /// Information gain I_C (Prágr22 Eq. 23).
    pub information_gain: f64,
}

/// The model of one gait.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct ModelReport {
    /// The gait.
    pub gait: String,
    /// Whether the model has a regressor yet.
    pub regressor: bool,
    /// Learning pairs the regressor trains on (all of L unless `max_learning_pairs` bounds
    /// them).
    pub learning_set: usize,
    /// Cells with a measured cost.
    pub measured_cells: usize,
    /// Terrain classes.
    pub classes: usize,
    /// Cost samples taken in this gait.
    pub cost_samples: usize,
    /// H^GT (Prágr22 Eq. 24), if defined.
    pub h_gt: Option<f64>,
    /// The classes.
    pub class_table: Vec<ClassReport>,
    /// Sampling manoeuvres in this gait.
    pub samplings: usize,
}

/// One navigation mode's drive of a benchmark tour.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct TourModeReport {
    /// Navigation mode.
    pub mode: &'static str,
    /// Tour time, simulated s.
    pub total_s: f64,
    /// Every segment reached its waypoint.
    pub completed: bool,
    /// The segments.
    pub segments: Vec<SegmentResult>,
    /// The driven trajectory.
    pub trajectory: Vec<TrajectorySample>,
}

/// A benchmark tour in every navigation mode.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct TourReport {
    /// The tour's name.
    pub name: String,
    /// One entry per navigation mode.
    pub modes: Vec<TourModeReport>,
}

/// `report.json` of `strider run` with a Prágr22 strategy.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct RunReport {
    /// Which mission.
    #[serde(flatten)]
    pub id: MissionId,
    /// The strategy's parameters.
    pub parameters: toml::Table,
    /// How the exploration ended.
    #[serde(flatten)]
    pub explored: Explored,
    /// Scans fused into the map.
    pub scans_fused: u64,
    /// Wall time per part of the mission loop, s.
    pub phase_wall_s: PhaseWall,
    /// Robot time per activity (driving, turning, look-around, sampling, stuck reflex,
    /// waiting), s.
    pub activity_s: Activity,
    /// Per-gait models.
    pub models: Vec<ModelReport>,
    /// The benchmark tours.
    pub tours: Vec<TourReport>,
    /// Stuck events.
    pub stuck_events: usize,
    /// Cost samples skipped while turning.
    pub turn_skipped_cost_samples: usize,
    /// Information-gain evaluations.
    pub information_gain_evaluations: GainEvaluations,
    /// Replans.
    pub replans: usize,
    /// Replan latency.
    pub replan_latency_ms: MedianMax,
    /// From new data to a new tour.
    pub goals_to_tour_ms: MedianMax,
    /// The parts of a replan.
    pub replan_parts_ms: ReplanPartsMs,
    /// Goal identification.
    pub goal_identification_ms: GoalIdentificationMs,
    /// Wall time of the mission, s.
    pub mission_wall_s: f64,
    /// Simulated over wall time.
    pub speedup: f64,
    /// Wall time of the whole command, s.
    pub wall_time_s: f64,
    /// The exploration trajectory.
    pub trajectory: Vec<TrajectorySample>,
}

/// The benchmark tours as reported.
pub fn tour_reports(tours: &[(String, Vec<TourResult>)]) -> Vec<TourReport> {
    tours
        .iter()
        .map(|(name, modes)| TourReport {
            name: name.clone(),
            modes: modes
                .iter()
                .map(|r| TourModeReport {
                    mode: r.mode.name(),
                    total_s: r.total_s,
                    completed: r.completed,
                    segments: r.segments.clone(),
                    trajectory: r.trajectory.clone(),
                })
                .collect(),
        })
        .collect()
}

/// The latency figures of a mission log.
pub fn replan_parts(log: &MissionLog) -> ReplanPartsMs {
    let part = |f: fn(&ReplanParts) -> f64| {
        let v: Vec<f64> = log.replan_parts.iter().map(f).collect();
        MedianMax::of(&v)
    };
    ReplanPartsMs {
        view: part(|p| p.view_ms),
        all_pairs: part(|p| p.all_pairs_ms),
        gtsp: part(|p| p.gtsp_ms),
        vertices: part(|p| p.vertices as f64),
    }
}

/// Per-gait model summaries: classes with dominant colour, cost and variance, sample counts,
/// H^GT.
pub fn models(mission: &Mission<TourExplorer>, log: &MissionLog) -> Vec<ModelReport> {
    let ex = mission.strategy();
    ex.models()
        .iter()
        .enumerate()
        .map(|(g, m)| {
            let update = &ex.model_updates()[g];
            ModelReport {
                gait: ex.params().gaits[g].name.clone(),
                regressor: m.has_regressor(),
                learning_set: m.learning_set_len(),
                measured_cells: m.measured_cells().len(),
                classes: m.igng().len(),
                cost_samples: log.cost_samples[g],
                h_gt: update.h_gt,
                class_table: update
                    .classes
                    .iter()
                    .map(|c| ClassReport {
                        id: c.id.0,
                        dominant_colour_bin: c
                            .median
                            .iter()
                            .enumerate()
                            .max_by(|a, b| a.1.total_cmp(b.1))
                            .map(|(k, _)| k),
                        cells: c.cells,
                        learning_cells: c.learning_cells,
                        cost: c.cost,
                        variance: c.variance,
                        information_gain: c.information_gain,
                    })
                    .collect(),
                samplings: log.samplings[g],
            }
        })
        .collect()
}
