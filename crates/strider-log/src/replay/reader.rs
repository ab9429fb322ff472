//! The MCAP message reader of a replay, bounded against corrupted lengths and counting the
//! bytes it read to say where a fault was found.

use crate::error::{LogError, mcap_reason};
use crate::limits::MAX_RECORD_BYTES;
use std::cell::Cell;
use std::fs::File;
use std::io::{BufReader, Cursor, Read};
use std::path::{Path, PathBuf};
use std::rc::Rc;
use std::sync::Arc;

/// Where a log's bytes come from: a file, or bytes in memory (named for messages).
#[derive(Clone, Debug)]
pub(super) enum Source {
    File(PathBuf),
    Bytes { name: PathBuf, bytes: Arc<[u8]> },
}

impl Source {
    /// The name errors give the log.
    pub(super) fn path(&self) -> &Path {
        match self {
            Source::File(p) => p,
            Source::Bytes { name, .. } => name,
        }
    }

    fn open(&self) -> Result<Box<dyn Read>, LogError> {
        Ok(match self {
            Source::File(p) => {
                let f = File::open(p).map_err(|e| LogError::io(p, e))?;
                Box::new(BufReader::with_capacity(1 << 20, f))
            }
            Source::Bytes { bytes, .. } => Box::new(Cursor::new(bytes.clone())),
        })
    }
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
pub(super) struct Reader {
    r: mcap::io::MessageReader<Counting<Box<dyn Read>>>,
    n: Rc<Cell<u64>>,
}

impl Reader {
    /// Opens `src` for reading its messages in file order.
    pub(super) fn open(src: &Source) -> Result<Reader, LogError> {
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
                    inner: src.open()?,
                    n: n.clone(),
                },
                options,
            ),
            n,
        })
    }

    /// The next message of `path` after `messages` read so far, `None` at the end.
    pub(super) fn next_message(
        &mut self,
        path: &Path,
        messages: u64,
    ) -> Option<Result<mcap::Message<'static>, LogError>> {
        let m = self.r.next()?;
        Some(m.map_err(|e| LogError::Mcap {
            path: path.into(),
            messages: messages as usize,
            offset: self.n.get(),
            reason: mcap_reason(&e, self.n.get()),
        }))
    }
}
