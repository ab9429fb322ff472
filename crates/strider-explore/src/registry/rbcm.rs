//! The parameters of the Prágr19 explorer (`rbcm-greedy`): Prágr19 Table I and §V as defaults.

use super::RobotSpec;
use super::typed::{ParamDoc, ParamError, StrategyParams, limits};
use crate::rbcm_greedy::RbcmGreedyParams;
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;
use strider_core::GaitId;
use strider_learn::gp::{GpParams, HyperBounds, Kernel, KernelKind};
use strider_learn::rbcm::{RbcmParams, RbcmVariant};

/// The `[strategy.rbcm-greedy]` table.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct RbcmTable {
    /// The gait walked throughout (unset: `adaptive` when the robot has it, else its first).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub gait: Option<String>,
    /// Mcost cell size, m.
    pub mcost_cell: f64,
    /// Descriptor neighbourhood δ_desc, m.
    pub delta_desc: f64,
    /// Score neighbourhood δ_score, m.
    pub delta_score: f64,
    /// λ_score of Eq. 16 for a gait not in `lambda_score_by_gait`.
    pub lambda_score: f64,
    /// λ_score of Eq. 16 per gait name.
    pub lambda_score_by_gait: BTreeMap<String, f64>,
    /// Committee size m_max (pairs per expert).
    pub m_max: usize,
    /// m_min: pairs an expert needs to take part in predictions.
    pub m_min: usize,
    /// Initial GP lengthscale of each expert (exponential kernel).
    pub gp_lengthscale: f64,
    /// Initial GP signal variance of each expert, rad⁴.
    pub gp_signal_variance: f64,
    /// Initial GP noise variance of each expert, rad⁴.
    pub gp_noise_variance: f64,
    /// Roll-variance window, s.
    pub cost_window_s: f64,
    /// One (descriptor, cost) pair kept per this much walking, s (unset: 60 s / m_max).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub sample_period_s: Option<f64>,
    /// Follow-the-carrot look-ahead: waypoint spacing, m.
    pub carrot_m: f64,
    /// Planning rate, Hz.
    pub plan_hz: f64,
    /// Control rate, Hz.
    pub control_hz: f64,
    /// Frontier exclusion radius around the robot, m (unset: the map's `r_spatial`).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub r_spatial: Option<f64>,
}

impl Default for RbcmTable {
    fn default() -> Self {
        Self {
            gait: None,
            mcost_cell: 0.10,
            delta_desc: 0.2,
            delta_score: 0.5,
            lambda_score: 0.001,
            lambda_score_by_gait: BTreeMap::new(),
            m_max: 50,
            m_min: 25,
            gp_lengthscale: 0.5,
            gp_signal_variance: 4e-4,
            gp_noise_variance: 2.5e-5,
            cost_window_s: 10.0,
            sample_period_s: None,
            carrot_m: 0.2,
            plan_hz: 1.0,
            control_hz: 10.0,
            r_spatial: None,
        }
    }
}

impl StrategyParams for RbcmTable {
    const DOCS: &'static [ParamDoc] = &[
        ParamDoc::new(
            "gait",
            "",
            "gait walked throughout; auto: adaptive if the robot has it, else its first (Prágr19 §V)",
        ).name(),
        ParamDoc::new("mcost_cell", "m", "Mcost cell size (Prágr19 §V)").within(0.01, 10.0),
        ParamDoc::new(
            "delta_desc",
            "m",
            "descriptor neighbourhood δ_desc (Prágr19 Eq. 7-10)",
        ).above(0.0, limits::MAX_DESCRIPTOR_RADIUS_M),
        ParamDoc::new(
            "delta_score",
            "m",
            "score neighbourhood δ_score (Prágr19 Eq. 15)",
        ).above(0.0, limits::MAX_RADIUS_M),
        ParamDoc::new(
            "lambda_score",
            "",
            "λ_score of Eq. 16 (Prágr19 Tbl. I, adaptive gait)",
        ).within(0.0, limits::MAX_MAGNITUDE),
        ParamDoc::new(
            "lambda_score_by_gait",
            "",
            "λ_score per gait name, e.g. { regular = 0.0005 } (Prágr19 Tbl. I)",
        ).each_within(0.0, limits::MAX_MAGNITUDE),
        ParamDoc::new("m_max", "pairs", "pairs per expert m_max (Prágr19 Tbl. I)").count(1, limits::MAX_EXPERT_PAIRS),
        ParamDoc::new(
            "m_min",
            "pairs",
            "pairs an expert needs to predict, m_min (Prágr19 Tbl. I)",
        ).count(0, limits::MAX_EXPERT_PAIRS),
        ParamDoc::new(
            "gp_lengthscale",
            "",
            "initial lengthscale of each expert, exponential kernel (Prágr19 §V-A)",
        ).above(0.0, 1000.0),
        ParamDoc::new(
            "gp_signal_variance",
            "rad⁴",
            "initial signal variance of each expert (ours, sized to the roll variances)",
        ).above(0.0, limits::MAX_MAGNITUDE),
        ParamDoc::new(
            "gp_noise_variance",
            "rad⁴",
            "initial noise variance of each expert (ours, sized to the roll variances)",
        ).above(0.0, limits::MAX_MAGNITUDE),
        ParamDoc::new("cost_window_s", "s", "roll-variance window (Prágr19 §IV-B)").above(0.0, limits::MAX_DURATION_S),
        ParamDoc::new(
            "sample_period_s",
            "s",
            "one pair kept per this much walking; auto: 60 s / m_max (Prágr19 §V)",
        ).above(0.0, limits::MAX_DURATION_S),
        ParamDoc::new(
            "carrot_m",
            "m",
            "follow-the-carrot waypoint spacing (Prágr19 §V)",
        ).within(0.01, 100.0),
        ParamDoc::new("plan_hz", "Hz", "planning cycle rate (ours)").above(0.0, limits::MAX_RATE_HZ),
        ParamDoc::new("control_hz", "Hz", "control rate (ours)").within(1.0, limits::MAX_RATE_HZ),
        ParamDoc::new(
            "r_spatial",
            "m",
            "frontier exclusion radius around the robot; auto: the map's (Prágr19 Eq. 13)",
        ).above(0.0, limits::MAX_RADIUS_M),
    ];

    fn check_together(&self) -> Result<(), ParamError> {
        if self.m_min > self.m_max {
            return Err(ParamError::new(
                "m_min",
                format!(
                    "= {}: must be at most m_max = {} pairs",
                    self.m_min, self.m_max
                ),
            ));
        }
        Ok(())
    }
}

