//! Map parameters (Prágr22 Table 3, Prágr19 Alg. 1 inputs, decisions 1–7). Defaults are the Prágr22
//! small-simulation column.

use serde::{Deserialize, Serialize};

/// How a cell's colour is formed from the colours observed in it (decision 3).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum ColorMode {
    /// Running mean of every observed colour.
    #[default]
    RunningMean,
    /// The first colour observed is kept (the paper's real deployment, glossy floor).
    FirstSeen,
}

/// Parameters of the colored 2.5D elevation map.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct MapParams {
    /// Cell size d_ν, metres.
    pub cell_size: f64,
    /// Tile edge in cells (decision 1).
    pub tile_size: u32,
    /// Roughness passability threshold ρ_obstacle, metres (Prágr22 Eq. 9; Prágr23 t_trav).
    pub rho_obstacle: f64,
    /// Robot footprint radius r_robot, metres (configuration-space inflation, Eq. 12).
    pub r_robot: f64,
    /// Sensor range r_sensor, metres (Eq. 11).
    pub r_sensor: f64,
    /// Sensor height above the terrain h_sensor, metres (observability, decision 5).
    pub sensor_height: f64,
    /// Colour histogram descriptor radius r_hist, metres.
    pub r_hist: f64,
    /// 5-D descriptor neighbourhood δ_desc, metres (Prágr19 Eq. 10).
    pub delta_desc: f64,
    /// Spatial clustering radius c_radius, metres (Alg. 3).
    pub c_radius: f64,
    /// Minimum cells per spatial cluster c_min_cells (Alg. 3).
    pub c_min_cells: usize,
    /// Range-independent depth noise σ_d of the measurement model, metres (decision 2).
    pub sigma_d: f64,
    /// Range-dependent depth noise factor k_d, 1/metre (σ = k_d · range², decision 2).
    pub k_d: f64,
    /// Mahalanobis distance beyond which a measurement is not fused but inflates the cell's
    /// variance (Fankhauser et al. 2014).
    pub mahalanobis_gate: f64,
    /// Variance added to a cell for each gated measurement, m².
    pub multi_height_noise: f64,
    /// How a cell's colour is formed.
    pub color_mode: ColorMode,
    /// Stride (cells) of the lattice on which Eq. 11 is evaluated (1 = every candidate cell).
    pub info_gain_stride: u32,
    /// Frontier cells closer than this to the robot are ignored (Prágr19 r_spatial), metres.
    pub r_spatial: f64,
    /// Returns farther than this from the sensor origin are not fused, metres (bounds the
    /// per-scan scratch raster against stray far points).
    pub max_point_range: f64,
}

impl Default for MapParams {
    fn default() -> Self {
        Self {
            cell_size: 0.05,
            tile_size: 64,
            rho_obstacle: 0.25,
            r_robot: 0.25,
            r_sensor: 2.5,
            sensor_height: 0.3,
            r_hist: 0.25,
            delta_desc: 0.15,
            c_radius: 0.5,
            c_min_cells: 10,
            sigma_d: 0.003,
            k_d: 0.0015,
            mahalanobis_gate: 3.0,
            multi_height_noise: 1e-5,
            color_mode: ColorMode::RunningMean,
            info_gain_stride: 1,
            r_spatial: 0.4,
            max_point_range: 20.0,
        }
    }
}
