//! Mission parameters: what the exploration stack needs to know about the robot and the task.
//!
//! Nothing here describes the world: the gaits, footprint and sensor-related map parameters come
//! from the robot's profile, the bounds and time limit from the task. A scenario (or a real
//! robot's configuration) is converted into [`MissionParams`] by the caller.

use serde::{Deserialize, Serialize};
use strider_core::GaitId;
use strider_learn::cost_model::CostModelParams;
use strider_learn::signals::InverseVelocityParams;
use strider_map::params::MapParams;
use strider_map::rect::WorldRect;

pub use strider_core::GaitSpec;

/// Exploration strategy (Prágr22 §5 and its baselines).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub enum Strategy {
    /// The paper's: spatial and cost-model goals ordered by an open GTSP tour (Alg. 1).
    Gtsp,
    /// The same goals, cheapest goal next (myopic baseline).
    Greedy,
    /// Spatial goals only, reactive gait, learns incidentally (Prágr22 §5.1.2 baseline).
    SpatialOnly,
}

impl Strategy {
    /// The command-line name.
    pub fn name(self) -> &'static str {
        match self {
            Strategy::Gtsp => "gtsp",
            Strategy::Greedy => "greedy",
            Strategy::SpatialOnly => "spatial-only",
        }
    }

    /// Parses a command-line name.
    pub fn parse(s: &str) -> Option<Self> {
        match s {
            "gtsp" => Some(Strategy::Gtsp),
            "greedy" => Some(Strategy::Greedy),
            "spatial-only" => Some(Strategy::SpatialOnly),
            _ => None,
        }
    }
}

/// The budget of one GTSP solve within a mission (the solver stops at the first limit hit;
/// the iteration limits decide on any instance a mission makes, so a mission is deterministic
/// for its seed).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct TourSolver {
    /// Wall-clock limit, s.
    pub time_limit_s: f64,
    /// Restarts.
    pub max_trials: usize,
    /// Iterations per restart.
    pub max_iterations: usize,
    /// The tour's horizon: at most this many goal sites enter one solve, whole goals nearest
    /// the robot first (`None`: every goal); a replan with none of them reachable plans every
    /// goal. Bounds a replan's site costs and GTSP on worlds whose frontier holds hundreds of
    /// goals.
    pub max_sites: Option<usize>,
    /// With a bounded horizon, the planning view covers the robot and the horizon's sites
    /// grown by this margin, m: room for the paths between them to go round what stands in
    /// the way.
    pub window_margin_m: f64,
}

impl Default for TourSolver {
    fn default() -> Self {
        Self {
            time_limit_s: 5.0,
            max_trials: 2,
            max_iterations: 2000,
            max_sites: None,
            window_margin_m: 10.0,
        }
    }
}

/// Module rates of Prágr22 Tbl. 4, in Hz. Mapping follows the sensor's own rate.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct Rates {
    /// Spatial goal identification (Alg. 2–3), 0.33 Hz.
    pub spatial_hz: f64,
    /// Learning and cost-goal identification (Alg. 5–10), 0.1 Hz.
    pub learning_hz: f64,
    /// Tour and path planning when the goals changed, 1 Hz.
    pub tour_hz: f64,
    /// Control tick: gait choice and motion, 20 Hz.
    pub control_hz: f64,
}

impl Default for Rates {
    fn default() -> Self {
        Self {
            spatial_hz: 0.33,
            learning_hz: 0.1,
            tour_hz: 1.0,
            control_hz: 20.0,
        }
    }
}

