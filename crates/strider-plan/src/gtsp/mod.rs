//! Generalized Traveling Salesman Problem solver.
//!
//! Given sets (clusters) of vertices and arc costs, find a cycle (or, for
//! exploration, a path from the robot's vertex) that visits exactly one
//! vertex of every set at minimum cost. Costs may be asymmetric.
//!
//! # Algorithm
//!
//! The design follows the large neighbourhood search of GLNS (Smith &
//! Imeson, "GLNS: An effective large neighborhood search heuristic for the
//! Generalized Traveling Salesman Problem", Computers & OR 87, 2017), written
//! from the published description, with a stronger local search in the
//! spirit of Karapetyan & Gutin ("Efficient local search algorithms for
//! known and new neighborhoods for the GTSP", EJOR 219, 2012):
//!
//! * `instance`: the instance as callers give it ([`Instance`]: vertices,
//!   sets, a dense [`CostMatrix`]), also what the TSPLIB reader produces.
//! * `problem`: the instance in solver form (sets as contiguous vertex
//!   ranges, row and column cost slices, set-to-set distances); open tours
//!   become closed tours with free arcs into the start vertex.
//! * `insertion_deletion`: removal (random, segment, related, worst) and
//!   insertion (random, nearest, farthest, cheapest order; cheapest position
//!   and vertex; optional noise) operators.
//! * `tour_optimizations`: cluster optimisation (optimal vertex per set
//!   for a fixed set order by a shortest path through the layered graph) and
//!   a don't-look-bit local search with move-opt, 2-opt and or-opt, exact for
//!   asymmetric costs.
//! * `adaptive_powers`: adaptive operator weights.
//! * `lns`: the trial / iteration loop with simulated-annealing acceptance.
//! * `exact`: Held–Karp dynamic programming for small instances.
//! * `parameter_defaults`: parameters and presets.
//!
//! Runs are deterministic for a seed; only the time limit depends on the
//! clock.

pub(crate) mod adaptive_powers;
pub(crate) mod exact;
pub(crate) mod insertion_deletion;
mod instance;
pub(crate) mod lns;
pub(crate) mod parameter_defaults;
pub(crate) mod problem;

/// Largest vertex count the solver takes (its tables grow with the square of it and must fit
/// [`crate::MEMORY_LIMIT_BYTES`]); about 12 000.
pub fn max_solver_vertices() -> u64 {
    Problem::max_vertices()
}
pub(crate) mod tour_optimizations;

use std::time::Instant;

use serde::{Deserialize, Serialize};
use thiserror::Error;

pub use instance::{CostMatrix, Instance, InstanceError, MAX_TOUR_COST};
pub use parameter_defaults::{Mode, SolverParams};

use crate::memory::{self, MemoryError};
use parameter_defaults::Settings;
use problem::Problem;

/// Largest estimated Held–Karp work ([`exact::work`]) solved exactly.
const EXACT_WORK_LIMIT: f64 = 3.0e7;
/// Largest number of sets solved exactly.
const EXACT_MAX_SETS: usize = 12;

/// A solution.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Solution {
    /// One vertex per set, in visiting order. Starts at the open/fixed start
    /// vertex if one was given, otherwise at the vertex of set 0.
    pub tour: Vec<usize>,
    /// Cost: closed-tour cost, or open-path cost (no return arc) when
    /// `open` was set.
    pub cost: i64,
    /// Wall-clock time in seconds.
    pub time_s: f64,
    /// LNS iterations performed (0 for the exact solver).
    pub iterations: u64,
    /// Trials performed.
    pub trials: usize,
    /// LNS iterations (counted over all trials) done when the returned tour was found: the
    /// rest of `iterations` only confirmed it (0 for the exact solver, or when the first local
    /// search found it).
    #[serde(default)]
    pub best_iteration: u64,
    /// True if the tour is proven optimal (exact solver).
    pub optimal: bool,
}

/// Invalid solver input.
#[derive(Debug, Error, PartialEq, Eq)]
pub enum SolveError {
    /// A start vertex is `>= n`.
    #[error("start vertex {vertex} out of range (n = {n})")]
    VertexOutOfRange {
        /// The vertex.
        vertex: usize,
        /// Number of vertices.
        n: usize,
    },
    /// A start vertex belongs to no set.
    #[error("start vertex {0} is in no set")]
    StartNotInSet(usize),
    /// A set is empty.
    #[error("set {0} is empty")]
    EmptySet(usize),
    /// A solver parameter out of its range.
    #[error("{0}")]
    BadParameter(String),
    /// Arc costs whose tour sums could overflow.
    #[error(transparent)]
    Costs(InstanceError),
    /// The solver's dense tables would not fit in memory.
    #[error(transparent)]
    TooLarge(MemoryError),
}

