//! `courtyard-large` (`001` §5.1.2): 20 × 25 m at 0.10 m, rooms and a corridor formed by 0.5 m
//! walls, 0.5–1 m boxes, patches of gray/red pavement, green turf and brown-green turf.
//!
//! Layout rules (every seed):
//! * a 3 × 4 grid of rooms; one row is a narrow corridor (2.6–3.2 m) open along its length;
//! * room-to-room wall segments are open, solid, or have a 2–3 m doorway; a random spanning tree
//!   of the rooms gets doorways or openings, so every room is reachable;
//! * boxes keep ≥ 1.3 m from wall lines and from each other (no pockets the 0.4 m robot cannot
//!   enter), and the generator re-draws until every admissible cell is reachable from the start;
//! * one closed counter-clockwise tour of 8 waypoints, from the bottom-left around the centre.

use rand::{RngExt, SeedableRng, rngs::ChaCha8Rng};
use strider_core::{Point2, Pose2, Rgb8};
use strider_map::MapParams;

use super::canvas::{Canvas, Look, resp, terrain};
use super::{MAX_ATTEMPTS, gen_error, snap, uni};
use crate::error::ScenarioError;
use crate::ground_truth::flood_fill;
use crate::model::{Bounds, Scenario, SimParams, Tour};
use crate::profiles;

pub(super) const DESCRIPTION: &str = "001 §5.1.2 large courtyard: 20×25 m at 0.10 m, rooms and a \
corridor walled at 0.5 m, boxes, gray/red pavement, green and brown-green turf (fast stuck, tall \
0.8), hexapod-large with a 10 m omnidirectional sensor, Table 3 right column; one \
counter-clockwise tour of 8 waypoints.";

/// Terrain indices.
pub const GRAY: u8 = 0;
/// Red pavement.
pub const RED: u8 = 1;
/// Green turf.
pub const GREEN_TURF: u8 = 2;
/// Brown-green (mixed) turf.
pub const BROWN_GREEN_TURF: u8 = 3;
/// Walls.
pub const WALL: u8 = 4;
/// Boxes.
pub const BOX: u8 = 5;

const W: f64 = 20.0;
const H: f64 = 25.0;
const RES: f64 = 0.10;
const WALL_T: f64 = 0.2;
const WALL_Z: f32 = 0.5;
const CLEAR: f64 = 1.3;

/// Range noise of the 10 m omnidirectional sensor: lidar-like, constant σ = 1 cm. The RGB-D
/// model's quadratic term (σ = k_d·r², 15 cm at 10 m) would describe a stereo camera, not a
/// long-range omnidirectional scanner.
const OMNI_SIGMA: f64 = 0.01;

fn sim_params() -> SimParams {
    SimParams {
        depth_sigma: OMNI_SIGMA,
        depth_k: 0.0,
        ..SimParams::default()
    }
}

fn map_params() -> MapParams {
    MapParams {
        sigma_d: OMNI_SIGMA,
        k_d: 0.0,
        cell_size: 0.10,
        r_sensor: 10.0,
        c_radius: 2.0,
        c_min_cells: 10,
        r_robot: 0.40,
        rho_obstacle: 0.25,
        r_hist: 0.30,
        sensor_height: 0.5,
        ..MapParams::default()
    }
}

#[derive(Clone, Copy, PartialEq)]
enum Seg {
    Open,
    Door,
    Solid,
}

