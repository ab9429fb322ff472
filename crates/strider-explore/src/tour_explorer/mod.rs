//! The exploration strategies of Prágr22 Alg. 1 with navigation by Alg. 4 on the mission kernel:
//! `gtsp` (spatial and cost-model goals ordered by an open GTSP tour), `greedy` (the same goals,
//! cheapest next) and `spatial-only` (spatial goals, reactive gait).
//!
//! Each module runs at its rate of Prágr22 Tbl. 4 and sees only the latest outputs of the others,
//! as the processes on the robot do: mapping whenever a scan arrives (the kernel's body), cost
//! measurement on every pose (20 Hz), spatial goals at 0.33 Hz, learning and cost-goal
//! identification at 0.1 Hz, the tour and path at 1 Hz when the goal set changed or the current
//! goal was reached.
//!
//! The files, one concept each: `strategy` (the kernel's tick and the module schedule),
//! `measure` (cost measurement and the stuck reflex; `stuck` holds the tests it shares with the
//! benchmark tours), `modules` (spatial goals and learning at their rates), `goals` (the goal
//! set and the goal the robot committed to), `decide` (goals reached, the tour, the path and
//! the gait choice), `manoeuvres` (the sampling walk), `log` and `snapshot` (what a mission
//! records and shows).
//!
//! Decisions where the paper is silent:
//! * a goal counts as reached when the robot is within 1.5 cells of its site or has finished
//!   the path to it;
//! * cost samples are taken only while the robot follows a path (a standing robot measures no
//!   terrain) and not when it turned (heading rate above 0.1 rad/s) within the sample's
//!   support, the window and the moving average before it (turning in place at path corners is
//!   the path's time, not the terrain's, and one such window's ratio would enter Δt of smoothed
//!   samples); the stuck reflex fires only while the robot is commanded to move and not over a
//!   window in which it turned (a turn on the spot makes no headway but is not stuck);
//! * at a reached spatial goal a robot whose sensors do not see all around turns once on the
//!   spot, so a limited field of view sees the r_sensor disc Eq. 11 assumed; a reached spatial
//!   goal is not pursued again within 2·r_robot; nor is a cost-goal site within 2·r_robot of
//!   where the same gait already sampled (a robot stuck beside a site measures the cells it
//!   stands on, the site stays a site, and the goal would draw the robot back for ever);
//! * the robot commits to the goal it pursues: a replan before it is reached (the goal set
//!   changed) keeps it first and re-orders the other goals behind it, for the GTSP tour and the
//!   greedy choice alike. Goal keys drift as the map and models change, so the pursued goal is
//!   recognised as the goal with its key, else the spatial goal nearest its site within
//!   c_radius, else a cost goal of its gait that still lists its site. Without this, every
//!   goal-set change (spatial goals at 0.33 Hz) may flip an open tour's direction between
//!   near-equal alternatives, and the robot walked back and forth between them;
//! * plans start from the nearest cell where the planning grid lets the centre be (known,
//!   admissible, the footprint inside the exploration bounds), the sampling manoeuvre walks only
//!   over such cells, and a path that starts in the robot's own cell does not send it to that
//!   cell's centre first;
//! * goals none of whose sites is reachable on the current planning grid are not pursued; the
//!   exploration ends (decision 25) when no reachable goal remains after the spatial and
//!   learning modules have both run, or at the time limit.

mod activity;
mod decide;
mod goals;
mod log;
mod manoeuvres;
mod measure;
mod modules;
mod snapshot;
mod strategy;
pub(crate) mod stuck;

pub use activity::Activity;
pub use log::{MissionLog, PhaseWall, ReplanParts};

use crate::kernel::{Every, Manoeuvre, MissionError};
use crate::params::{MissionParams, Strategy};
use crate::planner::{CostMode, GoalKey, PlanningView};
use strider_core::{Cell, CellRect, GaitId};
use strider_learn::cost_model::{CostGoal, GaitCostModel, ModelUpdate};
use strider_learn::descriptor_field::DescriptorField;
use strider_learn::signals::{FallbackTimer, InverseVelocityCost, TurningTime};
use strider_map::SpatialGoal;
use strider_map::descriptors::TA_BINS;
use strider_map::information_gain::GainCache;
use strider_map::reachability::Reachability;
use strider_plan::grid::Dijkstra;

