//! Interrupted work winds down: a mission stops at the tick after its cancellation flag is set
//! and says so, its recording is finished and renamed from `.part`, and a bench asked to stop
//! before any trial finished writes nothing.

use strider_experiments::cancel::Cancel;
use strider_experiments::pragr22::{Table5Options, table5};
use strider_experiments::progress::Silent;
use strider_experiments::trial::{mission_params, run_mission, termination};
use strider_explore::Strategy;
use strider_scenario::Scenario;

/// Runs a gtsp mission on courtyard-small that requests `cancel` once it passes `stop_at` s
/// (never when `None`), recording to `mcap`; returns (interrupted, termination, time, written).
fn mission(stop_at: Option<f64>, mcap: Option<&std::path::Path>) -> (bool, String, f64, u64) {
    let sc = Scenario::from_name_or_file("courtyard-small", 1).unwrap();
    let mut params = mission_params(&sc, Strategy::Gtsp, 1).unwrap();
    params.time_limit_s = 40.0;
    let cancel = Cancel::new();
    let (m, _, written) = run_mission(&sc, params, 1, (mcap, &cancel), |p| {
        if stop_at.is_some_and(|t| p.time_s >= t) {
            cancel.request();
        }
    })
    .unwrap();
    let t = m.record().exploration_time_s;
    let messages = written.map_or(0, |w| w.total());
    (m.interrupted(), termination(&m), t, messages)
}

#[test]
fn a_requested_flag_stops_the_mission_at_the_next_tick_and_finishes_its_recording() {
    let dir = std::env::temp_dir().join(format!("strider-interrupt-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    let file = dir.join("m.mcap");
    let (interrupted, why, t, messages) = mission(Some(5.0), Some(&file));
    assert!(interrupted);
    assert_eq!(why, "Interrupted");
    // The observer runs about once per simulated second; the loop stops at the next tick.
    assert!((5.0..6.5).contains(&t), "stopped at {t} s");
    assert!(messages > 0);
    assert!(
        !dir.join("m.mcap.part").exists(),
        "the .part file is renamed"
    );
    let bytes = std::fs::read(&file).unwrap();
    assert!(bytes.starts_with(b"\x89MCAP0\r\n") && bytes.ends_with(b"\x89MCAP0\r\n"));

    let (interrupted, why, t, _) = mission(None, None);
    assert!(!interrupted, "a flag never requested stops nothing");
    assert_ne!(why, "Interrupted");
    assert!(t >= 40.0 || why == "GoalsCleared", "{why} at {t} s");
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn a_bench_stopped_before_any_trial_finished_writes_nothing() {
    let out = std::env::temp_dir().join(format!("strider-interrupt-t5-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&out);
    let cancel = Cancel::new();
    cancel.request();
    let o = Table5Options {
        trials: 2,
        large_trials: 1,
        world_seeds: 1,
        jobs: 2,
        time_limit: Some(10.0),
        mcap_dir: None,
        resume: false,
        cancel,
        shard: None,
        sets: Vec::new(),
    };
    let t = table5(&o, &out, &Silent).unwrap();
    assert_eq!((t.finished, t.total), (0, 6));
    assert!(!t.complete());
    assert!(!out.exists(), "nothing to keep, nothing written");
}
