//! GTSP solver tests on small generated instances.

use proptest::prelude::*;
use rand::rngs::ChaCha8Rng;
use rand::{RngExt, SeedableRng};
use strider_plan::{CostMatrix, Instance, Mode, SolveError, SolverParams, solve};

/// Random instance: `n` vertices in `m` non-empty sets, Euclidean or random
/// (possibly asymmetric) costs.
fn random_instance(seed: u64, n: usize, m: usize, kind: u8) -> Instance {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let pts: Vec<(f64, f64)> = (0..n)
        .map(|_| (rng.random_range(0.0..100.0), rng.random_range(0.0..100.0)))
        .collect();
    let dist = match kind % 3 {
        0 => CostMatrix::from_fn(n, |i, j| {
            let (dx, dy) = (pts[i].0 - pts[j].0, pts[i].1 - pts[j].1);
            (dx * dx + dy * dy).sqrt().round() as i64
        }),
        1 => {
            let mut c = CostMatrix::from_fn(n, |_, _| 0);
            for i in 0..n {
                for j in 0..i {
                    let v = rng.random_range(1..100);
                    c.set(i, j, v);
                    c.set(j, i, v);
                }
            }
            c
        }
        _ => CostMatrix::from_fn(n, |i, j| if i == j { 0 } else { rng.random_range(1..100) }),
    };
    // Sets: a random assignment with every set non-empty.
    let mut owner: Vec<usize> = (0..n)
        .map(|v| if v < m { v } else { rng.random_range(0..m) })
        .collect();
    for i in (1..n).rev() {
        let j = rng.random_range(0..=i);
        owner.swap(i, j);
    }
    let mut sets = vec![Vec::new(); m];
    for (v, &s) in owner.iter().enumerate() {
        sets[s].push(v);
    }
    Instance::new(format!("r{seed}"), sets, dist).unwrap()
}

/// Exhaustive optimum (closed, or open from `open`).
fn brute_force(inst: &Instance, open: Option<usize>) -> i64 {
    let m = inst.sets.len();
    let mut best = i64::MAX;
    // Fix the first set (or the open start); permute the others.
    let first = open.map_or(0, |s| {
        inst.sets.iter().position(|x| x.contains(&s)).unwrap()
    });
    let mut rest: Vec<usize> = (0..m).filter(|&s| s != first).collect();
    fn permute(k: usize, rest: &mut Vec<usize>, f: &mut dyn FnMut(&[usize])) {
        if k == rest.len() {
            f(rest);
            return;
        }
        for i in k..rest.len() {
            rest.swap(k, i);
            permute(k + 1, rest, f);
            rest.swap(k, i);
        }
    }
    let firsts: Vec<usize> = match open {
        Some(s) => vec![s],
        None => inst.sets[first].clone(),
    };
    permute(0, &mut rest, &mut |order: &[usize]| {
        // Enumerate vertex choices.
        let mut choice = vec![0usize; order.len()];
        loop {
            for &a in &firsts {
                let mut tour = vec![a];
                tour.extend(order.iter().zip(&choice).map(|(&s, &c)| inst.sets[s][c]));
                let c = if open.is_some() {
                    inst.path_cost(&tour)
                } else {
                    inst.tour_cost(&tour)
                };
                best = best.min(c);
            }
            let mut k = 0;
            loop {
                if k == order.len() {
                    return;
                }
                choice[k] += 1;
                if choice[k] < inst.sets[order[k]].len() {
                    break;
                }
                choice[k] = 0;
                k += 1;
            }
        }
    });
    best
}

fn heuristic(iterations: u64, seed: u64) -> SolverParams {
    SolverParams {
        use_exact: false,
        max_iterations: Some(iterations),
        seed,
        time_limit_s: 1e9,
        ..SolverParams::default()
    }
}

