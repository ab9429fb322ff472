//! Recording a mission to MCAP or the live view ([`crate::sink`]): the robot's sensor stream as
//! ROS 2 messages (so the file can be replayed, [`crate::replay`]) and the mission's state with
//! Foxglove's schemas (so a user can scrub through it, or watch it, in Foxglove).
//!
//! The robot side is captured by [`Recording`], a [`Robot`] adaptor that forwards everything
//! to the wrapped robot and tees the sensor stream, the gait commands, the commanded paths and
//! the motion state per control tick into the [`Recorder`]; the mission side by
//! [`Recorder::snapshot`] of the mission's [`Snapshot`], taken by the mission's observer.
//! Neither changes what the mission does.
//!
//! Topics (defaults of [`Topics`]; frames `map` (world) and `base_link`, `sensor_<i>`):
//!
//! | topic | schema | rate |
//! |---|---|---|
//! | `/robot/odom` | `nav_msgs/msg/Odometry` | every pose (20 Hz) |
//! | `/robot/sensor_<i>/points` | `sensor_msgs/msg/PointCloud2` (x, y, z, rgb; frame `map`) | every fused scan |
//! | `/tf` | `tf2_msgs/msg/TFMessage` (`map` → `sensor_<i>`, the scan origin) | every fused scan |
//! | `/robot/gait` | `std_msgs/msg/String` (the gait's name) | on change |
//! | `/robot/motion` | `std_msgs/msg/UInt8` (bit 0 idle, bit 1 blocked) | every control tick |
//! | `/strider/robot` | `foxglove.FrameTransform` (`map` → `base_link`) | every pose |
//! | `/strider/map` | `foxglove.Grid`: elevation, colour, passability, per gait cost, variance, measured cost | every `grid_period_s` |
//! | `/strider/experienced_costs` | `foxglove.PointCloud` (measured cells: x, y, z, cost, gait) | every `grid_period_s` |
//! | `/strider/goals` | `foxglove.SceneUpdate` (spatial goals, cost goals per gait) | 1 Hz |
//! | `/strider/tour` | `foxglove.PosesInFrame` (the tour's sites in visiting order) | 1 Hz |
//! | `/strider/path` | `foxglove.PosesInFrame` (the commanded path) | each command |
//!
//! Sensor scans are written once, as ROS 2 PointCloud2 in the world frame: that is what a
//! robot records and what replay reads, and Foxglove displays it natively; writing them again
//! as `foxglove.PointCloud` would double the largest part of the file for the same picture.
//! `foxglove.PointCloud` carries the experienced costs instead.

use crate::error::LogError;
use crate::ros2::{
    self, Header, MsgType, Odometry, Quaternion, StringMsg, TfMessage, Time, Transform,
    TransformStamped, UInt8Msg, Vector3, seconds_to_nanos,
};
use crate::sink::{MessageSink, WriteSummary, Writer};
use crate::writer::McapFile;
use foxglove::bytes::Bytes;
use foxglove::messages as fg;
use std::cell::RefCell;
use std::collections::BTreeMap;
use std::path::Path;
use std::rc::Rc;
use strider_core::interface::{MotionState, Robot, SensorSink};
use strider_core::snapshot::{GoalKind, Layers, MeasuredCost, Snapshot};
use strider_core::{GaitId, Point2, PointCloud, PoseStamped};

/// Topic and frame names of a recording.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Topics {
    /// The fixed world frame.
    pub world_frame: String,
    /// The robot body frame.
    pub base_frame: String,
    /// nav_msgs/Odometry of the body.
    pub odometry: String,
    /// PointCloud2 of sensor `i`: this with `{i}` replaced.
    pub cloud_pattern: String,
    /// Sensor frame `i`: this with `{i}` replaced.
    pub sensor_frame_pattern: String,
    /// tf2_msgs/TFMessage.
    pub tf: String,
    /// std_msgs/String, the gait's name.
    pub gait: String,
    /// std_msgs/UInt8, the motion state per control tick.
    pub motion: String,
}

