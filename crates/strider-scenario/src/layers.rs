//! Where the PNG layers named by a scenario's `[world]` section come from: files next to the
//! scenario TOML ([`LayerDir`]) or bytes in memory (a map from the names the TOML uses to the
//! PNG bytes), so that a scenario can be loaded, and fuzzed, without a filesystem
//! ([`crate::Scenario::from_toml_str`]).

use std::collections::BTreeMap;
use std::fs::File;
use std::io::{BufRead, BufReader, Cursor, Seek};
use std::path::PathBuf;

/// A readable, seekable layer stream (what the PNG decoder needs).
pub trait LayerRead: BufRead + Seek {}
impl<T: BufRead + Seek> LayerRead for T {}

/// A provider of the layers a scenario names.
pub trait LayerSource {
    /// Opens the layer the TOML names `name`; an error of kind
    /// [`std::io::ErrorKind::NotFound`] when there is none.
    fn open(&self, name: &str) -> std::io::Result<Box<dyn LayerRead + '_>>;
    /// How error messages name layer `name` (its file path).
    fn path(&self, name: &str) -> PathBuf;
}

/// Layers as files, their names relative to a directory (the scenario TOML's).
#[derive(Clone, Debug)]
pub struct LayerDir(pub PathBuf);

impl LayerSource for LayerDir {
    fn open(&self, name: &str) -> std::io::Result<Box<dyn LayerRead + '_>> {
        Ok(Box::new(BufReader::new(File::open(self.path(name))?)))
    }
    fn path(&self, name: &str) -> PathBuf {
        self.0.join(name)
    }
}

/// Layers in memory: PNG bytes keyed by the names the TOML gives them.
impl LayerSource for BTreeMap<String, Vec<u8>> {
    fn open(&self, name: &str) -> std::io::Result<Box<dyn LayerRead + '_>> {
        match self.get(name) {
            Some(bytes) => Ok(Box::new(Cursor::new(bytes.as_slice()))),
            None => Err(std::io::ErrorKind::NotFound.into()),
        }
    }
    fn path(&self, name: &str) -> PathBuf {
        PathBuf::from(name)
    }
}
