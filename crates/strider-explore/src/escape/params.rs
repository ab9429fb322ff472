//! What an escape mission needs: the strategy, the robot, and the constants of Prágr23 Table 3.

use super::force_predictor::PredictorParams;
use super::haptic::HapticParams;
use super::reflexes::ReflexParams;
use super::view::ViewParams;
use crate::kernel::MissionError;
use strider_map::params::MapParams;
use strider_map::rect::WorldRect;

/// Which C4 strategy runs.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize)]
pub enum EscapeMode {
    /// C4 Alg. 2 with haptic learning.
    Escape,
    /// Every apparent obstacle is impassable; spatial goals only.
    Rigid,
}

impl EscapeMode {
    /// The command-line name.
    pub fn name(self) -> &'static str {
        match self {
            Self::Escape => "escape",
            Self::Rigid => "rigid",
        }
    }

    /// Parses a command-line name.
    pub fn parse(s: &str) -> Option<Self> {
        match s {
            "escape" => Some(Self::Escape),
            "rigid" => Some(Self::Rigid),
            _ => None,
        }
    }
}

/// Everything an escape mission needs.
#[derive(Clone, Debug, PartialEq)]
pub struct EscapeParams {
    /// The strategy.
    pub mode: EscapeMode,
    /// Map parameters (t_trav = `rho_obstacle`, r_sensor, r_robot; `c_radius` and `c_min_cells`
    /// are C4 d_cl and n_cl).
    pub map: MapParams,
    /// Walking speed, m/s (sizes the retreat).
    pub v_max: f64,
    /// Horizontal field of view per sensor, degrees (a robot that does not see all around
    /// looks around at spatial goals).
    pub sensor_hfov_deg: Vec<f64>,
    /// Exploration bounds.
    pub bounds: Option<WorldRect>,
    /// Time limit, s.
    pub time_limit_s: f64,
    /// Haptic model.
    pub haptic: HapticParams,
    /// Force predictor.
    pub predictor: PredictorParams,
    /// Reflexes.
    pub reflex: ReflexParams,
    /// Planning grid.
    pub view: ViewParams,
    /// Control tick, Hz.
    pub control_hz: f64,
    /// Rate of Alg. 2 lines 6–10 (predictions applied, spatial goals), Hz.
    pub view_hz: f64,
    /// Rate of the time series in the log, Hz.
    pub record_hz: f64,
    /// The exploration ends after this long without a goal, s.
    pub no_goal_grace_s: f64,
    /// Radius around a failed obstacle goal that is not pursued again, m.
    pub exclusion_m: f64,
    /// A newly chosen goal this close to the current one (same rule) keeps the current path, m.
    pub same_goal_m: f64,
    /// Spacing of the Eq. 8 candidate lattice, m (`None`: max(0.2 m, r_sensor/20)).
    pub info_gain_spacing_m: Option<f64>,
}

impl EscapeParams {
    /// C4 Table 3 values around the given map, robot speed and sensors.
    pub fn new(
        mode: EscapeMode,
        map: MapParams,
        v_max: f64,
        sensor_hfov_deg: Vec<f64>,
        bounds: Option<WorldRect>,
    ) -> Self {
        let view = ViewParams {
            r_robot: map.r_robot,
            ..ViewParams::default()
        };
        Self {
            mode,
            map: MapParams {
                c_radius: 1.0,
                c_min_cells: 10,
                ..map
            },
            v_max,
            sensor_hfov_deg,
            bounds,
            time_limit_s: 3600.0,
            haptic: HapticParams::default(),
            predictor: PredictorParams::lab(),
            reflex: ReflexParams::default(),
            view,
            control_hz: 10.0,
            view_hz: 0.5,
            record_hz: 0.2,
            no_goal_grace_s: 10.0,
            exclusion_m: 0.15,
            same_goal_m: 0.25,
            info_gain_spacing_m: None,
        }
    }

    pub(super) fn validate(&self) -> Result<(), MissionError> {
        let pos = |v: f64| v.is_finite() && v > 0.0;
        if !(pos(self.v_max)
            && pos(self.control_hz)
            && pos(self.view_hz)
            && pos(self.record_hz)
            && pos(self.predictor.learn_hz)
            && pos(self.time_limit_s)
            && pos(self.map.cell_size))
        {
            return Err(MissionError::Params(
                "speeds, rates, cell size and time limit must be positive".into(),
            ));
        }
        Ok(())
    }
}