/// Elevation hysteresis of the incremental Eq. 11 ([`GainCache`]), metres: the order of the
/// depth noise, so that the Kalman refinement of ground already seen does not re-evaluate the
/// gain of every candidate within r_sensor of the sensor footprint at each spatial update.
const GAIN_DZ: f64 = 0.01;

/// The sampling manoeuvre in progress (decision 24).
#[derive(Clone, Copy, Debug)]
struct Sampling {
    /// The gait the manoeuvre samples.
    gait: GaitId,
    /// The walk.
    walk: Manoeuvre,
}

/// What distinguishes the three Prágr22 strategies, decided once from the planner.
#[derive(Clone, Copy, Debug, PartialEq)]
struct Behaviour {
    /// Cost-model goals are pursued, and the exploration ends only once every model has a
    /// regressor.
    cost_goals: bool,
    /// Planning costs.
    costs: CostMode,
    /// The gait is chosen by Alg. 4 on the learned costs (else the fastest, reactively).
    learned_gait: bool,
    /// The cheapest goal next instead of the GTSP tour.
    cheapest_next: bool,
}

impl Behaviour {
    fn of(planner: Strategy) -> Self {
        let learned = Self {
            cost_goals: true,
            costs: CostMode::Learned,
            learned_gait: true,
            cheapest_next: false,
        };
        match planner {
            Strategy::Gtsp => learned,
            Strategy::Greedy => Self {
                cheapest_next: true,
                ..learned
            },
            Strategy::SpatialOnly => Self {
                cost_goals: false,
                costs: CostMode::Flat,
                learned_gait: false,
                cheapest_next: false,
            },
        }
    }
}

/// The module timers of Prágr22 Tbl. 4.
#[derive(Clone, Copy, Debug)]
struct Modules {
    spatial: Every,
    learning: Every,
    tour: Every,
}

/// The Prágr22 explorer's state: the per-gait models and the navigation state (the map is the
/// kernel's body).
pub struct TourExplorer {
    params: MissionParams,
    behaviour: Behaviour,
    models: Vec<GaitCostModel>,
    signal: InverseVelocityCost,
    fallback: FallbackTimer,
    desc: DescriptorField,
    /// The map revision the descriptors are up to date with.
    desc_revision: u64,
    spatial: Vec<SpatialGoal>,
    cost_goals: Vec<(u8, CostGoal)>,
    dij: Dijkstra,
    current: Option<(GoalKey, Cell)>,
    goal_keys: Vec<GoalKey>,
    sampling: Option<Sampling>,
    gait: GaitId,
    moving: bool,
    learned_once: bool,
    spatial_once: bool,
    log: MissionLog,
    unreachable_since: Option<f64>,
    /// Time spent turning over the stuck test's window and over a cost sample's support.
    turns: TurningTime,
    /// The latest planning view (per-gait grids for Alg. 4, the merged grid for paths).
    view: Option<PlanningView>,
    /// What the view was built from: (fused scans, learning updates, cost mode, window).
    view_key: Option<(u64, u64, CostMode, Option<CellRect>)>,
    /// What the spatial goals were computed from: scans fused, anchor cell, visited goals.
    spatial_key: Option<(u64, Option<Cell>, usize)>,
    /// Wall time of the latest spatial and learning runs since the last replan, ms (see
    /// `MissionLog::goals_to_tour_ms`).
    goal_ms_since_replan: (f64, f64),
    /// Learning updates so far.
    learn_generation: u64,
    /// The look-around in progress.
    looking: Option<Manoeuvre>,
    /// The last Alg. 6 outcome per gait model.
    updates: Vec<ModelUpdate>,
    /// Spatial goals reached so far: goals within 2·r_robot of one are not pursued again (what
    /// could not be seen from there, e.g. the sensor's blind zone around the robot, will not be
    /// seen by returning).
    visited: Vec<Cell>,
    /// (gait, cell) of every cost-goal site sampled and of where the robot stood then.
    sampled: Vec<(u8, Cell)>,
    /// Eq. 11 kept between spatial updates.
    gain: GainCache,
    /// The reachable cells of the last spatial update; kept so that each update refills the
    /// same buffers instead of allocating two map-sized ones.
    reach: Reachability,
    /// The last tour's (goal, site) order, the warm start of the next GTSP solve.
    last_tour: Vec<(GoalKey, Cell)>,
    /// Module timers, set when the mission starts.
    modules: Option<Modules>,
    /// The pose and time of the last control tick, for the activity times.
    last_tick: Option<activity::LastTick>,
}

