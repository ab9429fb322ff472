//! Validation of everything a scenario holds, each type checking its own parameters against
//! documented ranges ([`strider_map::params::Range`]) and the limits below, plus the checks
//! that need the whole scenario ([`Scenario::validate`]): layers of one size, terrain indices
//! and gait names defined, the map's cells not finer than the world's, the start on open ground.
//!
//! Every loop and allocation that depends on a scenario value is bounded through these checks:
//! the world's and the map's cell counts, the rays of a sensor, the discs of the footprint and
//! of the map's radii, and the simulator's steps and message rates.

use std::path::Path;

use strider_core::grid::disc_offsets;
use strider_core::{Cell, CellRect, Point2};
use strider_map::params::{ParamError, Range, check_count, fmt_value};
use strider_map::passability::{Passability, dense_passability, roughness};

use crate::error::ScenarioError;
use crate::model::{
    ElevationEncoding, GaitResponse, RobotProfile, Scenario, SensorKind, SensorSpec, SimParams,
    TerrainType, World,
};

/// Most cells a world may have (4096²): the loader, the simulator and the ground-truth layers
/// hold about 40 bytes per cell, so a world at the limit needs ≈ 700 MB. Checked against the
/// PNG headers before any layer is decoded.
pub const MAX_WORLD_CELLS: u64 = 1 << 24;
/// Most rays a sensor casts per scan (e.g. 1280 × 800): its ray directions take 24 bytes each
/// (24 MB at the limit) and every ray is cast at each scan. The built-in sensors cast 19 200
/// and 34 560.
pub const MAX_SENSOR_RAYS: u64 = 1 << 20;
/// Most range sensors on a robot: clouds carry the sensor's index as a byte, and each sensor
/// is scanned at its own rate.
pub const MAX_SENSORS: usize = 16;
/// Most gaits of a robot: gaits are addressed by a byte ([`strider_core::GaitId`]).
pub const MAX_GAITS: usize = 255;
/// Fewest map cells across the world's shorter side: a coarser map holds too few cells to tell
/// obstacles from open ground or to plan a path. With map cells never finer than the world's,
/// the map of a world holds at most [`MAX_WORLD_CELLS`] cells.
pub const MIN_MAP_CELLS_ACROSS: f64 = 4.0;
/// Longest footprint radius in world cells: the ground-truth admissibility and the start check
/// stamp discs of this radius (≈ 126 000 cells at the limit).
pub const MAX_FOOTPRINT_WORLD_CELLS: f64 = 200.0;

/// World resolution, metres per cell.
pub const WORLD_RESOLUTION: Range = Range::closed(0.001, 100.0, "m");
/// Elevation encoding scale, metres per 16-bit step: 65 535 steps of 1 m span 65 km.
pub const ELEVATION_SCALE: Range = Range::closed(1e-6, 1.0, "m");
/// Elevation encoding offset (elevation of sample 0), metres.
pub const ELEVATION_OFFSET: Range = Range::closed(-1e4, 1e4, "m");
/// Mission time limit, simulated seconds (≈ 11.6 days at most).
pub const TIME_LIMIT: Range = Range::above(0.0, 1e6, "s");
/// Motion integration step, seconds: below a millisecond a mission of hours takes billions of
/// steps; above a second the robot jumps over cells.
pub const SIM_DT: Range = Range::closed(1e-3, 1.0, "s");
/// Pose and proprioception stream rates, Hz (each message is one loop iteration).
pub const STREAM_RATE: Range = Range::closed(0.1, 1000.0, "Hz");
/// Sensor scan rate, Hz (each scan casts every ray of the sensor).
pub const SCAN_RATE: Range = Range::closed(0.1, 100.0, "Hz");
/// Sensor range, metres.
pub const SENSOR_RANGE: Range = Range::above(0.0, 1000.0, "m");
/// Sensor mounting height above the terrain under the robot, metres (at or below the ground the
/// sensor sees nothing).
pub const SENSOR_HEIGHT: Range = Range::above(0.0, 100.0, "m");
/// Gait top speed, m/s (legged robots walk below 2 m/s; the bound keeps one motion step within
/// a few cells).
pub const GAIT_SPEED: Range = Range::above(0.0, 10.0, "m/s");

