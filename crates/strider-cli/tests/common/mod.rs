//! Helpers shared by the end-to-end tests of the `strider` binary.

#![allow(dead_code)] // each test crate uses a subset

use std::path::PathBuf;
use std::process::{Command, Output};

/// Runs the `strider` binary built for these tests with `args`.
pub fn strider(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_strider"))
        .args(args)
        .output()
        .expect("run strider")
}

/// A fresh directory under the system temp dir, unique per test crate (`prefix`), process and
/// test (`name`).
pub fn temp_dir(prefix: &str, name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("strider-{prefix}-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

/// The process's stderr as text.
pub fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

/// The error contract: exit code 1 and exactly one line on stderr starting with `error: `;
/// returns the line.
pub fn one_line_error(o: &Output) -> String {
    let e = stderr(o);
    assert_eq!(o.status.code(), Some(1), "stderr: {e}");
    assert_eq!(
        e.trim_end().lines().count(),
        1,
        "one line expected, got: {e}"
    );
    assert!(e.starts_with("error: "), "{e}");
    e
}
