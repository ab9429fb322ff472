//! The large-neighbourhood-search driver (simulated-annealing acceptance).
//!
//! One *trial*: start from a tour (construction, warm start, or the best
//! tour so far), improve it with the local search, then iterate
//!
//! 1. draw a removal operator, an insertion order and a noise level with
//!    adaptive weights ([`super::adaptive_powers`]) and a number `k` of sets
//!    to remove (uniform in `1..=max_remove`);
//! 2. destroy and repair a copy of the current tour
//!    ([`super::insertion_deletion`]);
//! 3. run the local search on the sets whose tour neighbours changed, then
//!    cluster optimisation ([`super::tour_optimizations`]);
//! 4. accept the candidate if it is better, or with probability
//!    `exp(−Δ/T)` (Kirkpatrick et al. 1983); `T` decreases geometrically
//!    from `temp_start`·(mean edge cost of the initial tour) to
//!    `temp_end` times that over the trial's iterations (a restart from the
//!    best tour starts at `restart_temp` times that).
//!
//! A trial ends after its iteration budget, after `stall` iterations without
//! improving its best tour, or at the time limit. Trials alternate between a
//! fresh randomised construction and a restart from the best tour found. The
//! search ends after its trials, at the time limit, or once `stall_trials`
//! trials in a row have not improved the best tour ([`StalledTrials`]).

use std::time::Instant;

use rand::rngs::ChaCha8Rng;
use rand::{RngExt, SeedableRng};

use super::adaptive_powers::{Adaptive, Outcome};
use super::insertion_deletion::{InsertOrder, Operators, Removal};
use super::parameter_defaults::Settings;
use super::problem::Problem;
use super::tour_optimizations::LocalSearch;

/// Result of the search.
pub(crate) struct SearchResult {
    pub tour: Vec<u32>,
    pub iterations: u64,
    pub trials: usize,
    /// Iterations (over all trials) done when the returned tour was found.
    pub best_iteration: u64,
}

const NOISE_LEVELS: [f64; 3] = [0.0, 0.1, 0.4];

pub(crate) fn search(
    p: &Problem,
    settings: &Settings,
    seed: u64,
    warm: Option<Vec<u32>>,
    start: Instant,
    time_limit_s: f64,
) -> SearchResult {
    let mut search = Search::new(p, settings, seed, start, time_limit_s);
    let mut warm = warm;
    let mut stalled = StalledTrials::default();
    for trial in 0..settings.trials {
        if trial > 0 && search.out_of_time() {
            break;
        }
        if stalled.count >= settings.stall_trials {
            break;
        }
        search.trials += 1;
        // Mirrors `starting_tour`: odd trials restart from the best tour.
        let restart = warm.is_none() && trial % 2 == 1 && search.best.is_some();
        let tour = search.starting_tour(trial, warm.take());
        let go_on = search.run_trial(tour, restart);
        stalled.after_trial(search.best.as_ref().map(|b| b.1));
        if !go_on {
            break;
        }
    }
    let (tour, _) = search.best.expect("at least one trial");
    SearchResult {
        tour,
        iterations: search.iterations,
        trials: search.trials,
        best_iteration: search.best_iteration,
    }
}

/// Consecutive trials that ended without improving the best tour: the search's stopping rule
/// (a trial that merely finds the best tour again does not count as an improvement).
#[derive(Debug, Default)]
pub(crate) struct StalledTrials {
    /// Best cost after the last trial (`None` before the first).
    best: Option<i64>,
    /// Trials in a row that left it unchanged.
    pub count: usize,
}

impl StalledTrials {
    /// Records the best cost after a trial.
    pub fn after_trial(&mut self, best: Option<i64>) {
        let improved = match (self.best, best) {
            (Some(before), Some(now)) => now < before,
            (None, _) => true,
            (Some(_), None) => false,
        };
        self.count = if improved { 0 } else { self.count + 1 };
        self.best = best.or(self.best);
    }
}

/// The operators drawn for one iteration (indices into [`Removal::ALL`],
/// [`InsertOrder::ALL`] and the noise levels).
struct Draw {
    removal: usize,
    insertion: usize,
    noise: usize,
}

/// The current tour of a trial and its annealing schedule.
struct Trial {
    cur: Vec<u32>,
    cur_cost: i64,
    /// Cost of the trial's best tour.
    best: i64,
    since_improvement: u64,
    /// Mean edge cost of the trial's initial tour: the unit of the
    /// temperature, the noise and the cluster-optimisation window.
    mean_edge: f64,
    temp: f64,
    cooling: f64,
}

