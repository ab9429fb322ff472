//! `courtyard-small` (Prágr22 §5.1.1): a 6 × 5 m flat courtyard at 0.05 m with gray pavement, a
//! thin red pavement line and green/brown turf covering about a third of the area.
//!
//! Layout rules (every seed), the paper's two designed features of tour 1 by construction:
//! * a turf patch reaches from the east edge westward across the bottom-right → top-right
//!   segment of tour 1, so the straight segment crosses turf, and a pavement detour around
//!   its west end is kept free of turf over [`DETOUR_HALF_WIDTH_M`] either side, so the
//!   robot's footprint drives it without touching turf;
//! * a turf patch covers the top-left waypoint, with turf at least [`TOP_LEFT_TURF_RADIUS_M`]
//!   around it, so no route reaches it without crossing turf;
//! * further turf blobs (outside the detour) bring turf to 31–35 % of the area;
//! * a red pavement line ~0.1 m wide (that cluster erosion must remove) crosses the pavement.
//!
//! The courtyard is flat and open as in the paper: no wall rings it. The robot stays inside
//! because the simulator refuses motion off the world, and exploration goals outside the bounds
//! are dropped (decision 5).

use rand::{RngExt, SeedableRng, rngs::ChaCha8Rng};
use strider_core::Point2;
use strider_map::MapParams;

use super::builder::{self, Attempt, Frame, Layout, ScenarioBuilder};
use super::canvas::{Canvas, dist_to_segment};
use super::courtyard::{self, BROWN, BROWN_TURF, GRAY, GREEN_TURF, RED};
use super::draw::{uni, wobble};
use super::placement::{crosses, footprint_clear_of, on_terrain, reach_from, sample_cells};
use super::terrains::Look;
use crate::error::ScenarioError;
use crate::ground_truth::{flood_fill, point_in_mask};
use crate::model::{Scenario, World};
use crate::profiles;

pub(super) const DESCRIPTION: &str = "Prágr22 §5.1.1 small courtyard: 6×5 m at 0.05 m, gray \
pavement with a thin red line, green and brown turf (~1/3; fast gait gets stuck, tall 0.8), \
hexapod-small, Table 3 left column; tour 1 = four corners counter-clockwise (turf shortcut vs \
pavement detour on the right, turf at the top-left), tour 2 = 20 random admissible points.";

/// Turf terrain indices.
pub const TURF: [u8; 2] = [GREEN_TURF, BROWN_TURF];

const W: f64 = 6.0;
const H: f64 = 5.0;
const RES: f64 = 0.05;

pub(super) fn generate(seed: u64) -> Result<Scenario, ScenarioError> {
    let frame = Frame::new(W, H, RES, GRAY);
    let brown = Look::new(BROWN, 7.0, 0.003);
    ScenarioBuilder::new(
        "courtyard-small",
        DESCRIPTION,
        seed,
        frame,
        profiles::hexapod_small(),
    )
    // Prágr22 Table 3, left column.
    .map(|m| MapParams {
        r_sensor: 2.5,
        c_radius: 0.5,
        c_min_cells: 10,
        rho_obstacle: 0.25,
        r_hist: 0.25,
        sensor_height: 0.3,
        ..m
    })
    .strategy(&courtyard::STRATEGIES, courtyard::table3(false))
    .terrains(courtyard::terrains(0.003, ("brown turf", brown)))
    .time_limit(7200.0)
    .generate("no valid layout found", |a| {
        let corners = corners(a.rng);
        let mut c = a.canvas();
        paint_turf(&mut c, &corners, a.rng);
        paint_red_line(&mut c, a.rng);
        if !(0.28..=0.38).contains(&c.fraction(&TURF)) {
            return None;
        }
        let world = a.finish(&c);
        let adm = a.admissible(&world);
        if !tour1_holds(&world, &adm, &corners, a.map.r_robot) {
            return None;
        }
        let tour2 = tour2(&world, &adm, a, corners[0])?;
        Some(Layout {
            world,
            start: corners[0],
            tours: vec![
                builder::tour("tour-1", corners.to_vec(), true),
                builder::tour("tour-2", tour2, false),
            ],
        })
    })
}

/// Tour 1: the four corners counter-clockwise from the bottom-left, a random inset from the
/// edge.
fn corners(rng: &mut ChaCha8Rng) -> [Point2; 4] {
    let j = uni(rng, 0.0, 0.15);
    [
        Point2::new(0.6 + j, 0.6 + j),
        Point2::new(W - 0.6 - j, 0.6 + j),
        Point2::new(W - 0.6 - j, H - 0.6 - j),
        Point2::new(0.6 + j, H - 0.6 - j),
    ]
}

