//! Casting an omnidirectional sensor's azimuth columns at once gives every ray exactly the hit
//! of casting it on its own, and a scan exactly the same cloud.
mod common;

use common::*;
use proptest::prelude::*;
use rand::rngs::ChaCha8Rng;
use rand::{RngExt, SeedableRng};
use strider_core::{Cell, CellRect, Point3, PointCloud, Pose2, Rgb8};
use strider_scenario::{SensorKind, SensorSpec, World};
use strider_sim::{Heightfield, RangeSensor, RayHit, ScanNoise};

/// Bit-for-bit equality of two casts' results (`==` on `f64` would let −0 pass for +0).
fn same(a: &Option<RayHit>, b: &Option<RayHit>) -> bool {
    match (a, b) {
        (None, None) => true,
        (Some(a), Some(b)) => {
            let bits = |h: &RayHit| [h.range, h.point.x, h.point.y, h.point.z].map(f64::to_bits);
            bits(a) == bits(b) && (a.cell, a.index, a.face) == (b.cell, b.index, b.face)
        }
        _ => false,
    }
}

/// An omnidirectional sensor.
fn omni_spec(
    columns: u32,
    rows: u32,
    elevation: (f64, f64),
    range: f64,
    yaw_deg: f64,
) -> SensorSpec {
    SensorSpec {
        kind: SensorKind::Omni {
            min_elevation_deg: elevation.0,
            max_elevation_deg: elevation.1,
            columns,
            rows,
        },
        range,
        height: 0.5,
        yaw_deg,
        rate_hz: 2.0,
    }
}

/// Casts columns `cols` of `sensor` (robot heading `yaw`) from `origin` both ways and returns
/// the number of rays compared and of hits; panics with the first difference.
fn compare_columns(
    hf: &Heightfield,
    sensor: &RangeSensor,
    origin: Point3,
    yaw: f64,
    cols: impl Iterator<Item = usize>,
) -> (usize, usize) {
    let SensorKind::Omni { columns, rows, .. } = sensor.spec().kind else {
        unreachable!()
    };
    let (columns, rows) = (columns as usize, rows as usize);
    let range = sensor.spec().range;
    let (sy, cy) = yaw.sin_cos();
    let body = sensor.body_directions();
    let (mut dirs, mut hits) = (Vec::new(), Vec::new());
    let (mut rays, mut hit_count) = (0, 0);
    for c in cols {
        // World-frame directions as `RangeSensor::scan` turns them.
        dirs.clear();
        dirs.extend((0..rows).map(|r| {
            let b = body[r * columns + c];
            [b[0] * cy - b[1] * sy, b[0] * sy + b[1] * cy, b[2]]
        }));
        hf.cast_column(origin, &dirs, range, &mut hits);
        assert_eq!(hits.len(), rows);
        for (r, (u, got)) in dirs.iter().zip(&hits).enumerate() {
            let want = hf.cast_unit(origin, *u, range);
            assert!(
                same(got, &want),
                "column {c} row {r}: origin {origin:?} u {u:?} range {range}\n  column: {got:?}\n  ray:    {want:?}"
            );
            rays += 1;
            hit_count += want.is_some() as usize;
        }
    }
    (rays, hit_count)
}

/// Terrain shapes of the random worlds.
#[derive(Clone, Copy, Debug)]
enum Terrain {
    Flat,
    Rough,
    Steps,
    Walls,
    Spikes,
    Holes,
}

const TERRAINS: [Terrain; 6] = [
    Terrain::Flat,
    Terrain::Rough,
    Terrain::Steps,
    Terrain::Walls,
    Terrain::Spikes,
    Terrain::Holes,
];

