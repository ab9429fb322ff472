//! Fusion throughput on one thread and on every core: random clouds of 10⁶ returns over a
//! 6 × 5 m area.
//!
//! `cargo run --release -p strider-map --example fusion_speed`

use std::time::Instant;
use strider_core::{ColoredPoint, Point3, PointCloud};
use strider_map::{ElevationMap, MapParams};

/// SplitMix64: a tiny deterministic generator, enough for synthetic clouds.
struct Rng(u64);

impl Rng {
    fn next_f32(&mut self) -> f32 {
        self.0 = self.0.wrapping_add(0x9e37_79b9_7f4a_7c15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        ((z ^ (z >> 31)) >> 40) as f32 / (1u64 << 24) as f32
    }
}

fn cloud(rng: &mut Rng, n: usize) -> PointCloud {
    let points = (0..n)
        .map(|_| {
            let x = rng.next_f32() * 6.0;
            let y = rng.next_f32() * 5.0;
            let ground = if (2.0..2.5).contains(&x) {
                0.4
            } else {
                0.05 * x
            };
            ColoredPoint {
                x,
                y,
                z: ground + (rng.next_f32() - 0.5) * 0.01,
                rgb: [(x * 40.0) as u8, (y * 50.0) as u8, 90],
            }
        })
        .collect();
    PointCloud {
        stamp: 0.0,
        sensor: 0,
        origin: Point3::new(3.0, 2.5, 1.0),
        points,
    }
}

/// CPU time of this process (user + system) from `/proc/self/stat`, seconds; `None` off Linux.
/// The machine may be shared, so CPU time is the honest single-core figure.
fn cpu_time() -> Option<f64> {
    let stat = std::fs::read_to_string("/proc/self/stat").ok()?;
    let rest = stat.rsplit_once(')')?.1;
    let f: Vec<&str> = rest.split_whitespace().collect();
    let ticks: f64 = f.get(11)?.parse::<f64>().ok()? + f.get(12)?.parse::<f64>().ok()?;
    Some(ticks / 100.0) // USER_HZ
}

fn main() {
    let clouds: Vec<PointCloud> = {
        let mut rng = Rng(7);
        (0..4).map(|_| cloud(&mut rng, POINTS)).collect()
    };
    // Fusion splits a scan's per-return passes over the pool's threads: one thread first,
    // then every core.
    for threads in [1, 0] {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .expect("a thread pool");
        pool.install(|| run(&clouds));
    }
}

const POINTS: usize = 1_000_000;
const SCANS: usize = 20;

fn run(clouds: &[PointCloud]) {
    let mut map = ElevationMap::new(MapParams::default());
    // Warm-up: allocates the tiles and the scratch rasters.
    for c in &clouds[..2] {
        map.fuse(c);
    }
    let threads = rayon::current_num_threads();
    let t = Instant::now();
    let c0 = cpu_time();
    let mut total = 0;
    for k in 0..SCANS {
        let s = map.fuse(&clouds[k % clouds.len()]);
        total += s.fused_points + s.face_points;
    }
    let dt = t.elapsed().as_secs_f64();
    println!(
        "fuse on {threads} thread(s): {SCANS} scans × {POINTS} points in {dt:.3} s wall → {:.1} M points/s",
        total as f64 / dt / 1e6
    );
    if let (Some(a), Some(b)) = (c0, cpu_time()) {
        println!(
            "      {:.3} s CPU → {:.1} M points/s per CPU-second",
            b - a,
            total as f64 / (b - a) / 1e6
        );
    }
    let t = Instant::now();
    for k in 0..SCANS {
        map.integrate(&clouds[k % clouds.len()]);
    }
    let dt = t.elapsed().as_secs_f64();
    println!(
        "fuse + passability update: {:.1} M points/s; map: {} observed cells, {} tiles",
        (SCANS * POINTS) as f64 / dt / 1e6,
        map.observed_count(),
        map.elevation_layer().tile_count()
    );
}