fn turf_kind(rng: &mut ChaCha8Rng) -> u8 {
    if rng.random_bool(0.5) {
        GREEN_TURF
    } else {
        BROWN_TURF
    }
}

/// The east turf patch: a rectangle from the east edge across the bottom-right → top-right
/// segment of tour 1, with a rounded west end.
struct EastPatch {
    /// x of the rectangle's west side (the rounded end reaches further west), m.
    ax: f64,
    /// y of its bottom, m.
    by: f64,
    /// Its height, m.
    bh: f64,
    kind: u8,
    wobble: [(f64, f64, f64); 2],
}

impl EastPatch {
    fn draw(rng: &mut ChaCha8Rng) -> Self {
        let ax = uni(rng, 4.2, 4.8);
        let by = uni(rng, 1.5, 2.1);
        let bh = uni(rng, 1.0, 1.5);
        let kind = turf_kind(rng);
        let wobble = wobble(rng, TURF_WOBBLE);
        Self {
            ax,
            by,
            bh,
            kind,
            wobble,
        }
    }

    fn paint(&self, c: &mut Canvas) {
        c.rect(self.ax, self.by, W, self.by + self.bh, self.kind, None);
        let west_end = Point2::new(self.ax, self.by + self.bh / 2.0);
        let (rx, ry) = (0.35, self.bh / 2.0);
        c.blob(west_end, rx, ry, 0.0, &self.wobble, self.kind, None);
    }
}

/// Amplitudes of the turf outlines' wobble (harmonics 2 and 3).
const TURF_WOBBLE: [f64; 2] = [0.12, 0.08];

/// The turf, painted so that tour 1 has the paper's two designed features whatever the draws:
/// an east patch across the bottom-right → top-right segment with a pavement detour around its
/// west end kept free of turf ([`Detour`]), a patch of the other kind over the top-left corner
/// with a turf disc of [`TOP_LEFT_TURF_RADIUS_M`] under the waypoint, and interior blobs up to
/// 31–35 % of the area (outside the detour).
fn paint_turf(c: &mut Canvas, corners: &[Point2; 4], rng: &mut ChaCha8Rng) {
    use std::f64::consts::PI;
    let east = EastPatch::draw(rng);
    east.paint(c);
    let in_east: Vec<bool> = c.terrain.iter().map(|t| TURF.contains(t)).collect();
    let detour = Detour::around(c, &in_east, corners[1], corners[2]);
    // Top-left patch covering the top-left waypoint.
    let tl = corners[3];
    let t = if east.kind == GREEN_TURF {
        BROWN_TURF
    } else {
        GREEN_TURF
    };
    let wb = wobble(rng, TURF_WOBBLE);
    let (rx, ry) = (uni(rng, 1.1, 1.5), uni(rng, 1.0, 1.3));
    let centre = Point2::new(tl.x + uni(rng, -0.2, 0.3), tl.y + uni(rng, -0.3, 0.2));
    let angle = uni(rng, 0.0, PI);
    c.blob(centre, rx, ry, angle, &wb, t, None);
    detour.clear(c, &in_east);
    // Interior blobs up to the target fraction.
    let target = uni(rng, 0.31, 0.35);
    for _ in 0..INTERIOR_BLOBS {
        if c.fraction(&TURF) >= target {
            break;
        }
        let centre = Point2::new(uni(rng, 1.4, 4.0), uni(rng, 1.2, 4.0));
        let kind = turf_kind(rng);
        let wb = wobble(rng, TURF_WOBBLE);
        let (rx, ry) = (uni(rng, 0.4, 0.9), uni(rng, 0.4, 0.9));
        let angle = uni(rng, 0.0, PI);
        c.blob(centre, rx, ry, angle, &wb, kind, None);
        detour.clear(c, &in_east);
    }
    // The top-left waypoint stands deep in turf: no route reaches it without crossing turf.
    c.segment(tl, tl, TOP_LEFT_TURF_RADIUS_M, t, None, None);
}

/// Interior blobs drawn at most.
const INTERIOR_BLOBS: usize = 12;

/// Turf radius under the top-left waypoint, m: every route to the waypoint drives at least this
/// far over turf (the paper's "area around the top-left waypoint where the turf cannot be
/// avoided"), twice the footprint radius.
pub const TOP_LEFT_TURF_RADIUS_M: f64 = 0.5;

