//! Erosion and dilation of terrain-class maps (Prágr22 appendix Eq. 25–26, Alg. 7 line 9 and
//! Alg. 10 line 2; decision 18).
//!
//! A class map is a dense row-major [`Raster`] of [`TerrainCell`] over a `CellRect`; the
//! `_in_place` forms work on a row-major slice and visit only a given support (the described
//! cells), so that their cost follows the described cells rather than the map. Three states
//! keep "never described" apart from "eroded":
//!
//! * [`TerrainCell::Unknown`] — the cell has no descriptor (Alg. 7 assigns classes only to
//!   described cells). Neither operation ever changes it.
//! * [`TerrainCell::Eroded`] — the eroded non-class ∅ of Eq. 25: described, but too close to a
//!   class boundary.
//! * [`TerrainCell::Class`] — an IGNG terrain class.
//!
//! **Erosion** (Eq. 25), repeated n_erode^steps times: a class cell keeps its class only when all
//! of its 8 neighbours (δnb, the 8-neighbourhood of decision 18) carry the *same* class; otherwise
//! it becomes ∅. Decisions where the paper is silent: an eroded neighbour and an unknown neighbour
//! both count as different (the paper erodes "cells that border different (or already eroded)
//! terrain", and an undescribed neighbour is exactly such an unreliable border), and a neighbour
//! outside the raster counts as unknown — so pass a rectangle that covers the described cells
//! with at least a one-cell margin if the raster edge is not a real border.
//!
//! **Dilation** (Eq. 26), repeated n_dilate^steps times: an *eroded* cell (and only an eroded cell,
//! decision 18; class and unknown cells are never overwritten) takes the most common class among
//! the cells of the (2·n_size + 1)² window centred on it (δnb repeated n_size times = the
//! Chebyshev ball); eroded and unknown cells in the window do not vote, cells outside the raster do
//! not exist. Ties go to the lowest [`ClassId`]; with no voting cell the cell stays ∅. Each step
//! reads the previous step's map only (synchronous update), so the result does not depend on
//! the scan order.
//!
//! Table 3 defaults: n_erode^steps = 2, n_dilate^steps = 3, n_dilate^size = 2.

use strider_core::grid::NEIGHBOURS8;
use strider_map::descriptors::Raster;
use thiserror::Error;

use crate::igng::ClassId;

mod near;

pub use near::{dilate_near, erode_near};

/// A class-map cell: no descriptor, eroded, or a class.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum TerrainCell {
    /// No descriptor (never classified); left alone by erosion and dilation.
    #[default]
    Unknown,
    /// The eroded non-class ∅ of Eq. 25.
    Eroded,
    /// A terrain class.
    Class(ClassId),
}

impl TerrainCell {
    /// The class, if any.
    pub fn class(self) -> Option<ClassId> {
        match self {
            TerrainCell::Class(c) => Some(c),
            _ => None,
        }
    }
}

/// Errors of the morphology operations.
#[derive(Clone, Debug, Error, PartialEq, Eq)]
pub enum MorphologyError {
    /// The raster's value count does not match its rectangle.
    #[error("raster has {got} values but its rectangle holds {expected} cells")]
    ShapeMismatch {
        /// Cells in the rectangle.
        expected: usize,
        /// Values present.
        got: usize,
    },
}

fn check(raster: &Raster<TerrainCell>) -> Result<(), MorphologyError> {
    let expected = raster.rect.len();
    if raster.values.len() == expected {
        Ok(())
    } else {
        Err(MorphologyError::ShapeMismatch {
            expected,
            got: raster.values.len(),
        })
    }
}

/// A class map from per-cell optional classes (e.g. Alg. 7 line 8's output): `None` → Unknown.
pub fn from_classes(
    rect: strider_core::grid::CellRect,
    classes: &[Option<ClassId>],
) -> Result<Raster<TerrainCell>, MorphologyError> {
    let raster = Raster {
        rect,
        values: classes
            .iter()
            .map(|c| c.map_or(TerrainCell::Unknown, TerrainCell::Class))
            .collect(),
    };
    check(&raster)?;
    Ok(raster)
}

/// `steps` erosion steps of Eq. 25 (see the module documentation for the neighbour rules).
pub fn erode(
    raster: &Raster<TerrainCell>,
    steps: usize,
) -> Result<Raster<TerrainCell>, MorphologyError> {
    check(raster)?;
    let mut out = raster.clone();
    let support = known_cells(&out.values);
    let w = out.rect.width as usize;
    erode_in_place(&mut out.values, w, &support, steps);
    Ok(out)
}

/// `n_steps` dilation steps of Eq. 26 with a (2·`n_size` + 1)² window.
pub fn dilate(
    raster: &Raster<TerrainCell>,
    n_size: usize,
    n_steps: usize,
) -> Result<Raster<TerrainCell>, MorphologyError> {
    check(raster)?;
    let mut out = raster.clone();
    let support = known_cells(&out.values);
    let w = out.rect.width as usize;
    dilate_in_place(&mut out.values, w, &support, n_size, n_steps);
    Ok(out)
}

