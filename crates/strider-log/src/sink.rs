//! Where recorded messages go. A message is encoded once, by [`Writer`], and handed as bytes to
//! a [`MessageSink`]: the MCAP file (`writer::McapFile`), the live view (`live::LiveSink`), or
//! both through a [`Fanout`]. Every sink therefore carries the
//! same channels, schemas, stamps and payloads.
//!
//! A channel is described as MCAP and the Foxglove WebSocket protocol both describe it: a
//! topic, a schema (name, encoding, data) and a message encoding. ROS 2 messages are `cdr` with
//! `ros2msg` schemas; Foxglove's are `protobuf` with the `FileDescriptorSet` the [`foxglove`]
//! crate ships.

use crate::error::LogError;
use crate::ros2::MsgType;
use std::collections::{BTreeMap, HashSet};

/// A channel: its topic, schema and message encoding.
#[derive(Clone, Copy, Debug)]
pub struct Channel<'a> {
    /// The topic.
    pub topic: &'a str,
    /// The schema's name, e.g. `nav_msgs/msg/Odometry` or `foxglove.Grid`.
    pub schema_name: &'a str,
    /// The schema's encoding: `ros2msg` or `protobuf`.
    pub schema_encoding: &'a str,
    /// The schema itself.
    pub schema: &'a [u8],
    /// The messages' encoding: `cdr` or `protobuf`.
    pub message_encoding: &'a str,
}

/// A destination of encoded messages.
pub trait MessageSink {
    /// Opens the channel of `ch.topic`. [`Writer`] calls it once per topic, right before the
    /// topic's first message.
    fn open(&mut self, ch: &Channel<'_>) -> Result<(), LogError>;

    /// Writes one encoded message on an opened topic; `stamp_ns` is its log time, ns.
    fn write(&mut self, topic: &str, stamp_ns: i64, data: &[u8]) -> Result<(), LogError>;

    /// Writes a metadata record (free key–value text); a sink without metadata ignores it.
    fn metadata(&mut self, _name: &str, _kv: &BTreeMap<String, String>) -> Result<(), LogError> {
        Ok(())
    }

    /// Ends the output (an MCAP file writes its summary and footer). Called once, last.
    fn finish(&mut self) -> Result<(), LogError>;
}

impl<S: MessageSink + ?Sized> MessageSink for Box<S> {
    fn open(&mut self, ch: &Channel<'_>) -> Result<(), LogError> {
        (**self).open(ch)
    }
    fn write(&mut self, topic: &str, stamp_ns: i64, data: &[u8]) -> Result<(), LogError> {
        (**self).write(topic, stamp_ns, data)
    }
    fn metadata(&mut self, name: &str, kv: &BTreeMap<String, String>) -> Result<(), LogError> {
        (**self).metadata(name, kv)
    }
    fn finish(&mut self) -> Result<(), LogError> {
        (**self).finish()
    }
}

/// Several sinks fed the same messages, in order. Every sink gets every call even when an
/// earlier one failed (a failing file does not blank the live view); the first error is
/// returned.
#[derive(Default)]
pub struct Fanout(pub Vec<Box<dyn MessageSink>>);

impl Fanout {
    fn each(
        &mut self,
        mut f: impl FnMut(&mut dyn MessageSink) -> Result<(), LogError>,
    ) -> Result<(), LogError> {
        let mut first = Ok(());
        for s in &mut self.0 {
            let r = f(s.as_mut());
            if first.is_ok() {
                first = r;
            }
        }
        first
    }
}

impl MessageSink for Fanout {
    fn open(&mut self, ch: &Channel<'_>) -> Result<(), LogError> {
        self.each(|s| s.open(ch))
    }
    fn write(&mut self, topic: &str, stamp_ns: i64, data: &[u8]) -> Result<(), LogError> {
        self.each(|s| s.write(topic, stamp_ns, data))
    }
    fn metadata(&mut self, name: &str, kv: &BTreeMap<String, String>) -> Result<(), LogError> {
        self.each(|s| s.metadata(name, kv))
    }
    fn finish(&mut self) -> Result<(), LogError> {
        self.each(|s| s.finish())
    }
}

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

    fn count(&mut self, topic: &str) {
        match self.messages.get_mut(topic) {
            Some(n) => *n += 1,
            None => {
                self.messages.insert(topic.to_string(), 1);
            }
        }
    }
}

/// Encodes messages and writes them to a sink, opening each topic's channel with the schema of
/// its first message.
pub struct Writer<S> {
    sink: S,
    opened: HashSet<String>,
    summary: WriteSummary,
    buf: Vec<u8>,
}

impl<S: MessageSink> Writer<S> {
    /// Writes to `sink`.
    pub fn new(sink: S) -> Self {
        Self {
            sink,
            opened: HashSet::new(),
            summary: WriteSummary::default(),
            buf: Vec::new(),
        }
    }

    /// The sink.
    pub fn sink(&self) -> &S {
        &self.sink
    }

    fn open(&mut self, ch: &Channel<'_>) -> Result<(), LogError> {
        self.sink.open(ch)?;
        self.opened.insert(ch.topic.to_string());
        Ok(())
    }

    fn write_raw(&mut self, topic: &str, stamp_ns: i64, data: &[u8]) -> Result<(), LogError> {
        self.sink.write(topic, stamp_ns, data)?;
        self.summary.count(topic);
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
        if !self.opened.contains(topic) {
            let def = ty.definition();
            self.open(&Channel {
                topic,
                schema_name: ty.name(),
                schema_encoding: "ros2msg",
                schema: def.as_bytes(),
                message_encoding: "cdr",
            })?;
        }
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
        if !self.opened.contains(topic) {
            let schema = T::get_schema().ok_or_else(|| {
                LogError::Config(format!("topic {topic}: message type without a schema"))
            })?;
            let enc = T::get_message_encoding();
            self.open(&Channel {
                topic,
                schema_name: &schema.name,
                schema_encoding: &schema.encoding,
                schema: &schema.data,
                message_encoding: &enc,
            })?;
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
        self.sink.metadata(name, &kv)
    }

    /// Ends the output, returning what was written.
    pub fn finish(mut self) -> Result<WriteSummary, LogError> {
        self.sink.finish()?;
        Ok(self.summary)
    }
}
