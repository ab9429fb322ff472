//! A dense per-metre traversal-cost raster over a [`CellRect`] of the global lattice.
//!
//! Cell `ν` holds the per-metre cost c(ν) of Prágr22 Eq. 4 (used as the cost of every edge leaving
//! ν, decision 21). Finite costs must be strictly positive; `f32::INFINITY` marks a cell that is
//! not admissible (π(ν) = 0 in Eq. 1, or inside the inflated configuration-space obstacle of
//! decision 4). Paths never enter or leave such a cell.

use rayon::prelude::*;
use std::sync::atomic::{AtomicU64, Ordering};
use strider_core::{Cell, CellRect};

/// Source of unique grid ids (see [`CostGrid::id`]).
static NEXT_ID: AtomicU64 = AtomicU64::new(0);
use thiserror::Error;

/// Why a [`CostGrid`] (or a grid operation) was rejected.
#[derive(Clone, Debug, PartialEq, Error)]
pub enum GridError {
    /// The cost vector does not hold exactly one value per cell of the rectangle.
    #[error("cost vector has {got} values but the rectangle has {expected} cells")]
    SizeMismatch {
        /// `rect.len()`.
        expected: usize,
        /// Length of the supplied vector.
        got: usize,
    },
    /// A cost is NaN.
    #[error("cost of cell index {index} is NaN")]
    NanCost {
        /// Row-major index of the offending cell.
        index: usize,
    },
    /// A cost is zero, negative or −∞ (costs must be > 0; +∞ means inadmissible).
    #[error("cost {value} of cell index {index} is not positive")]
    NonPositiveCost {
        /// Row-major index of the offending cell.
        index: usize,
        /// The offending value.
        value: f32,
    },
    /// The cell size is not a finite positive number.
    #[error("cell size {0} is not finite and positive")]
    BadCellSize(f64),
    /// Two grids that must share rectangle and cell size do not.
    #[error("grids differ in rectangle or cell size")]
    ShapeMismatch,
    /// An operation needing at least one grid got none.
    #[error("no grid given")]
    Empty,
    /// A non-finite or negative parameter (e.g. `c_loss`, `r_robot`).
    #[error("parameter {name} = {value} is invalid")]
    BadParameter {
        /// Parameter name.
        name: &'static str,
        /// Its value.
        value: f64,
    },
}

/// Per-cell per-metre traversal cost over a rectangle of the global lattice, row-major
/// (row 0 = lowest `j`). Invariant: every value is either a finite positive number or `+∞`
/// (inadmissible). Grids are immutable once built.
#[derive(Clone, Debug)]
pub struct CostGrid {
    rect: CellRect,
    cell_size: f64,
    cost: Vec<f32>,
    min_cost: f32,
    max_cost: f32,
    id: u64,
}

impl PartialEq for CostGrid {
    /// Equal rectangle, cell size and costs (the id is ignored).
    fn eq(&self, other: &Self) -> bool {
        self.rect == other.rect && self.cell_size == other.cell_size && self.cost == other.cost
    }
}

impl CostGrid {
    /// A grid from a row-major cost vector, validated (see [`GridError`]).
    pub fn new(rect: CellRect, cell_size: f64, cost: Vec<f32>) -> Result<Self, GridError> {
        if !(cell_size.is_finite() && cell_size > 0.0) {
            return Err(GridError::BadCellSize(cell_size));
        }
        if cost.len() != rect.len() {
            return Err(GridError::SizeMismatch {
                expected: rect.len(),
                got: cost.len(),
            });
        }
        let (min_cost, max_cost) = cost_range(&cost)?;
        Ok(Self {
            rect,
            cell_size,
            cost,
            min_cost,
            max_cost,
            id: NEXT_ID.fetch_add(1, Ordering::Relaxed),
        })
    }

    /// A grid with every cell set to `value`.
    pub fn filled(rect: CellRect, cell_size: f64, value: f32) -> Result<Self, GridError> {
        Self::new(rect, cell_size, vec![value; rect.len()])
    }

    /// A grid whose cost at each cell is `f(cell)`.
    pub fn from_fn(
        rect: CellRect,
        cell_size: f64,
        f: impl FnMut(Cell) -> f32,
    ) -> Result<Self, GridError> {
        Self::new(rect, cell_size, rect.cells().map(f).collect())
    }

    /// An id unique to this grid's contents: assigned at construction, shared only by clones
    /// (grids are immutable), so searches can cache per-grid data by it.
    pub fn id(&self) -> u64 {
        self.id
    }

    /// The covered rectangle.
    pub fn rect(&self) -> CellRect {
        self.rect
    }

    /// Cell size d_ν in metres.
    pub fn cell_size(&self) -> f64 {
        self.cell_size
    }

    /// Row-major costs.
    pub fn costs(&self) -> &[f32] {
        &self.cost
    }

    /// Consumes the grid, returning its row-major costs.
    pub fn into_costs(self) -> Vec<f32> {
        self.cost
    }

    /// Smallest cost over the grid (`+∞` when no cell is admissible or the grid is empty).
    pub fn min_cost(&self) -> f32 {
        self.min_cost
    }

    /// Largest finite cost over the grid (0 when no cell is admissible).
    pub fn max_cost(&self) -> f32 {
        self.max_cost
    }

    /// Number of cells.
    pub fn len(&self) -> usize {
        self.cost.len()
    }

    /// True for a grid without cells.
    pub fn is_empty(&self) -> bool {
        self.cost.is_empty()
    }

