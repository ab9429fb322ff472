//! What a Prágr22 exploration records beyond the kernel's run record: the latency of each
//! module, the samples and manoeuvres, and where the wall time went.

/// What a Prágr22 exploration did, beyond the kernel's [`RunRecord`](crate::kernel::RunRecord).
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct MissionLog {
    /// Wall-clock latency of each replan (planning grid, all-pairs, GTSP, path), ms.
    pub replan_ms: Vec<f64>,
    /// The parts of each replan, in the order of `replan_ms`.
    pub replan_parts: Vec<ReplanParts>,
    /// Per replan, in the order of `replan_ms`: the replan plus the latest spatial goal
    /// identification and the latest learning update (with its cost goals) that ran since the
    /// previous replan, ms: the time from the newest data to a new tour when the modules run
    /// one after the other. Earlier runs between two replans were superseded by the latest and
    /// are not on that path.
    pub goals_to_tour_ms: Vec<f64>,
    /// Wall-clock latency of each spatial goal identification (passability, reachability,
    /// Eq. 11, Alg. 3), ms.
    pub spatial_goal_ms: Vec<f64>,
    /// Wall-clock latency of each learning update (descriptors, Alg. 5–10 for every gait, cost
    /// goals), ms.
    pub learning_ms: Vec<f64>,
    /// Robot time of each learning update, s, in the order of `learning_ms`.
    pub learning_at_s: Vec<f64>,
    /// Cost goals reached and sampled, per gait.
    pub samplings: Vec<usize>,
    /// Cost samples stored per gait.
    pub cost_samples: Vec<usize>,
    /// Stuck-reflex activations.
    pub stuck_events: usize,
    /// Cost samples dropped because the robot turned within their support ([`TurningTime`](strider_learn::signals::TurningTime)).
    pub turn_skipped: usize,
    /// Wall time per part of the loop, s.
    pub phase_wall_s: PhaseWall,
    /// Robot time per activity (driving, turning, look-around, sampling, stuck reflex,
    /// waiting), s.
    pub activity_s: super::activity::Activity,
    /// Eq. 11 sums evaluated afresh over all spatial updates.
    pub gain_evaluated: usize,
    /// Eq. 11 sums updated incrementally from nearby map changes over all spatial updates.
    pub gain_updated: usize,
}

/// What one replan did and where its time went (wall clock, ms).
#[derive(Clone, Copy, Debug, Default, PartialEq, serde::Serialize)]
pub struct ReplanParts {
    /// Robot time of the replan, s.
    pub t: f64,
    /// Rebuilding the planning view (0 when the map and models had not changed).
    pub view_ms: f64,
    /// The all-pairs site costs.
    pub all_pairs_ms: f64,
    /// The GTSP solve.
    pub gtsp_ms: f64,
    /// Vertices of the GTSP instance (robot + reachable sites).
    pub vertices: usize,
    /// No near goal was reachable within the horizon's window, so every goal was planned again
    /// on the whole map (the all-pairs and GTSP figures are that second plan's).
    pub whole_map: bool,
    /// Cells of the planning view the tour was planned on (0 without a view).
    pub view_cells: usize,
}

/// Wall time spent in each part of the mission loop, s.
#[derive(Clone, Copy, Debug, Default, PartialEq, serde::Serialize)]
pub struct PhaseWall {
    /// The robot (simulator) advancing, including the mapping and cost measurement it calls
    /// back into.
    pub robot: f64,
    /// Mapping alone (scan fusion in the sensor callback).
    pub mapping: f64,
    /// Spatial goals (passability, reachability, Eq. 11, Alg. 3).
    pub spatial: f64,
    /// Learning and cost-goal identification.
    pub learning: f64,
    /// Tour and path planning.
    pub planning: f64,
    /// Gait choice (Alg. 4).
    pub gait: f64,
}

impl MissionLog {
    /// An empty log for a robot with `gaits` gaits.
    pub(super) fn new(gaits: usize) -> Self {
        Self {
            replan_ms: Vec::new(),
            goals_to_tour_ms: Vec::new(),
            replan_parts: Vec::new(),
            spatial_goal_ms: Vec::new(),
            learning_ms: Vec::new(),
            learning_at_s: Vec::new(),
            samplings: vec![0; gaits],
            cost_samples: vec![0; gaits],
            stuck_events: 0,
            turn_skipped: 0,
            phase_wall_s: PhaseWall::default(),
            activity_s: Default::default(),
            gain_evaluated: 0,
            gain_updated: 0,
        }
    }
}
