//! The scenario file format: one TOML file naming three PNG layers, and its loader and writer.
//!
//! # Layout
//!
//! A scenario is a directory (or any place) holding `scenario.toml` and the PNG layers it names;
//! layer paths are relative to the TOML file. [`Scenario::load`] accepts the TOML file or its
//! directory; [`Scenario::save`] writes `scenario.toml`, `color.png`, `elevation.png` and
//! `terrain.png` into a directory, and loading them back gives an identical [`Scenario`] (this is
//! also how to get an editable copy of a built-in: `generate` then `save`).
//!
//! # Layers
//!
//! All three PNGs have the same size, one pixel per cell, and sit on the global cell lattice:
//! the lower-left pixel is cell `floor(origin / resolution)`, so `origin` must be a multiple of
//! `resolution`. **The image's top row is the world's highest y (north up)**; the loader flips
//! rows so that the model's row 0 is the lowest y.
//!
//! * `color`: 8-bit RGB (no alpha), the surface colour.
//! * `elevation`: 16-bit grayscale; the elevation in metres is `offset + scale · value`.
//! * `terrain`: 8-bit grayscale or indexed (palette, 1–8 bits) PNG; the sample (or palette
//!   index) is the terrain index of a `[[terrain]]` entry. Palette colours are ignored, so an
//!   indexed PNG can show the terrain map in any colours an image editor likes.
//!
//! # Complete example
//!
//! ```toml
//! name = "my-yard"
//! description = "A paved yard with a lawn."
//! world_seed = 0            # optional (0 for hand-made worlds)
//! time_limit_s = 3600.0     # optional mission time limit, simulated seconds (default 3600)
//!
//! [world]
//! resolution = 0.05         # metres per cell, > 0
//! origin = [0.0, 0.0]       # lower-left corner [x, y], a multiple of resolution
//! color = "color.png"
//! elevation = { file = "elevation.png", scale = 0.0005, offset = -1.0 }
//! terrain = "terrain.png"
//!
//! [[terrain]]
//! index = 0
//! name = "pavement"
//! gaits.fast = { speed_factor = 1.0 }
//! gaits.tall = { speed_factor = 1.0 }
//!
//! [[terrain]]
//! index = 1
//! name = "turf"
//! vibration = 0.0           # optional, m/s² (Nardi19)
//! energy_per_m = 1.0        # optional, relative (Nardi19)
//! gaits.fast = { speed_factor = 0.02, stuck = true }
//! gaits.tall = { speed_factor = 0.8, roll_variance = 0.0, power_w = 0.0 }
//!
//! [[terrain]]
//! index = 2
//! name = "curtain"
//! push_force_n = 0.8        # optional; absent = rigid
//!
//! [robot]
//! profile = "hexapod-small" # a built-in profile; any key below overrides it
//! max_step_m = 0.12
//! # ... or a full inline profile instead:
//! # name = "my-robot"
//! # gaits = [{ name = "fast", max_speed = 0.05 }]
//! # footprint_radius = 0.25
//! # sensors = [{ kind = "rgb-d", hfov_deg = 87.0, vfov_deg = 58.0, width_px = 160,
//! #              height_px = 120, tilt_deg = 16.0, range = 2.5, height = 0.3 }]
//!
//! [map]                     # MapParams; every key optional (defaults: Prágr22 Table 3 left)
//! cell_size = 0.05
//! r_robot = 0.25
//!
//! [sim]                     # SimParams; every key optional
//! speed_noise = 0.05
//!
//! [strategy.gtsp]           # parameters per strategy (`strider strategies` lists them);
//! c_loss = 10.0             # a section per strategy, checked by the strategy's typed
//!                           # parameters when it runs (unknown keys and wrong types fail)
//! [strategy.rbcm-greedy]
//! lambda_score_by_gait = { adaptive = 0.001, regular = 0.0005 }
//!
//! [start]
//! x = 0.6
//! y = 0.6
//! yaw = 0.0                 # radians, optional
//!
//! [bounds]                  # optional; default: the world inset by map.r_robot
//! min = { x = 0.25, y = 0.25 }
//! max = { x = 5.75, y = 4.75 }
//!
//! [[tours]]
//! name = "corners"
//! closed = true             # optional: return to the first waypoint
//! waypoints = [{ x = 0.6, y = 0.6 }, { x = 5.4, y = 0.6 }, { x = 5.4, y = 4.4 }]
//! ```
//!
//! Every terrain response's gait name must be a gait of the robot; gaits a terrain does not list
//! get [`crate::GaitResponse::default`]. The start and every waypoint must lie on the world,
//! the start on open ground (passable, and no obstacle within `map.r_robot`). Every value is
//! checked against its documented range, and the layers' size against a cell limit read from
//! the PNG headers before decoding ([`crate::validate`]). Errors name the file and the problem
//! in one line ([`ScenarioError`]), a parameter as `key = value: must be <range and unit>`.
//!
//! [`Scenario::from_toml_str`] loads the same format from a string, with the layers from any
//! [`LayerSource`] (e.g. PNG bytes in memory).