impl SimParams {
    /// Checks the noise levels, rates and the integration step against their ranges.
    pub fn validate(&self) -> Result<(), ParamError> {
        Range::closed(0.0, 10.0, "m").check("sim.depth_sigma", self.depth_sigma)?;
        Range::closed(0.0, 10.0, "1/m").check("sim.depth_k", self.depth_k)?;
        Range::closed(0.0, 255.0, "").check("sim.color_sigma", self.color_sigma)?;
        STREAM_RATE.check("sim.pose_rate_hz", self.pose_rate_hz)?;
        Range::closed(0.0, 10.0, "m").check("sim.pose_sigma_xy", self.pose_sigma_xy)?;
        Range::closed(0.0, 10.0, "rad").check("sim.pose_sigma_yaw", self.pose_sigma_yaw)?;
        Range::closed(0.0, 1.0, "").check("sim.speed_noise", self.speed_noise)?;
        STREAM_RATE.check("sim.proprio_rate_hz", self.proprio_rate_hz)?;
        Range::closed(0.0, 10.0, "").check("sim.proprio_noise", self.proprio_noise)?;
        SIM_DT.check("sim.dt", self.dt)
    }
}

impl SensorSpec {
    /// Checks the geometry, range, mounting and rate; `key` (e.g. `robot.sensors[0]`) prefixes
    /// the keys in errors.
    pub fn validate(&self, key: &str) -> Result<(), ParamError> {
        SENSOR_RANGE.check(&format!("{key}.range"), self.range)?;
        SENSOR_HEIGHT.check(&format!("{key}.height"), self.height)?;
        Range::closed(-360.0, 360.0, "°").check(&format!("{key}.yaw_deg"), self.yaw_deg)?;
        SCAN_RATE.check(&format!("{key}.rate_hz"), self.rate_hz)?;
        let within_90 = Range::closed(-90.0, 90.0, "°");
        let (cols, rows, names) = match self.kind {
            SensorKind::RgbD {
                hfov_deg,
                vfov_deg,
                width,
                height,
                tilt_deg,
            } => {
                let fov = Range::above(0.0, 179.0, "°");
                fov.check(&format!("{key}.hfov_deg"), hfov_deg)?;
                fov.check(&format!("{key}.vfov_deg"), vfov_deg)?;
                within_90.check(&format!("{key}.tilt_deg"), tilt_deg)?;
                (width, height, ("width_px", "height_px"))
            }
            SensorKind::Omni {
                min_elevation_deg,
                max_elevation_deg,
                columns,
                rows,
            } => {
                within_90.check(&format!("{key}.min_elevation_deg"), min_elevation_deg)?;
                Range::closed(min_elevation_deg, 90.0, "° (≥ min_elevation_deg)")
                    .check(&format!("{key}.max_elevation_deg"), max_elevation_deg)?;
                (columns, rows, ("columns", "rows"))
            }
        };
        check_count(
            &format!("{key}.{}", names.0),
            cols.into(),
            1,
            MAX_SENSOR_RAYS,
            "",
        )?;
        check_count(
            &format!("{key}.{}", names.1),
            rows.into(),
            1,
            MAX_SENSOR_RAYS,
            "",
        )?;
        let rays = u64::from(cols) * u64::from(rows);
        if rays > MAX_SENSOR_RAYS {
            return Err(ParamError::new(
                format!("{key}.{} × {}", names.0, names.1),
                format!("{cols} × {rows} = {rays} rays"),
                format!("at most {MAX_SENSOR_RAYS} rays per scan (lower the resolution)"),
            ));
        }
        Ok(())
    }

    /// Number of rays per scan.
    pub fn ray_count(&self) -> u64 {
        match self.kind {
            SensorKind::RgbD { width, height, .. } => u64::from(width) * u64::from(height),
            SensorKind::Omni { columns, rows, .. } => u64::from(columns) * u64::from(rows),
        }
    }
}

impl RobotProfile {
    /// Checks gaits, sensors, footprint, body and the physical constants against their ranges.
    /// A robot without sensors is valid (tours and navigation need none; exploring strategies
    /// refuse it when they start).
    pub fn validate(&self) -> Result<(), ParamError> {
        check_count(
            "robot.gaits (count)",
            self.gaits.len() as u64,
            1,
            MAX_GAITS as u64,
            "gaits",
        )?;
        for (i, g) in self.gaits.iter().enumerate() {
            GAIT_SPEED.check(&format!("robot.gaits[{i}].max_speed"), g.max_speed)?;
        }
        check_count(
            "robot.sensors (count)",
            self.sensors.len() as u64,
            0,
            MAX_SENSORS as u64,
            "sensors",
        )?;
        for (i, s) in self.sensors.iter().enumerate() {
            s.validate(&format!("robot.sensors[{i}]"))?;
        }
        Range::closed(0.0, 100.0, "m").check("robot.footprint_radius", self.footprint_radius)?;
        if let Some([l, w]) = self.body {
            Range::above(0.0, 100.0, "m").check("robot.body[0] (length)", l)?;
            Range::above(0.0, 100.0, "m").check("robot.body[1] (width)", w)?;
        }
        Range::above(0.0, 1e5, "kg").check("robot.mass_kg", self.mass_kg)?;
        Range::closed(0.0, 1e6, "W").check("robot.hotel_load_w", self.hotel_load_w)?;
        Range::closed(0.0, 100.0, "m").check("robot.max_step_m", self.max_step_m)?;
        Range::above(0.0, 100.0, "rad/s").check("robot.turn_rate", self.turn_rate)?;
        Range::closed(0.0, 1e6, "N").check("robot.max_push_force_n", self.max_push_force_n)
    }
}