/// The state of the whole search: generator, operators and their adaptive
/// weights, the best tour so far, counters and scratch space.
struct Search<'a> {
    p: &'a Problem,
    settings: &'a Settings,
    start: Instant,
    time_limit_s: f64,
    rng: ChaCha8Rng,
    ops: Operators,
    ls: LocalSearch,
    removal_w: Adaptive,
    insert_w: Adaptive,
    noise_w: Adaptive,
    best: Option<(Vec<u32>, i64)>,
    iterations: u64,
    trials: usize,
    /// `iterations` when the best tour was found.
    best_iteration: u64,
    removed: Vec<u32>,
    /// Set successor and predecessor of every set in the current tour.
    succ: Vec<u32>,
    pred: Vec<u32>,
    /// Sets whose tour neighbours a move changed.
    dirty: Vec<u32>,
}

impl<'a> Search<'a> {
    fn new(
        p: &'a Problem,
        settings: &'a Settings,
        seed: u64,
        start: Instant,
        time_limit_s: f64,
    ) -> Self {
        let mut ops = Operators::default();
        let mut ls = LocalSearch::new(p.m);
        ls.nn = settings.ls_nn;
        // No deadline for an infinite or unrepresentable limit.
        ls.stop_at = std::time::Duration::try_from_secs_f64(time_limit_s)
            .ok()
            .and_then(|d| start.checked_add(d));
        ops.insert_nn = settings.insert_nn;
        Search {
            p,
            settings,
            start,
            time_limit_s,
            rng: ChaCha8Rng::seed_from_u64(seed),
            ops,
            ls,
            removal_w: Adaptive::new(Removal::ALL.len()),
            insert_w: Adaptive::new(InsertOrder::ALL.len()),
            noise_w: Adaptive::new(NOISE_LEVELS.len()),
            best: None,
            iterations: 0,
            trials: 0,
            best_iteration: 0,
            removed: Vec::new(),
            succ: vec![0u32; p.m],
            pred: vec![0u32; p.m],
            dirty: Vec::new(),
        }
    }

    fn out_of_time(&self) -> bool {
        self.start.elapsed().as_secs_f64() >= self.time_limit_s
    }

    /// Whether the best tour costs at most the target (never without one).
    fn target_met(&self) -> bool {
        matches!((self.settings.target_cost, &self.best), (Some(t), Some((_, c))) if *c <= t)
    }

    /// The tour a trial starts from: the warm start, on odd trials the best
    /// tour so far, else a random construction.
    fn starting_tour(&mut self, trial: usize, warm: Option<Vec<u32>>) -> Vec<u32> {
        if let Some(w) = warm {
            w
        } else if trial % 2 == 1
            && let Some((b, _)) = &self.best
        {
            b.clone()
        } else {
            let p = self.p;
            let mut pending: Vec<u32> = (0..p.m as u32).collect();
            let mut t = Vec::with_capacity(p.m);
            self.ops.insert(
                p,
                &mut t,
                &mut pending,
                InsertOrder::Random,
                0,
                &mut self.rng,
            );
            t
        }
    }

    /// Keeps `tour` as the best one when it is cheaper.
    fn offer_best(&mut self, tour: &[u32], cost: i64) {
        if self.best.as_ref().is_none_or(|b| cost < b.1) {
            self.best = Some((tour.to_vec(), cost));
            self.best_iteration = self.iterations;
        }
    }

    /// One trial from `tour`: local search, then the iterations; a `restart` from the best
    /// tour starts cooler (`restart_temp`). False when the search ends: the instance is too
    /// small to iterate on, or the best tour meets the target cost.
    fn run_trial(&mut self, mut tour: Vec<u32>, restart: bool) -> bool {
        let (p, settings) = (self.p, self.settings);
        let c0 = p.tour_cost(&tour);
        let cost = self.ls.run(p, &mut tour, c0, None, i64::MAX);
        debug_assert_eq!(cost, p.tour_cost(&tour));
        self.offer_best(&tour, cost);
        if p.m < 4 || self.target_met() {
            return false;
        }
        let mean_edge = (cost as f64 / p.m as f64).max(1.0);
        let t0 =
            settings.temp_start * mean_edge * if restart { settings.restart_temp } else { 1.0 };
        let t_end = t0 * settings.temp_end;
        let mut trial = Trial {
            cur: tour,
            cur_cost: cost,
            best: cost,
            since_improvement: 0,
            mean_edge,
            temp: t0,
            cooling: (t_end / t0).powf(1.0 / settings.iterations.max(1) as f64),
        };
        let mut cand = Vec::with_capacity(p.m);
        for it in 0..settings.iterations {
            if it % 16 == 0 && self.out_of_time() {
                break;
            }
            if trial.since_improvement >= settings.stall {
                break;
            }
            self.iterations += 1;
            trial.since_improvement += 1;
            trial.temp *= trial.cooling;
            let (draw, c) = self.destroy_and_repair(&trial, &mut cand);
            let outcome = self.judge(&mut trial, c);
            if outcome != Outcome::Rejected {
                std::mem::swap(&mut trial.cur, &mut cand);
                trial.cur_cost = c;
                self.offer_best(&trial.cur, c);
            }
            self.learn_weights(&draw, outcome);
            if self.target_met() {
                return false;
            }
        }
        true
    }

