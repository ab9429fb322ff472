//! End-to-end tests of the `strider` binary: the commands a user runs, their files, and their
//! one-line errors on bad input.

use std::path::PathBuf;
use std::process::{Command, Output};

fn strider(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_strider"))
        .args(args)
        .output()
        .expect("run strider")
}

/// A fresh directory under the system temp dir, unique per test.
fn temp_dir(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("strider-cli-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

/// The error contract: exit code 1 and exactly one line on stderr starting with `error: `.
fn assert_one_line_error(o: &Output) -> String {
    assert_eq!(o.status.code(), Some(1), "stderr: {}", stderr(o));
    let e = stderr(o);
    assert_eq!(
        e.trim_end().lines().count(),
        1,
        "one line expected, got: {e}"
    );
    assert!(e.starts_with("error: "), "{e}");
    e
}

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
    let dir = temp_dir("render");
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
    let dir = temp_dir(tag);
    let o = strider(&["scenario", "export", name, "--out", dir.to_str().unwrap()]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(dir.join("scenario.toml").is_file());
    dir
}

#[test]
fn map_build_on_an_exported_scenario_writes_stats() {
    let scen = export("courtyard-small", "build-scen");
    let out = temp_dir("build-out");
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
    let out = temp_dir("errors-out");
    let out_s = out.to_str().unwrap();

    // Unknown built-in and missing file.
    let e = assert_one_line_error(&strider(&[
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
    let e = assert_one_line_error(&strider(&[
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
    let e = assert_one_line_error(&strider(&[
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
    let e = assert_one_line_error(&strider(&[
        "scenario",
        "render",
        toml_path.to_str().unwrap(),
        "--out",
        out_s,
    ]));
    assert!(e.contains("elevation.png") && e.contains("16-bit"), "{e}");

    // A robot without a range sensor cannot build a map.
    let e = assert_one_line_error(&strider(&[
        "map",
        "build",
        "--scenario",
        "energy-arena",
        "--out",
        out_s,
    ]));
    assert!(e.contains("sensor"), "{e}");

    // Nonsense numbers are refused, not run.
    let e = assert_one_line_error(&strider(&[
        "map",
        "build",
        "--lane-spacing=-1",
        "--out",
        out_s,
    ]));
    assert!(e.contains("lane-spacing"), "{e}");
}
