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