/// Checks what [`solve`] needs of its input before it allocates anything.
fn check_input(instance: &Instance, params: &SolverParams) -> Result<(), SolveError> {
    // +inf means "no time limit" (the iteration limits end the run).
    if params.time_limit_s.is_nan() || params.time_limit_s <= 0.0 {
        return Err(SolveError::BadParameter(format!(
            "time_limit_s = {}: must be a number of seconds > 0",
            params.time_limit_s
        )));
    }
    if let Some(s) = instance.sets.iter().position(|s| s.is_empty()) {
        return Err(SolveError::EmptySet(s));
    }
    if let Some(v) = instance.sets.iter().flatten().find(|&&v| v >= instance.n) {
        return Err(SolveError::VertexOutOfRange {
            vertex: *v,
            n: instance.n,
        });
    }
    if instance.dist.n() != instance.n {
        return Err(SolveError::Costs(InstanceError::MatrixSize {
            expected: instance.n,
            got: instance.dist.n(),
        }));
    }
    memory::check(
        Problem::estimate_bytes(instance),
        &format!(
            "solving {} sets over {} vertices (dense vertex and set tables)",
            instance.sets.len(),
            instance.n
        ),
        &format!(
            "the solver's tables grow with the square of the vertex count: use at most about \
             {} vertices",
            Problem::max_vertices()
        ),
    )
    .map_err(SolveError::TooLarge)?;
    instance.check_costs().map_err(SolveError::Costs)
}

/// Solves the GTSP instance. See the module docs.
pub fn solve(instance: &Instance, params: &SolverParams) -> Result<Solution, SolveError> {
    let start = Instant::now();
    check_input(instance, params)?;
    let anchor = params.open.or(params.fixed_start);
    if let Some(a) = anchor {
        if a >= instance.n {
            return Err(SolveError::VertexOutOfRange {
                vertex: a,
                n: instance.n,
            });
        }
        if !instance.sets.iter().any(|s| s.contains(&a)) {
            return Err(SolveError::StartNotInSet(a));
        }
    }
    let open = params.open.is_some();
    if instance.sets.is_empty() {
        return Ok(Solution {
            tour: Vec::new(),
            cost: 0,
            time_s: start.elapsed().as_secs_f64(),
            iterations: 0,
            trials: 0,
            best_iteration: 0,
            optimal: true,
        });
    }
    let p = Problem::new(instance, anchor, open);

    let (tour, iterations, trials, best_iteration, optimal) =
        if params.use_exact && p.m <= EXACT_MAX_SETS && exact::work(&p) <= EXACT_WORK_LIMIT {
            let (t, _) = exact::solve(&p);
            (t, 0, 0, 0, true)
        } else {
            let settings = Settings::new(params, p.m);
            let warm = params
                .warm_start
                .as_ref()
                .map(|w| warm_tour(&p, instance, w));
            let r = lns::search(&p, &settings, params.seed, warm, start, params.time_limit_s);
            (r.tour, r.iterations, r.trials, r.best_iteration, false)
        };
    let internal_cost = p.tour_cost(&tour);
    // Rotate and map back to original vertices.
    let first = match p.anchor {
        Some(a) => tour.iter().position(|&v| v == a).unwrap(),
        None => tour.iter().position(|&v| p.set_of(v) == 0).unwrap(),
    };
    let tour: Vec<usize> = (0..tour.len())
        .map(|i| p.orig[tour[(first + i) % tour.len()] as usize])
        .collect();
    let cost = if open {
        instance.path_cost(&tour)
    } else {
        instance.tour_cost(&tour)
    };
    debug_assert_eq!(cost, internal_cost);
    Ok(Solution {
        tour,
        cost,
        time_s: start.elapsed().as_secs_f64(),
        iterations,
        trials,
        best_iteration,
        optimal,
    })
}

/// Repairs a previous tour for the current sets: keeps the first valid
/// vertex of every set in order, then inserts the missing sets cheaply.
fn warm_tour(p: &Problem, instance: &Instance, prev: &[usize]) -> Vec<u32> {
    let mut internal = vec![u32::MAX; instance.n];
    for (i, &v) in p.orig.iter().enumerate() {
        internal[v] = i as u32;
    }
    let mut seen = vec![false; p.m];
    let mut tour = Vec::with_capacity(p.m);
    for &v in prev {
        if v < instance.n && internal[v] != u32::MAX {
            let iv = internal[v];
            let s = p.set_of(iv);
            if !seen[s] {
                seen[s] = true;
                tour.push(iv);
            }
        }
    }
    let mut pending: Vec<u32> = (0..p.m as u32).filter(|&s| !seen[s as usize]).collect();
    let mut ops = insertion_deletion::Operators::default();
    let mut rng = <rand::rngs::ChaCha8Rng as rand::SeedableRng>::seed_from_u64(0);
    ops.insert(
        p,
        &mut tour,
        &mut pending,
        insertion_deletion::InsertOrder::Cheapest,
        0,
        &mut rng,
    );
    tour
}
