//! `bonn-paths` (Nardi19): a 60 × 40 m outdoor area at 0.5 m with paved road, dirt road, gravel
//! and grass on gently rolling ground, and an aerial RGB layer in which the terrains are
//! distinguishable but noisy (per-cell noise plus low-frequency illumination).
//!
//! Layout rules (every seed): a paved road crosses the area west to east through random control
//! points; two dirt roads branch off it to the north and south edges; a gravel yard touches the
//! road and a gravel path leaves it; the rest is grass. Vibration (z-acceleration RMS, m/s²):
//! paved 0.5, dirt 1.5, gravel 4.0, grass 2.5; energy per metre: 1.0, 1.2, 1.6, 2.0 (relative),
//! drawn as power = energy per metre × speed, so the husky measures it through `power_w`.
//! Tours: `start-goal` (south-west to north-east) and `locations` A–D, one on each terrain.

use rand::{RngExt, rngs::ChaCha8Rng};
use strider_core::{Point2, Rgb8};
use strider_map::MapParams;

use super::builder::{self, Frame, Layout, ScenarioBuilder};
use super::canvas::Canvas;
use super::draw::uni;
use super::placement::{connected_from, snap};
use super::strategy;
use super::terrains::{Look, TerrainTable, powered, terrain};
use crate::error::ScenarioError;
use crate::model::{Scenario, TerrainType, World};
use crate::profiles;

pub(super) const DESCRIPTION: &str = "Nardi19 Bonn paths: 60×40 m at 0.5 m, paved road, dirt \
roads, gravel and grass with a noisy aerial colour layer; vibration paved 0.5 / dirt 1.5 / gravel \
4.0 / grass 2.5 m/s², energy per metre 1.0/1.2/1.6/2.0, husky; start-goal task and locations A–D.";

/// Terrain indices.
pub const PAVED: u8 = 0;
/// Dirt road.
pub const DIRT: u8 = 1;
/// Gravel.
pub const GRAVEL: u8 = 2;
/// Grass.
pub const GRASS: u8 = 3;

const W: f64 = 60.0;
const H: f64 = 40.0;
const RES: f64 = 0.5;

/// Smooth field: a sum of a few random plane waves, in [−1, 1].
fn waves(rng: &mut ChaCha8Rng, n: usize, wavelength: (f64, f64)) -> Vec<(f64, f64, f64, f64)> {
    (0..n)
        .map(|_| {
            let l = uni(rng, wavelength.0, wavelength.1);
            let th = uni(rng, 0.0, std::f64::consts::TAU);
            let k = std::f64::consts::TAU / l;
            (
                k * th.cos(),
                k * th.sin(),
                uni(rng, 0.0, std::f64::consts::TAU),
                1.0 / n as f64,
            )
        })
        .collect()
}

fn field(w: &[(f64, f64, f64, f64)], p: Point2) -> f64 {
    w.iter()
        .map(|&(kx, ky, ph, a)| a * (kx * p.x + ky * p.y + ph).sin())
        .sum()
}

pub(super) fn generate(seed: u64) -> Result<Scenario, ScenarioError> {
    let frame = Frame::new(W, H, RES, GRASS);
    let b = ScenarioBuilder::new("bonn-paths", DESCRIPTION, seed, frame, profiles::husky());
    let terrains = terrains(b.robot().gaits[0].max_speed);
    b.map(|m| MapParams {
        rho_obstacle: 0.3,
        r_sensor: 5.0,
        sensor_height: 0.5,
        r_hist: 1.0,
        c_radius: 2.0,
        ..m
    })
    .strategy(
        &["navigate"],
        strategy::params(&[("lambda", 1.0), ("grid", 0.5)], &[]),
    )
    .terrains(terrains)
    .generate("no valid layout found", |a| {
        let mut c = a.canvas();
        let road = paint_roads(&mut c, a.rng);
        paint_gravel(&mut c, &road, a.rng);
        let hills = waves(a.rng, 4, (25.0, 60.0));
        for k in 0..c.elev.len() {
            c.elev[k] = (0.5 + 0.4 * field(&hills, c.center(k))) as f32;
        }
        let light = waves(a.rng, 3, (10.0, 30.0));
        let mut world = a.finish(&c);
        illuminate(&mut world, &light);
        let adm = a.admissible(&world);
        let start = snap(&world, &adm, Point2::new(3.0, 3.0))?;
        let goal = snap(&world, &adm, Point2::new(W - 3.0, H - 3.0))?;
        let locations = locations(&world, &adm, a.rng)?;
        if !connected_from(&world, &adm, start) {
            return None;
        }
        Some(Layout {
            world,
            start,
            tours: vec![
                builder::tour("start-goal", vec![start, goal], false),
                builder::tour("locations", locations, false),
            ],
        })
    })
}

