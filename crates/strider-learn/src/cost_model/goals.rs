//! Goals of one gait's cost model (Alg. 9): sampling sites on a lattice of spacing d_S, one goal
//! per informative class, and the bootstrap goal of decision 16 before the regressor exists.

use strider_core::{Cell, CellRect};

use super::classes::ClassInfo;
use super::{GaitCostModel, ModelUpdate};
use crate::gp::differential_entropy;
use crate::igng::ClassId;
use crate::morphology::TerrainCell;

/// A cost-model goal γ_C(T): sampling sites of one terrain class (Alg. 9).
#[derive(Clone, Debug, PartialEq)]
pub struct CostGoal {
    /// The class to sample; `None` for the bootstrap goal of decision 16.
    pub class: Option<ClassId>,
    /// I_C of the class (for the bootstrap goal: the prior's entropy).
    pub information_gain: f64,
    /// Sampling sites, in lattice order.
    pub sites: Vec<Cell>,
}

impl GaitCostModel {
    /// Decision 16: before the regressor exists every described cell is one eroded class, and
    /// one bootstrap goal holds the lattice sites over admissible cells with no measured cost.
    pub(super) fn bootstrap_update(&mut self) -> ModelUpdate {
        self.raw.invalidate();
        self.class_touched = None;
        for &k in &self.prev_support {
            self.learn_class[k as usize] = TerrainCell::Unknown;
            self.plan_class[k as usize] = TerrainCell::Unknown;
        }
        for &k in &self.support {
            self.learn_class[k as usize] = TerrainCell::Eroded;
            self.plan_class[k as usize] = TerrainCell::Eroded;
        }
        let candidates = self.admissible_unmeasured();
        let sites = lattice_sites(
            self.rect,
            self.store,
            self.cell_size,
            self.params.d_s,
            candidates.into_iter(),
        );
        let goals = if sites.is_empty() {
            Vec::new()
        } else {
            vec![CostGoal {
                class: None,
                information_gain: differential_entropy(self.params.gp.kernel.prior_variance()),
                sites,
            }]
        };
        ModelUpdate {
            goals,
            ..ModelUpdate::default()
        }
    }

    /// Storage indices of the admissible cells of the rectangle without a measured cost,
    /// ascending. Most of a building's bounding box is unseen: runs of 32 inadmissible cells are
    /// skipped with one branch.
    fn admissible_unmeasured(&self) -> Vec<usize> {
        const RUN: usize = 32;
        let (rect, store) = (self.rect, self.store);
        let mut out = Vec::new();
        for dj in 0..rect.height as i32 {
            let Some(k0) = store.index(Cell::new(rect.min.i, rect.min.j + dj)) else {
                continue;
            };
            let row = &self.admissible[k0..k0 + rect.width as usize];
            for (n, run) in row.chunks(RUN).enumerate() {
                if !run.iter().fold(false, |any, &a| any | a) {
                    continue;
                }
                for (o, &a) in run.iter().enumerate() {
                    let k = k0 + n * RUN + o;
                    if a && !self.measured_mask[k] {
                        out.push(k);
                    }
                }
            }
        }
        out
    }

    /// Alg. 9 lines 3–9: the lattice sites over admissible unmeasured cells of informative
    /// classes, grouped into one goal per informative class; the informative classes left
    /// without a site are returned to be pruned.
    pub(super) fn class_goals(&self, classes: &[ClassInfo]) -> (Vec<CostGoal>, Vec<ClassId>) {
        // The informative classes (I_C > 0), looked up per described cell: a handful, so a
        // short sorted list beats a hash lookup on every cell of the map.
        let mut informative: Vec<ClassId> = classes
            .iter()
            .filter(|c| c.information_gain > 0.0)
            .map(|c| c.id)
            .collect();
        informative.sort_unstable();
        if informative.is_empty() {
            return (Vec::new(), Vec::new());
        }
        let candidates = self.support.iter().map(|&k| k as usize).filter(|&k| {
            self.admissible[k]
                && !self.measured_mask[k]
                && match self.learn_class[k] {
                    TerrainCell::Class(t) => informative.binary_search(&t).is_ok(),
                    _ => false,
                }
        });
        let sites = lattice_sites(
            self.rect,
            self.store,
            self.cell_size,
            self.params.d_s,
            candidates,
        );
        let mut goals: Vec<CostGoal> = Vec::new();
        for c in classes {
            if c.information_gain > 0.0 {
                goals.push(CostGoal {
                    class: Some(c.id),
                    information_gain: c.information_gain,
                    sites: Vec::new(),
                });
            }
        }
        for s in sites {
            if let Some(TerrainCell::Class(t)) = self.store.index(s).map(|k| self.learn_class[k])
                && let Some(g) = goals.iter_mut().find(|g| g.class == Some(t))
            {
                g.sites.push(s);
            }
        }
        let mut pruned = Vec::new();
        goals.retain(|g| {
            if g.sites.is_empty() {
                pruned.extend(g.class);
                false
            } else {
                true
            }
        });
        (goals, pruned)
    }
}

