//! Motion, streams and proprioception of the simulator.
mod common;

use common::*;
use strider_core::interface::{MotionState, Robot, SensorSink};
use strider_core::{GaitId, Point2, Pose2, PoseStamped, Proprioception};
use strider_scenario::{Scenario, SimParams, World};
use strider_sim::{SimError, Simulator};

#[derive(Default)]
struct Rec {
    poses: Vec<PoseStamped>,
    proprio: Vec<Proprioception>,
    clouds: usize,
}

impl SensorSink for Rec {
    fn on_pose(&mut self, p: &PoseStamped) {
        self.poses.push(*p);
    }
    fn on_cloud(&mut self, _c: &strider_core::PointCloud) {
        self.clouds += 1;
    }
    fn on_proprioception(&mut self, p: &Proprioception) {
        self.proprio.push(*p);
    }
}

fn sc(world: World, sim: SimParams, start: Pose2) -> Scenario {
    scenario(world, robot(Vec::new()), sim, start)
}

/// Advances until idle or blocked (or `limit` seconds); returns the final state.
/// A simulator of `world` with the test robot standing at `start`, heading +x.
fn sim_at(world: World, sim: SimParams, start: (f64, f64), seed: u64) -> Simulator {
    Simulator::new(&sc(world, sim, Pose2::new(start.0, start.1, 0.0)), seed).unwrap()
}

/// The noiseless test robot walking from (1, 1) towards (4, 1) for `limit` seconds across a
/// strip of terrain `t`, `z` high, at x = 2.5–2.6 m.
fn walk_across_strip(t: u8, z: f32, seed: u64, limit: f64) -> (Simulator, Rec, MotionState) {
    let mut world = flat_world(100, 40, 0.05);
    fill(&mut world, 50, 52, 0, 40, z, t);
    let mut sim = sim_at(world, noiseless(), (1.0, 1.0), seed);
    sim.follow(&[Point2::new(4.0, 1.0)]);
    let mut rec = Rec::default();
    let st = run(&mut sim, &mut rec, limit);
    (sim, rec, st)
}

fn run(sim: &mut Simulator, rec: &mut Rec, limit: f64) -> MotionState {
    let mut st = MotionState::default();
    while sim.now() < limit {
        st = sim.advance(0.5, rec).unwrap();
        if st.idle || st.blocked {
            break;
        }
    }
    st
}

fn straight_time(terrain: u8, sim_params: SimParams, seed: u64) -> f64 {
    let mut world = flat_world(100, 40, 0.05);
    fill(&mut world, 0, 100, 0, 40, 0.0, terrain);
    let mut sim = sim_at(world, sim_params, (0.5, 1.0), seed);
    sim.follow(&[Point2::new(0.5, 1.0), Point2::new(3.5, 1.0)]);
    let mut rec = Rec::default();
    let st = run(&mut sim, &mut rec, 1000.0);
    assert!(st.idle && !st.blocked);
    assert!(sim.pose().position().dist(Point2::new(3.5, 1.0)) <= 0.025);
    // Time when the pose stream first shows the goal reached.
    rec.poses
        .iter()
        .find(|p| p.position.xy().dist(Point2::new(3.5, 1.0)) <= 0.025)
        .unwrap()
        .stamp
}

#[test]
fn half_speed_terrain_takes_twice_as_long() {
    let t1 = straight_time(GROUND, noiseless(), 1);
    let t2 = straight_time(SLOW, noiseless(), 1);
    assert!((t1 - 59.5).abs() < 0.2, "{t1}"); // 2.975 m at 0.05 m/s
    assert!((t2 / t1 - 2.0).abs() < 0.01, "{t1} {t2}");
    // With speed noise the ratio holds on average.
    let n1 = straight_time(GROUND, SimParams::default(), 2);
    let n2 = straight_time(SLOW, SimParams::default(), 3);
    assert!((n2 / n1 - 2.0).abs() < 0.05, "{n1} {n2}");
}

#[test]
fn stuck_terrain_collapses_speed() {
    let mut world = flat_world(100, 40, 0.05);
    fill(&mut world, 0, 100, 0, 40, 0.0, TURF);
    let mut sim = sim_at(world, SimParams::default(), (0.5, 1.0), 4);
    sim.follow(&[Point2::new(3.5, 1.0)]);
    let mut rec = Rec::default();
    sim.advance(100.0, &mut rec).unwrap();
    let moved = sim.odometer_m();
    assert!(
        moved > 0.0 && moved <= 0.02 * 0.05 * 100.0 + 1e-12,
        "{moved}"
    );
    assert!(moved >= 0.008 * 0.05 * 100.0, "{moved}");
    // The tall gait walks turf at 0.8 of its speed.
    sim.set_gait(GaitId(1));
    let before = sim.odometer_m();
    sim.advance(100.0, &mut rec).unwrap();
    let v = (sim.odometer_m() - before) / 100.0;
    assert!((v / (0.8 * 0.0125) - 1.0).abs() < 0.05, "{v}");
    assert_eq!(rec.poses.last().unwrap().gait, GaitId(1));
    // Unknown gaits are ignored.
    sim.set_gait(GaitId(9));
    assert_eq!(sim.gait(), GaitId(1));
}

