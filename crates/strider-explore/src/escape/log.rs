//! What an escape mission records beyond the kernel's run record: the explored area and cell
//! states over time, the bumper contacts, the goals and the reflexes.

use super::force_predictor::ForcePrediction;
use super::goals::GoalKind;
use super::params::EscapeMode;
use super::view::CellStates;

/// One sample of the time series (C4 Figs. 11–12 and the explored area).
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct TimelineSample {
    /// Robot time since the start, s.
    pub t: f64,
    /// Observed map area, m².
    pub explored_m2: f64,
    /// Apparent obstacle cells by state.
    pub states: CellStates,
    /// Cells with haptic ground truth.
    pub haptic_cells: usize,
}

/// One contact of the bumper with an apparent obstacle.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct ContactEvent {
    /// Start, s since the mission start.
    pub t_start: f64,
    /// End, s.
    pub t_end: f64,
    /// Centroid of the touched cells, m.
    pub x: f64,
    /// Centroid of the touched cells, m.
    pub y: f64,
    /// Cells touched.
    pub cells: usize,
    /// Mean fused force over the touched cells at the end, N.
    pub force: f64,
    /// Mean prediction over the touched cells before the contact (`None`: no predictor).
    pub predicted: Option<ForcePrediction>,
    /// The contact contradicted a prediction of "traversable" (C4 §5.2, an over-optimistic
    /// prediction corrected).
    pub corrected: bool,
}

/// One goal chosen.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct GoalEvent {
    /// s since the mission start.
    pub t: f64,
    /// Rule.
    pub kind: GoalKind,
    /// Goal position, m.
    pub x: f64,
    /// Goal position, m.
    pub y: f64,
}

/// What an escape mission did, beyond the kernel's [`RunRecord`](crate::kernel::RunRecord).
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct EscapeLog {
    /// Strategy.
    pub mode: EscapeMode,
    /// Explored area and cell states over time.
    pub timeline: Vec<TimelineSample>,
    /// Bumper contacts.
    pub contacts: Vec<ContactEvent>,
    /// Goals chosen (each change of goal).
    pub goals: Vec<GoalEvent>,
    /// Push reflexes started.
    pub pushes: usize,
    /// Sample-and-retreat reflexes.
    pub samplings: usize,
    /// Predictor relearnings.
    pub relearns: usize,
}

impl EscapeLog {
    /// An empty log of a `mode` mission.
    pub(super) fn new(mode: EscapeMode) -> Self {
        Self {
            mode,
            timeline: Vec::new(),
            contacts: Vec::new(),
            goals: Vec::new(),
            pushes: 0,
            samplings: 0,
            relearns: 0,
        }
    }
}