impl TourExplorer {
    /// An explorer with untrained models.
    pub fn new(params: MissionParams) -> Result<Self, MissionError> {
        if params.gaits.is_empty() || params.gaits.len() > u8::MAX as usize {
            return Err(MissionError::params("the robot needs 1–255 gaits"));
        }
        let iv = params.inverse_velocity();
        let (signal, turns, fallback) =
            stuck::stuck_signals(&params, iv.window_s + iv.smoothing_s)?;
        let models = (0..params.gaits.len())
            .map(|g| {
                GaitCostModel::new(
                    GaitId(g as u8),
                    TA_BINS,
                    params.cost_model.clone(),
                    params.seed,
                )
                .map_err(MissionError::params)
            })
            .collect::<Result<Vec<_>, _>>()?;
        let n = params.gaits.len();
        Ok(Self {
            models,
            signal,
            fallback,
            desc: DescriptorField::empty(CellRect::new(Cell::new(0, 0), 0, 0), TA_BINS),
            desc_revision: 0,
            spatial: Vec::new(),
            cost_goals: Vec::new(),
            dij: Dijkstra::new(),
            current: None,
            goal_keys: Vec::new(),
            sampling: None,
            // Start with the fastest gait.
            gait: params.fastest_gait(),
            moving: false,
            learned_once: false,
            spatial_once: false,
            log: MissionLog::new(n),
            unreachable_since: None,
            turns,
            visited: Vec::new(),
            sampled: Vec::new(),
            gain: GainCache::new(GAIN_DZ),
            reach: Reachability::default(),
            last_tour: Vec::new(),
            updates: vec![ModelUpdate::default(); n],
            looking: None,
            view: None,
            view_key: None,
            spatial_key: None,
            goal_ms_since_replan: (0.0, 0.0),
            learn_generation: 0,
            modules: None,
            last_tick: None,
            behaviour: Behaviour::of(params.strategy),
            params,
        })
    }

    /// The per-gait cost models.
    pub fn models(&self) -> &[GaitCostModel] {
        &self.models
    }

    /// The last learning update (classes, H^GT, goals) of each gait model.
    pub fn model_updates(&self) -> &[ModelUpdate] {
        &self.updates
    }

    /// The latest descriptors.
    pub fn descriptors(&self) -> &DescriptorField {
        &self.desc
    }

    /// The parameters.
    pub fn params(&self) -> &MissionParams {
        &self.params
    }

    /// The log so far.
    pub fn log(&self) -> &MissionLog {
        &self.log
    }

    /// The current spatial goals (Alg. 3).
    pub fn spatial_goals(&self) -> &[SpatialGoal] {
        &self.spatial
    }

    /// The current cost-model goals with their gait index.
    pub fn cost_goals(&self) -> &[(u8, CostGoal)] {
        &self.cost_goals
    }

    /// The last planned tour: goals in visiting order with their chosen sites.
    pub fn tour(&self) -> &[(GoalKey, Cell)] {
        &self.last_tour
    }

    /// The goal being pursued and its site.
    pub fn current_goal(&self) -> Option<(GoalKey, Cell)> {
        self.current
    }

    /// The gait the explorer commands.
    pub fn gait(&self) -> GaitId {
        self.gait
    }

    /// Learning updates (Alg. 6 over every gait) run so far.
    pub fn learning_updates(&self) -> u64 {
        self.learn_generation
    }

    /// How many learning updates the planning view (the tour's costs and the gait choice)
    /// reflects; `None` before the first view. It catches up with
    /// [`learning_updates`](Self::learning_updates) at the next tour decision.
    pub fn view_learning_updates(&self) -> Option<u64> {
        self.view.as_ref().and(self.view_key).map(|k| k.1)
    }
}