    /// Row-major index of `c`, or `None` outside the grid.
    #[inline]
    pub fn index(&self, c: Cell) -> Option<usize> {
        self.rect.index(c)
    }

    /// The cell at row-major index `k` (must be `< len()`).
    #[inline]
    pub fn cell(&self, k: usize) -> Cell {
        self.rect.cell(k)
    }

    /// Cost of `c`, or `None` outside the grid.
    #[inline]
    pub fn cost(&self, c: Cell) -> Option<f32> {
        self.index(c).map(|k| self.cost[k])
    }

    /// True when `c` is inside the grid and admissible (finite cost).
    #[inline]
    pub fn is_admissible(&self, c: Cell) -> bool {
        self.cost(c).is_some_and(f32::is_finite)
    }

    /// True when the two grids share rectangle and cell size.
    pub fn same_shape(&self, other: &CostGrid) -> bool {
        self.rect == other.rect && self.cell_size == other.cell_size
    }
}

/// Cells per chunk of [`cost_range`]'s parallel pass.
const RANGE_CHUNK: usize = 1 << 15;

/// The least cost and the greatest finite cost (0 without one) of `cost`, or the error of its
/// first NaN or non-positive cost. Chunks are scanned side by side, each in a loop without an
/// early exit; the offending index is looked up only when a chunk has one.
fn cost_range(cost: &[f32]) -> Result<(f32, f32), GridError> {
    let range = |chunk: &[f32]| {
        let (mut lo, mut hi, mut bad) = (f32::INFINITY, 0.0f32, false);
        for &v in chunk {
            bad |= v.is_nan() | (v <= 0.0);
            lo = lo.min(v);
            hi = if v.is_finite() { hi.max(v) } else { hi };
        }
        (lo, hi, bad)
    };
    let (lo, hi, bad) = cost.par_chunks(RANGE_CHUNK).map(range).reduce(
        || (f32::INFINITY, 0.0, false),
        |a, b| (a.0.min(b.0), a.1.max(b.1), a.2 || b.2),
    );
    if !bad {
        return Ok((lo, hi));
    }
    let index = cost
        .iter()
        .position(|v| v.is_nan() || *v <= 0.0)
        .expect("a chunk saw a bad cost");
    let value = cost[index];
    Err(if value.is_nan() {
        GridError::NanCost { index }
    } else {
        GridError::NonPositiveCost { index, value }
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn rect(w: u32, h: u32) -> CellRect {
        CellRect::new(Cell::new(-2, 3), w, h)
    }

    #[test]
    fn validation() {
        assert_eq!(
            CostGrid::new(rect(2, 2), 0.1, vec![1.0; 3]),
            Err(GridError::SizeMismatch {
                expected: 4,
                got: 3
            })
        );
        assert_eq!(
            CostGrid::new(rect(2, 1), 0.1, vec![1.0, f32::NAN]),
            Err(GridError::NanCost { index: 1 })
        );
        assert_eq!(
            CostGrid::new(rect(2, 1), 0.1, vec![0.0, 1.0]),
            Err(GridError::NonPositiveCost {
                index: 0,
                value: 0.0
            })
        );
        assert!(matches!(
            CostGrid::new(rect(2, 1), 0.1, vec![1.0, f32::NEG_INFINITY]),
            Err(GridError::NonPositiveCost { index: 1, .. })
        ));
        assert_eq!(
            CostGrid::filled(rect(1, 1), 0.0, 1.0),
            Err(GridError::BadCellSize(0.0))
        );
        assert!(CostGrid::filled(rect(1, 1), f64::NAN, 1.0).is_err());
    }

    #[test]
    fn validation_over_many_chunks_reports_the_first_bad_cell_and_the_range() {
        let n = 3 * RANGE_CHUNK + 17;
        let r = CellRect::new(Cell::new(0, 0), n as u32, 1);
        let mut c: Vec<f32> = (0..n).map(|k| 1.0 + (k % 7) as f32).collect();
        c[2 * RANGE_CHUNK + 5] = f32::INFINITY;
        c[RANGE_CHUNK + 3] = 0.5;
        let g = CostGrid::new(r, 0.1, c.clone()).unwrap();
        assert_eq!((g.min_cost(), g.max_cost()), (0.5, 7.0));
        // Bad cells in later chunks too: the first one is reported.
        c[3 * RANGE_CHUNK + 1] = f32::NAN;
        c[2 * RANGE_CHUNK + 9] = -1.0;
        assert_eq!(
            CostGrid::new(r, 0.1, c.clone()),
            Err(GridError::NonPositiveCost {
                index: 2 * RANGE_CHUNK + 9,
                value: -1.0
            })
        );
        c[RANGE_CHUNK - 1] = f32::NAN;
        assert_eq!(
            CostGrid::new(r, 0.1, c),
            Err(GridError::NanCost {
                index: RANGE_CHUNK - 1
            })
        );
    }

    #[test]
    fn accessors() {
        let g = CostGrid::from_fn(
            rect(3, 2),
            0.5,
            |c| {
                if c.i == -1 { f32::INFINITY } else { 2.0 }
            },
        )
        .unwrap();
        assert_eq!(g.len(), 6);
        assert_eq!(g.min_cost(), 2.0);
        assert!(!g.is_admissible(Cell::new(-1, 3)));
        assert!(g.is_admissible(Cell::new(-2, 4)));
        assert!(!g.is_admissible(Cell::new(5, 5)));
        assert_eq!(g.cost(Cell::new(0, 4)), Some(2.0));
        assert_eq!(g.index(Cell::new(-2, 4)), Some(3));
    }
}
