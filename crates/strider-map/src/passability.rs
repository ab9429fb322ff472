//! Passability from roughness (`001` Eq. 7–9, thesis C4 Eq. 5–6, `000` §IV-B) and
//! configuration-space inflation (decision 4).
//!
//! ρ(ν) = max over *known* 8-neighbours ν' of |elevation(ν) − elevation(ν')| (Eq. 7–8; unknown
//! neighbours are ignored, decision 4); π(ν) = 0 when ρ(ν) > ρ_obstacle, else 1 (Eq. 9). The
//! robot's centre may only occupy cells with no impassable cell within r_robot (`000`
//! δ_impassable).
//!
//! The dense-raster functions here are the single definition of the rule: the tiled map applies
//! the same [`roughness`] per cell, and ground-truth passability of a world is computed with
//! [`dense_passability`] on its elevation layer.
//!
//! [`ElevationMap::update_passability`] maintains both layers of the tiled map incrementally
//! (`001` Alg. 2 line 3, `recomputePassability`): π only for the cells whose elevation changed
//! since the last call and their 8-neighbours, admissibility only within r_robot of a cell whose
//! π changed. Both run the dense functions above on a small raster read from the tiles.

use crate::map::ElevationMap;
use crate::rect;
use serde::{Deserialize, Serialize};
use strider_core::CellRect;
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
/// Computed without building the disc: it is ⌊r/d⌋, the offset (⌊r/d⌋, 0) always being inside,
/// and 0 for the parameters [`disc_offsets`] rejects (its disc is then the centre alone). Called
/// per information-gain update with r_sensor, whose disc has thousands of cells.
pub(crate) fn disc_reach(r: f64, d: f64) -> u32 {
    if !(r.is_finite() && d.is_finite() && d > 0.0 && r >= 0.0) {
        return 0;
    }
    (r / d).floor() as u32
}