impl RbcmTable {
    /// The gait walked on `robot`: the one named, or `adaptive`, or the first.
    pub fn gait_index(&self, robot: &RobotSpec) -> Result<usize, ParamError> {
        let gaits = &robot.gaits;
        match &self.gait {
            Some(name) => gaits.iter().position(|g| &g.name == name).ok_or_else(|| {
                let names: Vec<&str> = gaits.iter().map(|g| g.name.as_str()).collect();
                ParamError::new(
                    "gait",
                    format!(
                        "{name:?} is not a gait of robot {}; it has {}",
                        robot.name,
                        names.join(", ")
                    ),
                )
            }),
            None => Ok(gaits.iter().position(|g| g.name == "adaptive").unwrap_or(0)),
        }
    }

    /// The explorer's parameters on `robot`.
    pub fn explorer_params(&self, robot: &RobotSpec) -> Result<RbcmGreedyParams, ParamError> {
        let gi = self.gait_index(robot)?;
        let Some(g) = robot.gaits.get(gi) else {
            return Err(ParamError::no_gait());
        };
        for name in self.lambda_score_by_gait.keys() {
            if !robot.gaits.iter().any(|g| &g.name == name) {
                return Err(ParamError::new(
                    "lambda_score_by_gait",
                    format!("names {name:?}, not a gait of robot {}", robot.name),
                ));
            }
        }
        let lambda = self
            .lambda_score_by_gait
            .get(&g.name)
            .copied()
            .unwrap_or(self.lambda_score);
        let (l0, s0, n0) = (
            self.gp_lengthscale,
            self.gp_signal_variance,
            self.gp_noise_variance,
        );
        let mut map = robot.map.clone();
        if let Some(r) = self.r_spatial {
            map.r_spatial = r;
        }
        Ok(RbcmGreedyParams {
            map,
            gait: GaitId(gi as u8),
            gait_speed: g.v_max,
            mcost_cell: self.mcost_cell,
            delta_desc: self.delta_desc,
            delta_score: self.delta_score,
            lambda_score: lambda,
            rbcm: RbcmParams {
                m_max: self.m_max,
                m_min: self.m_min,
                variant: RbcmVariant::Robust,
            },
            gp: GpParams {
                kernel: Kernel {
                    kind: KernelKind::Exponential,
                    lengthscales: vec![l0],
                    signal_variance: s0,
                },
                noise_variance: n0,
                prior_mean: 0.0,
            },
            // Refitted within bounds relative to the initial values, ≤ 200 iterations (Prágr19 §V-A).
            fit: Some(HyperBounds {
                lengthscale: (0.1 * l0, 10.0 * l0),
                signal_variance: (0.01 * s0, 25.0 * s0),
                noise_variance: (0.01 * n0, s0),
                max_iterations: 200,
            }),
            window_s: self.cost_window_s,
            proprio_rate_hz: robot.proprio_rate_hz,
            pose_rate_hz: robot.pose_rate_hz,
            sample_period_s: self.sample_period_s.unwrap_or(60.0 / self.m_max as f64),
            carrot_m: self.carrot_m,
            control_hz: self.control_hz,
            plan_hz: self.plan_hz,
            bounds: robot.bounds,
            sensor_hfov_deg: robot.sensor_hfov_deg.clone(),
            time_limit_s: robot.time_limit_s,
        })
    }
}
