//! The replay configuration (TOML): which topics and frames of a log carry what, and the
//! robot, map and learning parameters the mission needs.
//!
//! Every key has a default matching what `strider run --mcap` records, so a configuration for
//! Strider's own logs only needs its `[mission]` table. A complete example:
//!
//! ```toml
//! world_frame = "map"            # the fixed frame the map is built in
//! keyframes = true               # fuse only the scans the mission's keyframe rule wants
//!                                # (false: fuse every scan in the log)
//! reorder_window_s = 1.0         # clouds may arrive this much out of stamp order in the file
//! motion_topic = "/robot/motion" # std_msgs/msg/UInt8, bit 0 = path done (idle), bit 1 =
//!                                # blocked; "" = none: the robot counts as driving throughout
//!
//! [pose]                         # the body pose stream (cost measurement, keyframes)
//! topic = "/robot/odom"          # nav_msgs/msg/Odometry; its header frame is chained to
//!                                # world_frame through /tf when it differs
//! from_tf = false                # true: take the pose from /tf (world_frame → base_frame)
//! base_frame = "base_link"
//!
//! [[clouds]]                     # one table per sensor, in the order of the sensor ids
//! topic = "/robot/sensor_0/points"   # sensor_msgs/msg/PointCloud2 with x, y, z and colour,
//!                                # or sensor_msgs/msg/LaserScan (the topic's schema decides:
//!                                # a planar laser, read without colour)
//! origin_frame = "sensor_0"      # the frame whose origin is the sensor (default: the
//!                                # cloud's own frame; required for clouds in world_frame)
//! missing_rgb = "error"          # or "gray": map clouds without a colour field (and
//!                                # LaserScans) uncoloured
//!
//! [gait]
//! topic = "/robot/gait"          # std_msgs/msg/String (gait name) or std_msgs/msg/UInt8
//!                                # (gait index); "" = none
//! default = "fast"               # before the first gait message, or throughout without one
//!                                # (default: the fastest gait)
//!
//! [tf]
//! topic = "/tf"
//! static_topic = "/tf_static"
//! tolerance_s = 0.5              # a transform is used up to this far outside its stamps
//!
//! [mission]
//! scenario = "courtyard-small"   # robot profile, map parameters and [strategy] table of a
//! world_seed = 1                 # scenario (built-in name or TOML file; its world is unused)
//! seed = 1                       # the mission's seed (IGNG batches)
//! strategy = "gtsp"
//! # ... or, instead of `scenario`, the robot and parameters themselves:
//! # gaits = [{ name = "fast", v_max = 0.05 }, { name = "tall", v_max = 0.0125 }]
//! # sensor_hfov_deg = [87.0]
//! # bounds = [[-5.0, -5.0], [5.0, 5.0]]   # optional
//! # [mission.map]                # MapParams (cell_size, r_robot, r_sensor, …)
//! # [mission.parameters]         # the keys of a scenario's [strategy] table
//! # turning_baseline_s = 0.5     # e.g.: heading-rate baseline, s, that tells turning from
//! #                              # walking; about a gait cycle for a robot whose body sways
//! ```
//!
//! Topics in the log that are not named here are ignored. The pose topic and every cloud
//! topic must have messages; the gait, motion and tf topics are used when present.

use crate::error::{LogError, plain};
use crate::limits::MAX_SPAN_S;
use crate::ros2::MissingRgb;
use serde::Deserialize;
use std::path::Path;
use strider_core::GaitSpec;
use strider_map::params::MapParams;

/// The whole replay configuration.
#[derive(Clone, Debug, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ReplayConfig {
    /// The fixed frame the map is built in.
    #[serde(default = "world")]
    pub world_frame: String,
    /// Whether `world_frame` was left out (it is then "map"): set by [`ReplayConfig::parse`],
    /// for the errors about frames.
    #[serde(skip)]
    pub world_frame_defaulted: bool,
    /// Fuse only the scans the mission's keyframe rule wants.
    #[serde(default = "yes")]
    pub keyframes: bool,
    /// How far out of stamp order clouds may be in the file, s.
    #[serde(default = "one")]
    pub reorder_window_s: f64,
    /// std_msgs/UInt8 motion state per control tick ("" = none).
    #[serde(default = "motion")]
    pub motion_topic: String,
    /// The pose stream.
    #[serde(default)]
    pub pose: PoseConfig,
    /// One entry per sensor, in sensor-id order.
    #[serde(default = "clouds")]
    pub clouds: Vec<CloudConfig>,
    /// Where the gait comes from.
    #[serde(default)]
    pub gait: GaitConfig,
    /// The transform topics.
    #[serde(default)]
    pub tf: TfConfig,
    /// Robot, map and learning parameters.
    pub mission: MissionConfig,
}

