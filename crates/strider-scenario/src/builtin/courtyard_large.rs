//! `courtyard-large` (Prágr22 §5.1.2): 20 × 25 m at 0.10 m, rooms and a corridor formed by 0.5 m
//! walls, 0.5–1 m boxes, patches of gray/red pavement, green turf and brown-green turf.
//!
//! Layout rules (every seed):
//! * a 3 × 4 grid of rooms; one row is a narrow corridor (2.6–3.2 m) open along its length;
//! * room-to-room wall segments are open, solid, or have a 2–3 m doorway; a random spanning tree
//!   of the rooms gets doorways or openings, so every room is reachable;
//! * boxes keep ≥ 1.3 m from wall lines and from each other (no pockets the 0.4 m robot cannot
//!   enter), and the generator re-draws until every admissible cell is reachable from the start;
//! * one closed counter-clockwise tour of 8 waypoints, from the bottom-left around the centre.

use rand::{RngExt, rngs::ChaCha8Rng};
use strider_core::{Point2, Rgb8};
use strider_map::MapParams;

use super::builder::{self, Frame, Layout, ScenarioBuilder};
use super::canvas::{Canvas, Rect};
use super::courtyard::{self, BROWN, BROWN_TURF as BROWN_GREEN_TURF, GRAY, GREEN, GREEN_TURF, RED};
use super::draw::{uni, wobble};
use super::placement::{connected_from, snap};
use super::terrains::{Look, TerrainTable};
use crate::error::ScenarioError;
use crate::model::{Scenario, SimParams, World};
use crate::profiles;

pub(super) const DESCRIPTION: &str = "Prágr22 §5.1.2 large courtyard: 20×25 m at 0.10 m, rooms and \
a corridor walled at 0.5 m, boxes, gray/red pavement, green and brown-green turf (fast stuck, tall \
0.8), hexapod-large with a 10 m omnidirectional sensor, Table 3 right column; one \
counter-clockwise tour of 8 waypoints.";

/// Walls.
pub const WALL: u8 = 4;
/// Boxes.
pub const BOX: u8 = 5;

const W: f64 = 20.0;
const H: f64 = 25.0;
const RES: f64 = 0.10;
const WALL_T: f64 = 0.2;
const WALL_Z: f32 = 0.5;
/// Clearance of boxes from wall lines and from each other: no pockets the 0.4 m robot cannot
/// enter.
const CLEAR: f64 = 1.3;

/// Range noise of the 10 m omnidirectional sensor: lidar-like, constant σ = 1 cm. The RGB-D
/// model's quadratic term (σ = k_d·r², 15 cm at 10 m) would describe a stereo camera, not a
/// long-range omnidirectional scanner.
const OMNI_SIGMA: f64 = 0.01;

/// The simulator's noise for the 10 m omnidirectional sensor (also `campus`'s).
pub(super) fn sim_params() -> SimParams {
    SimParams {
        depth_sigma: OMNI_SIGMA,
        depth_k: 0.0,
        ..SimParams::default()
    }
}

pub(super) fn generate(seed: u64) -> Result<Scenario, ScenarioError> {
    let frame = Frame::new(W, H, RES, GRAY);
    ScenarioBuilder::new(
        "courtyard-large",
        DESCRIPTION,
        seed,
        frame,
        profiles::hexapod_large(),
    )
    .map(map_params)
    .sim(sim_params())
    .strategy(&courtyard::STRATEGIES, courtyard::table3(true))
    .terrains(terrains())
    .time_limit(7200.0)
    .generate("no connected layout found", |a| {
        let mut c = a.canvas();
        paint_patches(&mut c, a.rng);
        let rooms = Rooms::draw(a.rng);
        let walls = rooms.connect(a.rng);
        rooms.paint_walls(&mut c, &walls, a.rng);
        c.border(WALL_T, WALL, WALL_Z);
        rooms.place_boxes(&mut c, a.rng);
        let world = a.finish(&c);
        let adm = a.admissible(&world);
        let tour = octagon_tour(&world, &adm, (W, H), 2.5)?;
        if !connected_from(&world, &adm, tour[0]) {
            return None;
        }
        Some(Layout {
            world,
            start: tour[0],
            tours: vec![builder::tour("benchmark", tour, true)],
        })
    })
}

/// Prágr22 Table 3, right column: the map of the 10 m omnidirectional sensor (also `campus`'s).
pub(super) fn map_params(m: MapParams) -> MapParams {
    MapParams {
        sigma_d: OMNI_SIGMA,
        k_d: 0.0,
        r_sensor: 10.0,
        c_radius: 2.0,
        c_min_cells: 10,
        rho_obstacle: 0.25,
        r_hist: 0.30,
        sensor_height: 0.5,
        ..m
    }
}

