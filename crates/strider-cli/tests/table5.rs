//! `strider bench table5` end to end, with missions cut short: every block of the table is
//! written, and `--mcap-dir` records one MCAP file per trial.

mod common;
use common::{one_line_error, strider, temp_dir};

#[test]
fn a_short_table5_writes_every_block_and_records_each_trial() {
    let dir = temp_dir("table5", "short");
    let (out, mcap) = (dir.join("out"), dir.join("mcap"));
    let o = strider(&[
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
        "--mcap-dir",
        mcap.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
    ]);
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
}

#[test]
fn bad_table5_options_are_one_line_errors() {
    let e = one_line_error(&strider(&["bench", "table5", "--trials", "0"]));
    assert!(e.contains("--trials"), "{e}");
    let e = one_line_error(&strider(&["bench", "table5", "--time-limit=-3"]));
    assert!(e.contains("--time-limit"), "{e}");
}