impl Default for Topics {
    fn default() -> Self {
        Self {
            world_frame: "map".into(),
            base_frame: "base_link".into(),
            odometry: "/robot/odom".into(),
            cloud_pattern: "/robot/sensor_{i}/points".into(),
            sensor_frame_pattern: "sensor_{i}".into(),
            tf: "/tf".into(),
            gait: "/robot/gait".into(),
            motion: "/robot/motion".into(),
        }
    }
}

impl Topics {
    /// The cloud topic of sensor `i`.
    pub fn cloud(&self, i: u8) -> String {
        self.cloud_pattern.replace("{i}", &i.to_string())
    }

    /// The frame of sensor `i`.
    pub fn sensor_frame(&self, i: u8) -> String {
        self.sensor_frame_pattern.replace("{i}", &i.to_string())
    }
}

pub use crate::ros2::motion_bits;

/// What to record.
#[derive(Clone, Debug)]
pub struct RecorderOptions {
    /// Topic and frame names.
    pub topics: Topics,
    /// Gait names by index (the gait topic carries names).
    pub gait_names: Vec<String>,
    /// Period of the map grid and experienced-cost snapshots, s of robot time.
    pub grid_period_s: f64,
    /// Write the ROS 2 sensor stream (needed for replay).
    pub sensor_stream: bool,
    /// Write the Foxglove visualisation topics.
    pub visualisation: bool,
}

impl RecorderOptions {
    /// Everything, grid every 5 s.
    pub fn new(gait_names: Vec<String>) -> Self {
        Self {
            topics: Topics::default(),
            gait_names,
            grid_period_s: 5.0,
            sensor_stream: true,
            visualisation: true,
        }
    }
}

/// Writes a mission to a [`MessageSink`]: an MCAP file, the live view or both (see
/// [`crate::sink`]). Methods never fail: the first write error is kept and reported by
/// [`Recorder::take_error`] (which [`Recording::advance`] calls every tick) and
/// [`Recorder::finish`].
pub struct Recorder {
    w: Writer<Box<dyn MessageSink>>,
    opts: RecorderOptions,
    /// Robot time of the latest control tick, s.
    now: f64,
    last_grid: Option<f64>,
    /// Latest body orientation (the sensor frames' orientation).
    last_pose: Option<PoseStamped>,
    error: Option<LogError>,
}

fn stamp(t: f64) -> (i64, Time) {
    let ns = seconds_to_nanos(t);
    (ns, Time::from_nanos(ns))
}

fn fg_time(ns: i64) -> fg::Timestamp {
    let ns = ns.max(0);
    let sec = (ns / 1_000_000_000).min(u32::MAX as i64) as u32;
    fg::Timestamp::new(sec, (ns % 1_000_000_000) as u32)
}

fn fg_pose(x: f64, y: f64, z: f64, q: Quaternion) -> fg::Pose {
    fg::Pose {
        position: Some(fg::Vector3 { x, y, z }),
        orientation: Some(fg::Quaternion {
            x: q.x,
            y: q.y,
            z: q.z,
            w: q.w,
        }),
    }
}

/// A distinct colour per gait (and white for spatial goals).
fn gait_color(g: usize, a: f64) -> fg::Color {
    const C: [[f64; 3]; 6] = [
        [0.12, 0.47, 0.71],
        [1.0, 0.5, 0.05],
        [0.17, 0.63, 0.17],
        [0.84, 0.15, 0.16],
        [0.58, 0.4, 0.74],
        [0.55, 0.34, 0.29],
    ];
    let c = C[g % C.len()];
    fg::Color {
        r: c[0],
        g: c[1],
        b: c[2],
        a,
    }
}

fn field(
    name: &str,
    offset: u32,
    t: fg::packed_element_field::NumericType,
) -> fg::PackedElementField {
    fg::PackedElementField {
        name: name.into(),
        offset,
        r#type: t as i32,
    }
}

