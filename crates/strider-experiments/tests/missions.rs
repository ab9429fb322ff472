//! Invariants of exploration missions over many seeds, with the simulator as the judge: the
//! robot's centre never enters a cell that is inadmissible in the ground truth, bounded
//! explorations terminate on their own, and the mission's code cannot reach the simulator.

use strider_core::interface::{MotionState, Robot, SensorSink};
use strider_core::{GaitId, Point2};
use strider_explore::FromParams;
use strider_explore::{Strategy, Termination, TourExplorer};
use strider_scenario::Scenario;
use strider_scenario::ground_truth::point_in_mask;
use strider_sim::Simulator;

use strider_experiments::trial::mission_params;

/// The simulator behind the robot interface, judging every step against the ground truth.
struct Judge {
    sim: Simulator,
    admissible: Vec<bool>,
    /// Ticks whose pose had its centre in a ground-truth inadmissible cell, with the pose.
    violations: Vec<(f64, Point2)>,
}

impl Judge {
    fn new(sc: &Scenario, seed: u64) -> Self {
        let sim = Simulator::new(sc, seed).expect("simulator");
        let admissible = sc.world.gt_admissible(sc.map.rho_obstacle, sc.map.r_robot);
        Self {
            sim,
            admissible,
            violations: Vec::new(),
        }
    }
}

impl Robot for Judge {
    type Error = <Simulator as Robot>::Error;
    fn now(&self) -> f64 {
        self.sim.now()
    }
    fn follow(&mut self, path: &[Point2]) {
        self.sim.follow(path);
    }
    fn set_gait(&mut self, gait: GaitId) {
        self.sim.set_gait(gait);
    }
    fn advance(&mut self, dt: f64, sink: &mut dyn SensorSink) -> Result<MotionState, Self::Error> {
        let s = self.sim.advance(dt, sink)?;
        let p = self.sim.pose();
        let c = Point2::new(p.x, p.y);
        if !point_in_mask(self.sim.world(), &self.admissible, c) {
            self.violations.push((self.sim.now(), c));
        }
        Ok(s)
    }
}

fn scenario(name: &str, world_seed: u64) -> Scenario {
    Scenario::from_name_or_file(name, world_seed).expect("built-in scenario")
}

/// Over several worlds with walls and boxes, mission and world seeds and all
/// three strategies, the robot's centre stays in ground-truth admissible cells for the whole
/// (time-limited) mission.
#[test]
fn centre_never_enters_an_inadmissible_cell() {
    for (name, world_seed, seed, strategy) in [
        ("escape-arena", 1, 1, Strategy::Gtsp),
        ("escape-arena", 2, 2, Strategy::Greedy),
        ("escape-arena", 3, 3, Strategy::SpatialOnly),
        ("escape-arena", 4, 4, Strategy::Gtsp),
        ("courtyard-small", 2, 5, Strategy::Gtsp),
        ("courtyard-small", 3, 6, Strategy::Greedy),
    ] {
        let sc = scenario(name, world_seed);
        let mut params = mission_params(&sc, strategy, seed).expect("params");
        params.time_limit_s = 150.0;
        let mut judge = Judge::new(&sc, seed);
        let mut mission = TourExplorer::mission(params).expect("mission");
        let log = mission.run(&mut judge).expect("mission runs").clone();
        assert!(log.driven_m > 0.3, "seed {seed}: the robot hardly moved");
        assert!(
            judge.violations.is_empty(),
            "{name} world {world_seed} seed {seed} {strategy:?}: centre in inadmissible cells at {:?}",
            &judge.violations[..judge.violations.len().min(5)]
        );
    }
}

