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

/// A parameter outside its allowed range: names the key, the value and what is allowed, in one
/// line (`map.cell_size = -0.1: must be a finite number in [0.01, 10] m`).
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
#[error("{key} = {value}: must be {allowed}")]
pub struct ParamError {
    /// Dotted key, e.g. `map.cell_size` or `robot.sensors[1].range`.
    pub key: String,
    /// The offending value, as written for a reader.
    pub value: String,
    /// What is allowed, with the unit (e.g. `a finite number in (0, 10] m`).
    pub allowed: String,
}

impl ParamError {
    /// The error of `key` = `value`, which must be `allowed`.
    pub fn new(
        key: impl Into<String>,
        value: impl Into<String>,
        allowed: impl Into<String>,
    ) -> Self {
        Self {
            key: key.into(),
            value: value.into(),
            allowed: allowed.into(),
        }
    }
}

/// `v` for an error message: plain decimals for ordinary magnitudes, scientific notation for
/// very large or small ones (Rust's `Display` writes 1e300 with 301 digits).
pub fn fmt_value(v: f64) -> String {
    let a = v.abs();
    if a != 0.0 && a.is_finite() && !(1e-4..1e5).contains(&a) {
        format!("{v:e}")
    } else {
        format!("{v}")
    }
}

/// The allowed interval of a real parameter and its unit: checks a value and words the
/// [`ParamError`] of one outside it. Non-finite values are always refused.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Range {
    /// Lower bound.
    pub min: f64,
    /// The lower bound itself is excluded (`> min` rather than `≥ min`).
    pub min_open: bool,
    /// Upper bound (inclusive).
    pub max: f64,
    /// Unit for messages (`m`, `Hz`, … or empty).
    pub unit: &'static str,
}

impl Range {
    /// `[min, max]` in `unit`.
    pub const fn closed(min: f64, max: f64, unit: &'static str) -> Self {
        Self {
            min,
            min_open: false,
            max,
            unit,
        }
    }
    /// `(min, max]` in `unit`.
    pub const fn above(min: f64, max: f64, unit: &'static str) -> Self {
        Self {
            min,
            min_open: true,
            max,
            unit,
        }
    }
    /// True when `v` is finite and inside.
    pub fn contains(&self, v: f64) -> bool {
        v.is_finite()
            && v <= self.max
            && if self.min_open {
                v > self.min
            } else {
                v >= self.min
            }
    }
    /// The interval in words, e.g. `a finite number in (0, 10] m`.
    pub fn describe(&self) -> String {
        let open = if self.min_open { '(' } else { '[' };
        let unit = if self.unit.is_empty() {
            String::new()
        } else {
            format!(" {}", self.unit)
        };
        format!(
            "a finite number in {open}{}, {}]{unit}",
            fmt_value(self.min),
            fmt_value(self.max)
        )
    }
    /// `Ok` when `value` is inside, else the error naming `key`.
    pub fn check(&self, key: &str, value: f64) -> Result<(), ParamError> {
        if self.contains(value) {
            Ok(())
        } else {
            Err(ParamError::new(key, fmt_value(value), self.describe()))
        }
    }
}

/// Checks an integer parameter against `[min, max]` (`what`: the unit, e.g. `cells`).
pub fn check_count(
    key: &str,
    value: u64,
    min: u64,
    max: u64,
    what: &str,
) -> Result<(), ParamError> {
    if (min..=max).contains(&value) {
        Ok(())
    } else {
        Err(ParamError::new(
            key,
            value.to_string(),
            format!("an integer in [{min}, {max}] {what}"),
        ))
    }
}