impl Recorder {
    /// Creates the MCAP file `path` and writes the recording's metadata.
    pub fn create(path: &Path, opts: RecorderOptions) -> Result<Self, LogError> {
        Self::new(Box::new(McapFile::create(path)?), opts)
    }

    /// Records into `sink` (e.g. a [`crate::sink::Fanout`] of an MCAP file and the live view),
    /// starting with the recording's metadata.
    pub fn new(sink: Box<dyn MessageSink>, opts: RecorderOptions) -> Result<Self, LogError> {
        let mut w = Writer::new(sink);
        let mut kv = BTreeMap::new();
        kv.insert("gaits".into(), opts.gait_names.join(","));
        kv.insert("world_frame".into(), opts.topics.world_frame.clone());
        kv.insert("base_frame".into(), opts.topics.base_frame.clone());
        w.metadata("strider", kv)?;
        Ok(Self {
            w,
            opts,
            now: 0.0,
            last_grid: None,
            last_pose: None,
            error: None,
        })
    }

    fn keep(&mut self, r: Result<(), LogError>) {
        if let Err(e) = r
            && self.error.is_none()
        {
            self.error = Some(e);
        }
    }

    /// The first write error so far, if any.
    pub fn take_error(&mut self) -> Result<(), LogError> {
        self.error.take().map_or(Ok(()), Err)
    }

    /// Records a pose: Odometry (ROS 2) and the body frame (Foxglove).
    pub fn pose(&mut self, p: &PoseStamped) {
        self.last_pose = Some(*p);
        let (ns, t) = stamp(p.stamp);
        let q = Quaternion::from_rpy(p.roll, p.pitch, p.yaw);
        let mut r = Ok(());
        if self.opts.sensor_stream {
            let mut odom = Odometry {
                header: Header {
                    stamp: t,
                    frame_id: self.opts.topics.world_frame.as_str().into(),
                },
                child_frame_id: self.opts.topics.base_frame.as_str().into(),
                ..Default::default()
            };
            odom.pose.pose.position = Vector3 {
                x: p.position.x,
                y: p.position.y,
                z: p.position.z,
            };
            odom.pose.pose.orientation = q;
            r = self.w.write_ros2(
                &self.opts.topics.odometry.clone(),
                MsgType::Odometry,
                ns,
                &odom,
            );
        }
        if r.is_ok() && self.opts.visualisation {
            let ft = fg::FrameTransform {
                timestamp: Some(fg_time(ns)),
                parent_frame_id: self.opts.topics.world_frame.clone(),
                child_frame_id: self.opts.topics.base_frame.clone(),
                translation: Some(fg::Vector3 {
                    x: p.position.x,
                    y: p.position.y,
                    z: p.position.z,
                }),
                rotation: Some(fg::Quaternion {
                    x: q.x,
                    y: q.y,
                    z: q.z,
                    w: q.w,
                }),
            };
            r = self.w.write_foxglove("/strider/robot", ns, &ft);
        }
        self.keep(r);
    }

    /// Records a scan: the PointCloud2 (world frame) and the sensor frame's origin on /tf.
    pub fn cloud(&mut self, c: &PointCloud) {
        if !self.opts.sensor_stream {
            return;
        }
        let (ns, t) = stamp(c.stamp);
        let topics = &self.opts.topics;
        let frame = topics.sensor_frame(c.sensor);
        let rotation = self.last_pose.map_or(Quaternion::IDENTITY, |p| {
            Quaternion::from_rpy(0.0, 0.0, p.yaw)
        });
        let tf = TfMessage {
            transforms: vec![TransformStamped {
                header: Header {
                    stamp: t,
                    frame_id: topics.world_frame.as_str().into(),
                },
                child_frame_id: frame.as_str().into(),
                transform: Transform {
                    translation: Vector3 {
                        x: c.origin.x,
                        y: c.origin.y,
                        z: c.origin.z,
                    },
                    rotation,
                },
            }],
        };
        let cloud_topic = topics.cloud(c.sensor);
        let world = topics.world_frame.clone();
        let tf_topic = topics.tf.clone();
        let r = self
            .w
            .write_ros2(&tf_topic, MsgType::TfMessage, ns, &tf)
            .and_then(|()| {
                let bytes = ros2::encode_cloud(t, &world, &c.points).map_err(|source| {
                    LogError::Decode {
                        topic: cloud_topic.clone(),
                        index: 0,
                        source,
                    }
                })?;
                self.w
                    .write_cdr(&cloud_topic, MsgType::PointCloud2, ns, &bytes)
            });
        self.keep(r);
    }

