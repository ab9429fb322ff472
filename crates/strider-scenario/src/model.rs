//! The in-memory scenario model: what a scenario file describes, validated.

use std::collections::BTreeMap;

use serde::{Deserialize, Serialize};
use strider_core::{Cell, CellRect, Point2, Pose2, Rgb8};
use strider_map::MapParams;
use strider_map::passability::{Passability, dense_admissible, dense_passability};

/// How one gait fares on one terrain type (simulator truth, never seen by the algorithms).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct GaitResponse {
    /// Fraction of the gait's maximum speed reached on this terrain.
    pub speed_factor: f64,
    /// The robot gets stuck: its speed collapses to ≤ 2 % of the gait's maximum.
    pub stuck: bool,
    /// Variance of the body roll angle while walking here, rad² (Prágr19 cost).
    pub roll_variance: f64,
    /// Electrical power draw while walking here at the achieved speed, watts (Prágr18,
    /// MartinCorke).
    pub power_w: f64,
}

impl Default for GaitResponse {
    fn default() -> Self {
        Self {
            speed_factor: 1.0,
            stuck: false,
            roll_variance: 0.0,
            power_w: 0.0,
        }
    }
}

/// One terrain type of the terrain table.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct TerrainType {
    /// Index used in the terrain layer.
    pub index: u8,
    /// Human-readable name.
    pub name: String,
    /// Response per gait, keyed by gait name; a gait not listed gets [`GaitResponse::default`].
    #[serde(default)]
    pub gaits: BTreeMap<String, GaitResponse>,
    /// Vertical-acceleration RMS while driving here, m/s² (Nardi19).
    #[serde(default)]
    pub vibration: f64,
    /// Relative energy per metre (Nardi19).
    #[serde(default = "one")]
    pub energy_per_m: f64,
    /// Force needed to push through this cell when it looks like an obstacle, newtons (Prágr23);
    /// `None`: rigid (cannot be pushed through).
    #[serde(default)]
    pub push_force_n: Option<f64>,
}

fn one() -> f64 {
    1.0
}

/// How the elevation layer is stored in its 16-bit PNG: `z = offset + scale · v` for a sample
/// `v ∈ 0..=65535`.
///
/// Generators quantize their elevations with [`ElevationEncoding::quantize`], so a generated
/// world saves and loads back bit for bit.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ElevationEncoding {
    /// Metres per 16-bit step (> 0).
    pub scale: f64,
    /// Elevation of sample value 0, metres.
    #[serde(default)]
    pub offset: f64,
}

impl Default for ElevationEncoding {
    /// Half a millimetre per step from −1 m: covers −1 m … 31.77 m.
    fn default() -> Self {
        Self {
            scale: 0.0005,
            offset: -1.0,
        }
    }
}

impl ElevationEncoding {
    /// Elevation of sample `v`, metres.
    #[inline]
    pub fn decode(self, v: u16) -> f32 {
        (self.offset + self.scale * v as f64) as f32
    }
    /// Sample for elevation `z` (nearest step), or `None` when `z` is not finite or out of range.
    #[inline]
    pub fn encode(self, z: f32) -> Option<u16> {
        let v = ((z as f64 - self.offset) / self.scale).round();
        (v.is_finite() && (0.0..=65535.0).contains(&v)).then_some(v as u16)
    }
    /// `z` snapped to the nearest representable elevation (clamped to the covered range).
    #[inline]
    pub fn quantize(self, z: f32) -> f32 {
        let v = ((z as f64 - self.offset) / self.scale).round();
        let v = if v.is_finite() {
            v.clamp(0.0, 65535.0)
        } else {
            0.0
        };
        self.decode(v as u16)
    }
}

/// The simulated world: co-registered layers on the global cell lattice plus the terrain table.
#[derive(Clone, Debug, PartialEq)]
pub struct World {
    /// Cell size of the layers, metres.
    pub resolution: f64,
    /// The cells the layers cover (row-major, row 0 = lowest y).
    pub rect: CellRect,
    /// Terrain surface elevation per cell, metres.
    pub elevation: Vec<f32>,
    /// Surface colour per cell.
    pub color: Vec<Rgb8>,
    /// Terrain type index per cell.
    pub terrain: Vec<u8>,
    /// The terrain table.
    pub terrains: Vec<TerrainType>,
}

