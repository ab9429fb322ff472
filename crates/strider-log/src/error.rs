//! The error type of the crate: what was wrong and where (file, topic, message index, byte
//! offset).

use crate::cdr::CdrError;
use std::path::PathBuf;

/// Errors of MCAP reading, writing and replay.
#[derive(Debug, thiserror::Error)]
pub enum LogError {
    /// The file could not be opened, created or written.
    #[error("{}: {source}", path.display())]
    Io {
        /// The file.
        path: PathBuf,
        /// The cause.
        source: std::io::Error,
    },
    /// The MCAP container is truncated or corrupt (bad magic, CRC, record lengths, unknown
    /// chunk compression, …).
    #[error(
        "{}: not a readable MCAP file after {messages} messages (near byte {offset}): {source} \
         (a recording cut short can be repaired with the mcap CLI's `mcap recover`)",
        path.display()
    )]
    Mcap {
        /// The file.
        path: PathBuf,
        /// Messages read before the fault.
        messages: usize,
        /// Bytes of the file read when the fault was found.
        offset: u64,
        /// The reader's diagnosis.
        source: mcap::McapError,
    },
    /// Writing the MCAP file failed.
    #[error("{}: cannot write MCAP: {source}", path.display())]
    Write {
        /// The file.
        path: PathBuf,
        /// The writer's error.
        source: mcap::McapError,
    },
    /// A topic the configuration needs has no message in the file.
    #[error("{}: no message on topic {topic} ({what}); topics in the file: {available}", path.display())]
    MissingTopic {
        /// The file.
        path: PathBuf,
        /// The topic.
        topic: String,
        /// What the topic was needed for.
        what: &'static str,
        /// The topics present, comma-separated.
        available: String,
    },
    /// A topic's messages are not in an encoding this reader decodes.
    #[error(
        "topic {topic}: message encoding {encoding:?} is not supported (ROS 2 \"cdr\" expected)"
    )]
    Encoding {
        /// The topic.
        topic: String,
        /// Its channel's message encoding.
        encoding: String,
    },
    /// A topic carries another message type than the one configured for it.
    #[error("topic {topic}: schema {schema:?}, expected {expected}")]
    Schema {
        /// The topic.
        topic: String,
        /// The channel's schema name.
        schema: String,
        /// What was expected.
        expected: String,
    },
    /// A message could not be decoded.
    #[error("topic {topic}, message {index}: {source}")]
    Decode {
        /// The topic.
        topic: String,
        /// Index of the message on its topic (0-based).
        index: usize,
        /// What the decoder found.
        source: CdrError,
    },
    /// A message decoded but its content is unusable (unknown gait, missing transform, …).
    #[error("topic {topic}, message {index}: {reason}")]
    Content {
        /// The topic.
        topic: String,
        /// Index of the message on its topic (0-based).
        index: usize,
        /// What was wrong.
        reason: String,
    },
    /// The replay configuration is invalid.
    #[error("replay config: {0}")]
    Config(String),
}

impl LogError {
    /// An I/O error on `path`.
    pub fn io(path: impl Into<PathBuf>, source: std::io::Error) -> Self {
        LogError::Io {
            path: path.into(),
            source,
        }
    }
}

/// A message of a log, by topic and index on the topic: what an error about its content says.
#[derive(Clone, Copy, Debug)]
pub(crate) struct MessageAt<'a> {
    /// The topic.
    pub(crate) topic: &'a str,
    /// Index of the message on its topic (0-based).
    pub(crate) index: usize,
}

impl MessageAt<'_> {
    /// The message could not be decoded.
    pub(crate) fn decode(self, source: CdrError) -> LogError {
        LogError::Decode {
            topic: self.topic.into(),
            index: self.index,
            source,
        }
    }

    /// The message decoded but its content is unusable.
    pub(crate) fn content(self, reason: String) -> LogError {
        LogError::Content {
            topic: self.topic.into(),
            index: self.index,
            reason,
        }
    }
}
