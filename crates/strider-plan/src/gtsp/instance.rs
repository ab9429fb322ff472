//! The (G)TSP instance the solver takes: vertices, their sets and a dense cost matrix.

use std::fmt;

use thiserror::Error;

/// Largest tour cost the solver works with: `i64::MAX / 8` (≈ 1.15·10¹⁸). Every tour of an
/// instance whose vertex count times its largest arc cost stays below it has a representable
/// cost, and the solver's move evaluations (sums and differences of a few tour-length terms)
/// keep a factor of 8 of headroom. [`Instance::check_costs`] enforces it.
pub const MAX_TOUR_COST: i64 = i64::MAX / 8;

/// Dense row-major integer cost matrix: `get(i, j)` is the cost of going
/// from vertex `i` to vertex `j`.
#[derive(Clone, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
pub struct CostMatrix {
    n: usize,
    data: Vec<i64>,
}

impl fmt::Debug for CostMatrix {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "CostMatrix({}x{})", self.n, self.n)
    }
}

impl CostMatrix {
    /// Builds a matrix from row-major data of length `n * n`.
    ///
    /// # Panics
    /// If `data.len() != n * n`.
    pub fn new(n: usize, data: Vec<i64>) -> Self {
        assert_eq!(data.len(), n * n, "cost matrix must have n*n entries");
        Self { n, data }
    }

    /// Builds a matrix by evaluating `f(i, j)` for every pair.
    pub fn from_fn(n: usize, mut f: impl FnMut(usize, usize) -> i64) -> Self {
        let mut data = Vec::with_capacity(n * n);
        for i in 0..n {
            for j in 0..n {
                data.push(f(i, j));
            }
        }
        Self { n, data }
    }

    /// Number of vertices.
    pub fn n(&self) -> usize {
        self.n
    }

    /// Cost of the arc `i -> j`.
    #[inline]
    pub fn get(&self, i: usize, j: usize) -> i64 {
        self.data[i * self.n + j]
    }

    /// Sets the cost of the arc `i -> j`.
    pub fn set(&mut self, i: usize, j: usize, c: i64) {
        self.data[i * self.n + j] = c;
    }

    /// Row `i`: costs of the arcs leaving `i`.
    pub fn row(&self, i: usize) -> &[i64] {
        &self.data[i * self.n..(i + 1) * self.n]
    }

    /// The arc `(i, j)`, `i != j`, with the largest absolute cost, or `None` for fewer than two
    /// vertices. The diagonal is never part of a g-tour and is ignored.
    pub fn largest_arc(&self) -> Option<(usize, usize, i64)> {
        let mut best: Option<(usize, usize, i64)> = None;
        for i in 0..self.n {
            for (j, &c) in self.row(i).iter().enumerate() {
                if i != j && best.is_none_or(|b| c.unsigned_abs() > b.2.unsigned_abs()) {
                    best = Some((i, j, c));
                }
            }
        }
        best
    }

    /// True if `get(i, j) == get(j, i)` for all pairs.
    pub fn is_symmetric(&self) -> bool {
        is_symmetric(&self.data, self.n)
    }
}

/// Tile side of [`is_symmetric`] and [`transpose`]: two 64 × 64 tiles of `i64` (64 KiB) stay
/// in cache, where a plain column walk of a large matrix misses it on every element.
const TILE: usize = 64;

/// True if the row-major n × n matrix `d` equals its transpose.
pub(crate) fn is_symmetric(d: &[i64], n: usize) -> bool {
    for bi in (0..n).step_by(TILE) {
        for bj in (0..=bi).step_by(TILE) {
            for i in bi..(bi + TILE).min(n) {
                for j in bj..(bj + TILE).min(i) {
                    if d[i * n + j] != d[j * n + i] {
                        return false;
                    }
                }
            }
        }
    }
    true
}

/// The transpose of the row-major n × n matrix `d`.
pub(crate) fn transpose(d: &[i64], n: usize) -> Vec<i64> {
    let mut t = vec![0i64; n * n];
    for bi in (0..n).step_by(TILE) {
        for bj in (0..n).step_by(TILE) {
            for i in bi..(bi + TILE).min(n) {
                for j in bj..(bj + TILE).min(n) {
                    t[j * n + i] = d[i * n + j];
                }
            }
        }
    }
    t
}

/// A (G)TSP instance: `n` vertices, a partition (or sub-partition) of them
/// into `sets`, and a dense cost matrix.
#[derive(Clone, Debug, serde::Serialize, serde::Deserialize)]
pub struct Instance {
    /// Instance name (`NAME` of the file).
    pub name: String,
    /// Number of vertices; vertices are `0..n`.
    pub n: usize,
    /// The vertex sets (clusters). A g-tour visits exactly one vertex of each.
    pub sets: Vec<Vec<usize>>,
    /// Arc costs.
    pub dist: CostMatrix,
    /// True if `dist` is symmetric.
    pub symmetric: bool,
}

