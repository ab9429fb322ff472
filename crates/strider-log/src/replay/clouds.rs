//! The point clouds of a replay: streamed from the file in a second pass, held in stamp order
//! within the reorder window, and decoded into the world frame only when delivered.

use super::reader::{Reader, Source};
use super::roles::{Role, check};
use super::tf::TfBuffer;
use crate::cdr;
use crate::config::{CloudConfig, ReplayConfig};
use crate::error::{LogError, MessageAt};
use crate::ros2::{self, DecodedCloud, HeaderPrefix, MsgType, nanos_to_seconds, seconds_to_nanos};
use std::cmp::Reverse;
use std::collections::{BinaryHeap, HashMap};
use std::path::PathBuf;
use strider_core::{Point3, PointCloud};

/// Most bytes of cloud messages held at once, waiting for delivery: the clouds stamped within
/// the reorder window of the delivery time are held (a few seconds of a sensor's clouds,
/// tens of MB); a log whose clouds all carry the same stamp would otherwise be held whole.
pub const MAX_PENDING_CLOUD_BYTES: usize = 1 << 30;

/// A cloud message waiting for delivery.
pub(super) struct PendingCloud {
    /// Stamp relative to the start of the log, ns.
    pub(super) ns: i64,
    /// Its number among the file's messages.
    pub(super) seq: u64,
    /// The index of its configured cloud topic.
    pub(super) sensor: u8,
    /// Its index on its topic.
    pub(super) index: usize,
    /// PointCloud2 or LaserScan.
    ty: MsgType,
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

/// The second pass over a log: its cloud messages in stamp order.
pub(super) struct CloudStream {
    path: PathBuf,
    roles: HashMap<String, Role>,
    /// The log's earliest stamp, ns.
    start_ns: i64,
    /// How far beyond the delivery time clouds are read ahead, ns.
    window_ns: i64,
    /// `None` once the file is read to its end.
    reader: Option<Reader>,
    /// Messages read.
    seq: u64,
    /// Clouds read per configured cloud topic.
    cloud_index: Vec<usize>,
    /// Stamp of the latest cloud read (relative ns).
    read_ns: i64,
    pending: BinaryHeap<Reverse<PendingCloud>>,
    /// Bytes of the pending clouds' messages.
    pending_bytes: usize,
}

impl CloudStream {
    /// The clouds of the log of `src` on the topics of `roles`, stamps relative to `start_ns`.
    pub(super) fn open(
        src: &Source,
        cfg: &ReplayConfig,
        roles: HashMap<String, Role>,
        start_ns: i64,
    ) -> Result<Self, LogError> {
        Ok(Self {
            path: src.path().into(),
            roles,
            start_ns,
            window_ns: seconds_to_nanos(cfg.reorder_window_s),
            reader: Some(Reader::open(src)?),
            seq: 0,
            cloud_index: vec![0; cfg.clouds.len()],
            read_ns: i64::MIN,
            pending: BinaryHeap::new(),
            pending_bytes: 0,
        })
    }

    /// The earliest pending cloud stamped at or before `limit` (relative ns).
    pub(super) fn peek(&self, limit: i64) -> Option<&PendingCloud> {
        self.pending.peek().map(|c| &c.0).filter(|c| c.ns <= limit)
    }

    /// Takes the earliest pending cloud.
    pub(super) fn pop(&mut self) -> Option<PendingCloud> {
        let c = self.pending.pop()?.0;
        self.pending_bytes -= c.data.len();
        Some(c)
    }

    /// Reads cloud messages until one stamped after `limit` + the reorder window (or the end).
    pub(super) fn fill(&mut self, limit: i64) -> Result<(), LogError> {
        while self.read_ns <= limit.saturating_add(self.window_ns) {
            let Some(reader) = self.reader.as_mut() else {
                return Ok(());
            };
            let Some(m) = reader.next_message(&self.path, self.seq) else {
                self.reader = None;
                return Ok(());
            };
            let m = m?;
            self.seq += 1;
            let Some(&Role::Cloud(i)) = self.roles.get(&m.channel.topic) else {
                continue;
            };
            let index = self.cloud_index[i as usize];
            self.cloud_index[i as usize] += 1;
            let at = MessageAt {
                topic: &m.channel.topic,
                index,
            };
            let schema = m.channel.schema.as_ref().map_or("", |s| s.name.as_str());
            let ty = check(
                at.topic,
                &m.channel.message_encoding,
                schema,
                Role::Cloud(i),
            )?;
            let h: HeaderPrefix = cdr::decode(&m.data).map_err(|e| at.decode(e))?;
            let ns = h.header.stamp.nanos().saturating_sub(self.start_ns);
            self.read_ns = self.read_ns.max(ns);
            self.pending_bytes += m.data.len();
            if self.pending_bytes > MAX_PENDING_CLOUD_BYTES {
                return Err(at.content(format!(
                    "more than {} MiB of clouds are stamped within reorder_window_s = {} s of \
                     each other: the stamps are inconsistent, or lower reorder_window_s",
                    MAX_PENDING_CLOUD_BYTES >> 20,
                    nanos_to_seconds(self.window_ns)
                )));
            }
            self.pending.push(Reverse(PendingCloud {
                ns,
                seq: self.seq,
                sensor: i,
                index,
                ty,
                data: m.data.into_owned(),
            }));
        }
        Ok(())
    }
}

/// Decodes cloud `c` of the configured cloud `cc` into the world frame `world` through `tf`;
/// also says whether it had no colour.
pub(super) fn world_cloud(
    c: &PendingCloud,
    cc: &CloudConfig,
    world: &str,
    tf: &TfBuffer,
) -> Result<(PointCloud, bool), LogError> {
    let at = MessageAt {
        topic: &cc.topic,
        index: c.index,
    };
    let DecodedCloud {
        header,
        mut points,
        uncoloured,
    } = match c.ty {
        MsgType::LaserScan => ros2::decode_scan(&c.data),
        _ => ros2::decode_cloud(&c.data, cc.missing_rgb),
    }
    .map_err(|e| at.decode(e))?;
    let t = header.stamp.nanos();
    let frame = header.frame_id.0;
    if frame.is_empty() {
        return Err(at.content("the cloud has no frame_id".into()));
    }
    let origin_frame = cc.origin_frame.as_deref().unwrap_or(&frame);
    if origin_frame == world {
        return Err(at.content(format!(
            "the cloud is in the world frame {world:?}: set origin_frame to the sensor's frame"
        )));
    }
    let origin = tf.lookup(origin_frame, t).map_err(|e| at.content(e))?;
    if frame != *world {
        let iso = tf.lookup(&frame, t).map_err(|e| at.content(e))?;
        for p in &mut points {
            let q = iso.apply([p.x as f64, p.y as f64, p.z as f64]);
            (p.x, p.y, p.z) = (q[0] as f32, q[1] as f32, q[2] as f32);
        }
    }
    let cloud = PointCloud::new(
        nanos_to_seconds(c.ns),
        c.sensor,
        Point3::new(origin.t[0], origin.t[1], origin.t[2]),
        points,
    );
    Ok((cloud, uncoloured))
}
