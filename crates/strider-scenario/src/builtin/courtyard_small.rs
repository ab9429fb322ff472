//! `courtyard-small` (`001` §5.1.1): a 6 × 5 m flat courtyard at 0.05 m with gray pavement, a
//! thin red pavement line and green/brown turf covering about a third of the area.
//!
//! Layout rules (every seed):
//! * a turf patch reaches from the east wall westward across the bottom-right → top-right
//!   segment of tour 1, so the straight segment crosses turf while a longer pavement detour
//!   around its west end exists;
//! * a turf patch covers the top-left waypoint (turf cannot be avoided there);
//! * further turf blobs bring turf to 31–35 % of the area;
//! * a red pavement line ~0.1 m wide (that cluster erosion must remove) crosses the pavement.
//!
//! The courtyard is flat and open as in the paper: no wall rings it. The robot stays inside
//! because the simulator refuses motion off the world, and exploration goals outside the bounds
//! are dropped (decision 5).

use rand::{RngExt, SeedableRng, rngs::ChaCha8Rng};
use strider_core::{Point2, Pose2, Rgb8};
use strider_map::MapParams;

use super::canvas::{Canvas, Look, resp, strategy_table, terrain};
use super::{MAX_ATTEMPTS, gen_error, sample_cells, uni};
use crate::error::ScenarioError;
use crate::ground_truth::{flood_fill, point_in_mask};
use crate::model::{Bounds, Scenario, SimParams, Tour};
use crate::profiles;

pub(super) const DESCRIPTION: &str = "001 §5.1.1 small courtyard: 6×5 m at 0.05 m, gray pavement \
with a thin red line, green and brown turf (~1/3; fast gait gets stuck, tall 0.8), hexapod-small, \
Table 3 left column; tour 1 = four corners counter-clockwise (turf shortcut vs pavement detour \
on the right, turf at the top-left), tour 2 = 20 random admissible points.";

/// Terrain indices.
pub const GRAY: u8 = 0;
/// Red pavement line.
pub const RED: u8 = 1;
/// Green turf.
pub const GREEN_TURF: u8 = 2;
/// Brown turf.
pub const BROWN_TURF: u8 = 3;

const W: f64 = 6.0;
const H: f64 = 5.0;
const RES: f64 = 0.05;

/// The `001` Table 3 left-column map parameters.
pub(super) fn map_params() -> MapParams {
    MapParams {
        cell_size: 0.05,
        r_sensor: 2.5,
        c_radius: 0.5,
        c_min_cells: 10,
        r_robot: 0.25,
        rho_obstacle: 0.25,
        r_hist: 0.25,
        sensor_height: 0.3,
        ..MapParams::default()
    }
}

/// `001` Table 3 values for the `001` strategies (`gtsp`, `greedy`, `spatial-only`); `large`
/// selects the right column. (Table 3's v_max is the robot profile's fastest gait.)
pub(super) fn table3(large: bool) -> toml::Table {
    let pick = |small: f64, big: f64| if large { big } else { small };
    let t = strategy_table(
        &[
            ("delta_t", pick(5.0, 1.0)),
            ("c_loss", pick(10.0, 7.5)),
            ("c_high", 20.0),
            ("c_max", 20.0),
            ("sigma_sense", 0.10),
            ("sigma_0_sq", 1.0),
            ("sigma_s", 1.0),
            ("sigma_eps", 0.5),
            ("lengthscale", 0.4),
            ("d_s", 0.44),
            ("igng_eps_winner", 1e-3),
            ("igng_eps_neighbour", 1e-5),
            ("dt_sample", pick(30.0, 12.0)),
            ("dt_fallback", pick(30.0, 3.0)),
        ],
        &[
            ("n_min", 25),
            ("n_erode_steps", 2),
            ("m_t", 10),
            ("n_dilate_steps", 3),
            ("n_dilate_size", 2),
            ("igng_age_mature", 100),
            ("igng_age_max", 50),
            ("igng_batch", 5000),
        ],
    );
    super::canvas::sections(&["gtsp", "greedy", "spatial-only"], &t)
}

