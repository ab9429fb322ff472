//! GTSPLIB benchmark.
//!
//! ```text
//! cargo run --release -p strider-plan --example gtsplib_bench -- \
//!     [--dir /work/shared/data/gtsplib] [--time 60] [--runs 1] [--seed 1]
//!     [--mode fast|default|slow] [--min-sets 31] [--max-sets 40] [--only NAME,...]
//! ```
//!
//! Reads `best_known.csv` in the directory, solves every selected instance
//! `runs` times and prints per-instance cost, gap to the best-known value,
//! time, then `instances=N mean_gap_pct=X max_gap_pct=Y total_s=Z`.
//! Every tour is checked for feasibility and its cost re-evaluated.

use std::path::PathBuf;

use strider_plan::tsplib::read_instance_file;
use strider_plan::{Mode, SolverParams, solve};

fn main() {
    let mut dir = PathBuf::from("/work/shared/data/gtsplib");
    let mut time = 60.0;
    let mut runs = 1usize;
    let mut seed = 1u64;
    let mut mode = Mode::Default;
    let mut min_sets = 0usize;
    let mut max_sets = usize::MAX;
    let mut only: Option<Vec<String>> = None;
    let mut args = std::env::args().skip(1);
    while let Some(a) = args.next() {
        let mut val = || args.next().unwrap_or_else(|| panic!("{a} needs a value"));
        match a.as_str() {
            "--dir" => dir = PathBuf::from(val()),
            "--time" => time = val().parse().expect("--time"),
            "--runs" => runs = val().parse().expect("--runs"),
            "--seed" => seed = val().parse().expect("--seed"),
            "--mode" => {
                mode = match val().as_str() {
                    "fast" => Mode::Fast,
                    "default" => Mode::Default,
                    "slow" => Mode::Slow,
                    m => panic!("unknown mode {m}"),
                }
            }
            "--min-sets" => min_sets = val().parse().expect("--min-sets"),
            "--max-sets" => max_sets = val().parse().expect("--max-sets"),
            "--only" => only = Some(val().split(',').map(str::to_string).collect()),
            "-h" | "--help" => {
                println!(
                    "usage: gtsplib_bench [--dir D] [--time S] [--runs R] [--seed N] \
                     [--mode fast|default|slow] [--min-sets K] [--max-sets K] [--only A,B]"
                );
                return;
            }
            _ => panic!("unknown argument {a}"),
        }
    }
    let csv = std::fs::read_to_string(dir.join("best_known.csv")).expect("best_known.csv");
    let mut gaps = Vec::new();
    let mut total = 0.0;
    println!(
        "{:<12} {:>5} {:>5} {:>10} {:>10} {:>10} {:>8} {:>8} {:>8}",
        "instance", "sets", "n", "best_known", "cost", "mean_cost", "gap_pct", "time_s", "iters"
    );
    for line in csv.lines().skip(1) {
        let f: Vec<&str> = line.split(',').collect();
        if f.len() < 4 {
            continue;
        }
        let name = f[0];
        let sets: usize = f[1].parse().unwrap();
        let bk: i64 = f[3].parse().unwrap();
        if sets < min_sets || sets > max_sets {
            continue;
        }
        if let Some(o) = &only
            && !o.iter().any(|x| x == name)
        {
            continue;
        }
        let inst = read_instance_file(dir.join(format!("{name}.gtsp"))).expect("read instance");
        let mut best = i64::MAX;
        let mut sum = 0.0;
        let mut tsum = 0.0;
        let mut iters = 0u64;
        for r in 0..runs {
            let params = SolverParams {
                mode,
                time_limit_s: time,
                seed: seed + r as u64,
                ..SolverParams::default()
            };
            let sol = solve(&inst, &params).expect("solve");
            inst.check_tour(&sol.tour).expect("feasible tour");
            assert_eq!(inst.tour_cost(&sol.tour), sol.cost, "cost re-evaluation");
            best = best.min(sol.cost);
            sum += sol.cost as f64;
            tsum += sol.time_s;
            iters += sol.iterations;
            let gap = 100.0 * (sol.cost - bk) as f64 / bk as f64;
            gaps.push(gap);
        }
        total += tsum;
        let mean = sum / runs as f64;
        println!(
            "{:<12} {:>5} {:>5} {:>10} {:>10} {:>10.1} {:>8.3} {:>8.3} {:>8}",
            name,
            sets,
            inst.n,
            bk,
            best,
            mean,
            100.0 * (mean - bk as f64) / bk as f64,
            tsum / runs as f64,
            iters / runs as u64
        );
    }
    let n = gaps.len();
    let mean = gaps.iter().sum::<f64>() / n.max(1) as f64;
    let max = gaps.iter().cloned().fold(0.0f64, f64::max);
    println!(
        "instances={} mean_gap_pct={:.4} max_gap_pct={:.4} total_s={:.2}",
        n / runs.max(1),
        mean,
        max,
        total
    );
}
