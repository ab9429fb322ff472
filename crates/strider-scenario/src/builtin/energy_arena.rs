//! `energy-arena` (`003`): a 2 × 1.5 m flat floor at 0.05 m of smooth timber (0.63 W at
//! 0.1 m/s) with a grey carpet band (1.21 W) lying across the straight lines from the base to the
//! three waypoints; a timber gap at one end of the band leaves an energy-cheaper detour. The rover
//! draws a 0.21 W hotel load; the benchmark runs 25 tours (`strategy.tours.n_tours`). As in `003` §4
//! the pose arrives at 30 Hz and the power at 10 Hz, both noisy.

use rand::{RngExt, SeedableRng, rngs::ChaCha8Rng};
use strider_core::{Point2, Pose2, Rgb8};
use strider_map::MapParams;

use super::canvas::{Canvas, Look, resp, strategy_table, terrain};
use super::{MAX_ATTEMPTS, gen_error, uni};
use crate::error::ScenarioError;
use crate::ground_truth::{flood_fill, point_in_mask};
use crate::model::{Bounds, Scenario, SimParams, Tour};
use crate::profiles;

pub(super) const DESCRIPTION: &str = "003 energy arena: 2×1.5 m at 0.05 m, smooth timber (0.63 W \
at 0.1 m/s) with a grey carpet band (1.21 W) across the straight lines between base and the 3 \
waypoints, rover-small (hotel load 0.21 W); tour = base + 3 waypoints, 25 tours.";

/// Terrain indices.
pub const TIMBER: u8 = 0;
/// Grey carpet.
pub const CARPET: u8 = 1;
/// Border wall.
pub const WALL: u8 = 2;

const W: f64 = 2.0;
const H: f64 = 1.5;
const RES: f64 = 0.05;

/// `003` §4: the overhead ArUco tracker updates the pose at 30 Hz and the robot logs its motor
/// power at 10 Hz. Both are noisy: a few millimetres and about a degree of tracker jitter (a
/// 100 mm marker seen by a webcam from about 1.5 m), and the default 5 % on the power reading.
fn sim_params() -> SimParams {
    SimParams {
        pose_rate_hz: 30.0,
        pose_sigma_xy: 0.003,
        pose_sigma_yaw: 0.02,
        proprio_rate_hz: 10.0,
        ..SimParams::default()
    }
}

pub(super) fn generate(seed: u64) -> Result<Scenario, ScenarioError> {
    let name = "energy-arena";
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let robot = profiles::rover_small();
    let map = MapParams {
        cell_size: 0.05,
        r_robot: robot.footprint_radius,
        rho_obstacle: 0.05,
        r_sensor: 0.5,
        sensor_height: 0.1,
        r_hist: 0.1,
        c_radius: 0.2,
        ..MapParams::default()
    };
    let terrains = vec![
        terrain(TIMBER, "timber", &[("drive", resp(1.0, false, 0.0, 0.63))]),
        terrain(
            CARPET,
            "grey carpet",
            &[("drive", resp(1.0, false, 0.0, 1.21))],
        ),
        terrain(WALL, "wall", &[]),
    ];
    let looks = [
        Look::new(TIMBER, Rgb8::new(170, 120, 70), 7.0, 0.0005),
        Look::new(CARPET, Rgb8::new(120, 120, 120), 6.0, 0.001),
        Look::new(WALL, Rgb8::new(240, 240, 240), 4.0, 0.0),
    ];
    for _ in 0..MAX_ATTEMPTS {
        let mut c = Canvas::new(W, H, RES, TIMBER);
        let base = Point2::new(uni(&mut rng, 0.2, 0.35), uni(&mut rng, 0.55, 0.95));
        let wps: Vec<Point2> = [0.3, 0.75, 1.2]
            .iter()
            .map(|&y| Point2::new(uni(&mut rng, 1.6, 1.8), y + uni(&mut rng, -0.08, 0.08)))
            .collect();
        let xc = uni(&mut rng, 0.85, 1.15);
        let half = uni(&mut rng, 0.15, 0.25);
        let tilt = uni(&mut rng, -0.15, 0.15);
        let gap_low = rng.random_bool(0.5);
        let (y0, y1) = if gap_low { (0.35, H) } else { (0.0, H - 0.35) };
        let cells = c.cells_in(0.0, y0, W, y1);
        c.paint(
            cells,
            |p, _| (p.x - (xc + tilt * (p.y - H / 2.0))).abs() <= half,
            CARPET,
            Some(0.005),
        );
        c.border(RES, WALL, 0.1);
        let world = c.finish(terrains.clone(), &looks, &mut rng);
        let adm = world.gt_admissible(map.rho_obstacle, map.r_robot);
        let mut tour = vec![base];
        tour.extend(wps.iter().copied());
        if !tour.iter().all(|&p| point_in_mask(&world, &adm, p)) {
            continue;
        }
        // Each straight base → waypoint line crosses the carpet; a timber-only detour exists.
        let crosses = |a: Point2, b: Point2| {
            (0..=100).any(|s| {
                let f = s as f64 / 100.0;
                let p = Point2::new(a.x + f * (b.x - a.x), a.y + f * (b.y - a.y));
                world
                    .index_at(p)
                    .is_some_and(|k| world.terrain[k] == CARPET)
            })
        };
        let timber: Vec<bool> = (0..adm.len())
            .map(|k| adm[k] && world.terrain[k] == TIMBER)
            .collect();
        let Some(bk) = world.index_at(base) else {
            continue;
        };
        let reach = flood_fill(&timber, world.width(), world.height(), bk);
        let ok = wps
            .iter()
            .all(|&w| crosses(base, w) && world.index_at(w).is_some_and(|k| reach[k]));
        if !ok {
            continue;
        }
        let r = map.r_robot;
        return Ok(Scenario {
            name: name.into(),
            description: DESCRIPTION.into(),
            world_seed: seed,
            world,
            robot,
            map,
            sim: sim_params(),
            strategy: super::canvas::sections(&["tours"], &strategy_table(&[], &[("n_tours", 25)])),
            start: Pose2::new(base.x, base.y, 0.0),
            bounds: Bounds {
                min: Point2::new(r, r),
                max: Point2::new(W - r, H - r),
            },
            tours: vec![Tour {
                name: "base-waypoints".into(),
                waypoints: tour,
                closed: true,
            }],
            time_limit_s: 3600.0,
            elevation_encoding: Default::default(),
        });
    }
    Err(gen_error(name, seed, "no valid layout found"))
}