impl ElevationMap {
    /// Recomputes passability (Eq. 7–9) for the cells whose elevation changed since the last call
    /// and their 8-neighbours, then admissibility (decision 4) within r_robot of every cell whose
    /// passability changed. Returns the rectangle whose admissibility was recomputed (`None` when
    /// nothing changed).
    pub fn update_passability(&mut self) -> Option<CellRect> {
        let dirty = self.dirty.take()?;
        let d = self.params.cell_size;
        let p_rect = rect::expand(dirty, 1);
        let e_rect = rect::expand(p_rect, 1);
        let mut elev = Vec::new();
        let mut obs = Vec::new();
        self.elevation.read_rect(e_rect, &mut elev);
        self.observed.read_rect(e_rect, &mut obs);
        let pass = dense_passability(
            &elev,
            Some(&obs),
            e_rect.width as usize,
            e_rect.height as usize,
            self.params.rho_obstacle,
        );
        let new_p = rect::crop(&pass, e_rect, p_rect);
        let mut old_p = Vec::new();
        self.passability.read_rect(p_rect, &mut old_p);
        let mut changed: Option<CellRect> = None;
        for (k, (a, b)) in new_p.iter().zip(&old_p).enumerate() {
            if a != b {
                changed = Some(rect::include(changed, p_rect.cell(k)));
            }
        }
        let changed = changed?;
        self.passability.write_rect(p_rect, &new_p);

        let reach = disc_reach(self.params.r_robot, d);
        let a_rect = rect::expand(changed, reach);
        let q_rect = rect::expand(a_rect, reach);
        let mut pq = Vec::new();
        self.passability.read_rect(q_rect, &mut pq);
        let adm = dense_admissible(
            &pq,
            q_rect.width as usize,
            q_rect.height as usize,
            self.params.r_robot,
            d,
        );
        self.admissible
            .write_rect(a_rect, &rect::crop(&adm, q_rect, a_rect));
        Some(a_rect)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn disc_reach_is_the_largest_offset_of_the_disc() {
        for (r, d) in [
            (0.0, 0.05),
            (0.05, 0.05),
            (0.25, 0.05),
            (2.5, 0.05),
            (0.3, 0.1),
            (0.29, 0.1),
            (1.0, 0.3),
            (-1.0, 0.1),
            (f64::NAN, 0.1),
            (0.5, 0.0),
        ] {
            let want = disc_offsets(r, d)
                .iter()
                .map(|&(di, dj)| di.unsigned_abs().max(dj.unsigned_abs()))
                .max()
                .unwrap_or(0);
            assert_eq!(disc_reach(r, d), want, "r {r} d {d}");
        }
    }

    #[test]
    fn hand_made_step() {
        // 5×3 raster with a 0.3 m step between columns 1 and 2.
        let e = [0.0f32, 0.0, 0.3, 0.3, 0.3].repeat(3);
        let p = dense_passability(&e, None, 5, 3, 0.25);
        let row: Vec<_> = p[5..10].to_vec();
        use Passability::*;
        assert_eq!(
            row,
            vec![Passable, Impassable, Impassable, Passable, Passable]
        );
        // Threshold is strict: a step equal to ρ_obstacle is passable.
        let p = dense_passability(&e, None, 5, 3, 0.3);
        assert!(p.iter().all(|&c| c == Passable));
    }

    #[test]
    fn unknown_neighbours_are_ignored() {
        let e = [0.0f32, 5.0, 0.0];
        let known = [true, false, true];
        let p = dense_passability(&e, Some(&known), 3, 1, 0.25);
        assert_eq!(p, vec![Passability::Unknown; 3]);
        let e = [0.0f32, 0.1, 5.0, 0.1];
        let known = [true, true, false, true];
        let p = dense_passability(&e, Some(&known), 4, 1, 0.25);
        assert_eq!(p[0], Passability::Passable);
        assert_eq!(p[2], Passability::Unknown);
        assert_eq!(p[3], Passability::Unknown);
    }

    #[test]
    fn inflation_blocks_disc() {
        let mut pass = vec![Passability::Passable; 11 * 11];
        pass[5 * 11 + 5] = Passability::Impassable;
        let adm = dense_admissible(&pass, 11, 11, 0.2, 0.1);
        let blocked = adm.iter().filter(|&&a| !a).count();
        assert_eq!(blocked, disc_offsets(0.2, 0.1).len());
        assert!(adm[5 * 11 + 8]);
        assert!(!adm[5 * 11 + 7]);
    }

    fn stepped_world() -> (Vec<f32>, Vec<bool>, CellRect) {
        // 24 × 16 cells starting at (-10, -7): terraces, a box and a few unknown cells.
        let r = CellRect::new(strider_core::Cell::new(-10, -7), 24, 16);
        let mut e = vec![0.0f32; r.len()];
        let mut known = vec![true; r.len()];
        for (k, c) in r.cells().enumerate() {
            e[k] = if c.i >= 4 { 0.2 } else { 0.0 } + if c.j >= 3 { 0.1 } else { 0.0 };
            if (-3..=-1).contains(&c.i) && (-2..=0).contains(&c.j) {
                e[k] = 0.6;
            }
            if c.i == 8 && c.j < -4 {
                known[k] = false;
            }
        }
        (e, known, r)
    }

    #[test]
    fn tiled_map_matches_dense_rule() {
        use strider_core::Rgb8;
        let (e, known, r) = stepped_world();
        let params = crate::MapParams {
            cell_size: 0.1,
            tile_size: 5,
            rho_obstacle: 0.15,
            r_robot: 0.2,
            ..Default::default()
        };
        let mut m = ElevationMap::new(params.clone());
        // Insert in two batches to exercise the incremental path.
        for (k, c) in r.cells().enumerate() {
            if known[k] && c.j < 0 {
                m.set_cell(c, e[k], 1e-4, Rgb8::default());
            }
        }
        m.update_passability();
        for (k, c) in r.cells().enumerate() {
            if known[k] && c.j >= 0 {
                m.set_cell(c, e[k], 1e-4, Rgb8::default());
            }
        }
        m.update_passability();
        let (w, h) = (r.width as usize, r.height as usize);
        let dense = dense_passability(&e, Some(&known), w, h, params.rho_obstacle);
        assert_eq!(m.passability_raster(r), dense);
        let adm = dense_admissible(&dense, w, h, params.r_robot, params.cell_size);
        assert_eq!(m.admissible_raster(r), adm);
        assert!(dense.contains(&Passability::Impassable));
        assert!(adm.iter().any(|&a| a));
        // Raising one cell to a pillar updates its neighbourhood incrementally.
        let pillar = strider_core::Cell::new(-8, -5);
        m.set_cell(pillar, 1.0, 1e-4, Rgb8::default());
        let a = m.update_passability().unwrap();
        assert!(a.contains(pillar));
        assert_eq!(m.passability(pillar), Passability::Impassable);
        // Impassable: the pillar and its 8-neighbours; r_robot = 2 cells beyond them.
        assert!(!m.is_admissible(pillar.offset(0, 3)));
        assert!(m.is_admissible(pillar.offset(0, 4)));
        assert_eq!(m.update_passability(), None, "nothing dirty");
    }
}