impl GaitResponse {
    /// Checks the response of gait `key` (e.g. `terrain[turf].gaits.fast`).
    pub fn validate(&self, key: &str) -> Result<(), ParamError> {
        Range::closed(0.0, 1.0, "").check(&format!("{key}.speed_factor"), self.speed_factor)?;
        Range::closed(0.0, 100.0, "rad²")
            .check(&format!("{key}.roll_variance"), self.roll_variance)?;
        Range::closed(0.0, 1e6, "W").check(&format!("{key}.power_w"), self.power_w)
    }
}

impl TerrainType {
    /// Checks the terrain's responses and physical constants.
    pub fn validate(&self) -> Result<(), ParamError> {
        let key = format!("terrain[{}]", self.name);
        Range::closed(0.0, 1e4, "m/s²").check(&format!("{key}.vibration"), self.vibration)?;
        Range::closed(0.0, 1e6, "").check(&format!("{key}.energy_per_m"), self.energy_per_m)?;
        if let Some(f) = self.push_force_n {
            Range::closed(0.0, 1e6, "N").check(&format!("{key}.push_force_n"), f)?;
        }
        for (g, r) in &self.gaits {
            r.validate(&format!("{key}.gaits.{g}"))?;
        }
        Ok(())
    }
}

impl ElevationEncoding {
    /// Checks that every 16-bit sample decodes to a finite, moderate elevation.
    pub fn validate(&self) -> Result<(), ParamError> {
        ELEVATION_SCALE.check("world.elevation.scale", self.scale)?;
        ELEVATION_OFFSET.check("world.elevation.offset", self.offset)
    }
}

/// `Ok` when a `width × height` world stays within [`MAX_WORLD_CELLS`] (checked arithmetic).
pub fn check_world_size(width: u32, height: u32) -> Result<(), ParamError> {
    let cells = u64::from(width) * u64::from(height);
    if cells > MAX_WORLD_CELLS {
        return Err(ParamError::new(
            "world size",
            format!("{width} × {height} = {cells} cells"),
            format!(
                "at most {MAX_WORLD_CELLS} cells (e.g. 4096 × 4096; use a coarser world.resolution or crop the layers)"
            ),
        ));
    }
    Ok(())
}

impl Scenario {
    /// Checks everything the scenario holds: each part's parameters against their ranges, the
    /// layers against each other and the terrain table, the gait names of terrain responses,
    /// the map against the world (cells not finer, footprint and radii within bounds), the start
    /// on the world and on open ground (admissible for the map's footprint and step threshold),
    /// bounds and tours. `path` names the scenario in error messages.
    pub fn validate(&self, path: &Path) -> Result<(), ScenarioError> {
        let param = |source: ParamError| ScenarioError::Param {
            path: path.to_path_buf(),
            source,
        };
        let bad = |m: String| Err(ScenarioError::invalid(path, m));
        let w = &self.world;
        WORLD_RESOLUTION
            .check("world.resolution", w.resolution)
            .map_err(param)?;
        check_world_size(w.rect.width, w.rect.height).map_err(param)?;
        self.validate_layers(path)?;
        for t in &w.terrains {
            t.validate().map_err(param)?;
        }
        let r = &self.robot;
        r.validate().map_err(param)?;
        let gait_names: Vec<&str> = r.gaits.iter().map(|g| g.name.as_str()).collect();
        for t in &w.terrains {
            if let Some(g) = t.gaits.keys().find(|g| !gait_names.contains(&g.as_str())) {
                return bad(format!(
                    "[[terrain]] '{}' (index {}): unknown gait '{g}' (robot '{}' has gaits: {})",
                    t.name,
                    t.index,
                    r.name,
                    gait_names.join(", ")
                ));
            }
        }
        self.map.validate().map_err(param)?;
        self.sim.validate().map_err(param)?;
        self.elevation_encoding.validate().map_err(param)?;
        TIME_LIMIT
            .check("time_limit_s", self.time_limit_s)
            .map_err(param)?;
        self.validate_against_world().map_err(param)?;
        self.validate_places(path)
    }