use std::fs;
use std::path::{Path, PathBuf};

use serde::{Deserialize, Serialize};
use strider_core::{Cell, CellRect, Point2, Pose2, Rgb8};
use strider_map::MapParams;

use crate::error::ScenarioError;
use crate::layers::{LayerDir, LayerSource};
use crate::model::{
    Bounds, ElevationEncoding, RobotProfile, Scenario, SimParams, TerrainType, Tour, World,
};
use crate::png_io;
use crate::profiles;
use crate::validate::WORLD_RESOLUTION;

/// File name of the scenario TOML inside a scenario directory.
pub const SCENARIO_FILE: &str = "scenario.toml";
/// File name [`Scenario::save`] gives the colour layer.
pub const COLOR_FILE: &str = "color.png";
/// File name [`Scenario::save`] gives the elevation layer.
pub const ELEVATION_FILE: &str = "elevation.png";
/// File name [`Scenario::save`] gives the terrain layer.
pub const TERRAIN_FILE: &str = "terrain.png";

fn default_time_limit() -> f64 {
    3600.0
}

/// The TOML document as written on disk.
#[derive(Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
struct FileDoc {
    name: String,
    #[serde(default)]
    description: String,
    #[serde(default)]
    world_seed: u64,
    #[serde(default = "default_time_limit")]
    time_limit_s: f64,
    world: WorldSection,
    #[serde(rename = "terrain")]
    terrains: Vec<TerrainType>,
    robot: toml::Table,
    #[serde(default)]
    map: MapParams,
    #[serde(default)]
    sim: SimParams,
    #[serde(default)]
    strategy: toml::Table,
    start: StartSection,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    bounds: Option<Bounds>,
    #[serde(default)]
    tours: Vec<Tour>,
}

#[derive(Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
struct WorldSection {
    resolution: f64,
    #[serde(default)]
    origin: [f64; 2],
    color: String,
    elevation: ElevationSection,
    terrain: String,
}

#[derive(Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
struct ElevationSection {
    file: String,
    scale: f64,
    #[serde(default)]
    offset: f64,
}

#[derive(Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
struct StartSection {
    x: f64,
    y: f64,
    #[serde(default)]
    yaw: f64,
}

/// 1-based line and column (in characters) of byte offset `at` in `text`.
fn line_col(text: &str, at: usize) -> (usize, usize) {
    let at = at.min(text.len());
    let mut at = at;
    while !text.is_char_boundary(at) {
        at -= 1;
    }
    let before = &text[..at];
    let line = before.matches('\n').count() + 1;
    let line_start = before.rfind('\n').map_or(0, |k| k + 1);
    (line, before[line_start..].chars().count() + 1)
}

fn toml_error(path: &Path, text: &str, e: &toml::de::Error) -> ScenarioError {
    let (line, column) = e.span().map_or((1, 1), |s| line_col(text, s.start));
    let message = strider_core::text::one_line(
        &e.message()
            .lines()
            .map(str::trim)
            .filter(|l| !l.is_empty())
            .collect::<Vec<_>>()
            .join("; "),
    );
    ScenarioError::Toml {
        path: path.to_path_buf(),
        line,
        column,
        message,
    }
}

/// Resolves `[robot]`: a built-in `profile` with overrides, or a full inline profile.
fn resolve_robot(path: &Path, table: toml::Table) -> Result<RobotProfile, ScenarioError> {
    let mut table = table;
    let merged = match table.remove("profile") {
        None => table,
        Some(toml::Value::String(name)) => {
            let base = profiles::profile(&name).ok_or_else(|| {
                ScenarioError::invalid(
                    path,
                    format!(
                        "[robot] unknown profile '{name}'; built-in profiles: {}",
                        profiles::PROFILE_NAMES.join(", ")
                    ),
                )
            })?;
            let mut merged = toml::Table::try_from(&base).map_err(|e| {
                ScenarioError::invalid(path, format!("[robot] profile '{name}': {e}"))
            })?;
            merged.extend(table);
            merged
        }
        Some(other) => {
            return Err(ScenarioError::invalid(
                path,
                format!(
                    "[robot] profile must be a string naming a built-in profile, found {}",
                    other.type_str()
                ),
            ));
        }
    };
    merged
        .try_into::<RobotProfile>()
        .map_err(|e| ScenarioError::invalid(path, format!("[robot] {}", e.message().trim())))
}

