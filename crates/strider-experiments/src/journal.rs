//! The finished trials of a bench, kept on disk as they complete (`DIR/trials/<key>.json`, each
//! written atomically), so that an interrupted bench loses only the trials that were running
//! and `--resume` runs only the missing ones.
//!
//! A trial file holds the trial's key (scenario, strategy, seeds), the bench's setting (what
//! else decides a trial's result, e.g. the time limit) and the trial. Trials are deterministic,
//! so a kept trial is the trial a new run would produce: a resumed bench gives the table of an
//! uninterrupted one. A file of another setting is refused (the table would mix two
//! experiments); a file that cannot be read (e.g. cut short by a crash) is run again.

use std::fs;
use std::path::{Path, PathBuf};

use anyhow::{Context, Result, bail};
use serde::de::DeserializeOwned;
use serde::{Deserialize, Serialize};
use serde_json::Value;

use crate::io::{create_dir, write_json};

/// The trial files of one bench's output directory.
pub(crate) struct Journal {
    dir: PathBuf,
    setting: Value,
}

/// A trial file.
#[derive(Serialize, Deserialize)]
struct Entry<T> {
    key: String,
    setting: Value,
    trial: T,
}

/// What reading the journal found for a key.
pub(crate) enum Kept<T> {
    /// The trial, finished by an earlier run.
    Trial(T),
    /// No usable file: run the trial. `Some(why)` when a file was there but unreadable.
    Missing(Option<String>),
}

impl Journal {
    /// The journal in `out/trials` of a bench run with `setting`. Without `resume` the run
    /// starts afresh: trial files of earlier runs there are removed (they may be of another
    /// setting, which a later `--resume` would refuse).
    pub(crate) fn open(out: &Path, setting: Value, resume: bool) -> Result<Self> {
        let dir = out.join("trials");
        if !resume && dir.is_dir() {
            for file in trial_files(&dir)? {
                fs::remove_file(&file)
                    .with_context(|| format!("{}: cannot remove", file.display()))?;
            }
        }
        Ok(Self { dir, setting })
    }

    /// The directory of the trial files.
    pub(crate) fn dir(&self) -> &Path {
        &self.dir
    }

    fn file(&self, key: &str) -> PathBuf {
        let name: String = key
            .chars()
            .map(|c| {
                if c.is_ascii_alphanumeric() || c == '-' || c == '.' {
                    c
                } else {
                    '_'
                }
            })
            .collect();
        self.dir.join(format!("{name}.json"))
    }

    /// The trial of `key` finished by an earlier run, if its file is there and readable.
    /// Errors when the file is of another setting (or another key with the same file name).
    pub(crate) fn load<T: DeserializeOwned>(&self, key: &str) -> Result<Kept<T>> {
        let file = self.file(key);
        let text = match fs::read_to_string(&file) {
            Ok(t) => t,
            Err(e) if e.kind() == std::io::ErrorKind::NotFound => return Ok(Kept::Missing(None)),
            Err(e) => return Ok(Kept::Missing(Some(format!("{}: {e}", file.display())))),
        };
        let entry: Entry<Value> = match serde_json::from_str(&text) {
            Ok(e) => e,
            Err(e) => return Ok(Kept::Missing(Some(format!("{}: {e}", file.display())))),
        };
        if entry.key != key || entry.setting != self.setting {
            bail!(
                "{}: a trial of {} with {}, not of {key} with {}: resume with the options of the earlier run, or write to another --out",
                file.display(),
                entry.key,
                entry.setting,
                self.setting
            );
        }
        Ok(match serde_json::from_value(entry.trial) {
            Ok(t) => Kept::Trial(t),
            Err(e) => Kept::Missing(Some(format!("{}: {e}", file.display()))),
        })
    }

    /// Keeps the finished trial of `key` (atomically; the directory is made on first use).
    pub(crate) fn save<T: Serialize>(&self, key: &str, trial: &T) -> Result<()> {
        create_dir(&self.dir)?;
        write_json(
            &self.file(key),
            &Entry {
                key: key.to_string(),
                setting: self.setting.clone(),
                trial,
            },
        )
    }
}

/// The `*.json` files of `dir`.
fn trial_files(dir: &Path) -> Result<Vec<PathBuf>> {
    let mut files = Vec::new();
    for e in fs::read_dir(dir).with_context(|| format!("{}: cannot list", dir.display()))? {
        let path = e
            .with_context(|| format!("{}: cannot list", dir.display()))?
            .path();
        if path.extension().is_some_and(|x| x == "json") && path.is_file() {
            files.push(path);
        }
    }
    Ok(files)
}

#[cfg(test)]
mod tests {
    use super::*;
    use serde_json::json;

    fn out(name: &str) -> PathBuf {
        let d = std::env::temp_dir().join(format!("strider-journal-{}-{name}", std::process::id()));
        let _ = fs::remove_dir_all(&d);
        d
    }

    #[test]
    fn a_kept_trial_is_read_back_and_a_fresh_run_forgets_it() {
        let d = out("keep");
        let j = Journal::open(&d, json!({"time_limit_s": 20.0}), false).unwrap();
        assert!(!j.dir().exists(), "the directory is made on first use");
        j.save("a/b w1 s1", &vec![0.1f64, 1e-300, 2.5]).unwrap();
        let j = Journal::open(&d, json!({"time_limit_s": 20.0}), true).unwrap();
        match j.load::<Vec<f64>>("a/b w1 s1").unwrap() {
            Kept::Trial(v) => assert_eq!(v, [0.1, 1e-300, 2.5]),
            Kept::Missing(why) => panic!("not kept: {why:?}"),
        }
        let j = Journal::open(&d, json!({"time_limit_s": 20.0}), false).unwrap();
        assert!(matches!(
            j.load::<Vec<f64>>("a/b w1 s1").unwrap(),
            Kept::Missing(None)
        ));
        let _ = fs::remove_dir_all(&d);
    }

    #[test]
    fn a_trial_of_another_setting_is_refused_and_a_torn_file_is_run_again() {
        let d = out("setting");
        Journal::open(&d, json!({"time_limit_s": 20.0}), false)
            .unwrap()
            .save("k", &1.0)
            .unwrap();
        let j = Journal::open(&d, json!({"time_limit_s": 30.0}), true).unwrap();
        let e = j.load::<f64>("k").err().expect("refused");
        assert!(e.to_string().contains("resume with the options"), "{e}");
        fs::write(j.file("k"), "{\"key\": \"k\", \"sett").unwrap();
        assert!(matches!(
            j.load::<f64>("k").unwrap(),
            Kept::Missing(Some(_))
        ));
        let _ = fs::remove_dir_all(&d);
    }
}