/// Pavement, the two turfs, walls and boxes (also `campus`'s).
pub(super) fn terrains() -> TerrainTable {
    let brown_green = Look::mixed(&[BROWN, GREEN], 8.0, 0.004);
    courtyard::terrains(0.004, ("brown-green turf", brown_green))
        .obstacle(WALL, "wall", Look::new(Rgb8::new(235, 235, 235), 4.0, 0.0))
        .obstacle(BOX, "box", Look::new(Rgb8::new(200, 170, 100), 8.0, 0.0))
}

/// 8–12 patches of red pavement and turf, painted first (walls and boxes paint over them).
fn paint_patches(c: &mut Canvas, rng: &mut ChaCha8Rng) {
    let n_patches = rng.random_range(8..13);
    for _ in 0..n_patches {
        let t = [
            RED,
            GREEN_TURF,
            GREEN_TURF,
            BROWN_GREEN_TURF,
            BROWN_GREEN_TURF,
        ][rng.random_range(0..5)];
        let centre = Point2::new(uni(rng, 1.0, W - 1.0), uni(rng, 1.0, H - 1.0));
        let (rx, ry) = if t == RED {
            (uni(rng, 0.8, 2.0), uni(rng, 0.8, 2.0))
        } else {
            (uni(rng, 1.2, 3.2), uni(rng, 1.2, 3.2))
        };
        let wob = wobble(rng, [0.15, 0.1]);
        let angle = uni(rng, 0.0, std::f64::consts::PI);
        c.blob(centre, rx, ry, angle, &wob, t, None);
    }
}

/// What a wall segment between two neighbouring rooms is.
#[derive(Clone, Copy, PartialEq)]
enum Seg {
    Open,
    Door,
    Solid,
}

/// A wall segment between neighbouring rooms `a` and `b`: vertical (between columns `col` and
/// `col + 1` of row `row`) or horizontal (between rows `row` and `row + 1` of column `col`).
#[derive(Clone, Copy)]
struct Edge {
    a: usize,
    b: usize,
    vertical: bool,
    col: usize,
    row: usize,
}

/// The room grid: 3 columns, 4 rows, one row a corridor open along its length.
struct Rooms {
    /// Column boundaries (x), west to east.
    xs: [f64; 4],
    /// Row boundaries (y), south to north.
    ys: [f64; 5],
    corridor_row: usize,
}

const COLS: usize = 3;
const ROWS: usize = 4;

/// Union-find root of `a`, with path halving.
fn find(p: &mut [usize], mut a: usize) -> usize {
    while p[a] != a {
        p[a] = p[p[a]];
        a = p[a];
    }
    a
}

impl Rooms {
    fn draw(rng: &mut ChaCha8Rng) -> Self {
        let xs = [
            0.0,
            W / 3.0 + uni(rng, -0.8, 0.8),
            2.0 * W / 3.0 + uni(rng, -0.8, 0.8),
            W,
        ];
        let corridor_row = rng.random_range(1..3usize);
        let corridor_h = uni(rng, 2.6, 3.2);
        let room_h = (H - corridor_h) / 3.0;
        let mut ys = [0.0; ROWS + 1];
        for r in 0..ROWS {
            let hgt = if r == corridor_row {
                corridor_h
            } else {
                room_h
            };
            ys[r + 1] = ys[r] + hgt;
        }
        for y in ys.iter_mut().take(ROWS).skip(1) {
            *y += uni(rng, -0.3, 0.3);
        }
        Self {
            xs,
            ys,
            corridor_row,
        }
    }

    /// Every wall segment between neighbouring rooms.
    fn edges() -> Vec<Edge> {
        let room = |col: usize, row: usize| row * COLS + col;
        let mut edges = Vec::new();
        for row in 0..ROWS {
            for col in 0..COLS {
                if col + 1 < COLS {
                    edges.push(Edge {
                        a: room(col, row),
                        b: room(col + 1, row),
                        vertical: true,
                        col,
                        row,
                    });
                }
                if row + 1 < ROWS {
                    edges.push(Edge {
                        a: room(col, row),
                        b: room(col, row + 1),
                        vertical: false,
                        col,
                        row,
                    });
                }
            }
        }
        edges
    }

