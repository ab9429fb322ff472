//! `cot-track` (thesis C1 §IV-B): the laboratory test track of the cost-of-transport study — six
//! 3 m sections of different surfaces along one straight lane at 0.05 m, each followed by a strip
//! of flat PVC ("at the far end of each examined terrain there is usually a section of flat
//! ground"): PVC flooring (flat), turf-like carpet (grass), soft black fabric (black), and wooden
//! blocks covered with the turf (grass rough), covered with the fabric (black rough) and bare
//! (blocks). Blocks are 10 × 10 cm with random heights up to 8 cm (up to 6 cm under a cover).
//!
//! Cost of transport CoT = P / (m g v) (thesis C1 Eq. 1) of the hexapod's adaptive gait. The
//! thesis gives the costs only qualitatively (§IV-C: flat, grass and grass rough differ little;
//! the blocks are less uniform, low-cost areas like flat with high-cost peaks; black and black
//! rough cost most, with peaks) and its Table I errors (≈ 6 with a variance ≈ 40) put them in
//! the tens, as usual for small hexapods. Our values: flat 20, grass 22, grass rough 24, blocks
//! 24 with peaks of 45, black 38, black rough 42 with peaks of 55. A peak is a block that stands
//! more than 4 cm above or below a neighbouring block (its own terrain type, `... (steep)`, with
//! the look of its surface), so geometry tells peaks apart where colour cannot. The simulator
//! realises a CoT through the speed factor sf and the gait power P = CoT · m g v_max · sf; its
//! power noise (`sim.proprio_noise` 0.2) stands in for the Hall-effect current sensor.
//!
//! Layout per seed: seed 1 keeps the thesis' order (increasing difficulty: flat, grass, black,
//! grass rough, black rough, blocks); other seeds shuffle the sections. Block heights are random
//! for every seed. One open tour `track` runs along the lane from start to end.

use rand::{RngExt, SeedableRng, rngs::ChaCha8Rng, seq::SliceRandom};
use strider_core::{Point2, Pose2, Rgb8};
use strider_map::MapParams;

use super::canvas::{Canvas, Look, resp, strategy_table, terrain};
use super::{MAX_ATTEMPTS, gen_error, snap};
use crate::error::ScenarioError;
use crate::ground_truth::flood_fill;
use crate::model::{Bounds, Scenario, SimParams, Tour};
use crate::profiles;

pub(super) const DESCRIPTION: &str = "thesis C1 cost-of-transport track: one lane at 0.05 m with \
six 3 m sections — flat PVC, grass, black fabric, grass rough, black rough, bare blocks (10 cm \
blocks ≤ 8 cm) — each followed by flat; CoT 20–55, hexapod-rss adaptive gait; one tour along the \
lane.";

/// Terrain indices: PVC flooring.
pub const FLAT: u8 = 0;
/// Turf-like carpet.
pub const GRASS: u8 = 1;
/// Soft black fabric.
pub const BLACK: u8 = 2;
/// Blocks covered with the turf.
pub const GRASS_ROUGH: u8 = 3;
/// Blocks covered with the fabric.
pub const BLACK_ROUGH: u8 = 4;
/// Bare wooden blocks.
pub const BLOCKS: u8 = 5;
/// Bare blocks standing > 4 cm above or below a neighbour (CoT peaks).
pub const BLOCKS_STEEP: u8 = 6;
/// Fabric-covered blocks standing > 4 cm above or below a neighbour (CoT peaks).
pub const BLACK_ROUGH_STEEP: u8 = 7;
/// Fence.
pub const FENCE: u8 = 8;

/// Section length and the flat strip after it, metres.
const SECTION: f64 = 3.0;
const GAP: f64 = 0.5;
const LEAD: f64 = 0.6;
const H: f64 = 1.6;
const RES: f64 = 0.05;
/// Patch width across the lane, metres.
const PATCH_W: f64 = 0.9;

