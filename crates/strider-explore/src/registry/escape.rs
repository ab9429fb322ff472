//! The parameters of the Prágr23 (thesis C4) strategies (`escape`, `rigid`): C4 Table 3 as defaults.

use super::RobotSpec;
use super::typed::{ParamDoc, ParamError, StrategyParams, limits};
use crate::escape::force_predictor::PredictorParams;
use crate::escape::{EscapeMode, EscapeParams};
use serde::{Deserialize, Serialize};

/// The descriptor of the force predictor.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Descriptor {
    /// Lab (a, b) of the cell (Prágr23 indoor).
    #[default]
    Lab,
    /// 8-bin colour-prototype histogram (Prágr23 outdoor).
    Hist8,
}

/// The `[strategy.escape]` (`rigid`) table.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct EscapeTable {
    /// The predictor's descriptor.
    pub descriptor: Descriptor,
    /// GP noise variance σ²_n, N² (unset: the descriptor's C4 value).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub gp_noise_variance: Option<f64>,
    /// GP signal variance σ²_exp, N² (unset: the descriptor's C4 value).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub gp_signal_variance: Option<f64>,
    /// GP lengthscale l_exp (unset: the descriptor's C4 value).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub gp_lengthscale: Option<f64>,
    /// Predictor relearning rate, Hz.
    pub learn_hz: f64,
    /// I^thr_predict: minimum information gain of a predictor goal, nat.
    pub i_thr_predict: f64,
    /// Histogram radius r_hist, m.
    pub r_hist: f64,
    /// F_trav: the largest force the robot pushes through, N.
    pub f_trav: f64,
    /// σ²_sensor of the bumper, N².
    pub sigma_sensor_sq: f64,
    /// σ²_0 of the haptic fusion, N².
    pub sigma_0_sq: f64,
    /// d_cl: spatial-goal cluster radius, m.
    pub d_cl: f64,
    /// n_cl: cells a spatial-goal cluster needs.
    pub n_cl: usize,
    /// Control rate, Hz.
    pub control_hz: f64,
    /// Rate of predictions applied and spatial goals, Hz.
    pub view_hz: f64,
    /// Rate of the log's time series, Hz.
    pub record_hz: f64,
    /// The exploration ends after this long without a goal, s.
    pub no_goal_grace_s: f64,
    /// Radius around a failed obstacle goal not pursued again, m.
    pub exclusion_m: f64,
    /// A new goal this close to the current one keeps the current path, m.
    pub same_goal_m: f64,
    /// Spacing of the Eq. 8 candidate lattice, m (unset: max(0.2 m, r_sensor/20)).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub info_gain_spacing_m: Option<f64>,
}

impl Default for EscapeTable {
    fn default() -> Self {
        let base = PredictorParams::lab();
        let p = EscapeParams::new(
            EscapeMode::Escape,
            Default::default(),
            1.0,
            Vec::new(),
            None,
        );
        Self {
            descriptor: Descriptor::Lab,
            gp_noise_variance: None,
            gp_signal_variance: None,
            gp_lengthscale: None,
            learn_hz: base.learn_hz,
            i_thr_predict: base.entropy_threshold,
            r_hist: base.r_hist,
            f_trav: p.haptic.f_trav,
            sigma_sensor_sq: p.haptic.sigma_sensor2,
            sigma_0_sq: p.haptic.sigma0_2,
            d_cl: p.map.c_radius,
            n_cl: p.map.c_min_cells,
            control_hz: p.control_hz,
            view_hz: p.view_hz,
            record_hz: p.record_hz,
            no_goal_grace_s: p.no_goal_grace_s,
            exclusion_m: p.exclusion_m,
            same_goal_m: p.same_goal_m,
            info_gain_spacing_m: None,
        }
    }
}