/// Smallest map cell size, metres: finer cells than a centimetre resolve nothing a depth sensor
/// measures (σ_d is millimetres at best, and grows with range), and multiply the cell count.
pub const MIN_CELL_SIZE_M: f64 = 0.01;
/// Largest map cell size, metres: a cell is compared with the robot's footprint and steps; at
/// 10 m one cell holds a whole robot and its surroundings.
pub const MAX_CELL_SIZE_M: f64 = 10.0;
/// Largest tile edge, cells: a tile of each of the map's seven layers is allocated on first
/// touch, about 30 bytes per cell together, so a 1024² tile costs ≈ 31 MB.
pub const MAX_TILE_SIZE: u32 = 1024;
/// Longest radius, in cells, of a map parameter that becomes a disc of cell offsets or a
/// scan raster (`r_sensor`, `r_hist`, `delta_desc`, `c_radius`, `r_spatial`,
/// `max_point_range`): a disc of 1000 cells holds 3.1 M offsets (25 MB) and is visited per
/// candidate cell, and a scan raster spans up to 2001² cells.
pub const MAX_RADIUS_CELLS: f64 = 1000.0;
/// Longest footprint radius `r_robot`, in cells: planners inflate obstacles by discs of up to
/// three footprint radii, which stay below 1.2 M offsets at 200 cells.
pub const MAX_FOOTPRINT_CELLS: f64 = 200.0;
/// Largest `c_min_cells`: a cluster cannot hold more cells than a map within the limits has.
pub const MAX_CLUSTER_CELLS: u64 = 1 << 24;
/// Largest `info_gain_stride`, cells: a coarser lattice than the longest radius evaluates no
/// candidate near the robot.
pub const MAX_INFO_GAIN_STRIDE: u32 = 1000;

impl MapParams {
    /// Checks every parameter against its documented range (see the constants of this module),
    /// naming the first offending key as `map.<key>`.
    pub fn validate(&self) -> Result<(), ParamError> {
        let d = self.cell_size;
        Range::closed(MIN_CELL_SIZE_M, MAX_CELL_SIZE_M, "m").check("map.cell_size", d)?;
        check_count(
            "map.tile_size",
            self.tile_size.into(),
            1,
            MAX_TILE_SIZE.into(),
            "cells",
        )?;
        Range::above(0.0, 100.0, "m").check("map.rho_obstacle", self.rho_obstacle)?;
        let cells = |n: f64| {
            format!(
                "m (at most {n} cells of map.cell_size = {} m)",
                fmt_value(d)
            )
        };
        let footprint = Range::closed(0.0, MAX_FOOTPRINT_CELLS * d, "m");
        check_with(
            &footprint,
            "map.r_robot",
            self.r_robot,
            &cells(MAX_FOOTPRINT_CELLS),
        )?;
        let radius = Range::closed(0.0, MAX_RADIUS_CELLS * d, "m");
        let positive_radius = Range::above(0.0, MAX_RADIUS_CELLS * d, "m");
        check_with(
            &positive_radius,
            "map.r_sensor",
            self.r_sensor,
            &cells(MAX_RADIUS_CELLS),
        )?;
        Range::above(0.0, 100.0, "m").check("map.sensor_height", self.sensor_height)?;
        for (key, v) in [
            ("map.r_hist", self.r_hist),
            ("map.delta_desc", self.delta_desc),
            ("map.c_radius", self.c_radius),
            ("map.r_spatial", self.r_spatial),
        ] {
            check_with(&radius, key, v, &cells(MAX_RADIUS_CELLS))?;
        }
        check_count(
            "map.c_min_cells",
            self.c_min_cells as u64,
            0,
            MAX_CLUSTER_CELLS,
            "cells",
        )?;
        // σ² is stored as f32: σ_d below a micrometre would square to a zero variance, and a
        // zero variance makes the Kalman gain 0/0.
        Range::closed(1e-6, 10.0, "m").check("map.sigma_d", self.sigma_d)?;
        Range::closed(0.0, 10.0, "1/m").check("map.k_d", self.k_d)?;
        Range::above(0.0, 1000.0, "").check("map.mahalanobis_gate", self.mahalanobis_gate)?;
        Range::closed(0.0, 100.0, "m²").check("map.multi_height_noise", self.multi_height_noise)?;
        check_count(
            "map.info_gain_stride",
            self.info_gain_stride.into(),
            1,
            MAX_INFO_GAIN_STRIDE.into(),
            "cells",
        )?;
        // Returns beyond r_sensor are what Eq. 11 promises the planner; dropping them would
        // leave goals that never get observed.
        let point_range = Range::closed(self.r_sensor, MAX_RADIUS_CELLS * d, "m");
        check_with(
            &point_range,
            "map.max_point_range",
            self.max_point_range,
            &format!("m (≥ map.r_sensor, at most {MAX_RADIUS_CELLS} cells of map.cell_size)"),
        )
    }
}

