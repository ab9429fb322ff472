//! End-to-end tests of `strider run --strategy rbcm-greedy` (the Prágr19 explorer): a whole
//! exploration of `lab-track` that must end by Eq. 16 with the terrains learned in the right
//! order, determinism, the planning figures in the report, and the one-line errors.

mod common;

use common::{one_line_error, strider, temp_dir};
use serde_json::Value;

fn run(dir: &std::path::Path, extra: &[&str]) -> Value {
    let out = dir.to_str().unwrap();
    let mut args = vec![
        "run",
        "--scenario",
        "lab-track",
        "--strategy",
        "rbcm-greedy",
        "-o",
        out,
    ];
    args.extend_from_slice(extra);
    let o = strider(&args);
    assert!(o.status.success(), "{}", common::stderr(&o));
    let text = std::fs::read_to_string(dir.join("report.json")).unwrap();
    serde_json::from_str(&text).unwrap()
}

fn mean_of(r: &Value, terrain: &str) -> f64 {
    r["terrains"]
        .as_array()
        .unwrap()
        .iter()
        .find(|t| t["terrain"] == terrain)
        .and_then(|t| t["predicted_mean"].as_f64())
        .unwrap_or_else(|| panic!("no prediction for {terrain}"))
}

#[test]
fn explores_lab_track_and_learns_easy_and_hard_terrain() {
    // World 10 is the quickest of the ten seeds measured (about 260 s simulated).
    let dir = temp_dir("rbcm", "full");
    let r = run(&dir, &["--world-seed", "10", "--seed", "10"]);
    assert_eq!(r["termination"], "GoalsCleared", "{}", r["termination"]);
    assert_eq!(r["terrains_learned"], true);
    let easy = ["flat", "grass", "carpet"].map(|t| mean_of(&r, t));
    let hard = ["cubes", "stairs"].map(|t| mean_of(&r, t));
    let easy_max = easy.iter().copied().fold(f64::NEG_INFINITY, f64::max);
    let hard_min = hard.iter().copied().fold(f64::INFINITY, f64::min);
    assert!(easy_max < hard_min, "easy {easy:?} hard {hard:?}");
    // Committee of m_max = 50 experts; every pair stored came from a walking window.
    let pairs = r["learning_pairs"].as_u64().unwrap();
    let experts = r["experts"].as_array().unwrap();
    assert!(pairs >= 25, "{pairs} pairs");
    assert_eq!(experts.len() as u64, pairs.div_ceil(50));
    // Planning figures are printed per part; the total is their sum.
    let pm = &r["planning_ms"];
    assert!(pm["all"]["cycles"].as_u64().unwrap() > 10);
    assert!(pm["all"]["median"].as_f64().unwrap() > 0.0);
    assert!(pm["max_traversable_cells"].as_u64().unwrap() > 500);
    for p in r["plans"].as_array().unwrap() {
        let parts = ["trv_ms", "inference_ms", "goals_ms", "path_ms"]
            .map(|k| p[k].as_f64().unwrap())
            .iter()
            .sum::<f64>();
        assert!((parts - p["total_ms"].as_f64().unwrap()).abs() < 1e-6);
    }
    // The last planning cycle found no goal (Eq. 16: ν* = ∅).
    let last = r["plans"].as_array().unwrap().last().unwrap();
    assert!(last["goal"].is_null());
    for f in ["mcost_mean.png", "mcost_std.png", "rbcm_planning.png"] {
        assert!(dir.join(f).exists(), "{f}");
    }
}

#[test]
fn same_seed_same_exploration() {
    let a = run(
        &temp_dir("rbcm", "det-a"),
        &["--world-seed", "3", "--seed", "3", "--time-limit", "120"],
    );
    let b = run(
        &temp_dir("rbcm", "det-b"),
        &["--world-seed", "3", "--seed", "3", "--time-limit", "120"],
    );
    assert_eq!(a["samples"], b["samples"]);
    assert_eq!(a["trajectory"], b["trajectory"]);
    assert_eq!(a["terrains"], b["terrains"]);
}

#[test]
fn regular_gait_uses_its_own_threshold() {
    let r = run(
        &temp_dir("rbcm", "regular"),
        &["--gait", "regular", "--time-limit", "60"],
    );
    assert_eq!(r["gait"], "regular");
    assert_eq!(r["lambda_score"].as_f64(), Some(0.0005));
    assert_eq!(r["termination"], "TimeLimit");
}

#[test]
fn bad_requests_fail_with_one_line() {
    let d = temp_dir("rbcm", "bad");
    let out = d.to_str().unwrap();
    let e = one_line_error(&strider(&[
        "run",
        "--scenario",
        "lab-track",
        "--strategy",
        "rbcm-greedy",
        "--gait",
        "trot",
        "-o",
        out,
    ]));
    assert!(
        e.contains("\"trot\" is not a gait") && e.contains("adaptive"),
        "{e}"
    );
    // A world where no terrain makes the robot roll: the strategy runs (the robot reports roll)
    // and the run says that the cost is the same everywhere.
    let o = strider(&[
        "run",
        "--scenario",
        "courtyard-small",
        "--strategy",
        "rbcm-greedy",
        "--time-limit",
        "20",
        "-o",
        out,
    ]);
    assert!(o.status.success(), "{}", common::stderr(&o));
    assert!(
        common::stderr(&o).contains("no terrain makes the robot roll"),
        "{}",
        common::stderr(&o)
    );
    // --gait is rbcm-greedy's parameter; the Prágr22 strategies choose gaits themselves.
    let e = one_line_error(&strider(&[
        "run",
        "--scenario",
        "lab-track",
        "--strategy",
        "gtsp",
        "--gait",
        "regular",
        "-o",
        out,
    ]));
    assert!(e.contains("`gait` is not a parameter"), "{e}");
}