/// Turf-free half-width of the pavement detour beside tour 1's bottom-right → top-right
/// segment, m: the footprint radius (0.25 m), plus the 0.4 m over which the cost transform of
/// Table 3 (c_loss = 10) raises pavement next to turf that the tall gait crosses at a fifth of
/// the fast gait's pavement speed ((5 − 1) / 10), plus a cell. The paper's learned robot drives
/// its detour at full speed (120 s, no spread): pavement the planner sees as pavement.
pub const DETOUR_HALF_WIDTH_M: f64 = 0.7;

/// The pavement detour around the east patch's west end: from the bottom-right waypoint west
/// below the patch, north past its west end at [`DETOUR_HALF_WIDTH_M`] from it, and east above
/// it to the top-right waypoint.
struct Detour {
    /// Bottom-right waypoint, south-west and north-west corners, top-right waypoint.
    polyline: [Point2; 4],
}

impl Detour {
    /// The detour from `br` to `tr` around the cells of `east` (the east patch).
    fn around(c: &Canvas, east: &[bool], br: Point2, tr: Point2) -> Self {
        let west = (0..east.len())
            .filter(|&k| east[k])
            .map(|k| c.center(k).x - c.res / 2.0)
            .fold(br.x, f64::min);
        let x = west - DETOUR_HALF_WIDTH_M - c.res;
        Self {
            polyline: [br, Point2::new(x, br.y), Point2::new(x, tr.y), tr],
        }
    }

    /// Repaints as gray pavement every turf cell but the east patch's own (`east`) within the
    /// half-width of the detour or inside it (between the detour and segment 2), so that the
    /// east patch is the only turf the detour goes around. The legs below and above the patch
    /// run closer to it than the half-width, where the footprint still clears it.
    fn clear(&self, c: &mut Canvas, east: &[bool]) {
        let h = DETOUR_HALF_WIDTH_M;
        let [br, sw, nw, tr] = self.polyline;
        let inside = |p: Point2| p.x >= sw.x && (br.y..=tr.y).contains(&p.y);
        let near = |p: Point2| {
            self.polyline
                .windows(2)
                .any(|leg| dist_to_segment(p, leg[0], leg[1]) <= h)
        };
        for k in c.cells_in(nw.x - h, br.y - h, c.width_m(), tr.y + h) {
            let p = c.center(k);
            if !east[k] && TURF.contains(&c.terrain[k]) && (inside(p) || near(p)) {
                c.terrain[k] = GRAY;
            }
        }
    }
}

/// A red pavement line ~0.1 m wide across the gray pavement (cluster erosion must remove it).
fn paint_red_line(c: &mut Canvas, rng: &mut ChaCha8Rng) {
    let y0 = uni(rng, 0.9, 1.4);
    let y1 = uni(rng, 0.9, 1.4);
    c.segment(
        Point2::new(0.0, y0),
        Point2::new(W, y1),
        0.05,
        RED,
        None,
        Some(&[GRAY]),
    );
}

/// Tour 1's promises, which the painting guarantees and this checks on the finished world:
/// every corner admissible, the first three on pavement and the top-left one on turf; the
/// straight bottom-right → top-right segment crosses turf while a detour exists on which no
/// cell of the footprint (`r_robot`) touches turf.
fn tour1_holds(world: &World, adm: &[bool], corners: &[Point2; 4], r_robot: f64) -> bool {
    let pave = [GRAY, RED];
    if !corners.iter().all(|&p| point_in_mask(world, adm, p))
        || !corners[..3].iter().all(|&p| on_terrain(world, p, &pave))
        || !on_terrain(world, corners[3], &TURF)
    {
        return false;
    }
    let clear = footprint_clear_of(world, adm, &TURF, r_robot);
    let (br, tr) = (corners[1], corners[2]);
    let detour = reach_from(world, &clear, br)
        .zip(world.index_at(tr))
        .is_some_and(|(reach, tr)| reach[tr]);
    crosses(world, br, tr, &TURF) && detour
}

/// Tour 2: 20 points reachable from the start and inside the exploration bounds (the open
/// courtyard's edge cells are admissible but outside them), drawn from a stream of this world
/// of their own.
fn tour2(world: &World, adm: &[bool], a: &Attempt<'_>, start: Point2) -> Option<Vec<Point2>> {
    let mut tour_rng = ChaCha8Rng::seed_from_u64(a.seed.wrapping_mul(0x9E37_79B9_7F4A_7C15) ^ 2);
    let mut all = flood_fill(
        adm,
        world.width(),
        world.height(),
        world.index_at(start).unwrap_or(0),
    );
    for (k, reachable) in all.iter_mut().enumerate() {
        *reachable &= a.bounds.contains(world.cell_center(k));
    }
    let tour2 = sample_cells(world, &all, 20, 0.5, &mut tour_rng);
    (tour2.len() == 20).then_some(tour2)
}
