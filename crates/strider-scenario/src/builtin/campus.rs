//! `campus`: a 200 × 200 m outdoor world at 0.10 m (4 M cells) for exploration at scale, with
//! the terrain families of the Prágr22 courtyards (gray and red pavement, green and brown-green
//! turf, walls and boxes) and the courtyard-large robot (hexapod-large, 10 m omnidirectional
//! sensor) and parameters (Prágr22 Table 3, right column).
//!
//! Layout rules (every seed):
//! * turf lawns and red-pavement squares over gray pavement, crossed by 3 m gray footpaths;
//! * 8–12 buildings of 14–30 m a side, 2 m walls, a gray floor, 1–3 outer doorways of 2–3 m and
//!   an inner wall with a doorway; buildings keep ≥ 6 m from each other and from the border;
//! * boxes (0.5–0.9 m, too small to stand on) outside the buildings keep ≥ 1.3 m from each other and from walls (no pockets the
//!   0.8 m robot cannot enter), and the generator re-draws until every admissible cell is
//!   reachable from the start;
//! * one closed counter-clockwise tour of 8 waypoints on the rectangle 15 m inside the border.

use rand::{RngExt, rngs::ChaCha8Rng};
use strider_core::Point2;

use super::builder::{self, Frame, Layout, ScenarioBuilder};
use super::canvas::{Canvas, Rect};
use super::courtyard::{self, BROWN_TURF, GRAY, GREEN_TURF, RED};
use super::courtyard_large::{self, BOX, WALL};
use super::draw::{uni, wobble};
use super::placement::{connected_from, snap};
use crate::error::ScenarioError;
use crate::model::Scenario;
use crate::profiles;

pub(super) const DESCRIPTION: &str = "Exploration at scale: 200×200 m at 0.10 m (4 M cells), \
lawns of green and brown-green turf, red squares and gray footpaths, 8–12 buildings with doors, \
boxes; hexapod-large with a 10 m omnidirectional sensor, Prágr22 Table 3 right column; one \
counter-clockwise tour of 8 waypoints.";

const W: f64 = 200.0;
const H: f64 = 200.0;
const RES: f64 = 0.10;
const WALL_T: f64 = 0.3;
/// Building walls occlude the 0.5 m high sensor.
const WALL_Z: f32 = 2.0;
const BORDER_Z: f32 = 0.5;
/// Clearance of boxes from walls and from each other (as in courtyard-large).
const CLEAR: f64 = 1.3;
/// Clearance of buildings from each other and from the border.
const BUILDING_GAP: f64 = 6.0;

pub(super) fn generate(seed: u64) -> Result<Scenario, ScenarioError> {
    let frame = Frame::new(W, H, RES, GRAY);
    ScenarioBuilder::new(
        "campus",
        DESCRIPTION,
        seed,
        frame,
        profiles::hexapod_large(),
    )
    .map(courtyard_large::map_params)
    .sim(courtyard_large::sim_params())
    .strategy(&courtyard::STRATEGIES, strategy_table())
    .terrains(courtyard_large::terrains())
    .time_limit(200_000.0)
    .generate("no connected layout found", |a| {
        let mut c = a.canvas();
        paint_grounds(&mut c, a.rng);
        let buildings = place_buildings(a.rng);
        for b in &buildings {
            b.paint(&mut c, a.rng);
        }
        c.border(WALL_T, WALL, BORDER_Z);
        place_boxes(&mut c, &buildings, a.rng);
        let world = a.finish(&c);
        let adm = a.admissible(&world);
        let tour = courtyard_large::octagon_tour(&world, &adm, (W, H), 15.0)?;
        let start = snap(&world, &adm, Point2::new(8.0, 8.0))?;
        if !connected_from(&world, &adm, start) {
            return None;
        }
        Some(Layout {
            world,
            start,
            tours: vec![builder::tour("benchmark", tour, true)],
        })
    })
}

/// Goal sites in one tour solve: the frontier of a 200 m world holds hundreds of goals, and a
/// replan plans over the nearest ones (the courtyards keep every goal).
const MAX_TOUR_SITES: i64 = 64;

