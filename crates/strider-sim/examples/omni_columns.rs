//! Times omnidirectional scans cast by azimuth columns (`RangeSensor::scan`) against the same
//! scans cast ray by ray (`RangeSensor::scan_ray_by_ray`), side by side, with the
//! `hexapod-large` sensor (720 × 48 rays, 10 m) on two worlds: the built-in `courtyard-large`
//! (seed 1) and a 60 × 75 m field at 0.1 m with gentle undulation, walls and boxes. Both paths
//! scan the same poses in alternating rounds; every pair of clouds is checked to be identical.
//!
//! `cargo run --release -p strider-sim --example omni_columns`
//! (`RAYON_NUM_THREADS=1` for one thread)

use std::time::{Duration, Instant};

use rand::rngs::ChaCha8Rng;
use rand::{RngExt, SeedableRng};
use strider_core::{Cell, CellRect, Point2, Point3, Rgb8};
use strider_scenario::{World, builtin, profiles};
use strider_sim::{Heightfield, RangeSensor, ScanNoise};

/// A `w × h` m field at cell size `d`: ±4 cm undulation with 3 mm roughness, 0.5 m walls with
/// doorways every 12 m, 0.5–1 m boxes.
fn field(w: f64, h: f64, d: f64) -> World {
    let (nw, nh) = ((w / d) as u32, (h / d) as u32);
    let n = (nw * nh) as usize;
    let mut rng = ChaCha8Rng::seed_from_u64(3);
    let mut elevation = Vec::with_capacity(n);
    for j in 0..nh {
        for i in 0..nw {
            let (x, y) = (i as f64 * d, j as f64 * d);
            let z = 0.04 * (x / 7.0).sin() * (y / 9.0).cos() + rng.random_range(0.0..0.003);
            let wall = (x % 12.0 < 0.2 && y % 12.0 > 2.5) || (y % 15.0 < 0.2 && x % 12.0 > 3.0);
            elevation.push(if wall { 0.5 } else { z as f32 });
        }
    }
    for _ in 0..150 {
        let (i0, j0) = (rng.random_range(0..nw - 10), rng.random_range(0..nh - 10));
        let (bw, bh) = (rng.random_range(4..10), rng.random_range(4..10));
        let z = rng.random_range(0.5f32..1.0);
        for j in j0..j0 + bh {
            for i in i0..i0 + bw {
                elevation[(j * nw + i) as usize] = z;
            }
        }
    }
    World {
        resolution: d,
        rect: CellRect::new(Cell::new(0, 0), nw, nh),
        elevation,
        color: vec![Rgb8::new(128, 128, 128); n],
        terrain: vec![0; n],
        terrains: Vec::new(),
    }
}

/// `count` sensor origins on low ground of `world`, `height` above it.
fn origins(world: &World, hf: &Heightfield, count: usize, height: f64) -> Vec<Point3> {
    let mut rng = ChaCha8Rng::seed_from_u64(11);
    let d = world.resolution;
    let (w, h) = (world.rect.width as f64 * d, world.rect.height as f64 * d);
    let mut out = Vec::with_capacity(count);
    while out.len() < count {
        let p = Point2::new(
            rng.random_range(0.5..w - 0.5),
            rng.random_range(0.5..h - 0.5),
        );
        if let Some(z) = hf.elevation_at(p).filter(|&z| z < 0.1) {
            out.push(Point3::new(p.x, p.y, z + height));
        }
    }
    out
}

/// Scans from every origin by columns and ray by ray, alternating, `rounds` times: ms per scan
/// of each (total time over all rounds) and points per scan.
fn time(world: &World, sensor: &RangeSensor, origins: &[Point3], rounds: u64) -> (f64, f64, usize) {
    let hf = Heightfield::from_world(world).unwrap();
    let noise = ScanNoise {
        depth_sigma: 0.01,
        depth_k: 0.0,
        color_sigma: 4.0,
    };
    let (mut columns, mut rays) = (Duration::ZERO, Duration::ZERO);
    let mut points = 0;
    // The first column scan builds the heightfield's neighbourhood maxima: not timed.
    let _ = sensor.scan(&hf, &world.color, origins[0], 0.0, &noise, 0.0, 1, 0);
    for round in 0..rounds {
        for (k, &o) in origins.iter().enumerate() {
            let (yaw, index) = (0.37 * k as f64 + round as f64, round * 1000 + k as u64);
            let t = Instant::now();
            let a = sensor.scan(&hf, &world.color, o, yaw, &noise, 0.0, 1, index);
            columns += t.elapsed();
            let t = Instant::now();
            let b = sensor.scan_ray_by_ray(&hf, &world.color, o, yaw, &noise, 0.0, 1, index);
            rays += t.elapsed();
            assert!(a.points == b.points, "clouds differ at {o:?}");
            points += a.points.len();
        }
    }
    let scans = (rounds as usize * origins.len()) as f64;
    let ms = |t: Duration| t.as_secs_f64() * 1000.0 / scans;
    (ms(rays), ms(columns), points / scans as usize)
}

fn main() {
    let spec = profiles::hexapod_large().sensors[0].clone();
    let sensor = RangeSensor::new(&spec, "hexapod-large").unwrap();
    let courtyard = builtin::generate("courtyard-large", 1).unwrap().world;
    let worlds = [
        ("courtyard-large (seed 1), 20 x 25 m", courtyard),
        ("field 60 x 75 m at 0.1 m", field(60.0, 75.0, 0.1)),
    ];
    println!(
        "{} rays per scan, {} rayon threads; ms per scan (noise included)",
        sensor.ray_count(),
        rayon::current_num_threads()
    );
    for (name, world) in &worlds {
        let hf = Heightfield::from_world(world).unwrap();
        let origins = origins(world, &hf, 40, spec.height);
        let (rays, columns, points) = time(world, &sensor, &origins, 5);
        println!(
            "{name}: ray by ray {rays:.2} ms, by columns {columns:.2} ms, ratio {:.2} ({points} points per scan, identical clouds)",
            rays / columns
        );
    }
}