    /// Layers of one size, terrain indices unique and defined.
    fn validate_layers(&self, path: &Path) -> Result<(), ScenarioError> {
        let bad = |m: String| Err(ScenarioError::invalid(path, m));
        let w = &self.world;
        if w.rect.is_empty()
            || w.elevation.len() != w.rect.len()
            || w.color.len() != w.rect.len()
            || w.terrain.len() != w.rect.len()
        {
            return bad("world layers are empty or differ in size".into());
        }
        let lattice_end =
            |min: i32, len: u32| i64::from(min) + i64::from(len) <= i64::from(i32::MAX);
        if !(lattice_end(w.rect.min.i, w.rect.width) && lattice_end(w.rect.min.j, w.rect.height)) {
            return bad("world layers reach beyond the cell lattice (move world.origin)".into());
        }
        for (k, t) in w.terrains.iter().enumerate() {
            if w.terrains[..k].iter().any(|o| o.index == t.index) {
                return bad(format!(
                    "[[terrain]] index {} is defined twice ('{}')",
                    t.index, t.name
                ));
            }
        }
        if let Some(k) = w.terrain.iter().position(|&i| w.terrain_type(i).is_none()) {
            let c = w.rect.cell(k);
            return bad(format!(
                "terrain index {} at cell ({}, {}) is not in the [[terrain]] table",
                w.terrain[k], c.i, c.j
            ));
        }
        if let Some(k) = w.elevation.iter().position(|z| !z.is_finite()) {
            let c = w.rect.cell(k);
            return bad(format!(
                "elevation {} at cell ({}, {}) is not finite",
                w.elevation[k], c.i, c.j
            ));
        }
        Ok(())
    }

    /// The map and the robot against the world: map cells not finer than the world's, and
    /// footprints within [`MAX_FOOTPRINT_WORLD_CELLS`] world cells.
    fn validate_against_world(&self) -> Result<(), ParamError> {
        let res = self.world.resolution;
        let cs = self.map.cell_size;
        let e = self.world.extent();
        let shorter = (e.max.x - e.min.x).min(e.max.y - e.min.y);
        let coarsest = shorter / MIN_MAP_CELLS_ACROSS;
        // Finer map cells than the world's see nothing the world does not hold, and multiply
        // the cell count.
        if cs < res || cs > coarsest {
            return Err(ParamError::new(
                "map.cell_size",
                fmt_value(cs),
                format!(
                    "in [{}, {}] m: not finer than the world's resolution, and at least {MIN_MAP_CELLS_ACROSS} cells across the world's shorter side ({} m)",
                    fmt_value(res),
                    fmt_value(coarsest),
                    fmt_value(shorter)
                ),
            ));
        }
        let footprint = Range::closed(0.0, MAX_FOOTPRINT_WORLD_CELLS * res, "m");
        let note = format!(
            " (at most {MAX_FOOTPRINT_WORLD_CELLS} cells of world.resolution = {} m)",
            fmt_value(res)
        );
        for (key, v) in [
            ("map.r_robot", self.map.r_robot),
            ("robot.footprint_radius", self.robot.footprint_radius),
        ] {
            footprint.check(key, v).map_err(|mut e| {
                e.allowed.push_str(&note);
                e
            })?;
        }
        Ok(())
    }