/// Above this many lattice points the best site per point is kept in a hash map instead of a
/// dense array (a d_S far below the cell size over a large map).
const MAX_DENSE_LATTICE: usize = 1 << 22;

/// Alg. 9 lines 4–7: for each point p_S of the global lattice of spacing d_S inside the
/// rectangle `rect` of cells of size `d`, the closest cell within √2/2·d_S of p_S among the
/// `candidates` (storage indices in `store`, ascending; cells of `rect`).
/// Lattice order (rows, then columns); ties go to the lower row-major index.
///
/// Each candidate offers itself to the few lattice points within reach of it, so the work
/// follows the candidates (the described cells), not the rectangle.
fn lattice_sites(
    rect: CellRect,
    store: CellRect,
    d: f64,
    ds: f64,
    candidates: impl Iterator<Item = usize>,
) -> Vec<Cell> {
    let Some(((a0, a1), (b0, b1))) = lattice_range(rect, d, ds) else {
        return Vec::new();
    };
    let r = std::f64::consts::FRAC_1_SQRT_2 * ds;
    let na = (a1 - a0 + 1) as usize;
    let mut best = LatticeBest::new(na.saturating_mul((b1 - b0 + 1) as usize));
    // Per column (row) of the rectangle: the lattice columns (rows) near enough, with the
    // squared offset, computed once instead of per candidate (the same floating-point values).
    // The lattice point's index is the sum of the two axes' parts.
    let cols = axis_reach(rect.min.i, rect.width, d, ds, r, (a0, a1), 1);
    let rows = axis_reach(rect.min.j, rect.height, d, ds, r, (b0, b1), na);
    let sw = store.width as usize;
    let (si, sj) = (
        (rect.min.i - store.min.i) as usize,
        (rect.min.j - store.min.j) as usize,
    );
    for k in candidates {
        let (ci, cj) = (k % sw - si, k / sw - sj);
        for &(b, dy2) in rows.at(cj) {
            for &(a, dx2) in cols.at(ci) {
                let d2 = dx2 + dy2;
                if d2 >= r2_loose(r) {
                    continue;
                }
                let dist = d2.sqrt();
                if dist < r {
                    best.offer(b + a, dist, k);
                }
            }
        }
    }
    let mut out = Vec::new();
    for (at, k) in best.into_sorted() {
        let (a, b) = (a0 + (at % na) as i64, b0 + (at / na) as i64);
        // A lattice point off the lattice of cells has no site.
        if Cell::containing(a as f64 * ds, b as f64 * ds, d).is_none() {
            continue;
        }
        let c = store.cell(k);
        if out.last() != Some(&c) {
            out.push(c);
        }
    }
    out
}

/// The lattice indices (a0..=a1, b0..=b1) of the points of spacing `ds` between the centres of
/// the extreme cells of `rect` (cell size `d`); `None` when there is none.
fn lattice_range(rect: CellRect, d: f64, ds: f64) -> Option<((i64, i64), (i64, i64))> {
    if rect.is_empty() {
        return None;
    }
    let lo = rect.min.center(d);
    let hi = Cell::new(
        rect.min.i + rect.width as i32 - 1,
        rect.min.j + rect.height as i32 - 1,
    )
    .center(d);
    let (a0, a1) = ((lo.x / ds).ceil() as i64, (hi.x / ds).floor() as i64);
    let (b0, b1) = ((lo.y / ds).ceil() as i64, (hi.y / ds).floor() as i64);
    (a0 <= a1 && b0 <= b1).then_some(((a0, a1), (b0, b1)))
}

/// A bound on squared distances beyond which the distance is certainly not below `r`: r² with
/// a relative margin far above the rounding of the squares and the square root. Only a quick
/// rejection; the kept pairs are still judged on `sqrt(dx² + dy²) < r`, as Alg. 9 states.
fn r2_loose(r: f64) -> f64 {
    r * r * (1.0 + 1e-9)
}

/// Per cell column (or row) `n` of a rectangle starting at cell `first`: the lattice indices
/// `v` in `range` that can be within r of the cell centre, as `(v − range.0)·stride`, each
/// with the squared offset.
struct AxisReach {
    start: Vec<usize>,
    items: Vec<(usize, f64)>,
}

impl AxisReach {
    fn at(&self, n: usize) -> &[(usize, f64)] {
        &self.items[self.start[n]..self.start[n + 1]]
    }
}

