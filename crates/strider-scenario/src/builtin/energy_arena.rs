//! `energy-arena` (MartinCorke): a 2 × 1.5 m flat floor at 0.05 m of smooth timber with a grey
//! carpet region that blocks the shortest tour through the base and three waypoints, and a timber
//! margin around the carpet along which a slightly longer tour skirts it (decision 27).
//!
//! Powers at 0.1 m/s are the paper's totals with the robot's 0.21 W hotel load included
//! (decision 28): 0.42 W of motive power on timber (0.63 W in all, 6.3 J/m) and 1.00 W on carpet
//! (1.21 W, 12.1 J/m); standing still costs the hotel load alone. The benchmark runs 25 tours
//! (`strategy.tours.n_tours`). As in MartinCorke §4 the pose arrives at 30 Hz and the power at
//! 10 Hz, both noisy.
//!
//! # The arena rule, by construction
//!
//! The base and the waypoints are the centres of the corner cells of a rectangle of cells. The
//! shortest closed tour through four rectangle corners is the rectangle's perimeter (either other
//! visiting order adds both diagonals), and the perimeter runs along cell centres. The carpet
//! covers every cell of the rectangle's edges but the four corner cells, plus a band of the
//! interior, so the perimeter lies on carpet except for half a cell at each end of each edge:
//! 0.2 m of a 2.1–3.0 m tour (at least 90 % carpet). Every cell outside the rectangle is timber,
//! so a tour can run along the centres of the first row of cells outside each edge, leaving and
//! rejoining each corner by one diagonal step: 8 · (√2 − 1) · 0.05 ≈ 0.17 m more (at most 8 %).
//! The world seed draws the rectangle's size and position, the corner the base is on and the
//! width of the interior carpet band; nothing is rejected, so every seed gives a world. A test
//! checks the rule with the project's tour planner for world seeds 1–20.

use rand::{RngExt, rngs::ChaCha8Rng};
use strider_core::{Point2, Rgb8};
use strider_map::MapParams;

use super::builder::{self, Frame, Layout, ScenarioBuilder};
use super::canvas::Canvas;
use super::placement::{reach_from, restrict_to};
use super::strategy;
use super::terrains::{Look, TerrainTable, powered};
use crate::error::ScenarioError;
use crate::ground_truth::point_in_mask;
use crate::model::{Scenario, SimParams, World};
use crate::profiles;

pub(super) const DESCRIPTION: &str = "MartinCorke energy arena: 2×1.5 m at 0.05 m, smooth timber \
(0.63 W at 0.1 m/s, hotel load included) with a grey carpet region (1.21 W) that blocks the \
shortest tour through base and 3 waypoints (>= 85 % of it on carpet) and a timber margin for a \
skirting tour <= 10 % longer, rover-small (hotel load 0.21 W); 25 tours.";

/// Terrain indices.
pub const TIMBER: u8 = 0;
/// Grey carpet.
pub const CARPET: u8 = 1;
/// Border wall.
pub const WALL: u8 = 2;

const W: f64 = 2.0;
const H: f64 = 1.5;
const RES: f64 = 0.05;

/// Motive power at 0.1 m/s, W: the paper's 0.63 W and 1.21 W less the 0.21 W hotel load of
/// `rover-small` (decision 28).
pub const TIMBER_MOTIVE_W: f64 = 0.42;
/// See [`TIMBER_MOTIVE_W`].
pub const CARPET_MOTIVE_W: f64 = 1.00;

/// Rectangle size in cells (edge lengths 0.70–0.95 m by 0.35–0.55 m: a 2.1–3.0 m tour, about
/// the paper's 2.4 m).
const WIDTH_CELLS: (usize, usize) = (14, 19);
const HEIGHT_CELLS: (usize, usize) = (7, 11);
/// Cells kept free between the rectangle and the wall (wall, the cell the robot's radius cannot
/// use, and the skirting row).
const CLEAR_CELLS: usize = 3;
/// Width of the interior carpet band in cells, edge row included; a band that reaches the
/// middle fills the rectangle.
const BAND_CELLS: (usize, usize) = (2, 6);

/// MartinCorke §4: the overhead ArUco tracker updates the pose at 30 Hz and the robot logs its
/// motor power at 10 Hz. Both are noisy: a few millimetres and about a degree of tracker jitter
/// (a 100 mm marker seen by a webcam from about 1.5 m), and the default 5 % on the power
/// reading.
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
    let frame = Frame::new(W, H, RES, TIMBER);
    ScenarioBuilder::new(
        "energy-arena",
        DESCRIPTION,
        seed,
        frame,
        profiles::rover_small(),
    )
    .map(|m| MapParams {
        rho_obstacle: 0.05,
        r_sensor: 0.5,
        sensor_height: 0.1,
        r_hist: 0.1,
        c_radius: 0.2,
        ..m
    })
    .sim(sim_params())
    .strategy(&["tours"], strategy::params(&[], &[("n_tours", 25)]))
    .terrains(terrains())
    .generate("the arena's corners are not on reachable timber", |a| {
        let plan = Plan::draw(a.rng);
        let mut c = a.canvas();
        plan.paint(&mut c);
        let world = a.finish(&c);
        let adm = a.admissible(&world);
        // Holds by construction; checked so that a change to the frame or the robot that broke
        // it fails here rather than in a tour.
        if !plan.corners_on_reachable_timber(&world, &adm) {
            return None;
        }
        Some(Layout {
            world,
            start: plan.base(),
            tours: vec![builder::tour("base-waypoints", plan.tour(), true)],
        })
    })
}

