//! Costs from a few cells to a few others on a part of the grid, kept with what they were
//! computed from so that a later call on an unchanged part reuses them.

use super::super::cost_grid::CostGrid;
use super::super::dijkstra::Dijkstra;
use strider_core::{Cell, CellRect};

/// The costs from each of `sources` to each of `targets` on the grid cut to `rect`, with the
/// costs of that part they were computed from.
#[derive(Clone, Debug)]
pub(super) struct Searched {
    rect: CellRect,
    costs: Vec<f32>,
    sources: Vec<Cell>,
    targets: Vec<Cell>,
    /// Row-major `sources × targets`, `+∞` where the part does not connect them.
    dists: Vec<f64>,
}

/// A search's reusable state.
#[derive(Default)]
pub(super) struct Scratch {
    dj: Dijkstra,
    row: Vec<f64>,
    pending: Vec<usize>,
}

impl Searched {
    /// The searches on `grid` cut to `rect` (inside the grid).
    pub(super) fn compute(
        s: &mut Scratch,
        grid: &CostGrid,
        rect: CellRect,
        sources: &[Cell],
        targets: &[Cell],
    ) -> Self {
        let part = CostGrid::new(rect, grid.cell_size(), costs_of(grid, rect))
            .expect("a part of a valid grid is valid");
        let mut dists = Vec::with_capacity(sources.len() * targets.len());
        for &u in sources {
            let found = s.dj.row_into(&part, u, targets, &mut s.pending, &mut s.row);
            if found.is_err() {
                s.row.clear();
                s.row.resize(targets.len(), f64::INFINITY);
            }
            dists.extend_from_slice(&s.row);
        }
        Self {
            rect,
            costs: part.into_costs(),
            sources: sources.to_vec(),
            targets: targets.to_vec(),
            dists,
        }
    }

    /// True when these are the searches [`compute`](Self::compute) would make now.
    pub(super) fn is_for(
        &self,
        grid: &CostGrid,
        rect: CellRect,
        sources: &[Cell],
        targets: &[Cell],
    ) -> bool {
        self.rect == rect
            && self.sources == sources
            && self.targets == targets
            && same_costs(grid, rect, &self.costs)
    }

    /// `prev` when it is for these searches, else `None` after computing them into `fresh`.
    pub(super) fn reuse_or_compute(
        prev: Option<&Searched>,
        s: &mut Scratch,
        grid: &CostGrid,
        rect: CellRect,
        sources: &[Cell],
        targets: &[Cell],
    ) -> Option<Self> {
        match prev {
            Some(p) if p.is_for(grid, rect, sources, targets) => None,
            _ => Some(Self::compute(s, grid, rect, sources, targets)),
        }
    }

    /// The cost from source `a` to target `b` (indices).
    pub(super) fn cost(&self, a: usize, b: usize) -> f64 {
        self.dists[a * self.targets.len() + b]
    }
}

/// The costs of `grid` over `rect` (inside the grid), row by row.
fn costs_of(grid: &CostGrid, rect: CellRect) -> Vec<f32> {
    let mut out = Vec::with_capacity(rect.len());
    for_rows(grid, rect, |row| out.extend_from_slice(row));
    out
}

/// Calls `f` with each row of `grid`'s costs over `rect` (inside the grid), lowest first.
fn for_rows(grid: &CostGrid, rect: CellRect, mut f: impl FnMut(&[f32])) {
    let costs = grid.costs();
    for dj in 0..rect.height as i32 {
        if let Some(k) = grid.index(Cell::new(rect.min.i, rect.min.j + dj)) {
            f(&costs[k..k + rect.width as usize]);
        }
    }
}

/// True when `grid` over `rect` holds exactly `costs`.
fn same_costs(grid: &CostGrid, rect: CellRect, costs: &[f32]) -> bool {
    let w = rect.width as usize;
    let mut k = 0;
    let mut same = costs.len() == rect.len();
    for_rows(grid, rect, |row| {
        same = same && row == &costs[k..k + w];
        k += w;
    });
    same
}