fn world() -> String {
    "map".into()
}
fn yes() -> bool {
    true
}
fn one() -> f64 {
    1.0
}
fn motion() -> String {
    "/robot/motion".into()
}
fn clouds() -> Vec<CloudConfig> {
    vec![CloudConfig {
        topic: "/robot/sensor_0/points".into(),
        origin_frame: Some("sensor_0".into()),
        missing_rgb: MissingRgb::Error,
    }]
}

/// The pose stream.
#[derive(Clone, Debug, PartialEq, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct PoseConfig {
    /// nav_msgs/msg/Odometry topic.
    pub topic: String,
    /// Take the pose from /tf instead.
    pub from_tf: bool,
    /// The body frame (for `from_tf`).
    pub base_frame: String,
}

impl Default for PoseConfig {
    fn default() -> Self {
        Self {
            topic: "/robot/odom".into(),
            from_tf: false,
            base_frame: "base_link".into(),
        }
    }
}

/// One sensor's point clouds.
#[derive(Clone, Debug, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct CloudConfig {
    /// sensor_msgs/msg/PointCloud2 or sensor_msgs/msg/LaserScan topic (its schema decides).
    pub topic: String,
    /// The frame whose origin is the sensor (default: the cloud's frame).
    #[serde(default)]
    pub origin_frame: Option<String>,
    /// What to do with clouds without colour.
    #[serde(default)]
    pub missing_rgb: MissingRgb,
}

/// Where the gait comes from.
#[derive(Clone, Debug, PartialEq, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct GaitConfig {
    /// std_msgs/String (name) or std_msgs/UInt8 (index) topic ("" = none).
    pub topic: String,
    /// The gait before the first message or throughout (default: the fastest).
    pub default: Option<String>,
}

impl Default for GaitConfig {
    fn default() -> Self {
        Self {
            topic: "/robot/gait".into(),
            default: None,
        }
    }
}

/// The transform topics.
#[derive(Clone, Debug, PartialEq, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct TfConfig {
    /// tf2_msgs/msg/TFMessage.
    pub topic: String,
    /// tf2_msgs/msg/TFMessage, latched static transforms.
    pub static_topic: String,
    /// A transform is used up to this far before its first or after its last stamp, s.
    pub tolerance_s: f64,
}

impl Default for TfConfig {
    fn default() -> Self {
        Self {
            topic: "/tf".into(),
            static_topic: "/tf_static".into(),
            tolerance_s: 0.5,
        }
    }
}

/// Robot, map and learning parameters: a scenario's, or given here.
#[derive(Clone, Debug, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct MissionConfig {
    /// Take the robot profile, map parameters and `[strategy]` table of this scenario
    /// (built-in name or TOML file).
    #[serde(default)]
    pub scenario: Option<String>,
    /// The scenario's world seed.
    #[serde(default = "one_u64")]
    pub world_seed: u64,
    /// The mission's seed.
    #[serde(default = "one_u64")]
    pub seed: u64,
    /// Exploration strategy name (it only decides whether the view for the gait choice is
    /// kept; learning is the same).
    #[serde(default = "gtsp")]
    pub strategy: String,
    /// The robot's gaits (without `scenario`).
    #[serde(default)]
    pub gaits: Vec<GaitSpec>,
    /// Horizontal field of view per sensor, degrees (without `scenario`).
    #[serde(default)]
    pub sensor_hfov_deg: Vec<f64>,
    /// Exploration bounds [[min x, min y], [max x, max y]] (without `scenario`).
    #[serde(default)]
    pub bounds: Option<[[f64; 2]; 2]>,
    /// Map parameters (without `scenario`).
    #[serde(default)]
    pub map: Option<MapParams>,
    /// The Prágr22 Tbl. 3 values by the names of a scenario's `[strategy]` table.
    #[serde(default)]
    pub parameters: toml::Table,
}

fn one_u64() -> u64 {
    1
}
fn gtsp() -> String {
    "gtsp".into()
}

/// Longest reorder window, s: clouds further out of stamp order than ten minutes mean a broken
/// clock, and the clouds within the window are held in memory.
pub const MAX_REORDER_WINDOW_S: f64 = 600.0;

/// Fastest gait speed accepted, m/s: faster is no walking or driving robot, and a typo.
pub const MAX_GAIT_SPEED: f64 = 100.0;