/// [`Range::check`] with `unit_note` in place of the range's unit (to say where a bound comes
/// from).
fn check_with(range: &Range, key: &str, value: f64, unit_note: &str) -> Result<(), ParamError> {
    range.check(key, value).map_err(|mut e| {
        let bare = Range { unit: "", ..*range };
        e.allowed = format!("{} {unit_note}", bare.describe());
        e
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn err(p: MapParams) -> String {
        p.validate().unwrap_err().to_string()
    }

    #[test]
    fn defaults_are_valid() {
        MapParams::default().validate().unwrap();
    }

    #[test]
    fn each_bad_value_names_key_value_and_range() {
        let d = MapParams::default;
        assert_eq!(
            err(MapParams {
                cell_size: -0.1,
                ..d()
            }),
            "map.cell_size = -0.1: must be a finite number in [0.01, 10] m"
        );
        assert_eq!(
            err(MapParams {
                cell_size: 0.0,
                ..d()
            }),
            "map.cell_size = 0: must be a finite number in [0.01, 10] m"
        );
        assert!(
            err(MapParams {
                cell_size: f64::NAN,
                ..d()
            })
            .starts_with("map.cell_size = NaN")
        );
        assert_eq!(
            err(MapParams {
                tile_size: 100_000,
                ..d()
            }),
            "map.tile_size = 100000: must be an integer in [1, 1024] cells"
        );
        assert_eq!(
            err(MapParams {
                sigma_d: f64::NAN,
                ..d()
            }),
            "map.sigma_d = NaN: must be a finite number in [1e-6, 10] m"
        );
        assert_eq!(
            err(MapParams {
                r_robot: 1e9,
                ..d()
            }),
            "map.r_robot = 1e9: must be a finite number in [0, 10] m (at most 200 cells of map.cell_size = 0.05 m)"
        );
        assert!(
            err(MapParams {
                r_robot: -0.25,
                ..d()
            })
            .starts_with("map.r_robot = -0.25: ")
        );
        assert_eq!(
            err(MapParams {
                max_point_range: 0.0,
                ..d()
            }),
            "map.max_point_range = 0: must be a finite number in [2.5, 50] m (≥ map.r_sensor, at most 1000 cells of map.cell_size)"
        );
        assert!(
            err(MapParams {
                r_sensor: f64::INFINITY,
                ..d()
            })
            .starts_with("map.r_sensor = inf: ")
        );
        assert!(
            err(MapParams {
                info_gain_stride: 0,
                ..d()
            })
            .starts_with("map.info_gain_stride = 0: ")
        );
        assert!(
            err(MapParams {
                mahalanobis_gate: 0.0,
                ..d()
            })
            .starts_with("map.mahalanobis_gate = 0: ")
        );
        assert!(
            err(MapParams {
                rho_obstacle: -1.0,
                ..d()
            })
            .starts_with("map.rho_obstacle = -1: ")
        );
        assert!(
            err(MapParams {
                sensor_height: 0.0,
                ..d()
            })
            .starts_with("map.sensor_height = 0: ")
        );
        assert!(
            err(MapParams {
                k_d: -0.0015,
                ..d()
            })
            .starts_with("map.k_d = -0.0015: ")
        );
        assert!(
            err(MapParams {
                c_min_cells: usize::MAX,
                ..d()
            })
            .starts_with("map.c_min_cells = 18446744073709551615: ")
        );
    }

    #[test]
    fn maps_from_outside_parameters_are_checked() {
        let bad = MapParams {
            cell_size: -0.1,
            ..MapParams::default()
        };
        assert!(crate::ElevationMap::try_new(bad).is_err());
        assert!(crate::ElevationMap::try_new(MapParams::default()).is_ok());
    }

    #[test]
    fn values_print_compactly() {
        assert_eq!(fmt_value(1e300), "1e300");
        assert_eq!(fmt_value(-1e-9), "-1e-9");
        assert_eq!(fmt_value(0.05), "0.05");
        assert_eq!(fmt_value(-0.0), "-0");
        assert_eq!(fmt_value(f64::NEG_INFINITY), "-inf");
        assert_eq!(
            Range::above(0.0, 1.0, "").describe(),
            "a finite number in (0, 1]"
        );
    }
}
