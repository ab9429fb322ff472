//! End-to-end tests of `strider tours` (MartinCorke repeated tours): its tables and figures,
//! and its one-line errors on bad tours.

use std::path::Path;

mod common;
use common::{one_line_error, stderr, strider, temp_dir};

use serde_json::Value;

fn json(path: &Path) -> Value {
    let text = std::fs::read_to_string(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    serde_json::from_str(&text).unwrap()
}

fn is_png(path: &Path) -> bool {
    std::fs::read(path).is_ok_and(|b| b.starts_with(b"\x89PNG\r\n\x1a\n"))
}

/// Runs `strider tours ARGS --out OUT` and checks that it succeeded.
fn run_tours(out: &Path, args: &[&str]) {
    let mut all = vec!["tours"];
    all.extend_from_slice(args);
    all.extend(["--out", out.to_str().unwrap()]);
    let o = strider(&all);
    assert!(o.status.success(), "{}", stderr(&o));
}

#[test]
fn tours_write_tables_and_figures() {
    let dir = temp_dir("tours", "run");
    let out = dir.to_str().unwrap();
    let o = strider(&["tours", "--tours", "5", "--out", out]);
    assert!(o.status.success(), "{}", stderr(&o));
    let stdout = String::from_utf8_lossy(&o.stdout);
    assert!(
        stdout.contains("energy-arena") && stdout.contains("tour 1"),
        "{stdout}"
    );

    let r = json(&dir.join("tours.json"));
    let tours = r["tours"].as_array().unwrap();
    assert_eq!(tours.len(), 5);
    assert_eq!(r["always_shortest"].as_array().unwrap().len(), 5);
    let s = &r["summary"];
    assert_eq!(s["acceptance"]["first_tour_is_shortest"], Value::Bool(true));
    // Same robot, same noise seed, same first plan: the same first tour energy.
    assert_eq!(tours[0]["energy_j"], r["always_shortest"][0]["energy_j"]);
    for t in tours {
        let e = t["energy_j"].as_f64().unwrap();
        assert!(e.is_finite() && e > 10.0, "{t}");
        assert!(t["samples"].as_u64().unwrap() > 50, "{t}");
    }
    // Tour 1 learnt and refitted with hyperparameters inside the bounds.
    let l = tours[0]["fit"]["lengthscale"].as_f64().unwrap();
    let bounds = r["params"]["lengthscale_bounds_m"].as_array().unwrap();
    assert!(l >= bounds[0].as_f64().unwrap() && l <= bounds[1].as_f64().unwrap());
    assert_eq!(r["published"]["first_tour_j"].as_f64(), Some(28.7));

    let series = json(&dir.join("energy_per_tour.json"));
    assert_eq!(series["exploring_j"].as_array().unwrap().len(), 5);
    assert_eq!(
        series["cumulative_always_shortest_j"]
            .as_array()
            .unwrap()
            .len(),
        5
    );

    let md = std::fs::read_to_string(dir.join("tours.md")).unwrap();
    assert!(md.contains("28.7 J") && md.contains("| 5 |"), "{md}");
    for f in [
        "energy_per_tour.png",
        "cumulative_energy.png",
        "cumulative_difference.png",
        "map_truth.png",
        "map_after_tour_01.png",
        "map_after_tour_05.png",
    ] {
        assert!(is_png(&dir.join(f)), "{f}");
    }
    assert!(!dir.join("map_after_tour_10.png").exists());
}

#[test]
fn several_seeds_are_counted_and_runs_repeat() {
    let dir = temp_dir("tours", "seeds");
    let out = dir.to_str().unwrap();
    let o = strider(&[
        "tours", "--tours", "2", "--seeds", "2", "--seed", "4", "--out", out,
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let s = json(&dir.join("summary.json"));
    assert_eq!(s["counts"]["of"].as_u64(), Some(2));
    assert_eq!(s["counts"]["first_tour_is_shortest"].as_u64(), Some(2));
    assert_eq!(s["seeds"], serde_json::json!([4, 5]));
    let a = json(&dir.join("seed-4/energy_per_tour.json"));
    let b = json(&dir.join("seed-5/energy_per_tour.json"));
    assert_ne!(a["exploring_j"], b["exploring_j"], "different noise seeds");
    assert!(
        std::fs::read_to_string(dir.join("summary.md"))
            .unwrap()
            .contains("of 2")
    );

    // The same seed again gives the same tours.
    let again = temp_dir("tours", "seeds-again");
    run_tours(&again, &["--tours", "2", "--seed", "4"]);
    assert_eq!(json(&again.join("energy_per_tour.json")), a);
}

#[test]
fn several_worlds_are_pooled() {
    let dir = temp_dir("tours", "worlds");
    let out = dir.to_str().unwrap();
    run_tours(
        &dir,
        &[
            "--tours",
            "2",
            "--world-seed",
            "3",
            "--world-seeds",
            "2",
            "--seeds",
            "2",
        ],
    );
    let w = json(&dir.join("worlds.json"));
    assert_eq!(w["runs"].as_u64(), Some(4));
    assert_eq!(w["world_seeds"], serde_json::json!([3, 4]));
    assert_eq!(w["per_world"].as_array().unwrap().len(), 2);
    let o_runs = w["overtaking"]["runs"].as_u64().unwrap();
    assert_eq!(o_runs + w["overtaking"]["never"].as_u64().unwrap(), 4);
    // Each world keeps its own per-seed reports and summary, made by its own command.
    let a = json(&dir.join("world-3/seed-1/tours.json"));
    assert_eq!(a["world_seed"].as_u64(), Some(3));
    assert!(dir.join("world-4/seed-2/tours.json").exists());
    let summary = std::fs::read_to_string(dir.join("world-4/summary.md")).unwrap();
    assert!(
        summary.contains("--world-seed 4 --seed 1 --seeds 2"),
        "{summary}"
    );
    let md = std::fs::read_to_string(dir.join("worlds.md")).unwrap();
    assert!(
        md.contains("--world-seed 3 --seed 1 --world-seeds 2 --seeds 2 --tours 2")
            && md.contains("28.7 J")
            && md.contains("| 4 | 2 |"),
        "{md}"
    );
    // The same world and seed alone gives the same tours.
    let alone = temp_dir("tours", "worlds-alone");
    run_tours(&alone, &["--tours", "2", "--world-seed", "3"]);
    assert_eq!(
        json(&alone.join("energy_per_tour.json")),
        json(&dir.join("world-3/seed-1/energy_per_tour.json"))
    );
    // Too many runs, or a world range past the last seed, are refused before any run.
    let e = one_line_error(&strider(&[
        "tours",
        "--world-seeds",
        "1000",
        "--seeds",
        "11",
        "--out",
        out,
    ]));
    assert!(e.contains("10000 runs"), "{e}");
    let e = one_line_error(&strider(&[
        "tours",
        "--world-seed",
        "18446744073709551615",
        "--world-seeds",
        "2",
        "--out",
        out,
    ]));
    assert!(e.contains("--world-seeds 2"), "{e}");
}

#[test]
fn bad_tours_give_one_line_errors() {
    let dir = temp_dir("tours", "bad");
    let scen = dir.join("scenario");
    let o = strider(&[
        "scenario",
        "export",
        "energy-arena",
        "--out",
        scen.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let toml = std::fs::read_to_string(scen.join("scenario.toml")).unwrap();
    let (head, tours) = toml.split_once("[[tours]]").unwrap();
    // The waypoints' coordinate lines, in order.
    let coords: Vec<&str> = tours
        .lines()
        .filter(|l| l.starts_with("x = ") || l.starts_with("y = "))
        .collect();
    assert_eq!(coords.len(), 8);
    let write = |name: &str, tours: String| {
        let p = scen.join(name);
        std::fs::write(&p, format!("{head}[[tours]]{tours}")).unwrap();
        p
    };
    let out = dir.join("out");
    let out = out.to_str().unwrap();

    // Waypoint 2 becomes a copy of waypoint 1.
    let dup = tours
        .replacen(coords[4], coords[2], 1)
        .replacen(coords[5], coords[3], 1);
    let p = write("dup.toml", dup);
    let e = one_line_error(&strider(&[
        "tours",
        "-s",
        p.to_str().unwrap(),
        "--out",
        out,
    ]));
    assert!(e.contains("waypoints 1 and 2 are duplicates"), "{e}");

    // Waypoint 3 moves into the border wall: inside the world, outside the drivable area.
    // (Waypoints may share a coordinate, so the line is found by position, not by text.)
    let mut xs = 0;
    let far: String = tours
        .split_inclusive('\n')
        .map(|l| {
            if l.starts_with("x = ") {
                xs += 1;
                if xs == 4 {
                    return "x = 1.98\n".to_string();
                }
            }
            l.to_string()
        })
        .collect();
    let p = write("far.toml", far);
    let e = one_line_error(&strider(&[
        "tours",
        "-s",
        p.to_str().unwrap(),
        "--out",
        out,
    ]));
    assert!(e.contains("waypoint 3") && e.contains("unreachable"), "{e}");

    let e = one_line_error(&strider(&["tours", "--seeds", "0", "--out", out]));
    assert!(e.contains("--seeds"), "{e}");
    let e = one_line_error(&strider(&["tours", "--tours", "0", "--out", out]));
    assert!(e.contains("--tours"), "{e}");
    let e = one_line_error(&strider(&["tours", "-s", "no-such-world", "--out", out]));
    assert!(e.contains("no-such-world"), "{e}");
}