    /// Records the gait selected at robot time `t`.
    pub fn gait(&mut self, t: f64, g: GaitId) {
        if !self.opts.sensor_stream {
            return;
        }
        let name = self
            .opts
            .gait_names
            .get(g.0 as usize)
            .cloned()
            .unwrap_or_else(|| g.0.to_string());
        let topic = self.opts.topics.gait.clone();
        let r = self.w.write_ros2(
            &topic,
            MsgType::String,
            seconds_to_nanos(t),
            &StringMsg {
                data: name.as_str().into(),
            },
        );
        self.keep(r);
    }

    /// Records the motion state at the end of a control tick ending at `t`.
    pub fn motion(&mut self, t: f64, s: MotionState) {
        self.now = t;
        if !self.opts.sensor_stream {
            return;
        }
        let bits = if s.idle { motion_bits::IDLE } else { 0 }
            | if s.blocked { motion_bits::BLOCKED } else { 0 };
        let topic = self.opts.topics.motion.clone();
        let r = self.w.write_ros2(
            &topic,
            MsgType::UInt8,
            seconds_to_nanos(t),
            &UInt8Msg { data: bits },
        );
        self.keep(r);
    }

    /// Records a commanded path at robot time `t`.
    pub fn path(&mut self, t: f64, path: &[Point2]) {
        if !self.opts.visualisation {
            return;
        }
        let z = self.last_pose.map_or(0.0, |p| p.position.z);
        let ns = seconds_to_nanos(t);
        let msg = fg::PosesInFrame {
            timestamp: Some(fg_time(ns)),
            frame_id: self.opts.topics.world_frame.clone(),
            poses: path
                .iter()
                .map(|p| fg_pose(p.x, p.y, z, Quaternion::IDENTITY))
                .collect(),
        };
        let r = self.w.write_foxglove("/strider/path", ns, &msg);
        self.keep(r);
    }

    /// True when the map grid and the experienced costs are due (`grid_period_s` of robot
    /// time since the last ones): ask the mission for a snapshot with layers then.
    pub fn grid_due(&self) -> bool {
        self.opts.visualisation
            && self
                .last_grid
                .is_none_or(|t| self.now - t >= self.opts.grid_period_s)
    }

    /// Records a mission's state: goals and tour always, the map grid and the experienced
    /// costs when the snapshot has layers.
    pub fn snapshot(&mut self, s: &Snapshot) {
        if !self.opts.visualisation {
            return;
        }
        let ns = seconds_to_nanos(s.time_s);
        let r = self.goals(s, ns);
        self.keep(r);
        if let Some(layers) = &s.layers {
            self.last_grid = Some(self.now);
            let r = self
                .grid(layers, s.cell_size, ns)
                .and_then(|()| self.costs(&s.measured, ns));
            self.keep(r);
        }
    }