/// The four terrains; `v_max` is the husky's speed.
fn terrains(v_max: f64) -> TerrainTable {
    let grass = Look::mixed(
        &[
            Rgb8::new(75, 125, 55),
            Rgb8::new(60, 105, 45),
            Rgb8::new(90, 135, 60),
        ],
        12.0,
        0.015,
    );
    // (index, name, vibration, energy/m, speed factor, look)
    #[rustfmt::skip]
    let table = [
        (PAVED, "paved road", 0.5, 1.0, 1.0, Look::new(Rgb8::new(95, 95, 100), 12.0, 0.002)),
        (DIRT, "dirt road", 1.5, 1.2, 0.9, Look::new(Rgb8::new(150, 115, 75), 14.0, 0.008)),
        (GRAVEL, "gravel", 4.0, 1.6, 0.8, Look::new(Rgb8::new(185, 180, 165), 14.0, 0.01)),
        (GRASS, "grass", 2.5, 2.0, 0.7, grass),
    ];
    // The draw is energy per metre × the speed reached (W = J/m · m/s), so the energy the
    // robot measures per metre (power over speed) is the table's energy per metre.
    table
        .into_iter()
        .fold(TerrainTable::new(), |t, (i, n, vib, e, s, look)| {
            let drive = [("drive", powered(s, e * s * v_max))];
            t.row(
                TerrainType {
                    vibration: vib,
                    energy_per_m: e,
                    ..terrain(i, n, &drive)
                },
                look,
            )
        })
}

/// The paved road west → east through random control points, and a dirt road branching off it
/// to the north and to the south edge. Returns the road's control points.
fn paint_roads(c: &mut Canvas, rng: &mut ChaCha8Rng) -> Vec<Point2> {
    let mut road = vec![Point2::new(-1.0, uni(rng, 8.0, 16.0))];
    for k in 1..4 {
        road.push(Point2::new(
            k as f64 * 15.0 + uni(rng, -3.0, 3.0),
            uni(rng, 10.0, 30.0),
        ));
    }
    road.push(Point2::new(W + 1.0, uni(rng, 24.0, 32.0)));
    for s in road.windows(2) {
        c.segment(s[0], s[1], 2.0, PAVED, None, None);
    }
    for north in [true, false] {
        let a = road[rng.random_range(1..4)];
        let end = Point2::new(
            a.x + uni(rng, -12.0, 12.0),
            if north { H + 1.0 } else { -1.0 },
        );
        let mid = Point2::new(
            (a.x + end.x) / 2.0 + uni(rng, -5.0, 5.0),
            (a.y + end.y) / 2.0,
        );
        c.segment(a, mid, 1.25, DIRT, None, Some(&[GRASS]));
        c.segment(mid, end, 1.25, DIRT, None, Some(&[GRASS]));
    }
    road
}

/// A gravel yard touching the road at one of its control points, and a gravel path leaving
/// the yard.
fn paint_gravel(c: &mut Canvas, road: &[Point2], rng: &mut ChaCha8Rng) {
    let a = road[rng.random_range(1..4)];
    let (gw, gh) = (uni(rng, 6.0, 10.0), uni(rng, 5.0, 8.0));
    let up = rng.random_bool(0.5);
    let gy = if up { a.y + 1.5 } else { a.y - 1.5 - gh };
    let cells = c.cells_in(a.x - gw / 2.0, gy, a.x + gw / 2.0, gy + gh);
    c.paint(cells, |_, t| t == GRASS, GRAVEL, None);
    let p0 = Point2::new(a.x + gw / 2.0, gy + gh / 2.0);
    let p1 = Point2::new(p0.x + uni(rng, 8.0, 15.0), p0.y + uni(rng, -6.0, 6.0));
    c.segment(p0, p1, 1.0, GRAVEL, None, Some(&[GRASS]));
}

/// The aerial image's low-frequency illumination: ±8 % brightness following `light`.
fn illuminate(world: &mut World, light: &[(f64, f64, f64, f64)]) {
    for k in 0..world.color.len() {
        let f = 1.0 + 0.08 * field(light, world.cell_center(k));
        world.color[k] = Rgb8(
            world.color[k]
                .0
                .map(|v| (v as f64 * f).round().clamp(0.0, 255.0) as u8),
        );
    }
}

/// Locations A–D: one admissible cell inside a 3 × 3 patch of each terrain, drawn at random
/// (`None` when a terrain has no such cell).
fn locations(world: &World, adm: &[bool], rng: &mut ChaCha8Rng) -> Option<Vec<Point2>> {
    let (ww, wh) = (world.width(), world.height());
    let mut locations = Vec::new();
    for t in [PAVED, DIRT, GRAVEL, GRASS] {
        let cand: Vec<usize> = (0..adm.len())
            .filter(|&k| {
                let (x, y) = (k % ww, k / ww);
                adm[k]
                    && x > 2
                    && y > 2
                    && x + 3 < ww
                    && y + 3 < wh
                    && (0..9).all(|d| world.terrain[(y + d / 3 - 1) * ww + x + d % 3 - 1] == t)
            })
            .collect();
        if cand.is_empty() {
            return None;
        }
        locations.push(world.cell_center(cand[rng.random_range(0..cand.len())]));
    }
    Some(locations)
}