/// Errors of [`Instance::new`] and of tour checks.
#[derive(Debug, Error, PartialEq, Eq)]
pub enum InstanceError {
    /// The matrix dimension differs from `n`.
    #[error("cost matrix is {got}x{got}, expected {expected}x{expected}")]
    MatrixSize {
        /// Expected dimension.
        expected: usize,
        /// Actual dimension.
        got: usize,
    },
    /// A set has no vertex.
    #[error("set {set} has no vertex")]
    EmptySet {
        /// 0-based set index.
        set: usize,
    },
    /// A vertex index is `>= n`.
    #[error("vertex {vertex} out of range (n = {n})")]
    VertexOutOfRange {
        /// The vertex.
        vertex: usize,
        /// Number of vertices.
        n: usize,
    },
    /// A vertex belongs to two sets.
    #[error("vertex {vertex} is in sets {first} and {second}")]
    VertexInTwoSets {
        /// The vertex.
        vertex: usize,
        /// First set.
        first: usize,
        /// Second set.
        second: usize,
    },
    /// A vertex belongs to no set.
    #[error("vertex {vertex} is in no set")]
    VertexInNoSet {
        /// The vertex.
        vertex: usize,
    },
    /// Arc costs so large that a tour's cost could overflow.
    #[error(
        "arc {from} -> {to} costs {cost}; with {n} vertices a tour could cost up to {n} × {cost}, \
         more than the limit {limit} (MAX_TOUR_COST): scale the costs down"
    )]
    CostTooLarge {
        /// 0-based tail of the most expensive arc.
        from: usize,
        /// 0-based head.
        to: usize,
        /// Its cost.
        cost: i64,
        /// Number of vertices.
        n: usize,
        /// [`MAX_TOUR_COST`].
        limit: i64,
    },
    /// A tour visits a set twice or misses one.
    #[error("tour is infeasible: {0}")]
    InfeasibleTour(String),
}

impl Instance {
    /// Builds an instance. Every set must be non-empty and no vertex may be
    /// in two sets; vertices in no set are allowed (the solver ignores them).
    pub fn new(
        name: impl Into<String>,
        sets: Vec<Vec<usize>>,
        dist: CostMatrix,
    ) -> Result<Self, InstanceError> {
        let n = dist.n();
        let mut owner = vec![usize::MAX; n];
        for (s, set) in sets.iter().enumerate() {
            if set.is_empty() {
                return Err(InstanceError::EmptySet { set: s });
            }
            for &v in set {
                if v >= n {
                    return Err(InstanceError::VertexOutOfRange { vertex: v, n });
                }
                if owner[v] != usize::MAX {
                    return Err(InstanceError::VertexInTwoSets {
                        vertex: v,
                        first: owner[v],
                        second: s,
                    });
                }
                owner[v] = s;
            }
        }
        let symmetric = dist.is_symmetric();
        Ok(Self {
            name: name.into(),
            n,
            sets,
            dist,
            symmetric,
        })
    }

    /// A plain TSP: every vertex is its own set.
    pub fn tsp(name: impl Into<String>, dist: CostMatrix) -> Self {
        let sets = (0..dist.n()).map(|v| vec![v]).collect();
        Self::new(name, sets, dist).expect("singleton sets are valid")
    }

    /// Number of sets.
    pub fn num_sets(&self) -> usize {
        self.sets.len()
    }

    /// `set_of()[v]` is the set containing `v`, if any.
    pub fn set_of(&self) -> Vec<Option<usize>> {
        let mut owner = vec![None; self.n];
        for (s, set) in self.sets.iter().enumerate() {
            for &v in set {
                owner[v] = Some(s);
            }
        }
        owner
    }

    /// Checks that no tour can overflow: the vertex count times the largest arc cost (in
    /// absolute value) must not exceed [`MAX_TOUR_COST`].
    pub fn check_costs(&self) -> Result<(), InstanceError> {
        let Some((from, to, cost)) = self.dist.largest_arc() else {
            return Ok(());
        };
        let worst = (self.n as u128).saturating_mul(u128::from(cost.unsigned_abs()));
        if worst > MAX_TOUR_COST as u128 {
            return Err(InstanceError::CostTooLarge {
                from,
                to,
                cost,
                n: self.n,
                limit: MAX_TOUR_COST,
            });
        }
        Ok(())
    }

    /// Cost of the closed tour `tour[0] -> tour[1] -> ... -> tour[0]`
    /// (0 for fewer than two vertices). Saturates at `i64::MIN` / `i64::MAX`, which no tour of
    /// an instance that passes [`Instance::check_costs`] reaches.
    pub fn tour_cost(&self, tour: &[usize]) -> i64 {
        if tour.len() < 2 {
            return 0;
        }
        self.path_cost(tour)
            .saturating_add(self.dist.get(tour[tour.len() - 1], tour[0]))
    }

    /// Cost of the open path `tour[0] -> ... -> tour[last]`; saturates as
    /// [`Instance::tour_cost`].
    pub fn path_cost(&self, tour: &[usize]) -> i64 {
        tour.windows(2)
            .fold(0i64, |c, w| c.saturating_add(self.dist.get(w[0], w[1])))
    }

    /// Checks that `tour` visits exactly one vertex of every set.
    pub fn check_tour(&self, tour: &[usize]) -> Result<(), InstanceError> {
        let owner = self.set_of();
        let mut seen = vec![false; self.sets.len()];
        for &v in tour {
            if v >= self.n {
                return Err(InstanceError::VertexOutOfRange {
                    vertex: v,
                    n: self.n,
                });
            }
            let Some(s) = owner[v] else {
                return Err(InstanceError::InfeasibleTour(format!(
                    "vertex {v} is in no set"
                )));
            };
            if seen[s] {
                return Err(InstanceError::InfeasibleTour(format!(
                    "set {s} visited twice"
                )));
            }
            seen[s] = true;
        }
        if let Some(s) = seen.iter().position(|&b| !b) {
            return Err(InstanceError::InfeasibleTour(format!(
                "set {s} not visited"
            )));
        }
        Ok(())
    }
}
