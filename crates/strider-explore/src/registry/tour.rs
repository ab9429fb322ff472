//! The parameters of the Prágr22 explorers (`gtsp`, `greedy`, `spatial-only`): Prágr22 Table 3
//! (left column) and Table 4 as defaults, our own design choices with today's behaviour.

use super::RobotSpec;
use super::typed::{ParamDoc, StrategyParams, limits};
use crate::params::{MissionParams, Rates, Strategy, TourSolver};
use serde::{Deserialize, Serialize};
use strider_learn::cost_model::CostModelParams;
use strider_learn::gp::{GpParams, Kernel, KernelKind};

/// The `[strategy.gtsp]` (`greedy`, `spatial-only`) table.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct TourParams {
    /// GP lengthscale l over the colour-histogram descriptor.
    pub lengthscale: f64,
    /// GP signal variance σ_s.
    pub sigma_s: f64,
    /// GP noise standard deviation σ_ε (noise variance σ_ε²).
    pub sigma_eps: f64,
    /// σ_sense of the measured-cost fusion.
    pub sigma_sense: f64,
    /// σ_0² of the measured-cost fusion.
    pub sigma_0_sq: f64,
    /// n_min: cells a terrain class needs before it is learned.
    pub n_min: usize,
    /// m_t: measurements per cell kept.
    pub m_t: usize,
    /// d_s: learning-set spacing in descriptor space.
    pub d_s: f64,
    /// c_max: the largest cost.
    pub c_max: f64,
    /// Erosion steps of the class masks (Alg. 10).
    pub n_erode_steps: usize,
    /// Dilation steps of the class masks (Alg. 10).
    pub n_dilate_steps: usize,
    /// Dilation size of the class masks (Alg. 10).
    pub n_dilate_size: usize,
    /// IGNG ε_winner.
    pub igng_eps_winner: f64,
    /// IGNG ε_neighbour.
    pub igng_eps_neighbour: f64,
    /// IGNG age_mature.
    pub igng_age_mature: u32,
    /// IGNG age_max.
    pub igng_age_max: u32,
    /// IGNG batch size.
    pub igng_batch: usize,
    /// Δt: the cost measurement window, s.
    pub delta_t: f64,
    /// c_high of the tanh bound (Eq. 20).
    pub c_high: f64,
    /// c_loss of the distance transform.
    pub c_loss: f64,
    /// Δt_sample: duration of the sampling manoeuvre, s.
    pub dt_sample: f64,
    /// Δt_fallback: duration of the stuck reflex, s.
    pub dt_fallback: f64,
    /// Baseline over which the heading rate tells turning from walking, s.
    pub turning_baseline_s: f64,
    /// Sampling sites kept per cost goal in the GTSP instance.
    pub max_sites_per_goal: usize,
    /// Spatial goal identification rate, Hz (Table 4).
    pub spatial_hz: f64,
    /// Learning and cost-goal identification rate, Hz (Table 4).
    pub learning_hz: f64,
    /// Tour and path planning rate, Hz (Table 4).
    pub tour_hz: f64,
    /// Control rate: gait choice and motion, Hz (Table 4).
    pub control_hz: f64,
    /// Wall-clock budget of one GTSP solve in a mission, s.
    pub gtsp_time_limit_s: f64,
    /// Restarts of one GTSP solve in a mission.
    pub gtsp_max_trials: usize,
    /// Iterations per restart of one GTSP solve in a mission.
    pub gtsp_max_iterations: usize,
    /// Goal sites in one tour solve, nearest goals first (unset: every goal).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub max_tour_sites: Option<usize>,
    /// With a bounded horizon, the margin of the planning view around the robot and the
    /// horizon's sites, m.
    pub tour_window_margin_m: f64,
    /// Spacing of the Eq. 11 candidate lattice, m (unset: max(0.2 m, r_sensor/20)).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub info_gain_spacing_m: Option<f64>,
    /// Learning pairs the regressor trains on, the newest measured (unset: all of L).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub max_learning_pairs: Option<usize>,
    /// Turn once on the spot at a reached spatial goal when the sensors do not see all around.
    pub look_around: bool,
    /// Keep the pursued goal first when the goal set changes before it is reached.
    pub commit_to_goal: bool,
    /// A window that finds the robot stuck is also a cost sample of its gait.
    pub stuck_windows_as_samples: bool,
}

