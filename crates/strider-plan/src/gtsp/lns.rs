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
//!    `temp_end` times that over the trial's iterations.
//!
//! A trial ends after its iteration budget, after `stall` iterations without
//! improving its best tour, or at the time limit. Trials alternate between a
//! fresh randomised construction and a restart from the best tour found.

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
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let mut ops = Operators::default();
    let mut ls = LocalSearch::new(p.m);
    ls.nn = settings.ls_nn;
    ops.insert_nn = settings.insert_nn;
    let out_of_time = |start: &Instant| start.elapsed().as_secs_f64() >= time_limit_s;

    let mut removal_w = Adaptive::new(Removal::ALL.len());
    let mut insert_w = Adaptive::new(InsertOrder::ALL.len());
    let mut noise_w = Adaptive::new(NOISE_LEVELS.len());

    let mut best: Option<(Vec<u32>, i64)> = None;
    let mut iterations = 0u64;
    let mut trials = 0usize;
    let mut removed = Vec::new();
    let mut succ = vec![0u32; p.m];
    let mut pred = vec![0u32; p.m];
    let mut dirty = Vec::new();
    let mut warm = warm;

    for trial in 0..settings.trials {
        if trial > 0 && out_of_time(&start) {
            break;
        }
        trials += 1;
        // Starting tour.
        let mut cur: Vec<u32> = if let Some(w) = warm.take() {
            w
        } else if trial % 2 == 1
            && let Some((b, _)) = &best
        {
            b.clone()
        } else {
            let mut pending: Vec<u32> = (0..p.m as u32).collect();
            let mut t = Vec::with_capacity(p.m);
            ops.insert(p, &mut t, &mut pending, InsertOrder::Random, 0, &mut rng);
            t
        };
        let c0 = p.tour_cost(&cur);
        let mut cur_cost = ls.run(p, &mut cur, c0, None, i64::MAX);
        debug_assert_eq!(cur_cost, p.tour_cost(&cur));
        let mut trial_best = cur_cost;
        if best.as_ref().is_none_or(|b| cur_cost < b.1) {
            best = Some((cur.clone(), cur_cost));
        }
        if p.m < 4 {
            break;
        }
        let mean_edge = (cur_cost as f64 / p.m as f64).max(1.0);
        let t0 = settings.temp_start * mean_edge;
        let t_end = t0 * settings.temp_end;
        let cooling = (t_end / t0).powf(1.0 / settings.iterations.max(1) as f64);
        let mut temp = t0;
        let mut since_improvement = 0u64;
        let mut cand = Vec::with_capacity(p.m);
        for it in 0..settings.iterations {
            if it % 16 == 0 && out_of_time(&start) {
                break;
            }
            if since_improvement >= settings.stall {
                break;
            }
            iterations += 1;
            since_improvement += 1;
            temp *= cooling;

            let ri = removal_w.pick(&mut rng);
            let ii = insert_w.pick(&mut rng);
            let ni = noise_w.pick(&mut rng);
            let k = rng.random_range(1..=settings.max_remove);
            let noise = (NOISE_LEVELS[ni] * mean_edge) as i64;

            for (i, &v) in cur.iter().enumerate() {
                let s = p.set_of(v);
                succ[s] = p.set_of(cur[(i + 1) % cur.len()]) as u32;
                pred[s] = p.set_of(cur[(i + cur.len() - 1) % cur.len()]) as u32;
            }
            cand.clear();
            cand.extend_from_slice(&cur);
            ops.remove(p, &mut cand, k, Removal::ALL[ri], &mut rng, &mut removed);
            ops.insert(
                p,
                &mut cand,
                &mut removed,
                InsertOrder::ALL[ii],
                noise,
                &mut rng,
            );
            dirty.clear();
            let l = cand.len();
            for i in 0..l {
                let s = p.set_of(cand[i]);
                let nx = p.set_of(cand[(i + 1) % l]) as u32;
                let pv = p.set_of(cand[(i + l - 1) % l]) as u32;
                if succ[s] != nx || pred[s] != pv {
                    dirty.push(s as u32);
                }
            }
            let c = p.tour_cost(&cand);
            let co_above = cur_cost
                + (settings.co_window * temp) as i64
                + (settings.co_slack * mean_edge) as i64;
            let c = ls.run(p, &mut cand, c, Some(&dirty), co_above);
            debug_assert_eq!(c, p.tour_cost(&cand));

            let outcome = if c < trial_best {
                trial_best = c;
                since_improvement = 0;
                Outcome::NewBest
            } else if c < cur_cost {
                Outcome::Improved
            } else if c == cur_cost
                || (c > cur_cost && rng.random::<f64>() < (-((c - cur_cost) as f64) / temp).exp())
            {
                Outcome::Accepted
            } else {
                Outcome::Rejected
            };
            if outcome != Outcome::Rejected {
                std::mem::swap(&mut cur, &mut cand);
                cur_cost = c;
                if best.as_ref().is_none_or(|b| c < b.1) {
                    best = Some((cur.clone(), c));
                }
            }
            removal_w.record(ri, outcome);
            insert_w.record(ii, outcome);
            noise_w.record(ni, outcome);
            if iterations.is_multiple_of(100) {
                removal_w.update();
                insert_w.update();
                noise_w.update();
            }
        }
    }
    let (tour, _) = best.expect("at least one trial");
    SearchResult {
        tour,
        iterations,
        trials,
    }
}
