//! `cot-track` (Prágr18 §IV-B): the laboratory test track of the cost-of-transport study — six
//! 3 m sections of different surfaces along one straight lane at 0.05 m, each followed by a strip
//! of flat PVC ("at the far end of each examined terrain there is usually a section of flat
//! ground"): PVC flooring (flat), turf-like carpet (grass), soft black fabric (black), and wooden
//! blocks covered with the turf (grass rough), covered with the fabric (black rough) and bare
//! (blocks). Blocks are 10 × 10 cm with random heights up to 8 cm (up to 6 cm under a cover).
//!
//! Cost of transport CoT = P / (m g v) (Prágr18 Eq. 1) of the hexapod's adaptive gait. The
//! paper gives the costs only qualitatively (§IV-C: flat, grass and grass rough differ little;
//! the blocks are less uniform, low-cost areas like flat with high-cost peaks; black and black
//! rough cost most, with peaks) and its Table I errors (≈ 6 with a variance ≈ 40) put them in
//! the tens, as usual for small hexapods. Our values: flat 20, grass 22, grass rough 24, blocks
//! 24 with peaks of 45, black 38, black rough 42 with peaks of 55. A peak is a block that stands
//! more than 4 cm above or below a neighbouring block (its own terrain type, `... (steep)`, with
//! the look of its surface), so geometry tells peaks apart where colour cannot. The simulator
//! realises a CoT through the speed factor sf and the gait power P = CoT · m g v_max · sf; its
//! power noise (`sim.proprio_noise` 0.2) stands in for the Hall-effect current sensor.
//!
//! Layout per seed: seed 1 keeps the paper's order (increasing difficulty: flat, grass, black,
//! grass rough, black rough, blocks); other seeds shuffle the sections. Block heights are random
//! for every seed. One open tour `track` runs along the lane from start to end.

use rand::seq::SliceRandom;
use strider_core::{Point2, Rgb8};
use strider_map::MapParams;

use super::builder::{self, Frame, Layout, ScenarioBuilder};
use super::canvas::Canvas;
use super::draw::{BlockLevels, TOP_LEVEL};
use super::placement::{reach_from, snap};
use super::strategy;
use super::terrains::{Look, TerrainTable, powered};
use crate::error::ScenarioError;
use crate::model::{RobotProfile, Scenario, SimParams};
use crate::profiles;

pub(super) const DESCRIPTION: &str = "Prágr18 cost-of-transport track: one lane at 0.05 m with six \
3 m sections — flat PVC, grass, black fabric, grass rough, black rough, bare blocks (10 cm blocks \
≤ 8 cm) — each followed by flat; CoT 20–55, hexapod-rss adaptive gait; one tour along the lane.";

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

/// Length of the floor, metres: a lead-in, six sections with their flat strips, a margin.
const W: f64 = LEAD + 6.0 * (SECTION + GAP) + 0.3;

pub(super) fn generate(seed: u64) -> Result<Scenario, ScenarioError> {
    let frame = Frame::new(W, H, RES, FLAT);
    let b = ScenarioBuilder::new(
        "cot-track",
        DESCRIPTION,
        seed,
        frame,
        profiles::hexapod_rss(),
    );
    let terrains = terrains(b.robot());
    b.map(|m| MapParams {
        r_sensor: 2.5,
        rho_obstacle: 0.25,
        sensor_height: 0.3,
        r_hist: 0.25,
        delta_desc: 0.2,
        c_radius: 0.5,
        ..m
    })
    .sim(SimParams {
        proprio_noise: 0.2,
        ..SimParams::default()
    })
    .strategy(
        &["learn-bench"],
        strategy::params(&[("cost_window_s", 3.0)], &[]),
    )
    .terrains(terrains)
    .generate("no passable lane found", |a| {
        let mut order = [FLAT, GRASS, BLACK, GRASS_ROUGH, BLACK_ROUGH, BLOCKS];
        if seed != 1 {
            order.shuffle(a.rng);
        }
        let mut c = a.canvas();
        let blocks = BlockLevels::draw(a.rng, c.w, c.h);
        for (s, &t) in order.iter().enumerate() {
            paint_section(&mut c, s, t, &blocks);
        }
        c.border(RES, FENCE, 0.3);
        let world = a.finish(&c);
        let adm = a.admissible(&world);
        let start = snap(&world, &adm, Point2::new(0.35, H / 2.0))?;
        let end = snap(&world, &adm, Point2::new(W - 0.35, H / 2.0))?;
        let reach = reach_from(&world, &adm, start)?;
        if !reach[world.index_at(end)?] {
            return None;
        }
        Some(Layout {
            world,
            start,
            tours: vec![builder::tour("track", vec![start, end], false)],
        })
    })
}