    fn goals(&mut self, s: &Snapshot, ns: i64) -> Result<(), LogError> {
        let world = self.opts.topics.world_frame.clone();
        let d = s.cell_size;
        let white = fg::Color {
            r: 1.0,
            g: 1.0,
            b: 1.0,
            a: 0.9,
        };
        let entities = s
            .goals
            .iter()
            .map(|set| {
                let (color, r) = match set.kind {
                    GoalKind::Spatial => (white, 2.0 * d),
                    GoalKind::Cost { model } => (gait_color(model, 0.9), 1.5 * d),
                };
                fg::SceneEntity {
                    timestamp: Some(fg_time(ns)),
                    frame_id: world.clone(),
                    id: set.name.clone(),
                    spheres: set
                        .sites
                        .iter()
                        .map(|p| fg::SpherePrimitive {
                            pose: Some(fg_pose(p.x, p.y, p.z + r, Quaternion::IDENTITY)),
                            size: Some(fg::Vector3 {
                                x: 2.0 * r,
                                y: 2.0 * r,
                                z: 2.0 * r,
                            }),
                            color: Some(color),
                        })
                        .collect(),
                    ..Default::default()
                }
            })
            .collect();
        self.w.write_foxglove(
            "/strider/goals",
            ns,
            &fg::SceneUpdate {
                deletions: Vec::new(),
                entities,
            },
        )?;
        let tour = fg::PosesInFrame {
            timestamp: Some(fg_time(ns)),
            frame_id: world,
            poses: s
                .tour
                .iter()
                .map(|p| fg_pose(p.x, p.y, p.z, Quaternion::IDENTITY))
                .collect(),
        };
        self.w.write_foxglove("/strider/tour", ns, &tour)
    }

    fn grid(&mut self, layers: &Layers, d: f64, ns: i64) -> Result<(), LogError> {
        use fg::packed_element_field::NumericType as N;
        let rect = layers.rect;
        if rect.is_empty() {
            return Ok(()); // nothing mapped yet
        }
        let models = &layers.models;
        let nm = models.len();
        // f32 layers first (4-byte aligned), then the bytes.
        let mut fields = vec![
            field("elevation", 0, N::Float32),
            field("elevation_variance", 4, N::Float32),
        ];
        for (g, m) in models.iter().enumerate() {
            let o = 8 + 12 * g as u32;
            fields.push(field(&format!("cost_{}", m.name), o, N::Float32));
            fields.push(field(&format!("variance_{}", m.name), o + 4, N::Float32));
            fields.push(field(&format!("measured_{}", m.name), o + 8, N::Float32));
        }
        let b = 8 + 12 * nm as u32;
        for (k, n) in ["red", "green", "blue", "alpha", "passability"]
            .iter()
            .enumerate()
        {
            fields.push(field(n, b + k as u32, N::Uint8));
        }
        let stride = (b + 5).div_ceil(4) * 4;
        let mut data = Vec::with_capacity(rect.len() * stride as usize);
        for k in 0..rect.len() {
            let start = data.len();
            data.extend_from_slice(&layers.elevation[k].to_le_bytes());
            data.extend_from_slice(&layers.elevation_variance[k].to_le_bytes());
            for m in models {
                data.extend_from_slice(&m.cost[k].to_le_bytes());
                data.extend_from_slice(&m.variance[k].to_le_bytes());
                data.extend_from_slice(&m.measured[k].to_le_bytes());
            }
            data.extend_from_slice(&layers.color[k]);
            data.push(if layers.observed[k] { 255 } else { 0 });
            data.push(layers.passability[k]);
            data.resize(start + stride as usize, 0);
        }
        let msg = fg::Grid {
            timestamp: Some(fg_time(ns)),
            frame_id: self.opts.topics.world_frame.clone(),
            pose: Some(fg_pose(
                rect.min.i as f64 * d,
                rect.min.j as f64 * d,
                0.0,
                Quaternion::IDENTITY,
            )),
            column_count: rect.width,
            cell_size: Some(fg::Vector2 { x: d, y: d }),
            row_stride: stride * rect.width,
            cell_stride: stride,
            fields,
            data: Bytes::from(data),
        };
        self.w.write_foxglove("/strider/map", ns, &msg)
    }

