//! Writing an experiment's outputs: directories, text files, pretty JSON and bytes (PNG), with
//! errors that name the path.
//!
//! Every file is written atomically ([`write_bytes`]): into a temporary file in the same
//! directory, flushed to disk, then renamed over the target. A reader (or a run interrupted
//! half-way) sees the previous file or the new one, never a torn one.

use std::fs;
use std::io::Write;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicU64, Ordering};

use anyhow::Context;
use serde::Serialize;

/// An error and its causes in one line, each cause once (a cause already in the message is
/// not repeated): what the command prints after `error:` and what the Python package raises.
pub fn error_line(e: &anyhow::Error) -> String {
    let mut line = e.to_string();
    for cause in e.chain().skip(1) {
        let c = cause.to_string();
        if !line.contains(&c) {
            line.push_str(": ");
            line.push_str(&c);
        }
    }
    strider_core::text::one_line(&line)
}

/// Creates `dir` and its parents.
pub fn create_dir(dir: &Path) -> anyhow::Result<()> {
    fs::create_dir_all(dir).with_context(|| format!("{}: cannot create directory", dir.display()))
}

/// Writes `bytes` to `path` atomically (see the module docs).
pub fn write_bytes(path: &Path, bytes: &[u8]) -> anyhow::Result<()> {
    let tmp = temp_beside(path);
    let written = (|| -> std::io::Result<()> {
        let mut f = fs::File::create(&tmp)?;
        f.write_all(bytes)?;
        // On disk before the rename, so that a crash cannot leave a renamed empty file.
        f.sync_all()?;
        fs::rename(&tmp, path)
    })();
    if written.is_err() {
        let _ = fs::remove_file(&tmp);
    }
    written.with_context(|| format!("{}: cannot write", path.display()))
}

/// A fresh hidden name in `path`'s directory for writing `path` (unique per process and
/// call, as trials write side by side).
fn temp_beside(path: &Path) -> PathBuf {
    static NEXT: AtomicU64 = AtomicU64::new(0);
    let n = NEXT.fetch_add(1, Ordering::Relaxed);
    let name = path
        .file_name()
        .map_or_else(String::new, |f| f.to_string_lossy().into_owned());
    path.with_file_name(format!(".{name}.{}-{n}.tmp", std::process::id()))
}

/// Writes `text` to `path` atomically.
pub fn write_text(path: &Path, text: &str) -> anyhow::Result<()> {
    write_bytes(path, text.as_bytes())
}

/// Writes `value` as pretty JSON followed by a newline, atomically.
pub fn write_json(path: &Path, value: &impl Serialize) -> anyhow::Result<()> {
    write_text(path, &(serde_json::to_string_pretty(value)? + "\n"))
}

/// The file name `path` gets while it is being written by a writer that streams into it (an
/// MCAP recording): `path` with `.part` appended. It is renamed to `path` once complete.
pub fn part_path(path: &Path) -> PathBuf {
    let mut s = path.as_os_str().to_owned();
    s.push(".part");
    PathBuf::from(s)
}

/// Renames the finished `part` file to `path`.
pub fn finish_part(part: &Path, path: &Path) -> anyhow::Result<()> {
    fs::rename(part, path)
        .with_context(|| format!("{}: cannot rename to {}", part.display(), path.display()))
}

/// Writes a set of files into `dir` with `write`, a writer that does not write atomically
/// itself (e.g. a scenario's export): it writes into a fresh staging directory inside `dir`,
/// then each file is renamed into `dir` (atomically, file by file) and the staging directory
/// removed. A failed or interrupted `write` leaves the files of `dir` as they were.
pub fn write_staged(
    dir: &Path,
    write: impl FnOnce(&Path) -> anyhow::Result<()>,
) -> anyhow::Result<()> {
    create_dir(dir)?;
    let staging = temp_beside(&dir.join("staging"));
    let staged = write(&staging).and_then(|()| {
        for e in
            fs::read_dir(&staging).with_context(|| format!("{}: cannot list", staging.display()))?
        {
            let from = e
                .with_context(|| format!("{}: cannot list", staging.display()))?
                .path();
            let to = dir.join(from.file_name().unwrap_or_default());
            fs::rename(&from, &to).with_context(|| format!("{}: cannot write", to.display()))?;
        }
        Ok(())
    });
    let _ = fs::remove_dir_all(&staging);
    staged
}

