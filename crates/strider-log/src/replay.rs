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
//! * A cloud is transformed from its frame into the world frame through /tf (a cloud already
//!   in the world frame is used bit for bit); its origin is the translation of `origin_frame`
//!   (default: its own frame). Transforms are interpolated between stamps and used up to
//!   `tolerance_s` outside them; a missing transform is an error.

use crate::config::ReplayConfig;
use crate::error::LogError;
use crate::ros2::{
    self, DecodedCloud, HeaderPrefix, MsgType, Odometry, Quaternion, StringMsg, TfMessage,
    Transform, UInt8Msg,
};
use crate::{cdr, recorder::motion_bits};
use std::cell::Cell;
use std::cmp::Reverse;
use std::collections::{BTreeMap, BinaryHeap, HashMap};
use std::fs::File;
use std::io::{BufReader, Read};
use std::path::{Path, PathBuf};
use std::rc::Rc;
use strider_core::GaitSpec;
use strider_core::interface::{MotionState, Robot, SensorSink};
use strider_core::{GaitId, Point2, Point3, PointCloud, PoseStamped};

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

/// Counts the bytes read (shared with the owner of the reader, which keeps the source), to
/// say where a fault was found.
struct Counting<R> {
    inner: R,
    n: Rc<Cell<u64>>,
}

impl<R: Read> Read for Counting<R> {
    fn read(&mut self, buf: &mut [u8]) -> std::io::Result<usize> {
        let k = self.inner.read(buf)?;
        self.n.set(self.n.get() + k as u64);
        Ok(k)
    }
}

/// A message reader and its byte count.
struct Reader {
    r: mcap::io::MessageReader<Counting<BufReader<File>>>,
    n: Rc<Cell<u64>>,
}

fn open_reader(path: &Path) -> Result<Reader, LogError> {
    let f = File::open(path).map_err(|e| LogError::io(path, e))?;
    let n = Rc::new(Cell::new(0));
    // Bounded record and chunk sizes: a corrupted length must not make the reader allocate
    // what it announces; CRCs checked, so a corrupted chunk is reported as such.
    let options = mcap::sans_io::LinearReaderOptions::default()
        .with_record_length_limit(MAX_RECORD_BYTES)
        .with_validate_chunk_crcs(true)
        .with_validate_data_section_crc(true);
    Ok(Reader {
        r: mcap::io::MessageReader::new_with_options(
            Counting {
                inner: BufReader::with_capacity(1 << 20, f),
                n: n.clone(),
            },
            options,
        ),
        n,
    })
}

/// A rigid transform p' = q·p + t.
#[derive(Clone, Copy, Debug, PartialEq)]
struct Iso {
    q: Quaternion,
    t: [f64; 3],
}

impl Iso {
    const IDENTITY: Iso = Iso {
        q: Quaternion::IDENTITY,
        t: [0.0; 3],
    };

    fn from_msg(tr: &Transform) -> Option<Iso> {
        let v = tr.translation;
        (v.x.is_finite() && v.y.is_finite() && v.z.is_finite())
            .then_some(())
            .and(tr.rotation.normalized())
            .map(|q| Iso {
                q,
                t: [v.x, v.y, v.z],
            })
    }

    /// `self ∘ o`: first `o`, then `self`.
    fn compose(&self, o: &Iso) -> Iso {
        let r = self.q.rotate(o.t);
        Iso {
            q: self.q.product(o.q),
            t: [r[0] + self.t[0], r[1] + self.t[1], r[2] + self.t[2]],
        }
    }

    fn apply(&self, p: [f64; 3]) -> [f64; 3] {
        let r = self.q.rotate(p);
        [r[0] + self.t[0], r[1] + self.t[1], r[2] + self.t[2]]
    }