impl Scenario {
    /// Loads a scenario from its TOML file, or from a directory holding `scenario.toml`.
    /// Layer paths are relative to the TOML file. Never panics on bad input: every problem is a
    /// one-line [`ScenarioError`] naming the file.
    pub fn load(path: impl AsRef<Path>) -> Result<Scenario, ScenarioError> {
        let path = path.as_ref();
        let file = if path.is_dir() {
            path.join(SCENARIO_FILE)
        } else {
            path.to_path_buf()
        };
        let text = fs::read_to_string(&file).map_err(|e| {
            if e.kind() == std::io::ErrorKind::NotFound {
                ScenarioError::MissingFile {
                    path: file.clone(),
                    what: "scenario file".into(),
                }
            } else {
                ScenarioError::Read {
                    path: file.clone(),
                    source: e,
                }
            }
        })?;
        let dir = file.parent().unwrap_or(Path::new("."));
        Self::from_toml_str(&text, &file, &LayerDir(dir.to_path_buf()))
    }

    /// Parses scenario TOML `text` and decodes the PNG layers it names from `layers` (files
    /// with [`LayerDir`], or a `BTreeMap<String, Vec<u8>>` of PNG bytes keyed by the names the
    /// TOML uses, which needs no filesystem). `file` names the scenario in error messages.
    /// Validates the result ([`Scenario::validate`]). Never panics and allocates nothing beyond
    /// the documented limits ([`crate::validate`]) on bad input: every problem is a one-line
    /// [`ScenarioError`].
    pub fn from_toml_str(
        text: &str,
        file: &Path,
        layers: &dyn LayerSource,
    ) -> Result<Scenario, ScenarioError> {
        let doc: FileDoc = toml::from_str(text).map_err(|e| toml_error(file, text, &e))?;
        doc.into_scenario(file, layers)
    }

    /// Writes the scenario into directory `dir` (created if needed) as `scenario.toml` plus
    /// `color.png`, `elevation.png` and `terrain.png`; returns the TOML path. The robot is
    /// written as a full inline profile. [`Scenario::load`] of the result gives back an equal
    /// scenario.
    pub fn save(&self, dir: impl AsRef<Path>) -> Result<PathBuf, ScenarioError> {
        let dir = dir.as_ref();
        let file = dir.join(SCENARIO_FILE);
        self.validate(&file)?;
        fs::create_dir_all(dir).map_err(|e| ScenarioError::Write {
            path: dir.to_path_buf(),
            source: e,
        })?;
        let w = &self.world;
        let (width, height) = (w.width(), w.height());
        let enc = self.elevation_encoding;
        // Image order: top row = highest y.
        let image_rows = (0..height).rev();
        let mut color = Vec::with_capacity(w.rect.len());
        let mut elev = Vec::with_capacity(w.rect.len());
        let mut terrain = Vec::with_capacity(w.rect.len());
        for j in image_rows {
            for i in 0..width {
                let k = j * width + i;
                color.push(w.color[k].0);
                terrain.push(w.terrain[k]);
                let v = enc.encode(w.elevation[k]).ok_or_else(|| {
                    ScenarioError::invalid(
                        &file,
                        format!(
                            "elevation {} m at cell {:?} cannot be stored with scale {} and offset {}",
                            w.elevation[k],
                            w.rect.cell(k),
                            enc.scale,
                            enc.offset
                        ),
                    )
                })?;
                elev.push(v);
            }
        }
        let (wu, hu) = (w.rect.width, w.rect.height);
        png_io::write_rgb8(&dir.join(COLOR_FILE), wu, hu, &color)?;
        png_io::write_gray16(&dir.join(ELEVATION_FILE), wu, hu, &elev)?;
        png_io::write_gray8(&dir.join(TERRAIN_FILE), wu, hu, &terrain)?;

        let origin = w.origin();
        let robot = toml::Table::try_from(&self.robot)
            .map_err(|e| ScenarioError::invalid(&file, format!("[robot] {e}")))?;
        let doc = FileDoc {
            name: self.name.clone(),
            description: self.description.clone(),
            world_seed: self.world_seed,
            time_limit_s: self.time_limit_s,
            world: WorldSection {
                resolution: w.resolution,
                origin: [origin.x, origin.y],
                color: COLOR_FILE.into(),
                elevation: ElevationSection {
                    file: ELEVATION_FILE.into(),
                    scale: enc.scale,
                    offset: enc.offset,
                },
                terrain: TERRAIN_FILE.into(),
            },
            terrains: w.terrains.clone(),
            robot,
            map: self.map.clone(),
            sim: self.sim.clone(),
            strategy: self.strategy.clone(),
            start: StartSection {
                x: self.start.x,
                y: self.start.y,
                yaw: self.start.yaw,
            },
            bounds: Some(self.bounds),
            tours: self.tours.clone(),
        };
        let text = toml::to_string_pretty(&doc)
            .map_err(|e| ScenarioError::invalid(&file, format!("cannot serialise: {e}")))?;
        fs::write(&file, text).map_err(|e| ScenarioError::Write {
            path: file.clone(),
            source: e,
        })?;
        Ok(file)
    }
}

