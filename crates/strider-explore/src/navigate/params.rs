//! What navigation minimises, with which model and parameters, and why it can fail.

use serde::Serialize;
use strider_learn::mixture::{MixtureError, MixtureParams};
use strider_plan::grid::lcb::LcbParams;
use strider_plan::grid::{GridError, SearchError};
use thiserror::Error;

/// What the robot learns to avoid (Nardi19 §VI-B).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize)]
pub enum Objective {
    /// Vertical-acceleration RMS, m/s² per cell; cost ∫ v ds.
    Vibration,
    /// Energy per metre, J/m per cell; cost = energy used, J.
    Energy,
}

impl Objective {
    /// The report name.
    pub fn name(self) -> &'static str {
        match self {
            Objective::Vibration => "vibration",
            Objective::Energy => "energy",
        }
    }

    /// Parses a report name.
    pub fn parse(s: &str) -> Option<Objective> {
        match s {
            "vibration" => Some(Objective::Vibration),
            "energy" => Some(Objective::Energy),
            _ => None,
        }
    }
}

/// The model of Nardi19 Table I.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize)]
pub enum ModelKind {
    /// One GP on position.
    SingleGp,
    /// GP mixture, gating on position.
    GpMixture,
    /// GP mixture, gating on position and aerial colour (the paper's approach).
    GpMixtureAerial,
}

impl ModelKind {
    /// All models, in Table I order.
    pub const ALL: [ModelKind; 3] = [
        ModelKind::SingleGp,
        ModelKind::GpMixture,
        ModelKind::GpMixtureAerial,
    ];

    /// The report name.
    pub fn name(self) -> &'static str {
        match self {
            ModelKind::SingleGp => "single-gp",
            ModelKind::GpMixture => "gp-mixture",
            ModelKind::GpMixtureAerial => "gp-mixture-aerial",
        }
    }

    /// Parses a report name.
    pub fn parse(s: &str) -> Option<ModelKind> {
        ModelKind::ALL.into_iter().find(|m| m.name() == s)
    }
}

/// Why navigation could not run.
#[derive(Debug, Error)]
pub enum NavigateError {
    /// Inputs of inconsistent sizes (grid map, aerial image).
    #[error("{0}")]
    BadInput(String),
    /// A parameter out of its domain.
    #[error("bad navigation parameter: {0}")]
    Params(String),
    /// A waypoint of the task lies outside the grid or on a cell the robot may not occupy.
    #[error("waypoint {index} ({x:.2}, {y:.2}) is outside the grid map or not traversable")]
    Inadmissible {
        /// Index of the waypoint in the task.
        index: usize,
        /// Its x, metres.
        x: f64,
        /// Its y, metres.
        y: f64,
    },
    /// No traversable path joins two consecutive waypoints.
    #[error("no traversable path from waypoint {from} to waypoint {to}")]
    Unreachable {
        /// Index of the start waypoint.
        from: usize,
        /// Index of the goal waypoint.
        to: usize,
    },
    /// The model failed.
    #[error("model: {0}")]
    Model(#[from] MixtureError),
    /// The cost grid could not be built.
    #[error("cost grid: {0}")]
    Grid(#[from] GridError),
    /// The search could not start.
    #[error("planner: {0}")]
    Search(#[from] SearchError),
    /// The robot (or creating it) failed.
    #[error("robot: {0}")]
    Robot(String),
}

/// Parameters of `navigate`: the model, the objective, the planning cost and the runs.
#[derive(Clone, Debug, PartialEq)]
pub struct NavigateParams {
    /// The model.
    pub model: ModelKind,
    /// What to minimise.
    pub objective: Objective,
    /// λ, the rectifier and the cost floor of Eq. 7.
    pub lcb: LcbParams,
    /// Runs of the task (Nardi19: 25).
    pub runs: usize,
    /// The mixture's parameters (`max_components` is forced to 1 for the single GP).
    pub mixture: MixtureParams,
    /// μ before any observation (the same everywhere, so the first path is a shortest one).
    pub prior_mean: f64,
    /// σ before any observation.
    pub prior_std: f64,
    /// Control period: how much robot time passes between checks of the motion, seconds.
    pub control_dt: f64,
    /// The robot's top speed, m/s (for the per-segment time limit 60 s + 20 × the straight
    /// distance at top speed).
    pub max_speed: f64,
}

impl Default for NavigateParams {
    /// The aerial mixture minimising vibration, softplus LCB with λ = 1, 25 runs, prior μ = 0,
    /// σ = 1, control at 10 Hz, top speed 1 m/s.
    fn default() -> Self {
        NavigateParams {
            model: ModelKind::GpMixtureAerial,
            objective: Objective::Vibration,
            lcb: LcbParams::default(),
            runs: 25,
            mixture: MixtureParams::default(),
            prior_mean: 0.0,
            prior_std: 1.0,
            control_dt: 0.1,
            max_speed: 1.0,
        }
    }
}

impl NavigateParams {
    pub(super) fn validate(&self) -> Result<(), NavigateError> {
        let bad = |s: String| Err(NavigateError::Params(s));
        if self.runs == 0 {
            return bad("at least one run is needed".into());
        }
        if !(self.prior_mean.is_finite() && self.prior_std.is_finite() && self.prior_std >= 0.0) {
            return bad("the prior mean and standard deviation must be finite (σ ≥ 0)".into());
        }
        if !(self.control_dt.is_finite() && self.control_dt > 0.0) {
            return bad(format!(
                "control period {} must be positive",
                self.control_dt
            ));
        }
        if !(self.max_speed.is_finite() && self.max_speed > 0.0) {
            return bad(format!("top speed {} must be positive", self.max_speed));
        }
        Ok(())
    }
}
