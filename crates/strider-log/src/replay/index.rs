//! The checking pass of a replay: every message on a configured topic is checked and all but
//! the clouds' payloads are decoded, so a faulty log is reported before any work.

use super::reader::{Reader, Source};
use super::roles::{Role, check};
use super::tf::{Iso, TfBuffer};
use crate::cdr;
use crate::config::ReplayConfig;
use crate::error::{LogError, MessageAt};
use crate::limits::MAX_SPAN_S;
use crate::ros2::{
    HeaderPrefix, MissingRgb, MsgType, Odometry, Quaternion, StringMsg, TfMessage, UInt8Msg,
    nanos_to_seconds,
};
use std::collections::{BTreeMap, HashMap};
use std::path::Path;
use strider_core::GaitId;

/// Most poses, transforms, gait and motion messages a replay keeps from its checking pass
/// (about 100 bytes each, 1 GB in all): 28 hours of a 100 Hz pose stream. A longer log is
/// split, or its pose stream thinned, before it is replayed.
pub const MAX_INDEXED: usize = 10_000_000;

/// A stamp (ns) with the topic and index of the message that carried it.
type Stamped = (i64, String, usize);

/// What the checking pass learnt of a log. Stamps are the log's own (ns); `seq` numbers count
/// the messages of the file from 1, in file order.
pub(super) struct LogIndex {
    /// Messages per topic.
    counts: BTreeMap<String, usize>,
    /// Messages in the file (all topics).
    pub(super) messages: u64,
    /// The transform tree.
    pub(super) tf: TfBuffer,
    /// Odometry: (stamp, seq, index on the topic, frame, pose in that frame; a NaN rotation
    /// when it was unusable).
    pub(super) odoms: Vec<(i64, u64, usize, String, Iso)>,
    /// The stamps of the base frame's transforms, when the pose comes from /tf: (stamp, seq).
    pub(super) base_tf: Vec<(i64, u64)>,
    /// Gait messages: (log time, seq, gait).
    pub(super) gaits: Vec<(i64, u64, GaitId)>,
    /// Motion-state messages: (log time, seq, bits).
    pub(super) motion: Vec<(i64, u64, u8)>,
    /// Clouds per configured cloud topic.
    pub(super) cloud_count: Vec<usize>,
    /// The clouds' stamps.
    pub(super) cloud_ns: Vec<i64>,
    /// The order of the stamps of the poses and clouds in the file.
    pub(super) order: StampOrder,
    /// Poses, transforms, gait and motion messages kept.
    kept: usize,
    /// The earliest and latest stamps.
    lo: Stamped,
    hi: Stamped,
}

/// What the pass needs to read a message.
struct Context<'a> {
    cfg: &'a ReplayConfig,
    roles: &'a HashMap<String, Role>,
    gait_names: &'a [&'a str],
}

impl LogIndex {
    /// Reads and checks the log of `src`.
    pub(super) fn read(
        src: &Source,
        cfg: &ReplayConfig,
        roles: &HashMap<String, Role>,
        gait_names: &[&str],
    ) -> Result<Self, LogError> {
        let path = src.path();
        let mut reader = Reader::open(src)?;
        let mut ix = LogIndex {
            counts: BTreeMap::new(),
            messages: 0,
            tf: TfBuffer::new(cfg),
            odoms: Vec::new(),
            base_tf: Vec::new(),
            gaits: Vec::new(),
            motion: Vec::new(),
            cloud_count: vec![0; cfg.clouds.len()],
            cloud_ns: Vec::new(),
            order: StampOrder::default(),
            kept: 0,
            lo: (i64::MAX, String::new(), 0),
            hi: (i64::MIN, String::new(), 0),
        };
        let cx = Context {
            cfg,
            roles,
            gait_names,
        };
        while let Some(m) = reader.next_message(path, ix.messages) {
            let m = m?;
            ix.messages += 1;
            ix.take(&m, &cx)?;
        }
        Ok(ix)
    }

