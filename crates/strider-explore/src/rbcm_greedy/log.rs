//! What an `rbcm-greedy` exploration records beyond the kernel's run record: every planning
//! cycle with its timings, every learning pair, refusals and goals reached.

use super::goals::GoalKind;

/// One planning cycle's timings (wall clock) and outcome.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct PlanRecord {
    /// Robot time, s.
    pub t: f64,
    /// Traversable Mcost cells.
    pub traversable_cells: usize,
    /// Passability and reachability on the elevation map, ms.
    pub trv_ms: f64,
    /// Mcost inference: descriptors and committee predictions (Eq. 11–12), ms.
    pub inference_ms: f64,
    /// Of which the descriptors, ms.
    pub descriptor_ms: f64,
    /// Of which the committee predictions, ms.
    pub predict_ms: f64,
    /// Goal selection: Eq. 14 search, Eq. 15 scores, frontiers (Eq. 13), Eq. 16, ms.
    pub goals_ms: f64,
    /// Path extraction and waypoints, ms.
    pub path_ms: f64,
    /// Everything above, ms.
    pub total_ms: f64,
    /// The goal chosen, if any.
    pub goal: Option<GoalKind>,
    /// The best Eq. 15 score; `None` without a model or without a reachable cost goal.
    pub best_score: Option<f64>,
}

/// One stored learning pair.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct CostRecord {
    /// Window middle time, s.
    pub t: f64,
    /// Attributed position, m.
    pub x: f64,
    /// Attributed position, m.
    pub y: f64,
    /// Roll variance over the window, rad².
    pub cost: f64,
}

/// What an `rbcm-greedy` exploration did, beyond the kernel's
/// [`RunRecord`](crate::kernel::RunRecord).
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct RbcmGreedyLog {
    /// Every planning cycle.
    pub plans: Vec<PlanRecord>,
    /// Every learning pair stored.
    pub samples: Vec<CostRecord>,
    /// Cost windows dropped because their cell had no descriptor yet.
    pub undescribed_samples: usize,
    /// Wall time of each committee update (insertion and refit), ms.
    pub learning_ms: Vec<f64>,
    /// Times the robot's motion was blocked on a cell Mtrv called traversable (a step its legs
    /// cannot take); the cell ahead is then excluded from Mcost.
    pub refusals: usize,
    /// Cost goals reached (and sampled).
    pub cost_goals_reached: usize,
    /// Spatial goals reached.
    pub spatial_goals_reached: usize,
}

impl RbcmGreedyLog {
    /// An empty log.
    pub(super) fn new() -> Self {
        Self {
            plans: Vec::new(),
            samples: Vec::new(),
            undescribed_samples: 0,
            learning_ms: Vec::new(),
            refusals: 0,
            cost_goals_reached: 0,
            spatial_goals_reached: 0,
        }
    }
}