    /// Interpolation at fraction `a` from `self` to `o` (translation linear, rotation nlerp
    /// along the shorter arc: the stamps of a tf stream are close together).
    fn lerp(&self, o: &Iso, a: f64) -> Iso {
        let mut q2 = o.q;
        let dot = self.q.x * q2.x + self.q.y * q2.y + self.q.z * q2.z + self.q.w * q2.w;
        if dot < 0.0 {
            q2 = Quaternion {
                x: -q2.x,
                y: -q2.y,
                z: -q2.z,
                w: -q2.w,
            };
        }
        let l = |x: f64, y: f64| x + (y - x) * a;
        let q = Quaternion {
            x: l(self.q.x, q2.x),
            y: l(self.q.y, q2.y),
            z: l(self.q.z, q2.z),
            w: l(self.q.w, q2.w),
        }
        .normalized()
        .unwrap_or(self.q);
        Iso {
            q,
            t: [
                l(self.t[0], o.t[0]),
                l(self.t[1], o.t[1]),
                l(self.t[2], o.t[2]),
            ],
        }
    }
}

/// The transform tree over the whole log.
#[derive(Default)]
struct TfBuffer {
    /// child → (stamp ns, parent, child-in-parent), sorted by stamp.
    dynamic: HashMap<String, Vec<(i64, String, Iso)>>,
    /// child → (parent, child-in-parent).
    statics: HashMap<String, (String, Iso)>,
    tolerance_ns: i64,
}

impl TfBuffer {
    fn edge(&self, child: &str, t: i64) -> Result<(String, Iso), String> {
        if let Some((p, iso)) = self.statics.get(child) {
            return Ok((p.clone(), *iso));
        }
        let Some(v) = self.dynamic.get(child).filter(|v| !v.is_empty()) else {
            return Err(format!("no transform of frame {child:?}"));
        };
        let k = v.partition_point(|e| e.0 < t);
        if k < v.len() && v[k].0 == t {
            return Ok((v[k].1.clone(), v[k].2));
        }
        let secs = |ns: i64| ns as f64 * 1e-9;
        if k == 0 {
            return if v[0].0 - t <= self.tolerance_ns {
                Ok((v[0].1.clone(), v[0].2))
            } else {
                Err(format!(
                    "frame {child:?} has no transform before {:.3} s (first at {:.3} s)",
                    secs(t),
                    secs(v[0].0)
                ))
            };
        }
        if k == v.len() {
            let last = &v[k - 1];
            return if t - last.0 <= self.tolerance_ns {
                Ok((last.1.clone(), last.2))
            } else {
                Err(format!(
                    "frame {child:?} has no transform after {:.3} s (last at {:.3} s)",
                    secs(t),
                    secs(last.0)
                ))
            };
        }
        let (a, b) = (&v[k - 1], &v[k]);
        if a.1 != b.1 {
            // The parent changed between the two stamps: no interpolation across trees.
            return Ok((a.1.clone(), a.2));
        }
        let f = (t - a.0) as f64 / (b.0 - a.0) as f64;
        Ok((a.1.clone(), a.2.lerp(&b.2, f)))
    }

    /// `frame` expressed in `world` at `t`: the chain of parents up to `world`.
    fn lookup(&self, frame: &str, world: &str, t: i64) -> Result<Iso, String> {
        let mut total = Iso::IDENTITY;
        let mut f = frame.to_string();
        let mut first = true;
        for _ in 0..64 {
            if f == world {
                return Ok(total);
            }
            let (parent, e) = self.edge(&f, t)?;
            total = if first { e } else { e.compose(&total) };
            first = false;
            f = parent;
        }
        Err(format!(
            "frame {frame:?}: no chain to {world:?} within 64 transforms"
        ))
    }
}

/// A pose before its gait is known.
struct RawPose {
    ns: i64,
    seq: u64,
    pose: PoseStamped,
}

/// A cloud message waiting for delivery.
struct PendingCloud {
    ns: i64,
    seq: u64,
    sensor: u8,
    index: usize,
    data: Vec<u8>,
}

