//! Where inputs live on disk: the regression inputs kept in the repository, the failures and
//! the case in progress under the target directory.

use std::fs;
use std::path::{Path, PathBuf};

/// Every file of `regressions/<target>/` with its name, sorted by name.
pub(crate) fn regressions(manifest_dir: &Path, target: &str) -> Vec<(String, Vec<u8>)> {
    let dir = manifest_dir.join("regressions").join(target);
    let Ok(entries) = fs::read_dir(&dir) else {
        return Vec::new();
    };
    let mut files: Vec<PathBuf> = entries
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.is_file())
        .collect();
    files.sort();
    files
        .into_iter()
        .filter_map(|p| {
            let name = p.file_name()?.to_string_lossy().into_owned();
            fs::read(&p).ok().map(|b| (name, b))
        })
        .collect()
}

/// The folder for this target's failures and its case in progress: `<tmp>/fuzz/<target>`,
/// where `tmp` is the test's `CARGO_TARGET_TMPDIR`.
pub(crate) fn work_dir(tmp: &Path, target: &str) -> PathBuf {
    let dir = tmp.join("fuzz").join(target);
    let _ = fs::create_dir_all(&dir);
    dir
}

/// Writes a failing input as `<dir>/<fnv-hash>.bin`; returns its path.
pub(crate) fn save_failure(dir: &Path, bytes: &[u8]) -> PathBuf {
    let path = dir.join(format!("{:016x}.bin", fnv1a(bytes)));
    let _ = fs::write(&path, bytes);
    path
}

fn fnv1a(bytes: &[u8]) -> u64 {
    bytes.iter().fold(0xcbf2_9ce4_8422_2325u64, |h, &b| {
        (h ^ u64::from(b)).wrapping_mul(0x0100_0000_01b3)
    })
}
