//! Replay of a recorded ROS 2 log behind the [`Robot`] interface, so the very same
//! mission kernel maps and learns from it (`strider_explore::Mission::ingest`).
//!
//! Opening a log reads it once ([`LogReplay::open`]): every message on a configured topic is
//! checked (encoding `cdr`, the expected schema) and the small ones are decoded — poses, gait,
//! motion state and transforms — so a truncated or corrupt file, a missing topic or an
//! undecodable message is reported before any work, with the topic, the message index and the
//! byte offset. The point clouds are then streamed in a second pass and decoded only when
//! delivered (and only when the mission wants the scan, see `keyframes`).
//!
//! Time is the log's own: robot time 0 is the earliest stamp of a pose, cloud, gait or motion
//! message, and [`Robot::advance`]`(dt)` delivers the messages stamped in (t, t + dt] (header
//! stamps; the log time for the header-less gait and motion messages) in stamp order, ties in
//! file order — the order they were recorded in. Stamps are compared in integer nanoseconds
//! with 1 ns of slack, the simulator's own tolerance, so a log recorded from the simulator
//! replays tick by tick. Commands (`follow`, `set_gait`) are ignored.
//!
//! * Poses come from `nav_msgs/Odometry` (chained to the world frame through /tf when its
//!   frame differs) or from /tf (`world_frame` → `base_frame`). A pose whose orientation is
//!   zero or not finite is skipped (counted in [`ReplayStats::bad_poses`]).
//! * The gait of a pose is the latest gait message before it; before the first one (or
//!   without a gait topic) the configured default, else the fastest gait.
//! * The motion state returned by `advance` is the latest motion message (bit 0 idle, bit 1
//!   blocked); without a motion topic the robot counts as driving throughout (cost samples
//!   are then also taken while it stands: trim such phases off the log).
//! * A cloud topic carries `sensor_msgs/PointCloud2` or `sensor_msgs/LaserScan` (read as the
//!   cloud of its valid ranges in the scan's frame, without colour; see `ros2::decode_scan`).
//!   A cloud is transformed from its frame into the world frame through /tf (a cloud already
//!   in the world frame is used bit for bit); its origin is the translation of `origin_frame`
//!   (default: its own frame). Transforms are interpolated between stamps and used up to
//!   `tolerance_s` outside them; a missing transform is an error.
//!
//! * Once read, the log is checked for plausibility ([`LogReplay::plausibility`]): speeds
//!   above the gaits' v_max, pose jumps, stamps going backwards, clouds without a pose near
//!   them. They are counted and warned about, not refused.
//!
//! The parts, in the order a replay uses them: `roles` (what each topic is for), `reader` (the
//! bounded MCAP reader), `index` (the checking pass), `tf` (the transform tree), `poses` (world
//! poses and their gaits), `plausibility` (the checks) and `clouds` (the streamed clouds).

mod clouds;
mod index;
mod plausibility;
mod poses;
mod reader;
mod roles;
mod tf;

pub use crate::limits::{MAX_RECORD_BYTES, MAX_SPAN_S};
pub use clouds::MAX_PENDING_CLOUD_BYTES;
pub use index::MAX_INDEXED;
pub use plausibility::{
    JUMP_MIN_M, JUMP_SPEED_FACTOR, Plausibility, SPEED_BASELINE_S, SPEED_MARGIN,
};

use crate::config::ReplayConfig;
use crate::error::{LogError, MessageAt};
use crate::ros2::{motion_bits, nanos_to_seconds, seconds_to_nanos};
use clouds::{CloudStream, PendingCloud, world_cloud};
use index::LogIndex;
use poses::{TimedPose, assign_gaits, default_gait, world_poses};
use reader::Source;
use roles::topic_roles;
use std::path::Path;
use std::sync::Arc;
use strider_core::GaitSpec;
use strider_core::interface::{MotionState, Robot, SensorSink};
use strider_core::{GaitId, Point2};
use tf::TfBuffer;

/// Counts of a replay.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct ReplayStats {
    /// Messages in the file (all topics).
    pub messages: usize,
    /// Poses in the log / delivered so far.
    pub poses: usize,
    /// Poses delivered so far.
    pub poses_delivered: usize,
    /// Poses skipped for an unusable orientation.
    pub bad_poses: usize,
    /// Clouds in the log.
    pub clouds: usize,
    /// Clouds delivered (decoded and fused).
    pub clouds_delivered: usize,
    /// Clouds the mission did not want (keyframe rule), not decoded.
    pub clouds_skipped: usize,
    /// Clouds without colour mapped gray.
    pub clouds_uncoloured: usize,
    /// Points delivered.
    pub points: usize,
}