/// Explorations of a bounded area end by themselves (goals cleared or none reachable), well
/// before the time limit, whatever the seed and strategy; and the same seed gives the same
/// mission.
#[test]
fn bounded_explorations_terminate_and_repeat_exactly() {
    for (world_seed, seed, strategy) in [
        (1, 1, Strategy::Gtsp),
        (2, 7, Strategy::Greedy),
        (3, 8, Strategy::SpatialOnly),
        (4, 9, Strategy::Gtsp),
    ] {
        let mut sc = scenario("courtyard-small", world_seed);
        // A 1.6 × 1.6 m square around the start.
        let s = sc.start;
        sc.bounds.min = Point2::new(s.x - 0.8, s.y - 0.8);
        sc.bounds.max = Point2::new(s.x + 0.8, s.y + 0.8);
        let run = || {
            let mut params = mission_params(&sc, strategy, seed).expect("params");
            params.time_limit_s = 1500.0;
            let mut sim = Simulator::new(&sc, seed).expect("simulator");
            let mut mission = TourExplorer::mission(params).expect("mission");
            let run = mission.run(&mut sim).expect("mission runs").clone();
            let log = mission.strategy().log().clone();
            (run, log, mission.body().map().observed_count())
        };
        let (a, log_a, cells_a) = run();
        assert_ne!(
            a.termination,
            Termination::TimeLimit,
            "world {world_seed} seed {seed} {strategy:?} did not terminate in {} s",
            a.exploration_time_s
        );
        let (b, log_b, cells_b) = run();
        assert_eq!(a.trajectory, b.trajectory, "same seed, same trajectory");
        assert_eq!(a.termination, b.termination);
        assert_eq!(log_a.cost_samples, log_b.cost_samples);
        assert_eq!(cells_a, cells_b);
    }
}

/// A pose stream with heading jitter (5 mrad, as from a real robot's odometry) still yields
/// cost samples: the heading rate is measured over the mission's turning baseline. Measured
/// tick to tick the jitter reads as turning nearly all the time and hardly any sample is kept.
#[test]
fn cost_samples_survive_heading_jitter() {
    let mut sc = scenario("courtyard-small", 1);
    sc.sim.pose_sigma_yaw = 0.005;
    let samples = |baseline: Option<f64>| {
        let mut params = mission_params(&sc, Strategy::Gtsp, 1).expect("params");
        params.time_limit_s = 200.0;
        if let Some(b) = baseline {
            params.turning_baseline_s = b;
        }
        let mut sim = Simulator::new(&sc, 1).expect("simulator");
        let mut mission = TourExplorer::mission(params).expect("mission");
        mission.run(&mut sim).expect("mission runs");
        mission.strategy().log().cost_samples.iter().sum::<usize>()
    };
    let (smoothed, tick) = (samples(None), samples(Some(0.05)));
    assert!(
        smoothed >= 50,
        "only {smoothed} cost samples with a 0.5 s baseline"
    );
    assert!(tick * 4 < smoothed, "tick to tick {tick} vs {smoothed}");
    // A baseline that is not positive is a parameter error.
    let mut params = mission_params(&sc, Strategy::Gtsp, 1).expect("params");
    params.turning_baseline_s = 0.0;
    let err = TourExplorer::mission(params)
        .err()
        .expect("rejected")
        .to_string();
    assert!(err.contains("baseline"), "{err}");
}

/// The learning update leaves the planning view to the planner, but the gait choice reads that
/// view: at the next tour decision (1 / tour_hz later) it reflects the new models, whether or
/// not a new tour is planned.
#[test]
fn planning_view_follows_the_models_within_a_tour_period() {
    let sc = scenario("courtyard-small", 1);
    let mut params = mission_params(&sc, Strategy::Gtsp, 1).expect("params");
    params.time_limit_s = 300.0;
    let period = 1.0 / params.rates.tour_hz;
    let mut sim = Simulator::new(&sc, 1).expect("simulator");
    let mut mission = TourExplorer::mission(params).expect("mission");
    // (time, learning updates, updates the view reflects) at every observation.
    let mut seen: Vec<(f64, u64, u64)> = Vec::new();
    mission
        .run_watched(&mut sim, |m, p| {
            if let Some(v) = m.strategy().view_learning_updates() {
                seen.push((p.time_s, m.strategy().learning_updates(), v));
            }
        })
        .expect("mission runs");
    let updates = seen.last().map_or(0, |s| s.1);
    assert!(updates >= 10, "only {updates} learning updates");
    let mut caught_up = 0;
    for (k, &(t, learned, _)) in seen.iter().enumerate() {
        let Some(&(t2, _, _)) = seen[k..].iter().find(|s| s.2 >= learned) else {
            panic!("the view never reflects learning update {learned} (seen at {t:.1} s)");
        };
        assert!(
            t2 - t <= 2.0 * period + 0.1,
            "learning update {learned} seen at {t:.1} s, in the view only at {t2:.1} s"
        );
        caught_up += (t2 > t) as usize;
    }
    assert!(caught_up > 0, "the view never lagged: the test saw nothing");
}

