//! The MCAP file sink over the [`mcap`] crate: one channel per topic, ROS 2 messages in the
//! `cdr` encoding with `ros2msg` schemas, Foxglove messages in the `protobuf` encoding with the
//! schemas the [`foxglove`] crate ships. Chunks are zstd-compressed (single-threaded: the
//! simulation already uses the cores). [`McapWriter`] is the [`Writer`] that encodes into it.

use crate::error::LogError;
use crate::sink::{Channel, MessageSink, Writer};
use std::collections::{BTreeMap, HashMap};
use std::fs::File;
use std::io::BufWriter;
use std::path::{Path, PathBuf};

pub use crate::sink::WriteSummary;

/// An MCAP file being written.
pub type McapWriter = Writer<McapFile>;

impl McapWriter {
    /// Creates (truncates) `path`.
    pub fn create(path: &Path) -> Result<Self, LogError> {
        Ok(Writer::new(McapFile::create(path)?))
    }
}

/// An MCAP file as a [`MessageSink`].
pub struct McapFile {
    path: PathBuf,
    w: mcap::Writer<BufWriter<File>>,
    /// Channel id and the latest sequence number per topic.
    channels: HashMap<String, (u16, u32)>,
}

impl McapFile {
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
        })
    }

    fn err(&self, source: mcap::McapError) -> LogError {
        LogError::Write {
            path: self.path.clone(),
            source,
        }
    }
}

impl MessageSink for McapFile {
    fn open(&mut self, ch: &Channel<'_>) -> Result<(), LogError> {
        if self.channels.contains_key(ch.topic) {
            return Ok(());
        }
        let sid = self
            .w
            .add_schema(ch.schema_name, ch.schema_encoding, ch.schema)
            .map_err(|e| self.err(e))?;
        let id = self
            .w
            .add_channel(sid, ch.topic, ch.message_encoding, &BTreeMap::new())
            .map_err(|e| self.err(e))?;
        self.channels.insert(ch.topic.to_string(), (id, 0));
        Ok(())
    }

    fn write(&mut self, topic: &str, stamp_ns: i64, data: &[u8]) -> Result<(), LogError> {
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
            .map_err(|e| self.err(e))
    }

    fn metadata(&mut self, name: &str, kv: &BTreeMap<String, String>) -> Result<(), LogError> {
        self.w
            .write_metadata(&mcap::records::Metadata {
                name: name.into(),
                metadata: kv.clone(),
            })
            .map_err(|e| self.err(e))
    }

    fn finish(&mut self) -> Result<(), LogError> {
        self.w.finish().map(|_| ()).map_err(|e| self.err(e))
    }
}
