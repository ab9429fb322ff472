//! `escape-arena` (Prágr23 §5.2): about 7 × 5 m (35 m²) at 0.05 m in three sections with no
//! line of sight between them: an office room with rigid wooden boxes and white walls, a purple
//! fabric curtain in its wall to a corridor, and a second curtain splitting the corridor.
//!
//! Walls and curtains are 1 m high, so curtains look like obstacles (step > t_trav = 0.12 m =
//! `map.rho_obstacle`) and block the view; a curtain needs 0.5–1 N to push through
//! (`push_force_n`, drawn per seed), boxes 15 N, walls are rigid (`None`). With all apparent
//! obstacles rigid only the office is reachable; with the curtains pushed, everything is.

use rand::{RngExt, rngs::ChaCha8Rng};
use strider_core::{Point2, Rgb8};
use strider_map::MapParams;

use super::builder::{self, Attempt, Frame, Layout, ScenarioBuilder};
use super::canvas::{Canvas, Rect};
use super::draw::uni;
use super::placement::{reach_from, snap};
use super::strategy;
use super::terrains::{Look, TerrainTable, speed, terrain};
use crate::error::ScenarioError;
use crate::model::{Scenario, TerrainType, World};
use crate::profiles;

pub(super) const DESCRIPTION: &str = "Prágr23 §5.2 escape arena: ~35 m² at 0.05 m, an office with \
rigid wooden boxes and white walls, a purple curtain (0.5–1 N) to a corridor that a second curtain \
splits; three sections without line of sight, hexapod-bumper (t_trav 0.12 m, F_trav 2 N).";

/// Terrain indices.
pub const FLOOR: u8 = 0;
/// White walls.
pub const WALL: u8 = 1;
/// Rigid wooden boxes.
pub const BOX: u8 = 2;
/// Purple fabric curtains.
pub const CURTAIN: u8 = 3;

const W: f64 = 7.0;
const H: f64 = 5.0;
const RES: f64 = 0.05;
const WALL_T: f64 = 0.1;
const WALL_Z: f32 = 1.0;

pub(super) fn generate(seed: u64) -> Result<Scenario, ScenarioError> {
    let frame = Frame::new(W, H, RES, FLOOR);
    let mut b = ScenarioBuilder::new(
        "escape-arena",
        DESCRIPTION,
        seed,
        frame,
        profiles::hexapod_bumper(),
    )
    .map(|m| MapParams {
        r_sensor: 2.0,
        rho_obstacle: 0.12,
        sensor_height: 0.3,
        r_hist: 0.25,
        c_radius: 0.5,
        ..m
    })
    .strategy(
        &["escape", "rigid"],
        strategy::params(&[("f_trav", 2.0)], &[]),
    );
    // Curtains need 0.5–1 N, in steps of 0.05 N.
    let curtain_force = (uni(b.rng(), 0.5, 1.0) * 20.0).round() / 20.0;
    b.terrains(terrains(curtain_force))
        .generate("no valid layout found", |a| {
            let plan = Plan::draw(a.rng);
            let mut c = a.canvas();
            plan.paint_walls(&mut c);
            plan.place_boxes(&mut c, a.rng);
            let world = a.finish(&c);
            let adm = a.admissible(&world);
            let start = snap(&world, &adm, Point2::new(0.6, 0.6))?;
            let sections: Vec<Point2> = plan
                .section_centres()
                .iter()
                .filter_map(|&p| snap(&world, &adm, p))
                .collect();
            if sections.len() != 3 || !plan.curtains_separate(a, &world, &adm, start)? {
                return None;
            }
            Some(Layout {
                world,
                start,
                tours: vec![builder::tour("sections", sections, false)],
            })
        })
}

fn terrains(curtain_force: f64) -> TerrainTable {
    TerrainTable::new()
        .add(
            FLOOR,
            "floor",
            &[("walk", speed(1.0))],
            Look::new(Rgb8::new(120, 120, 125), 6.0, 0.001),
        )
        .obstacle(WALL, "wall", Look::white_wall())
        .row(
            TerrainType {
                push_force_n: Some(15.0),
                ..terrain(BOX, "wooden box", &[])
            },
            Look::new(Rgb8::new(130, 90, 50), 8.0, 0.0),
        )
        .row(
            TerrainType {
                push_force_n: Some(curtain_force),
                ..terrain(CURTAIN, "curtain", &[("walk", speed(0.8))])
            },
            Look::new(Rgb8::new(170, 60, 170), 8.0, 0.0),
        )
}

