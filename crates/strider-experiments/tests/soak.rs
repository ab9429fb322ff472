//! `strider bench soak` in small: every strategy's missions keep the invariants, the soak is
//! deterministic whatever the number of jobs, and its judge does not change the missions it
//! watches.

use std::time::Duration;

use strider_experiments::progress::Silent;
use strider_experiments::soak::judge::Judge;
use strider_experiments::soak::robot::Judged;
use strider_experiments::soak::{self, SoakOptions};
use strider_experiments::trial::{configure, load, robot_spec};
use strider_explore::rbcm_greedy::RbcmGreedy;
use strider_explore::registry::{Configured, STRATEGIES};
use strider_explore::{FromParams, Mission};
use strider_sim::Simulator;

fn options(missions: usize, jobs: usize) -> SoakOptions {
    SoakOptions {
        missions,
        seed: 3,
        jobs,
        time_limit: Some(6.0),
        rerun: None,
    }
}

/// One short mission of each strategy: no invariant broken, every strategy listed, and the
/// same results (apart from wall time) with one job or two.
#[test]
fn a_small_soak_of_every_strategy_keeps_the_invariants_and_repeats() {
    let n = STRATEGIES.len();
    let a = soak::run(&options(n, 2), &Silent).expect("soak runs");
    assert_eq!(a.violations, 0, "{}", soak::markdown(&a));
    assert_eq!(a.summary, format!("{n} missions, 0 invariant violations"));
    for s in STRATEGIES {
        assert!(
            a.results.iter().any(|r| r.task.strategy == s.name),
            "{} is missing",
            s.name
        );
        assert!(a.cells.iter().any(|c| c.strategy == s.name));
    }
    for r in &a.results {
        assert!(r.poses_judged > 0, "{}: no pose judged", r.task);
        assert!(r.snapshots_judged > 0, "{}: no snapshot judged", r.task);
        assert!(r.explored.is_some(), "{}", r.task);
    }
    let md = soak::markdown(&a);
    assert!(md.contains("None.") && md.contains(&a.summary), "{md}");

    let b = soak::run(&options(n, 1), &Silent).expect("soak runs");
    let without_wall = |s: &soak::Soak| {
        let mut v = serde_json::to_value(&s.results).unwrap();
        for r in v.as_array_mut().unwrap() {
            r["wall_s"] = 0.into();
        }
        v
    };
    assert_eq!(without_wall(&a), without_wall(&b));
}

/// A mission watched by the judge, which splits each 10 Hz control tick of `rbcm-greedy` at
/// the 20 Hz pose ticks, is the very mission `strider run` runs without it.
#[test]
fn the_judge_does_not_change_the_mission() {
    let sc = load("lab-track", 2).unwrap();
    let (_, cfg) = configure(&sc, "rbcm-greedy", &[]).unwrap();
    let Configured::Rbcm(table) = cfg else {
        panic!("rbcm-greedy is a Prágr19 strategy");
    };
    let mission = || {
        let mut p = table.explorer_params(&robot_spec(&sc)).unwrap();
        p.time_limit_s = 8.0;
        RbcmGreedy::mission(p).unwrap()
    };
    let seed = 5;
    let mut plain = mission();
    plain
        .run(&mut Simulator::new(&sc, seed).unwrap())
        .expect("runs");
    let judge = Judge::new(&sc).unwrap();
    let mut watched: Mission<RbcmGreedy> = mission();
    let mut robot = Judged::new(
        Simulator::new(&sc, seed).unwrap(),
        &sc,
        &judge,
        Duration::from_secs(3600),
    );
    watched.run(&mut robot).expect("runs");
    let (a, b) = (plain.record(), watched.record());
    assert!(
        a.driven_m > 0.0,
        "the robot did not move: the test saw nothing"
    );
    assert_eq!(a.trajectory, b.trajectory);
    assert_eq!(a.driven_m, b.driven_m);
    assert_eq!(a.exploration_time_s, b.exploration_time_s);
    assert_eq!(
        plain.body().map().observed_count(),
        watched.body().map().observed_count()
    );
    assert!(robot.findings.is_empty(), "{:?}", robot.findings);
    // Split at (nearly) every pose tick: about two poses judged per control tick.
    let ticks = (8.0 * 10.0) as u64;
    assert!(
        robot.counts.poses > ticks * 3 / 2,
        "{} poses judged in {ticks} control ticks ({} not split)",
        robot.counts.poses,
        robot.counts.unsplit
    );
}

/// Options out of range are refused with the flag, the value and the range.
#[test]
fn bad_options_name_the_flag_and_the_range() {
    for (o, want) in [
        (options(0, 1), "--missions = 0: must be 1 to"),
        (options(1, 0), "--jobs = 0: must be 1 to"),
        (
            SoakOptions {
                time_limit: Some(f64::NAN),
                ..options(1, 1)
            },
            "--time-limit",
        ),
        (
            SoakOptions {
                rerun: Some("escape@lab-track:1:1".into()),
                ..options(1, 1)
            },
            "no haptic bumper",
        ),
    ] {
        let e = soak::run(&o, &Silent).unwrap_err().to_string();
        assert!(e.contains(want), "{e}");
    }
}