/// A recorded log behind the [`Robot`] interface.
pub struct LogReplay {
    cfg: ReplayConfig,
    start_ns: i64,
    end_ns: i64,
    tf: TfBuffer,
    /// (stamp relative to the start, seq, pose), in that order.
    poses: Vec<TimedPose>,
    next_pose: usize,
    /// (log time relative to the start, seq, bits), in that order.
    motion: Vec<(i64, u64, u8)>,
    next_motion: usize,
    state: MotionState,
    clouds: CloudStream,
    /// The delivery limit of the previous `advance` (relative ns): a cloud stamped at or
    /// before it arrives too late.
    delivered_to: i64,
    now: f64,
    stats: ReplayStats,
    warnings: Vec<String>,
    plausibility: Plausibility,
}

impl LogReplay {
    /// Opens and checks a log (see the module docs); `gaits` are the robot's gaits (their names,
    /// and the fastest is the start gait unless the configuration names one).
    pub fn open(path: &Path, cfg: &ReplayConfig, gaits: &[GaitSpec]) -> Result<Self, LogError> {
        Self::open_source(Source::File(path.into()), cfg, gaits)
    }

    /// [`LogReplay::open`] of a log in memory; errors call it `name`. Any bytes give a replay
    /// or an error, never a panic; what they make the reader allocate is bounded by
    /// [`MAX_RECORD_BYTES`] a record, the clouds held by [`MAX_PENDING_CLOUD_BYTES`] and the
    /// index by [`MAX_INDEXED`].
    pub fn from_bytes(
        name: &str,
        bytes: impl Into<Arc<[u8]>>,
        cfg: &ReplayConfig,
        gaits: &[GaitSpec],
    ) -> Result<Self, LogError> {
        let src = Source::Bytes {
            name: name.into(),
            bytes: bytes.into(),
        };
        Self::open_source(src, cfg, gaits)
    }

    fn open_source(src: Source, cfg: &ReplayConfig, gaits: &[GaitSpec]) -> Result<Self, LogError> {
        let path = src.path();
        let roles = topic_roles(cfg)?;
        let gait = default_gait(cfg, gaits)?;
        let gait_names: Vec<&str> = gaits.iter().map(|g| g.name.as_str()).collect();
        // Pass 1: check everything, decode all but the clouds.
        let mut ix = LogIndex::read(&src, cfg, &roles, &gait_names)?;
        ix.require_topics(path, cfg)?;
        ix.tf.sort();
        let (start, end) = ix.span_ns()?;
        let mut stats = ReplayStats {
            messages: ix.messages as usize,
            clouds: ix.cloud_count.iter().sum(),
            ..Default::default()
        };
        let (mut poses, bad) = world_poses(&ix, cfg, start, gait)?;
        stats.bad_poses = bad;
        assign_gaits(&mut poses, &mut ix.gaits, start, gait);
        stats.poses = poses.len();
        let warnings = fallback_warnings(cfg, &ix, bad, gait_names.get(gait.0 as usize));
        let plausibility = check_plausibility(&mut ix, &poses, gaits, cfg, start);
        let mut motion = std::mem::take(&mut ix.motion);
        motion.sort_by_key(|m| (m.0, m.1));
        for m in &mut motion {
            m.0 = m.0.saturating_sub(start);
        }
        Ok(Self {
            cfg: cfg.clone(),
            start_ns: start,
            end_ns: end,
            tf: ix.tf,
            poses,
            next_pose: 0,
            motion,
            next_motion: 0,
            state: MotionState::default(),
            clouds: CloudStream::open(&src, cfg, roles, start)?,
            delivered_to: i64::MIN,
            now: 0.0,
            stats,
            warnings,
            plausibility,
        })
    }

    /// Length of the log, s (from the earliest to the latest stamp).
    pub fn duration_s(&self) -> f64 {
        nanos_to_seconds(self.end_ns.saturating_sub(self.start_ns))
    }

    /// The mission time limit that replays the whole log with control ticks of `dt`: the
    /// mission stops after the tick that reaches the last stamp.
    pub fn time_limit_s(&self, dt: f64) -> f64 {
        let n = (self.duration_s() / dt - 1e-6).ceil().max(1.0);
        (n - 0.5) * dt
    }

    /// Counts so far.
    pub fn stats(&self) -> &ReplayStats {
        &self.stats
    }

    /// Notes about fallbacks taken (no gait topic, no motion topic, skipped poses).
    pub fn warnings(&self) -> &[String] {
        &self.warnings
    }

    /// What the plausibility checks found in the log (its warnings: [`Plausibility::warnings`]).
    pub fn plausibility(&self) -> &Plausibility {
        &self.plausibility
    }