/// One draw of the arena's walls: the office to the west, the corridor to the east.
struct Plan {
    /// Corridor width.
    cw: f64,
    /// West side of the dividing wall `[wx, wx + WALL_T]`.
    wx: f64,
    /// South side of the corridor curtain `[m, m + WALL_T]`.
    m: f64,
    /// The curtain in the dividing wall: its width and south end.
    c1_w: f64,
    c1_y: f64,
}

impl Plan {
    fn draw(rng: &mut ChaCha8Rng) -> Self {
        let cw = uni(rng, 1.4, 1.8);
        let m = uni(rng, 2.6, 3.3);
        let c1_w = uni(rng, 1.0, 1.2);
        let c1_y = uni(rng, WALL_T + 0.3, m - 0.3 - c1_w);
        Self {
            cw,
            wx: W - WALL_T - cw - WALL_T,
            m,
            c1_w,
            c1_y,
        }
    }

    /// Border, dividing wall and the two curtains.
    fn paint_walls(&self, c: &mut Canvas) {
        let (wx, m) = (self.wx, self.m);
        c.border(WALL_T, WALL, WALL_Z);
        c.rect(wx, 0.0, wx + WALL_T, H, WALL, Some(WALL_Z));
        c.rect(
            wx,
            self.c1_y,
            wx + WALL_T,
            self.c1_y + self.c1_w,
            CURTAIN,
            Some(WALL_Z),
        );
        c.rect(
            wx + WALL_T,
            m,
            W - WALL_T,
            m + WALL_T,
            CURTAIN,
            Some(WALL_Z),
        );
    }

    /// 3–5 boxes in the office, clear of walls, of each other, of the curtain and of the start.
    fn place_boxes(&self, c: &mut Canvas, rng: &mut ChaCha8Rng) {
        let clear = 0.75;
        let door = Point2::new(self.wx, self.c1_y + self.c1_w / 2.0);
        let door = Rect::at(door.x, door.y, 0.0, 0.0);
        let mut boxes: Vec<Rect> = Vec::new();
        let n = rng.random_range(3..6usize);
        for _ in 0..20 {
            if boxes.len() >= n {
                break;
            }
            let (bw, bh) = (uni(rng, 0.4, 0.8), uni(rng, 0.4, 0.8));
            let bx = uni(rng, WALL_T + clear, self.wx - clear - bw);
            let by = uni(rng, WALL_T + clear, H - WALL_T - clear - bh);
            let b = Rect::at(bx, by, bw, bh);
            let near_door = b.gap(&door) < 1.3;
            let near_start = b.x0 < 1.3 && b.y0 < 1.3;
            if !near_door && !near_start && boxes.iter().all(|o| b.gap(o) >= clear) {
                let z = uni(rng, 0.4, 0.7) as f32;
                c.fill(b, BOX, Some(z));
                boxes.push(b);
            }
        }
    }

    /// Aim points of the three sections: office, corridor south and north of its curtain.
    fn section_centres(&self) -> [Point2; 3] {
        let (wx, m, cw) = (self.wx, self.m, self.cw);
        [
            Point2::new(wx / 2.0, H / 2.0),
            Point2::new(wx + WALL_T + cw / 2.0, m / 2.0),
            Point2::new(wx + WALL_T + cw / 2.0, (m + H) / 2.0),
        ]
    }

    /// With all apparent obstacles rigid the office is one connected piece and the corridor is
    /// out of reach; with the curtains pushed, everything is reachable (`None`: start off the
    /// world).
    fn curtains_separate(
        &self,
        a: &Attempt<'_>,
        world: &World,
        adm: &[bool],
        start: Point2,
    ) -> Option<bool> {
        let office = reach_from(world, adm, start)?;
        let office_only =
            (0..adm.len()).all(|k| !adm[k] || office[k] == (world.cell_center(k).x < self.wx));
        let mut open = world.clone();
        for k in 0..open.elevation.len() {
            if open.terrain[k] == CURTAIN {
                open.elevation[k] = 0.0;
            }
        }
        let open_adm = a.admissible(&open);
        let all = reach_from(&open, &open_adm, start)?;
        Some(office_only && all == open_adm)
    }
}