fn check(inst: &Instance, sol: &strider_plan::Solution, open: bool) {
    inst.check_tour(&sol.tour).unwrap();
    let c = if open {
        inst.path_cost(&sol.tour)
    } else {
        inst.tour_cost(&sol.tour)
    };
    assert_eq!(c, sol.cost);
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(48))]

    #[test]
    fn tours_are_feasible_and_costs_exact(seed in 0u64..10_000, n in 1usize..16, mfrac in 0.0f64..1.0,
                                         kind in 0u8..3, exact in any::<bool>(), open in any::<bool>()) {
        let m = 1 + ((n - 1) as f64 * mfrac) as usize;
        let inst = random_instance(seed, n, m, kind);
        let mut params = heuristic(60, seed);
        params.use_exact = exact;
        if open {
            params.open = Some((seed as usize) % n);
        }
        let sol = solve(&inst, &params).unwrap();
        check(&inst, &sol, open);
        if open {
            prop_assert_eq!(sol.tour[0], (seed as usize) % n);
        }
    }

    #[test]
    fn exact_equals_brute_force(seed in 0u64..10_000, n in 1usize..=8, mfrac in 0.0f64..1.0, kind in 0u8..3) {
        let m = 1 + ((n - 1) as f64 * mfrac) as usize;
        let inst = random_instance(seed, n, m, kind);
        let sol = solve(&inst, &SolverParams::default()).unwrap();
        prop_assert!(sol.optimal);
        check(&inst, &sol, false);
        prop_assert_eq!(sol.cost, brute_force(&inst, None));
        let open = (seed as usize) % n;
        let sol = solve(&inst, &SolverParams { open: Some(open), ..SolverParams::default() }).unwrap();
        check(&inst, &sol, true);
        prop_assert_eq!(sol.tour[0], open);
        prop_assert_eq!(sol.cost, brute_force(&inst, Some(open)));
    }
}

/// The heuristic with every trial of the default preset: its stopping rule may end the search
/// after three of the four, and on a few small random instances only the fourth finds the
/// optimum.
fn all_trials() -> SolverParams {
    SolverParams {
        use_exact: false,
        stall_trials: Some(usize::MAX),
        ..SolverParams::default()
    }
}

#[test]
fn heuristic_reaches_exact_optimum() {
    for seed in 0..12u64 {
        let n = 14 + (seed as usize % 8);
        let m = 6 + (seed as usize % 5);
        let inst = random_instance(seed, n, m, seed as u8);
        let exact = solve(&inst, &SolverParams::default()).unwrap();
        assert!(exact.optimal);
        let heur = solve(&inst, &all_trials()).unwrap();
        check(&inst, &heur, false);
        assert_eq!(heur.cost, exact.cost, "seed {seed}: heuristic vs exact");
        // Open tours too.
        let open = Some(seed as usize % n);
        let exact = solve(
            &inst,
            &SolverParams {
                open,
                ..SolverParams::default()
            },
        )
        .unwrap();
        let heur = solve(
            &inst,
            &SolverParams {
                open,
                ..all_trials()
            },
        )
        .unwrap();
        check(&inst, &heur, true);
        assert_eq!(
            heur.cost, exact.cost,
            "seed {seed}: open heuristic vs exact"
        );
    }
}

#[test]
fn the_search_ends_after_the_given_number_of_trials_without_improvement() {
    // Eight sets: the first trial finds the optimum, so every later trial stalls.
    for seed in 0..6u64 {
        let inst = random_instance(seed, 20, 8, seed as u8);
        let optimum = solve(&inst, &SolverParams::default()).unwrap().cost;
        for stall_trials in [1usize, 2, 3] {
            let p = SolverParams {
                max_trials: Some(8),
                stall_trials: Some(stall_trials),
                ..heuristic(400, seed)
            };
            let sol = solve(&inst, &p).unwrap();
            check(&inst, &sol, false);
            assert_eq!(sol.cost, optimum, "seed {seed}");
            assert!(
                sol.trials <= 1 + stall_trials,
                "seed {seed}: {} trials with stall_trials = {stall_trials}",
                sol.trials
            );
            assert!(sol.trials > stall_trials, "seed {seed}: stopped early");
        }
        // Zero is read as one; a count above the trials keeps every trial.
        let zero = solve(
            &inst,
            &SolverParams {
                max_trials: Some(8),
                stall_trials: Some(0),
                ..heuristic(400, seed)
            },
        )
        .unwrap();
        assert_eq!(zero.trials, 2, "seed {seed}");
        let all = solve(
            &inst,
            &SolverParams {
                max_trials: Some(5),
                stall_trials: Some(usize::MAX),
                ..heuristic(400, seed)
            },
        )
        .unwrap();
        assert_eq!(all.trials, 5, "seed {seed}");
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(24))]

    /// The stopping rule never runs more trials than allowed, always runs at least one, and
    /// keeps the run deterministic for a seed.
    #[test]
    fn stalled_trials_bound_the_trials(seed in 0u64..1000, n in 4usize..40, mfrac in 0.0f64..1.0,
                                       kind in 0u8..3, trials in 1usize..6, stall in 0usize..4) {
        let m = ((n as f64 * mfrac) as usize).clamp(1, n);
        let inst = random_instance(seed, n, m, kind);
        let p = SolverParams {
            max_trials: Some(trials),
            stall_trials: Some(stall),
            ..heuristic(150, seed)
        };
        let a = solve(&inst, &p).unwrap();
        check(&inst, &a, false);
        prop_assert!(a.trials >= 1 && a.trials <= trials);
        let b = solve(&inst, &p).unwrap();
        prop_assert_eq!(&a.tour, &b.tour);
        prop_assert_eq!(a.trials, b.trials);
    }
}

