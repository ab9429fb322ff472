//! Prágr23 (thesis C4): exploration with online learning of traversable yet visually rigid obstacles
//! (the `escape` strategy, C4 Alg. 2) and the `rigid` baseline that treats every apparent
//! obstacle as impassable.
//!
//! * [`haptic`]: bumper filtering, per-cell Kalman fusion of the force to pass through (C4
//!   Eq. 9) and the traversability fusion of C4 Eq. 4.
//! * [`force_predictor`]: the GP force predictor on Lab (a, b) or the 8-bin histogram and its
//!   information gain (C4 Eq. 10–19).
//! * [`view`]: the Eq. 4 classification of the map and the planning grid of C4 Eq. 20.
//! * [`goals`]: goal selection of C4 Alg. 2 (Eq. 22–26).
//! * [`reflexes`]: the approach/push and sample/retreat reflexes of C4 §5.1.
//!
//! [`EscapeMission`] runs C4 Alg. 2 on the mission kernel ([`crate::kernel`]): the map is
//! updated from every fused scan (line 4), the predictor relearned at 0.03 Hz (line 5),
//! predictions applied and spatial goals identified at `view_hz` (lines 6–10), and a goal chosen (lines 11–20) whenever the view was
//! rebuilt, the robot stopped, or a reflex ended. It reads only what the robot reports (poses,
//! clouds, the bumper force, the motion state).
//!
//! The mission itself is split by concept: `strategy` (the kernel's tick), `modules` (relearning,
//! the view and spatial goals, the time series), `decide` (goal choice and path), `bumper`
//! (contacts, pushes and reflexes), with its parameters in [`params`], its record in [`log`]
//! and the contact geometry in [`contact`].
//!
//! Decisions where the thesis is silent:
//! * the predictor is learned as soon as the first haptic measurement exists (Alg. 2 line 12
//!   distinguishes "P is not learned"; waiting up to 33 s for the first scheduled relearn would
//!   send the robot to sample the obstacle it just sampled), then at the fixed rate;
//! * the bumper force is assigned to the apparent obstacle cells nearest ahead of the robot in
//!   a narrow corridor (`contact_half_width`) reaching r_robot beyond the body centre;
//! * a spatial goal counts as reached within 1.5 cells or at the end of its path, or when a
//!   push reflex ends within 2·r_robot of it (a goal on a pushable obstacle); the robot then
//!   turns on the spot once (its cameras look front and back only) and the goal is not pursued
//!   again within 2·r_robot, as in the Prágr22 mission;
//! * an obstacle goal whose approach ends without a bumper measurement on it is not pursued
//!   again within `exclusion_m`;
//! * the exploration ends when no goal has been found for `no_goal_grace_s`.

mod bumper;
pub mod contact;
mod decide;
pub mod force_predictor;
pub mod goals;
pub mod haptic;
pub mod log;
mod modules;
pub mod params;
pub mod reflexes;
mod strategy;
pub mod view;

pub use contact::corridor_cells;
pub use log::{ContactEvent, EscapeLog, GoalEvent, TimelineSample};
pub use params::{EscapeMode, EscapeParams};

use crate::kernel::{Body, Every, Manoeuvre, MissionError};
use contact::ContactAcc;
use force_predictor::ForcePredictor;
use goals::Goal;
use haptic::{BumperFilter, HapticModel};
use reflexes::Reflex;
use strider_core::{Cell, Pose2};
use strider_map::SpatialGoal;
use strider_plan::grid::Dijkstra;
use view::TravView;

/// The C4 escape mission (see the module docs).
pub struct EscapeMission {
    params: EscapeParams,
    haptic: HapticModel,
    filter: BumperFilter,
    predictor: ForcePredictor,
    reflex: Reflex,
    view: Option<TravView>,
    spatial: Vec<SpatialGoal>,
    visited: Vec<Cell>,
    failed: Vec<Cell>,
    current: Option<Goal>,
    looking: Option<Manoeuvre>,
    dij: Dijkstra,
    no_goal_since: Option<f64>,
    contact: Option<ContactAcc>,
    hard_contact: bool,
    t0: f64,
    /// Module timers, set when the mission starts.
    modules: Option<Modules>,
    /// The goal is chosen afresh at the next tick.
    replan: bool,
    log: EscapeLog,
}

/// The module timers of C4 Alg. 2.
#[derive(Clone, Copy, Debug)]
struct Modules {
    /// Alg. 2 line 5: relearning the predictor.
    learn: Every,
    /// Lines 6–10: predictions applied, spatial goals.
    view: Every,
    /// The log's time series.
    record: Every,
}

impl EscapeMission {
    /// A mission with an empty map and no predictor.
    pub fn new(params: EscapeParams) -> Result<Self, MissionError> {
        params.validate()?;
        Ok(Self {
            haptic: HapticModel::new(params.haptic.clone()),
            filter: BumperFilter::default(),
            predictor: ForcePredictor::new(params.predictor.clone()),
            reflex: Reflex::new(params.reflex.clone()),
            view: None,
            spatial: Vec::new(),
            visited: Vec::new(),
            failed: Vec::new(),
            current: None,
            looking: None,
            dij: Dijkstra::new(),
            no_goal_since: None,
            contact: None,
            hard_contact: false,
            t0: 0.0,
            modules: None,
            replan: true,
            log: EscapeLog::new(params.mode),
            params,
        })
    }

    /// The haptic model.
    pub fn haptic(&self) -> &HapticModel {
        &self.haptic
    }

    /// The force predictor.
    pub fn predictor(&self) -> &ForcePredictor {
        &self.predictor
    }

    /// The latest traversability view.
    pub fn view(&self) -> Option<&TravView> {
        self.view.as_ref()
    }

    /// The parameters.
    pub fn params(&self) -> &EscapeParams {
        &self.params
    }

    /// The log so far.
    pub fn log(&self) -> &EscapeLog {
        &self.log
    }

    fn learns(&self) -> bool {
        self.params.mode == EscapeMode::Escape
    }

    fn robot_pose(&self, body: &Body) -> Option<Pose2> {
        body.pose()
            .map(|p| Pose2::new(p.position.x, p.position.y, p.yaw))
    }
}
