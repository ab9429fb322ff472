//! `escape-arena` (thesis C4 §5.2): about 7 × 5 m (35 m²) at 0.05 m in three sections with no
//! line of sight between them: an office room with rigid wooden boxes and white walls, a purple
//! fabric curtain in its wall to a corridor, and a second curtain splitting the corridor.
//!
//! Walls and curtains are 1 m high, so curtains look like obstacles (step > t_trav = 0.12 m =
//! `map.rho_obstacle`) and block the view; a curtain needs 0.5–1 N to push through
//! (`push_force_n`, drawn per seed), boxes 15 N, walls are rigid (`None`). With all apparent
//! obstacles rigid only the office is reachable; with the curtains pushed, everything is.

use rand::{RngExt, SeedableRng, rngs::ChaCha8Rng};
use strider_core::{Point2, Pose2, Rgb8};
use strider_map::MapParams;

use super::canvas::{Canvas, Look, resp, strategy_table, terrain};
use super::{MAX_ATTEMPTS, gen_error, snap, uni};
use crate::error::ScenarioError;
use crate::ground_truth::flood_fill;
use crate::model::{Bounds, Scenario, SimParams, Tour};
use crate::profiles;

pub(super) const DESCRIPTION: &str = "Thesis C4 §5.2 escape arena: ~35 m² at 0.05 m, an office \
with rigid wooden boxes and white walls, a purple curtain (0.5–1 N) to a corridor that a second \
curtain splits; three sections without line of sight, hexapod-bumper (t_trav 0.12 m, F_trav 2 N).";

/// Terrain indices.
pub const FLOOR: u8 = 0;
/// White walls.
pub const WALL: u8 = 1;
/// Rigid wooden boxes.
pub const BOX: u8 = 2;
/// Purple fabric curtains.
pub const CURTAIN: u8 = 3;

const W: f64 = 7.0;
const H: f64 = 5.0;
const RES: f64 = 0.05;
const WALL_T: f64 = 0.1;
const WALL_Z: f32 = 1.0;