/// [`erode`] in place on a row-major class map of width `w`, visiting only the cells listed in
/// `support`: every cell that is not [`TerrainCell::Unknown`] must be listed (the others can
/// be, and stay unknown). The work is proportional to the support, not to the map, which is
/// what a sparse map (a building seen by a laser) needs.
pub fn erode_in_place(values: &mut [TerrainCell], w: usize, support: &[u32], steps: usize) {
    synchronous_steps(values, w, support, steps, 1, erode_rule);
}

/// One erosion step at (x, y) of a `w` × `h` map: a class cell with a neighbour of another
/// value (or off the map) becomes eroded.
fn erode_rule(cur: &[TerrainCell], w: usize, h: usize, x: usize, y: usize) -> Option<TerrainCell> {
    let TerrainCell::Class(c) = cur[y * w + x] else {
        return None;
    };
    let keep = NEIGHBOURS8.iter().all(|&(di, dj)| {
        let (nx, ny) = (x as i64 + di as i64, y as i64 + dj as i64);
        nx >= 0
            && ny >= 0
            && (nx as usize) < w
            && (ny as usize) < h
            && cur[ny as usize * w + nx as usize] == TerrainCell::Class(c)
    });
    (!keep).then_some(TerrainCell::Eroded)
}

/// The value of cell (x, y) of a `w` × `h` map after `steps` erosion steps, read off the map
/// directly: a class cell keeps its class only when every cell within `steps` of it (in x and
/// in y) lies on the map and has that class; other cells never change. (One step asks this of
/// the 8-neighbourhood; if the squares of radius s − 1 around a cell and its 8 neighbours are
/// all one class, so is the square of radius s around it.)
fn eroded_at(
    values: &[TerrainCell],
    w: usize,
    h: usize,
    x: usize,
    y: usize,
    steps: usize,
) -> TerrainCell {
    let v = values[y * w + x];
    if !matches!(v, TerrainCell::Class(_)) {
        return v;
    }
    let inside = x >= steps && y >= steps && x + steps < w && y + steps < h;
    let uniform = inside
        && (y - steps..=y + steps).all(|ny| {
            values[ny * w + x - steps..=ny * w + x + steps]
                .iter()
                .all(|&u| u == v)
        });
    if uniform { v } else { TerrainCell::Eroded }
}

/// [`dilate`] in place, visiting only `support` (as for [`erode_in_place`]).
pub fn dilate_in_place(
    values: &mut [TerrainCell],
    w: usize,
    support: &[u32],
    n_size: usize,
    n_steps: usize,
) {
    synchronous_steps(values, w, support, n_steps, n_size, dilate_rule(n_size));
}

/// One dilation step at (x, y): an eroded cell takes the class most frequent in its
/// (2·n_size + 1)² window (ties to the lowest id). `votes` is kept between cells.
fn dilate_rule(
    n_size: usize,
) -> impl FnMut(&[TerrainCell], usize, usize, usize, usize) -> Option<TerrainCell> {
    let mut votes: Vec<(ClassId, u32)> = Vec::new();
    move |cur, w, h, x, y| {
        if cur[y * w + x] != TerrainCell::Eroded {
            return None;
        }
        votes.clear();
        let (x0, x1) = (x.saturating_sub(n_size), (x + n_size).min(w - 1));
        let (y0, y1) = (y.saturating_sub(n_size), (y + n_size).min(h - 1));
        for wy in y0..=y1 {
            for wx in x0..=x1 {
                if let TerrainCell::Class(c) = cur[wy * w + wx] {
                    match votes.iter_mut().find(|(vc, _)| *vc == c) {
                        Some((_, n)) => *n += 1,
                        None => votes.push((c, 1)),
                    }
                }
            }
        }
        votes
            .iter()
            .copied()
            .max_by(|a, b| a.1.cmp(&b.1).then(b.0.cmp(&a.0)))
            .map(|(c, _)| TerrainCell::Class(c))
    }
}

/// Row-major indices of the cells that are not unknown.
fn known_cells(values: &[TerrainCell]) -> Vec<u32> {
    (0..values.len() as u32)
        .filter(|&k| values[k as usize] != TerrainCell::Unknown)
        .collect()
}