/// A random `w × h` world of cell size `d` whose lower-left cell is `min`.
fn random_world(
    rng: &mut ChaCha8Rng,
    terrain: Terrain,
    (w, h): (u32, u32),
    d: f64,
    min: Cell,
) -> World {
    let n = (w * h) as usize;
    let base: f32 = rng.random_range(-0.3..0.3);
    let mut elevation = vec![base; n];
    let cell = |rng: &mut ChaCha8Rng| rng.random_range(0..n);
    match terrain {
        Terrain::Flat => {}
        Terrain::Rough => {
            for z in &mut elevation {
                *z += rng.random_range(0.0..0.02);
            }
        }
        Terrain::Steps => {
            for _ in 0..rng.random_range(1..6) {
                let (i0, j0) = (rng.random_range(0..w), rng.random_range(0..h));
                let (i1, j1) = (rng.random_range(i0..=w), rng.random_range(j0..=h));
                let z = base + rng.random_range(-0.2..0.6);
                for j in j0..j1 {
                    for i in i0..i1 {
                        elevation[(j * w + i) as usize] = z;
                    }
                }
            }
        }
        Terrain::Walls => {
            for _ in 0..rng.random_range(1..4) {
                let z = base + rng.random_range(0.2..1.2);
                if rng.random_bool(0.5) {
                    let i = rng.random_range(0..w);
                    for j in 0..h {
                        elevation[(j * w + i) as usize] = z;
                    }
                } else {
                    let j = rng.random_range(0..h);
                    for i in 0..w {
                        elevation[(j * w + i) as usize] = z;
                    }
                }
            }
        }
        Terrain::Spikes => {
            for _ in 0..rng.random_range(1..(n / 8).max(2)) {
                let k = cell(rng);
                elevation[k] = base + rng.random_range(0.1..2.0);
            }
        }
        Terrain::Holes => {
            for z in &mut elevation {
                *z += rng.random_range(0.0..0.05);
            }
            for _ in 0..rng.random_range(1..(n / 4).max(2)) {
                let k = cell(rng);
                elevation[k] = [f32::NAN, f32::INFINITY, f32::NEG_INFINITY][rng.random_range(0..3)];
            }
        }
    }
    World {
        resolution: d,
        rect: CellRect::new(min, w, h),
        elevation,
        color: vec![Rgb8::new(100, 110, 120); n],
        terrain: vec![GROUND; n],
        terrains: terrains(),
    }
}

/// A sensor origin for `world`: inside, outside or on the edge of the world, possibly on a
/// cell boundary or corner, possibly inside a column.
fn random_origin(rng: &mut ChaCha8Rng, world: &World, hf: &Heightfield) -> Point3 {
    let d = world.resolution;
    let (x0, y0) = (world.rect.min.i as f64 * d, world.rect.min.j as f64 * d);
    let (ww, hh) = (world.rect.width as f64 * d, world.rect.height as f64 * d);
    let mut coord = |lo: f64, len: f64, cells: u32| match rng.random_range(0..6) {
        // On a cell boundary, the world's edges included.
        0 | 1 => lo + rng.random_range(0..=cells) as f64 * d,
        // Outside.
        2 => lo + rng.random_range(-0.5..1.5) * len,
        _ => lo + rng.random_range(0.0..1.0) * len,
    };
    let (x, y) = (
        coord(x0, ww, world.rect.width),
        coord(y0, hh, world.rect.height),
    );
    let ground = hf
        .elevation_at(strider_core::Point2::new(x, y))
        .unwrap_or(0.0);
    // Above the ground, or inside the column under the origin.
    let z = ground
        + if rng.random_bool(0.1) {
            -0.05
        } else {
            rng.random_range(0.01..1.5)
        };
    Point3::new(x, y, z)
}

/// Elevation ranges of the random sensors: all up, all down, nearly ±90°, exactly 0° and
/// anything.
fn random_elevation(rng: &mut ChaCha8Rng) -> (f64, f64) {
    match rng.random_range(0..6) {
        0 => (rng.random_range(0.0..30.0), rng.random_range(30.0..89.0)),
        1 => (rng.random_range(-89.0..-30.0), rng.random_range(-30.0..0.0)),
        2 => (-90.0, 90.0),
        3 => (0.0, 0.0),
        4 => (-40.0, 10.0),
        _ => {
            let (a, b) = (rng.random_range(-90.0..90.0), rng.random_range(-90.0..90.0));
            (f64::min(a, b), f64::max(a, b))
        }
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(192))]

    /// Random worlds (flat, rough, steps, walls, spikes, holes; tiny and odd sizes; shifted
    /// rectangles), origins (inside, outside, on the edge, on cell boundaries, inside a column)
    /// and omnidirectional sensors (1–64 rows, 1–800 columns, elevations up, down, ±90°, 0°):
    /// every ray of every column cast with `cast_column` hits exactly what `cast_unit` hits.
    #[test]
    fn columns_hit_exactly_what_single_rays_hit(
        seed in 0u64..u64::MAX,
        terrain in 0usize..TERRAINS.len(),
        w in 1u32..48,
        h in 1u32..48,
        d in prop::sample::select(vec![0.1, 0.05, 0.25, 1.0, 0.037, 0.3]),
        rows in 1u32..=64,
        columns in 1u32..=800,
        range in prop::sample::select(vec![0.05, 0.7, 3.0, 10.0, 40.0]),
        yaw_kind in 0usize..3,
    ) {
        let mut rng = ChaCha8Rng::seed_from_u64(seed);
        let min = Cell::new(rng.random_range(-6..6), rng.random_range(-6..6));
        let world = random_world(&mut rng, TERRAINS[terrain], (w, h), d, min);
        let hf = Heightfield::from_world(&world).unwrap();
        // Exact quarter and eighth turns put rays along the axes and diagonals.
        let yaw = match yaw_kind {
            0 => rng.random_range(0..8) as f64 * std::f64::consts::FRAC_PI_4,
            _ => rng.random_range(-4.0..4.0),
        };
        let mount = if rng.random_bool(0.5) { 0.0 } else { rng.random_range(-180.0..180.0) };
        let spec = omni_spec(columns, rows, random_elevation(&mut rng), range, mount);
        let sensor = RangeSensor::new(&spec, "s").unwrap();
        let origin = random_origin(&mut rng, &world, &hf);
        // At most ~80 columns per case, spread over the whole turn.
        let step = (columns as usize).div_ceil(80);
        let first = rng.random_range(0..step);
        compare_columns(&hf, &sensor, origin, yaw, (first..columns as usize).step_by(step));
    }
}

