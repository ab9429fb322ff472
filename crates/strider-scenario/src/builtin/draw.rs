//! Random draws the generators share. Every generator draws from one ChaCha8 stream seeded with
//! the world seed, so the order of the draws is part of each world's definition.

use rand::{RngExt, rngs::ChaCha8Rng};

/// Uniform sample in `[lo, hi)` (`lo` when the interval is empty).
pub(crate) fn uni(rng: &mut ChaCha8Rng, lo: f64, hi: f64) -> f64 {
    if hi > lo {
        rng.random_range(lo..hi)
    } else {
        lo
    }
}

/// The wobble of a blob outline (see [`super::canvas::Canvas::blob`]): harmonics 2 and 3 with
/// amplitudes drawn up to `amplitude` and random phases.
pub(crate) fn wobble(rng: &mut ChaCha8Rng, amplitude: [f64; 2]) -> [(f64, f64, f64); 2] {
    use std::f64::consts::TAU;
    [
        (2.0, uni(rng, 0.0, amplitude[0]), uni(rng, 0.0, TAU)),
        (3.0, uni(rng, 0.0, amplitude[1]), uni(rng, 0.0, TAU)),
    ]
}

/// Wooden blocks of 10 × 10 cm (2 × 2 cells at 5 cm): one random height level in `0..=16` per
/// block, drawn row by row over the whole canvas.
pub(crate) struct BlockLevels {
    /// Blocks per row.
    pub width: usize,
    /// Block rows.
    pub height: usize,
    levels: Vec<u32>,
}

/// The highest level of [`BlockLevels`].
pub(crate) const TOP_LEVEL: u32 = 16;

impl BlockLevels {
    /// Levels for a canvas of `cells_w × cells_h` cells.
    pub fn draw(rng: &mut ChaCha8Rng, cells_w: usize, cells_h: usize) -> Self {
        let (width, height) = (cells_w.div_ceil(2), cells_h.div_ceil(2));
        let levels = (0..width * height)
            .map(|_| rng.random_range(0..=TOP_LEVEL))
            .collect();
        Self {
            width,
            height,
            levels,
        }
    }

    /// The block of cell (`i`, `j`).
    pub fn block_of(i: usize, j: usize) -> (usize, usize) {
        (i / 2, j / 2)
    }

    /// Level of block (`bi`, `bj`).
    pub fn level(&self, bi: usize, bj: usize) -> u32 {
        self.levels[bj * self.width + bi]
    }
}