#[test]
fn deterministic_for_a_seed() {
    let inst = random_instance(7, 150, 40, 0);
    let a = solve(&inst, &heuristic(300, 5)).unwrap();
    let b = solve(&inst, &heuristic(300, 5)).unwrap();
    assert_eq!(a.tour, b.tour);
    assert_eq!(a.cost, b.cost);
    assert_eq!(a.iterations, b.iterations);
    let asym = random_instance(8, 120, 30, 2);
    let a = solve(&asym, &heuristic(300, 9)).unwrap();
    let b = solve(&asym, &heuristic(300, 9)).unwrap();
    assert_eq!(a.tour, b.tour);
    check(&asym, &a, false);
}

#[test]
fn open_tour_semantics() {
    // Points on a line: 0 -- 1 -- 2 -- 3 (unit spacing, each its own set).
    let dist = CostMatrix::from_fn(4, |i, j| (i as i64 - j as i64).abs() * 10);
    let inst = Instance::tsp("line", dist);
    let closed = solve(&inst, &SolverParams::default()).unwrap();
    assert_eq!(closed.cost, 60);
    let open = solve(
        &inst,
        &SolverParams {
            open: Some(0),
            ..SolverParams::default()
        },
    )
    .unwrap();
    assert_eq!(open.tour, vec![0, 1, 2, 3]);
    assert_eq!(open.cost, 30);
    let open = solve(
        &inst,
        &SolverParams {
            open: Some(1),
            use_exact: false,
            ..SolverParams::default()
        },
    )
    .unwrap();
    assert_eq!(open.tour[0], 1);
    assert_eq!(open.cost, 40, "1 -> 0 -> 2 -> 3");
    // The open start replaces the other vertices of its set.
    let inst = random_instance(3, 30, 8, 0);
    let start = inst.sets[2][0];
    let sol = solve(
        &inst,
        &SolverParams {
            open: Some(start),
            use_exact: false,
            ..SolverParams::default()
        },
    )
    .unwrap();
    assert_eq!(sol.tour[0], start);
    check(&inst, &sol, true);
    // Fixed start on a closed tour.
    let fixed = inst.sets[5][inst.sets[5].len() - 1];
    let sol = solve(
        &inst,
        &SolverParams {
            fixed_start: Some(fixed),
            use_exact: false,
            ..SolverParams::default()
        },
    )
    .unwrap();
    assert_eq!(sol.tour[0], fixed);
    check(&inst, &sol, false);
}

#[test]
fn warm_start_over_changed_sets() {
    let inst = random_instance(11, 120, 30, 0);
    let first = solve(&inst, &heuristic(400, 1)).unwrap();
    // Warm start on the same instance, fast mode: never worse than before
    // after the local search (the start tour is a local optimum already).
    let again = solve(
        &inst,
        &SolverParams {
            mode: Mode::Fast,
            warm_start: Some(first.tour.clone()),
            use_exact: false,
            max_iterations: Some(50),
            ..SolverParams::default()
        },
    )
    .unwrap();
    check(&inst, &again, false);
    assert!(again.cost <= first.cost);

    // Change the sets: drop set 0, split set 1, add garbage to the old tour.
    let mut sets: Vec<Vec<usize>> = inst.sets[1..].to_vec();
    let s1 = sets[0].clone();
    if s1.len() > 1 {
        let (a, b) = s1.split_at(s1.len() / 2);
        sets[0] = a.to_vec();
        sets.push(b.to_vec());
    }
    let changed = Instance::new("changed", sets, inst.dist.clone()).unwrap();
    let mut prev = first.tour.clone();
    prev.push(10_000);
    prev.push(prev[3]);
    let sol = solve(
        &changed,
        &SolverParams {
            mode: Mode::Fast,
            warm_start: Some(prev),
            use_exact: false,
            ..SolverParams::default()
        },
    )
    .unwrap();
    check(&changed, &sol, false);
}

