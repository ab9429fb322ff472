//! Passability from roughness (Prágr22 Eq. 7–9, Prágr23 Eq. 5–6, Prágr19 §IV-B) and
//! configuration-space inflation (decision 4).
//!
//! ρ(ν) = max over *known* 8-neighbours ν' of |elevation(ν) − elevation(ν')| (Eq. 7–8; unknown
//! neighbours are ignored, decision 4); π(ν) = 0 when ρ(ν) > ρ_obstacle, else 1 (Eq. 9). The
//! robot's centre may only occupy cells with no impassable cell within r_robot (Prágr19
//! δ_impassable).
//!
//! The dense-raster functions here are the single definition of the rule: the tiled map applies
//! the same [`roughness`] per cell, and ground-truth passability of a world is computed with
//! [`dense_passability`] on its elevation layer.
//!
//! [`ElevationMap::update_passability`] maintains both layers of the tiled map incrementally
//! (Prágr22 Alg. 2 line 3, `recomputePassability`): π only for the cells whose elevation changed
//! since the last call and their 8-neighbours, admissibility only within r_robot of a cell whose
//! π changed. Both run the dense functions above on a small raster read from the tiles.

pub(crate) mod rule;

pub(crate) use rule::disc_reach;
pub use rule::{Passability, classify, dense_admissible, dense_passability, roughness};

use crate::map::ElevationMap;
use crate::rect;
use strider_core::CellRect;

impl ElevationMap {
    /// Recomputes passability (Eq. 7–9) for the cells whose elevation changed since the last call
    /// and their 8-neighbours, then admissibility (decision 4) within r_robot of every cell whose
    /// passability changed. Returns the bounding rectangle of the cells whose admissibility was
    /// recomputed (`None` when nothing changed).
    ///
    /// The work follows the changed blocks of the map's [`ChangeLog`](crate::changes::ChangeLog),
    /// not their bounding rectangle: a long-range scan changes cells tens of metres apart, and
    /// the rectangle between them would be mostly unchanged map. Every cell's passability and
    /// admissibility depend on its neighbourhood only, so each block is done on its own; all
    /// passability first, so that admissibility reads the new passability everywhere.
    pub fn update_passability(&mut self) -> Option<CellRect> {
        self.dirty.take()?;
        self.admissible_changes.begin();
        let blocks = dense_or_sparse(self.changes.changed_since(self.passability_revision));
        self.passability_revision = self.changes.revision();
        let changed: Vec<CellRect> = blocks
            .into_iter()
            .filter_map(|b| self.recompute_passability(b))
            .collect();
        changed
            .into_iter()
            .map(|c| self.recompute_admissibility(c))
            .reduce(rect::union)
    }

    /// π for the cells of `dirty` and their 8-neighbours; the bounding rectangle of the cells
    /// whose π changed.
    fn recompute_passability(&mut self, dirty: CellRect) -> Option<CellRect> {
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
        Some(changed)
    }

    /// Admissibility within r_robot of the cells of `changed`; the rectangle recomputed.
    fn recompute_admissibility(&mut self, changed: CellRect) -> CellRect {
        let d = self.params.cell_size;
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
        self.admissible_changes.mark_rect(a_rect);
        a_rect
    }
}

/// The changed blocks as they are best recomputed: one rectangle around them all when they fill
/// at least half of it (a dense scan, where one pass beats many small ones), else each run.
fn dense_or_sparse(blocks: Vec<CellRect>) -> Vec<CellRect> {
    let Some(all) = blocks.iter().copied().reduce(rect::union) else {
        return blocks;
    };
    let area: usize = blocks.iter().map(CellRect::len).sum();
    if all.len() <= 2 * area {
        vec![all]
    } else {
        blocks
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use strider_core::grid::disc_offsets;

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

    proptest::proptest! {
        #![proptest_config(proptest::prelude::ProptestConfig::with_cases(32))]

        /// However the cells arrive (many batches, spread over many change blocks), the
        /// incrementally kept layers equal the dense rule over the whole map.
        #[test]
        fn incremental_layers_equal_the_dense_rule(
            batches in proptest::collection::vec(
                proptest::collection::vec((-40i32..40, -30i32..30, 0usize..4), 1..80),
                1..6,
            )
        ) {
            use strider_core::{Cell, Rgb8};
            let params = crate::MapParams {
                cell_size: 0.1,
                rho_obstacle: 0.15,
                r_robot: 0.2,
                ..Default::default()
            };
            let mut m = ElevationMap::new(params.clone());
            let heights = [0.0f32, 0.1, 0.3, 0.8];
            for batch in batches {
                for (i, j, h) in batch {
                    for dj in 0..2 {
                        for di in 0..3 {
                            m.set_cell(Cell::new(i + di, j + dj), heights[h], 1e-4, Rgb8::default());
                        }
                    }
                }
                m.update_passability();
            }
            let known_rect = m.known_bounds().expect("cells were written");
            let r = rect::expand(known_rect, 4);
            let (w, h) = (r.width as usize, r.height as usize);
            let e = m.elevation_raster(r);
            let known: Vec<bool> = r.cells().map(|c| m.is_observed(c)).collect();
            let dense = dense_passability(&e, Some(&known), w, h, params.rho_obstacle);
            proptest::prop_assert_eq!(m.passability_raster(r), dense.clone());
            let adm = dense_admissible(&dense, w, h, params.r_robot, params.cell_size);
            proptest::prop_assert_eq!(m.admissible_raster(r), adm);
        }
    }
}
