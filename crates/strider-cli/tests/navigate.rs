//! End-to-end tests of `strider navigate` (Nardi19): a short run writes the tables and figures
//! with every configuration, and bad input ends in one clear line.

mod common;
use common::{one_line_error, strider, temp_dir};

#[test]
fn navigate_writes_tables_and_figures() {
    let out = temp_dir("nav", "run");
    let o = strider(&[
        "navigate",
        "--runs",
        "2",
        "--objectives",
        "vibration",
        "--out",
        out.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let report: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("navigate.json")).unwrap()).unwrap();
    let groups = report["groups"].as_array().unwrap();
    assert_eq!(groups.len(), 2);
    for g in groups {
        let configs = g["configs"].as_array().unwrap();
        let expected = if g["task"] == "start-goal" { 4 } else { 3 };
        assert_eq!(configs.len(), expected, "{}", g["task"]);
        let lc = g["least_cost"]["experienced_cost"].as_f64().unwrap();
        let sp = g["shortest"]["experienced_cost"].as_f64().unwrap();
        assert!(lc > 0.0 && sp > lc, "least-cost {lc} vs shortest {sp}");
        // Run 1 plans on the same uniform prior with the same simulator seed: every softplus
        // model drives the same path and measures the same cost.
        let run1: Vec<f64> = configs
            .iter()
            .filter(|c| c["rectifier"] == "softplus")
            .map(|c| c["runs"][0]["experienced_cost"].as_f64().unwrap())
            .collect();
        assert!(run1.windows(2).all(|w| w[0] == w[1]), "{run1:?}");
        for c in configs {
            let runs = c["runs"].as_array().unwrap();
            assert_eq!(runs.len(), 2);
            let rmse = c["final"]["rmse"].as_f64().unwrap();
            assert!(rmse.is_finite() && rmse > 0.0);
            assert!(c["final"]["mahalanobis"].as_f64().unwrap().is_finite());
            assert!(runs[1]["visited_cells"].as_u64().unwrap() > 0);
        }
    }
    assert_eq!(report["published_table_1"].as_array().unwrap().len(), 3);
    let md = std::fs::read_to_string(out.join("navigate.md")).unwrap();
    assert!(
        md.contains("Table I") && md.contains("16.15 / 265.84"),
        "{md}"
    );
    for f in [
        "terrain.png",
        "truth_vibration.png",
        "start-goal_vibration_paths.png",
        "start-goal_vibration_cost_per_run.png",
        "locations_vibration_paths.png",
        "locations_vibration_gp-mixture-aerial_mean.png",
        "start-goal_vibration_gp-mixture-aerial_relu_std.png",
    ] {
        assert!(out.join(f).is_file(), "{f} missing");
    }
}

#[test]
fn navigate_rejects_bad_input() {
    let dir = temp_dir("nav", "bad");
    let small = dir.join("small.png");
    image::RgbImage::from_pixel(100, 80, image::Rgb([10, 20, 30]))
        .save(&small)
        .unwrap();
    let out = dir.join("out");
    let o = dir.to_str().unwrap();
    let e = one_line_error(&strider(&[
        "navigate",
        "--aerial",
        small.to_str().unwrap(),
        "--runs",
        "1",
        "--out",
        out.to_str().unwrap(),
    ]));
    assert!(
        e.contains("aerial image") && e.contains("100×80") && e.contains("120×80"),
        "{e}"
    );
    let e = one_line_error(&strider(&[
        "navigate",
        "--aerial",
        dir.join("missing.png").to_str().unwrap(),
        "--out",
        o,
    ]));
    assert!(e.contains("missing.png"), "{e}");
    let e = one_line_error(&strider(&["navigate", "--runs", "0", "--out", o]));
    assert!(e.contains("--runs"), "{e}");
    let e = one_line_error(&strider(&["navigate", "--sites", "one", "--out", o]));
    assert!(e.contains("--sites"), "{e}");
    let e = one_line_error(&strider(&["navigate", "--objectives", "speed", "--out", o]));
    assert!(e.contains("speed"), "{e}");
    let e = one_line_error(&strider(&["navigate", "--lambda", "NaN", "--out", o]));
    assert!(e.contains("--lambda"), "{e}");
    let e = one_line_error(&strider(&["navigate", "--scenario", "nowhere", "--out", o]));
    assert!(e.contains("nowhere"), "{e}");
}

#[test]
fn a_lambda_sweep_writes_one_table_and_a_run_per_lambda() {
    let out = temp_dir("nav", "lambdas");
    let o = strider(&[
        "navigate",
        "--runs",
        "1",
        "--objectives",
        "vibration",
        "--lambdas",
        "0.5,3",
        "--out",
        out.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    for l in ["0.5", "3"] {
        let md = std::fs::read_to_string(out.join(format!("lambda-{l}/navigate.md"))).unwrap();
        assert!(md.contains(&format!("--lambda {l}")), "{md}");
    }
    let sweep: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("lambdas.json")).unwrap()).unwrap();
    let rows = sweep["rows"].as_array().unwrap();
    // One start-goal objective on one site, per λ.
    assert_eq!(rows.len(), 2);
    assert_eq!(rows[0]["lambda"].as_f64(), Some(0.5));
    assert_eq!(rows[1]["lambda"].as_f64(), Some(3.0));
    for r in rows {
        assert!(r["relu"]["visited_cells"].as_f64().unwrap() > 0.0);
        assert!(r["softplus_converges_sooner"].is_boolean());
    }
    let md = std::fs::read_to_string(out.join("lambdas.md")).unwrap();
    assert!(
        md.contains("--lambdas 0.5,3") && md.contains("| 3 | 1 | vibration |"),
        "{md}"
    );
    // A bad λ in the list is refused before any run.
    let e = one_line_error(&strider(&[
        "navigate",
        "--lambdas",
        "1,-2",
        "--out",
        out.to_str().unwrap(),
    ]));
    assert!(e.contains("--lambdas -2"), "{e}");
}