/// The CoT table realised for `robot`'s adaptive gait, and the fence.
fn terrains(robot: &RobotProfile) -> TerrainTable {
    let adaptive = robot
        .gaits
        .iter()
        .find(|g| g.name == "adaptive")
        .map_or(0.05, |g| g.max_speed);
    let mg = robot.mass_kg * 9.81;
    let pvc = Rgb8::new(150, 150, 150);
    let turf = Rgb8::new(50, 150, 50);
    let fabric = Rgb8::new(25, 25, 30);
    let wood = Rgb8::new(170, 120, 70);
    // (terrain, name, CoT, speed factor, look)
    #[rustfmt::skip]
    let table = [
        (FLAT, "flat", 20.0, 1.0, Look::new(pvc, 5.0, 0.0005)),
        (GRASS, "grass", 22.0, 0.9, Look::new(turf, 9.0, 0.004)),
        (BLACK, "black", 38.0, 0.7, Look::new(fabric, 4.0, 0.002)),
        (GRASS_ROUGH, "grass rough", 24.0, 0.85, Look::new(turf, 9.0, 0.002)),
        (BLACK_ROUGH, "black rough", 42.0, 0.6, Look::new(fabric, 4.0, 0.001)),
        (BLOCKS, "blocks", 24.0, 0.8, Look::new(wood, 9.0, 0.0)),
        (BLOCKS_STEEP, "blocks (steep)", 45.0, 0.5, Look::new(wood, 9.0, 0.0)),
        (BLACK_ROUGH_STEEP, "black rough (steep)", 55.0, 0.45, Look::new(fabric, 4.0, 0.001)),
    ];
    table
        .into_iter()
        .fold(TerrainTable::new(), |t, (i, n, cot, sf, look)| {
            // P = CoT · m g v, v = v_max · sf; both gaits respond alike (the drive uses the
            // adaptive one, as in the paper).
            let r = powered(sf, cot * mg * adaptive * sf);
            t.add(i, n, &[("adaptive", r.clone()), ("regular", r)], look)
        })
        .obstacle(FENCE, "fence", Look::white_wall())
}

/// Paints section `s` (0 = nearest the start) of terrain `t` across the lane; on block
/// terrains each cell takes its block's height, and blocks standing more than 4 cm above or
/// below a neighbour become the terrain's steep variant.
fn paint_section(c: &mut Canvas, s: usize, t: u8, blocks: &BlockLevels) {
    let (y0, y1) = ((H - PATCH_W) / 2.0, (H + PATCH_W) / 2.0);
    let x0 = LEAD + s as f64 * (SECTION + GAP);
    let cells = c.cells_in(x0, y0, x0 + SECTION, y1);
    let rough = matches!(t, GRASS_ROUGH | BLACK_ROUGH | BLOCKS);
    // Covered blocks top out at 6 cm (the cover fills the gaps a little).
    let max_h = if t == BLOCKS { 0.08 } else { 0.06 };
    let h_of = |bi: usize, bj: usize| blocks.level(bi, bj) as f64 / TOP_LEVEL as f64 * max_h;
    for k in cells {
        c.terrain[k] = t;
        if !rough {
            continue;
        }
        let (bi, bj) = BlockLevels::block_of(k % c.w, k / c.w);
        let z = h_of(bi, bj);
        c.elev[k] = z as f32;
        let steep = [(1i64, 0i64), (-1, 0), (0, 1), (0, -1)]
            .iter()
            .any(|&(di, dj)| {
                let (ni, nj) = (bi as i64 + di, bj as i64 + dj);
                ni >= 0
                    && nj >= 0
                    && (ni as usize) < blocks.width
                    && (nj as usize) < blocks.height
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
