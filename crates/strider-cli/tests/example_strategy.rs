//! The example strategy written outside the kernel (`examples/nearest_frontier.rs`) implements
//! the `Strategy` trait, explores, and runs through the comparison beside a registry strategy.

#[path = "../examples/nearest_frontier.rs"]
mod nearest_frontier;

use strider_experiments::compare::{self, CompareOptions, Entrant};

#[test]
fn the_example_strategy_explores_and_is_compared() {
    let options = CompareOptions {
        scenarios: vec!["courtyard-small".into(), "lab-track".into()],
        trials: 1,
        world_seeds: 1,
        jobs: 2,
        time_limit: Some(90.0),
        cancel: Default::default(),
        shard: None,
    };
    let entrants = vec![
        Entrant::registered("greedy").unwrap(),
        nearest_frontier::entrant(),
    ];
    let result = compare::run(&options, &entrants, || {}).unwrap();
    assert_eq!(result.trials.len(), 4);
    for t in result
        .trials
        .iter()
        .filter(|t| t.trial.strategy == "nearest-frontier")
    {
        assert!(t.trial.observed_cells > 1000, "{t:?}");
        assert!(t.tour_time_s.is_some(), "{t:?}");
    }
    let md = compare::markdown(&result, "test");
    assert!(md.contains("| nearest-frontier |"), "{md}");
}