impl ReplayConfig {
    /// Parses and checks a configuration; any text gives a configuration or an error, never a
    /// panic.
    pub fn parse(text: &str) -> Result<Self, LogError> {
        let mut c: ReplayConfig = toml::from_str(text).map_err(|e| toml_error(text, &e))?;
        c.world_frame_defaulted =
            toml::from_str::<toml::Table>(text).is_ok_and(|t| !t.contains_key("world_frame"));
        c.validate()?;
        Ok(c)
    }

    /// Reads and parses a configuration file.
    pub fn load(path: &Path) -> Result<Self, LogError> {
        let text = std::fs::read_to_string(path).map_err(|e| LogError::io(path, e))?;
        Self::parse(&text).map_err(|e| match e {
            LogError::Config(m) => LogError::Config(format!("{}: {m}", path.display())),
            e => e,
        })
    }

    /// Checks every value against its range, once, where the configuration enters.
    fn validate(&self) -> Result<(), LogError> {
        let bad = |m: String| Err(LogError::Config(m));
        if self.world_frame.is_empty() {
            return bad("world_frame is empty: name the fixed frame the map is built in".into());
        }
        if !(0.0..=MAX_REORDER_WINDOW_S).contains(&self.reorder_window_s) {
            return bad(format!(
                "reorder_window_s = {}: must be a finite number ≥ 0 s and ≤ {MAX_REORDER_WINDOW_S} s",
                self.reorder_window_s
            ));
        }
        if !(0.0..=MAX_SPAN_S).contains(&self.tf.tolerance_s) {
            return bad(format!(
                "[tf] tolerance_s = {}: must be a finite number ≥ 0 s and ≤ {MAX_SPAN_S} s",
                self.tf.tolerance_s
            ));
        }
        self.validate_topics()?;
        self.mission.validate(self.clouds.len())
    }

    /// Checks the topics and frames.
    fn validate_topics(&self) -> Result<(), LogError> {
        let bad = |m: String| Err(LogError::Config(m));
        if self.clouds.is_empty() {
            return bad("no [[clouds]] topic: the map needs point clouds".into());
        }
        if self.clouds.len() > u8::MAX as usize {
            return bad(format!("{} cloud topics: at most 255", self.clouds.len()));
        }
        for (k, c) in self.clouds.iter().enumerate() {
            if c.topic.is_empty() {
                return bad(format!("[[clouds]] {k}: the topic is empty"));
            }
            if c.origin_frame.as_deref() == Some("") {
                return bad(format!(
                    "[[clouds]] {k} ({}): origin_frame is empty; leave it out to use the \
                     cloud's own frame",
                    c.topic
                ));
            }
        }
        if self.pose.from_tf {
            if self.tf.topic.is_empty() || self.pose.base_frame.is_empty() {
                return bad("[pose] from_tf = true needs a [tf] topic and a base_frame".into());
            }
        } else if self.pose.topic.is_empty() {
            return bad("[pose] needs a topic, or from_tf = true".into());
        }
        Ok(())
    }
}

impl MissionConfig {
    /// Checks the robot given here (or that a scenario gives it), for `clouds` cloud topics.
    fn validate(&self, clouds: usize) -> Result<(), LogError> {
        let bad = |m: String| Err(LogError::Config(m));
        if self.scenario.is_some() {
            if !self.gaits.is_empty()
                || !self.sensor_hfov_deg.is_empty()
                || self.map.is_some()
                || self.bounds.is_some()
            {
                return bad(
                    "[mission]: give either a scenario or gaits/sensor_hfov_deg/map/bounds, not both"
                        .into(),
                );
            }
            return Ok(());
        }
        if self.gaits.is_empty() {
            return bad("[mission] needs a scenario or gaits".into());
        }
        self.validate_gaits()?;
        if self.sensor_hfov_deg.len() != clouds {
            return bad(format!(
                "[mission] sensor_hfov_deg has {} entries for {clouds} [[clouds]] topics: give \
                 each cloud topic's horizontal field of view, in their order (360 for an \
                 omnidirectional sensor)",
                self.sensor_hfov_deg.len()
            ));
        }
        for (k, &f) in self.sensor_hfov_deg.iter().enumerate() {
            if !(f > 0.0 && f <= 360.0) {
                return bad(format!(
                    "[mission] sensor_hfov_deg[{k}] = {f}: must be a finite number > 0° and ≤ 360°"
                ));
            }
        }
        if let Some([lo, hi]) = self.bounds {
            let finite = lo.iter().chain(&hi).all(|v| v.is_finite());
            if !finite || lo[0] >= hi[0] || lo[1] >= hi[1] {
                return bad(format!(
                    "[mission] bounds = [{lo:?}, {hi:?}]: must be [[min x, min y], [max x, max y]] \
                     of finite numbers in m with min < max"
                ));
            }
        }
        if let Some(map) = &self.map {
            map.validate()
                .map_err(|e| LogError::Config(format!("[mission.map] {e}")))?;
        }
        Ok(())
    }