    /// What each of [`Self::edges`] becomes: the corridor's own segments are open; a random
    /// spanning tree of the rooms (Kruskal over shuffled edges) gets doorways or openings, the
    /// other segments are solid, doorways or open at random; rooms the corridor runs left
    /// apart are joined by doorways.
    fn connect(&self, rng: &mut ChaCha8Rng) -> Vec<Seg> {
        let edges = Self::edges();
        let mut order: Vec<usize> = (0..edges.len()).collect();
        rand::seq::SliceRandom::shuffle(order.as_mut_slice(), rng);
        let mut parent: Vec<usize> = (0..COLS * ROWS).collect();
        let mut state = vec![Seg::Solid; edges.len()];
        for &e in &order {
            let Edge {
                a,
                b,
                vertical,
                row,
                ..
            } = edges[e];
            let (ra, rb) = (find(&mut parent, a), find(&mut parent, b));
            let corridor_run = vertical && row == self.corridor_row;
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
        for (e, edge) in edges.iter().enumerate() {
            let (ra, rb) = (find(&mut parent, edge.a), find(&mut parent, edge.b));
            if ra != rb {
                state[e] = Seg::Door;
                parent[ra] = rb;
            }
        }
        state
    }

    /// Paints the solid segments and the walls beside each 2–3 m doorway.
    fn paint_walls(&self, c: &mut Canvas, state: &[Seg], rng: &mut ChaCha8Rng) {
        let (xs, ys) = (&self.xs, &self.ys);
        let half = WALL_T / 2.0;
        for (e, edge) in Self::edges().iter().enumerate() {
            if state[e] == Seg::Open {
                continue;
            }
            let (cx, r) = (edge.col, edge.row);
            let (s0, s1, line) = if edge.vertical {
                (ys[r], ys[r + 1], xs[cx + 1])
            } else {
                (xs[cx], xs[cx + 1], ys[r + 1])
            };
            let mut spans = vec![(s0 - half, s1 + half)];
            if state[e] == Seg::Door {
                let dw = uni(rng, 2.0, 3.0).min(s1 - s0 - 1.0);
                let d0 = uni(rng, s0 + 0.5, s1 - 0.5 - dw);
                spans = vec![(s0 - half, d0), (d0 + dw, s1 + half)];
            }
            for (a, b) in spans {
                if edge.vertical {
                    c.rect(line - half, a, line + half, b, WALL, Some(WALL_Z));
                } else {
                    c.rect(a, line - half, b, line + half, WALL, Some(WALL_Z));
                }
            }
        }
    }

    /// Up to two 0.6–1.6 m boxes, 0.5–1 m high, in each room (not in the corridor), at least
    /// [`CLEAR`] from wall lines and from each other.
    fn place_boxes(&self, c: &mut Canvas, rng: &mut ChaCha8Rng) {
        let (xs, ys) = (&self.xs, &self.ys);
        let half = WALL_T / 2.0;
        let mut boxes: Vec<Rect> = Vec::new();
        for r in 0..ROWS {
            if r == self.corridor_row {
                continue;
            }
            for cx in 0..COLS {
                let n = rng.random_range(0..3usize);
                for _ in 0..n {
                    let (bw, bh) = (uni(rng, 0.6, 1.6), uni(rng, 0.6, 1.6));
                    let (x0, x1) = (xs[cx] + CLEAR + half, xs[cx + 1] - CLEAR - half - bw);
                    let (y0, y1) = (ys[r] + CLEAR + half, ys[r + 1] - CLEAR - half - bh);
                    if x1 <= x0 || y1 <= y0 {
                        continue;
                    }
                    let (bx, by) = (uni(rng, x0, x1), uni(rng, y0, y1));
                    let b = Rect::at(bx, by, bw, bh);
                    if boxes.iter().all(|o| b.gap(o) >= CLEAR) {
                        let z = uni(rng, 0.5, 1.0) as f32;
                        c.fill(b, BOX, Some(z));
                        boxes.push(b);
                    }
                }
            }
        }
    }
}

/// The benchmark tour of a `w` × `h` m world: 8 targets counter-clockwise from the bottom-left,
/// on the rectangle `inset` m inside its border, each snapped to the nearest admissible cell
/// (`None` when one cannot be).
pub(super) fn octagon_tour(
    world: &World,
    adm: &[bool],
    (w, h): (f64, f64),
    inset: f64,
) -> Option<Vec<Point2>> {
    use std::f64::consts::FRAC_PI_4;
    let centre = Point2::new(w / 2.0, h / 2.0);
    let (hx, hy) = (w / 2.0 - inset, h / 2.0 - inset);
    (0..8)
        .map(|k| {
            let th = -3.0 * FRAC_PI_4 + k as f64 * FRAC_PI_4;
            let (s, co) = th.sin_cos();
            let t = (hx / co.abs().max(1e-9)).min(hy / s.abs().max(1e-9));
            snap(world, adm, Point2::new(centre.x + t * co, centre.y + t * s))
        })
        .collect()
}
