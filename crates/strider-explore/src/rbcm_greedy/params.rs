//! What the Prágr19 explorer needs to know about the robot, the task and the method.

use crate::kernel::MissionError;
use strider_core::GaitId;
use strider_learn::gp::{GpParams, HyperBounds};
use strider_learn::rbcm::RbcmParams;
use strider_map::MapParams;
use strider_map::rect::WorldRect;

/// Everything the Prágr19 explorer needs (defaults: Prágr19 Table I and §V).
#[derive(Clone, Debug)]
pub struct RbcmGreedyParams {
    /// Elevation map (M2.5D) parameters; `rho_obstacle` is h_max, `r_robot` δ_impassable,
    /// `r_spatial` the frontier exclusion radius around the robot.
    pub map: MapParams,
    /// The gait walked throughout (the paper's adaptive or regular gait profile).
    pub gait: GaitId,
    /// Its maximum speed, m/s.
    pub gait_speed: f64,
    /// Mcost cell size, metres (10 cm).
    pub mcost_cell: f64,
    /// Descriptor neighbourhood δ_desc, metres.
    pub delta_desc: f64,
    /// Score neighbourhood δ_score, metres (0.5).
    pub delta_score: f64,
    /// λ_score of Eq. 16 (0.001 adaptive, 0.0005 regular).
    pub lambda_score: f64,
    /// Committee: m_max (50) and m_min (25).
    pub rbcm: RbcmParams,
    /// Initial (shared) GP hyperparameters of each expert; exponential kernel in Prágr19.
    pub gp: GpParams,
    /// Per-expert hyperparameter fitting bounds; `None` keeps the shared hyperparameters.
    pub fit: Option<HyperBounds>,
    /// Roll-variance window, seconds (10).
    pub window_s: f64,
    /// Proprioception and pose rates, Hz (ring sizes of the cost signal).
    pub proprio_rate_hz: f64,
    /// Pose rate, Hz.
    pub pose_rate_hz: f64,
    /// One (descriptor, cost) pair is kept per this much walking time, seconds.
    pub sample_period_s: f64,
    /// Follow-the-carrot look-ahead: waypoint spacing along the path, metres (0.2).
    pub carrot_m: f64,
    /// Control period rate, Hz.
    pub control_hz: f64,
    /// Planning (decision) rate, Hz.
    pub plan_hz: f64,
    /// Exploration bounds; frontiers outside are ignored.
    pub bounds: Option<WorldRect>,
    /// Horizontal field of view of each sensor, degrees (360: omnidirectional).
    pub sensor_hfov_deg: Vec<f64>,
    /// Mission time limit, seconds.
    pub time_limit_s: f64,
}

impl RbcmGreedyParams {
    /// Checks the sizes, rates and λ_score.
    pub(super) fn validate(&self) -> Result<(), MissionError> {
        for (name, v) in [
            ("mcost_cell", self.mcost_cell),
            ("delta_desc", self.delta_desc),
            ("delta_score", self.delta_score),
            ("gait_speed", self.gait_speed),
            ("sample_period_s", self.sample_period_s),
            ("carrot_m", self.carrot_m),
            ("control_hz", self.control_hz),
            ("plan_hz", self.plan_hz),
            ("time_limit_s", self.time_limit_s),
        ] {
            if !(v.is_finite() && v > 0.0) {
                return Err(MissionError::params(format!(
                    "{name} must be a positive number, got {v}"
                )));
            }
        }
        if !(self.lambda_score.is_finite() && self.lambda_score >= 0.0) {
            return Err(MissionError::params(
                "lambda_score must be a non-negative number",
            ));
        }
        Ok(())
    }
}