#[test]
fn turns_in_place_then_walks() {
    let world = flat_world(60, 60, 0.05);
    let mut sim = sim_at(world, noiseless(), (1.0, 1.0), 5);
    sim.follow(&[Point2::new(1.0, 2.0)]);
    let mut rec = Rec::default();
    sim.advance(1.0, &mut rec).unwrap();
    let p = sim.pose();
    assert_eq!(p.position(), Point2::new(1.0, 1.0), "turning in place");
    assert!((p.yaw - 0.5).abs() < 1e-9, "{}", p.yaw);
    // π/2 − 20° at 0.5 rad/s before walking starts.
    sim.advance(2.0, &mut rec).unwrap();
    assert!(sim.pose().y > 1.0);
    let st = run(&mut sim, &mut rec, 200.0);
    assert!(st.idle);
    assert!(
        (sim.pose().yaw - std::f64::consts::FRAC_PI_2).abs() < 0.05,
        "{}",
        sim.pose().yaw
    );
    assert!(sim.pose().position().dist(Point2::new(1.0, 2.0)) <= 0.025);
    // Heading never over-rotates between stream samples.
    assert!(
        rec.poses
            .windows(2)
            .all(|w| (w[1].yaw - w[0].yaw).abs() <= 0.5 * 0.05 + 1e-9)
    );
}

#[test]
fn a_wall_blocks_and_presses_the_bumper() {
    let (mut sim, mut rec, st) = walk_across_strip(WALL, 0.5, 6, 200.0);
    assert!(st.blocked && !st.idle);
    let x = sim.pose().x;
    assert!(x < 2.5 && x > 2.45, "{x}");
    let last = rec.proprio.last().unwrap();
    assert!(
        (last.bumper_force - 3.0).abs() < 1e-9,
        "pushing with all it has: {}",
        last.bumper_force
    );
    // Staying blocked while the path is unchanged; a new path frees it.
    let st = sim.advance(1.0, &mut rec).unwrap();
    assert!(st.blocked);
    assert_eq!(sim.pose().x, x);
    sim.follow(&[Point2::new(1.0, 1.0)]);
    let st = run(&mut sim, &mut rec, 400.0);
    assert!(st.idle && !st.blocked);
    assert_eq!(rec.proprio.last().unwrap().bumper_force, 0.0);
    // A small step is climbed.
    let mut world = flat_world(100, 40, 0.05);
    fill(&mut world, 50, 100, 0, 40, 0.2, GROUND);
    let mut sim = sim_at(world, noiseless(), (1.0, 1.0), 6);
    sim.follow(&[Point2::new(4.0, 1.0)]);
    assert!(run(&mut sim, &mut rec, 200.0).idle);
    assert!((sim.body_z() - 0.2).abs() < 1e-6);
    // The edge of the world blocks too.
    let world = flat_world(40, 40, 0.05);
    let mut sim = sim_at(world, noiseless(), (1.0, 1.0), 6);
    sim.follow(&[Point2::new(4.0, 1.0)]);
    assert!(run(&mut sim, &mut rec, 200.0).blocked);
    assert!(sim.pose().x < 2.0);
}