pub(super) fn generate(seed: u64) -> Result<Scenario, ScenarioError> {
    let name = "courtyard-large";
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let map = map_params();
    let pave = resp(1.0, false, 0.0, 0.0);
    let turf_fast = resp(0.02, true, 0.0, 0.0);
    let turf_tall = resp(0.8, false, 0.0, 0.0);
    let terrains = vec![
        terrain(
            GRAY,
            "gray pavement",
            &[("fast", pave.clone()), ("tall", pave.clone())],
        ),
        terrain(
            RED,
            "red pavement",
            &[("fast", pave.clone()), ("tall", pave.clone())],
        ),
        terrain(
            GREEN_TURF,
            "green turf",
            &[("fast", turf_fast.clone()), ("tall", turf_tall.clone())],
        ),
        terrain(
            BROWN_GREEN_TURF,
            "brown-green turf",
            &[("fast", turf_fast), ("tall", turf_tall)],
        ),
        terrain(WALL, "wall", &[]),
        terrain(BOX, "box", &[]),
    ];
    let green = Rgb8::new(50, 150, 50);
    let brown = Rgb8::new(130, 90, 50);
    let looks = [
        Look::new(GRAY, Rgb8::new(128, 128, 128), 7.0, 0.001),
        Look::new(RED, Rgb8::new(190, 40, 40), 7.0, 0.001),
        Look::new(GREEN_TURF, green, 9.0, 0.004),
        Look::mixed(BROWN_GREEN_TURF, &[brown, green], 8.0, 0.004),
        Look::new(WALL, Rgb8::new(235, 235, 235), 4.0, 0.0),
        Look::new(BOX, Rgb8::new(200, 170, 100), 8.0, 0.0),
    ];
    for _ in 0..MAX_ATTEMPTS {
        let mut c = Canvas::new(W, H, RES, GRAY);
        // Terrain patches first (walls and boxes paint over them).
        let n_patches = rng.random_range(8..13);
        for _ in 0..n_patches {
            let t = [
                RED,
                GREEN_TURF,
                GREEN_TURF,
                BROWN_GREEN_TURF,
                BROWN_GREEN_TURF,
            ][rng.random_range(0..5)];
            let centre = Point2::new(uni(&mut rng, 1.0, W - 1.0), uni(&mut rng, 1.0, H - 1.0));
            let (rx, ry) = if t == RED {
                (uni(&mut rng, 0.8, 2.0), uni(&mut rng, 0.8, 2.0))
            } else {
                (uni(&mut rng, 1.2, 3.2), uni(&mut rng, 1.2, 3.2))
            };
            let wob = [
                (
                    2.0,
                    uni(&mut rng, 0.0, 0.15),
                    uni(&mut rng, 0.0, std::f64::consts::TAU),
                ),
                (
                    3.0,
                    uni(&mut rng, 0.0, 0.1),
                    uni(&mut rng, 0.0, std::f64::consts::TAU),
                ),
            ];
            c.blob(
                centre,
                rx,
                ry,
                uni(&mut rng, 0.0, std::f64::consts::PI),
                &wob,
                t,
                None,
            );
        }
        // Room grid: 3 columns, 4 rows, one row a corridor.
        let xs = [
            0.0,
            W / 3.0 + uni(&mut rng, -0.8, 0.8),
            2.0 * W / 3.0 + uni(&mut rng, -0.8, 0.8),
            W,
        ];
        let corridor_row = rng.random_range(1..3usize);
        let corridor_h = uni(&mut rng, 2.6, 3.2);
        let room_h = (H - corridor_h) / 3.0;
        let mut ys = [0.0; 5];
        for r in 0..4 {
            let hgt = if r == corridor_row {
                corridor_h
            } else {
                room_h
            };
            ys[r + 1] = ys[r] + hgt;
        }
        for y in ys.iter_mut().take(4).skip(1) {
            *y += uni(&mut rng, -0.3, 0.3);
        }
        let room = |cx: usize, ry: usize| ry * 3 + cx;
        // Edges: (room a, room b, vertical wall?, col, row).
        let mut edges: Vec<(usize, usize, bool, usize, usize)> = Vec::new();
        for r in 0..4 {
            for cx in 0..3 {
                if cx + 1 < 3 {
                    edges.push((room(cx, r), room(cx + 1, r), true, cx, r));
                }
                if r + 1 < 4 {
                    edges.push((room(cx, r), room(cx, r + 1), false, cx, r));
                }
            }
        }
        // Random spanning tree (Kruskal over shuffled edges).
        let mut order: Vec<usize> = (0..edges.len()).collect();
        rand::seq::SliceRandom::shuffle(order.as_mut_slice(), &mut rng);
        let mut parent: Vec<usize> = (0..12).collect();
        fn find(p: &mut [usize], mut a: usize) -> usize {
            while p[a] != a {
                p[a] = p[p[a]];
                a = p[a];
            }
            a
        }
        let mut state = vec![Seg::Solid; edges.len()];
        for &e in &order {
            let (a, b, vertical, _, r) = edges[e];
            let (ra, rb) = (find(&mut parent, a), find(&mut parent, b));
            let corridor_run = vertical && r == corridor_row;
            if corridor_run {
                state[e] = Seg::Open;
            } else if ra != rb {
                state[e] = if rng.random_bool(0.75) {
                    Seg::Door
                } else {
                    Seg::Open
                };
            } else {
                let u: f64 = rng.random_range(0.0..1.0);
                state[e] = if u < 0.5 {
                    Seg::Solid
                } else if u < 0.85 {
                    Seg::Door
                } else {
                    Seg::Open
                };
            }
            if ra != rb && state[e] != Seg::Solid {
                parent[ra] = rb;
            }
        }
        // Corridor runs may have joined components; make sure all rooms are joined.
        for (e, &(a, b, ..)) in edges.iter().enumerate() {
            let (ra, rb) = (find(&mut parent, a), find(&mut parent, b));
            if ra != rb {
                state[e] = Seg::Door;
                parent[ra] = rb;
            }
        }
        // Paint walls.
        let half = WALL_T / 2.0;
        for (e, &(_, _, vertical, cx, r)) in edges.iter().enumerate() {
            if state[e] == Seg::Open {
                continue;
            }
            let (s0, s1, line) = if vertical {
                (ys[r], ys[r + 1], xs[cx + 1])
            } else {
                (xs[cx], xs[cx + 1], ys[r + 1])
            };
            let mut spans = vec![(s0 - half, s1 + half)];
            if state[e] == Seg::Door {
                let dw = uni(&mut rng, 2.0, 3.0).min(s1 - s0 - 1.0);
                let d0 = uni(&mut rng, s0 + 0.5, s1 - 0.5 - dw);
                spans = vec![(s0 - half, d0), (d0 + dw, s1 + half)];
            }
            for (a, b) in spans {
                if vertical {
                    c.rect(line - half, a, line + half, b, WALL, Some(WALL_Z));
                } else {
                    c.rect(a, line - half, b, line + half, WALL, Some(WALL_Z));
                }
            }
        }
        c.border(WALL_T, WALL, WALL_Z);
        // Boxes inside rooms (not in the corridor).
        let mut boxes: Vec<[f64; 4]> = Vec::new();
        for r in 0..4 {
            if r == corridor_row {
                continue;
            }
            for cx in 0..3 {
                let n = rng.random_range(0..3usize);
                for _ in 0..n {
                    let (bw, bh) = (uni(&mut rng, 0.6, 1.6), uni(&mut rng, 0.6, 1.6));
                    let (x0, x1) = (xs[cx] + CLEAR + half, xs[cx + 1] - CLEAR - half - bw);
                    let (y0, y1) = (ys[r] + CLEAR + half, ys[r + 1] - CLEAR - half - bh);
                    if x1 <= x0 || y1 <= y0 {
                        continue;
                    }
                    let (bx, by) = (uni(&mut rng, x0, x1), uni(&mut rng, y0, y1));
                    let b = [bx, by, bx + bw, by + bh];
                    let far = boxes.iter().all(|o| {
                        let dx = (o[0] - b[2]).max(b[0] - o[2]).max(0.0);
                        let dy = (o[1] - b[3]).max(b[1] - o[3]).max(0.0);
                        dx.hypot(dy) >= CLEAR
                    });
                    if far {
                        let z = uni(&mut rng, 0.5, 1.0) as f32;
                        c.rect(b[0], b[1], b[2], b[3], BOX, Some(z));
                        boxes.push(b);
                    }
                }
            }
        }
        let world = c.finish(terrains.clone(), &looks, &mut rng);
        let adm = world.gt_admissible(map.rho_obstacle, map.r_robot);
        // Tour: 8 targets counter-clockwise from the bottom-left.
        let centre = Point2::new(W / 2.0, H / 2.0);
        let (hx, hy) = (W / 2.0 - 2.5, H / 2.0 - 2.5);
        let mut tour = Vec::new();
        for k in 0..8 {
            let th = -3.0 * std::f64::consts::FRAC_PI_4 + k as f64 * std::f64::consts::FRAC_PI_4;
            let (s, co) = th.sin_cos();
            let t = (hx / co.abs().max(1e-9)).min(hy / s.abs().max(1e-9));
            let target = Point2::new(centre.x + t * co, centre.y + t * s);
            match snap(&world, &adm, target) {
                Some(p) => tour.push(p),
                None => break,
            }
        }
        if tour.len() != 8 {
            continue;
        }
        let Some(start) = world.index_at(tour[0]) else {
            continue;
        };
        let reach = flood_fill(&adm, world.width(), world.height(), start);
        if reach != adm {
            continue;
        }
        let r = map.r_robot;
        return Ok(Scenario {
            name: name.into(),
            description: DESCRIPTION.into(),
            world_seed: seed,
            world,
            robot: profiles::hexapod_large(),
            map,
            sim: sim_params(),
            strategy: super::courtyard_small::table3(true),
            start: Pose2::new(tour[0].x, tour[0].y, 0.0),
            bounds: Bounds {
                min: Point2::new(r, r),
                max: Point2::new(W - r, H - r),
            },
            tours: vec![Tour {
                name: "benchmark".into(),
                waypoints: tour,
                closed: true,
            }],
            time_limit_s: 7200.0,
            elevation_encoding: Default::default(),
        });
    }
    Err(gen_error(name, seed, "no connected layout found"))
}