/// A courtyard-like world (walls, boxes, rough pavement) under the `hexapod-large` sensor from
/// many poses, all columns: ground hits on tops and sides, walls seen over passed blocks.
#[test]
fn courtyard_columns_hit_exactly_what_single_rays_hit() {
    let mut rng = ChaCha8Rng::seed_from_u64(5);
    let mut world = flat_world(90, 110, 0.1);
    for z in &mut world.elevation {
        *z = rng.random_range(0.0..0.004);
    }
    fill(&mut world, 0, 90, 50, 52, 0.5, WALL);
    fill(&mut world, 40, 42, 0, 110, 0.5, WALL);
    fill(&mut world, 40, 42, 60, 80, 0.0, GROUND);
    for _ in 0..12 {
        let (i, j) = (rng.random_range(0..84), rng.random_range(0..104));
        fill(
            &mut world,
            i,
            i + 6,
            j,
            j + 6,
            rng.random_range(0.5..1.0),
            BOX,
        );
    }
    let hf = Heightfield::from_world(&world).unwrap();
    let sensor = RangeSensor::new(&omni_spec(720, 48, (-40.0, 10.0), 10.0, 0.0), "s").unwrap();
    let (mut rays, mut hits) = (0, 0);
    for _ in 0..6 {
        let (x, y) = (rng.random_range(0.5..8.5), rng.random_range(0.5..10.5));
        let ground = hf.elevation_at(strider_core::Point2::new(x, y)).unwrap();
        let origin = Point3::new(x, y, ground + 0.5);
        let yaw = rng.random_range(-3.0..3.0);
        let (r, k) = compare_columns(&hf, &sensor, origin, yaw, 0..720);
        rays += r;
        hits += k;
    }
    assert!(rays == 6 * 720 * 48 && hits > rays / 2, "{hits} of {rays}");
}

/// Origins on cell corners and boundaries, rays along the axes and diagonals, over rough
/// ground with holes: the cases where rounding decides which cell comes first.
#[test]
fn grid_aligned_columns_hit_exactly_what_single_rays_hit() {
    let mut rng = ChaCha8Rng::seed_from_u64(6);
    let mut world = flat_world(40, 40, 0.1);
    for z in &mut world.elevation {
        *z = if rng.random_bool(0.03) {
            f32::NAN
        } else {
            rng.random_range(0.0..0.01)
        };
    }
    fill(&mut world, 30, 31, 0, 40, 0.4, WALL);
    let hf = Heightfield::from_world(&world).unwrap();
    let sensor = RangeSensor::new(&omni_spec(8, 40, (-60.0, 5.0), 3.0, 0.0), "s").unwrap();
    for (x, y) in [
        (2.0, 2.0),
        (2.0, 2.05),
        (2.05, 2.0),
        (0.0, 1.0),
        (4.0, 4.0),
        (1.3, 3.7),
    ] {
        for z in [0.3, 0.004] {
            for k in 0..8 {
                let yaw = k as f64 * std::f64::consts::FRAC_PI_4;
                compare_columns(&hf, &sensor, Point3::new(x, y, z), yaw, 0..8);
            }
        }
    }
}