    fn costs(&mut self, measured: &[MeasuredCost], ns: i64) -> Result<(), LogError> {
        use fg::packed_element_field::NumericType as N;
        let mut data = Vec::with_capacity(20 * measured.len());
        for m in measured {
            let p = m.at;
            for v in [
                p.x as f32,
                p.y as f32,
                p.z as f32,
                m.cost as f32,
                m.model as f32,
            ] {
                data.extend_from_slice(&v.to_le_bytes());
            }
        }
        let msg = fg::PointCloud {
            timestamp: Some(fg_time(ns)),
            frame_id: self.opts.topics.world_frame.clone(),
            pose: Some(fg_pose(0.0, 0.0, 0.0, Quaternion::IDENTITY)),
            point_stride: 20,
            fields: vec![
                field("x", 0, N::Float32),
                field("y", 4, N::Float32),
                field("z", 8, N::Float32),
                field("cost", 12, N::Float32),
                field("gait", 16, N::Float32),
            ],
            data: Bytes::from(data),
        };
        self.w
            .write_foxglove("/strider/experienced_costs", ns, &msg)
    }

    /// Ends the recording (an MCAP file is closed), returning what was written (or the first
    /// error of the recording).
    pub fn finish(mut self) -> Result<WriteSummary, LogError> {
        self.take_error()?;
        self.w.finish()
    }
}

/// A [`Robot`] adaptor that records the robot's sensor stream and the commands it receives.
pub struct Recording<R> {
    robot: R,
    rec: Rc<RefCell<Recorder>>,
}

/// An error of the robot or of the recording.
#[derive(Debug, thiserror::Error)]
pub enum RecordingError<E: std::error::Error + 'static> {
    /// The wrapped robot failed.
    #[error(transparent)]
    Robot(E),
    /// Writing the recording failed.
    #[error(transparent)]
    Log(#[from] LogError),
}

impl<R: Robot> Recording<R> {
    /// Wraps `robot`, recording into `rec` (shared with the mission observer that takes the
    /// snapshots).
    pub fn new(robot: R, rec: Rc<RefCell<Recorder>>) -> Self {
        Self { robot, rec }
    }

    /// The wrapped robot.
    pub fn inner(&self) -> &R {
        &self.robot
    }
}

/// Forwards to the mission's sink and to the recorder.
struct Tee<'a> {
    sink: &'a mut dyn SensorSink,
    rec: &'a mut Recorder,
}

impl SensorSink for Tee<'_> {
    fn on_pose(&mut self, pose: &PoseStamped) {
        self.sink.on_pose(pose);
        self.rec.pose(pose);
    }
    fn on_cloud(&mut self, cloud: &PointCloud) {
        self.sink.on_cloud(cloud);
        self.rec.cloud(cloud);
    }
    fn wants_cloud(&self, sensor: u8) -> bool {
        // Only the scans the mission wants are produced, fused and recorded.
        self.sink.wants_cloud(sensor)
    }
    fn on_proprioception(&mut self, p: &strider_core::Proprioception) {
        self.sink.on_proprioception(p);
    }
}

impl<R: Robot> Robot for Recording<R> {
    type Error = RecordingError<R::Error>;

    fn now(&self) -> f64 {
        self.robot.now()
    }

    fn follow(&mut self, path: &[Point2]) {
        self.robot.follow(path);
        let t = self.robot.now();
        self.rec.borrow_mut().path(t, path);
    }

    fn set_gait(&mut self, gait: GaitId) {
        self.robot.set_gait(gait);
        let t = self.robot.now();
        self.rec.borrow_mut().gait(t, gait);
    }

    fn advance(&mut self, dt: f64, sink: &mut dyn SensorSink) -> Result<MotionState, Self::Error> {
        let mut rec = self.rec.borrow_mut();
        let state = {
            let mut tee = Tee {
                sink,
                rec: &mut rec,
            };
            self.robot
                .advance(dt, &mut tee)
                .map_err(RecordingError::Robot)?
        };
        rec.motion(self.robot.now(), state);
        rec.take_error()?;
        Ok(state)
    }
}
