//! `energy-arena` (MartinCorke): a 2 × 1.5 m flat floor at 0.05 m of smooth timber (0.63 W at
//! 0.1 m/s) with a grey carpet band (1.21 W) lying across the straight lines from the base to the
//! three waypoints; a timber gap at one end of the band leaves an energy-cheaper detour. The rover
//! draws a 0.21 W hotel load; the benchmark runs 25 tours (`strategy.tours.n_tours`). As in
//! MartinCorke §4 the pose arrives at 30 Hz and the power at 10 Hz, both noisy.

use rand::{RngExt, rngs::ChaCha8Rng};
use strider_core::{Point2, Rgb8};
use strider_map::MapParams;

use super::builder::{self, Frame, Layout, ScenarioBuilder};
use super::canvas::Canvas;
use super::draw::uni;
use super::placement::{crosses, reach_from, restrict_to};
use super::strategy;
use super::terrains::{Look, TerrainTable, powered};
use crate::error::ScenarioError;
use crate::ground_truth::point_in_mask;
use crate::model::{Scenario, SimParams, World};
use crate::profiles;

pub(super) const DESCRIPTION: &str = "MartinCorke energy arena: 2×1.5 m at 0.05 m, smooth timber \
(0.63 W at 0.1 m/s) with a grey carpet band (1.21 W) across the straight lines between base and \
the 3 waypoints, rover-small (hotel load 0.21 W); tour = base + 3 waypoints, 25 tours.";

/// Terrain indices.
pub const TIMBER: u8 = 0;
/// Grey carpet.
pub const CARPET: u8 = 1;
/// Border wall.
pub const WALL: u8 = 2;

const W: f64 = 2.0;
const H: f64 = 1.5;
const RES: f64 = 0.05;

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
    .generate("no valid layout found", |a| {
        let plan = Plan::draw(a.rng);
        let mut c = a.canvas();
        plan.paint(&mut c);
        let world = a.finish(&c);
        let adm = a.admissible(&world);
        let tour = plan.tour();
        if !(tour.iter().all(|&p| point_in_mask(&world, &adm, p)) && plan.has_detours(&world, &adm))
        {
            return None;
        }
        Some(Layout {
            world,
            start: plan.base,
            tours: vec![builder::tour("base-waypoints", tour, true)],
        })
    })
}

fn terrains() -> TerrainTable {
    TerrainTable::new()
        .add(
            TIMBER,
            "timber",
            &[("drive", powered(1.0, 0.63))],
            Look::new(Rgb8::new(170, 120, 70), 7.0, 0.0005),
        )
        .add(
            CARPET,
            "grey carpet",
            &[("drive", powered(1.0, 1.21))],
            Look::new(Rgb8::new(120, 120, 120), 6.0, 0.001),
        )
        .obstacle(WALL, "wall", Look::white_wall())
}

/// One draw of the arena: the base, the three waypoints and the carpet band.
struct Plan {
    base: Point2,
    waypoints: Vec<Point2>,
    /// Band centre line: x at mid-height, and its tilt (dx/dy).
    xc: f64,
    tilt: f64,
    /// Half the band's width.
    half: f64,
    /// The timber gap is at the bottom (else at the top).
    gap_low: bool,
}

impl Plan {
    fn draw(rng: &mut ChaCha8Rng) -> Self {
        let base = Point2::new(uni(rng, 0.2, 0.35), uni(rng, 0.55, 0.95));
        let waypoints = [0.3, 0.75, 1.2]
            .iter()
            .map(|&y| Point2::new(uni(rng, 1.6, 1.8), y + uni(rng, -0.08, 0.08)))
            .collect();
        let xc = uni(rng, 0.85, 1.15);
        let half = uni(rng, 0.15, 0.25);
        let tilt = uni(rng, -0.15, 0.15);
        let gap_low = rng.random_bool(0.5);
        Self {
            base,
            waypoints,
            xc,
            tilt,
            half,
            gap_low,
        }
    }

    /// The carpet band (5 mm high) with its gap, and the border wall.
    fn paint(&self, c: &mut Canvas) {
        let (y0, y1) = if self.gap_low {
            (0.35, H)
        } else {
            (0.0, H - 0.35)
        };
        let cells = c.cells_in(0.0, y0, W, y1);
        c.paint(
            cells,
            |p, _| (p.x - (self.xc + self.tilt * (p.y - H / 2.0))).abs() <= self.half,
            CARPET,
            Some(0.005),
        );
        c.border(RES, WALL, 0.1);
    }

    /// The base, then the waypoints.
    fn tour(&self) -> Vec<Point2> {
        let mut tour = vec![self.base];
        tour.extend(self.waypoints.iter().copied());
        tour
    }

    /// Each straight base → waypoint line crosses the carpet, and a timber-only detour exists.
    fn has_detours(&self, world: &World, adm: &[bool]) -> bool {
        let timber = restrict_to(world, adm, &[TIMBER]);
        let Some(reach) = reach_from(world, &timber, self.base) else {
            return false;
        };
        self.waypoints.iter().all(|&w| {
            crosses(world, self.base, w, &[CARPET]) && world.index_at(w).is_some_and(|k| reach[k])
        })
    }
}