impl PartialEq for PendingCloud {
    fn eq(&self, o: &Self) -> bool {
        (self.ns, self.seq) == (o.ns, o.seq)
    }
}
impl Eq for PendingCloud {}
impl PartialOrd for PendingCloud {
    fn partial_cmp(&self, o: &Self) -> Option<std::cmp::Ordering> {
        Some(self.cmp(o))
    }
}
impl Ord for PendingCloud {
    fn cmp(&self, o: &Self) -> std::cmp::Ordering {
        (self.ns, self.seq).cmp(&(o.ns, o.seq))
    }
}

/// What a topic is used for.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Role {
    Odometry,
    Tf,
    TfStatic,
    Gait,
    Motion,
    Cloud(u8),
}

/// A recorded log behind the [`Robot`] interface.
pub struct LogReplay {
    path: PathBuf,
    cfg: ReplayConfig,
    roles: HashMap<String, Role>,
    start_ns: i64,
    end_ns: i64,
    tf: TfBuffer,
    poses: Vec<(i64, u64, PoseStamped)>,
    next_pose: usize,
    motion: Vec<(i64, u64, u8)>,
    next_motion: usize,
    state: MotionState,
    reader: Option<Reader>,
    /// Messages read by the cloud pass.
    seq: u64,
    cloud_index: Vec<usize>,
    /// Stamp of the latest cloud read (relative ns).
    read_ns: i64,
    pending: BinaryHeap<Reverse<PendingCloud>>,
    now: f64,
    stats: ReplayStats,
    warnings: Vec<String>,
}

/// Largest record (and decompressed chunk) read, bytes: far above any sensor message, and a
/// bound on what a corrupted length field can make the reader allocate.
pub const MAX_RECORD_BYTES: usize = 256 << 20;

/// Longest log accepted, s: a longer span means a bogus stamp, which would make the replay
/// tick through years of nothing.
pub const MAX_SPAN_S: f64 = 7.0 * 86400.0;

fn secs(ns: i64) -> f64 {
    ns as f64 / 1e9
}