impl Default for TourParams {
    fn default() -> Self {
        let rates = Rates::default();
        let solver = TourSolver::default();
        Self {
            lengthscale: 0.4,
            sigma_s: 1.0,
            sigma_eps: 0.5,
            sigma_sense: 0.10,
            sigma_0_sq: 1.0,
            n_min: 25,
            m_t: 10,
            d_s: 0.44,
            c_max: 20.0,
            n_erode_steps: 2,
            n_dilate_steps: 3,
            n_dilate_size: 2,
            igng_eps_winner: 1e-3,
            igng_eps_neighbour: 1e-5,
            igng_age_mature: 100,
            igng_age_max: 50,
            igng_batch: 5000,
            delta_t: 5.0,
            c_high: 20.0,
            c_loss: 10.0,
            dt_sample: 30.0,
            dt_fallback: 30.0,
            turning_baseline_s: 0.5,
            max_sites_per_goal: 16,
            spatial_hz: rates.spatial_hz,
            learning_hz: rates.learning_hz,
            tour_hz: rates.tour_hz,
            control_hz: rates.control_hz,
            gtsp_time_limit_s: solver.time_limit_s,
            gtsp_max_trials: solver.max_trials,
            gtsp_max_iterations: solver.max_iterations,
            max_tour_sites: solver.max_sites,
            tour_window_margin_m: solver.window_margin_m,
            info_gain_spacing_m: None,
            max_learning_pairs: None,
            look_around: false,
            commit_to_goal: true,
            stuck_windows_as_samples: true,
        }
    }
}

