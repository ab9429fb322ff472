//! The error type of the crate: what was wrong and where (file, topic, message index, byte
//! offset).

use crate::cdr::CdrError;
use std::path::PathBuf;
use strider_core::text::one_line;

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
    /// The file is not an MCAP file, or its container is truncated or corrupt (bad magic, CRC,
    /// record lengths, unknown chunk compression, …).
    #[error("{}: {} (near byte {offset}, after {messages} messages)", path.display(), one_line(.reason))]
    Mcap {
        /// The file.
        path: PathBuf,
        /// Messages read before the fault.
        messages: usize,
        /// Bytes of the file read when the fault was found.
        offset: u64,
        /// What is wrong, one line of plain text (see [`mcap_reason`]).
        reason: String,
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
    #[error(
        "{}: no message on topic {} ({what}); topics in the file: {}",
        path.display(),
        one_line(.topic),
        one_line(.available)
    )]
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
        "topic {}: message encoding {encoding:?} is not supported (ROS 2 \"cdr\" expected)",
        one_line(.topic)
    )]
    Encoding {
        /// The topic.
        topic: String,
        /// Its channel's message encoding.
        encoding: String,
    },
    /// A topic carries another message type than the one configured for it.
    #[error("topic {}: schema {schema:?}, expected {expected}", one_line(.topic))]
    Schema {
        /// The topic.
        topic: String,
        /// The channel's schema name.
        schema: String,
        /// What was expected.
        expected: String,
    },
    /// A message could not be decoded.
    #[error("topic {}, message {index}: {}", one_line(.topic), one_line(&.source.to_string()))]
    Decode {
        /// The topic.
        topic: String,
        /// Index of the message on its topic (0-based).
        index: usize,
        /// What the decoder found.
        source: CdrError,
    },
    /// A message decoded but its content is unusable (unknown gait, missing transform, …).
    #[error("topic {}, message {index}: {}", one_line(.topic), one_line(.reason))]
    Content {
        /// The topic.
        topic: String,
        /// Index of the message on its topic (0-based).
        index: usize,
        /// What was wrong.
        reason: String,
    },
    /// The replay configuration is invalid.
    #[error("replay config: {}", one_line(.0))]
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

/// What an MCAP reader's error says about a file, as one line of plain text: the reader's own
/// diagnosis carries terminal colour codes and a multi-line backtrace of the record parser,
/// which are reduced to the innermost cause.
pub fn mcap_reason(e: &mcap::McapError, offset: u64) -> String {
    use mcap::McapError as E;
    match e {
        E::BadMagic if offset <= 8 => {
            "not an MCAP file: it does not begin with the MCAP magic bytes".into()
        }
        E::UnexpectedEof if offset == 0 => "the file is empty, not an MCAP file".into(),
        E::UnexpectedEof => "the file ends in the middle of a record (it was cut short, or a \
                             record's length is corrupt; a recording cut short can be repaired \
                             with the mcap CLI's `mcap recover`)"
            .into(),
        // The reader holds the whole record: a field running past its end is corruption.
        E::Parse(p) if p.is_eof() => {
            "corrupt MCAP: a record's fields run past its end (a length inside it is wrong)".into()
        }
        E::Parse(p) => format!(
            "corrupt MCAP: a record could not be parsed ({})",
            plain(&p.root_cause().to_string())
        ),
        E::RecordTooLarge { opcode, len } => format!(
            "corrupt MCAP: a record (opcode {opcode:#04x}) claims {len} bytes, more than the \
             {} MiB a record may have",
            crate::limits::MAX_RECORD_BYTES >> 20
        ),
        E::ChunkTooLarge(len) => format!(
            "corrupt MCAP: a chunk claims {len} bytes uncompressed, more than the {} MiB a \
             chunk may have",
            crate::limits::MAX_RECORD_BYTES >> 20
        ),
        // A sound file written with a compression this reader lacks: nothing to repair.
        E::UnsupportedCompression(name) => format!(
            "its chunks are compressed with {}, which this reader does not decompress (it \
             reads zstd, lz4 and uncompressed chunks, the compressions MCAP defines): rewrite \
             the file with one of them",
            quoted_prefix(name, 32)
        ),
        E::Io(io) => format!("cannot read: {}", plain(&io.to_string())),
        e => format!("corrupt MCAP: {}", plain(&e.to_string())),
    }
}

/// The first `max` characters of `name`, quoted with control characters escaped (a name read
/// from a file can be long and hold anything).
fn quoted_prefix(name: &str, max: usize) -> String {
    let mut s = format!("{:?}", name.chars().take(max).collect::<String>());
    if name.chars().nth(max).is_some() {
        s.push('…');
    }
    s
}

/// `text` as one line of plain text: terminal escape sequences and other control characters
/// removed, whitespace runs collapsed to one space. Foreign error messages pass through it
/// before they are shown.
pub fn plain(text: &str) -> String {
    let mut out = String::with_capacity(text.len());
    let mut chars = text.chars().peekable();
    while let Some(c) = chars.next() {
        if c == '\u{1b}' {
            // CSI: ESC [ parameters… final byte in @..=~; other escapes: ESC and one character.
            if chars.next_if_eq(&'[').is_some() {
                while chars.next().is_some_and(|c| !('@'..='~').contains(&c)) {}
            } else {
                chars.next();
            }
        } else if c.is_whitespace() || c.is_control() {
            if !out.is_empty() && !out.ends_with(' ') {
                out.push(' ');
            }
        } else {
            out.push(c);
        }
    }
    out.trim_end().to_string()
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

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn plain_strips_escapes_and_joins_lines() {
        assert_eq!(
            plain("\u{1b}[1m\u{1b}[1mError: not enough bytes\u{1b}[22m\n   at x\r\n\u{7}"),
            "Error: not enough bytes at x"
        );
        assert_eq!(plain("  a\tb  "), "a b");
        assert_eq!(plain("\u{1b}"), "");
        assert_eq!(plain("\u{1b}[31"), "");
    }
}
