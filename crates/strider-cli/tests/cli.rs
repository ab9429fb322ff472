//! End-to-end tests of the `strider` binary: the commands a user runs, their files, and their
//! one-line errors on bad input.

use std::path::PathBuf;

mod common;
use common::{one_line_error, stderr, strider, temp_dir};

#[test]
fn scenario_list_names_every_builtin() {
    let o = strider(&["scenario", "list"]);
    assert!(o.status.success());
    let out = String::from_utf8_lossy(&o.stdout);
    for name in [
        "courtyard-small",
        "courtyard-large",
        "lab-track",
        "escape-arena",
        "energy-arena",
        "bonn-paths",
    ] {
        assert!(
            out.lines().any(|l| l.starts_with(name)),
            "{name} missing from:\n{out}"
        );
    }
}

#[test]
fn scenario_render_writes_layers() {
    let dir = temp_dir("cli", "render");
    let o = strider(&[
        "scenario",
        "render",
        "lab-track",
        "--world-seed",
        "2",
        "--out",
        dir.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    for f in [
        "color.png",
        "elevation.png",
        "terrain.png",
        "passability.png",
        "tours.png",
        "render.json",
    ] {
        assert!(dir.join(f).is_file(), "{f} missing");
    }
    let legend: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(dir.join("render.json")).unwrap()).unwrap();
    assert_eq!(legend["world_seed"], 2);
    assert!(legend["terrains"].as_array().unwrap().len() >= 5);
}

fn export(name: &str, tag: &str) -> PathBuf {
    let dir = temp_dir("cli", tag);
    let o = strider(&["scenario", "export", name, "--out", dir.to_str().unwrap()]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(dir.join("scenario.toml").is_file());
    dir
}

#[test]
fn map_build_on_an_exported_scenario_writes_stats() {
    let scen = export("courtyard-small", "build-scen");
    let out = temp_dir("cli", "build-out");
    let o = strider(&[
        "map",
        "build",
        "--scenario",
        scen.join("scenario.toml").to_str().unwrap(),
        "--time-limit",
        "40",
        "--out",
        out.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let stats: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("map_stats.json")).unwrap())
            .unwrap();
    let f = |k: &str| {
        stats[k]
            .as_f64()
            .unwrap_or_else(|| panic!("{k} missing in {stats}"))
    };
    assert!(f("fused_points") > 1e5);
    assert!(f("points_per_second") > 0.0);
    // 40 s of driving sees only part of the courtyard, but what it sees it must see well.
    assert!(f("observed_fraction") > 0.9, "{stats}");
    assert!(f("elevation_rmse_m") < 0.01, "{stats}");
    assert!(f("passability_agreement") > 0.99, "{stats}");
    for png in [
        "color.png",
        "elevation.png",
        "passability.png",
        "admissible.png",
        "variance.png",
        "path.png",
    ] {
        assert!(out.join(png).is_file(), "{png} missing");
    }
}

#[test]
fn errors_are_one_line_and_name_the_problem() {
    let out = temp_dir("cli", "errors-out");
    let out_s = out.to_str().unwrap();

    // Unknown built-in and missing file.
    let e = one_line_error(&strider(&[
        "scenario",
        "render",
        "no-such-world",
        "--out",
        out_s,
    ]));
    assert!(
        e.contains("courtyard-small"),
        "should list the valid names: {e}"
    );
    let e = one_line_error(&strider(&[
        "map",
        "build",
        "--scenario",
        "/nonexistent/s.toml",
        "--out",
        out_s,
    ]));
    assert!(e.contains("/nonexistent/s.toml"), "{e}");

    // Malformed TOML: the error names the file, line and column.
    let scen = export("courtyard-small", "errors-scen");
    let toml_path = scen.join("scenario.toml");
    let text = std::fs::read_to_string(&toml_path).unwrap();
    std::fs::write(&toml_path, text.replacen("[world]", "[world\n", 1)).unwrap();
    let e = one_line_error(&strider(&[
        "scenario",
        "render",
        toml_path.to_str().unwrap(),
        "--out",
        out_s,
    ]));
    assert!(e.contains("scenario.toml:"), "{e}");

    // Wrong PNG depth: an 8-bit RGB image where the 16-bit elevation belongs.
    std::fs::write(&toml_path, &text).unwrap();
    std::fs::copy(scen.join("color.png"), scen.join("elevation.png")).unwrap();
    let e = one_line_error(&strider(&[
        "scenario",
        "render",
        toml_path.to_str().unwrap(),
        "--out",
        out_s,
    ]));
    assert!(e.contains("elevation.png") && e.contains("16-bit"), "{e}");

    // A robot without a range sensor cannot build a map.
    let e = one_line_error(&strider(&[
        "map",
        "build",
        "--scenario",
        "energy-arena",
        "--out",
        out_s,
    ]));
    assert!(e.contains("sensor"), "{e}");

    // Nonsense numbers are refused, not run.
    let e = one_line_error(&strider(&[
        "map",
        "build",
        "--lane-spacing=-1",
        "--out",
        out_s,
    ]));
    assert!(e.contains("lane-spacing"), "{e}");
}

/// A 6-vertex, 3-set GTSPLIB instance (EUC_2D): sets {1,2}, {3,4}, {5,6}. The best tour visits
/// vertices 1, 3, 5, the 3-4-5 triangle (0,0), (3,0), (0,4): 3 + 5 + 4 = 12.
const TINY: &str = "NAME: tiny6\nTYPE: GTSP\nDIMENSION: 6\nGTSP_SETS: 3\nEDGE_WEIGHT_TYPE: EUC_2D\n\
NODE_COORD_SECTION\n1 0 0\n2 -10 -10\n3 3 0\n4 30 0\n5 0 4\n6 0 40\n\
GTSP_SET_SECTION\n1 1 2 -1\n2 3 4 -1\n3 5 6 -1\nEOF\n";

#[test]
fn gtsp_solve_prints_one_json_object_with_a_feasible_tour() {
    let dir = temp_dir("cli", "gtsp-solve");
    let f = dir.join("tiny6.gtsp");
    std::fs::write(&f, TINY).unwrap();
    let o = strider(&[
        "gtsp",
        "solve",
        f.to_str().unwrap(),
        "--time-limit",
        "1",
        "--json",
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let out = String::from_utf8_lossy(&o.stdout);
    assert_eq!(out.trim().lines().count(), 1, "{out}");
    let v: serde_json::Value = serde_json::from_str(out.trim()).unwrap();
    assert_eq!(v["cost"], 12);
    let mut tour: Vec<u64> = v["tour"]
        .as_array()
        .unwrap()
        .iter()
        .map(|x| x.as_u64().unwrap())
        .collect();
    tour.sort();
    assert_eq!(tour, vec![1, 3, 5], "1-based ids, one per set");
    assert!(v["time_s"].as_f64().unwrap() >= 0.0);
    // Object keys in the documented order.
    assert!(
        out.find("\"cost\"") < out.find("\"tour\"")
            && out.find("\"tour\"") < out.find("\"time_s\"")
    );
}

#[test]
fn gtsp_bench_reports_gaps_and_a_summary_line() {
    let dir = temp_dir("cli", "gtsp-bench");
    std::fs::write(dir.join("tiny6.gtsp"), TINY).unwrap();
    std::fs::write(
        dir.join("best_known.csv"),
        "instance,sets,vertices,best_known,source\ntiny6,3,6,12,hand\n",
    )
    .unwrap();
    let json = dir.join("bench.json");
    let o = strider(&[
        "gtsp",
        "bench",
        dir.to_str().unwrap(),
        "--time-limit",
        "1",
        "--runs",
        "2",
        "--json",
        json.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let out = String::from_utf8_lossy(&o.stdout);
    let last = out.trim().lines().last().unwrap();
    assert!(
        last.starts_with("instances=1 mean_gap_pct=0.0000 max_gap_pct=0.0000 total_s="),
        "{last}"
    );
    let v: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(json).unwrap()).unwrap();
    assert_eq!(v["instances"][0]["costs"], serde_json::json!([12, 12]));

    // A malformed instance: the error names the file and the line.
    std::fs::write(dir.join("tiny6.gtsp"), TINY.replace("3 3 0", "3 3 zero")).unwrap();
    let e = one_line_error(&strider(&[
        "gtsp",
        "bench",
        dir.to_str().unwrap(),
        "--time-limit",
        "1",
    ]));
    assert!(e.contains("tiny6.gtsp") && e.contains("line 9"), "{e}");
}

#[test]
fn gp_predict_writes_mean_and_variance_and_reports_bad_rows() {
    let dir = temp_dir("cli", "gp-predict");
    let (train, query, out, timing) = (
        dir.join("train.csv"),
        dir.join("query.csv"),
        dir.join("pred.csv"),
        dir.join("timing.json"),
    );
    // One training point at x = 0 with y = 1; defaults: SE, l = 0.4, σ_s² = 1, σ_n² = 0.25.
    std::fs::write(&train, "x,y\n0.0,1.0\n").unwrap();
    std::fs::write(&query, "x\n0.0\n0.4\n").unwrap();
    let o = strider(&[
        "gp",
        "predict",
        "--train",
        train.to_str().unwrap(),
        "--query",
        query.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
        "--timing-json",
        timing.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let text = std::fs::read_to_string(&out).unwrap();
    let mut lines = text.lines();
    assert_eq!(lines.next(), Some("mean,variance"));
    let rows: Vec<(f64, f64)> = lines
        .map(|l| {
            let (a, b) = l.split_once(',').unwrap();
            (a.parse().unwrap(), b.parse().unwrap())
        })
        .collect();
    // At x = 0: mean = 1/1.25 = 0.8, variance = 1 − 1/1.25 = 0.2. At x = 0.4 (r = 1):
    // k = e^(−1/2), mean = k/1.25, variance = 1 − k²/1.25.
    let k = (-0.5f64).exp();
    let want = [(0.8, 0.2), (k / 1.25, 1.0 - k * k / 1.25)];
    assert_eq!(rows.len(), 2);
    for (r, w) in rows.iter().zip(want) {
        assert!(
            (r.0 - w.0).abs() < 1e-15 && (r.1 - w.1).abs() < 1e-15,
            "{r:?} vs {w:?}"
        );
    }
    let v: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&timing).unwrap()).unwrap();
    assert_eq!(
        (v["n_train"].as_u64(), v["n_query"].as_u64()),
        (Some(1), Some(2))
    );
    assert!(v["fit_s"].as_f64().unwrap() >= 0.0 && v["predict_s"].as_f64().unwrap() >= 0.0);

    // Bad rows: the error names the file, the line and the problem.
    for (content, needle) in [
        ("x,y\n0.0,1.0\n0.5\n", "line 3: 1 columns"),
        ("x,y\n0.0,one\n", "line 2: field 2 \"one\" is not a number"),
        ("x,y\n0.0,NaN\n", "line 2: field 2 is NaN"),
    ] {
        std::fs::write(&train, content).unwrap();
        let e = one_line_error(&strider(&[
            "gp",
            "predict",
            "--train",
            train.to_str().unwrap(),
            "--query",
            query.to_str().unwrap(),
            "--out",
            out.to_str().unwrap(),
        ]));
        assert!(e.contains("train.csv") && e.contains(needle), "{e}");
    }
}

/// A short mission: it runs, writes a report with both gait models, and the same seed gives
/// the same mission (trajectory, models, termination).
#[test]
fn run_writes_a_deterministic_report() {
    let d = temp_dir("cli", "run");
    let mut reports = Vec::new();
    for k in 0..2 {
        let out = d.join(format!("r{k}"));
        let o = strider(&[
            "run",
            "--time-limit",
            "15",
            "--seed",
            "3",
            "--out",
            out.to_str().unwrap(),
        ]);
        assert!(o.status.success(), "stderr: {}", stderr(&o));
        let html = std::fs::read_to_string(out.join("report.html")).unwrap();
        for fig in [
            "dominant_colour.png",
            "prediction_tall.png",
            "exploration_path.png",
        ] {
            assert!(html.contains(fig), "report.html shows {fig}");
            assert!(out.join(fig).exists(), "{fig} written");
        }
        let text = std::fs::read_to_string(out.join("report.json")).unwrap();
        let mut v: serde_json::Value = serde_json::from_str(&text).unwrap();
        let t = v["exploration_time_s"].as_f64().unwrap();
        assert!((14.9..=15.2).contains(&t), "{t}");
        assert_eq!(v["models"].as_array().unwrap().len(), 2);
        assert!(v["trajectory"].as_array().unwrap().len() > 10);
        for k in [
            "mission_wall_s",
            "wall_time_s",
            "speedup",
            "replan_latency_ms",
            "goals_to_tour_ms",
            "replan_parts_ms",
            "goal_identification_ms",
            "phase_wall_s",
        ] {
            v.as_object_mut().unwrap().remove(k);
        }
        reports.push(v);
    }
    assert_eq!(reports[0], reports[1]);
    let o = strider(&["run", "--strategy", "nope", "--out", d.to_str().unwrap()]);
    assert!(one_line_error(&o).contains("unknown strategy"));
}