impl StrategyParams for TourParams {
    const DOCS: &'static [ParamDoc] = &[
        ParamDoc::new(
            "lengthscale",
            "",
            "GP lengthscale l over the 9-colour histogram (Prágr22 Tbl. 3)",
        )
        .above(0.0, 1000.0),
        ParamDoc::new("sigma_s", "", "GP signal variance σ_s (Prágr22 Tbl. 3)")
            .above(0.0, limits::MAX_MAGNITUDE),
        ParamDoc::new(
            "sigma_eps",
            "",
            "GP noise standard deviation σ_ε (Prágr22 Tbl. 3)",
        )
        .above(0.0, 1000.0),
        ParamDoc::new(
            "sigma_sense",
            "",
            "σ_sense of the per-cell cost fusion (Prágr22 Tbl. 3)",
        )
        .above(0.0, 1000.0),
        ParamDoc::new(
            "sigma_0_sq",
            "",
            "σ_0² of the per-cell cost fusion (Prágr22 Tbl. 3)",
        )
        .above(0.0, limits::MAX_MAGNITUDE),
        ParamDoc::new(
            "n_min",
            "cells",
            "cells a terrain class needs before it is learned (Prágr22 Tbl. 3)",
        )
        .count(1, 1_000_000),
        ParamDoc::new("m_t", "", "measurements kept per cell (Prágr22 Tbl. 3)")
            .count(1, limits::MAX_MEASUREMENTS_PER_CELL),
        ParamDoc::new(
            "d_s",
            "",
            "learning-set spacing in descriptor space (Prágr22 Tbl. 3)",
        )
        .above(0.0, 10.0),
        ParamDoc::new("c_max", "", "largest cost (Prágr22 Tbl. 3)")
            .within(1.0, limits::MAX_MAGNITUDE),
        ParamDoc::new(
            "n_erode_steps",
            "",
            "erosion steps of the class masks (Prágr22 Alg. 10)",
        )
        .count(0, 100),
        ParamDoc::new(
            "n_dilate_steps",
            "",
            "dilation steps of the class masks (Prágr22 Alg. 10)",
        )
        .count(0, 100),
        ParamDoc::new(
            "n_dilate_size",
            "cells",
            "dilation size of the class masks (Prágr22 Alg. 10)",
        )
        .count(0, 100),
        ParamDoc::new("igng_eps_winner", "", "IGNG ε_winner (Prágr22 Tbl. 3)").above(0.0, 1.0),
        ParamDoc::new(
            "igng_eps_neighbour",
            "",
            "IGNG ε_neighbour (Prágr22 Tbl. 3)",
        )
        .above(0.0, 1.0),
        ParamDoc::new("igng_age_mature", "", "IGNG age_mature (Prágr22 Tbl. 3)")
            .count(1, 1_000_000),
        ParamDoc::new("igng_age_max", "", "IGNG age_max (Prágr22 Tbl. 3)").count(1, 1_000_000),
        ParamDoc::new("igng_batch", "", "IGNG batch size (Prágr22 Tbl. 3)")
            .count(1, limits::MAX_IGNG_BATCH),
        ParamDoc::new(
            "delta_t",
            "s",
            "Δt, the cost measurement window (Prágr22 Tbl. 3)",
        )
        .above(0.0, limits::MAX_DURATION_S),
        ParamDoc::new(
            "c_high",
            "",
            "c_high of the tanh bound, Eq. 20 (Prágr22 Tbl. 3)",
        )
        .within(1.0, limits::MAX_MAGNITUDE),
        ParamDoc::new(
            "c_loss",
            "",
            "c_loss of the distance transform (Prágr22 Tbl. 3)",
        )
        .above(0.0, limits::MAX_MAGNITUDE),
        ParamDoc::new(
            "dt_sample",
            "s",
            "Δt_sample, the sampling manoeuvre (Prágr22 Tbl. 3)",
        )
        .above(0.0, limits::MAX_DURATION_S),
        ParamDoc::new(
            "dt_fallback",
            "s",
            "Δt_fallback, the stuck reflex (Prágr22 Tbl. 3)",
        )
        .above(0.0, limits::MAX_DURATION_S),
        ParamDoc::new(
            "turning_baseline_s",
            "s",
            "baseline of the heading rate that tells turning from walking (ours)",
        )
        .above(0.0, 60.0),
        ParamDoc::new(
            "max_sites_per_goal",
            "",
            "sampling sites kept per cost goal in the GTSP (ours)",
        )
        .count(1, limits::MAX_SITES_PER_GOAL),
        ParamDoc::new(
            "spatial_hz",
            "Hz",
            "spatial goal identification (Prágr22 Tbl. 4)",
        )
        .above(0.0, limits::MAX_RATE_HZ),
        ParamDoc::new(
            "learning_hz",
            "Hz",
            "learning and cost goals (Prágr22 Tbl. 4)",
        )
        .above(0.0, limits::MAX_RATE_HZ),
        ParamDoc::new("tour_hz", "Hz", "tour and path planning (Prágr22 Tbl. 4)")
            .above(0.0, limits::MAX_RATE_HZ),
        ParamDoc::new(
            "control_hz",
            "Hz",
            "gait choice and motion (Prágr22 Tbl. 4)",
        )
        .within(1.0, limits::MAX_RATE_HZ),
        ParamDoc::new(
            "gtsp_time_limit_s",
            "s",
            "wall-clock budget of one GTSP solve (ours)",
        )
        .above(0.0, limits::MAX_DURATION_S),
        ParamDoc::new("gtsp_max_trials", "", "restarts of one GTSP solve (ours)").count(1, 1000),
        ParamDoc::new(
            "gtsp_max_iterations",
            "",
            "iterations per restart of one GTSP solve (ours)",
        )
        .count(1, 10_000_000),
        ParamDoc::new(
            "max_tour_sites",
            "",
            "goal sites in one tour solve, whole goals nearest the robot first; unset: every goal (ours)",
        )
        .count(2, 1_000_000),
        ParamDoc::new(
            "tour_window_margin_m",
            "m",
            "with max_tour_sites, the planning view's margin around the robot and the horizon's sites (ours)",
        )
        .above(0.0, 10_000.0),
        ParamDoc::new(
            "info_gain_spacing_m",
            "m",
            "Eq. 11 candidate spacing; auto: max(0.2 m, r_sensor/20) (ours)",
        )
        .above(0.0, 100.0),
        ParamDoc::new(
            "max_learning_pairs",
            "",
            "learning pairs the GP regressor trains on, the newest measured; unset: all, as Prágr22 (ours)",
        )
        .count(1, 1_000_000),
        ParamDoc::new(
            "look_around",
            "",
            "turn once on the spot at a reached spatial goal (ours)",
        )
        .flag(),
        ParamDoc::new(
            "commit_to_goal",
            "",
            "keep the pursued goal first when the goals change (ours)",
        )
        .flag(),
        ParamDoc::new(
            "stuck_windows_as_samples",
            "",
            "a window that finds the robot stuck is also a cost sample of its gait (ours)",
        )
        .flag(),
    ];
}

