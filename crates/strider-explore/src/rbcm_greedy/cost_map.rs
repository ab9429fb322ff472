//! The traversal cost map Mcost of Prágr19 §IV-C (Eq. 11–12) and the cost-goal score (Eq. 15).
//!
//! Mcost has its own resolution (10 cm on `lab-track`, about one gait cycle's step). Each Mcost
//! cell ν′ is traversable when the elevation-map cell ν nearest its centre is admissible
//! (passable by step height and outside the δ_impassable inflation, decision 4) and reachable
//! from the robot; its mean and confidence are the committee's prediction at desc(ν), the 5-D
//! descriptor of Prágr19 Eq. 10 (decision 7). A traversable cell whose descriptor cannot be formed
//! yet (less than half of its δ_desc disc known) gets the prior: unknown terrain is uncertain.
//!
//! Only the newest expert of the committee ever changes (decision 15), so the predictions of the
//! frozen experts are cached per Mcost cell with the descriptor they were made for
//! ([`PredictionCache`]); a cycle predicts with the growing expert everywhere and with the frozen
//! ones only where a descriptor changed (the map near the robot) or an expert froze since. The
//! paper's planning time grew with the map (23.2 s at 910 cells); this keeps it flat.

use rayon::prelude::*;
use std::collections::HashMap;
use std::time::Instant;
use strider_core::{Cell, CellRect, Point2};
use strider_learn::gp::Prediction;
use strider_learn::rbcm::Rbcm;
use strider_map::ElevationMap;
use strider_map::descriptors::shape_lab_descriptors_at;
use strider_map::reachability::Reachability;

/// Mcost: per-cell predicted mean μ (Eq. 11) and standard deviation σ (Eq. 12) over the
/// traversable cells of a rectangle of the Mcost lattice.
#[derive(Clone, Debug)]
pub struct CostMap {
    /// The Mcost lattice rectangle (cells of size `cell_size`).
    pub rect: CellRect,
    /// Mcost cell size, metres.
    pub cell_size: f64,
    /// Traversable (admissible and reachable) cells, row-major over `rect`.
    pub traversable: Vec<bool>,
    /// Predicted mean μ(ν′) (Eq. 11); NaN where not traversable.
    pub mean: Vec<f64>,
    /// Predicted standard deviation σ(ν′) (Eq. 12, latent); NaN where not traversable.
    pub std: Vec<f64>,
    /// Traversable cells whose descriptor could not be formed (they carry the prior).
    pub undescribed: usize,
    /// Wall time of the descriptors in the last build, ms.
    pub descriptor_ms: f64,
    /// Wall time of the committee predictions in the last build, ms.
    pub predict_ms: f64,
    /// Frozen-expert predictions made afresh in the last build (the rest came from the cache).
    pub fresh_predictions: usize,
}

/// Cached predictions of the frozen experts per Mcost cell (module docs).
#[derive(Clone, Debug, Default)]
pub struct PredictionCache {
    cells: HashMap<Cell, Cached>,
}

#[derive(Clone, Debug)]
struct Cached {
    desc: [f32; 5],
    /// Predictions of experts 0, 1, … (all frozen), in order.
    preds: Vec<Prediction>,
}

impl CostMap {
    /// An empty map.
    pub fn empty(cell_size: f64) -> Self {
        Self {
            rect: CellRect::new(Cell::new(0, 0), 0, 0),
            cell_size,
            traversable: Vec::new(),
            mean: Vec::new(),
            std: Vec::new(),
            undescribed: 0,
            descriptor_ms: 0.0,
            predict_ms: 0.0,
            fresh_predictions: 0,
        }
    }