/// Learning pairs each gait's regressor trains on: a full exploration measures tens of
/// thousands of cells, and an exact GP over all of them would not fit in memory (the
/// courtyards stay far below this).
const MAX_LEARNING_PAIRS: i64 = 2000;

/// courtyard-large's parameters (Prágr22 Table 3, right column) with a bounded tour horizon
/// and a bounded regressor.
fn strategy_table() -> toml::Table {
    let mut t = courtyard::table3(true);
    t.insert(
        "max_tour_sites".to_string(),
        toml::Value::Integer(MAX_TOUR_SITES),
    );
    t.insert(
        "max_learning_pairs".to_string(),
        toml::Value::Integer(MAX_LEARNING_PAIRS),
    );
    t
}

/// Lawns (40–60 turf blobs of 4–14 m), 15–25 red squares of 2–6 m, then 4–7 straight 3 m
/// footpaths of gray pavement across the lawns.
fn paint_grounds(c: &mut Canvas, rng: &mut ChaCha8Rng) {
    let lawns = rng.random_range(40..61);
    for _ in 0..lawns {
        let t = if rng.random_bool(0.5) {
            GREEN_TURF
        } else {
            BROWN_TURF
        };
        blob(c, rng, t, (4.0, 14.0));
    }
    let squares = rng.random_range(15..26);
    for _ in 0..squares {
        blob(c, rng, RED, (2.0, 6.0));
    }
    let paths = rng.random_range(4..8);
    for _ in 0..paths {
        let a = Point2::new(uni(rng, 0.0, W), uni(rng, 0.0, H));
        let b = Point2::new(uni(rng, 0.0, W), uni(rng, 0.0, H));
        c.segment(a, b, 1.5, GRAY, None, Some(&[GREEN_TURF, BROWN_TURF]));
    }
}

/// One wobbly blob of terrain `t` with semi-axes drawn from `radii`.
fn blob(c: &mut Canvas, rng: &mut ChaCha8Rng, t: u8, radii: (f64, f64)) {
    let centre = Point2::new(uni(rng, 2.0, W - 2.0), uni(rng, 2.0, H - 2.0));
    let (rx, ry) = (uni(rng, radii.0, radii.1), uni(rng, radii.0, radii.1));
    let wob = wobble(rng, [0.15, 0.1]);
    let angle = uni(rng, 0.0, std::f64::consts::PI);
    c.blob(centre, rx, ry, angle, &wob, t, None);
}

/// A building: its outline and where its doorways and inner wall are.
struct Building {
    outline: Rect,
}

/// 8–12 buildings of 14–30 m a side, at least [`BUILDING_GAP`] apart and from the border (at
/// most 400 draws: fewer buildings rather than no layout).
fn place_buildings(rng: &mut ChaCha8Rng) -> Vec<Building> {
    let want = rng.random_range(8..13usize);
    let mut out: Vec<Building> = Vec::with_capacity(want);
    for _ in 0..400 {
        if out.len() == want {
            break;
        }
        let (bw, bh) = (uni(rng, 14.0, 30.0), uni(rng, 14.0, 30.0));
        let x = uni(rng, BUILDING_GAP, W - BUILDING_GAP - bw);
        let y = uni(rng, BUILDING_GAP, H - BUILDING_GAP - bh);
        let r = Rect::at(x, y, bw, bh);
        // Keep the start corner free.
        let clear_of_start = r.x0 > 20.0 || r.y0 > 20.0;
        if clear_of_start && out.iter().all(|b| r.gap(&b.outline) >= BUILDING_GAP) {
            out.push(Building { outline: r });
        }
    }
    out
}