    /// Start, bounds and tours on the world; the start on open ground.
    fn validate_places(&self, path: &Path) -> Result<(), ScenarioError> {
        let bad = |m: String| Err(ScenarioError::invalid(path, m));
        let w = &self.world;
        let s = self.start.position();
        if !self.start.yaw.is_finite() {
            return Err(ScenarioError::Param {
                path: path.to_path_buf(),
                source: ParamError::new(
                    "start.yaw",
                    fmt_value(self.start.yaw),
                    "a finite angle in radians",
                ),
            });
        }
        if !(s.is_finite() && w.contains(s)) {
            return bad(format!("[start] {}", outside(w, s)));
        }
        if let Some(why) = self.start_blocked() {
            return bad(format!("[start] {} {why}", pair(s)));
        }
        let b = self.bounds;
        if !(b.min.is_finite() && b.max.is_finite() && b.min.x < b.max.x && b.min.y < b.max.y) {
            return bad(format!(
                "[bounds] min {} must lie below and left of max {}",
                pair(b.min),
                pair(b.max)
            ));
        }
        // Grids over the bounds (e.g. the energy map of tours) are sized by them; beyond the
        // world there is nothing to explore. One cell of slack for rounded corners.
        let (e, slack) = (w.extent(), w.resolution);
        if b.min.x < e.min.x - slack
            || b.min.y < e.min.y - slack
            || b.max.x > e.max.x + slack
            || b.max.y > e.max.y + slack
        {
            return bad(format!(
                "[bounds] min {} … max {} reach beyond the world {}",
                pair(b.min),
                pair(b.max),
                extent(w)
            ));
        }
        for t in &self.tours {
            if t.waypoints.is_empty() {
                return bad(format!("[[tours]] '{}' has no waypoints", t.name));
            }
            for (k, p) in t.waypoints.iter().enumerate() {
                if !p.is_finite() || !w.contains(*p) {
                    return bad(format!(
                        "[[tours]] '{}' waypoint {}: {}",
                        t.name,
                        k + 1,
                        outside(w, *p)
                    ));
                }
            }
        }
        Ok(())
    }

    /// Why the robot cannot stand at the start, if it cannot: the start cell must be passable
    /// and no impassable cell may lie within `map.r_robot` (the rule of
    /// [`World::gt_admissible`], which the robot's own map applies), evaluated on a window
    /// around the start only, so the cost does not grow with the world.
    fn start_blocked(&self) -> Option<String> {
        let w = &self.world;
        let d = w.resolution;
        let (r, rho) = (self.map.r_robot, self.map.rho_obstacle);
        let c = Cell::containing(self.start.x, self.start.y, d)?;
        let disc = disc_offsets(r, d);
        let reach = disc
            .iter()
            .map(|&(i, j)| i.abs().max(j.abs()))
            .max()
            .unwrap_or(0);
        // The disc plus one cell: the roughness of a disc cell needs its neighbours.
        let m = reach + 1;
        let win = CellRect::new(c.offset(-m, -m), (2 * m + 1) as u32, (2 * m + 1) as u32);
        let elev: Vec<f32> = win
            .cells()
            .map(|q| w.rect.index(q).map_or(f32::NAN, |k| w.elevation[k]))
            .collect();
        let side = win.width as usize;
        let pass = dense_passability(&elev, None, side, side, rho);
        let step = |q: Cell| {
            let k = win.index(q)?;
            let z = elev[k];
            let nb = q
                .neighbours8()
                .map(|n| win.index(n).map(|i| elev[i]).filter(|v| v.is_finite()));
            roughness(z, nb)
        };
        let centre = win.index(c)?;
        match (pass[centre], step(c)) {
            (Passability::Passable, _) => {}
            (_, Some(s)) => {
                return Some(format!(
                    "is in an obstacle: its cell ({}, {}) has a step of {s} m (more than map.rho_obstacle = {rho} m); move the start onto open ground",
                    c.i, c.j
                ));
            }
            (_, None) => {
                return Some(format!(
                    "is on cell ({}, {}), which has no neighbour on the world to measure a step against; the world needs at least 2 × 2 cells",
                    c.i, c.j
                ));
            }
        }
        for &(di, dj) in &disc {
            let q = c.offset(di, dj);
            if win
                .index(q)
                .is_some_and(|k| pass[k] == Passability::Impassable)
            {
                let s = step(q).unwrap_or(f32::NAN);
                return Some(format!(
                    "is within map.r_robot = {r} m of the obstacle cell ({}, {}) (a step of {s} m, more than map.rho_obstacle = {rho} m); the robot's footprint would overlap it — move the start onto open ground",
                    q.i, q.j
                ));
            }
        }
        None
    }
}

/// "(x, y) lies outside the world [x0, x1] × [y0, y1] m".
fn outside(world: &World, p: Point2) -> String {
    format!("{} lies outside the world {}", pair(p), extent(world))
}

/// "(x, y)", each coordinate compact.
fn pair(p: Point2) -> String {
    format!("({}, {})", fmt_value(p.x), fmt_value(p.y))
}

/// "[x0, x1] × [y0, y1] m".
fn extent(world: &World) -> String {
    let b = world.extent();
    format!(
        "[{}, {}] × [{}, {}] m",
        fmt_value(b.min.x),
        fmt_value(b.max.x),
        fmt_value(b.min.y),
        fmt_value(b.max.y)
    )
}