impl World {
    /// Layer width (columns).
    pub fn width(&self) -> usize {
        self.rect.width as usize
    }
    /// Layer height (rows).
    pub fn height(&self) -> usize {
        self.rect.height as usize
    }
    /// World coordinates of the lower-left corner of the layers.
    pub fn origin(&self) -> Point2 {
        Point2::new(
            self.rect.min.i as f64 * self.resolution,
            self.rect.min.j as f64 * self.resolution,
        )
    }
    /// The area the layers cover, as bounds (lower-left and upper-right corners).
    pub fn extent(&self) -> Bounds {
        let o = self.origin();
        Bounds {
            min: o,
            max: Point2::new(
                o.x + self.rect.width as f64 * self.resolution,
                o.y + self.rect.height as f64 * self.resolution,
            ),
        }
    }
    /// Centre of the cell at layer index `k` (must be `< rect.len()`).
    pub fn cell_center(&self, k: usize) -> Point2 {
        self.rect.cell(k).center(self.resolution)
    }
    /// True when `p` lies on a cell of the layers.
    pub fn contains(&self, p: Point2) -> bool {
        self.index_at(p).is_some()
    }
    /// Ground-truth passability of every cell (Prágr22 Eq. 7–9 on the true elevation, all cells
    /// known), row-major like the layers.
    pub fn gt_passability(&self, rho_obstacle: f64) -> Vec<Passability> {
        dense_passability(
            &self.elevation,
            None,
            self.width(),
            self.height(),
            rho_obstacle,
        )
    }
    /// Ground-truth admissibility of every cell for a robot of footprint radius `r_robot`
    /// (decision 4: passable, with no impassable cell within `r_robot`), row-major.
    pub fn gt_admissible(&self, rho_obstacle: f64, r_robot: f64) -> Vec<bool> {
        let pass = self.gt_passability(rho_obstacle);
        dense_admissible(&pass, self.width(), self.height(), r_robot, self.resolution)
    }
    /// Layer index of the cell containing world point `p`, if inside.
    pub fn index_at(&self, p: Point2) -> Option<usize> {
        Cell::containing(p.x, p.y, self.resolution).and_then(|c| self.rect.index(c))
    }
    /// The terrain type with layer index `idx`.
    pub fn terrain_type(&self, idx: u8) -> Option<&TerrainType> {
        self.terrains.iter().find(|t| t.index == idx)
    }
}

/// A locomotion gait of a robot profile (Prágr22 Table 2).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct GaitSpec {
    /// Name (key into the terrain table's per-gait responses).
    pub name: String,
    /// Maximum forward speed, m/s.
    pub max_speed: f64,
}

/// Geometry of a range sensor.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(tag = "kind", rename_all = "kebab-case", deny_unknown_fields)]
pub enum SensorKind {
    /// A pinhole RGB-D camera with a rectangular field of view.
    RgbD {
        /// Horizontal field of view, degrees.
        hfov_deg: f64,
        /// Vertical field of view, degrees.
        vfov_deg: f64,
        /// Image columns (file key `width_px`: a plain `width`/`height` would collide with
        /// [`SensorSpec::height`] through `#[serde(flatten)]`).
        #[serde(rename = "width_px")]
        width: u32,
        /// Image rows (file key `height_px`).
        #[serde(rename = "height_px")]
        height: u32,
        /// Downward tilt of the optical axis, degrees.
        #[serde(default)]
        tilt_deg: f64,
    },
    /// An omnidirectional (lidar-like) sensor with colour.
    Omni {
        /// Lowest beam elevation, degrees (negative: down).
        min_elevation_deg: f64,
        /// Highest beam elevation, degrees.
        max_elevation_deg: f64,
        /// Azimuth columns over 360°.
        columns: u32,
        /// Beams (rows).
        rows: u32,
    },
}

/// A range sensor mounted on the robot.
///
/// (No `deny_unknown_fields` here: serde does not support it together with `flatten`; unknown
/// keys are still rejected by [`SensorKind`], which receives every key this struct does not use.)
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct SensorSpec {
    /// Geometry.
    #[serde(flatten)]
    pub kind: SensorKind,
    /// Maximum range, metres.
    pub range: f64,
    /// Height above the terrain under the robot, metres.
    pub height: f64,
    /// Mounting heading relative to the body, degrees (a rear camera: 180).
    #[serde(default)]
    pub yaw_deg: f64,
    /// Scan rate, Hz.
    #[serde(default = "five")]
    pub rate_hz: f64,
}

fn five() -> f64 {
    5.0
}

