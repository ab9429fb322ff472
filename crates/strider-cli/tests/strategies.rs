//! The strategy registry at the command line: `strider strategies` lists every strategy with
//! its paper and typed parameters, and bad parameters fail with one line naming the key.

mod common;
use common::{one_line_error, strider, temp_dir};

#[test]
fn strategies_lists_every_strategy_with_paper_and_parameters() {
    let o = strider(&["strategies"]);
    assert!(o.status.success());
    let out = String::from_utf8_lossy(&o.stdout);
    let names = [
        "gtsp",
        "greedy",
        "spatial-only",
        "rbcm-greedy",
        "escape",
        "rigid",
    ];
    for name in names {
        assert!(out.lines().any(|l| l == name), "{name} missing:\n{out}");
        assert!(out.contains(&format!("[strategy.{name}]")), "{name}");
    }
    assert_eq!(out.matches("  paper [").count(), names.len());
    for (key, unit) in [
        ("n_min", "cells"),
        ("delta_t", "s"),
        ("mcost_cell", "m"),
        ("f_trav", "N"),
    ] {
        assert!(
            out.lines()
                .any(|l| l.trim_start().starts_with(key) && l.contains(unit)),
            "{key} with its unit {unit}"
        );
    }
}

#[test]
fn bad_parameters_fail_with_one_line_naming_the_key() {
    let d = temp_dir("strategies", "bad");
    let out = d.to_str().unwrap();
    for (strategy, set, key) in [
        ("gtsp", "n_min=-3", "n_min"),
        ("gtsp", "lenghtscale=0.5", "lenghtscale"),
        ("greedy", "c_loss=fast", "c_loss"),
        ("spatial-only", "delta_t=0", "delta_t"),
        ("rbcm-greedy", "m_min=60", "m_min"),
        ("rbcm-greedy", "gait=trot", "gait"),
        ("escape", "descriptor=hsv", "descriptor"),
    ] {
        let scenario = match strategy {
            "rbcm-greedy" => "lab-track",
            "escape" => "escape-arena",
            _ => "courtyard-small",
        };
        let e = one_line_error(&strider(&[
            "run",
            "--scenario",
            scenario,
            "--strategy",
            strategy,
            "--set",
            set,
            "-o",
            out,
        ]));
        assert!(
            e.contains(key) && e.contains(strategy),
            "{strategy} --set {set}: {e}"
        );
    }
    let e = one_line_error(&strider(&["run", "--strategy", "frontier", "-o", out]));
    assert!(e.contains("gtsp") && e.contains("rbcm-greedy"), "{e}");
    let e = one_line_error(&strider(&["run", "--set", "n_min", "-o", out]));
    assert!(e.contains("KEY=VALUE"), "{e}");
    // A strategy the robot cannot carry.
    let e = one_line_error(&strider(&[
        "run",
        "--scenario",
        "courtyard-small",
        "--strategy",
        "escape",
        "-o",
        out,
    ]));
    assert!(e.contains("bumper"), "{e}");
}

/// A scenario file's `[strategy.<name>]` sections are checked: a misspelt section, a key left
/// directly under `[strategy]` and a wrong type each fail with one line that says where.
#[test]
fn scenario_strategy_sections_are_checked() {
    let d = temp_dir("strategies", "sections");
    let dir = d.join("sc");
    let o = strider(&[
        "scenario",
        "export",
        "courtyard-small",
        "--out",
        dir.to_str().unwrap(),
    ]);
    assert!(o.status.success());
    let file = dir.join("scenario.toml");
    let original = std::fs::read_to_string(&file).unwrap();
    let out = d.join("out");
    let run = |text: String| {
        std::fs::write(&file, text).unwrap();
        one_line_error(&strider(&[
            "run",
            "--scenario",
            file.to_str().unwrap(),
            "--time-limit",
            "5",
            "-o",
            out.to_str().unwrap(),
        ]))
    };
    let e = run(format!("{original}\n[strategy.gsp]\nc_loss = 1.0\n"));
    assert!(e.contains("[strategy.gsp]") && e.contains("gtsp"), "{e}");
    let e = run(original.replacen(
        "[strategy.gtsp]",
        "[strategy]\nc_loss = 3.0\n\n[strategy.gtsp]",
        1,
    ));
    assert!(
        e.contains("`c_loss`") && e.contains("[strategy.gtsp]"),
        "{e}"
    );
    let e = run(original.replace("c_loss = 10.0", "c_loss = \"ten\""));
    assert!(
        e.contains("section [strategy.gtsp]") && e.contains("c_loss"),
        "{e}"
    );
}
