//! `lab-track` (`000` §V): a 4 × 3 m fenced laboratory test track at 0.05 m with flat PVC,
//! turf-like grass, red carpet, wooden cubes (10 × 10 cm blocks up to 8 cm high, one patch of
//! about 2.3 × 1.2 m as in the paper), a ramp (up to 10 cm) and stairs (4 cm steps).
//!
//! Layout rules (every seed): the interior is split into two rows; the cubes take two adjacent
//! columns of one row, and grass, carpet, ramp and stairs are shuffled over the remaining four
//! slots; PVC fills the gaps. Ramps and stairs are humps (up then down) along a random axis.
//! Every step is below ρ_obstacle, so everything inside the fence is passable.
//!
//! Cost (`000`: roll variance over a 10 s window): flat 0.005, grass/carpet 0.008, ramp 0.02,
//! cubes 0.03, stairs 0.05; the regular gait is faster but doubles the roll variance on cubes
//! and stairs. The simulator adds the noise (`sim.proprio_noise`).

use rand::{RngExt, SeedableRng, rngs::ChaCha8Rng, seq::SliceRandom};
use strider_core::{Point2, Pose2, Rgb8};
use strider_map::MapParams;

use super::canvas::{Canvas, Look, resp, strategy_table, terrain};
use super::{MAX_ATTEMPTS, gen_error, snap, uni};
use crate::error::ScenarioError;
use crate::ground_truth::flood_fill;
use crate::model::{Bounds, Scenario, SimParams, Tour};
use crate::profiles;

pub(super) const DESCRIPTION: &str = "000 §V laboratory test track: 4×3 m fenced arena at 0.05 m \
with flat PVC, grass, red carpet, wooden cubes (≤ 8 cm), a ramp and 4 cm stairs; cost = roll \
variance (regular gait doubled on cubes/stairs), hexapod-rss; one tour over the terrain patches.";

/// Terrain indices.
pub const FLAT: u8 = 0;
/// Turf-like carpet.
pub const GRASS: u8 = 1;
/// Red carpet.
pub const CARPET: u8 = 2;
/// Wooden cubes.
pub const CUBES: u8 = 3;
/// Ramp.
pub const RAMP: u8 = 4;
/// Stairs.
pub const STAIRS: u8 = 5;
/// Fence.
pub const FENCE: u8 = 6;

/// `lab-track`: 4 × 3 m.
const SIZE: (f64, f64) = (4.0, 3.0);
/// `lab-track-large`: 5 × 4 m, the same rules on a bigger floor.
const SIZE_LARGE: (f64, f64) = (5.0, 4.0);
const RES: f64 = 0.05;

pub(super) fn generate(seed: u64) -> Result<Scenario, ScenarioError> {
    generate_sized(seed, "lab-track", DESCRIPTION, SIZE)
}

pub(super) const DESCRIPTION_LARGE: &str = "lab-track on a 5×4 m floor (same terrains, rules and \
costs): its Mcost reaches the ≥ 900 traversable 10 cm cells at which 000 reported planning times \
(23.2 s at 910 cells), which the 4×3 m track minus the robot's inflation cannot (≈ 760).";

pub(super) fn generate_large(seed: u64) -> Result<Scenario, ScenarioError> {
    generate_sized(seed, "lab-track-large", DESCRIPTION_LARGE, SIZE_LARGE)
}