/// A robot profile (the scenario format in docs/guide.md, "Scenarios and your own world").
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RobotProfile {
    /// Profile name (e.g. `hexapod-small`).
    pub name: String,
    /// Gaits; the first is the default (fast) gait.
    pub gaits: Vec<GaitSpec>,
    /// Range sensors (may be empty for proprioceptive-only robots).
    #[serde(default)]
    pub sensors: Vec<SensorSpec>,
    /// Footprint radius r_robot, metres.
    pub footprint_radius: f64,
    /// Rectangular body (length, width), metres, when the profile has one.
    #[serde(default)]
    pub body: Option<[f64; 2]>,
    /// Mass, kg (cost of transport).
    #[serde(default = "one")]
    pub mass_kg: f64,
    /// Hotel load (power drawn at rest), watts (MartinCorke).
    #[serde(default)]
    pub hotel_load_w: f64,
    /// Highest step the robot can physically climb, metres (the simulator refuses steeper
    /// steps unless the cell can be pushed through).
    #[serde(default = "max_step")]
    pub max_step_m: f64,
    /// Turning rate in place, rad/s.
    #[serde(default = "half")]
    pub turn_rate: f64,
    /// Has a haptic bumper (Prágr23).
    #[serde(default)]
    pub bumper: bool,
    /// Largest force the robot exerts when walking into an obstacle, newtons (Prágr23): cells whose
    /// terrain's `push_force_n` is at most this can be pushed through. 0: cannot push.
    #[serde(default)]
    pub max_push_force_n: f64,
}

fn max_step() -> f64 {
    0.25
}

fn half() -> f64 {
    0.5
}

/// Simulator noise and rates (the truth the simulator applies, not what the map assumes).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct SimParams {
    /// Range-independent depth noise σ_d, metres (standard deviation, along the ray).
    pub depth_sigma: f64,
    /// Range-dependent depth noise factor k_d (σ = k_d · range²).
    pub depth_k: f64,
    /// Colour noise, standard deviation per channel (0–255 scale).
    pub color_sigma: f64,
    /// Pose stream rate, Hz.
    pub pose_rate_hz: f64,
    /// Pose noise: position standard deviation, metres.
    pub pose_sigma_xy: f64,
    /// Pose noise: heading standard deviation, radians.
    pub pose_sigma_yaw: f64,
    /// Multiplicative speed noise, standard deviation (fraction of the nominal speed).
    pub speed_noise: f64,
    /// Proprioception rate, Hz.
    pub proprio_rate_hz: f64,
    /// Noise on proprioceptive signals (fraction of the nominal value).
    pub proprio_noise: f64,
    /// Integration step of the motion model, seconds.
    pub dt: f64,
}

impl Default for SimParams {
    fn default() -> Self {
        Self {
            depth_sigma: 0.003,
            depth_k: 0.0015,
            color_sigma: 4.0,
            pose_rate_hz: 20.0,
            pose_sigma_xy: 0.0,
            pose_sigma_yaw: 0.0,
            speed_noise: 0.05,
            proprio_rate_hz: 20.0,
            proprio_noise: 0.05,
            dt: 0.05,
        }
    }
}

/// Exploration bounds: goals outside are dropped (decision 5).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Bounds {
    /// Lower-left corner.
    pub min: Point2,
    /// Upper-right corner.
    pub max: Point2,
}

impl Bounds {
    /// True when `p` lies inside (inclusive).
    pub fn contains(&self, p: Point2) -> bool {
        p.x >= self.min.x && p.x <= self.max.x && p.y >= self.min.y && p.y <= self.max.y
    }
}

/// A benchmark tour: waypoints visited in order (Prágr22 §5).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Tour {
    /// Tour name.
    pub name: String,
    /// Waypoints, world coordinates.
    pub waypoints: Vec<Point2>,
    /// Return to the first waypoint at the end.
    #[serde(default)]
    pub closed: bool,
}

/// A complete scenario.
#[derive(Clone, Debug, PartialEq)]
pub struct Scenario {
    /// Scenario name.
    pub name: String,
    /// One-paragraph description.
    pub description: String,
    /// World seed the scenario was generated with (0 for file scenarios).
    pub world_seed: u64,
    /// The world (simulator truth).
    pub world: World,
    /// The robot.
    pub robot: RobotProfile,
    /// Map parameters.
    pub map: MapParams,
    /// Simulator parameters.
    pub sim: SimParams,
    /// Parameters per strategy (and per command: `tours`, `navigate`, `learn-bench`): the
    /// `[strategy.<name>]` sections, each checked by its strategy's typed parameters.
    pub strategy: toml::Table,
    /// Start pose.
    pub start: Pose2,
    /// Exploration bounds.
    pub bounds: Bounds,
    /// Benchmark tours.
    pub tours: Vec<Tour>,
    /// Mission time limit, simulated seconds.
    pub time_limit_s: f64,
    /// How the world's elevation layer is written to (and was read from) its 16-bit PNG; the
    /// world's elevations must be representable in it for [`Scenario::save`].
    pub elevation_encoding: ElevationEncoding,
}
