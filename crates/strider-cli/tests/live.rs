//! `--live` and `--rate` at the command line: bad values and a busy address are one-line errors
//! before anything runs; Ctrl-C during a paced live mission winds it down (report kept, exit
//! code 130) and the server stops with the command. The protocol itself is tested in
//! strider-experiments (`tests/live.rs`).

mod common;

use std::io::{BufRead, BufReader};
use std::net::{TcpListener, TcpStream};
use std::process::{Command, Stdio};
use std::sync::mpsc;
use std::time::{Duration, Instant};

use common::{one_line_error, strider, temp_dir};

/// The longest any wait of these tests lasts before it fails (a stuck command, not a timing).
const PATIENCE: Duration = Duration::from_secs(120);

#[test]
fn bad_rates_and_addresses_are_refused_with_the_range() {
    for bad in ["0", "-2", "1e9", "NaN"] {
        let e = one_line_error(&strider(&["run", "--rate", bad]));
        assert!(
            e.contains("--rate") && e.contains("from 0.01 to 1e4"),
            "{e}"
        );
    }
    // A bare --live before the positional log takes the log for its address.
    let e = one_line_error(&strider(&[
        "replay", "--live", "log.mcap", "--config", "c.toml",
    ]));
    assert!(e.contains("'log.mcap'") && e.contains("--live=ADDR"), "{e}");
}

#[test]
fn a_busy_address_is_one_line_and_makes_no_output_directory() {
    let busy = TcpListener::bind("127.0.0.1:0").unwrap();
    let addr = busy.local_addr().unwrap().to_string();
    let dir = temp_dir("live", "busy");
    let out = dir.join("out");
    let e = one_line_error(&strider(&[
        "run",
        "--time-limit",
        "5",
        "--out",
        out.to_str().unwrap(),
        "--live",
        &addr,
    ]));
    assert!(
        e.contains(&format!("live view: cannot serve on {addr}")),
        "{e}"
    );
    assert!(!out.exists(), "no output directory");
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn ctrl_c_during_a_paced_live_run_keeps_the_report_and_stops_the_server() {
    let dir = temp_dir("live", "interrupt");
    let out = dir.join("out");
    let mut child = Command::new(env!("CARGO_BIN_EXE_strider"))
        .args(["run", "--time-limit", "100000", "--rate", "1"])
        .arg("--out")
        .arg(&out)
        .args(["--live", "127.0.0.1:0"])
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    // The first line on stderr says where the view is served.
    let mut lines = BufReader::new(child.stderr.take().unwrap()).lines();
    let (tx, rx) = mpsc::channel();
    let reader = std::thread::spawn(move || {
        for l in lines.by_ref() {
            let _ = tx.send(l.unwrap());
        }
    });
    let first = rx
        .recv_timeout(PATIENCE)
        .expect("a line about the live view");
    let url = first
        .split_whitespace()
        .find(|w| w.starts_with("ws://"))
        .unwrap_or_else(|| panic!("no ws:// address in {first:?}"))
        .trim_end_matches(':');
    let addr = url.trim_start_matches("ws://");
    assert!(first.contains("Foxglove WebSocket"), "{first}");
    TcpStream::connect(addr).expect("the live view accepts connections");

    let kill = Command::new("kill")
        .args(["-INT", &child.id().to_string()])
        .status()
        .unwrap();
    assert!(kill.success());
    let start = Instant::now();
    let status = loop {
        if let Some(s) = child.try_wait().unwrap() {
            break s;
        }
        assert!(start.elapsed() < PATIENCE, "the command did not wind down");
        std::thread::sleep(Duration::from_millis(50));
    };
    reader.join().unwrap();
    let rest: Vec<String> = rx.try_iter().collect();
    assert_eq!(status.code(), Some(130), "stderr: {first} {rest:?}");
    assert!(
        rest.last()
            .is_some_and(|l| l.starts_with("interrupted: kept the report")),
        "{rest:?}"
    );
    assert!(TcpStream::connect(addr).is_err(), "the server stopped");
    let report: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("report.json")).unwrap()).unwrap();
    assert_eq!(report["interrupted"], true);
    let _ = std::fs::remove_dir_all(&dir);
}