impl TourParams {
    /// The mission parameters of `planner` on `robot` with these values.
    pub fn mission_params(&self, robot: &RobotSpec, planner: Strategy, seed: u64) -> MissionParams {
        let gp = GpParams {
            kernel: Kernel {
                kind: KernelKind::SquaredExponential,
                lengthscales: vec![self.lengthscale],
                signal_variance: self.sigma_s,
            },
            noise_variance: self.sigma_eps * self.sigma_eps,
            // Decision 12: costs are modelled as y − 1 with a zero-mean GP.
            prior_mean: 1.0,
        };
        let mut cm = CostModelParams::new(gp);
        cm.sigma_sense2 = self.sigma_sense;
        cm.sigma0_2 = self.sigma_0_sq;
        cm.n_min = self.n_min;
        cm.m_t = self.m_t;
        cm.d_s = self.d_s;
        cm.c_max = self.c_max;
        cm.erode_steps = self.n_erode_steps;
        cm.dilate_steps = self.n_dilate_steps;
        cm.dilate_size = self.n_dilate_size;
        cm.igng.eps_winner = self.igng_eps_winner;
        cm.igng.eps_neighbour = self.igng_eps_neighbour;
        cm.igng.age_mature = self.igng_age_mature;
        cm.igng.age_max = self.igng_age_max;
        cm.igng.batch = self.igng_batch;
        cm.max_learning_pairs = self.max_learning_pairs;
        MissionParams {
            map: robot.map.clone(),
            gaits: robot.gaits.clone(),
            cost_model: cm,
            window_s: self.delta_t,
            c_high: self.c_high,
            c_loss: self.c_loss,
            dt_sample: self.dt_sample,
            dt_fallback: self.dt_fallback,
            turning_baseline_s: self.turning_baseline_s,
            bounds: robot.bounds,
            time_limit_s: robot.time_limit_s,
            strategy: planner,
            rates: Rates {
                spatial_hz: self.spatial_hz,
                learning_hz: self.learning_hz,
                tour_hz: self.tour_hz,
                control_hz: self.control_hz,
            },
            max_sites_per_goal: self.max_sites_per_goal,
            sensor_hfov_deg: robot.sensor_hfov_deg.clone(),
            seed,
            look_around: self.look_around,
            commit_to_goal: self.commit_to_goal,
            solver: TourSolver {
                time_limit_s: self.gtsp_time_limit_s,
                max_trials: self.gtsp_max_trials,
                max_iterations: self.gtsp_max_iterations,
                max_sites: self.max_tour_sites,
                window_margin_m: self.tour_window_margin_m,
            },
            info_gain_spacing_m: self.info_gain_spacing_m,
            stuck_samples: self.stuck_windows_as_samples,
        }
    }
}