/// Fans of rays in exactly diagonal and axis-aligned horizontal directions, from cell corners
/// and from points a few ulps off them: crossings tie exactly, or nearly, all along the rays,
/// so the walk's tie rule and the margins of the column's bounds decide.
#[test]
fn fans_through_cell_corners_hit_exactly_what_single_rays_hit() {
    let mut rng = ChaCha8Rng::seed_from_u64(9);
    let mut world = flat_world(48, 48, 0.125);
    for z in &mut world.elevation {
        *z = rng.random_range(0.0..0.02);
    }
    fill(&mut world, 36, 37, 0, 48, 0.3, WALL);
    let hf = Heightfield::from_world(&world).unwrap();
    let h = std::f64::consts::FRAC_1_SQRT_2;
    let horizontals = [
        [h, h],
        [-h, h],
        [h, -h],
        [-h, -h],
        [1.0, 0.0],
        [0.0, -1.0],
        [h, h * (1.0 + f64::EPSILON)],
    ];
    let (mut dirs, mut hits) = (Vec::new(), Vec::new());
    let mut rays = 0;
    for corner in [(3.0, 3.0), (2.875, 3.125), (1.5, 4.25)] {
        for (dx, dy) in [
            (0.0, 0.0),
            (1e-15, 0.0),
            (0.0, -3e-16),
            (4e-16, 4e-16),
            (2e-13, -1e-13),
        ] {
            for z in [0.25, 0.05, 0.015] {
                let origin = Point3::new(corner.0 + dx, corner.1 + dy, z);
                for g in horizontals {
                    dirs.clear();
                    dirs.extend((0..40).map(|r| {
                        let e = (-70.0 + 1.9 * r as f64).to_radians();
                        [e.cos() * g[0], e.cos() * g[1], e.sin()]
                    }));
                    hf.cast_column(origin, &dirs, 4.0, &mut hits);
                    for (u, got) in dirs.iter().zip(&hits) {
                        let want = hf.cast_unit(origin, *u, 4.0);
                        assert!(same(got, &want), "{origin:?} {u:?}: {got:?} vs {want:?}");
                        rays += 1;
                    }
                }
            }
        }
    }
    assert_eq!(rays, 3 * 5 * 3 * 7 * 40);
}

/// Point clouds of `spec` over `world` from `pose` with noise: by columns and ray by ray.
fn both_scans(
    spec: &SensorSpec,
    world: &World,
    pose: Pose2,
    seed: u64,
) -> (PointCloud, PointCloud) {
    let hf = Heightfield::from_world(world).unwrap();
    let s = RangeSensor::new(spec, "s").unwrap();
    let z = hf.elevation_at(pose.position()).unwrap();
    let noise = ScanNoise {
        depth_sigma: 0.01,
        depth_k: 0.001,
        color_sigma: 4.0,
    };
    let o = s.origin(pose, z);
    let args = (
        &hf,
        world.color.as_slice(),
        o,
        pose.yaw,
        &noise,
        1.5,
        seed,
        7,
    );
    (
        s.scan(
            args.0, args.1, args.2, args.3, args.4, args.5, args.6, args.7,
        ),
        s.scan_ray_by_ray(
            args.0, args.1, args.2, args.3, args.4, args.5, args.6, args.7,
        ),
    )
}

/// Bit-for-bit equality of two clouds.
fn assert_same_cloud(a: &PointCloud, b: &PointCloud) {
    assert_eq!((a.stamp, a.origin, a.sensor), (b.stamp, b.origin, b.sensor));
    assert_eq!(a.points.len(), b.points.len());
    for (p, q) in a.points.iter().zip(&b.points) {
        let bits = |p: &strider_core::ColoredPoint| [p.x, p.y, p.z].map(f32::to_bits);
        assert_eq!((bits(p), p.rgb), (bits(q), q.rgb));
    }
}

/// A whole omnidirectional scan with noise is the same cloud as casting ray by ray, on any
/// number of threads (the noise is drawn per chunk of rays in ray order from the hits).
#[test]
fn column_scans_give_the_ray_by_ray_cloud() {
    let mut world = flat_world(150, 150, 0.1);
    let mut rng = ChaCha8Rng::seed_from_u64(8);
    for z in &mut world.elevation {
        *z = rng.random_range(0.0..0.005);
    }
    fill(&mut world, 90, 95, 20, 120, 1.0, WALL);
    fill(&mut world, 20, 30, 60, 66, 0.6, BOX);
    let specs = [
        omni_spec(720, 48, (-40.0, 10.0), 10.0, 0.0),
        omni_spec(360, 16, (-30.0, 15.0), 10.0, 90.0),
        // More rays than a chunk per row, and fewer.
        omni_spec(1500, 3, (-10.0, 0.0), 6.0, 0.0),
        omni_spec(7, 5, (-90.0, 90.0), 3.0, 0.0),
    ];
    for (k, spec) in specs.iter().enumerate() {
        for (pose, seed) in [
            (Pose2::new(7.0, 7.0, 0.1), 1),
            (Pose2::new(3.05, 6.2, -2.0), 2),
        ] {
            let run = |threads: usize| {
                rayon::ThreadPoolBuilder::new()
                    .num_threads(threads)
                    .build()
                    .unwrap()
                    .install(|| both_scans(spec, &world, pose, seed + k as u64))
            };
            let (columns, rays) = run(1);
            assert!(
                columns.points.len() > 10,
                "sensor {k}: {}",
                columns.points.len()
            );
            assert_same_cloud(&columns, &rays);
            let (columns3, _) = run(3);
            assert_same_cloud(&columns3, &rays);
        }
    }
}
