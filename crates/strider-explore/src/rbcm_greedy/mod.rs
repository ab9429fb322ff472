//! The `rbcm-greedy` explorer of Prágr19 (Alg. 1): online incremental traversal-cost learning with
//! a robust Bayesian committee machine (RBCM) of GP experts on the 5-D shape + Lab descriptor
//! (Eq. 7–10), the roll-variance cost, and myopic, variance-driven goal selection.
//!
//! Each planning cycle (at `plan_hz`, and whenever the robot stops or is blocked):
//! 1. passability and the reachable set on the elevation map (Mtrv: step height above h_max and
//!    the δ_impassable inflation, decision 4);
//! 2. Mcost at its own resolution from the committee (Eq. 11–12, [`cost_map`]);
//! 3. one Dijkstra from the robot under the Eq. 14 edge cost
//!    ([`strider_plan::grid::MeanEdgeDijkstra`]); the cheapest frontier representative
//!    (Eq. 13) is ν_spatial, the reachable cell of highest median-σ score (Eq. 15) is ν_cost;
//! 4. the decision rule Eq. 16 with λ_score; the cheapest path to the goal is handed to the
//!    robot as waypoints every carrot distance (20 cm) along it, which is what the paper's
//!    follow-the-carrot controller with that look-ahead tracks.
//!
//! The cost is the roll variance over a 10 s window ([`RollVarianceCost`]), attributed to the
//! window's middle pose and paired with that cell's descriptor at that moment; one pair is kept
//! every `sample_period_s` of walking (the paper's m_max = 50 "about one expert per minute"), and
//! only from windows the robot spent walking (a standing robot's roll says nothing about the
//! terrain). Each pair is added to the newest expert, whose hyperparameters are then refitted
//! (bounded, ≤ 200 iterations, Prágr19 §V-A).
//!
//! The explorer is split by concept: `strategy` (the kernel's tick), `learning` (roll windows
//! into the committee), `plan` (the planning cycle above), [`carrot_waypoints`] (the path handed
//! to the robot), with its parameters in [`params`] and its record in [`log`].
//!
//! Decisions where the paper is silent:
//! * without a model (no expert of ≥ m_min pairs) there is no cost goal: Alg. 1 line 4 gets the
//!   experts with at least m_min observations, and the paper's robot "chooses to go towards the
//!   nearby spatial goal" while its cost and confidence are uniform;
//! * a reached cost goal is sampled: the robot walks straight on for one cost window over
//!   traversable cells (as decision 24 does for Prágr22), otherwise it would stand on the
//!   uncertain terrain measuring nothing; a reached spatial goal is not pursued again within
//!   2·r_robot and, with a limited field of view, the robot turns once on the spot there;
//! * planning costs are μ clamped below at the smallest cost measured so far (no terrain is
//!   cheaper than the cheapest one experienced; the zero-mean experts predict 0 far from data),
//!   and uniform before the first measurement;
//! * a cost goal just reached is not chosen again (nor any cell within δ_score/2 of it) for two
//!   cost windows, so the pairs of its sampling walk are learned before the score is judged;
//! * when the robot's motion is blocked on a cell Mtrv calls traversable (a step its legs cannot
//!   take), the Mcost cell ahead of it is excluded from then on, and a goal the robot is refused
//!   on the way to five times is given up (as if reached);
//! * the exploration ends when Eq. 16 yields no goal (or at the time limit); it also ends when
//!   the robot has had no traversable Mcost cell for 30 s.

mod carrot;
pub mod cost_map;
pub mod goals;
mod learning;
pub mod log;
pub mod params;
mod plan;
mod strategy;

pub use carrot::carrot_waypoints;
pub use log::{CostRecord, PlanRecord, RbcmGreedyLog};
pub use params::RbcmGreedyParams;