impl LogReplay {
    /// Opens and checks a log (see the module docs); `gaits` are the robot's gaits (their names,
    /// and the fastest is the start gait unless the configuration names one).
    pub fn open(path: &Path, cfg: &ReplayConfig, gaits: &[GaitSpec]) -> Result<Self, LogError> {
        let mut roles: HashMap<String, Role> = HashMap::new();
        let mut add = |topic: &str, role: Role| -> Result<(), LogError> {
            if topic.is_empty() {
                return Ok(());
            }
            if let Some(r) = roles.insert(topic.to_string(), role)
                && r != role
            {
                return Err(LogError::Config(format!(
                    "topic {topic} is configured twice ({r:?} and {role:?})"
                )));
            }
            Ok(())
        };
        if !cfg.pose.from_tf {
            add(&cfg.pose.topic, Role::Odometry)?;
        }
        add(&cfg.tf.topic, Role::Tf)?;
        add(&cfg.tf.static_topic, Role::TfStatic)?;
        add(&cfg.gait.topic, Role::Gait)?;
        add(&cfg.motion_topic, Role::Motion)?;
        for (i, c) in cfg.clouds.iter().enumerate() {
            add(&c.topic, Role::Cloud(i as u8))?;
        }
        let gait_names: Vec<&str> = gaits.iter().map(|g| g.name.as_str()).collect();
        let default_gait = match &cfg.gait.default {
            Some(name) => GaitId(gait_names.iter().position(|g| g == name).ok_or_else(|| {
                LogError::Config(format!(
                    "[gait] default {name:?} is not a gait of the robot ({})",
                    gait_names.join(", ")
                ))
            })? as u8),
            None => strider_core::snapshot::fastest_gait(gaits),
        };

        // Pass 1: check everything, decode all but the clouds.
        let mut reader = open_reader(path)?;
        let mut counts: BTreeMap<String, usize> = BTreeMap::new();
        let mut tf = TfBuffer {
            tolerance_ns: ros2::seconds_to_nanos(cfg.tf.tolerance_s),
            ..Default::default()
        };
        let mut odoms: Vec<(i64, u64, usize, String, Iso)> = Vec::new();
        let mut base_tf: Vec<(i64, u64)> = Vec::new();
        let mut gaits: Vec<(i64, u64, GaitId)> = Vec::new();
        let mut motion: Vec<(i64, u64, u8)> = Vec::new();
        let mut cloud_count = vec![0usize; cfg.clouds.len()];
        // The earliest and latest stamps with the topic and index that carried them.
        let mut lo: (i64, String, usize) = (i64::MAX, String::new(), 0);
        let mut hi: (i64, String, usize) = (i64::MIN, String::new(), 0);
        let mut seq: u64 = 0;
        let mut span = |ns: i64, topic: &str, index: usize| {
            if ns < lo.0 {
                lo = (ns, topic.to_string(), index);
            }
            if ns > hi.0 {
                hi = (ns, topic.to_string(), index);
            }
        };
        while let Some(m) = reader.r.next() {
            let m = m.map_err(|source| LogError::Mcap {
                path: path.into(),
                messages: seq as usize,
                offset: reader.n.get(),
                source,
            })?;
            seq += 1;
            let topic = &m.channel.topic;
            let index = {
                let c = counts.entry(topic.clone()).or_default();
                *c += 1;
                *c - 1
            };
            let Some(&role) = roles.get(topic) else {
                continue;
            };
            let schema = m.channel.schema.as_ref().map_or("", |s| s.name.as_str());
            check(topic, &m.channel.message_encoding, schema, role)?;
            let dec = |source| LogError::Decode {
                topic: topic.clone(),
                index,
                source,
            };
            let content = |reason: String| LogError::Content {
                topic: topic.clone(),
                index,
                reason,
            };
            let log_ns = i64::try_from(m.log_time).unwrap_or(i64::MAX);
            match role {
                Role::Odometry => {
                    let o: Odometry = cdr::decode(&m.data).map_err(dec)?;
                    let ns = o.header.stamp.nanos();
                    span(ns, topic, index);
                    let p = o.pose.pose;
                    let iso = Iso {
                        q: p.orientation.normalized().unwrap_or(Quaternion {
                            x: f64::NAN,
                            y: f64::NAN,
                            z: f64::NAN,
                            w: f64::NAN,
                        }),
                        t: [p.position.x, p.position.y, p.position.z],
                    };
                    odoms.push((ns, seq, index, o.header.frame_id.0, iso));
                }
                Role::Tf | Role::TfStatic => {
                    let msg: TfMessage = cdr::decode(&m.data).map_err(dec)?;
                    for ts in msg.transforms {
                        let Some(iso) = Iso::from_msg(&ts.transform) else {
                            return Err(content(format!(
                                "transform {} → {} is not finite or has a zero rotation",
                                ts.header.frame_id.0, ts.child_frame_id.0
                            )));
                        };
                        let child = ts.child_frame_id.0;
                        let parent = ts.header.frame_id.0;
                        if child == parent {
                            return Err(content(format!("frame {child:?} is its own parent")));
                        }
                        if role == Role::TfStatic {
                            tf.statics.insert(child, (parent, iso));
                        } else {
                            let ns = ts.header.stamp.nanos();
                            if cfg.pose.from_tf && child == cfg.pose.base_frame {
                                span(ns, topic, index);
                                base_tf.push((ns, seq));
                            }
                            tf.dynamic.entry(child).or_default().push((ns, parent, iso));
                        }
                    }
                }
                Role::Gait => {
                    let g =
                        if schema == MsgType::UInt8.name() {
                            let v: UInt8Msg = cdr::decode(&m.data).map_err(dec)?;
                            if (v.data as usize) >= gait_names.len() {
                                return Err(content(format!(
                                    "gait index {} but the robot has {} gaits",
                                    v.data,
                                    gait_names.len()
                                )));
                            }
                            GaitId(v.data)
                        } else {
                            let v: StringMsg = cdr::decode(&m.data).map_err(dec)?;
                            let k = gait_names.iter().position(|g| *g == v.data.0).ok_or_else(
                                || {
                                    content(format!(
                                        "unknown gait {:?} (the robot's gaits: {})",
                                        v.data.0,
                                        gait_names.join(", ")
                                    ))
                                },
                            )?;
                            GaitId(k as u8)
                        };
                    span(log_ns, topic, index);
                    gaits.push((log_ns, seq, g));
                }
                Role::Motion => {
                    let v: UInt8Msg = cdr::decode(&m.data).map_err(dec)?;
                    span(log_ns, topic, index);
                    motion.push((log_ns, seq, v.data));
                }
                Role::Cloud(i) => {
                    // Only the header now; the payload is checked when it is delivered.
                    let h: HeaderPrefix = cdr::decode(&m.data).map_err(dec)?;
                    span(h.header.stamp.nanos(), topic, index);
                    cloud_count[i as usize] += 1;
                }
            }
        }
        let available = || {
            if counts.is_empty() {
                "none".to_string()
            } else {
                counts.keys().cloned().collect::<Vec<_>>().join(", ")
            }
        };
        let missing = |topic: &str, what: &'static str| LogError::MissingTopic {
            path: path.into(),
            topic: topic.into(),
            what,
            available: available(),
        };
        for (c, n) in cfg.clouds.iter().zip(&cloud_count) {
            if *n == 0 {
                return Err(missing(&c.topic, "point clouds"));
            }
        }
        if cfg.pose.from_tf {
            if base_tf.is_empty() {
                return Err(missing(&cfg.tf.topic, "the pose from tf"));
            }
        } else if odoms.is_empty() {
            return Err(missing(&cfg.pose.topic, "the pose"));
        }
        for v in tf.dynamic.values_mut() {
            v.sort_by_key(|e| e.0);
        }
        let start = lo.0;
        let span_s = secs(hi.0.saturating_sub(lo.0));
        if span_s > MAX_SPAN_S {
            return Err(LogError::Content {
                topic: hi.1,
                index: hi.2,
                reason: format!(
                    "its stamp is {span_s:.0} s after the earliest one (topic {}, message {}): \
                     the stamps are inconsistent (more than {MAX_SPAN_S:.0} s apart)",
                    lo.1, lo.2
                ),
            });
        }
        let mut warnings = Vec::new();
        let mut stats = ReplayStats {
            messages: seq as usize,
            clouds: cloud_count.iter().sum(),
            ..Default::default()
        };

