//! Interrupted work loses nothing: Ctrl-C during a recorded `strider run` leaves a finished,
//! readable MCAP file and a report marked incomplete, exit code 130 and one line saying what
//! was kept; a failed command removes the output directory it created.

mod common;

use std::path::Path;
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

use common::{one_line_error, stderr, strider, temp_dir};

/// Waits (polling) until `path` exists; false after `limit` (a stuck command, not a timing).
fn wait_for(path: &Path, limit: Duration) -> bool {
    let start = Instant::now();
    while !path.exists() {
        if start.elapsed() > limit {
            return false;
        }
        std::thread::sleep(Duration::from_millis(50));
    }
    true
}

/// Reads the whole MCAP file: every message parses and the summary section is there.
fn read_mcap(file: &Path) -> (usize, usize) {
    let bytes = std::fs::read(file).unwrap();
    let summary = mcap::Summary::read(&bytes)
        .expect("the summary parses")
        .expect("the file has a summary section (it was finished)");
    let mut messages = 0;
    for m in mcap::MessageStream::new(&bytes).unwrap() {
        m.expect("every message parses");
        messages += 1;
    }
    (messages, summary.channels.len())
}

#[test]
fn ctrl_c_during_a_recorded_run_keeps_a_readable_recording_and_a_partial_report() {
    let dir = temp_dir("interrupt", "run");
    let (out, file) = (dir.join("out"), dir.join("run.mcap"));
    let child = Command::new(env!("CARGO_BIN_EXE_strider"))
        .args([
            "run",
            "--scenario",
            "courtyard-large",
            "--time-limit",
            "100000",
        ])
        .arg("--out")
        .arg(&out)
        .arg("--mcap")
        .arg(&file)
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let part = dir.join("run.mcap.part");
    assert!(
        wait_for(&part, Duration::from_secs(120)),
        "the recording never started"
    );
    // Let the mission run a little, then Ctrl-C.
    std::thread::sleep(Duration::from_millis(1500));
    let kill = Command::new("kill")
        .args(["-INT", &child.id().to_string()])
        .status()
        .unwrap();
    assert!(kill.success());
    let o = child.wait_with_output().unwrap();
    let e = stderr(&o);
    assert_eq!(o.status.code(), Some(130), "stderr: {e}");
    assert_eq!(e.trim_end().lines().count(), 1, "one line: {e}");
    assert!(e.starts_with("interrupted: kept the report"), "{e}");
    assert!(e.contains("report.json") && e.contains("run.mcap"), "{e}");

    assert!(!part.exists(), "the .part file was renamed");
    let (messages, channels) = read_mcap(&file);
    assert!(messages > 0 && channels > 0, "{messages} messages");

    let report: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("report.json")).unwrap()).unwrap();
    assert_eq!(report["complete"], false);
    assert_eq!(report["interrupted"], true);
    assert_eq!(report["termination"], "Interrupted");
    let t = report["exploration_time_s"].as_f64().unwrap();
    assert!(t > 0.0 && t < 100_000.0, "{t}");
    assert!(out.join("report.html").exists());
}

#[test]
fn a_run_that_fails_removes_the_output_directory_it_created() {
    let dir = temp_dir("interrupt", "fail");
    let out = dir.join("new/run");
    // The recording cannot be created: the mission fails after the output directory was made.
    let missing = dir.join("no-such-dir/run.mcap");
    let e = one_line_error(&strider(&[
        "run",
        "--time-limit",
        "5",
        "--out",
        out.to_str().unwrap(),
        "--mcap",
        missing.to_str().unwrap(),
    ]));
    assert!(e.contains("run.mcap"), "{e}");
    assert!(
        !dir.join("new").exists(),
        "the empty output directory stayed"
    );
    assert!(dir.exists(), "a directory that existed before stays");
}