    /// Builds Mcost from the elevation map, the reachable set (computed from the robot's cell on
    /// `map`) and the committee, with descriptor radius `delta_desc`, reusing and refreshing
    /// `cache` (which must only ever be used with this one committee).
    pub fn build(
        map: &ElevationMap,
        reach: &Reachability,
        rbcm: &Rbcm,
        cache: &mut PredictionCache,
        cell_size: f64,
        delta_desc: f64,
    ) -> Self {
        let mut out = Self::empty(cell_size);
        let Some(known) = map.known_bounds() else {
            return out;
        };
        let d = map.cell_size();
        let lo = known.cell(0).center(d);
        let hi = known.cell(known.len() - 1).center(d);
        let (Some(a), Some(b)) = (
            Cell::containing(lo.x, lo.y, cell_size),
            Cell::containing(hi.x, hi.y, cell_size),
        ) else {
            return out;
        };
        out.rect = CellRect::new(a, (b.i - a.i + 1) as u32, (b.j - a.j + 1) as u32);
        let n = out.rect.len();
        // The elevation cell nearest each Mcost centre, when it is a reachable admissible one.
        let sources: Vec<Option<Cell>> = (0..n)
            .map(|k| {
                let p = out.rect.cell(k).center(cell_size);
                map.cell_at(p.x, p.y).filter(|&c| reach.is_goal_cell(c))
            })
            .collect();
        out.traversable = sources.iter().map(Option::is_some).collect();
        let w = Instant::now();
        let (ks, cells): (Vec<usize>, Vec<Cell>) = sources
            .iter()
            .enumerate()
            .filter_map(|(k, s)| s.map(|c| (k, c)))
            .unzip();
        let described: Vec<(usize, [f32; 5])> = ks
            .into_iter()
            .zip(shape_lab_descriptors_at(map, &cells, delta_desc))
            .filter_map(|(k, d)| d.map(|d| (k, d)))
            .collect();
        out.descriptor_ms = w.elapsed().as_secs_f64() * 1e3;
        let prior_mean = rbcm.params().prior_mean;
        let prior_std = rbcm.params().kernel.prior_variance().max(0.0).sqrt();
        out.mean = vec![f64::NAN; n];
        out.std = vec![f64::NAN; n];
        for (k, &t) in out.traversable.iter().enumerate() {
            if t {
                out.mean[k] = prior_mean;
                out.std[k] = prior_std;
            }
        }
        out.undescribed = out.traversable.iter().filter(|&&t| t).count() - described.len();
        if described.is_empty() {
            return out;
        }
        let w = Instant::now();
        let preds = out.predict(rbcm, cache, &described);
        for (&(k, _), p) in described.iter().zip(&preds) {
            if p.mean.is_finite() && p.latent_variance.is_finite() {
                out.mean[k] = p.mean; // Eq. 11
                out.std[k] = p.latent_variance.max(0.0).sqrt(); // Eq. 12
            }
        }
        out.predict_ms = w.elapsed().as_secs_f64() * 1e3;
        out
    }

    /// Committee predictions for the described cells, frozen experts from the cache.
    fn predict(
        &mut self,
        rbcm: &Rbcm,
        cache: &mut PredictionCache,
        described: &[(usize, [f32; 5])],
    ) -> Vec<Prediction> {
        let experts = rbcm.experts();
        let frozen = rbcm.frozen_experts();
        let cells: Vec<Cell> = described.iter().map(|&(k, _)| self.rect.cell(k)).collect();
        for (c, (_, d)) in cells.iter().zip(described) {
            let e = cache.cells.entry(*c).or_insert_with(|| Cached {
                desc: *d,
                preds: Vec::new(),
            });
            if e.desc != *d {
                e.desc = *d;
                e.preds.clear();
            }
            e.preds.truncate(frozen); // a committee never loses experts; defensive
        }
        // Frozen experts each predict the cells that lack their prediction, in expert order;
        // most cells lack none, so start at the first expert some cell lacks.
        let have: Vec<usize> = cells.iter().map(|c| cache.cells[c].preds.len()).collect();
        let first = have.iter().copied().min().unwrap_or(frozen);
        let mut xs = Vec::new();
        let mut idx = Vec::new();
        for (i, expert) in experts.iter().enumerate().take(frozen).skip(first) {
            xs.clear();
            idx.clear();
            for (j, &h) in have.iter().enumerate() {
                // A cell that had h predictions gets expert i for every i ≥ h.
                if h <= i {
                    idx.push(j);
                    xs.extend(described[j].1.iter().map(|&v| f64::from(v)));
                }
            }
            if idx.is_empty() {
                continue;
            }
            let (mut mu, mut var) = (vec![0.0; idx.len()], vec![0.0; idx.len()]);
            if expert.predict_batch(&xs, &mut mu, &mut var).is_err() {
                mu.fill(f64::NAN);
                var.fill(f64::NAN);
            }
            self.fresh_predictions += idx.len();
            for ((&j, &m), &v) in idx.iter().zip(&mu).zip(&var) {
                if let Some(e) = cache.cells.get_mut(&cells[j]) {
                    e.preds.push(Prediction {
                        mean: m,
                        latent_variance: v,
                    });
                }
            }
        }
        // The growing expert predicts everywhere.
        let growing = (frozen < experts.len() && rbcm.takes_part(frozen)).then(|| {
            let xs: Vec<f64> = described
                .iter()
                .flat_map(|(_, d)| d.iter().map(|&v| f64::from(v)))
                .collect();
            let n = described.len();
            let (mut mu, mut var) = (vec![0.0; n], vec![0.0; n]);
            if experts[frozen]
                .predict_batch(&xs, &mut mu, &mut var)
                .is_err()
            {
                mu.fill(f64::NAN);
                var.fill(f64::NAN);
            }
            (mu, var)
        });
        let kss: Vec<f64> = experts
            .iter()
            .map(|e| e.params().kernel.prior_variance())
            .collect();
        cells
            .iter()
            .enumerate()
            .map(|(j, c)| {
                let cached = &cache.cells[c].preds;
                let frozen_parts = (0..frozen)
                    .filter(|&i| rbcm.takes_part(i))
                    .map(|i| (cached[i], kss[i]));
                let grow_part = growing.as_ref().map(|(mu, var)| {
                    (
                        Prediction {
                            mean: mu[j],
                            latent_variance: var[j],
                        },
                        kss[frozen],
                    )
                });
                rbcm.combine_predictions(frozen_parts.chain(grow_part))
            })
            .collect()
    }

