//! `strider bench table5` end to end, with missions cut short: every block of the table is
//! written, `--mcap-dir` records one MCAP file per trial, every finished trial is kept in
//! `OUT/trials`, and `--resume` runs only the missing trials and gives the same table.

mod common;
use common::{one_line_error, strider, temp_dir};
use serde_json::Value;
use std::path::Path;

/// `strider bench table5` of one trial per row, 20 s missions, into `out`, with `extra` flags.
fn table5(out: &Path, extra: &[&str]) -> std::process::Output {
    let mut args = vec![
        "bench",
        "table5",
        "--trials",
        "1",
        "--world-seeds",
        "1",
        "--jobs",
        "2",
        "--time-limit",
        "20",
        "--out",
        out.to_str().unwrap(),
    ];
    args.extend_from_slice(extra);
    strider(&args)
}

fn read_json(file: &Path) -> Value {
    serde_json::from_str(&std::fs::read_to_string(file).unwrap()).unwrap()
}

/// Drops what depends on the machine and its load: wall-clock durations and latencies.
fn without_wall_clock(v: &mut Value) {
    match v {
        Value::Object(map) => {
            map.retain(|k, _| !(k.contains("wall") || k.contains("_ms")));
            map.values_mut().for_each(without_wall_clock);
        }
        Value::Array(items) => items.iter_mut().for_each(without_wall_clock),
        _ => {}
    }
}

#[test]
fn a_short_table5_writes_every_block_records_each_trial_and_resumes() {
    let dir = temp_dir("table5", "short");
    let (out, mcap) = (dir.join("out"), dir.join("mcap"));
    let o = table5(&out, &["--mcap-dir", mcap.to_str().unwrap()]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let md = std::fs::read_to_string(out.join("table5.md")).unwrap();
    let json: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("table5.json")).unwrap()).unwrap();
    assert!(json.is_object());
    for row in [
        "large tour proposed",
        "large tour spatial-only",
        "large exploration proposed",
        "large exploration spatial-only",
    ] {
        assert!(md.contains(row), "{row} missing from table5.md");
    }
    // One recording per trial: small gtsp and greedy, large gtsp and spatial-only.
    let mut files: Vec<String> = std::fs::read_dir(&mcap)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    files.sort();
    assert_eq!(
        files,
        [
            "courtyard-large-gtsp-w1-s1.mcap",
            "courtyard-large-spatial-only-w1-s1.mcap",
            "courtyard-small-greedy-w1-s1.mcap",
            "courtyard-small-gtsp-w1-s1.mcap",
        ]
    );
    for f in &files {
        let bytes = std::fs::read(mcap.join(f)).unwrap();
        assert!(
            bytes.starts_with(b"\x89MCAP0\r\n"),
            "{f} is not an MCAP file"
        );
        assert!(bytes.ends_with(b"\x89MCAP0\r\n"), "{f} is not closed");
    }
    resume_runs_the_missing_trials_only(&dir, &out);
}

/// An interrupted table (here: two of its four trial files kept) resumed gives the table of
/// the uninterrupted run `done`; the kept trials are reused as they were.
fn resume_runs_the_missing_trials_only(dir: &Path, done: &Path) {
    let out = dir.join("resumed");
    std::fs::create_dir_all(out.join("trials")).unwrap();
    for kept in ["courtyard-small-gtsp-w1-s1", "courtyard-large-gtsp-w1-s1"] {
        let name = format!("{kept}.json");
        std::fs::copy(
            done.join("trials").join(&name),
            out.join("trials").join(&name),
        )
        .unwrap();
    }
    let o = table5(&out, &["--resume"]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let (mut want, mut got) = (
        read_json(&done.join("table5.json")),
        read_json(&out.join("table5.json")),
    );
    assert_eq!(got["complete"], true);
    // The kept trials were read back, not run again: even their wall times are the same.
    let wall = |v: &Value, strategy: &str, scenario: &str| {
        v["trial_results"]
            .as_array()
            .unwrap()
            .iter()
            .find(|t| t["strategy"] == strategy && t["scenario"] == scenario)
            .map(|t| t["wall_s"].clone())
    };
    for scenario in ["courtyard-small", "courtyard-large"] {
        assert_eq!(wall(&want, "gtsp", scenario), wall(&got, "gtsp", scenario));
    }
    without_wall_clock(&mut want);
    without_wall_clock(&mut got);
    assert_eq!(want, got, "the resumed table differs");
    let table = |p: &Path| -> Vec<String> {
        std::fs::read_to_string(p.join("table5.md"))
            .unwrap()
            .lines()
            .filter(|l| !l.contains(" wall") && !l.contains(" ms"))
            .map(str::to_string)
            .collect()
    };
    assert_eq!(table(done), table(&out));

    // Kept trials of another setting are refused rather than mixed into the table.
    let e = one_line_error(&strider(&[
        "bench",
        "table5",
        "--trials",
        "1",
        "--world-seeds",
        "1",
        "--time-limit",
        "30",
        "--resume",
        "--out",
        out.to_str().unwrap(),
    ]));
    assert!(e.contains("resume with the options"), "{e}");
}

#[test]
fn bad_table5_options_are_one_line_errors() {
    let e = one_line_error(&strider(&["bench", "table5", "--trials", "0"]));
    assert!(e.contains("--trials"), "{e}");
    let e = one_line_error(&strider(&["bench", "table5", "--time-limit=-3"]));
    assert!(e.contains("--time-limit"), "{e}");
    let e = one_line_error(&strider(&[
        "bench",
        "table5",
        "--trials",
        "18446744073709551615",
    ]));
    assert!(
        e.contains("'18446744073709551615' for '--trials <TRIALS>'")
            && e.contains("from 1 to 10000"),
        "{e}"
    );
}

#[test]
fn set_applies_strategy_parameters_to_every_trial_and_is_checked() {
    let dir = temp_dir("table5", "set");
    let out = dir.join("t5");
    let o = table5(&out, &["--large-trials", "0", "--set", "look_around=false"]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let json = read_json(&out.join("table5.json"));
    assert_eq!(json["set"], serde_json::json!([["look_around", "false"]]));
    let md = std::fs::read_to_string(out.join("table5.md")).unwrap();
    assert!(md.contains("`--set look_around=false`"), "{md}");
    // The kept trials were made with the parameter: resuming without it is refused.
    let e = one_line_error(&table5(&out, &["--large-trials", "0", "--resume"]));
    assert!(e.contains("resume with the options"), "{e}");

    let e = one_line_error(&table5(&out, &["--set", "look_around=maybe"]));
    assert!(
        e.contains("look_around") && e.contains("true or false"),
        "{e}"
    );
    let e = one_line_error(&table5(&out, &["--set", "no_such_key=1"]));
    assert!(e.contains("`no_such_key` is not a parameter"), "{e}");
    let e = one_line_error(&table5(&out, &["--set", "look_around"]));
    assert!(e.contains("expected KEY=VALUE"), "{e}");
    let _ = std::fs::remove_dir_all(&dir);
}