    /// Delivers the poses and the clouds stamped up to `limit` (relative ns) in stamp order,
    /// ties in file order.
    fn deliver(&mut self, limit: i64, sink: &mut dyn SensorSink) -> Result<(), LogError> {
        loop {
            let pose = self.poses.get(self.next_pose).filter(|p| p.0 <= limit);
            let cloud = self.clouds.peek(limit);
            let pose_first = match (pose, cloud) {
                (None, None) => break,
                (Some(p), Some(c)) => (p.0, p.1) < (c.ns, c.seq),
                (Some(_), None) => true,
                (None, Some(_)) => false,
            };
            if pose_first {
                let p = self.poses[self.next_pose].2;
                self.next_pose += 1;
                self.stats.poses_delivered += 1;
                sink.on_pose(&p);
            } else if let Some(c) = self.clouds.pop() {
                if c.ns <= self.delivered_to {
                    return Err(self.late(&c));
                }
                if self.cfg.keyframes && !sink.wants_cloud(c.sensor) {
                    self.stats.clouds_skipped += 1;
                    continue;
                }
                let cc = &self.cfg.clouds[c.sensor as usize];
                let (pc, uncoloured) = world_cloud(&c, cc, &self.cfg.world_frame, &self.tf)?;
                if uncoloured {
                    if self.stats.clouds_uncoloured == 0 {
                        self.warnings.push(format!(
                            "{}: clouds without colour are mapped gray (missing_rgb = \"gray\")",
                            cc.topic
                        ));
                    }
                    self.stats.clouds_uncoloured += 1;
                }
                self.stats.clouds_delivered += 1;
                self.stats.points += pc.points.len();
                sink.on_cloud(&pc);
            }
        }
        Ok(())
    }

    /// The error of cloud `c`, which comes after clouds stamped later than it were delivered.
    fn late(&self, c: &PendingCloud) -> LogError {
        let at = MessageAt {
            topic: &self.cfg.clouds[c.sensor as usize].topic,
            index: c.index,
        };
        at.content(format!(
            "stamped {:.3} s into the log, after clouds up to {:.3} s were delivered: the \
             clouds are more than reorder_window_s = {} s out of stamp order in the file \
             (raise reorder_window_s)",
            nanos_to_seconds(c.ns),
            nanos_to_seconds(self.delivered_to),
            self.cfg.reorder_window_s
        ))
    }

    /// The motion state of the latest motion message stamped up to `limit` (relative ns).
    fn follow_motion(&mut self, limit: i64) {
        while let Some(&(ns, _, bits)) = self.motion.get(self.next_motion) {
            if ns > limit {
                break;
            }
            self.state = MotionState {
                idle: bits & motion_bits::IDLE != 0,
                blocked: bits & motion_bits::BLOCKED != 0,
            };
            self.next_motion += 1;
        }
    }
}

/// The notes about the fallbacks a log makes the replay take: skipped poses, no gait messages
/// (every pose then has the default gait, `default_gait`), no motion-state messages.
fn fallback_warnings(
    cfg: &ReplayConfig,
    ix: &LogIndex,
    bad_poses: usize,
    default_gait: Option<&&str>,
) -> Vec<String> {
    let mut warnings = Vec::new();
    if bad_poses > 0 {
        warnings.push(format!(
            "{bad_poses} poses skipped: orientation zero or not finite"
        ));
    }
    if cfg.gait.topic.is_empty() || ix.gaits.is_empty() {
        warnings.push(format!(
            "no gait messages: every pose counts as gait {:?}",
            default_gait.unwrap_or(&"?")
        ));
    }
    if cfg.motion_topic.is_empty() || ix.motion.is_empty() {
        warnings.push(
            "no motion-state messages: the robot counts as driving throughout the log".into(),
        );
    }
    warnings
}

/// The plausibility checks of the log of `ix` with its world `poses` (relative to `start`) for
/// a robot with `gaits`.
fn check_plausibility(
    ix: &mut LogIndex,
    poses: &[TimedPose],
    gaits: &[GaitSpec],
    cfg: &ReplayConfig,
    start: i64,
) -> Plausibility {
    let mut p = Plausibility {
        backward_stamps: ix.order.backward,
        first_backward: ix.order.first.take(),
        ..Default::default()
    };
    p.check_poses(poses, gaits);
    let clouds: Vec<i64> = std::mem::take(&mut ix.cloud_ns)
        .into_iter()
        .map(|ns| ns.saturating_sub(start))
        .collect();
    p.check_clouds(&clouds, poses, seconds_to_nanos(cfg.tf.tolerance_s));
    p
}

impl Robot for LogReplay {
    type Error = LogError;

    fn now(&self) -> f64 {
        self.now
    }

    fn follow(&mut self, _path: &[Point2]) {}

    fn set_gait(&mut self, _gait: GaitId) {}

    fn advance(&mut self, dt: f64, sink: &mut dyn SensorSink) -> Result<MotionState, LogError> {
        if !(dt.is_finite() && dt >= 0.0) {
            return Err(LogError::Config(format!("advance by {dt} s")));
        }
        self.now += dt;
        let limit = seconds_to_nanos(self.now).saturating_add(1);
        self.clouds.fill(limit)?;
        self.deliver(limit, sink)?;
        self.delivered_to = self.delivered_to.max(limit);
        self.follow_motion(limit);
        Ok(self.state)
    }
}