/// The learning, mapping, planning and exploration crates cannot read simulator ground truth:
/// none of them depends on the simulator or the scenario crate (normal dependencies).
#[test]
fn algorithm_crates_do_not_depend_on_the_simulator() {
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("..");
    for krate in [
        "strider-core",
        "strider-map",
        "strider-learn",
        "strider-plan",
        "strider-explore",
    ] {
        let toml = std::fs::read_to_string(root.join(krate).join("Cargo.toml")).expect(krate);
        // The [dependencies] table only (dev-dependencies may use anything).
        let deps: String = toml
            .split("\n[")
            .filter(|sec| sec.starts_with("dependencies]") || sec.starts_with("[dependencies]"))
            .collect();
        for forbidden in ["strider-sim", "strider-scenario", "strider-cli"] {
            assert!(
                !deps.contains(forbidden),
                "{krate} depends on {forbidden}: the algorithms must not see the simulator"
            );
        }
    }
}

/// `stuck_windows_as_samples = false` keeps the windows that find the robot stuck out of the
/// models (by default they teach the gait where it gets stuck).
#[test]
fn stuck_windows_as_samples_can_be_switched_off() {
    let sc = scenario("courtyard-small", 1);
    let samples = |stuck_samples: bool| {
        let mut params = mission_params(&sc, Strategy::Gtsp, 1).expect("params");
        params.time_limit_s = 600.0;
        params.stuck_samples = stuck_samples;
        let mut sim = Simulator::new(&sc, 1).expect("simulator");
        let mut mission = TourExplorer::mission(params).expect("mission");
        mission.run(&mut sim).expect("mission runs");
        let log = mission.strategy().log();
        (log.cost_samples.iter().sum::<usize>(), log.stuck_events)
    };
    let (with, stuck) = samples(true);
    let (without, _) = samples(false);
    assert!(stuck > 0, "the robot never got stuck: the test saw nothing");
    assert!(
        without < with,
        "{without} samples without stuck windows, {with} with"
    );
}

/// The robot's time by activity adds up to the mission's time; the look-around runs with a
/// narrow camera (`courtyard-small`) and never with an omnidirectional sensor
/// (`courtyard-large`), nor when switched off.
#[test]
fn activity_times_add_up_and_look_around_needs_a_narrow_sensor() {
    let activity = |name: &str, look_around: bool| {
        let sc = scenario(name, 1);
        let mut params = mission_params(&sc, Strategy::Gtsp, 1).expect("params");
        params.time_limit_s = 300.0;
        params.look_around = look_around;
        let mut sim = Simulator::new(&sc, 1).expect("simulator");
        let mut mission = TourExplorer::mission(params).expect("mission");
        mission.run(&mut sim).expect("mission runs");
        let a = mission.strategy().log().activity_s;
        let t = mission.record().exploration_time_s;
        assert!(
            (a.total() - t).abs() < 1.0,
            "{name}: {} s of activity in {t} s",
            a.total()
        );
        assert!(
            a.driving > 0.25 * t,
            "{name}: driving {} of {t} s",
            a.driving
        );
        a
    };
    assert!(activity("courtyard-small", true).look_around > 0.0);
    assert_eq!(activity("courtyard-small", false).look_around, 0.0);
    assert_eq!(activity("courtyard-large", true).look_around, 0.0);
}