        // Poses in the world frame.
        let world = &cfg.world_frame;
        let mut raw: Vec<RawPose> = Vec::new();
        let mut bad = 0usize;
        let mut push = |ns: i64, seq: u64, iso: Iso, z: f64| {
            if !iso.q.w.is_finite() {
                bad += 1;
                return;
            }
            let (roll, pitch, yaw) = iso.q.to_rpy();
            raw.push(RawPose {
                ns: ns.saturating_sub(start),
                seq,
                pose: PoseStamped {
                    stamp: secs(ns.saturating_sub(start)),
                    position: Point3::new(iso.t[0], iso.t[1], z),
                    roll,
                    pitch,
                    yaw,
                    gait: default_gait,
                },
            });
        };
        if cfg.pose.from_tf {
            for &(ns, s) in &base_tf {
                let iso = tf
                    .lookup(&cfg.pose.base_frame, world, ns)
                    .map_err(|reason| LogError::Content {
                        topic: cfg.tf.topic.clone(),
                        index: 0,
                        reason,
                    })?;
                push(ns, s, iso, iso.t[2]);
            }
        } else {
            for (ns, s, index, frame, iso) in odoms {
                let iso = if frame == *world || !iso.q.w.is_finite() {
                    iso
                } else {
                    tf.lookup(&frame, world, ns)
                        .map_err(|reason| LogError::Content {
                            topic: cfg.pose.topic.clone(),
                            index,
                            reason,
                        })?
                        .compose(&iso)
                };
                push(ns, s, iso, iso.t[2]);
            }
        }
        stats.bad_poses = bad;
        if bad > 0 {
            warnings.push(format!(
                "{bad} poses skipped: orientation zero or not finite"
            ));
        }
        // The gait of each pose: the latest gait message before it in (stamp, file) order.
        raw.sort_by_key(|p| (p.ns, p.seq));
        gaits.sort_by_key(|g| (g.0, g.1));
        let mut k = 0;
        let mut gait = default_gait;
        let mut poses = Vec::with_capacity(raw.len());
        for mut p in raw {
            while k < gaits.len() && (gaits[k].0.saturating_sub(start), gaits[k].1) < (p.ns, p.seq)
            {
                gait = gaits[k].2;
                k += 1;
            }
            p.pose.gait = gait;
            poses.push((p.ns, p.seq, p.pose));
        }
        stats.poses = poses.len();
        if cfg.gait.topic.is_empty() || gaits.is_empty() {
            warnings.push(format!(
                "no gait messages: every pose counts as gait {:?}",
                gait_names.get(default_gait.0 as usize).unwrap_or(&"?")
            ));
        }
        if cfg.motion_topic.is_empty() || motion.is_empty() {
            warnings.push(
                "no motion-state messages: the robot counts as driving throughout the log".into(),
            );
        }
        motion.sort_by_key(|m| (m.0, m.1));
        for m in &mut motion {
            m.0 = m.0.saturating_sub(start);
        }
        Ok(Self {
            path: path.into(),
            cfg: cfg.clone(),
            roles,
            start_ns: start,
            end_ns: hi.0,
            tf,
            poses,
            next_pose: 0,
            motion,
            next_motion: 0,
            state: MotionState::default(),
            reader: Some(open_reader(path)?),
            seq: 0,
            cloud_index: vec![0; cfg.clouds.len()],
            read_ns: i64::MIN,
            pending: BinaryHeap::new(),
            now: 0.0,
            stats,
            warnings,
        })
    }

    /// Length of the log, s (from the earliest to the latest stamp).
    pub fn duration_s(&self) -> f64 {
        secs(self.end_ns.saturating_sub(self.start_ns))
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

    /// Reads cloud messages until one stamped after `limit` + the reorder window (or the end).
    fn fill(&mut self, limit: i64) -> Result<(), LogError> {
        let window = ros2::seconds_to_nanos(self.cfg.reorder_window_s);
        while self.read_ns <= limit.saturating_add(window) {
            let Some(reader) = self.reader.as_mut() else {
                return Ok(());
            };
            let Some(m) = reader.r.next() else {
                self.reader = None;
                return Ok(());
            };
            let m = m.map_err(|source| LogError::Mcap {
                path: self.path.clone(),
                messages: self.seq as usize,
                offset: reader.n.get(),
                source,
            })?;
            self.seq += 1;
            let Some(&Role::Cloud(i)) = self.roles.get(&m.channel.topic) else {
                continue;
            };
            let index = self.cloud_index[i as usize];
            self.cloud_index[i as usize] += 1;
            let h: HeaderPrefix = cdr::decode(&m.data).map_err(|source| LogError::Decode {
                topic: m.channel.topic.clone(),
                index,
                source,
            })?;
            let ns = h.header.stamp.nanos().saturating_sub(self.start_ns);
            self.read_ns = self.read_ns.max(ns);
            self.pending.push(Reverse(PendingCloud {
                ns,
                seq: self.seq,
                sensor: i,
                index,
                data: m.data.into_owned(),
            }));
        }
        Ok(())
    }

    /// Decodes a cloud into the world frame.
    fn cloud(&mut self, c: &PendingCloud) -> Result<PointCloud, LogError> {
        let cc = &self.cfg.clouds[c.sensor as usize];
        let topic = &cc.topic;
        let DecodedCloud {
            header,
            mut points,
            uncoloured,
        } = ros2::decode_cloud(&c.data, cc.missing_rgb).map_err(|source| LogError::Decode {
            topic: topic.clone(),
            index: c.index,
            source,
        })?;
        let content = |reason: String| LogError::Content {
            topic: topic.clone(),
            index: c.index,
            reason,
        };
        let world = &self.cfg.world_frame;
        let t = header.stamp.nanos();
        let frame = header.frame_id.0;
        if frame.is_empty() {
            return Err(content("the cloud has no frame_id".into()));
        }
        let origin_frame = cc.origin_frame.as_deref().unwrap_or(&frame);
        if origin_frame == world {
            return Err(content(format!(
                "the cloud is in the world frame {world:?}: set origin_frame to the sensor's frame"
            )));
        }
        let origin = self.tf.lookup(origin_frame, world, t).map_err(content)?;
        if frame != *world {
            let iso = self.tf.lookup(&frame, world, t).map_err(content)?;
            for p in &mut points {
                let q = iso.apply([p.x as f64, p.y as f64, p.z as f64]);
                (p.x, p.y, p.z) = (q[0] as f32, q[1] as f32, q[2] as f32);
            }
        }
        if uncoloured {
            if self.stats.clouds_uncoloured == 0 {
                self.warnings.push(format!(
                    "{topic}: clouds without colour are mapped gray (missing_rgb = \"gray\")"
                ));
            }
            self.stats.clouds_uncoloured += 1;
        }
        Ok(PointCloud {
            stamp: secs(c.ns),
            sensor: c.sensor,
            origin: Point3::new(origin.t[0], origin.t[1], origin.t[2]),
            points,
        })
    }
}