/// Up to `steps` synchronous passes over the `support` cells of a map of width `w`:
/// `rule(map, width, height, x, y)` gives the new value of cell (x, y) from the previous pass's
/// map only, or `None` to keep it (it returns `Some` only for a real change). Each pass
/// collects its changes before writing them; stops early after a pass that changed nothing.
///
/// `rule` reads no farther than `reach` cells (in x and in y) from its cell. So a cell whose
/// neighbourhood did not change in a pass gives the same answer in the next one, and the
/// passes after the first visit only the cells within `reach` of the last pass's changes (a
/// cell off the support is unknown, and the rules keep unknown cells).
fn synchronous_steps(
    values: &mut [TerrainCell],
    w: usize,
    support: &[u32],
    steps: usize,
    reach: usize,
    mut rule: impl FnMut(&[TerrainCell], usize, usize, usize, usize) -> Option<TerrainCell>,
) {
    if w == 0 {
        return;
    }
    let h = values.len() / w;
    let mut changes: Vec<(usize, TerrainCell)> = Vec::new();
    let mut visit: Vec<u32> = Vec::new();
    let mut near_changes = false;
    let span = (2 * reach + 1) * (2 * reach + 1);
    for step in 0..steps {
        changes.clear();
        let cells = if near_changes { &visit[..] } else { support };
        for &k in cells {
            let k = k as usize;
            if k >= values.len() {
                continue;
            }
            if let Some(v) = rule(values, w, h, k % w, k / w) {
                changes.push((k, v));
            }
        }
        if changes.is_empty() {
            break;
        }
        for &(k, v) in &changes {
            values[k] = v;
        }
        // Listing the cells near many changes costs more than visiting the whole support.
        near_changes = step + 1 < steps && changes.len().saturating_mul(span) < support.len();
        if near_changes {
            next_visit(&changes, w, h, reach, &mut visit);
        }
    }
}

/// The cells within `reach` (in x and in y) of the changed cells, ascending, each once.
fn next_visit(
    changes: &[(usize, TerrainCell)],
    w: usize,
    h: usize,
    reach: usize,
    out: &mut Vec<u32>,
) {
    out.clear();
    for &(k, _) in changes {
        let (x, y) = (k % w, k / w);
        let (x0, x1) = (x.saturating_sub(reach), (x + reach).min(w - 1));
        for ny in y.saturating_sub(reach)..=(y + reach).min(h - 1) {
            out.extend((x0..=x1).map(|nx| (ny * w + nx) as u32));
        }
    }
    out.sort_unstable();
    out.dedup();
}

#[cfg(test)]
mod tests {
    use super::*;
    use strider_core::grid::{Cell, CellRect};

    #[test]
    fn tie_goes_to_lowest_id() {
        // Row: [C5, ∅, C2]: one vote each.
        let r = Raster {
            rect: CellRect::new(Cell::new(0, 0), 3, 1),
            values: vec![
                TerrainCell::Class(ClassId(5)),
                TerrainCell::Eroded,
                TerrainCell::Class(ClassId(2)),
            ],
        };
        let d = dilate(&r, 1, 1).unwrap();
        assert_eq!(d.values[1], TerrainCell::Class(ClassId(2)));
    }

    #[test]
    fn empty_raster_is_fine() {
        let r = Raster {
            rect: CellRect::new(Cell::new(0, 0), 0, 0),
            values: vec![],
        };
        assert!(erode(&r, 2).unwrap().values.is_empty());
        assert!(dilate(&r, 2, 3).unwrap().values.is_empty());
    }

    /// Every pass over the whole support, as the rules are defined.
    fn full_passes(
        values: &mut [TerrainCell],
        w: usize,
        steps: usize,
        mut rule: impl FnMut(&[TerrainCell], usize, usize, usize, usize) -> Option<TerrainCell>,
    ) {
        let h = values.len() / w;
        for _ in 0..steps {
            let changes: Vec<(usize, TerrainCell)> = (0..values.len())
                .filter_map(|k| rule(values, w, h, k % w, k / w).map(|v| (k, v)))
                .collect();
            for (k, v) in changes {
                values[k] = v;
            }
        }
    }

    fn cell_of(code: u8) -> TerrainCell {
        match code {
            0 => TerrainCell::Unknown,
            1 => TerrainCell::Eroded,
            c => TerrainCell::Class(ClassId(u32::from(c - 2))),
        }
    }

    proptest::proptest! {
        /// Passes that visit only the cells near the last pass's changes give the maps of full
        /// passes.
        #[test]
        fn passes_near_changes_equal_full_passes(
            w in 1usize..14,
            codes in proptest::collection::vec(0u8..6, 1..180),
            steps in 0usize..5,
            n_size in 1usize..4,
        ) {
            let values: Vec<TerrainCell> = codes[..codes.len() / w * w]
                .iter()
                .map(|&c| cell_of(c))
                .collect();
            proptest::prop_assume!(!values.is_empty());
            let support = known_cells(&values);
            let mut fast = values.clone();
            erode_in_place(&mut fast, w, &support, steps);
            let mut slow = values.clone();
            full_passes(&mut slow, w, steps, erode_rule);
            proptest::prop_assert_eq!(&fast, &slow);
            let h = values.len() / w;
            let direct: Vec<TerrainCell> =
                (0..values.len()).map(|k| eroded_at(&values, w, h, k % w, k / w, steps)).collect();
            proptest::prop_assert_eq!(&direct, &slow);
            let support = known_cells(&fast);
            dilate_in_place(&mut fast, w, &support, n_size, steps);
            full_passes(&mut slow, w, steps, dilate_rule(n_size));
            proptest::prop_assert_eq!(fast, slow);
        }
    }
}