#[test]
fn invalid_inputs() {
    let inst = random_instance(1, 10, 3, 0);
    assert_eq!(
        solve(
            &inst,
            &SolverParams {
                open: Some(10),
                ..SolverParams::default()
            }
        ),
        Err(SolveError::VertexOutOfRange { vertex: 10, n: 10 })
    );
    let partial = Instance::new(
        "p",
        vec![vec![0, 1], vec![2]],
        CostMatrix::from_fn(4, |i, j| (i + j) as i64),
    )
    .unwrap();
    assert_eq!(
        solve(
            &partial,
            &SolverParams {
                fixed_start: Some(3),
                ..SolverParams::default()
            }
        ),
        Err(SolveError::StartNotInSet(3))
    );
    // Vertices in no set are ignored.
    let sol = solve(&partial, &SolverParams::default()).unwrap();
    assert_eq!(sol.tour.len(), 2);
    let empty = Instance::new("e", vec![], CostMatrix::from_fn(0, |_, _| 0)).unwrap();
    assert_eq!(solve(&empty, &SolverParams::default()).unwrap().cost, 0);
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(24))]

    /// The iteration at which the returned tour was found lies within the run and is the same
    /// for the same seed; a run whose best tour comes from the first local search reports 0.
    #[test]
    fn the_best_tour_is_found_within_the_iterations_run(seed in 0u64..1000, n in 6usize..40,
                                                         mfrac in 0.2f64..1.0, kind in 0u8..3,
                                                         trials in 1usize..4) {
        let m = ((n as f64 * mfrac) as usize).clamp(5, n);
        let inst = random_instance(seed, n, m, kind);
        let p = SolverParams { max_trials: Some(trials), ..heuristic(300, seed) };
        let sol = solve(&inst, &p).unwrap();
        check(&inst, &sol, false);
        prop_assert!(sol.best_iteration <= sol.iterations);
        let again = solve(&inst, &p).unwrap();
        prop_assert_eq!((again.best_iteration, again.cost), (sol.best_iteration, sol.cost));
        let exact = solve(&inst, &SolverParams::default()).unwrap();
        if exact.optimal {
            prop_assert_eq!(exact.best_iteration, 0);
        }
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(24))]

    /// A target cost ends the search where the unbounded search first reached it: with the
    /// unbounded search's cost as the target, the same tour after exactly the iterations it
    /// took to find it; with a target below that cost, the unbounded search itself; with one
    /// above every tour, the first local optimum.
    #[test]
    fn a_target_cost_stops_the_search_where_it_is_first_met(
        seed in 0u64..1000,
        n in 24usize..60,
        m in 8usize..20,
        kind in 0u8..3,
        open in proptest::bool::ANY,
    ) {
        let inst = random_instance(seed, n, m, kind);
        let base = SolverParams {
            open: open.then_some(seed as usize % n),
            max_trials: Some(3),
            ..heuristic(600, seed)
        };
        let free = solve(&inst, &base).unwrap();
        check(&inst, &free, open);
        let at = |target: i64| {
            solve(&inst, &SolverParams { target_cost: Some(target), ..base.clone() }).unwrap()
        };
        let met = at(free.cost);
        check(&inst, &met, open);
        prop_assert_eq!(&met.tour, &free.tour);
        prop_assert_eq!(met.iterations, free.best_iteration);
        prop_assert_eq!(met.best_iteration, free.best_iteration);
        prop_assert!(met.trials <= free.trials);
        let below = at(free.cost - 1);
        prop_assert_eq!(&below.tour, &free.tour);
        prop_assert_eq!(below.iterations, free.iterations);
        prop_assert_eq!(below.trials, free.trials);
        let above = at(i64::MAX);
        check(&inst, &above, open);
        prop_assert_eq!(above.iterations, 0);
        prop_assert_eq!(above.trials, 1);
    }
}