#[test]
fn curtains_are_pushed_through() {
    let (sim, rec, st) = walk_across_strip(CURTAIN, 0.8, 7, 400.0);
    assert!(st.idle && !st.blocked);
    assert!((sim.body_z() - 0.0).abs() < 1e-9);
    let forces: Vec<f64> = rec
        .proprio
        .iter()
        .map(|p| p.bumper_force)
        .filter(|&f| f > 0.0)
        .collect();
    assert!(!forces.is_empty());
    assert!(forces.iter().all(|&f| (f - 0.8).abs() < 1e-9));
    // The push slows it down: longer than the free walk of 3 m at 0.05 m/s.
    assert!(sim.now() > 61.0, "{}", sim.now());
    // The body never rides on top of the curtain.
    assert!(rec.poses.iter().all(|p| p.position.z.abs() < 1e-9));

    // A box needing 15 N is not pushed by a 3-N robot: blocked, bumper at 3 N.
    let (_, rec, st) = walk_across_strip(BOX, 0.4, 7, 400.0);
    assert!(st.blocked);
    // Through the servo torque and back (the Prágr23 Table 4 calibration): equal up to rounding.
    assert!((rec.proprio.last().unwrap().bumper_force - 3.0).abs() < 1e-9);
    // A robot that cannot push is stopped by the curtain; without a bumper it feels nothing.
    let mut world = flat_world(100, 40, 0.05);
    fill(&mut world, 50, 52, 0, 40, 0.8, CURTAIN);
    let mut s = sc(world, noiseless(), Pose2::new(1.0, 1.0, 0.0));
    s.robot.max_push_force_n = 0.0;
    s.robot.bumper = false;
    let mut sim = Simulator::new(&s, 7).unwrap();
    sim.follow(&[Point2::new(4.0, 1.0)]);
    let mut rec = Rec::default();
    assert!(run(&mut sim, &mut rec, 400.0).blocked);
    assert!(rec.proprio.iter().all(|p| p.bumper_force == 0.0));
}

#[test]
fn streams_come_at_their_rates_in_time_order() {
    let world = flat_world(60, 60, 0.05);
    let mut s = sc(world, SimParams::default(), Pose2::new(1.0, 1.0, 0.0));
    s.sim.proprio_rate_hz = 10.0;
    s.robot.sensors = vec![rgbd(8, 6, 2.5)];
    let mut sim = Simulator::new(&s, 8).unwrap();
    sim.follow(&[Point2::new(2.0, 1.0)]);
    let mut rec = Rec::default();
    for _ in 0..7 {
        sim.advance(10.0 / 7.0, &mut rec).unwrap();
    }
    assert!((sim.now() - 10.0).abs() < 1e-9);
    assert_eq!(rec.poses.len(), 201);
    for (k, p) in rec.poses.iter().enumerate() {
        assert_eq!(p.stamp, k as f64 / 20.0);
    }
    assert_eq!(rec.proprio.len(), 101);
    assert_eq!(rec.clouds, 51);
    // Advancing by zero emits nothing new.
    sim.advance(0.0, &mut rec).unwrap();
    assert_eq!(rec.poses.len(), 201);
    assert!(matches!(
        sim.advance(-1.0, &mut rec),
        Err(SimError::InvalidDuration(_))
    ));
    assert!(matches!(
        sim.advance(f64::NAN, &mut rec),
        Err(SimError::InvalidDuration(_))
    ));
}

#[test]
fn roll_variance_matches_the_terrain() {
    let mut world = flat_world(400, 20, 0.05);
    fill(&mut world, 0, 400, 0, 20, 0.0, ROUGH);
    let mut sim = sim_at(world, SimParams::default(), (0.5, 0.5), 9);
    sim.set_gait(GaitId(1)); // tall: 0.06 rad², 0.0125 m/s
    sim.follow(&[Point2::new(19.0, 0.5)]);
    let mut rec = Rec::default();
    sim.advance(400.0, &mut rec).unwrap();
    let roll: Vec<f64> = rec.proprio.iter().skip(20).map(|p| p.roll).collect();
    let var = |x: &[f64]| {
        let m = x.iter().sum::<f64>() / x.len() as f64;
        x.iter().map(|v| (v - m).powi(2)).sum::<f64>() / (x.len() - 1) as f64
    };
    let v = var(&roll);
    assert!((v / 0.06 - 1.0).abs() < 0.1, "{v}");
    // 10-s windows estimate it too (on average, each within a factor of two).
    let windows: Vec<f64> = roll.chunks_exact(200).map(var).collect();
    let mean = windows.iter().sum::<f64>() / windows.len() as f64;
    assert!((mean / 0.06 - 1.0).abs() < 0.1, "{mean}");
    assert!(
        windows.iter().all(|w| *w > 0.03 && *w < 0.12),
        "{windows:?}"
    );
    // Power and vibration while walking.
    let p = &rec.proprio[100];
    assert!((p.power_w / 4.5 - 1.0).abs() < 0.3, "{}", p.power_w);
    assert!(p.vibration > 0.0);
}

#[test]
fn at_rest_only_the_hotel_load() {
    let world = flat_world(60, 60, 0.05);
    let mut sim = sim_at(world, noiseless(), (1.0, 1.0), 10);
    let mut rec = Rec::default();
    let st = sim.advance(5.0, &mut rec).unwrap();
    assert!(st.idle);
    for p in &rec.proprio {
        assert_eq!(p.power_w, 0.5);
        assert_eq!(p.vibration, 0.0);
        assert_eq!(p.roll, 0.0);
        assert_eq!(p.bumper_force, 0.0);
    }
}