impl Building {
    /// Gray floor, four 2 m walls with 1–3 doorways of 2–3 m, and a wall across the longer
    /// side with one doorway; the outer doorways keep clear of the inner wall's ends.
    fn paint(&self, c: &mut Canvas, rng: &mut ChaCha8Rng) {
        let r = self.outline;
        c.fill(r, GRAY, None);
        let doors = rng.random_range(1..4usize);
        let mut with_door = [false; 4];
        for _ in 0..doors {
            with_door[rng.random_range(0..4usize)] = true;
        }
        let (w, h) = (r.x1 - r.x0, r.y1 - r.y0);
        // The inner wall runs across the longer side, at `cut` along it.
        let across_x = w >= h;
        let cut = if across_x {
            uni(rng, 0.4 * w, 0.6 * w)
        } else {
            uni(rng, 0.4 * h, 0.6 * h)
        };
        // Sides counter-clockwise from the south one; the inner wall meets the south and
        // north sides (at `cut` from the west, i.e. `w - cut` from the north side's start) or
        // the east and west ones.
        let sides = [
            (
                Point2::new(r.x0, r.y0),
                Point2::new(r.x1, r.y0),
                across_x.then_some(cut),
            ),
            (
                Point2::new(r.x1, r.y0),
                Point2::new(r.x1, r.y1),
                (!across_x).then_some(cut),
            ),
            (
                Point2::new(r.x1, r.y1),
                Point2::new(r.x0, r.y1),
                across_x.then_some(w - cut),
            ),
            (
                Point2::new(r.x0, r.y1),
                Point2::new(r.x0, r.y0),
                (!across_x).then_some(h - cut),
            ),
        ];
        for (k, &(a, b, avoid)) in sides.iter().enumerate() {
            wall_with_door(c, (a, b), with_door[k].then_some(avoid), rng);
        }
        let (a, b) = if across_x {
            (Point2::new(r.x0 + cut, r.y0), Point2::new(r.x0 + cut, r.y1))
        } else {
            (Point2::new(r.x0, r.y0 + cut), Point2::new(r.x1, r.y0 + cut))
        };
        wall_with_door(c, (a, b), Some(None), rng);
    }
}

/// A straight wall from `a` to `b`; with `door` = `Some(avoid)`, one 2–3 m doorway at least
/// 1.5 m from either end and, when `avoid` is given, at least 1.5 m from that point along the
/// wall (where another wall meets it).
fn wall_with_door(
    c: &mut Canvas,
    (a, b): (Point2, Point2),
    door: Option<Option<f64>>,
    rng: &mut ChaCha8Rng,
) {
    let len = a.dist(b);
    let at = |s: f64| Point2::new(a.x + (b.x - a.x) * s / len, a.y + (b.y - a.y) * s / len);
    let half = WALL_T / 2.0;
    let Some(avoid) = door else {
        c.segment(a, b, half, WALL, Some(WALL_Z), None);
        return;
    };
    let dw = uni(rng, 2.0, 3.0);
    // The stretch before `avoid` or the one after it, whichever is longer, holds the door.
    let (lo, hi) = match avoid {
        Some(p) if p > len - p => (1.5, p - 1.5 - dw),
        Some(p) => (p + 1.5, len - 1.5 - dw),
        None => (1.5, len - 1.5 - dw),
    };
    let d0 = uni(rng, lo, hi.max(lo));
    c.segment(a, at(d0), half, WALL, Some(WALL_Z), None);
    c.segment(at(d0 + dw), b, half, WALL, Some(WALL_Z), None);
}

/// 150–250 boxes of 0.5–0.9 m (bins, benches, planters), 0.5–1 m high, outside the buildings, at least [`CLEAR`] from
/// the buildings' walls, the border and each other. (A larger box has a flat top the robot's
/// footprint fits on: admissible cells no path reaches.)
fn place_boxes(c: &mut Canvas, buildings: &[Building], rng: &mut ChaCha8Rng) {
    let want = rng.random_range(150..251usize);
    let mut boxes: Vec<Rect> = Vec::with_capacity(want);
    let margin = CLEAR + WALL_T;
    for _ in 0..4 * want {
        if boxes.len() == want {
            break;
        }
        let (bw, bh) = (uni(rng, 0.5, 0.9), uni(rng, 0.5, 0.9));
        let b = Rect::at(
            uni(rng, margin, W - margin - bw),
            uni(rng, margin, H - margin - bh),
            bw,
            bh,
        );
        let clear_of_start = b.x0 > 15.0 || b.y0 > 15.0;
        let clear = buildings.iter().all(|h| b.gap(&h.outline) >= margin)
            && boxes.iter().all(|o| b.gap(o) >= CLEAR);
        if clear && clear_of_start {
            c.fill(b, BOX, Some(uni(rng, 0.5, 1.0) as f32));
            boxes.push(b);
        }
    }
}
