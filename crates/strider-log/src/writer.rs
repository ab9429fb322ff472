//! A thin MCAP writer over the [`mcap`] crate: one channel per topic, ROS 2 messages in the
//! `cdr` encoding with `ros2msg` schemas, Foxglove messages in the `protobuf` encoding with the
//! schemas the [`foxglove`] crate ships. Chunks are zstd-compressed (single-threaded: the
//! simulation already uses the cores).

use crate::error::LogError;
use crate::ros2::MsgType;
use std::collections::{BTreeMap, HashMap};
use std::fs::File;
use std::io::BufWriter;
use std::path::{Path, PathBuf};

/// Counts of what was written.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct WriteSummary {
    /// Messages per topic.
    pub messages: BTreeMap<String, u64>,
}

impl WriteSummary {
    /// All messages.
    pub fn total(&self) -> u64 {
        self.messages.values().sum()
    }
}

/// An MCAP file being written.
pub struct McapWriter {
    path: PathBuf,
    w: mcap::Writer<BufWriter<File>>,
    /// Channel id and next sequence number per topic.
    channels: HashMap<String, (u16, u32)>,
    summary: WriteSummary,
    buf: Vec<u8>,
}

impl McapWriter {
    /// Creates (truncates) `path`.
    pub fn create(path: &Path) -> Result<Self, LogError> {
        let file = File::create(path).map_err(|e| LogError::io(path, e))?;
        let w = mcap::WriteOptions::new()
            .compression(Some(mcap::Compression::Zstd))
            .compression_threads(0)
            .profile("ros2")
            .library(format!("strider-log {}", env!("CARGO_PKG_VERSION")))
            .create(BufWriter::new(file))
            .map_err(|source| LogError::Write {
                path: path.into(),
                source,
            })?;
        Ok(Self {
            path: path.into(),
            w,
            channels: HashMap::new(),
            summary: WriteSummary::default(),
            buf: Vec::new(),
        })
    }

    fn err(&self, source: mcap::McapError) -> LogError {
        LogError::Write {
            path: self.path.clone(),
            source,
        }
    }

    /// The channel of `topic`, created with the given schema on first use.
    fn channel(
        &mut self,
        topic: &str,
        schema: (&str, &str, &[u8]),
        message_encoding: &str,
    ) -> Result<u16, LogError> {
        if let Some(&(id, _)) = self.channels.get(topic) {
            return Ok(id);
        }
        let (name, encoding, data) = schema;
        let sid = self
            .w
            .add_schema(name, encoding, data)
            .map_err(|e| self.err(e))?;
        let id = self
            .w
            .add_channel(sid, topic, message_encoding, &BTreeMap::new())
            .map_err(|e| self.err(e))?;
        self.channels.insert(topic.to_string(), (id, 0));
        Ok(id)
    }

    fn write_raw(&mut self, topic: &str, stamp_ns: i64, data: &[u8]) -> Result<(), LogError> {
        let Some(e) = self.channels.get_mut(topic) else {
            return Err(LogError::Config(format!("topic {topic}: no channel")));
        };
        e.1 = e.1.wrapping_add(1);
        let (id, seq) = *e;
        let t = stamp_ns.max(0) as u64;
        let header = mcap::records::MessageHeader {
            channel_id: id,
            sequence: seq,
            log_time: t,
            publish_time: t,
        };
        self.w
            .write_to_known_channel(&header, data)
            .map_err(|e| self.err(e))?;
        *self.summary.messages.entry(topic.to_string()).or_default() += 1;
        Ok(())
    }

    /// Writes an already CDR-encoded ROS 2 message of type `ty` on `topic`.
    pub fn write_cdr(
        &mut self,
        topic: &str,
        ty: MsgType,
        stamp_ns: i64,
        cdr: &[u8],
    ) -> Result<(), LogError> {
        let def = ty.definition();
        self.channel(topic, (ty.name(), "ros2msg", def.as_bytes()), "cdr")?;
        self.write_raw(topic, stamp_ns, cdr)
    }

    /// Encodes and writes a ROS 2 message.
    pub fn write_ros2<T: serde::Serialize>(
        &mut self,
        topic: &str,
        ty: MsgType,
        stamp_ns: i64,
        msg: &T,
    ) -> Result<(), LogError> {
        let bytes = crate::cdr::encode(msg).map_err(|source| LogError::Decode {
            topic: topic.into(),
            index: 0,
            source,
        })?;
        self.write_cdr(topic, ty, stamp_ns, &bytes)
    }

    /// Encodes and writes a message with one of Foxglove's schemas (protobuf).
    pub fn write_foxglove<T: foxglove::Encode>(
        &mut self,
        topic: &str,
        stamp_ns: i64,
        msg: &T,
    ) -> Result<(), LogError> {
        if !self.channels.contains_key(topic) {
            let schema = T::get_schema().ok_or_else(|| {
                LogError::Config(format!("topic {topic}: message type without a schema"))
            })?;
            let enc = T::get_message_encoding();
            self.channel(topic, (&schema.name, &schema.encoding, &schema.data), &enc)?;
        }
        let mut buf = std::mem::take(&mut self.buf);
        buf.clear();
        if let Some(n) = msg.encoded_len() {
            buf.reserve(n);
        }
        let r = msg
            .encode(&mut buf)
            .map_err(|e| LogError::Config(format!("topic {topic}: cannot encode: {e}")))
            .and_then(|()| self.write_raw(topic, stamp_ns, &buf));
        self.buf = buf;
        r
    }

    /// Writes a metadata record (free key–value text).
    pub fn metadata(&mut self, name: &str, kv: BTreeMap<String, String>) -> Result<(), LogError> {
        self.w
            .write_metadata(&mcap::records::Metadata {
                name: name.into(),
                metadata: kv,
            })
            .map_err(|e| self.err(e))
    }

    /// Writes the summary section and closes the file.
    pub fn finish(mut self) -> Result<WriteSummary, LogError> {
        self.w.finish().map_err(|e| self.err(e))?;
        Ok(self.summary)
    }
}