    /// Checks the gaits: named, each once, with a positive speed, at most 255 (a gait message
    /// carries the index as a byte).
    fn validate_gaits(&self) -> Result<(), LogError> {
        let bad = |m: String| Err(LogError::Config(m));
        if self.gaits.len() > u8::MAX as usize {
            return bad(format!("[mission] {} gaits: at most 255", self.gaits.len()));
        }
        for (k, g) in self.gaits.iter().enumerate() {
            if g.name.is_empty() {
                return bad(format!("[mission] gait {k} has no name"));
            }
            if self.gaits[..k].iter().any(|h| h.name == g.name) {
                return bad(format!("[mission] gait {:?} is given twice", g.name));
            }
            if !(g.v_max > 0.0 && g.v_max <= MAX_GAIT_SPEED) {
                return bad(format!(
                    "[mission] gait {:?} v_max = {}: must be a finite number > 0 m/s and ≤ \
                     {MAX_GAIT_SPEED} m/s",
                    g.name, g.v_max
                ));
            }
        }
        Ok(())
    }
}

/// A TOML error as one line: where in `text`, and what.
fn toml_error(text: &str, e: &toml::de::Error) -> LogError {
    let at = e.span().map(|span| {
        let before = text.get(..span.start).unwrap_or(text);
        let line = before.matches('\n').count() + 1;
        let line_start = before.rfind('\n').map_or(0, |k| k + 1);
        let column = before[line_start..].chars().count() + 1;
        format!("line {line}, column {column}: ")
    });
    LogError::Config(format!("{}{}", at.unwrap_or_default(), plain(e.message())))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn minimal_config_has_the_recorders_defaults() {
        let c = ReplayConfig::parse("[mission]\nscenario = \"courtyard-small\"\n").unwrap();
        assert_eq!(c.pose.topic, "/robot/odom");
        assert_eq!(c.clouds[0].topic, "/robot/sensor_0/points");
        assert_eq!(c.clouds[0].origin_frame.as_deref(), Some("sensor_0"));
        assert_eq!(c.gait.topic, "/robot/gait");
        assert_eq!(c.motion_topic, "/robot/motion");
        assert!(c.keyframes);
    }

    #[test]
    fn explicit_robot_parses() {
        let c = ReplayConfig::parse(
            r#"
            world_frame = "odom"
            [pose]
            from_tf = true
            [[clouds]]
            topic = "/camera/points"
            missing_rgb = "gray"
            [gait]
            topic = ""
            default = "walk"
            [mission]
            gaits = [{ name = "walk", v_max = 0.3 }]
            sensor_hfov_deg = [87.0]
            bounds = [[-1.0, -1.0], [1.0, 1.0]]
            [mission.map]
            cell_size = 0.1
            [mission.parameters]
            delta_t = 4.0
            "#,
        )
        .unwrap();
        assert!(c.pose.from_tf);
        assert_eq!(c.clouds[0].missing_rgb, MissingRgb::Gray);
        assert_eq!(c.mission.map.as_ref().unwrap().cell_size, 0.1);
        assert_eq!(c.mission.parameters["delta_t"].as_float(), Some(4.0));
    }

    #[test]
    fn bad_configs_are_refused() {
        for (text, needle) in [
            ("", "mission"),
            ("[mission]\n", "scenario or gaits"),
            (
                "clouds = []\n[mission]\nscenario = \"x\"\n",
                "no [[clouds]]",
            ),
            ("bogus = 1\n[mission]\nscenario = \"x\"\n", "bogus"),
            (
                "[mission]\nscenario = \"x\"\ngaits = [{ name = \"a\", v_max = 1.0 }]\n",
                "either",
            ),
        ] {
            let e = ReplayConfig::parse(text).unwrap_err().to_string();
            assert!(e.contains(needle), "{text:?}: {e}");
        }
    }

    /// A configuration with its own robot: one gait, one cloud topic, `extra` in [mission].
    fn robot(extra: &str) -> String {
        format!(
            "[mission]\ngaits = [{{ name = \"walk\", v_max = 0.3 }}]\nsensor_hfov_deg = [87.0]\n{extra}"
        )
    }

    #[test]
    fn every_numeric_key_is_checked_with_one_line() {
        assert!(ReplayConfig::parse(&robot("")).is_ok());
        let two_clouds = "[[clouds]]\ntopic = \"/a\"\n[[clouds]]\ntopic = \"/b\"\n";
        for (text, needle) in [
            (
                robot("").replace("[87.0]", "[87.0, 90.0]"),
                "sensor_hfov_deg has 2 entries for 1 [[clouds]] topics",
            ),
            (
                format!("{two_clouds}{}", robot("")),
                "sensor_hfov_deg has 1 entries for 2 [[clouds]] topics",
            ),
            (robot("").replace("[87.0]", "[]"), "has 0 entries"),
            (
                robot("").replace("[87.0]", "[nan]"),
                "sensor_hfov_deg[0] = NaN: must be a finite number > 0° and ≤ 360°",
            ),
            (
                robot("").replace("[87.0]", "[0.0]"),
                "sensor_hfov_deg[0] = 0",
            ),
            (
                robot("").replace("[87.0]", "[400.0]"),
                "sensor_hfov_deg[0] = 400",
            ),
            (
                robot("").replace("[87.0]", "[-inf]"),
                "sensor_hfov_deg[0] = -inf",
            ),
            (
                robot("bounds = [[1.0, -1.0], [-1.0, 1.0]]"),
                "bounds = [[1.0, -1.0], [-1.0, 1.0]]: must be",
            ),
            (
                robot("bounds = [[nan, -1.0], [1.0, 1.0]]"),
                "bounds = [[NaN",
            ),
            (robot("bounds = [[0.0, 0.0], [0.0, 1.0]]"), "min < max"),
            (
                robot("").replace("v_max = 0.3", "v_max = -0.3"),
                "gait \"walk\" v_max = -0.3: must be a finite number > 0 m/s",
            ),
            (
                robot("").replace("v_max = 0.3", "v_max = nan"),
                "v_max = NaN",
            ),
            (robot("").replace("v_max = 0.3", "v_max = 1e9"), "≤ 100 m/s"),
            (robot("").replace("\"walk\"", "\"\""), "gait 0 has no name"),
            (
                robot("").replace(
                    "{ name = \"walk\", v_max = 0.3 }",
                    "{ name = \"a\", v_max = 0.3 }, { name = \"a\", v_max = 0.1 }",
                ),
                "given twice",
            ),
            (
                format!("reorder_window_s = -1.0\n{}", robot("")),
                "reorder_window_s = -1: must be a finite number ≥ 0 s and ≤ 600 s",
            ),
            (format!("reorder_window_s = nan\n{}", robot("")), "= NaN"),
            (format!("reorder_window_s = 1e9\n{}", robot("")), "≤ 600 s"),
            (
                format!("[tf]\ntolerance_s = inf\n{}", robot("")),
                "[tf] tolerance_s = inf",
            ),
            (
                format!("world_frame = \"\"\n{}", robot("")),
                "world_frame is empty",
            ),
            (
                format!("[[clouds]]\ntopic = \"\"\n{}", robot("")),
                "the topic is empty",
            ),
            (
                format!("[pose]\nfrom_tf = true\nbase_frame = \"\"\n{}", robot("")),
                "base_frame",
            ),
            (
                format!("reorder_window_s = \"x\"\n{}", robot("")),
                "line 1, column 20: invalid type",
            ),
        ] {
            let e = ReplayConfig::parse(&text).unwrap_err().to_string();
            assert!(e.contains(needle), "{text:?}: {e}");
            assert!(e.starts_with("replay config: ") && !e.contains('\n'), "{e}");
        }
    }

    #[test]
    fn toml_errors_name_the_line_and_column() {
        let e = ReplayConfig::parse("[mission]\nscenario = \"x\"\nbogus = 1\n")
            .unwrap_err()
            .to_string();
        assert!(
            e.starts_with("replay config: line 3, column 1: unknown field `bogus`"),
            "{e}"
        );
        // Not TOML at all, and a multi-byte character before the error.
        for text in ["\u{feff}ä = [", "\u{0}", "[[[", "é"] {
            let e = ReplayConfig::parse(text).unwrap_err().to_string();
            assert!(e.contains("line 1") && !e.contains('\n'), "{e}");
        }
    }
}
