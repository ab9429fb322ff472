//! Timing of the class maps' erosion and dilation redone near changed cells against the
//! whole-map operations, at Prágr22 Table 3's steps (erosion 2 steps, dilation 3 steps of size
//! 2), on a 2000 × 1500-cell map of six classes in irregular patches, after 300, 3000 and
//! 30 000 cells scattered over it changed class (a learning update reclassifies cells wherever
//! their descriptors sit between two prototypes, so its changes are scattered like this).
//!
//! `cargo run --release -p strider-learn --example morphology_near_speed`

use std::time::Instant;
use strider_learn::igng::ClassId;
use strider_learn::morphology::{
    TerrainCell, dilate_in_place, dilate_near, erode_in_place, erode_near,
};

const W: usize = 2000;
const H: usize = 1500;
const ERODE_STEPS: usize = 2;
const DILATE_SIZE: usize = 2;
const DILATE_STEPS: usize = 3;

/// A seeded linear congruential generator: the same map and changes on every run.
struct Lcg(u64);

impl Lcg {
    fn below(&mut self, n: usize) -> usize {
        self.0 = self
            .0
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        (self.0 >> 33) as usize % n
    }
}

/// Patches: each cell takes the class of its nearest of 400 random seeds.
fn patches(rng: &mut Lcg) -> Vec<TerrainCell> {
    let seeds: Vec<(i64, i64, u32)> = (0..400)
        .map(|_| {
            (
                rng.below(W) as i64,
                rng.below(H) as i64,
                rng.below(6) as u32,
            )
        })
        .collect();
    (0..W * H)
        .map(|k| {
            let (x, y) = ((k % W) as i64, (k / W) as i64);
            let nearest = seeds
                .iter()
                .min_by_key(|&&(sx, sy, _)| (sx - x).pow(2) + (sy - y).pow(2))
                .map_or(0, |s| s.2);
            TerrainCell::Class(ClassId(nearest))
        })
        .collect()
}

fn ms(t: Instant) -> f64 {
    t.elapsed().as_secs_f64() * 1e3
}

fn main() {
    let mut rng = Lcg(12345);
    let mut raw = patches(&mut rng);
    let support: Vec<u32> = (0..(W * H) as u32).collect();
    let mut eroded = raw.clone();
    erode_in_place(&mut eroded, W, &support, ERODE_STEPS);
    let mut dilated = eroded.clone();
    dilate_in_place(&mut dilated, W, &support, DILATE_SIZE, DILATE_STEPS);
    let mut scratch = Vec::new();
    println!("{W} x {H} cells; times in ms");
    println!(
        "| cells changed | erode_near | dilate_near | whole-map erosion | whole-map dilation |"
    );
    println!("|---|---|---|---|---|");
    for n in [300usize, 3000, 30_000] {
        let mut changed: Vec<u32> = (0..n).map(|_| rng.below(W * H) as u32).collect();
        changed.sort_unstable();
        changed.dedup();
        for &k in &changed {
            raw[k as usize] = TerrainCell::Class(ClassId(rng.below(6) as u32));
        }
        let t = Instant::now();
        let t_changed = erode_near(&raw, &mut eroded, W, &changed, ERODE_STEPS);
        let erode_ms = ms(t);
        let t = Instant::now();
        dilate_near(
            &eroded,
            &mut dilated,
            W,
            &t_changed,
            DILATE_SIZE,
            DILATE_STEPS,
            &mut scratch,
        );
        let dilate_ms = ms(t);
        let mut whole = raw.clone();
        let t = Instant::now();
        erode_in_place(&mut whole, W, &support, ERODE_STEPS);
        let whole_erode_ms = ms(t);
        assert_eq!(
            whole, eroded,
            "erode_near differs from the whole-map erosion"
        );
        let t = Instant::now();
        dilate_in_place(&mut whole, W, &support, DILATE_SIZE, DILATE_STEPS);
        let whole_dilate_ms = ms(t);
        assert_eq!(
            whole, dilated,
            "dilate_near differs from the whole-map dilation"
        );
        println!(
            "| {} | {erode_ms:.1} | {dilate_ms:.1} | {whole_erode_ms:.1} | {whole_dilate_ms:.1} |",
            changed.len()
        );
    }
}