pub(super) fn generate(seed: u64) -> Result<Scenario, ScenarioError> {
    let name = "escape-arena";
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let robot = profiles::hexapod_bumper();
    let map = MapParams {
        cell_size: 0.05,
        r_sensor: 2.0,
        r_robot: robot.footprint_radius,
        rho_obstacle: 0.12,
        sensor_height: 0.3,
        r_hist: 0.25,
        c_radius: 0.5,
        ..MapParams::default()
    };
    let curtain_force = (uni(&mut rng, 0.5, 1.0) * 20.0).round() / 20.0;
    let walk = resp(1.0, false, 0.0, 0.0);
    let mut terrains = vec![
        terrain(FLOOR, "floor", &[("walk", walk)]),
        terrain(WALL, "wall", &[]),
        terrain(BOX, "wooden box", &[]),
        terrain(CURTAIN, "curtain", &[("walk", resp(0.8, false, 0.0, 0.0))]),
    ];
    terrains[2].push_force_n = Some(15.0);
    terrains[3].push_force_n = Some(curtain_force);
    let looks = [
        Look::new(FLOOR, Rgb8::new(120, 120, 125), 6.0, 0.001),
        Look::new(WALL, Rgb8::new(240, 240, 240), 4.0, 0.0),
        Look::new(BOX, Rgb8::new(130, 90, 50), 8.0, 0.0),
        Look::new(CURTAIN, Rgb8::new(170, 60, 170), 8.0, 0.0),
    ];
    for _ in 0..MAX_ATTEMPTS {
        let mut c = Canvas::new(W, H, RES, FLOOR);
        let cw = uni(&mut rng, 1.4, 1.8);
        let wx = W - WALL_T - cw - WALL_T; // dividing wall [wx, wx + WALL_T]
        let m = uni(&mut rng, 2.6, 3.3); // corridor curtain [m, m + WALL_T]
        let c1_w = uni(&mut rng, 1.0, 1.2);
        let c1_y = uni(&mut rng, WALL_T + 0.3, m - 0.3 - c1_w);
        c.border(WALL_T, WALL, WALL_Z);
        c.rect(wx, 0.0, wx + WALL_T, H, WALL, Some(WALL_Z));
        c.rect(wx, c1_y, wx + WALL_T, c1_y + c1_w, CURTAIN, Some(WALL_Z));
        c.rect(
            wx + WALL_T,
            m,
            W - WALL_T,
            m + WALL_T,
            CURTAIN,
            Some(WALL_Z),
        );
        // Boxes in the office, clear of walls, of each other and of the curtain.
        let clear = 0.75;
        let door = Point2::new(wx, c1_y + c1_w / 2.0);
        let mut boxes: Vec<[f64; 4]> = Vec::new();
        let n = rng.random_range(3..6usize);
        for _ in 0..20 {
            if boxes.len() >= n {
                break;
            }
            let (bw, bh) = (uni(&mut rng, 0.4, 0.8), uni(&mut rng, 0.4, 0.8));
            let bx = uni(&mut rng, WALL_T + clear, wx - clear - bw);
            let by = uni(&mut rng, WALL_T + clear, H - WALL_T - clear - bh);
            let b = [bx, by, bx + bw, by + bh];
            let gap = |o: &[f64; 4]| {
                let dx = (o[0] - b[2]).max(b[0] - o[2]).max(0.0);
                let dy = (o[1] - b[3]).max(b[1] - o[3]).max(0.0);
                dx.hypot(dy)
            };
            let near_door = {
                let dx = (b[0] - door.x).max(door.x - b[2]).max(0.0);
                let dy = (b[1] - door.y).max(door.y - b[3]).max(0.0);
                dx.hypot(dy) < 1.3
            };
            let near_start = b[0] < 1.3 && b[1] < 1.3;
            if !near_door && !near_start && boxes.iter().all(|o| gap(o) >= clear) {
                let z = uni(&mut rng, 0.4, 0.7) as f32;
                c.rect(b[0], b[1], b[2], b[3], BOX, Some(z));
                boxes.push(b);
            }
        }
        let world = c.finish(terrains.clone(), &looks, &mut rng);
        let adm = world.gt_admissible(map.rho_obstacle, map.r_robot);
        let (ww, wh) = (world.width(), world.height());
        let Some(start) = snap(&world, &adm, Point2::new(0.6, 0.6)) else {
            continue;
        };
        let targets = [
            Point2::new(wx / 2.0, H / 2.0),
            Point2::new(wx + WALL_T + cw / 2.0, m / 2.0),
            Point2::new(wx + WALL_T + cw / 2.0, (m + H) / 2.0),
        ];
        let sections: Vec<Point2> = targets
            .iter()
            .filter_map(|&p| snap(&world, &adm, p))
            .collect();
        if sections.len() != 3 {
            continue;
        }
        let Some(sk) = world.index_at(start) else {
            continue;
        };
        // Rigid view: the office is one connected piece and the corridor is out of reach.
        let office = flood_fill(&adm, ww, wh, sk);
        let office_all =
            (0..adm.len()).all(|k| !adm[k] || office[k] == (world.cell_center(k).x < wx));
        // Curtains pushed: everything is reachable.
        let mut open = world.clone();
        for k in 0..open.elevation.len() {
            if open.terrain[k] == CURTAIN {
                open.elevation[k] = 0.0;
            }
        }
        let open_adm = open.gt_admissible(map.rho_obstacle, map.r_robot);
        let all = flood_fill(&open_adm, ww, wh, sk);
        if !office_all || all != open_adm {
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
            sim: SimParams::default(),
            strategy: super::canvas::sections(
                &["escape", "rigid"],
                &strategy_table(&[("f_trav", 2.0)], &[]),
            ),
            start: Pose2::new(start.x, start.y, 0.0),
            bounds: Bounds {
                min: Point2::new(r, r),
                max: Point2::new(W - r, H - r),
            },
            tours: vec![Tour {
                name: "sections".into(),
                waypoints: sections,
                closed: false,
            }],
            time_limit_s: 3600.0,
            elevation_encoding: Default::default(),
        });
    }
    Err(gen_error(name, seed, "no valid layout found"))
}