pub(super) fn generate(seed: u64) -> Result<Scenario, ScenarioError> {
    let name = "cot-track";
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let robot = profiles::hexapod_rss();
    let w = LEAD + 6.0 * (SECTION + GAP) + 0.3;
    let map = MapParams {
        cell_size: RES,
        r_sensor: 2.5,
        r_robot: robot.footprint_radius,
        rho_obstacle: 0.25,
        sensor_height: 0.3,
        r_hist: 0.25,
        delta_desc: 0.2,
        c_radius: 0.5,
        ..MapParams::default()
    };
    let adaptive = robot
        .gaits
        .iter()
        .find(|g| g.name == "adaptive")
        .map_or(0.05, |g| g.max_speed);
    let mg = robot.mass_kg * 9.81;
    // (terrain, name, CoT, speed factor)
    let table: [(u8, &str, f64, f64); 8] = [
        (FLAT, "flat", 20.0, 1.0),
        (GRASS, "grass", 22.0, 0.9),
        (BLACK, "black", 38.0, 0.7),
        (GRASS_ROUGH, "grass rough", 24.0, 0.85),
        (BLACK_ROUGH, "black rough", 42.0, 0.6),
        (BLOCKS, "blocks", 24.0, 0.8),
        (BLOCKS_STEEP, "blocks (steep)", 45.0, 0.5),
        (BLACK_ROUGH_STEEP, "black rough (steep)", 55.0, 0.45),
    ];
    let mut terrains: Vec<_> = table
        .iter()
        .map(|&(i, n, cot, sf)| {
            // P = CoT · m g v, v = v_max · sf; both gaits respond alike (the drive uses the
            // adaptive one, as in the thesis).
            let r = resp(sf, false, 0.0, cot * mg * adaptive * sf);
            terrain(i, n, &[("adaptive", r.clone()), ("regular", r)])
        })
        .collect();
    terrains.push(terrain(FENCE, "fence", &[]));
    let pvc = Rgb8::new(150, 150, 150);
    let turf = Rgb8::new(50, 150, 50);
    let fabric = Rgb8::new(25, 25, 30);
    let wood = Rgb8::new(170, 120, 70);
    let looks = [
        Look::new(FLAT, pvc, 5.0, 0.0005),
        Look::new(GRASS, turf, 9.0, 0.004),
        Look::new(BLACK, fabric, 4.0, 0.002),
        Look::new(GRASS_ROUGH, turf, 9.0, 0.002),
        Look::new(BLACK_ROUGH, fabric, 4.0, 0.001),
        Look::new(BLOCKS, wood, 9.0, 0.0),
        Look::new(BLOCKS_STEEP, wood, 9.0, 0.0),
        Look::new(BLACK_ROUGH_STEEP, fabric, 4.0, 0.001),
        Look::new(FENCE, Rgb8::new(240, 240, 240), 4.0, 0.0),
    ];
    for _ in 0..MAX_ATTEMPTS {
        let mut order = [FLAT, GRASS, BLACK, GRASS_ROUGH, BLACK_ROUGH, BLOCKS];
        if seed != 1 {
            order.shuffle(&mut rng);
        }
        let mut c = Canvas::new(w, H, RES, FLAT);
        let (y0, y1) = ((H - PATCH_W) / 2.0, (H + PATCH_W) / 2.0);
        // One random height per 2 × 2-cell block over the whole canvas.
        let blocks_w = c.w.div_ceil(2);
        let blocks_h = c.h.div_ceil(2);
        let heights: Vec<u32> = (0..blocks_w * blocks_h)
            .map(|_| rng.random_range(0..=16u32))
            .collect();
        for (s, &t) in order.iter().enumerate() {
            let x0 = LEAD + s as f64 * (SECTION + GAP);
            let cells = c.cells_in(x0, y0, x0 + SECTION, y1);
            let rough = matches!(t, GRASS_ROUGH | BLACK_ROUGH | BLOCKS);
            // Covered blocks top out at 6 cm (the cover fills the gaps a little).
            let max_h = if t == BLOCKS { 0.08 } else { 0.06 };
            let h_of = |bi: usize, bj: usize| heights[bj * blocks_w + bi] as f64 / 16.0 * max_h;
            for k in cells {
                c.terrain[k] = t;
                if !rough {
                    continue;
                }
                let (bi, bj) = ((k % c.w) / 2, (k / c.w) / 2);
                let z = h_of(bi, bj);
                c.elev[k] = z as f32;
                let steep = [(1i64, 0i64), (-1, 0), (0, 1), (0, -1)]
                    .iter()
                    .any(|&(di, dj)| {
                        let (ni, nj) = (bi as i64 + di, bj as i64 + dj);
                        ni >= 0
                            && nj >= 0
                            && (ni as usize) < blocks_w
                            && (nj as usize) < blocks_h
                            && (h_of(ni as usize, nj as usize) - z).abs() > 0.04
                    });
                if steep {
                    c.terrain[k] = match t {
                        BLOCKS => BLOCKS_STEEP,
                        BLACK_ROUGH => BLACK_ROUGH_STEEP,
                        other => other,
                    };
                }
            }
        }
        c.border(RES, FENCE, 0.3);
        let world = c.finish(terrains.clone(), &looks, &mut rng);
        let adm = world.gt_admissible(map.rho_obstacle, map.r_robot);
        let (Some(start), Some(end)) = (
            snap(&world, &adm, Point2::new(0.35, H / 2.0)),
            snap(&world, &adm, Point2::new(w - 0.35, H / 2.0)),
        ) else {
            continue;
        };
        let (Some(sk), Some(ek)) = (world.index_at(start), world.index_at(end)) else {
            continue;
        };
        if !flood_fill(&adm, world.width(), world.height(), sk)[ek] {
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
            sim: SimParams {
                proprio_noise: 0.2,
                ..SimParams::default()
            },
            strategy: super::canvas::sections(
                &["learn-bench"],
                &strategy_table(&[("cost_window_s", 3.0)], &[]),
            ),
            start: Pose2::new(start.x, start.y, 0.0),
            bounds: Bounds {
                min: Point2::new(r, r),
                max: Point2::new(w - r, H - r),
            },
            tours: vec![Tour {
                name: "track".into(),
                waypoints: vec![start, end],
                closed: false,
            }],
            time_limit_s: 3600.0,
            elevation_encoding: Default::default(),
        });
    }
    Err(gen_error(name, seed, "no passable lane found"))
}