#[test]
fn pitch_follows_the_slope() {
    let mut world = flat_world(100, 20, 0.05);
    for k in 0..world.elevation.len() {
        let i = k % 100;
        world.elevation[k] = (i as f32 * 0.05) * 0.1; // 10 % uphill in +x
    }
    let mut sim = sim_at(world, noiseless(), (1.0, 0.5), 11);
    let mut rec = Rec::default();
    sim.advance(0.0, &mut rec).unwrap();
    let p = rec.poses[0];
    assert!((p.pitch + 0.1f64.atan()).abs() < 1e-3, "{}", p.pitch);
    assert!((p.position.z - 0.1).abs() < 1e-6, "{}", p.position.z);
}

#[test]
fn invalid_scenarios_are_refused() {
    let world = flat_world(20, 20, 0.05);
    let s = sc(world.clone(), noiseless(), Pose2::new(5.0, 0.5, 0.0));
    let e = Simulator::new(&s, 0).unwrap_err();
    assert!(matches!(e, SimError::StartOutsideWorld { .. }));
    assert!(e.to_string().contains("outside the world"));
    let mut s = sc(world.clone(), noiseless(), Pose2::new(0.5, 0.5, 0.0));
    s.robot.gaits.clear();
    assert!(matches!(
        Simulator::new(&s, 0),
        Err(SimError::NoGait { .. })
    ));
    let mut s = sc(world.clone(), noiseless(), Pose2::new(0.5, 0.5, 0.0));
    s.sim.dt = f64::NAN;
    let e = Simulator::new(&s, 0).unwrap_err();
    assert!(e.to_string().contains("sim.dt"), "{e}");
    let mut s = sc(world.clone(), noiseless(), Pose2::new(0.5, 0.5, 0.0));
    s.robot.sensors = vec![rgbd(0, 10, 2.0)];
    let e = Simulator::new(&s, 0).unwrap_err();
    assert!(
        e.to_string().contains("robot.sensors[0].width_px = 0"),
        "{e}"
    );
    let mut s = sc(world, noiseless(), Pose2::new(0.5, 0.5, f64::NAN));
    let e = Simulator::new(&s, 0).unwrap_err();
    assert!(e.to_string().contains("start.yaw"), "{e}");
    s.start.yaw = 0.0;
    Simulator::new(&s, 0).unwrap();
}

/// Each value that would hang the event loop or allocate without bound is refused with its
/// key, value and range.
#[test]
fn rates_steps_and_sensor_sizes_are_bounded() {
    let base = || {
        sc(
            flat_world(20, 20, 0.05),
            noiseless(),
            Pose2::new(0.5, 0.5, 0.0),
        )
    };
    let refused = |s: Scenario, expected: &str| {
        let e = Simulator::new(&s, 0).unwrap_err().to_string();
        assert!(e.starts_with(expected), "{e}");
    };
    let mut s = base();
    s.sim.dt = 1e-9;
    refused(s, "sim.dt = 1e-9: must be a finite number in [0.001, 1] s");
    let mut s = base();
    s.sim.pose_rate_hz = 1e9;
    refused(
        s,
        "sim.pose_rate_hz = 1e9: must be a finite number in [0.1, 1000] Hz",
    );
    let mut s = base();
    s.robot.sensors = vec![rgbd(160, 120, 2.5)];
    s.robot.sensors[0].rate_hz = 1e9;
    refused(s, "robot.sensors[0].rate_hz = 1e9: must be");
    let mut s = base();
    s.robot.sensors = vec![rgbd(100_000, 10_000, 2.5)];
    refused(
        s,
        "robot.sensors[0].width_px × height_px = 100000 × 10000 = 1000000000 rays: must be at most 1048576 rays",
    );
    let mut s = base();
    s.robot.sensors = vec![omni(720, 48, 1e12)];
    refused(
        s,
        "robot.sensors[0].range = 1e12: must be a finite number in (0, 1000] m",
    );
    let mut s = base();
    s.robot.sensors = vec![rgbd(160, 120, 2.5)];
    s.robot.sensors[0].height = -0.3;
    refused(s, "robot.sensors[0].height = -0.3: must be");
    let mut s = base();
    s.robot.footprint_radius = 1e9;
    refused(s, "robot.footprint_radius = 1e9: must be");
    let mut s = base();
    s.robot.gaits[1].max_speed = f64::INFINITY;
    refused(s, "robot.gaits[1].max_speed = inf: must be");
}
