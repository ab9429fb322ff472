//! Golden missions: short missions of every exploration strategy on several scenarios, world
//! seeds and seeds, whose `report.json` must stay the same (apart from wall-clock fields) as
//! the code is reorganised. A change of behaviour that is intended rewrites the files with
//! `STRIDER_BLESS=1 cargo test -p strider-cli --test golden` in a commit of its own that
//! says why.

use serde_json::Value;
use std::path::{Path, PathBuf};

mod common;
use common::{stderr, strider, temp_dir};

/// (name, scenario, world seed, strategy, seed, simulated time limit in s).
const MISSIONS: [(&str, &str, &str, &str, &str, &str); 6] = [
    (
        "gtsp-courtyard-small",
        "courtyard-small",
        "1",
        "gtsp",
        "1",
        "200",
    ),
    (
        "greedy-courtyard-small",
        "courtyard-small",
        "2",
        "greedy",
        "3",
        "200",
    ),
    (
        "spatial-only-courtyard-large",
        "courtyard-large",
        "1",
        "spatial-only",
        "2",
        "150",
    ),
    (
        "rbcm-greedy-lab-track",
        "lab-track",
        "1",
        "rbcm-greedy",
        "1",
        "150",
    ),
    (
        "escape-escape-arena",
        "escape-arena",
        "1",
        "escape",
        "1",
        "200",
    ),
    (
        "rigid-escape-arena",
        "escape-arena",
        "1",
        "rigid",
        "2",
        "120",
    ),
];

/// Drops what depends on the machine and its load: wall-clock durations and rates.
fn without_wall_clock(v: &mut Value) {
    match v {
        Value::Object(map) => {
            map.retain(|k, _| !(k.contains("wall") || k.ends_with("_ms") || k == "speedup"));
            map.values_mut().for_each(without_wall_clock);
        }
        Value::Array(items) => items.iter_mut().for_each(without_wall_clock),
        _ => {}
    }
}

fn golden_file(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/golden")
        .join(format!("{name}.json"))
}

/// The first path at which `a` and `b` differ.
fn first_difference(a: &Value, b: &Value, at: &str) -> Option<String> {
    match (a, b) {
        (Value::Object(x), Value::Object(y)) => {
            let keys: std::collections::BTreeSet<&String> = x.keys().chain(y.keys()).collect();
            keys.into_iter().find_map(|k| match (x.get(k), y.get(k)) {
                (Some(p), Some(q)) => first_difference(p, q, &format!("{at}.{k}")),
                _ => Some(format!("{at}.{k}: present on one side only")),
            })
        }
        (Value::Array(x), Value::Array(y)) if x.len() == y.len() => x
            .iter()
            .zip(y)
            .enumerate()
            .find_map(|(i, (p, q))| first_difference(p, q, &format!("{at}[{i}]"))),
        _ if a == b => None,
        _ => Some(format!("{at}: {} != {}", short(a), short(b))),
    }
}

fn short(v: &Value) -> String {
    let s = v.to_string();
    if s.len() > 120 {
        format!("{}…", &s[..120])
    } else {
        s
    }
}

#[test]
fn golden_missions_are_unchanged() {
    let bless = std::env::var_os("STRIDER_BLESS").is_some();
    let mut failures = Vec::new();
    for (name, scenario, world_seed, strategy, seed, limit) in MISSIONS {
        let dir = temp_dir("golden", name);
        let o = strider(&[
            "run",
            "--scenario",
            scenario,
            "--world-seed",
            world_seed,
            "--strategy",
            strategy,
            "--seed",
            seed,
            "--time-limit",
            limit,
            "--out",
            dir.to_str().unwrap(),
        ]);
        assert!(o.status.success(), "{name}: {}", stderr(&o));
        let text = std::fs::read_to_string(dir.join("report.json")).unwrap();
        let mut report: Value = serde_json::from_str(&text).unwrap();
        without_wall_clock(&mut report);
        let file = golden_file(name);
        if bless {
            std::fs::write(&file, serde_json::to_string_pretty(&report).unwrap() + "\n").unwrap();
            continue;
        }
        let want: Value = serde_json::from_str(
            &std::fs::read_to_string(&file).unwrap_or_else(|e| panic!("{}: {e}", file.display())),
        )
        .unwrap();
        if let Some(d) = first_difference(&want, &report, name) {
            failures.push(d);
        }
    }
    assert!(
        failures.is_empty(),
        "golden missions changed:\n{}",
        failures.join("\n")
    );
}