impl StrategyParams for EscapeTable {
    const DOCS: &'static [ParamDoc] = &[
        ParamDoc::new(
            "descriptor",
            "",
            "force predictor descriptor: lab or hist8 (Prágr23 §4.3, §5.3)",
        )
        .one_of(&["lab", "hist8"]),
        ParamDoc::new(
            "gp_noise_variance",
            "N²",
            "GP noise variance σ²_n; auto: 0.1 (Prágr23 Tbl. 3)",
        )
        .above(0.0, limits::MAX_MAGNITUDE),
        ParamDoc::new(
            "gp_signal_variance",
            "N²",
            "GP signal variance σ²_exp; auto: 1 (Prágr23 Tbl. 3)",
        )
        .above(0.0, limits::MAX_MAGNITUDE),
        ParamDoc::new(
            "gp_lengthscale",
            "",
            "GP lengthscale l_exp; auto: 1 for lab, 0.4 for hist8 (Prágr23 Tbl. 3)",
        )
        .above(0.0, 1000.0),
        ParamDoc::new(
            "learn_hz",
            "Hz",
            "predictor relearning rate (Prágr23 Tbl. 3)",
        )
        .above(0.0, limits::MAX_RATE_HZ),
        ParamDoc::new(
            "i_thr_predict",
            "nat",
            "minimum information gain of a predictor goal (Prágr23 Tbl. 3)",
        )
        .within(0.0, 1000.0),
        ParamDoc::new("r_hist", "m", "histogram radius (Prágr23 Tbl. 3)")
            .above(0.0, limits::MAX_DESCRIPTOR_RADIUS_M),
        ParamDoc::new(
            "f_trav",
            "N",
            "largest force the robot pushes through, F_trav (Prágr23 Tbl. 3)",
        )
        .above(0.0, limits::MAX_MAGNITUDE),
        ParamDoc::new(
            "sigma_sensor_sq",
            "N²",
            "bumper noise variance σ²_sensor (Prágr23 Tbl. 3)",
        )
        .above(0.0, limits::MAX_MAGNITUDE),
        ParamDoc::new(
            "sigma_0_sq",
            "N²",
            "prior variance σ²_0 of the haptic fusion (Prágr23 Tbl. 3)",
        )
        .above(0.0, limits::MAX_MAGNITUDE),
        ParamDoc::new(
            "d_cl",
            "m",
            "spatial-goal cluster radius d_cl (Prágr23 Tbl. 3)",
        )
        .above(0.0, limits::MAX_RADIUS_M),
        ParamDoc::new(
            "n_cl",
            "cells",
            "cells a spatial-goal cluster needs, n_cl (Prágr23 Tbl. 3)",
        )
        .count(1, 1_000_000),
        ParamDoc::new("control_hz", "Hz", "control rate (ours)").within(1.0, limits::MAX_RATE_HZ),
        ParamDoc::new(
            "view_hz",
            "Hz",
            "predictions applied and spatial goals, Alg. 2 lines 6-10 (ours)",
        )
        .above(0.0, limits::MAX_RATE_HZ),
        ParamDoc::new("record_hz", "Hz", "rate of the report's time series (ours)")
            .above(0.0, limits::MAX_RATE_HZ),
        ParamDoc::new(
            "no_goal_grace_s",
            "s",
            "the exploration ends after this long without a goal (ours)",
        )
        .within(0.0, 86_400.0),
        ParamDoc::new(
            "exclusion_m",
            "m",
            "radius around a failed obstacle goal not pursued again (ours)",
        )
        .within(0.0, limits::MAX_RADIUS_M),
        ParamDoc::new(
            "same_goal_m",
            "m",
            "a new goal this close to the current one keeps the path (ours)",
        )
        .within(0.0, limits::MAX_RADIUS_M),
        ParamDoc::new(
            "info_gain_spacing_m",
            "m",
            "Eq. 8 candidate spacing; auto: max(0.2 m, r_sensor/20) (ours)",
        )
        .above(0.0, 100.0),
    ];
}

impl EscapeTable {
    /// The mission's parameters for `mode` on `robot`.
    pub fn escape_params(
        &self,
        robot: &RobotSpec,
        mode: EscapeMode,
    ) -> Result<EscapeParams, ParamError> {
        let Some(gait) = robot.gaits.first() else {
            return Err(ParamError::no_gait());
        };
        let mut p = EscapeParams::new(
            mode,
            robot.map.clone(),
            gait.v_max,
            robot.sensor_hfov_deg.clone(),
            robot.bounds,
        );
        p.time_limit_s = robot.time_limit_s;
        let base = match self.descriptor {
            Descriptor::Lab => PredictorParams::lab(),
            Descriptor::Hist8 => PredictorParams::histogram(),
        };
        p.predictor = PredictorParams {
            noise_variance: self.gp_noise_variance.unwrap_or(base.noise_variance),
            signal_variance: self.gp_signal_variance.unwrap_or(base.signal_variance),
            lengthscale: self.gp_lengthscale.unwrap_or(base.lengthscale),
            learn_hz: self.learn_hz,
            entropy_threshold: self.i_thr_predict,
            r_hist: self.r_hist,
            ..base
        };
        p.haptic.f_trav = self.f_trav;
        p.haptic.sigma_sensor2 = self.sigma_sensor_sq;
        p.haptic.sigma0_2 = self.sigma_0_sq;
        p.map.c_radius = self.d_cl;
        p.map.c_min_cells = self.n_cl;
        p.control_hz = self.control_hz;
        p.view_hz = self.view_hz;
        p.record_hz = self.record_hz;
        p.no_goal_grace_s = self.no_goal_grace_s;
        p.exclusion_m = self.exclusion_m;
        p.same_goal_m = self.same_goal_m;
        p.info_gain_spacing_m = self.info_gain_spacing_m;
        Ok(p)
    }
}