    /// Checks message `m` and keeps what the replay needs of it.
    fn take(&mut self, m: &mcap::Message, cx: &Context) -> Result<(), LogError> {
        let topic = &m.channel.topic;
        let index = {
            let c = self.counts.entry(topic.clone()).or_default();
            *c += 1;
            *c - 1
        };
        let Some(&role) = cx.roles.get(topic) else {
            return Ok(());
        };
        let schema = m.channel.schema.as_ref().map_or("", |s| s.name.as_str());
        let ty = check(topic, &m.channel.message_encoding, schema, role)?;
        let at = MessageAt { topic, index };
        self.keep(at)?;
        let log_ns = i64::try_from(m.log_time).unwrap_or(i64::MAX);
        match role {
            Role::Odometry => {
                let o: Odometry = cdr::decode(&m.data).map_err(|e| at.decode(e))?;
                self.odometry(o, at);
            }
            Role::Tf | Role::TfStatic => {
                let msg: TfMessage = cdr::decode(&m.data).map_err(|e| at.decode(e))?;
                if role == Role::TfStatic {
                    self.tf.note_static_message();
                }
                self.transforms(msg, role == Role::TfStatic, at, cx.cfg)?;
            }
            Role::Gait => {
                let g = gait(&m.data, ty, at, cx.gait_names)?;
                self.span(log_ns, at);
                self.gaits.push((log_ns, self.messages, g));
            }
            Role::Motion => {
                let v: UInt8Msg = cdr::decode(&m.data).map_err(|e| at.decode(e))?;
                self.span(log_ns, at);
                self.motion.push((log_ns, self.messages, v.data));
            }
            Role::Cloud(i) => {
                if ty == MsgType::LaserScan
                    && cx.cfg.clouds[i as usize].missing_rgb == MissingRgb::Error
                {
                    return Err(at.content(format!(
                        "{} has no colour: set missing_rgb = \"gray\" in the cloud's replay \
                         config to map it uncoloured",
                        ty.name()
                    )));
                }
                // Only the header now; the payload is checked when it is delivered.
                let h: HeaderPrefix = cdr::decode(&m.data).map_err(|e| at.decode(e))?;
                let ns = h.header.stamp.nanos();
                self.span(ns, at);
                self.order.note(topic, topic, index, ns);
                self.cloud_ns.push(ns);
                self.cloud_count[i as usize] += 1;
            }
        }
        Ok(())
    }

    /// Counts a message kept (a transform message counts once more per transform), refusing
    /// more than [`MAX_INDEXED`].
    fn keep(&mut self, at: MessageAt) -> Result<(), LogError> {
        self.kept += 1;
        if self.kept > MAX_INDEXED {
            return Err(at.content(format!(
                "more than {MAX_INDEXED} poses, transforms, gait and motion messages: split \
                 the log, or thin its pose and /tf streams"
            )));
        }
        Ok(())
    }

    /// Widens the span of stamps to `ns`.
    fn span(&mut self, ns: i64, at: MessageAt) {
        if ns < self.lo.0 {
            self.lo = (ns, at.topic.to_string(), at.index);
        }
        if ns > self.hi.0 {
            self.hi = (ns, at.topic.to_string(), at.index);
        }
    }

    /// Keeps an odometry message's pose (with a NaN rotation when its orientation is unusable).
    fn odometry(&mut self, o: Odometry, at: MessageAt) {
        let ns = o.header.stamp.nanos();
        self.span(ns, at);
        self.order.note(at.topic, at.topic, at.index, ns);
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
        self.odoms
            .push((ns, self.messages, at.index, o.header.frame_id.0, iso));
    }

    /// Adds a /tf or /tf_static message's transforms to the tree.
    fn transforms(
        &mut self,
        msg: TfMessage,
        is_static: bool,
        at: MessageAt,
        cfg: &ReplayConfig,
    ) -> Result<(), LogError> {
        for ts in msg.transforms {
            self.keep(at)?;
            let Some(iso) = Iso::from_msg(&ts.transform) else {
                return Err(at.content(format!(
                    "transform {} → {} is not finite or has a zero rotation",
                    ts.header.frame_id.0, ts.child_frame_id.0
                )));
            };
            let child = ts.child_frame_id.0;
            let parent = ts.header.frame_id.0;
            if child == parent {
                return Err(at.content(format!("frame {child:?} is its own parent")));
            }
            if is_static {
                self.tf.add_static(child, parent, iso);
            } else {
                let ns = ts.header.stamp.nanos();
                if cfg.pose.from_tf && child == cfg.pose.base_frame {
                    self.span(ns, at);
                    self.order.note(&child, at.topic, at.index, ns);
                    self.base_tf.push((ns, self.messages));
                }
                self.tf.add(child, ns, parent, iso);
            }
        }
        Ok(())
    }