impl FileDoc {
    fn into_scenario(
        self,
        file: &Path,
        layers: &dyn LayerSource,
    ) -> Result<Scenario, ScenarioError> {
        let bad = |m: String| ScenarioError::invalid(file, m);
        let param = |source| ScenarioError::Param {
            path: file.to_path_buf(),
            source,
        };
        let ws = &self.world;
        let res = ws.resolution;
        WORLD_RESOLUTION
            .check("world.resolution", res)
            .map_err(param)?;
        let mut min_cell = [0i32; 2];
        for (a, &o) in ws.origin.iter().enumerate() {
            let q = o / res;
            if !q.is_finite() || (q - q.round()).abs() > 1e-6 || q.abs() > 1e9 {
                return Err(bad(format!(
                    "[world] origin [{}, {}] must be a multiple of the resolution {res} m (the layers sit on the cell lattice floor(x / resolution))",
                    ws.origin[0], ws.origin[1]
                )));
            }
            min_cell[a] = q.round() as i32;
        }
        let enc = ElevationEncoding {
            scale: ws.elevation.scale,
            offset: ws.elevation.offset,
        };
        enc.validate().map_err(param)?;
        if self.terrains.is_empty() {
            return Err(bad("no [[terrain]] entries".into()));
        }
        let robot = resolve_robot(file, self.robot)?;

        // Layers, in image order, then flipped to row 0 = lowest y.
        let color_path = layers.path(&ws.color);
        let elev_path = layers.path(&ws.elevation.file);
        let terr_path = layers.path(&ws.terrain);
        let color = png_io::read_rgb8(layers, &ws.color, "colour layer named in [world] color")?;
        let elev = png_io::read_gray16(
            layers,
            &ws.elevation.file,
            "elevation layer named in [world] elevation",
        )?;
        let terr = png_io::read_index8(
            layers,
            &ws.terrain,
            "terrain layer named in [world] terrain",
        )?;
        for (p, w, h) in [
            (&elev_path, elev.width, elev.height),
            (&terr_path, terr.width, terr.height),
        ] {
            if (w, h) != (color.width, color.height) {
                return Err(ScenarioError::SizeMismatch {
                    path: p.clone(),
                    width: w,
                    height: h,
                    reference: color_path.clone(),
                    ref_width: color.width,
                    ref_height: color.height,
                });
            }
        }
        let mut seen = [false; 256];
        for t in &self.terrains {
            seen[t.index as usize] = true;
        }
        if let Some(k) = terr.data.iter().position(|&i| !seen[i as usize]) {
            let index = terr.data[k];
            return Err(ScenarioError::UnknownTerrainIndex {
                path: terr_path,
                index,
                x: (k % color.width as usize) as u32,
                y: (k / color.width as usize) as u32,
                count: terr.data.iter().filter(|&&i| i == index).count(),
            });
        }
        let (width, height) = (color.width as usize, color.height as usize);
        let flip = |k: usize| (height - 1 - k / width) * width + k % width;
        let n = width * height;
        let world = World {
            resolution: res,
            rect: CellRect::new(
                Cell::new(min_cell[0], min_cell[1]),
                color.width,
                color.height,
            ),
            elevation: (0..n).map(|k| enc.decode(elev.data[flip(k)])).collect(),
            color: (0..n).map(|k| Rgb8(color.data[flip(k)])).collect(),
            terrain: (0..n).map(|k| terr.data[flip(k)]).collect(),
            terrains: self.terrains,
        };
        let bounds = self.bounds.unwrap_or_else(|| {
            let e = world.extent();
            let r = self.map.r_robot;
            Bounds {
                min: Point2::new(e.min.x + r, e.min.y + r),
                max: Point2::new(e.max.x - r, e.max.y - r),
            }
        });
        let scenario = Scenario {
            name: self.name,
            description: self.description,
            world_seed: self.world_seed,
            world,
            robot,
            map: self.map,
            sim: self.sim,
            strategy: self.strategy,
            start: Pose2::new(self.start.x, self.start.y, self.start.yaw),
            bounds,
            tours: self.tours,
            time_limit_s: self.time_limit_s,
            elevation_encoding: enc,
        };
        scenario.validate(file)?;
        Ok(scenario)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn line_col_counts_chars() {
        let t = "a = 1\nbé = x\n";
        assert_eq!(line_col(t, 0), (1, 1));
        assert_eq!(line_col(t, 6), (2, 1));
        assert_eq!(line_col(t, t.find('x').unwrap()), (2, 6));
    }
}