fn generate_sized(
    seed: u64,
    name: &str,
    description: &str,
    (width, height): (f64, f64),
) -> Result<Scenario, ScenarioError> {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let robot = profiles::hexapod_rss();
    let map = MapParams {
        cell_size: 0.05,
        r_sensor: 2.5,
        r_robot: robot.footprint_radius,
        rho_obstacle: 0.25,
        sensor_height: 0.3,
        r_hist: 0.25,
        delta_desc: 0.15,
        c_radius: 0.5,
        ..MapParams::default()
    };
    // (terrain, name, roll variance adaptive, regular, speed adaptive, regular)
    let table: [(u8, &str, f64, f64, f64, f64); 6] = [
        (FLAT, "flat", 0.005, 0.005, 1.0, 1.0),
        (GRASS, "grass", 0.008, 0.008, 0.9, 0.85),
        (CARPET, "carpet", 0.008, 0.008, 0.95, 0.9),
        (CUBES, "cubes", 0.03, 0.06, 0.8, 0.6),
        (RAMP, "ramp", 0.02, 0.02, 0.85, 0.8),
        (STAIRS, "stairs", 0.05, 0.10, 0.7, 0.5),
    ];
    let mut terrains: Vec<_> = table
        .iter()
        .map(|&(i, n, va, vr, sa, sr)| {
            terrain(
                i,
                n,
                &[
                    ("adaptive", resp(sa, false, va, 0.0)),
                    ("regular", resp(sr, false, vr, 0.0)),
                ],
            )
        })
        .collect();
    terrains.push(terrain(FENCE, "fence", &[]));
    let looks = [
        Look::new(FLAT, Rgb8::new(140, 140, 140), 5.0, 0.0005),
        Look::new(GRASS, Rgb8::new(50, 150, 50), 9.0, 0.004),
        Look::new(CARPET, Rgb8::new(190, 40, 40), 7.0, 0.001),
        Look::new(CUBES, Rgb8::new(130, 90, 50), 9.0, 0.0),
        Look::new(RAMP, Rgb8::new(40, 70, 190), 7.0, 0.0005),
        Look::new(STAIRS, Rgb8::new(220, 200, 50), 7.0, 0.0),
        Look::new(FENCE, Rgb8::new(240, 240, 240), 4.0, 0.0),
    ];
    for _ in 0..MAX_ATTEMPTS {
        let mut c = Canvas::new(width, height, RES, FLAT);
        let (x_in, y_in) = (0.15, 0.15);
        let col_w = (width - 2.0 * x_in) / 3.0;
        let row_h = (height - 2.0 * y_in) / 2.0;
        let cube_row = rng.random_range(0..2usize);
        let cube_col = rng.random_range(0..2usize); // cubes take columns cube_col, cube_col + 1
        let mut slots: Vec<(usize, usize)> = Vec::new();
        for r in 0..2 {
            for col in 0..3 {
                if !(r == cube_row && (col == cube_col || col == cube_col + 1)) {
                    slots.push((col, r));
                }
            }
        }
        let mut feats = [GRASS, CARPET, RAMP, STAIRS];
        feats.shuffle(&mut rng);
        let mut centres: Vec<(u8, Point2)> = Vec::new();
        // Cubes: ≈ 2.3 × 1.2 m of 10 × 10 cm blocks.
        {
            let x0 = x_in + cube_col as f64 * col_w + uni(&mut rng, 0.05, 0.2);
            let y0 = y_in + cube_row as f64 * row_h + uni(&mut rng, 0.05, 0.15);
            let (cw, ch) = (
                uni(&mut rng, 2.0, 2.3),
                uni(&mut rng, 1.0, 1.2).min(row_h - 0.2),
            );
            for k in c.cells_in(x0, y0, x0 + cw, y0 + ch) {
                c.terrain[k] = CUBES;
            }
            // Block heights: one random height per 2 × 2-cell block.
            let blocks_w = ((width / 0.1).ceil()) as usize;
            let heights: Vec<f32> = (0..blocks_w * ((height / 0.1).ceil() as usize))
                .map(|_| (rng.random_range(0..=16u32) as f32) * 0.005)
                .collect();
            for k in 0..c.terrain.len() {
                if c.terrain[k] == CUBES {
                    let (bi, bj) = ((k % c.w) / 2, (k / c.w) / 2);
                    c.elev[k] = heights[bj * blocks_w + bi];
                }
            }
            centres.push((CUBES, Point2::new(x0 + cw / 2.0, y0 + ch / 2.0)));
        }
        for (&(col, r), &f) in slots.iter().zip(feats.iter()) {
            let sx0 = x_in + col as f64 * col_w;
            let sy0 = y_in + r as f64 * row_h;
            let (pw, ph) = (
                uni(&mut rng, 0.8, col_w - 0.2),
                uni(&mut rng, 0.8, row_h - 0.2),
            );
            let x0 = sx0 + uni(&mut rng, 0.05, col_w - pw - 0.05);
            let y0 = sy0 + uni(&mut rng, 0.05, row_h - ph - 0.05);
            let along_x = rng.random_bool(0.5);
            let cells = c.cells_in(x0, y0, x0 + pw, y0 + ph);
            for k in cells {
                c.terrain[k] = f;
                let p = c.center(k);
                let (u, len) = if along_x {
                    (p.x - x0, pw)
                } else {
                    (p.y - y0, ph)
                };
                let edge = u.min(len - u).max(0.0);
                c.elev[k] = match f {
                    RAMP => (0.10 * (edge / (len / 2.0 - 0.1)).min(1.0)) as f32,
                    STAIRS => {
                        let tread = 0.15;
                        0.04 * ((edge / tread).floor() + 1.0).min(3.0) as f32
                    }
                    _ => 0.0,
                };
            }
            centres.push((f, Point2::new(x0 + pw / 2.0, y0 + ph / 2.0)));
        }
        c.border(RES, FENCE, 0.3);
        let world = c.finish(terrains.clone(), &looks, &mut rng);
        let adm = world.gt_admissible(map.rho_obstacle, map.r_robot);
        let Some(start) = snap(&world, &adm, Point2::new(0.45, 0.45)) else {
            continue;
        };
        let Some(sk) = world.index_at(start) else {
            continue;
        };
        let reach = flood_fill(&adm, world.width(), world.height(), sk);
        if reach != adm {
            continue;
        }
        // Tour over the patches, counter-clockwise around the arena centre.
        let mid = Point2::new(width / 2.0, height / 2.0);
        centres.sort_by(|a, b| {
            let ang = |p: Point2| (p.y - mid.y).atan2(p.x - mid.x);
            ang(a.1).total_cmp(&ang(b.1))
        });
        let waypoints: Vec<Point2> = centres
            .iter()
            .filter_map(|&(_, p)| snap(&world, &adm, p))
            .collect();
        if waypoints.len() != 5 {
            continue;
        }
        let r = map.r_robot;
        return Ok(Scenario {
            name: name.into(),
            description: description.into(),
            world_seed: seed,
            world,
            robot,
            map,
            sim: SimParams::default(),
            strategy: rbcm_section(strategy_table(
                &[
                    ("mcost_cell", 0.10),
                    ("cost_window_s", 10.0),
                    ("delta_desc", 0.15),
                    ("r_spatial", 0.4),
                    // `000` rbcm-greedy (Alg. 1, Eq. 15–16).
                    ("delta_score", 0.5),
                    ("lambda_score", 0.001),
                    // Expert priors sized to roll variances of 0.005–0.1 rad²: σ_s 0.02,
                    // σ_n 0.005 (refitted per expert within bounds).
                    ("gp_lengthscale", 0.5),
                    ("gp_signal_variance", 4e-4),
                    ("gp_noise_variance", 2.5e-5),
                ],
                &[("m_max", 50), ("m_min", 25)],
            )),
            start: Pose2::new(start.x, start.y, 0.0),
            bounds: Bounds {
                min: Point2::new(r, r),
                max: Point2::new(width - r, height - r),
            },
            tours: vec![Tour {
                name: "patches".into(),
                waypoints,
                closed: true,
            }],
            time_limit_s: 3600.0,
            elevation_encoding: Default::default(),
        });
    }
    Err(gen_error(name, seed, "no connected layout found"))
}

/// The `[strategy]` table: `rbcm-greedy` with `000` Table I's λ_score per gait.
fn rbcm_section(mut table: toml::Table) -> toml::Table {
    let by_gait: toml::Table = [("adaptive", 0.001), ("regular", 0.0005)]
        .iter()
        .map(|&(g, v)| (g.to_string(), toml::Value::Float(v)))
        .collect();
    table.insert("lambda_score_by_gait".into(), toml::Value::Table(by_gait));
    super::canvas::sections(&["rbcm-greedy"], &table)
}