    /// Marks `c` not traversable (a cell the robot was refused entry to).
    pub fn exclude(&mut self, c: Cell) {
        if let Some(k) = self.rect.index(c)
            && self.traversable[k]
        {
            self.traversable[k] = false;
            self.mean[k] = f64::NAN;
            self.std[k] = f64::NAN;
        }
    }

    /// Number of traversable cells.
    pub fn traversable_count(&self) -> usize {
        self.traversable.iter().filter(|&&t| t).count()
    }

    /// The Mcost cell containing world point `p`.
    pub fn cell_at(&self, p: Point2) -> Option<Cell> {
        Cell::containing(p.x, p.y, self.cell_size)
    }

    /// True when `c` is a traversable cell of the map.
    pub fn is_traversable(&self, c: Cell) -> bool {
        self.rect.index(c).is_some_and(|k| self.traversable[k])
    }

    /// The traversable cell nearest `c` within `radius` cells (ties in row-major order).
    pub fn nearest_traversable(&self, c: Cell, radius: i32) -> Option<Cell> {
        let mut best: Option<(i64, Cell)> = None;
        for dj in -radius..=radius {
            for di in -radius..=radius {
                let q = Cell::new(c.i + di, c.j + dj);
                let d2 = (di as i64).pow(2) + (dj as i64).pow(2);
                if self.is_traversable(q) && best.is_none_or(|(b, _)| d2 < b) {
                    best = Some((d2, q));
                }
            }
        }
        best.map(|(_, q)| q)
    }

    /// The cost-goal score of Prágr19 Eq. 15 for every traversable cell: the median σ over the
    /// traversable cells within `delta_score` metres (the cell itself included); NaN elsewhere.
    pub fn scores(&self, delta_score: f64) -> Vec<f64> {
        let offs = strider_core::grid::disc_offsets(delta_score, self.cell_size);
        let (w, h) = (self.rect.width as i32, self.rect.height as i32);
        (0..self.rect.len())
            .into_par_iter()
            .map_init(Vec::new, |buf: &mut Vec<f64>, k| {
                if !self.traversable[k] {
                    return f64::NAN;
                }
                let (i, j) = ((k as i32) % w, (k as i32) / w);
                buf.clear();
                for &(di, dj) in &offs {
                    let (a, b) = (i + di, j + dj);
                    if a < 0 || b < 0 || a >= w || b >= h {
                        continue;
                    }
                    let q = (b * w + a) as usize;
                    if self.traversable[q] && self.std[q].is_finite() {
                        buf.push(self.std[q]);
                    }
                }
                median(buf)
            })
            .collect()
    }

    /// Per-cell planning cost: μ clamped below at `floor` (> 0); `+∞` where not traversable.
    pub fn planning_costs(&self, floor: f64) -> Vec<f32> {
        self.mean
            .iter()
            .zip(&self.traversable)
            .map(|(&m, &t)| {
                if t {
                    (if m.is_finite() { m.max(floor) } else { floor }) as f32
                } else {
                    f32::INFINITY
                }
            })
            .collect()
    }
}

