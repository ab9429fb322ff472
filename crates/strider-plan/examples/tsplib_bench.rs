//! TSPLIB benchmark (plain TSP = one vertex per set).
//!
//! ```text
//! cargo run --release -p strider-plan --example tsplib_bench -- \
//!     [--dir /work/shared/data/tsplib] [--time 60] [--seed 1] [--mode fast|default|slow]
//! ```
//!
//! Reads `optima.csv`, re-evaluates every supplied `.opt.tour` (reader
//! check), solves every instance and prints cost, gap to the optimum and
//! time, then `instances=N mean_gap_pct=X max_gap_pct=Y total_s=Z`.

use std::path::PathBuf;

use strider_plan::tsplib::{read_instance_file, read_tour_file};
use strider_plan::{Mode, SolverParams, solve};

fn main() {
    let mut dir = PathBuf::from("/work/shared/data/tsplib");
    let mut time = 60.0;
    let mut seed = 1u64;
    let mut mode = Mode::Default;
    let mut args = std::env::args().skip(1);
    while let Some(a) = args.next() {
        let mut val = || args.next().unwrap_or_else(|| panic!("{a} needs a value"));
        match a.as_str() {
            "--dir" => dir = PathBuf::from(val()),
            "--time" => time = val().parse().expect("--time"),
            "--seed" => seed = val().parse().expect("--seed"),
            "--mode" => {
                mode = match val().as_str() {
                    "fast" => Mode::Fast,
                    "default" => Mode::Default,
                    "slow" => Mode::Slow,
                    m => panic!("unknown mode {m}"),
                }
            }
            _ => panic!("unknown argument {a}"),
        }
    }
    let csv = std::fs::read_to_string(dir.join("optima.csv")).expect("optima.csv");
    let (mut gaps, mut total) = (Vec::new(), 0.0);
    for line in csv.lines().skip(1) {
        let f: Vec<&str> = line.split(',').collect();
        let (name, opt, tour_file) = (f[0], f[3].parse::<i64>().unwrap(), f[4]);
        let inst = read_instance_file(dir.join(format!("{name}.tsp"))).expect("read instance");
        let tour_check = if tour_file.is_empty() {
            "-".to_string()
        } else {
            let t = read_tour_file(dir.join(tour_file)).expect("read tour");
            inst.check_tour(&t).expect("opt tour feasible");
            let c = inst.tour_cost(&t);
            assert_eq!(c, opt, "{name}: opt.tour re-evaluates to {c}");
            "ok".to_string()
        };
        let params = SolverParams {
            mode,
            time_limit_s: time,
            seed,
            ..SolverParams::default()
        };
        let sol = solve(&inst, &params).expect("solve");
        inst.check_tour(&sol.tour).expect("feasible");
        assert_eq!(inst.tour_cost(&sol.tour), sol.cost);
        let gap = 100.0 * (sol.cost - opt) as f64 / opt as f64;
        gaps.push(gap);
        total += sol.time_s;
        println!(
            "{name:<10} n={:<4} opt={opt:<7} cost={:<7} gap_pct={gap:.3} time_s={:.2} opt_tour={tour_check}",
            inst.n, sol.cost, sol.time_s
        );
    }
    let n = gaps.len();
    println!(
        "instances={n} mean_gap_pct={:.4} max_gap_pct={:.4} total_s={total:.2}",
        gaps.iter().sum::<f64>() / n.max(1) as f64,
        gaps.iter().cloned().fold(0.0f64, f64::max)
    );
}
