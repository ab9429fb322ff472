//! Writing an experiment's outputs: directories, text files and pretty JSON, with errors that
//! name the path.

use std::fs;
use std::path::Path;

use anyhow::Context;
use serde::Serialize;

/// Creates `dir` and its parents.
pub fn create_dir(dir: &Path) -> anyhow::Result<()> {
    fs::create_dir_all(dir).with_context(|| format!("{}: cannot create directory", dir.display()))
}

/// Writes `text` to `path`.
pub fn write_text(path: &Path, text: &str) -> anyhow::Result<()> {
    fs::write(path, text).with_context(|| format!("{}: cannot write", path.display()))
}

/// Writes `value` as pretty JSON followed by a newline.
pub fn write_json(path: &Path, value: &impl Serialize) -> anyhow::Result<()> {
    write_text(path, &(serde_json::to_string_pretty(value)? + "\n"))
}

/// Serializes (key, value) pairs as a JSON object in their order (`serialize_with`).
pub(crate) fn ordered_map<S, V>(pairs: &[(String, V)], s: S) -> Result<S::Ok, S::Error>
where
    S: serde::Serializer,
    V: Serialize,
{
    s.collect_map(pairs.iter().map(|(k, v)| (k, v)))
}
