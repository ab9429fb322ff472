//! The passability rule on dense rasters (Prágr22 Eq. 7–9) and configuration-space
//! admissibility (decision 4): the single definition that the tiled map and ground truth both
//! apply.

use serde::{Deserialize, Serialize};
use strider_core::grid::{NEIGHBOURS8, disc_offsets};

/// Passability of a cell.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[repr(u8)]
pub enum Passability {
    /// Not observed (or no known neighbour to judge the step against).
    #[default]
    Unknown = 0,
    /// π(ν) = 1.
    Passable = 1,
    /// π(ν) = 0.
    Impassable = 2,
}

/// Roughness ρ(ν) (Eq. 7) of a cell with elevation `z` given its neighbours' elevations
/// (`None` = unknown). Returns `None` when no neighbour is known.
#[inline]
pub fn roughness(z: f32, neighbours: impl IntoIterator<Item = Option<f32>>) -> Option<f32> {
    let mut rho: Option<f32> = None;
    for n in neighbours.into_iter().flatten() {
        let step = (z - n).abs(); // Eq. 8
        rho = Some(rho.map_or(step, |r: f32| r.max(step)));
    }
    rho
}

/// π(ν) from ρ(ν) (Eq. 9).
#[inline]
pub fn classify(rho: Option<f32>, rho_obstacle: f64) -> Passability {
    match rho {
        None => Passability::Unknown,
        Some(r) if r > rho_obstacle as f32 => Passability::Impassable,
        Some(_) => Passability::Passable,
    }
}

/// Passability of every cell of a dense row-major raster (`width × height`). `known[k] == false`
/// marks unobserved cells (all known when `None`); cells outside the raster are unknown.
/// A known cell whose neighbours are all unknown stays [`Passability::Unknown`]: no step can be
/// measured.
pub fn dense_passability(
    elevation: &[f32],
    known: Option<&[bool]>,
    width: usize,
    height: usize,
    rho_obstacle: f64,
) -> Vec<Passability> {
    assert_eq!(elevation.len(), width * height, "elevation raster size");
    let is_known = |k: usize| known.is_none_or(|m| m[k]) && elevation[k].is_finite();
    let mut out = vec![Passability::Unknown; width * height];
    for y in 0..height {
        for x in 0..width {
            let k = y * width + x;
            if !is_known(k) {
                continue;
            }
            let nb = NEIGHBOURS8.iter().map(|&(di, dj)| {
                let (nx, ny) = (x as i64 + di as i64, y as i64 + dj as i64);
                if nx < 0 || ny < 0 || nx >= width as i64 || ny >= height as i64 {
                    return None;
                }
                let nk = ny as usize * width + nx as usize;
                is_known(nk).then(|| elevation[nk])
            });
            out[k] = classify(roughness(elevation[k], nb), rho_obstacle);
        }
    }
    out
}

/// Configuration-space admissibility of a dense raster: a cell is admissible when it is passable
/// and no impassable cell lies within `r_robot` (cell size `d`). Unknown cells are not admissible
/// and do not block.
pub fn dense_admissible(
    pass: &[Passability],
    width: usize,
    height: usize,
    r_robot: f64,
    d: f64,
) -> Vec<bool> {
    assert_eq!(pass.len(), width * height, "passability raster size");
    let disc = disc_offsets(r_robot, d);
    let mut blocked = vec![false; width * height];
    for y in 0..height {
        for x in 0..width {
            if pass[y * width + x] != Passability::Impassable {
                continue;
            }
            for &(di, dj) in &disc {
                let (nx, ny) = (x as i64 + di as i64, y as i64 + dj as i64);
                if nx >= 0 && ny >= 0 && nx < width as i64 && ny < height as i64 {
                    blocked[ny as usize * width + nx as usize] = true;
                }
            }
        }
    }
    pass.iter()
        .zip(&blocked)
        .map(|(&p, &b)| p == Passability::Passable && !b)
        .collect()
}

/// Largest cell offset of the disc of radius `r` (cell size `d`), as used by [`disc_offsets`].
/// Computed without building the disc: it is ⌊r/d⌋ (capped like the disc), the offset
/// (⌊r/d⌋, 0) always being inside, and 0 for the parameters [`disc_offsets`] rejects (its disc
/// is then the centre alone). Called per information-gain update with r_sensor, whose disc has
/// thousands of cells.
pub(crate) fn disc_reach(r: f64, d: f64) -> u32 {
    if !(r.is_finite() && d.is_finite() && d > 0.0 && r >= 0.0) {
        return 0;
    }
    (r / d)
        .min(strider_core::grid::MAX_DISC_RADIUS_CELLS as f64)
        .floor() as u32
}