    /// Checks that every topic the configuration needs has messages.
    pub(super) fn require_topics(&self, path: &Path, cfg: &ReplayConfig) -> Result<(), LogError> {
        let available = || {
            if self.counts.is_empty() {
                "none".to_string()
            } else {
                self.counts.keys().cloned().collect::<Vec<_>>().join(", ")
            }
        };
        let missing = |topic: &str, what: &'static str| LogError::MissingTopic {
            path: path.into(),
            topic: topic.into(),
            what,
            available: available(),
        };
        for (c, n) in cfg.clouds.iter().zip(&self.cloud_count) {
            if *n == 0 {
                return Err(missing(&c.topic, "point clouds"));
            }
        }
        if cfg.pose.from_tf {
            if self.base_tf.is_empty() {
                return Err(missing(&cfg.tf.topic, "the pose from tf"));
            }
        } else if self.odoms.is_empty() {
            return Err(missing(&cfg.pose.topic, "the pose"));
        }
        Ok(())
    }

    /// The earliest and the latest stamp, checked to lie at most [`MAX_SPAN_S`] apart.
    pub(super) fn span_ns(&self) -> Result<(i64, i64), LogError> {
        let (lo, hi) = (&self.lo, &self.hi);
        let span_s = nanos_to_seconds(hi.0.saturating_sub(lo.0));
        if span_s > MAX_SPAN_S {
            return Err(LogError::Content {
                topic: hi.1.clone(),
                index: hi.2,
                reason: format!(
                    "its stamp is {span_s:.0} s after the earliest one (topic {}, message {}): \
                     the stamps are inconsistent (more than {MAX_SPAN_S:.0} s apart)",
                    lo.1, lo.2
                ),
            });
        }
        Ok((lo.0, hi.0))
    }
}

/// The gait of a gait message of type `ty`: an index (`std_msgs/UInt8`) or a name
/// (`std_msgs/String`) of one of the robot's `gait_names`.
fn gait(data: &[u8], ty: MsgType, at: MessageAt, gait_names: &[&str]) -> Result<GaitId, LogError> {
    if ty == MsgType::UInt8 {
        let v: UInt8Msg = cdr::decode(data).map_err(|e| at.decode(e))?;
        if (v.data as usize) >= gait_names.len() {
            return Err(at.content(format!(
                "gait index {} but the robot has {} gaits",
                v.data,
                gait_names.len()
            )));
        }
        return Ok(GaitId(v.data));
    }
    let v: StringMsg = cdr::decode(data).map_err(|e| at.decode(e))?;
    let k = gait_names
        .iter()
        .position(|g| *g == v.data.0)
        .ok_or_else(|| {
            at.content(format!(
                "unknown gait {:?} (the robot's gaits: {})",
                v.data.0,
                gait_names.join(", ")
            ))
        })?;
    Ok(GaitId(k as u8))
}

/// The latest stamp per topic (or frame) in file order, counting stamps that go backwards.
#[derive(Default)]
pub(super) struct StampOrder {
    last: std::collections::HashMap<String, i64>,
    pub(super) backward: usize,
    pub(super) first: Option<(String, usize)>,
}

impl StampOrder {
    /// Notes message `index` of `topic` stamped `ns`, ordered among those of `key` (the
    /// topic, or a frame of it).
    pub(super) fn note(&mut self, key: &str, topic: &str, index: usize, ns: i64) {
        match self.last.get_mut(key) {
            Some(last) if ns < *last => {
                self.backward += 1;
                if self.first.is_none() {
                    self.first = Some((topic.to_string(), index));
                }
            }
            Some(last) => *last = ns,
            None => {
                self.last.insert(key.to_string(), ns);
            }
        }
    }
}
