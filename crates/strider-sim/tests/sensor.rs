//! Range sensors: field of view, noise, determinism.
mod common;

use common::*;
use strider_core::{Point3, PointCloud, Pose2};
use strider_scenario::SensorKind;
use strider_sim::{Heightfield, RangeSensor, ScanNoise, Simulator};

fn scan(
    spec: &strider_scenario::SensorSpec,
    world: &strider_scenario::World,
    pose: Pose2,
    noise: ScanNoise,
    seed: u64,
) -> PointCloud {
    let hf = Heightfield::from_world(world).unwrap();
    let s = RangeSensor::new(spec, "s").unwrap();
    let z = hf.elevation_at(pose.position()).unwrap();
    s.scan(
        &hf,
        &world.color,
        s.origin(pose, z),
        pose.yaw,
        &noise,
        0.0,
        seed,
        0,
    )
}

#[test]
fn rgbd_points_stay_in_the_fov_and_range() {
    let mut world = flat_world(120, 120, 0.05);
    fill(&mut world, 80, 82, 30, 90, 0.5, WALL);
    for (yaw, mount) in [(0.3, 0.0), (2.0, 180.0), (-1.0, 45.0)] {
        let mut spec = rgbd(64, 48, 2.5);
        spec.yaw_deg = mount;
        let pose = Pose2::new(3.0, 3.0, yaw);
        let cloud = scan(&spec, &world, pose, ScanNoise::NONE, 1);
        assert!(cloud.points.len() > 1000, "{}", cloud.points.len());
        let s = RangeSensor::new(&spec, "s").unwrap();
        let SensorKind::RgbD {
            hfov_deg,
            vfov_deg,
            tilt_deg,
            ..
        } = spec.kind
        else {
            unreachable!()
        };
        let o = cloud.origin;
        assert_eq!(o, Point3::new(3.0, 3.0, 0.3));
        let heading = yaw + mount.to_radians();
        for p in &cloud.points {
            let v = [p.x as f64 - o.x, p.y as f64 - o.y, p.z as f64 - o.z];
            let r = (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt();
            assert!(r <= 2.5 + 1e-5);
            // Into the camera frame, independently of RangeSensor::in_fov.
            let (sy, cy) = heading.sin_cos();
            let (bx, by) = (v[0] * cy + v[1] * sy, -v[0] * sy + v[1] * cy);
            let (st, ct) = tilt_deg.to_radians().sin_cos();
            let (cx, cz) = (bx * ct - v[2] * st, bx * st + v[2] * ct);
            assert!(cx > 0.0);
            assert!((by / cx).abs() <= (hfov_deg.to_radians() / 2.0).tan() + 1e-4);
            assert!((cz / cx).abs() <= (vfov_deg.to_radians() / 2.0).tan() + 1e-4);
            assert!(
                s.in_fov(yaw, [v[0], v[1], v[2]]) || {
                    // f32 rounding at the very edge of the image
                    let e = 1e-3;
                    (by / cx).abs() > (hfov_deg.to_radians() / 2.0).tan() - e
                        || (cz / cx).abs() > (vfov_deg.to_radians() / 2.0).tan() - e
                }
            );
        }
    }
}

#[test]
fn omni_covers_all_directions() {
    let world = flat_world(200, 200, 0.1);
    let spec = omni(360, 16, 10.0);
    let cloud = scan(
        &spec,
        &world,
        Pose2::new(10.0, 10.0, 0.7),
        ScanNoise::NONE,
        1,
    );
    let mut bins = [0usize; 36];
    for p in &cloud.points {
        let a = (p.y as f64 - 10.0).atan2(p.x as f64 - 10.0);
        let b = (((a + std::f64::consts::PI) / std::f64::consts::TAU) * 36.0) as usize;
        bins[b.min(35)] += 1;
        let r = ((p.x as f64 - 10.0).powi(2)
            + (p.y as f64 - 10.0).powi(2)
            + (p.z as f64 - 0.5).powi(2))
        .sqrt();
        assert!(r <= 10.0 + 1e-4);
    }
    assert!(bins.iter().all(|&n| n > 0), "{bins:?}");
    let (min, max) = (bins.iter().min().unwrap(), bins.iter().max().unwrap());
    assert!(max - min <= max / 5, "uniform in azimuth: {bins:?}");
}

#[test]
fn depth_noise_has_the_modelled_statistics() {
    let world = flat_world(120, 120, 0.05);
    let noise = ScanNoise {
        depth_sigma: 0.01,
        depth_k: 0.01,
        color_sigma: 6.0,
    };
    let spec = rgbd(160, 120, 2.5);
    let pose = Pose2::new(3.0, 3.0, 0.4);
    let cloud = scan(&spec, &world, pose, noise, 7);
    let o = cloud.origin;
    let (mut n, mut sum, mut sum2) = (0.0, 0.0, 0.0);
    let (mut csum, mut csum2) = (0.0, 0.0);
    for p in &cloud.points {
        let v = [p.x as f64 - o.x, p.y as f64 - o.y, p.z as f64 - o.z];
        let r = (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt();
        // True range along this (noise-free) direction over flat ground at z = 0.
        let r_true = o.z * r / -v[2];
        let z = (r - r_true) / noise.depth_std(r_true);
        n += 1.0;
        sum += z;
        sum2 += z * z;
        // Colour noise against the true cell colour.
        let c =
            strider_core::Cell::containing(o.x + v[0] / r * r_true, o.y + v[1] / r * r_true, 0.05)
                .unwrap();
        let truth = world.color[world.rect.index(c).unwrap()];
        let e = p.rgb[1] as f64 - truth.0[1] as f64;
        csum += e;
        csum2 += e * e;
    }
    let mean = sum / n;
    let std = (sum2 / n - mean * mean).sqrt();
    assert!(n > 10000.0);
    assert!(mean.abs() < 0.03, "mean {mean}");
    assert!((std - 1.0).abs() < 0.03, "std {std}");
    let cmean = csum / n;
    let cstd = (csum2 / n - cmean * cmean).sqrt();
    assert!(cmean.abs() < 0.2, "{cmean}");
    assert!((cstd - 6.0).abs() < 0.3, "{cstd}");
}

#[test]
fn scans_are_deterministic_and_thread_count_independent() {
    let mut world = flat_world(150, 150, 0.1);
    fill(&mut world, 90, 95, 20, 120, 1.0, WALL);
    let spec = omni(720, 24, 10.0);
    let noise = ScanNoise {
        depth_sigma: 0.01,
        depth_k: 0.002,
        color_sigma: 4.0,
    };
    let pose = Pose2::new(7.0, 7.0, 0.1);
    let run = |threads: usize, seed: u64| {
        rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap()
            .install(|| scan(&spec, &world, pose, noise, seed))
    };
    let a = run(1, 5);
    let b = run(4, 5);
    let c = run(3, 6);
    assert!(a.points.len() > 5000);
    assert_eq!(a.points, b.points, "identical on 1 and 4 threads");
    assert_ne!(a.points, c.points, "another seed draws other noise");
}

#[test]
fn simulator_runs_are_reproducible() {
    let mut world = flat_world(80, 80, 0.05);
    fill(&mut world, 50, 52, 10, 70, 0.5, WALL);
    let sc = scenario(
        world,
        robot(vec![rgbd(40, 30, 2.5), omni(90, 8, 3.0)]),
        strider_scenario::SimParams {
            pose_sigma_xy: 0.01,
            pose_sigma_yaw: 0.01,
            ..Default::default()
        },
        Pose2::new(1.0, 1.0, 0.0),
    );
    #[derive(Default)]
    struct Rec {
        poses: Vec<strider_core::PoseStamped>,
        clouds: Vec<(f64, u8, Vec<strider_core::ColoredPoint>)>,
        proprio: Vec<strider_core::Proprioception>,
    }
    impl strider_core::interface::SensorSink for Rec {
        fn on_pose(&mut self, p: &strider_core::PoseStamped) {
            self.poses.push(*p);
        }
        fn on_cloud(&mut self, c: &PointCloud) {
            self.clouds.push((c.stamp, c.sensor, c.points.clone()));
        }
        fn on_proprioception(&mut self, p: &strider_core::Proprioception) {
            self.proprio.push(*p);
        }
    }
    use strider_core::interface::Robot;
    let run = |seed: u64| {
        let mut sim = Simulator::new(&sc, seed).unwrap();
        let mut rec = Rec::default();
        sim.follow(&[
            strider_core::Point2::new(1.0, 1.0),
            strider_core::Point2::new(2.0, 1.5),
            strider_core::Point2::new(2.0, 3.0),
        ]);
        for _ in 0..20 {
            sim.advance(0.5, &mut rec).unwrap();
        }
        rec
    };
    let (a, b, c) = (run(1), run(1), run(2));
    assert_eq!(a.poses, b.poses);
    assert_eq!(a.clouds, b.clouds);
    assert_eq!(a.proprio, b.proprio);
    assert_ne!(a.poses, c.poses);
    assert_ne!(a.clouds, c.clouds);
    // Clouds: 5 Hz RGB-D and 2 Hz omni over 10 s, both at t = 0.
    assert_eq!(a.clouds.len(), 51 + 21);
    assert!(a.clouds.windows(2).all(|w| w[0].0 <= w[1].0), "time order");
    assert_eq!(
        a.clouds.iter().filter(|c| c.1 == 1).count(),
        21,
        "omni is sensor 1"
    );
    assert!(a.clouds.iter().all(|c| c.1 < 2));
    // scan_now takes one cloud per sensor without moving or advancing time.
    let mut sim = Simulator::new(&sc, 1).unwrap();
    let clouds = sim.scan_now();
    assert_eq!(clouds.len(), 2);
    assert_eq!((clouds[0].sensor, clouds[1].sensor), (0, 1));
    assert!(
        clouds
            .iter()
            .all(|c| !c.points.is_empty() && c.stamp == 0.0)
    );
    assert_eq!(sim.now(), 0.0);
}
