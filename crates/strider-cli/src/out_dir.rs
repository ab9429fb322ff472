//! A failed command leaves no empty output directory behind: the directories it would create
//! are noted before it runs, and after a failure those it created are removed again if they
//! hold no file (a directory that existed before is never touched).

use std::fs;
use std::path::{Path, PathBuf};

use crate::args::{BenchCommand, Command, LearnCommand, MapCommand, ScenarioCommand};

/// The output directories of `command`.
pub fn of(command: &Command) -> Vec<PathBuf> {
    let dirs: Vec<&Path> = match command {
        Command::Run(a) => vec![a.out.as_path()],
        Command::Replay(a) => vec![a.out.as_path()],
        Command::Tours(a) => vec![a.out.as_path()],
        Command::Navigate(a) => vec![a.out.as_path()],
        Command::Learn(LearnCommand::Bench(a)) => vec![a.out.as_path()],
        Command::Learn(LearnCommand::C4Vegetation(a)) => vec![a.out.as_path()],
        Command::Bench(BenchCommand::Table5(a)) => {
            let mut v = vec![a.out.as_path()];
            v.extend(a.mcap_dir.as_deref());
            v
        }
        Command::Bench(BenchCommand::Compare(a)) => vec![a.out.as_path()],
        Command::Bench(BenchCommand::Merge(a)) => vec![a.out.as_path()],
        Command::Bench(BenchCommand::Soak(a)) => vec![a.out.as_path()],
        Command::Bench(BenchCommand::Scale(a)) => vec![a.out.as_path()],
        Command::Scenario(ScenarioCommand::Render(a)) => vec![a.out.as_path()],
        Command::Scenario(ScenarioCommand::Export(a)) => vec![a.out.as_path()],
        Command::Map(MapCommand::Build(a)) => vec![a.out.as_path()],
        Command::Strategies
        | Command::Scenario(ScenarioCommand::List)
        | Command::Gtsp(_)
        | Command::Gp(_) => Vec::new(),
    };
    dirs.into_iter().map(Path::to_path_buf).collect()
}

/// The outermost missing directory of each output directory, noted before the command runs.
pub struct Fresh(Vec<PathBuf>);

impl Fresh {
    /// Notes which of `dirs` (or their parents) do not exist yet.
    pub fn before(dirs: &[PathBuf]) -> Self {
        Self(dirs.iter().filter_map(|d| outermost_missing(d)).collect())
    }

    /// Removes each noted directory if the command created it and left no file in it.
    pub fn remove_if_empty(&self) {
        for d in &self.0 {
            remove_empty_tree(d);
        }
    }
}

/// The outermost of `dir` and its parents that does not exist.
fn outermost_missing(dir: &Path) -> Option<PathBuf> {
    dir.ancestors()
        .take_while(|p| !p.as_os_str().is_empty() && fs::symlink_metadata(p).is_err())
        .last()
        .map(Path::to_path_buf)
}

/// Removes `dir` and the directories below it if none holds anything but empty directories;
/// returns whether `dir` is gone.
fn remove_empty_tree(dir: &Path) -> bool {
    let Ok(entries) = fs::read_dir(dir) else {
        return false;
    };
    let mut empty = true;
    for e in entries {
        let Ok(e) = e else {
            empty = false;
            continue;
        };
        let is_dir = e.file_type().is_ok_and(|t| t.is_dir());
        empty &= is_dir && remove_empty_tree(&e.path());
    }
    empty && fs::remove_dir(dir).is_ok()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn temp(name: &str) -> PathBuf {
        let d = std::env::temp_dir().join(format!("strider-outdir-{}-{name}", std::process::id()));
        let _ = fs::remove_dir_all(&d);
        fs::create_dir_all(&d).unwrap();
        d
    }

    #[test]
    fn only_created_directories_without_files_are_removed() {
        let base = temp("tree");
        let out = base.join("a/b/out");
        let fresh = Fresh::before(std::slice::from_ref(&out));
        assert_eq!(fresh.0, [base.join("a")]);
        fs::create_dir_all(out.join("trials")).unwrap();
        fresh.remove_if_empty();
        assert!(!base.join("a").exists() && base.exists());

        fs::create_dir_all(out.join("trials")).unwrap();
        fs::write(out.join("trials/t.json"), "{}").unwrap();
        fresh.remove_if_empty();
        assert!(
            out.join("trials/t.json").exists(),
            "a file keeps its directories"
        );

        let existing = Fresh::before(std::slice::from_ref(&out));
        assert!(
            existing.0.is_empty(),
            "an existing directory is never noted"
        );
        let _ = fs::remove_dir_all(&base);
    }
}