fn looks() -> Vec<Look> {
    vec![
        Look::new(GRAY, Rgb8::new(128, 128, 128), 7.0, 0.001),
        Look::new(RED, Rgb8::new(190, 40, 40), 7.0, 0.001),
        Look::new(GREEN_TURF, Rgb8::new(50, 150, 50), 9.0, 0.003),
        Look::new(BROWN_TURF, Rgb8::new(130, 90, 50), 7.0, 0.003),
    ]
}

/// Turf terrain indices.
pub const TURF: [u8; 2] = [GREEN_TURF, BROWN_TURF];

pub(super) fn generate(seed: u64) -> Result<Scenario, ScenarioError> {
    let name = "courtyard-small";
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let map = map_params();
    let robot = profiles::hexapod_small();
    let fast = resp(1.0, false, 0.0, 0.0);
    let turf_fast = resp(0.02, true, 0.0, 0.0);
    let turf_tall = resp(0.8, false, 0.0, 0.0);
    let terrains = vec![
        terrain(
            GRAY,
            "gray pavement",
            &[("fast", fast.clone()), ("tall", fast.clone())],
        ),
        terrain(
            RED,
            "red pavement",
            &[("fast", fast.clone()), ("tall", fast.clone())],
        ),
        terrain(
            GREEN_TURF,
            "green turf",
            &[("fast", turf_fast.clone()), ("tall", turf_tall.clone())],
        ),
        terrain(
            BROWN_TURF,
            "brown turf",
            &[("fast", turf_fast), ("tall", turf_tall)],
        ),
    ];
    for _ in 0..MAX_ATTEMPTS {
        let j = uni(&mut rng, 0.0, 0.15);
        let corners = [
            Point2::new(0.6 + j, 0.6 + j),
            Point2::new(W - 0.6 - j, 0.6 + j),
            Point2::new(W - 0.6 - j, H - 0.6 - j),
            Point2::new(0.6 + j, H - 0.6 - j),
        ];
        let mut c = Canvas::new(W, H, RES, GRAY);
        let turf_kind = |rng: &mut ChaCha8Rng| {
            if rng.random_bool(0.5) {
                GREEN_TURF
            } else {
                BROWN_TURF
            }
        };
        // East patch across the bottom-right → top-right segment.
        let ax = uni(&mut rng, 4.2, 4.8);
        let by = uni(&mut rng, 1.5, 2.1);
        let bh = uni(&mut rng, 1.0, 1.5);
        let t = turf_kind(&mut rng);
        c.rect(ax, by, W, by + bh, t, None);
        let wob = |rng: &mut ChaCha8Rng| {
            [
                (
                    2.0,
                    uni(rng, 0.0, 0.12),
                    uni(rng, 0.0, std::f64::consts::TAU),
                ),
                (
                    3.0,
                    uni(rng, 0.0, 0.08),
                    uni(rng, 0.0, std::f64::consts::TAU),
                ),
            ]
        };
        let wb = wob(&mut rng);
        c.blob(
            Point2::new(ax, by + bh / 2.0),
            0.35,
            bh / 2.0,
            0.0,
            &wb,
            t,
            None,
        );
        // Top-left patch covering the top-left waypoint (the other turf kind).
        let tl = corners[3];
        let t = if t == GREEN_TURF {
            BROWN_TURF
        } else {
            GREEN_TURF
        };
        let wb = wob(&mut rng);
        let (rx, ry) = (uni(&mut rng, 1.1, 1.5), uni(&mut rng, 1.0, 1.3));
        c.blob(
            Point2::new(
                tl.x + uni(&mut rng, -0.2, 0.3),
                tl.y + uni(&mut rng, -0.3, 0.2),
            ),
            rx,
            ry,
            uni(&mut rng, 0.0, std::f64::consts::PI),
            &wb,
            t,
            None,
        );
        // Interior blobs up to the target fraction.
        let target = uni(&mut rng, 0.31, 0.35);
        for _ in 0..8 {
            if c.fraction(&TURF) >= target {
                break;
            }
            let centre = Point2::new(uni(&mut rng, 1.4, 4.0), uni(&mut rng, 1.2, 4.0));
            let t = turf_kind(&mut rng);
            let wb = wob(&mut rng);
            let (rx, ry) = (uni(&mut rng, 0.4, 0.9), uni(&mut rng, 0.4, 0.9));
            c.blob(
                centre,
                rx,
                ry,
                uni(&mut rng, 0.0, std::f64::consts::PI),
                &wb,
                t,
                None,
            );
        }
        // Thin red line across the pavement.
        let y0 = uni(&mut rng, 0.9, 1.4);
        let y1 = uni(&mut rng, 0.9, 1.4);
        c.segment(
            Point2::new(0.0, y0),
            Point2::new(W, y1),
            0.05,
            RED,
            None,
            Some(&[GRAY]),
        );
        let frac = c.fraction(&TURF);
        if !(0.28..=0.38).contains(&frac) {
            continue;
        }
        let world = c.finish(terrains.clone(), &looks(), &mut rng);
        let adm = world.gt_admissible(map.rho_obstacle, map.r_robot);
        let on = |p: Point2, set: &[u8]| {
            world
                .index_at(p)
                .is_some_and(|k| set.contains(&world.terrain[k]))
        };
        let pave = [GRAY, RED];
        if !corners.iter().all(|&p| point_in_mask(&world, &adm, p))
            || !corners[..3].iter().all(|&p| on(p, &pave))
            || !on(corners[3], &TURF)
        {
            continue;
        }
        // Straight BR→TR crosses turf; a pavement-only detour exists.
        let crosses = (0..=100).any(|s| {
            let f = s as f64 / 100.0;
            let p = Point2::new(
                corners[1].x + f * (corners[2].x - corners[1].x),
                corners[1].y + f * (corners[2].y - corners[1].y),
            );
            on(p, &TURF)
        });
        let pave_adm: Vec<bool> = (0..adm.len())
            .map(|k| adm[k] && pave.contains(&world.terrain[k]))
            .collect();
        let (Some(br), Some(tr)) = (world.index_at(corners[1]), world.index_at(corners[2])) else {
            continue;
        };
        let reach = flood_fill(&pave_adm, world.width(), world.height(), br);
        if !crosses || !reach[tr] {
            continue;
        }
        // Tour 2: 20 admissible points from a fixed seed stream of this world.
        let mut tour_rng = ChaCha8Rng::seed_from_u64(seed.wrapping_mul(0x9E37_79B9_7F4A_7C15) ^ 2);
        let r = map.r_robot;
        let bounds = Bounds {
            min: Point2::new(r, r),
            max: Point2::new(W - r, H - r),
        };
        let mut all = flood_fill(
            &adm,
            world.width(),
            world.height(),
            world.index_at(corners[0]).unwrap_or(0),
        );
        // Tour points lie inside the exploration bounds (the open courtyard's edge cells are
        // admissible but outside them).
        for (k, a) in all.iter_mut().enumerate() {
            *a &= bounds.contains(world.rect.cell(k).center(RES));
        }
        let tour2 = sample_cells(&world, &all, 20, 0.5, &mut tour_rng);
        if tour2.len() != 20 {
            continue;
        }
        return Ok(Scenario {
            name: name.into(),
            description: DESCRIPTION.into(),
            world_seed: seed,
            world,
            robot,
            map,
            sim: SimParams::default(),
            strategy: table3(false),
            start: Pose2::new(corners[0].x, corners[0].y, 0.0),
            bounds,
            tours: vec![
                Tour {
                    name: "tour-1".into(),
                    waypoints: corners.to_vec(),
                    closed: true,
                },
                Tour {
                    name: "tour-2".into(),
                    waypoints: tour2,
                    closed: false,
                },
            ],
            time_limit_s: 7200.0,
            elevation_encoding: Default::default(),
        });
    }
    Err(gen_error(name, seed, "no valid layout found"))
}