use crate::kernel::{Body, Every, Manoeuvre, MissionError};
use cost_map::{CostMap, PredictionCache};
use goals::Goal;
use strider_core::{Cell, Point2};
use strider_learn::rbcm::Rbcm;
use strider_learn::signals::{RollVarianceCost, RollVarianceParams};
use strider_map::reachability::Reachability;
use strider_plan::grid::MeanEdgeDijkstra;

/// Seconds without a traversable cell under the robot after which the exploration gives up.
const NO_CELL_TIMEOUT_S: f64 = 30.0;

/// Refusals on the way to one goal after which it is given up (treated as reached).
const MAX_REFUSALS_PER_GOAL: usize = 5;

/// The Prágr19 explorer: map, committee, cost signal and goal state.
pub struct RbcmGreedy {
    params: RbcmGreedyParams,
    reach: Reachability,
    rbcm: Rbcm,
    roll: RollVarianceCost,
    search: MeanEdgeDijkstra,
    cost_map: CostMap,
    cache: PredictionCache,
    walking_since: Option<f64>,
    last_sample_t: f64,
    min_cost: f64,
    goal: Option<Goal>,
    /// The sampling walk or look-around in progress.
    manoeuvre: Option<Manoeuvre>,
    visited: Vec<Point2>,
    no_cell_since: Option<f64>,
    /// Mcost cells the robot was refused entry to (its motion reported *blocked*).
    refused: Vec<Cell>,
    /// Cost goals reached: (time, centre).
    reached_cost: Vec<(f64, Point2)>,
    blocked_on_goal: usize,
    /// The planning cycle's timer, set when the mission starts.
    plan_every: Option<Every>,
    log: RbcmGreedyLog,
}

impl RbcmGreedy {
    /// A new explorer with an empty map and committee.
    pub fn new(params: RbcmGreedyParams) -> Result<Self, MissionError> {
        params.validate()?;
        let rbcm = Rbcm::new(5, params.gp.clone(), params.rbcm)
            .map_err(|e| MissionError::params(format!("committee: {e}")))?;
        let roll = RollVarianceCost::new(RollVarianceParams {
            window_s: params.window_s,
            rate_hz: params.proprio_rate_hz,
            pose_rate_hz: params.pose_rate_hz,
        })
        .map_err(MissionError::params)?;
        Ok(Self {
            reach: Reachability::default(),
            rbcm,
            roll,
            search: MeanEdgeDijkstra::new(),
            cost_map: CostMap::empty(params.mcost_cell),
            cache: PredictionCache::default(),
            walking_since: None,
            last_sample_t: f64::NEG_INFINITY,
            min_cost: f64::INFINITY,
            goal: None,
            manoeuvre: None,
            visited: Vec::new(),
            no_cell_since: None,
            refused: Vec::new(),
            reached_cost: Vec::new(),
            blocked_on_goal: 0,
            plan_every: None,
            log: RbcmGreedyLog::new(),
            params,
        })
    }

    /// The learned committee.
    pub fn rbcm(&self) -> &Rbcm {
        &self.rbcm
    }

    /// The cost map of the last planning cycle.
    pub fn cost_map(&self) -> &CostMap {
        &self.cost_map
    }

    /// The log so far.
    pub fn log(&self) -> &RbcmGreedyLog {
        &self.log
    }

    /// The parameters.
    pub fn params(&self) -> &RbcmGreedyParams {
        &self.params
    }

    /// Builds Mcost for the current map and committee from the robot's current cell (for a
    /// final report after the exploration; planning does this every cycle).
    pub fn refresh_cost_map(&mut self, body: &mut Body) {
        if let Some(c) = body.anchor_cell() {
            self.rebuild_cost_map(body, c);
        }
    }

    /// True when the committee has an expert that takes part in predictions.
    pub fn has_model(&self) -> bool {
        let m_min = self.params.rbcm.m_min.max(1);
        self.rbcm.experts().iter().any(|e| e.len() >= m_min)
    }
}
