//! The figures of one seed's tours that MartinCorke reports: first and converged tour energy,
//! the drop, the convergence and overtaking tours, and the acceptance criteria.

use serde::Serialize;

use super::{MAX_CONVERGENCE_TOUR, MIN_DROP, OVERTAKE_BEFORE, SeedRun};
use crate::stats::mean;

/// Figures of one seed derived from its runs.
#[derive(Clone, Debug)]
pub struct SeedFigures {
    /// Energy of tour 1, J.
    pub first_j: f64,
    /// Motive energy of tour 1, J.
    pub first_motive_j: f64,
    /// Mean energy of the converged tours, J.
    pub converged_j: f64,
    /// Their mean motive energy, J.
    pub converged_motive_j: f64,
    /// Drop of the converged tour against the always-shortest mean.
    pub drop_vs_shortest: f64,
    /// The first tour counted as converged.
    pub converged_from: usize,
    /// The tour from which the plan stopped changing.
    pub converged: Option<usize>,
    /// Drop of the converged tour against tour 1.
    pub drop: f64,
    /// The first tour from which exploring stays cheaper in total to the end.
    pub overtake: Option<usize>,
    /// Tour 1 drives the shortest path.
    pub first_is_shortest: bool,
    /// Mean energy of the always-shortest tours, J.
    pub shortest_mean_j: f64,
    /// Mean energy of the tours on the true costs, J.
    pub known_mean_j: f64,
    /// Their drop against the always-shortest mean.
    pub known_drop: f64,
    /// Cumulative energy after each tour: (exploring, always-shortest), J.
    pub cumulative: Vec<(f64, f64)>,
}

/// The acceptance criteria of one seed.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct Acceptance {
    /// Tour 1 drives the shortest path.
    pub first_tour_is_shortest: bool,
    /// The energy falls by at least 30 %.
    pub drop_at_least_30_percent: bool,
    /// The plan converges within 10 tours.
    pub converged_within_10_tours: bool,
    /// The cumulative energy overtakes always-shortest before tour 10.
    pub overtakes_before_tour_10: bool,
}

fn mean_of(v: impl Iterator<Item = f64>) -> f64 {
    mean(&v.collect::<Vec<f64>>()).unwrap_or(f64::NAN)
}

impl SeedFigures {
    /// The figures of one seed's runs.
    pub fn of(r: &SeedRun) -> Self {
        let t = &r.outcome.tours;
        let e: Vec<f64> = t.iter().map(|x| x.measured.energy_j).collect();
        let s: Vec<f64> = r.shortest.iter().map(|x| x.measured.energy_j).collect();
        let n = e.len();
        // Converged: the tours from convergence on drive one plan; without convergence, the
        // last five tours stand in.
        let from = r
            .outcome
            .convergence_tour
            .unwrap_or(n.saturating_sub(4).max(1));
        let converged_j = mean_of(e[from - 1..].iter().copied());
        let converged_motive_j = mean_of(t[from - 1..].iter().map(|x| x.measured.motive_energy_j));
        let cumulative: Vec<(f64, f64)> = e
            .iter()
            .zip(&s)
            .scan((0.0, 0.0), |acc, (a, b)| {
                *acc = (acc.0 + a, acc.1 + b);
                Some(*acc)
            })
            .collect();
        let first_is_shortest = t
            .first()
            .zip(r.shortest.first())
            .is_some_and(|(x, y)| x.plan == y.plan);
        let known_mean_j = mean_of(r.known.iter().map(|x| x.measured.energy_j));
        let shortest_mean_j = mean_of(s.iter().copied());
        Self {
            first_j: e[0],
            first_motive_j: t[0].measured.motive_energy_j,
            converged_j,
            converged_motive_j,
            drop_vs_shortest: 1.0 - converged_j / shortest_mean_j,
            converged_from: from,
            converged: r.outcome.convergence_tour,
            drop: 1.0 - converged_j / e[0],
            overtake: overtake(&cumulative),
            first_is_shortest,
            shortest_mean_j,
            known_mean_j,
            known_drop: 1.0 - known_mean_j / shortest_mean_j,
            cumulative,
        }
    }

    /// The acceptance criteria.
    pub fn acceptance(&self) -> Acceptance {
        Acceptance {
            first_tour_is_shortest: self.first_is_shortest,
            drop_at_least_30_percent: self.drop >= MIN_DROP,
            converged_within_10_tours: self.converged.is_some_and(|c| c <= MAX_CONVERGENCE_TOUR),
            overtakes_before_tour_10: self.overtake.is_some_and(|k| k < OVERTAKE_BEFORE),
        }
    }
}

/// The first tour from which exploring stays strictly cheaper in total to the end.
fn overtake(cumulative: &[(f64, f64)]) -> Option<usize> {
    let mut overtake = None;
    for k in (0..cumulative.len()).rev() {
        if cumulative[k].0 < cumulative[k].1 {
            overtake = Some(k + 1);
        } else {
            break;
        }
    }
    overtake
}

/// A tour number, or "never".
pub(crate) fn tour_or_never(v: Option<usize>) -> String {
    v.map_or("never".into(), |k| k.to_string())
}
