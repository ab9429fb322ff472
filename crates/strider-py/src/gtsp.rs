//! `strider.gtsp`: the generalized-TSP solver on GTSPLIB/TSPLIB files or on a cost matrix and
//! vertex sets, solved and checked by the function `strider gtsp solve` calls.

use std::path::PathBuf;

use numpy::{IntoPyArray, PyArray2, PyArrayMethods, PyReadonlyArray2};
use pyo3::prelude::*;
use strider_experiments::gtsp::{parse_mode, read_instance, solve_checked};
use strider_plan::{CostMatrix, Instance as RustInstance, SolverParams};

use crate::errors::{msg, to_py};

/// The largest arc cost accepted from a matrix: a tour's cost (a sum of at most n arcs) then
/// stays far from overflowing.
const MAX_ARC_COST: i64 = 1 << 40;

/// A GTSP instance: `n` vertices, `sets` of vertex indices (0-based), an integer cost matrix.
#[pyclass(module = "strider.gtsp", frozen)]
pub struct Instance {
    inner: RustInstance,
}

#[pymethods]
impl Instance {
    /// The instance's name.
    #[getter]
    fn name(&self) -> &str {
        &self.inner.name
    }
    /// The number of vertices.
    #[getter]
    fn n(&self) -> usize {
        self.inner.n
    }
    /// The vertex sets, 0-based vertex indices.
    #[getter]
    fn sets(&self) -> Vec<Vec<usize>> {
        self.inner.sets.clone()
    }
    /// Whether the cost matrix is symmetric.
    #[getter]
    fn symmetric(&self) -> bool {
        self.inner.symmetric
    }
    /// The n × n cost matrix as an int64 array.
    fn matrix<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray2<i64>>> {
        let n = self.inner.n;
        let flat: Vec<i64> = (0..n)
            .flat_map(|i| self.inner.dist.row(i).to_vec())
            .collect();
        flat.into_pyarray(py).reshape([n, n])
    }
    fn __repr__(&self) -> String {
        format!(
            "Instance(name={:?}, n={}, sets={})",
            self.inner.name,
            self.inner.n,
            self.inner.sets.len()
        )
    }
}

/// A solution: `cost`, `tour` (one 0-based vertex per set, in visiting order), `time_s`.
#[pyclass(module = "strider.gtsp", frozen, get_all)]
pub struct Solution {
    /// The tour's cost.
    cost: i64,
    /// The tour, 0-based vertex indices (the command prints them 1-based, as in the file).
    tour: Vec<usize>,
    /// Solver wall time, s.
    time_s: f64,
    /// Whether the solver proved the tour optimal.
    optimal: bool,
}

#[pymethods]
impl Solution {
    fn __repr__(&self) -> String {
        format!("Solution(cost={}, tour={:?})", self.cost, self.tour)
    }
}

/// Reads a GTSPLIB or TSPLIB file.
#[pyfunction]
pub fn read(py: Python<'_>, path: PathBuf) -> PyResult<Instance> {
    let inner = py.detach(|| read_instance(&path)).map_err(to_py)?;
    Ok(Instance { inner })
}

fn solver_params(
    seed: u64,
    time_limit: f64,
    mode: &str,
    target_cost: Option<i64>,
) -> PyResult<SolverParams> {
    if !(time_limit.is_finite() && time_limit > 0.0 && time_limit <= 604_800.0) {
        return Err(msg(format!(
            "time_limit {time_limit}: must be a finite number of seconds > 0 and ≤ 604800 (one week)"
        )));
    }
    Ok(SolverParams {
        mode: parse_mode(mode).map_err(to_py)?,
        time_limit_s: time_limit,
        seed,
        target_cost,
        ..SolverParams::default()
    })
}

fn solve_inner(py: Python<'_>, inst: &RustInstance, p: &SolverParams) -> PyResult<Solution> {
    let sol = py
        .detach(|| solve_checked(inst, p, &inst.name))
        .map_err(to_py)?;
    Ok(Solution {
        cost: sol.cost,
        tour: sol.tour,
        time_s: sol.time_s,
        optimal: sol.optimal,
    })
}

/// Solves an instance read by `read`.
#[pyfunction]
#[pyo3(signature = (instance, seed = 1, time_limit = 60.0, mode = "default", target_cost = None))]
pub fn solve(
    py: Python<'_>,
    instance: &Instance,
    seed: u64,
    time_limit: f64,
    mode: &str,
    target_cost: Option<i64>,
) -> PyResult<Solution> {
    let p = solver_params(seed, time_limit, mode, target_cost)?;
    solve_inner(py, &instance.inner, &p)
}

/// Solves the instance of an n × n integer cost matrix and vertex sets (0-based).
#[pyfunction]
#[pyo3(signature = (matrix, sets, seed = 1, time_limit = 60.0, mode = "default", name = "matrix", target_cost = None))]
// One argument per Python keyword argument.
#[allow(clippy::too_many_arguments)]
pub fn solve_matrix(
    py: Python<'_>,
    matrix: PyReadonlyArray2<'_, i64>,
    sets: Vec<Vec<usize>>,
    seed: u64,
    time_limit: f64,
    mode: &str,
    name: &str,
    target_cost: Option<i64>,
) -> PyResult<Solution> {
    let p = solver_params(seed, time_limit, mode, target_cost)?;
    let m = matrix.as_array();
    let (n, cols) = m.dim();
    if n != cols || n == 0 {
        return Err(msg(format!(
            "the cost matrix is {n}x{cols}: it must be square and non-empty"
        )));
    }
    if let Some(c) = m.iter().find(|c| !(0..=MAX_ARC_COST).contains(*c)) {
        return Err(msg(format!(
            "arc cost {c}: costs must be in [0, {MAX_ARC_COST}]"
        )));
    }
    let dist = CostMatrix::new(n, m.iter().copied().collect());
    let inst = RustInstance::new(name, sets, dist).map_err(|e| msg(e.to_string()))?;
    solve_inner(py, &inst, &p)
}
