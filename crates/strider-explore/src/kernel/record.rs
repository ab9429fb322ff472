//! What every mission records and reports, whatever its strategy: why it stopped, how long it
//! took, how far the robot drove and where, and the progress shown while it runs.

/// Why a mission stopped.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize)]
pub enum Termination {
    /// The strategy reports no (reachable) goal left.
    GoalsCleared,
    /// Goals remain but none has been reachable for the strategy's grace period.
    NoReachableGoals,
    /// The time limit was reached first.
    TimeLimit,
    /// The strategy failed (e.g. a strategy written in Python raised an exception) and the
    /// mission stopped there.
    StrategyFailed,
}

/// Errors of a mission.
#[derive(Debug, thiserror::Error)]
pub enum MissionError {
    /// The robot failed.
    #[error("robot: {0}")]
    Robot(String),
    /// Invalid parameters.
    #[error("mission parameters: {0}")]
    Params(String),
}

impl MissionError {
    /// Invalid parameters, with the reason a parameter check gave.
    pub fn params(why: impl std::fmt::Display) -> Self {
        Self::Params(why.to_string())
    }

    /// The robot failed, as its error says.
    pub fn robot(why: impl std::fmt::Display) -> Self {
        Self::Robot(why.to_string())
    }
}

/// One logged trajectory sample.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct TrajectorySample {
    /// Robot time, s.
    pub t: f64,
    /// Position, m.
    pub x: f64,
    /// Position, m.
    pub y: f64,
    /// Gait in use.
    pub gait: u8,
}

/// What every mission records, whatever its strategy.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct RunRecord {
    /// Why it stopped.
    pub termination: Termination,
    /// Robot time from start to termination, s.
    pub exploration_time_s: f64,
    /// Distance driven (from the pose stream), m.
    pub driven_m: f64,
    /// Trajectory at 2 Hz.
    pub trajectory: Vec<TrajectorySample>,
    /// Wall time of the run, s.
    pub wall_s: f64,
}

impl RunRecord {
    /// A run not started yet: `termination` until it stops, nothing driven.
    pub fn new(termination: Termination) -> Self {
        Self {
            termination,
            exploration_time_s: 0.0,
            driven_m: 0.0,
            trajectory: Vec::new(),
            wall_s: 0.0,
        }
    }
}

/// A mission's progress, for progress displays (about once per simulated second).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MissionProgress {
    /// Robot time since the start, s.
    pub time_s: f64,
    /// The mission's time limit, s.
    pub time_limit_s: f64,
    /// Observed map cells.
    pub observed_cells: usize,
    /// Current spatial goals.
    pub spatial_goals: usize,
    /// Current cost-model goals (all models).
    pub cost_goals: usize,
    /// Learning-set sizes summed over the models.
    pub learning_set: usize,
}

/// What a strategy adds to [`MissionProgress`].
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct GoalCounts {
    /// Current spatial goals.
    pub spatial_goals: usize,
    /// Current cost-model goals (all models).
    pub cost_goals: usize,
    /// Learning-set sizes summed over the models.
    pub learning_set: usize,
}
