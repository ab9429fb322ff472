//! Lower-confidence-bound path planning of Nardi19 §V-A (Eq. 7–8, decision 26).
//!
//! The g-cost of Eq. 7 is g(x) = g(x′) + ‖x − x′‖ · ρ(μ(x) − λσ(x)): the step into x costs its
//! length times the rectified lower confidence bound of the model *at x*, the cell entered,
//! with ρ the softplus log(1 + eˣ) of Eq. 8 or, for comparison, the ReLU max(0, x).
//!
//! This reuses the grid planner ([`Dijkstra::astar`]) rather than a second search: the grid
//! planner charges each step the cost of the cell it *leaves* (decision 21), and a path
//! x₀ … x_k charged by the cells entered costs exactly what the reversed path x_k … x₀ costs
//! when charged by the cells left. So [`lcb_path`] searches from the goal to the start on the
//! grid of ρ values and reverses the result; the corner rule is symmetric, so the reversed
//! path is a legal forward path. The A* heuristic is the grid planner's octile distance × the
//! smallest ρ on the map, which is at least decision 26's Euclidean distance × min ρ and still
//! never overestimates, so the optimum is the same.
//!
//! The grid needs strictly positive costs, and the ReLU is 0 wherever μ ≤ λσ: every ρ value is
//! raised to at least [`LcbParams::floor`] (10⁻³ by default), which among paths of zero
//! rectified cost prefers the shortest.

use strider_core::{Cell, CellRect};

use super::cost_grid::{CostGrid, GridError};
use super::dijkstra::{Dijkstra, SearchError};

/// The rectifier ρ applied to the lower confidence bound μ − λσ.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Rectifier {
    /// softplus(x) = log(1 + eˣ) (Eq. 8): known low-cost cells stay cheaper than very
    /// uncertain ones.
    Softplus,
    /// ReLU max(0, x): every cell whose bound is negative costs the same (the floor).
    Relu,
}

impl Rectifier {
    /// ρ(x).
    pub fn apply(self, x: f64) -> f64 {
        match self {
            Rectifier::Softplus => softplus(x),
            Rectifier::Relu => x.max(0.0),
        }
    }

    /// The report name: "softplus" or "relu".
    pub fn name(self) -> &'static str {
        match self {
            Rectifier::Softplus => "softplus",
            Rectifier::Relu => "relu",
        }
    }

    /// Parses a report name.
    pub fn parse(s: &str) -> Option<Rectifier> {
        match s {
            "softplus" => Some(Rectifier::Softplus),
            "relu" => Some(Rectifier::Relu),
            _ => None,
        }
    }
}

/// softplus(x) = log(1 + eˣ) (Eq. 8), without overflow for large x.
pub fn softplus(x: f64) -> f64 {
    if x > 30.0 {
        // log(1 + eˣ) − x = log(1 + e⁻ˣ) < 1e-13 here.
        x
    } else {
        x.exp().ln_1p()
    }
}

/// Parameters of the LCB cost.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LcbParams {
    /// λ ≥ 0, the width of the confidence bound (decision 26: 1).
    pub lambda: f64,
    /// The rectifier.
    pub rectifier: Rectifier,
    /// Smallest per-metre cost, > 0 (the grid's costs must be positive).
    pub floor: f64,
}

impl Default for LcbParams {
    /// λ = 1, softplus, floor 10⁻³.
    fn default() -> Self {
        LcbParams {
            lambda: 1.0,
            rectifier: Rectifier::Softplus,
            floor: 1e-3,
        }
    }
}

/// The per-metre cost grid max(ρ(μ − λσ), floor) over `rect`, `+∞` where `admissible` is
/// false. `mean`, `std` and `admissible` are row-major over `rect`.
pub fn lcb_grid(
    rect: CellRect,
    cell_size: f64,
    mean: &[f64],
    std: &[f64],
    admissible: &[bool],
    params: &LcbParams,
) -> Result<CostGrid, GridError> {
    if !(params.lambda.is_finite() && params.lambda >= 0.0) {
        return Err(GridError::BadParameter {
            name: "lambda",
            value: params.lambda,
        });
    }
    if !(params.floor.is_finite() && params.floor > 0.0 && (params.floor as f32) > 0.0) {
        return Err(GridError::BadParameter {
            name: "floor",
            value: params.floor,
        });
    }
    for (got, _) in [
        (mean.len(), "mean"),
        (std.len(), "std"),
        (admissible.len(), "mask"),
    ] {
        if got != rect.len() {
            return Err(GridError::SizeMismatch {
                expected: rect.len(),
                got,
            });
        }
    }
    let mut cost = Vec::with_capacity(rect.len());
    for (index, ((&m, &s), &ok)) in mean.iter().zip(std).zip(admissible).enumerate() {
        if !ok {
            cost.push(f32::INFINITY);
            continue;
        }
        if !(m.is_finite() && s.is_finite() && s >= 0.0) {
            return Err(GridError::NanCost { index });
        }
        let c = params
            .rectifier
            .apply(m - params.lambda * s)
            .max(params.floor);
        cost.push(c as f32);
    }
    CostGrid::new(rect, cell_size, cost)
}