/// Serializes (key, value) pairs as a JSON object in their order (`serialize_with`).
pub(crate) fn ordered_map<S, V>(pairs: &[(String, V)], s: S) -> Result<S::Ok, S::Error>
where
    S: serde::Serializer,
    V: Serialize,
{
    s.collect_map(pairs.iter().map(|(k, v)| (k, v)))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn dir(name: &str) -> PathBuf {
        let d = std::env::temp_dir().join(format!("strider-io-{}-{name}", std::process::id()));
        let _ = fs::remove_dir_all(&d);
        fs::create_dir_all(&d).unwrap();
        d
    }

    #[test]
    fn a_write_replaces_the_file_and_leaves_no_temporary_file() {
        let d = dir("replace");
        let f = d.join("a.json");
        write_text(&f, "old").unwrap();
        write_json(&f, &serde_json::json!({"k": 1})).unwrap();
        assert_eq!(fs::read_to_string(&f).unwrap(), "{\n  \"k\": 1\n}\n");
        let names: Vec<_> = fs::read_dir(&d)
            .unwrap()
            .map(|e| e.unwrap().file_name())
            .collect();
        assert_eq!(names, ["a.json"]);
        let _ = fs::remove_dir_all(&d);
    }

    #[test]
    fn a_failed_write_keeps_the_old_file_and_names_the_path() {
        let d = dir("fail");
        let f = d.join("a.txt");
        write_text(&f, "old").unwrap();
        // A directory in the way of the rename: the write fails, the old file stays.
        let blocked = d.join("sub");
        fs::create_dir_all(blocked.join("x")).unwrap();
        let e = write_text(&blocked, "new").unwrap_err();
        assert!(format!("{e:#}").contains("sub: cannot write"), "{e:#}");
        assert_eq!(fs::read_to_string(&f).unwrap(), "old");
        let names: Vec<_> = fs::read_dir(&d)
            .unwrap()
            .map(|e| e.unwrap().file_name())
            .collect();
        assert_eq!(names.len(), 2, "{names:?}");
        let _ = fs::remove_dir_all(&d);
    }

    #[test]
    fn staged_files_land_in_the_directory_and_a_failure_leaves_it_as_it_was() {
        let d = dir("staged");
        write_text(&d.join("keep.txt"), "old").unwrap();
        write_staged(&d, |s| {
            fs::create_dir_all(s)?;
            fs::write(s.join("keep.txt"), "new")?;
            Ok(fs::write(s.join("b.png"), [1u8])?)
        })
        .unwrap();
        assert_eq!(fs::read_to_string(d.join("keep.txt")).unwrap(), "new");
        let e = write_staged(&d, |s| {
            fs::create_dir_all(s)?;
            fs::write(s.join("keep.txt"), "half")?;
            anyhow::bail!("cannot encode")
        });
        assert!(e.is_err());
        assert_eq!(fs::read_to_string(d.join("keep.txt")).unwrap(), "new");
        let mut names: Vec<_> = fs::read_dir(&d)
            .unwrap()
            .map(|e| e.unwrap().file_name())
            .collect();
        names.sort();
        assert_eq!(names, ["b.png", "keep.txt"]);
        let _ = fs::remove_dir_all(&d);
    }

    #[test]
    fn the_part_file_is_beside_the_target() {
        assert_eq!(
            part_path(Path::new("/x/run.mcap")),
            Path::new("/x/run.mcap.part")
        );
    }
}
