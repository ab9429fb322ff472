//! Numeric flags out of their range are one-line errors naming the flag, the value and the
//! range, before anything runs (and before any output directory is made); a scenario without
//! the signal an objective needs is refused instead of giving a NaN cost.

mod common;
use common::{one_line_error, strider, temp_dir};

/// The error of `args` (one line, exit code 1), checked to name each of `parts`.
fn refused(args: &[&str], parts: &[&str]) -> String {
    let e = one_line_error(&strider(args));
    for p in parts {
        assert!(e.contains(p), "{args:?}: {p:?} missing from {e}");
    }
    e
}

#[test]
fn a_negative_time_limit_reaches_the_range_check() {
    refused(
        &["run", "--time-limit", "-1"],
        &["'-1'", "--time-limit", "> 0 and ≤ 1e6"],
    );
    refused(&["run", "--time-limit", "2e6"], &["'2e6'", "≤ 1e6"]);
}

#[test]
fn map_build_refuses_time_limits_that_are_not_positive() {
    let dir = temp_dir("flags", "map-build");
    let out = dir.join("map");
    for bad in ["-1", "0", "NaN", "inf"] {
        refused(
            &[
                "map",
                "build",
                &format!("--time-limit={bad}"),
                "--out",
                out.to_str().unwrap(),
            ],
            &[&format!("'{bad}'"), "--time-limit", "> 0"],
        );
    }
    refused(
        &[
            "map",
            "build",
            "--lane-spacing",
            "1e9",
            "--out",
            out.to_str().unwrap(),
        ],
        &["'1e9'", "--lane-spacing", "≤ 1e3"],
    );
    assert!(!out.exists(), "a refused command makes no output directory");
}

#[test]
fn counts_and_job_numbers_are_capped() {
    refused(
        &["tours", "--seeds", "18446744073709551615"],
        &["'18446744073709551615'", "--seeds", "from 1 to 1000"],
    );
    refused(&["tours", "--tours", "0"], &["--tours", "from 1 to 10000"]);
    for jobs in ["2000", "100000", "0", "-4"] {
        refused(
            &["navigate", "--jobs", jobs],
            &[&format!("'{jobs}'"), "--jobs", "from 1 to 256"],
        );
    }
    refused(&["navigate", "--runs", "0"], &["--runs", "from 1 to 1000"]);
    refused(
        &["navigate", "--lambda", "-1"],
        &["--lambda", "from 0 to 100"],
    );
    refused(
        &["bench", "compare", "--jobs", "257"],
        &["--jobs", "from 1 to 256"],
    );
    refused(
        &["learn", "bench", "--pairs", "1000000"],
        &["--pairs", "from 2 to 2000"],
    );
    refused(&["run", "--seed", "-1"], &["--seed", "from 0 to"]);
}

#[test]
fn an_objective_the_scenario_has_no_signal_for_is_refused() {
    let dir = temp_dir("flags", "objective");
    let out = dir.join("nav");
    refused(
        &[
            "navigate",
            "--scenario",
            "courtyard-small",
            "--runs",
            "1",
            "--objectives",
            "vibration",
            "--out",
            out.to_str().unwrap(),
        ],
        &[
            "--objectives vibration",
            "courtyard-small",
            "no vibration signal",
            "provides energy",
        ],
    );
    assert!(!out.exists());
}