/// Checks a topic's encoding and schema against its role.
fn check(topic: &str, encoding: &str, schema: &str, role: Role) -> Result<(), LogError> {
    if encoding != "cdr" {
        return Err(LogError::Encoding {
            topic: topic.into(),
            encoding: encoding.into(),
        });
    }
    let expected: &[MsgType] = match role {
        Role::Odometry => &[MsgType::Odometry],
        Role::Tf | Role::TfStatic => &[MsgType::TfMessage],
        Role::Gait => &[MsgType::String, MsgType::UInt8],
        Role::Motion => &[MsgType::UInt8],
        Role::Cloud(_) => &[MsgType::PointCloud2],
    };
    // rosbag2 also writes the ROS 1 style name without "/msg/" for some types.
    let matches = |t: &MsgType| schema == t.name() || schema == t.name().replace("/msg/", "/");
    if expected.iter().any(matches) {
        Ok(())
    } else {
        Err(LogError::Schema {
            topic: topic.into(),
            schema: schema.into(),
            expected: expected
                .iter()
                .map(|t| t.name())
                .collect::<Vec<_>>()
                .join(" or "),
        })
    }
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
        let limit = ros2::seconds_to_nanos(self.now).saturating_add(1);
        self.fill(limit)?;
        loop {
            let pose = self.poses.get(self.next_pose).filter(|p| p.0 <= limit);
            let cloud = self.pending.peek().map(|c| &c.0).filter(|c| c.ns <= limit);
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
            } else if let Some(Reverse(c)) = self.pending.pop() {
                if self.cfg.keyframes && !sink.wants_cloud(c.sensor) {
                    self.stats.clouds_skipped += 1;
                    continue;
                }
                let pc = self.cloud(&c)?;
                self.stats.clouds_delivered += 1;
                self.stats.points += pc.points.len();
                sink.on_cloud(&pc);
            }
        }
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
        Ok(self.state)
    }
}