/// The median of `v` (mean of the two middle values for an even count); NaN when empty.
/// Reorders `v`.
pub fn median(v: &mut [f64]) -> f64 {
    let n = v.len();
    if n == 0 {
        return f64::NAN;
    }
    let (_, &mut hi, _) = v.select_nth_unstable_by(n / 2, f64::total_cmp);
    if n % 2 == 1 {
        hi
    } else {
        let lo = v[..n / 2].iter().copied().fold(f64::NEG_INFINITY, f64::max);
        0.5 * (lo + hi)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn median_odd_even_empty() {
        assert_eq!(median(&mut [3.0, 1.0, 2.0]), 2.0);
        assert_eq!(median(&mut [4.0, 1.0, 3.0, 2.0]), 2.5);
        assert!(median(&mut []).is_nan());
    }

    fn toy(std: Vec<f64>, traversable: Vec<bool>, w: u32) -> CostMap {
        let n = std.len();
        CostMap {
            rect: CellRect::new(Cell::new(0, 0), w, (n as u32) / w),
            cell_size: 0.1,
            traversable,
            mean: vec![0.01; n],
            std,
            undescribed: 0,
            descriptor_ms: 0.0,
            predict_ms: 0.0,
            fresh_predictions: 0,
        }
    }

    #[test]
    fn eq15_score_is_the_neighbourhood_median() {
        // 5 × 1 strip; δ_score 0.15 m covers the cell and its two neighbours.
        let m = toy(vec![1.0, 5.0, 2.0, 9.0, 3.0], vec![true; 5], 5);
        let s = m.scores(0.15);
        assert_eq!(s[0], 3.0); // median{1, 5}
        assert_eq!(s[1], 2.0); // median{1, 5, 2}
        assert_eq!(s[2], 5.0); // median{5, 2, 9}
        assert_eq!(s[4], 6.0); // median{9, 3}
    }

    #[test]
    fn untraversable_cells_neither_score_nor_count() {
        let m = toy(vec![1.0, 100.0, 2.0], vec![true, false, true], 3);
        let s = m.scores(0.25);
        assert!(s[1].is_nan());
        assert_eq!(s[0], 1.5);
        let c = m.planning_costs(0.005);
        assert!(c[1].is_infinite());
        assert_eq!(c[0], 0.01);
        assert_eq!(
            m.nearest_traversable(Cell::new(1, 0), 1),
            Some(Cell::new(0, 0))
        );
    }

    /// Cached frozen-expert predictions give exactly the committee's own prediction, across
    /// cycles in which experts freeze and the map changes.
    #[test]
    fn cached_predictions_equal_direct_ones() {
        use strider_core::Rgb8;
        use strider_learn::gp::{GpParams, Kernel, KernelKind};
        use strider_learn::rbcm::{RbcmParams, RbcmVariant};
        use strider_map::MapParams;
        let mut map = ElevationMap::new(MapParams {
            cell_size: 0.05,
            r_robot: 0.0,
            ..MapParams::default()
        });
        let paint = |map: &mut ElevationMap, bump: f32| {
            for j in 0..30 {
                for i in 0..40 {
                    let z = if i > 20 {
                        0.01 * ((i * j) % 5) as f32 + bump
                    } else {
                        0.0
                    };
                    let col = if j > 15 {
                        Rgb8::new(50, 150, 50)
                    } else {
                        Rgb8::new(140, 140, 140)
                    };
                    map.set_cell(Cell::new(i, j), z, 1e-4, col);
                }
            }
            map.update_passability();
        };
        paint(&mut map, 0.0);
        let gp = GpParams {
            kernel: Kernel {
                kind: KernelKind::Exponential,
                lengthscales: vec![0.5],
                signal_variance: 4e-4,
            },
            noise_variance: 2.5e-5,
            prior_mean: 0.0,
        };
        let mut rbcm = Rbcm::new(
            5,
            gp,
            RbcmParams {
                m_max: 7,
                m_min: 3,
                variant: RbcmVariant::Robust,
            },
        )
        .unwrap();
        let mut cache = PredictionCache::default();
        let mut k = 0;
        for round in 0..4 {
            // New pairs (experts freeze along the way), then a changed patch of the map.
            for _ in 0..6 {
                let c = Cell::new((k * 7) % 40, (k * 11) % 30);
                if let Some(d) = shape_lab_descriptors_at(&map, &[c], 0.15)[0] {
                    rbcm.push(&d.map(f64::from), 0.005 + 0.001 * (k % 9) as f64)
                        .unwrap();
                }
                k += 1;
            }
            if round == 2 {
                paint(&mut map, 0.02);
            }
            let reach = Reachability::compute(&map, Cell::new(5, 5));
            let cm = CostMap::build(&map, &reach, &rbcm, &mut cache, 0.1, 0.15);
            let fresh = CostMap::build(
                &map,
                &reach,
                &rbcm,
                &mut PredictionCache::default(),
                0.1,
                0.15,
            );
            assert!(cm.traversable_count() > 200);
            for q in 0..cm.rect.len() {
                assert_eq!(cm.traversable[q], fresh.traversable[q]);
                if !cm.traversable[q] {
                    continue;
                }
                assert_eq!(cm.mean[q].to_bits(), fresh.mean[q].to_bits());
                assert_eq!(cm.std[q].to_bits(), fresh.std[q].to_bits());
                let c = map
                    .cell_at(cm.rect.cell(q).center(0.1).x, cm.rect.cell(q).center(0.1).y)
                    .unwrap();
                if let Some(d) = shape_lab_descriptors_at(&map, &[c], 0.15)[0] {
                    let p = rbcm.predict(&d.map(f64::from));
                    assert!((p.mean - cm.mean[q]).abs() < 1e-12);
                    assert!((p.latent_variance.sqrt() - cm.std[q]).abs() < 1e-9);
                }
            }
        }
        assert!(rbcm.frozen_experts() >= 2);
    }
}