/// Everything an exploration mission needs.
#[derive(Clone, Debug, PartialEq)]
pub struct MissionParams {
    /// Map parameters (cell size, r_robot, ρ_obstacle, r_sensor, r_hist, …).
    pub map: MapParams,
    /// The robot's gaits, indexed by [`GaitId`].
    pub gaits: Vec<GaitSpec>,
    /// Parameters shared by the per-gait cost models.
    pub cost_model: CostModelParams,
    /// Δt, the cost measurement window, s (Prágr22 Tbl. 3).
    pub window_s: f64,
    /// c_high of the tanh bound (Eq. 20).
    pub c_high: f64,
    /// c_loss of the distance transform (decision 21).
    pub c_loss: f64,
    /// Δt_sample, duration of the sampling manoeuvre, s.
    pub dt_sample: f64,
    /// Δt_fallback, duration of the stuck reflex, s.
    pub dt_fallback: f64,
    /// Baseline over which the heading rate is measured to tell turning from walking, s
    /// (strategy-table key `turning_baseline_s`, default 0.5): long enough to average out
    /// the pose stream's heading jitter, and a legged robot's body sway, about a gait cycle.
    /// See [`strider_learn::signals::TurningTime`].
    pub turning_baseline_s: f64,
    /// Exploration bounds; goals outside are ignored.
    pub bounds: Option<WorldRect>,
    /// Mission time limit (robot time), s.
    pub time_limit_s: f64,
    /// Strategy.
    pub strategy: Strategy,
    /// Module rates.
    pub rates: Rates,
    /// Sampling sites kept per cost goal in the GTSP instance (decision 23).
    pub max_sites_per_goal: usize,
    /// Horizontal field of view of each sensor (by sensor id), degrees; 360 for an
    /// omnidirectional sensor. Missing entries count as 360. A sensor that sees all around
    /// needs neither the look-around at spatial goals nor scans taken for turning alone.
    pub sensor_hfov_deg: Vec<f64>,
    /// Seed of every random choice of the mission (IGNG batches, GTSP).
    pub seed: u64,
    /// At a reached spatial goal, a robot whose sensors do not see all around turns once on
    /// the spot (our design choice, not the paper's; default off, as in Prágr22 Alg. 1).
    pub look_around: bool,
    /// A replan before the pursued goal is reached keeps that goal first (our design choice,
    /// not the paper's; default on).
    pub commit_to_goal: bool,
    /// The budget of each GTSP solve.
    pub solver: TourSolver,
    /// A window that finds the robot stuck is also a cost sample of its gait (our design
    /// choice, not the paper's; default on): the model learns where the gait gets stuck.
    pub stuck_samples: bool,
    /// Spacing of the Eq. 11 candidate lattice, m (`None`: max(0.2 m, r_sensor/20)).
    pub info_gain_spacing_m: Option<f64>,
}

impl MissionParams {
    /// The rough-terrain gait used by the stuck reflex: the slowest one.
    pub fn rough_gait(&self) -> GaitId {
        let mut best = 0usize;
        for (g, s) in self.gaits.iter().enumerate() {
            if s.v_max < self.gaits[best].v_max {
                best = g;
            }
        }
        GaitId(best as u8)
    }

    /// True when sensor `id` sees all around (horizontal field of view ≥ 360°).
    pub fn sees_all_around(&self, id: usize) -> bool {
        self.sensor_hfov_deg.get(id).is_none_or(|&f| f >= 360.0)
    }

    /// True when the sensors together see all around the robot without turning (every
    /// sensor omnidirectional, or none given).
    pub fn needs_look_around(&self) -> bool {
        !(0..self.sensor_hfov_deg.len().max(1)).all(|k| self.sees_all_around(k))
    }

    /// The fastest gait (ties: the lowest index): the start gait and the reactive gait.
    pub fn fastest_gait(&self) -> GaitId {
        strider_core::snapshot::fastest_gait(&self.gaits)
    }

    /// Parameters of the inverse-velocity cost signal (Eq. 19–20): every gait is scaled by the
    /// v_max over all gaits, so costs are comparable across gaits for Eq. 13.
    pub fn inverse_velocity(&self) -> InverseVelocityParams {
        InverseVelocityParams::new(
            self.window_s,
            vec![self.v_max(); self.gaits.len()],
            self.c_high,
            self.cost_model.c_max,
        )
    }

    /// v_max over all gaits (Eq. 20 scales costs by it).
    pub fn v_max(&self) -> f64 {
        self.gaits.iter().map(|g| g.v_max).fold(0.0, f64::max)
    }
}