/// The path from `start` to `goal` (both included) minimising Eq. 7 on `grid`, and its cost
/// Σ ‖x − x′‖ · c(x) over the cells entered; `None` when the goal is unreachable or either end
/// is not admissible (or outside).
pub fn lcb_path(
    dij: &mut Dijkstra,
    grid: &CostGrid,
    start: Cell,
    goal: Cell,
) -> Result<Option<(Vec<Cell>, f64)>, SearchError> {
    if !grid.is_admissible(start) || !grid.is_admissible(goal) {
        return Ok(None);
    }
    // Reverse search: see the module docs.
    let cost = dij.astar(grid, goal, start)?;
    if !cost.is_finite() {
        return Ok(None);
    }
    let Some(mut path) = dij.path_to(start) else {
        return Ok(None);
    };
    path.reverse();
    Ok(Some((path, cost)))
}

/// Cost of a cell path charged by the cells entered (Eq. 7): Σ ‖x_{i+1} − x_i‖ · c(x_{i+1});
/// `None` when the path is not a legal 8-connected path on `grid` (see
/// [`path_cost`](super::path_cost)).
pub fn entered_cost(grid: &CostGrid, path: &[Cell]) -> Option<f64> {
    let rev: Vec<Cell> = path.iter().rev().copied().collect();
    super::path_cost(grid, &rev)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn softplus_is_stable_and_smooth() {
        assert!((softplus(0.0) - std::f64::consts::LN_2).abs() < 1e-15);
        assert_eq!(softplus(1000.0), 1000.0);
        assert!(softplus(-1000.0) >= 0.0 && softplus(-1000.0) < 1e-300);
        assert!((softplus(30.0) - 30.0).abs() < 1e-12);
        assert!((softplus(30.000001) - softplus(29.999999)).abs() < 1e-5);
        assert_eq!(Rectifier::Relu.apply(-2.0), 0.0);
        assert_eq!(Rectifier::parse("relu"), Some(Rectifier::Relu));
        assert_eq!(Rectifier::parse("x"), None);
    }

    #[test]
    fn cost_is_charged_by_the_entered_cell() {
        // 3 × 1 corridor; costs 1, 2, 4 (λ = 0, ReLU, so ρ(μ) = μ).
        let rect = CellRect::new(Cell::new(0, 0), 3, 1);
        let p = LcbParams {
            lambda: 0.0,
            rectifier: Rectifier::Relu,
            floor: 1e-3,
        };
        let g = lcb_grid(rect, 0.5, &[1.0, 2.0, 4.0], &[0.0; 3], &[true; 3], &p).unwrap();
        let (path, cost) = lcb_path(&mut Dijkstra::new(), &g, Cell::new(0, 0), Cell::new(2, 0))
            .unwrap()
            .unwrap();
        assert_eq!(
            path,
            vec![Cell::new(0, 0), Cell::new(1, 0), Cell::new(2, 0)]
        );
        assert!((cost - 0.5 * (2.0 + 4.0)).abs() < 1e-9);
        assert!((entered_cost(&g, &path).unwrap() - cost).abs() < 1e-9);
    }

    #[test]
    fn bad_inputs_are_errors() {
        let rect = CellRect::new(Cell::new(0, 0), 2, 1);
        let p = LcbParams::default();
        assert!(lcb_grid(rect, 1.0, &[1.0], &[0.0; 2], &[true; 2], &p).is_err());
        assert!(lcb_grid(rect, 1.0, &[f64::NAN, 1.0], &[0.0; 2], &[true; 2], &p).is_err());
        assert!(lcb_grid(rect, 1.0, &[1.0; 2], &[-1.0, 0.0], &[true; 2], &p).is_err());
        // A NaN in an inadmissible cell is never read.
        assert!(lcb_grid(rect, 1.0, &[f64::NAN, 1.0], &[0.0; 2], &[false, true], &p).is_ok());
        let bad = LcbParams { lambda: -1.0, ..p };
        assert!(lcb_grid(rect, 1.0, &[1.0; 2], &[0.0; 2], &[true; 2], &bad).is_err());
        let bad = LcbParams { floor: 0.0, ..p };
        assert!(lcb_grid(rect, 1.0, &[1.0; 2], &[0.0; 2], &[true; 2], &bad).is_err());
    }
}