    /// Steps 1–3: draws the operators, destroys and repairs a copy of the
    /// current tour into `cand` and improves it; returns the draw and the
    /// candidate's cost.
    fn destroy_and_repair(&mut self, trial: &Trial, cand: &mut Vec<u32>) -> (Draw, i64) {
        let (p, settings) = (self.p, self.settings);
        let draw = Draw {
            removal: self.removal_w.pick(&mut self.rng),
            insertion: self.insert_w.pick(&mut self.rng),
            noise: self.noise_w.pick(&mut self.rng),
        };
        let k = self.rng.random_range(1..=settings.max_remove);
        let noise = (NOISE_LEVELS[draw.noise] * trial.mean_edge) as i64;
        self.record_neighbours(&trial.cur);
        cand.clear();
        cand.extend_from_slice(&trial.cur);
        self.ops.remove(
            p,
            cand,
            k,
            Removal::ALL[draw.removal],
            &mut self.rng,
            &mut self.removed,
        );
        self.ops.insert(
            p,
            cand,
            &mut self.removed,
            InsertOrder::ALL[draw.insertion],
            noise,
            &mut self.rng,
        );
        self.mark_dirty(cand);
        let c = p.tour_cost(cand);
        let co_above = trial.cur_cost
            + (settings.co_window * trial.temp) as i64
            + (settings.co_slack * trial.mean_edge) as i64;
        let c = self.ls.run(p, cand, c, Some(&self.dirty), co_above);
        debug_assert_eq!(c, p.tour_cost(cand));
        (draw, c)
    }

    /// Records the set neighbours of every set in `tour`.
    fn record_neighbours(&mut self, tour: &[u32]) {
        let p = self.p;
        let Some(&last) = tour.last() else {
            return;
        };
        let mut prev = p.set_of(last);
        for &v in tour {
            let s = p.set_of(v);
            self.succ[prev] = s as u32;
            self.pred[s] = prev as u32;
            prev = s;
        }
    }

    /// Collects the sets of `cand` whose neighbours differ from the recorded
    /// ones: where the local search must look.
    fn mark_dirty(&mut self, cand: &[u32]) {
        let p = self.p;
        self.dirty.clear();
        let l = cand.len();
        for i in 0..l {
            let s = p.set_of(cand[i]);
            let nx = p.set_of(cand[if i + 1 == l { 0 } else { i + 1 }]) as u32;
            let pv = p.set_of(cand[if i == 0 { l - 1 } else { i - 1 }]) as u32;
            if self.succ[s] != nx || self.pred[s] != pv {
                self.dirty.push(s as u32);
            }
        }
    }

    /// Step 4: the outcome of a candidate of cost `c` against the current
    /// tour (simulated-annealing acceptance).
    fn judge(&mut self, trial: &mut Trial, c: i64) -> Outcome {
        let cur_cost = trial.cur_cost;
        if c < trial.best {
            trial.best = c;
            trial.since_improvement = 0;
            Outcome::NewBest
        } else if c < cur_cost {
            Outcome::Improved
        } else if c == cur_cost
            || (c > cur_cost
                && self.rng.random::<f64>() < (-((c - cur_cost) as f64) / trial.temp).exp())
        {
            Outcome::Accepted
        } else {
            Outcome::Rejected
        }
    }

    /// Scores the drawn operators; every 100 iterations the weights move.
    fn learn_weights(&mut self, draw: &Draw, outcome: Outcome) {
        self.removal_w.record(draw.removal, outcome);
        self.insert_w.record(draw.insertion, outcome);
        self.noise_w.record(draw.noise, outcome);
        if self.iterations.is_multiple_of(100) {
            self.removal_w.update();
            self.insert_w.update();
            self.noise_w.update();
        }
    }
}

#[cfg(test)]
mod tests {
    use super::StalledTrials;

    #[test]
    fn only_a_strictly_better_best_resets_the_count_of_stalled_trials() {
        let mut s = StalledTrials::default();
        s.after_trial(Some(100));
        assert_eq!(s.count, 0, "the first trial sets the best");
        s.after_trial(Some(100));
        assert_eq!(s.count, 1, "finding the best again is no improvement");
        s.after_trial(Some(100));
        assert_eq!(s.count, 2);
        s.after_trial(Some(99));
        assert_eq!(s.count, 0);
        s.after_trial(None);
        assert_eq!(s.count, 1, "a trial without a tour improves nothing");
        s.after_trial(Some(99));
        assert_eq!(
            s.count, 2,
            "the best is remembered across a trial without a tour"
        );
    }

    #[test]
    fn a_first_trial_without_a_tour_counts_as_no_stall() {
        let mut s = StalledTrials::default();
        s.after_trial(None);
        assert_eq!(s.count, 0);
        s.after_trial(Some(5));
        assert_eq!(s.count, 0);
    }
}