fn axis_reach(
    first: i32,
    len: u32,
    d: f64,
    ds: f64,
    r: f64,
    range: (i64, i64),
    stride: usize,
) -> AxisReach {
    let mut start = Vec::with_capacity(len as usize + 1);
    let mut items = Vec::new();
    for n in 0..len as i64 {
        start.push(items.len());
        let x = ((first as i64 + n) as f64 + 0.5) * d;
        let (v0, v1) = (((x - r) / ds).floor() as i64, ((x + r) / ds).ceil() as i64);
        for v in v0.max(range.0)..=v1.min(range.1) {
            let dx2 = (x - v as f64 * ds).powi(2);
            // Farther along this axis alone than r: the distance is at least r whatever the
            // other axis gives (the margin keeps this true under rounding).
            if dx2 < r2_loose(r) {
                items.push(((v - range.0) as usize * stride, dx2));
            }
        }
    }
    start.push(items.len());
    AxisReach { start, items }
}

/// The closest candidate (distance, storage index) per lattice point.
enum LatticeBest {
    Dense { dist: Vec<f64>, at: Vec<usize> },
    Sparse(rustc_hash::FxHashMap<usize, (f64, usize)>),
}

impl LatticeBest {
    fn new(points: usize) -> Self {
        if points <= MAX_DENSE_LATTICE {
            Self::Dense {
                dist: vec![f64::INFINITY; points],
                at: vec![usize::MAX; points],
            }
        } else {
            Self::Sparse(Default::default())
        }
    }

    /// Keeps candidate `k` at `dist` for lattice point `p` if it is closer than the best so
    /// far, or as close with a lower index.
    #[inline]
    fn offer(&mut self, p: usize, dist: f64, k: usize) {
        match self {
            Self::Dense { dist: bd, at } => {
                if dist < bd[p] || (dist == bd[p] && k < at[p]) {
                    (bd[p], at[p]) = (dist, k);
                }
            }
            Self::Sparse(m) => {
                let e = m.entry(p).or_insert((f64::INFINITY, usize::MAX));
                if dist < e.0 || (dist == e.0 && k < e.1) {
                    *e = (dist, k);
                }
            }
        }
    }

    /// (lattice point, storage index) by lattice point.
    fn into_sorted(self) -> Vec<(usize, usize)> {
        match self {
            Self::Dense { at, .. } => at
                .into_iter()
                .enumerate()
                .filter(|&(_, k)| k != usize::MAX)
                .collect(),
            Self::Sparse(m) => {
                let mut v: Vec<(usize, usize)> = m.into_iter().map(|(p, (_, k))| (p, k)).collect();
                v.sort_unstable();
                v
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::descriptor_field::storage_rect;
    use proptest::prelude::*;
    use strider_core::Point2;

    /// Alg. 9 lines 4–7 as written: per lattice point, the closest admissible cell around it.
    fn reference(rect: CellRect, d: f64, ds: f64, ok: impl Fn(usize) -> bool) -> Vec<Cell> {
        let r = std::f64::consts::FRAC_1_SQRT_2 * ds;
        let Some(((a0, a1), (b0, b1))) = lattice_range(rect, d, ds) else {
            return Vec::new();
        };
        let reach = (r / d).ceil() as i32 + 1;
        let mut out = Vec::new();
        for b in b0..=b1 {
            for a in a0..=a1 {
                let p = Point2::new(a as f64 * ds, b as f64 * ds);
                let Some(pc) = Cell::containing(p.x, p.y, d) else {
                    continue;
                };
                let mut best: Option<(f64, usize)> = None;
                for dj in -reach..=reach {
                    for di in -reach..=reach {
                        let c = Cell::new(pc.i + di, pc.j + dj);
                        let Some(k) = rect.index(c) else { continue };
                        let cc = c.center(d);
                        let dist = ((cc.x - p.x).powi(2) + (cc.y - p.y).powi(2)).sqrt();
                        if dist >= r || !ok(k) {
                            continue;
                        }
                        if best.is_none_or(|(bd, bk)| dist < bd || (dist == bd && k < bk)) {
                            best = Some((dist, k));
                        }
                    }
                }
                if let Some((_, k)) = best {
                    let c = rect.cell(k);
                    if out.last() != Some(&c) {
                        out.push(c);
                    }
                }
            }
        }
        out
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(64))]

        /// The candidate-driven lattice equals the per-lattice-point search cell for cell.
        #[test]
        fn lattice_sites_equal_the_reference(
            (i0, j0, w, h) in (-90i32..90, -90i32..90, 1u32..60, 1u32..60),
            d in prop::sample::select(vec![0.05, 0.1, 0.2]),
            ds in 0.1f64..1.5,
            seed in any::<u64>(),
            density in 0u64..100,
        ) {
            let rect = CellRect::new(Cell::new(i0, j0), w, h);
            let store = storage_rect(rect);
            let ok = |k: usize| {
                let x = (k as u64 ^ seed).wrapping_mul(0x9E37_79B9_7F4A_7C15) >> 33;
                x % 100 < density
            };
            let want = reference(rect, d, ds, ok);
            let candidates: Vec<usize> = (0..rect.len())
                .filter(|&k| ok(k))
                .map(|k| store.index(rect.cell(k)).expect("inside"))
                .collect();
            let got = lattice_sites(rect, store, d, ds, candidates.into_iter());
            prop_assert_eq!(got, want);
        }
    }
}