fn terrains() -> TerrainTable {
    TerrainTable::new()
        .add(
            TIMBER,
            "timber",
            &[("drive", powered(1.0, TIMBER_MOTIVE_W))],
            Look::new(Rgb8::new(170, 120, 70), 7.0, 0.0005),
        )
        .add(
            CARPET,
            "grey carpet",
            &[("drive", powered(1.0, CARPET_MOTIVE_W))],
            Look::new(Rgb8::new(120, 120, 120), 6.0, 0.001),
        )
        .obstacle(WALL, "wall", Look::white_wall())
}

/// One draw of the arena: the rectangle of cells whose corners are the base and the waypoints,
/// which corner the base is on, and the interior carpet band.
struct Plan {
    /// Lower-left and upper-right corner cells, column and row.
    lo: (usize, usize),
    hi: (usize, usize),
    /// Index of the base's corner, counter-clockwise from the lower left.
    base_corner: usize,
    /// Width of the carpet band inside the rectangle, cells (edge row included).
    band: usize,
}

impl Plan {
    fn draw(rng: &mut ChaCha8Rng) -> Self {
        let (cols, rows) = ((W / RES).round() as usize, (H / RES).round() as usize);
        let w = rng.random_range(WIDTH_CELLS.0..=WIDTH_CELLS.1);
        let h = rng.random_range(HEIGHT_CELLS.0..=HEIGHT_CELLS.1);
        let i0 = rng.random_range(CLEAR_CELLS..=cols - 1 - CLEAR_CELLS - w);
        let j0 = rng.random_range(CLEAR_CELLS..=rows - 1 - CLEAR_CELLS - h);
        Self {
            lo: (i0, j0),
            hi: (i0 + w, j0 + h),
            base_corner: rng.random_range(0..4),
            band: rng.random_range(BAND_CELLS.0..=BAND_CELLS.1),
        }
    }

    /// The centre of cell (i, j).
    fn center(i: usize, j: usize) -> Point2 {
        Point2::new((i as f64 + 0.5) * RES, (j as f64 + 0.5) * RES)
    }

    /// The four corners counter-clockwise from the lower left.
    fn corners(&self) -> [Point2; 4] {
        let ((i0, j0), (i1, j1)) = (self.lo, self.hi);
        [
            Self::center(i0, j0),
            Self::center(i1, j0),
            Self::center(i1, j1),
            Self::center(i0, j1),
        ]
    }

    fn base(&self) -> Point2 {
        self.corners()[self.base_corner]
    }

    /// The base, then the other corners counter-clockwise.
    fn tour(&self) -> Vec<Point2> {
        let c = self.corners();
        (0..4).map(|k| c[(self.base_corner + k) % 4]).collect()
    }

    /// Carpet (5 mm high) on the rectangle's cells within the band of its edges, corner cells
    /// excepted; the border wall.
    fn paint(&self, c: &mut Canvas) {
        let ((i0, j0), (i1, j1)) = (self.lo, self.hi);
        let band = self.band as f64;
        // The rectangle's cell edges: its cell centres lie half a cell inside them.
        let cells = c.cells_in(
            i0 as f64 * RES,
            j0 as f64 * RES,
            (i1 + 1) as f64 * RES,
            (j1 + 1) as f64 * RES,
        );
        c.paint(
            cells,
            |p, _| {
                let (i, j) = ((p.x / RES - 0.5).round(), (p.y / RES - 0.5).round());
                let (di, dj) = (
                    (i - i0 as f64).min(i1 as f64 - i),
                    (j - j0 as f64).min(j1 as f64 - j),
                );
                let corner = di == 0.0 && dj == 0.0;
                !corner && di.min(dj) < band
            },
            CARPET,
            Some(0.005),
        );
        c.border(RES, WALL, 0.1);
    }

    /// Every corner lies on an admissible timber cell, all four in one timber region.
    fn corners_on_reachable_timber(&self, world: &World, adm: &[bool]) -> bool {
        let timber = restrict_to(world, adm, &[TIMBER]);
        let Some(reach) = reach_from(world, &timber, self.base()) else {
            return false;
        };
        self.corners()
            .iter()
            .all(|&p| point_in_mask(world, adm, p) && world.index_at(p).is_some_and(|k| reach[k]))
    }
}
