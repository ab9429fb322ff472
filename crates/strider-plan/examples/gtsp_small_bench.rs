//! GTSP timing on GTSPLIB instances and on mission-sized open tours with warm starts.
//!
//! ```text
//! cargo run --release -p strider-plan --example gtsp_small_bench -- gtsplib \
//!     [--dir /work/shared/data/gtsplib] [--min-sets 31] [--max-sets 89] [--runs 3] [--seed 1] \
//!     [--trials N] [--stall-trials N] [--stall-per-set N] [--iterations N]
//! cargo run --release -p strider-plan --example gtsp_small_bench -- mission \
//!     [--dir /work/shared/data/gtsplib] [--max-sets 40] [--runs 5] [--seed 1] \
//!     [--trials N] [--iterations N] [--stall N] [--references FILE] [--warm-only 1]
//! ```
//!
//! `gtsplib` solves every instance of the folder's `best_known.csv` within the set-count range
//! with the default preset (`--trials`, `--stall-trials` and `--stall-per-set` override its trial counts and its stall
//! iterations per set, `--iterations` its iterations per trial), `runs`
//! seeds each, and prints per instance the best and mean gap, the
//! minimum and mean time, iterations, the iterations done when the returned tour was found
//! (`it_best`; the rest confirmed it) and trials.
//!
//! `mission` imitates how an exploration mission calls the solver: open tours from a vertex of
//! the first set, the mission's budget (fast preset, 2 trials of at most 2000 iterations, 300
//! stall iterations), warm-started from the tour of the instance without one set (a goal that
//! has just appeared) and, separately, cold; then warm-started with the default preset instead
//! of the mission's budget. The reference cost of each open instance is the best
//! of eight slow-preset runs. Prints per instance and start the time (min and mean over the
//! seeds) and the gap to the reference (mean and worst). `--trials`, `--iterations` and `--stall`
//! override the mission budget; `--references FILE` keeps the reference costs between runs (read
//! when the file exists, written otherwise); `--warm-only 1` runs only the warm-started mission
//! rows.

use std::path::{Path, PathBuf};
use std::process::ExitCode;

use strider_plan::tsplib::read_instance_file;
use strider_plan::{Instance, Mode, Solution, SolverParams, solve};

struct Args {
    dir: PathBuf,
    min_sets: usize,
    max_sets: usize,
    runs: u64,
    seed: u64,
    /// Override of the preset's trials (`--trials`).
    trials: Option<usize>,
    /// Override of the preset's stalled trials (`--stall-trials`).
    stall_trials: Option<usize>,
    /// Override of the preset's stall iterations per set (`--stall-per-set`).
    stall_per_set: Option<u64>,
    /// Override of the iterations per trial (`--iterations`; `mission`: of the mission budget).
    iterations: Option<u64>,
    /// `mission`: override of the mission budget's stall iterations (`--stall`).
    stall: Option<u64>,
    /// `mission`: a file of reference costs, read when it exists, else written (`--references`).
    references: Option<PathBuf>,
    /// `mission`: only the warm-started runs with the mission budget (`--warm-only 1`).
    warm_only: bool,
}

/// The options after the subcommand, or a one-line error naming the bad one.
fn parse(
    mut args: impl Iterator<Item = String>,
    max_sets: usize,
    runs: u64,
) -> Result<Args, String> {
    let mut a = Args {
        dir: PathBuf::from("/work/shared/data/gtsplib"),
        min_sets: 0,
        max_sets,
        runs,
        seed: 1,
        trials: None,
        stall_trials: None,
        stall_per_set: None,
        iterations: None,
        stall: None,
        references: None,
        warm_only: false,
    };
    while let Some(k) = args.next() {
        let v = args.next().ok_or_else(|| format!("{k} needs a value"))?;
        match k.as_str() {
            "--dir" => a.dir = PathBuf::from(v),
            "--min-sets" => a.min_sets = number(&k, &v)?,
            "--max-sets" => a.max_sets = number(&k, &v)?,
            "--runs" => a.runs = number(&k, &v)?,
            "--seed" => a.seed = number(&k, &v)?,
            "--trials" => a.trials = Some(number(&k, &v)?),
            "--stall-trials" => a.stall_trials = Some(number(&k, &v)?),
            "--stall-per-set" => a.stall_per_set = Some(number(&k, &v)?),
            "--iterations" => a.iterations = Some(number(&k, &v)?),
            "--stall" => a.stall = Some(number(&k, &v)?),
            "--references" => a.references = Some(PathBuf::from(v)),
            "--warm-only" => a.warm_only = v != "0",
            _ => return Err(format!("unknown argument {k}")),
        }
    }
    if a.runs == 0 {
        return Err("--runs must be at least 1".into());
    }
    Ok(a)
}

/// `v`, the value of option `k`, as a non-negative integer.
fn number<T: std::str::FromStr>(k: &str, v: &str) -> Result<T, String> {
    v.parse()
        .map_err(|_| format!("{k} takes a non-negative integer, got {v:?}"))
}

/// `(name, sets, best_known)` rows of `best_known.csv` within the set-count range.
fn references(a: &Args) -> Result<Vec<(String, usize, i64)>, String> {
    let path = a.dir.join("best_known.csv");
    let csv = std::fs::read_to_string(&path)
        .map_err(|e| format!("cannot read {}: {e}", path.display()))?;
    Ok(csv
        .lines()
        .skip(1)
        .filter_map(|l| {
            let f: Vec<&str> = l.split(',').collect();
            let sets: usize = f.get(1)?.trim().parse().ok()?;
            let best: i64 = f.get(3)?.trim().parse().ok()?;
            (sets >= a.min_sets && sets <= a.max_sets).then(|| (f[0].to_string(), sets, best))
        })
        .collect())
}

fn read(dir: &Path, name: &str) -> Result<Instance, String> {
    let path = dir.join(format!("{name}.gtsp"));
    read_instance_file(&path).map_err(|e| format!("{}: {e}", path.display()))
}

fn checked(inst: &Instance, p: &SolverParams) -> Result<Solution, String> {
    let sol = solve(inst, p).map_err(|e| format!("the solver refused the instance: {e}"))?;
    inst.check_tour(&sol.tour)
        .map_err(|e| format!("the solver returned an infeasible tour: {e}"))?;
    Ok(sol)
}

fn gtsplib(a: &Args) -> Result<(), String> {
    println!(
        "{:<12} {:>4} {:>8} {:>8} {:>8} {:>8} {:>8} {:>8} {:>8} {:>6}",
        "instance",
        "sets",
        "best",
        "gap_min",
        "gap_mean",
        "t_min",
        "t_mean",
        "iters",
        "it_best",
        "trials"
    );
    let (mut gaps, mut total) = (Vec::new(), 0.0);
    for (name, sets, best) in references(a)? {
        let inst = read(&a.dir, &name)?;
        let stall = a.stall_per_set.map(|f| (f * sets as u64).max(1000));
        let (mut g, mut t, mut it, mut tr) = (Vec::new(), Vec::new(), 0u64, 0usize);
        let mut it_best = 0u64;
        for k in 0..a.runs {
            let p = SolverParams {
                seed: a.seed.wrapping_add(k),
                max_trials: a.trials,
                max_iterations: a.iterations,
                stall_trials: a.stall_trials,
                stall_iterations: stall,
                ..SolverParams::default()
            };
            let sol = checked(&inst, &p)?;
            g.push(100.0 * (sol.cost - best) as f64 / best.max(1) as f64);
            t.push(sol.time_s);
            it += sol.iterations;
            it_best += sol.best_iteration;
            tr += sol.trials;
        }
        let n = a.runs as f64;
        println!(
            "{name:<12} {sets:>4} {best:>8} {:>8.4} {:>8.4} {:>8.3} {:>8.3} {:>8} {:>8} {:>6.1}",
            g.iter().cloned().fold(f64::INFINITY, f64::min),
            g.iter().sum::<f64>() / n,
            t.iter().cloned().fold(f64::INFINITY, f64::min),
            t.iter().sum::<f64>() / n,
            it / a.runs,
            it_best / a.runs,
            tr as f64 / n
        );
        total += t.iter().sum::<f64>();
        gaps.extend(g);
    }
    println!(
        "instances={} mean_gap_pct={:.4} max_gap_pct={:.4} total_s={total:.2}",
        gaps.len() / a.runs.max(1) as usize,
        gaps.iter().sum::<f64>() / gaps.len().max(1) as f64,
        gaps.iter().cloned().fold(0.0f64, f64::max)
    );
    Ok(())
}

/// The mission's solver budget (see the exploration crate's tour solver defaults) with the
/// overrides of `a`, or with `default_preset` the default preset and its stopping rule.
fn mission_params(
    a: &Args,
    seed: u64,
    open: usize,
    warm: Option<Vec<usize>>,
    default_preset: bool,
) -> SolverParams {
    let base = SolverParams {
        time_limit_s: 5.0,
        seed,
        open: Some(open),
        warm_start: warm,
        ..SolverParams::default()
    };
    if default_preset {
        return base;
    }
    SolverParams {
        mode: Mode::Fast,
        max_trials: Some(a.trials.unwrap_or(2)),
        max_iterations: Some(a.iterations.unwrap_or(2000)),
        stall_iterations: Some(a.stall.unwrap_or(300)),
        ..base
    }
}

/// The reference cost of the open instance: the best of eight slow-preset runs, or the value
/// stored for `name` in `cache`.
fn reference_cost(
    inst: &Instance,
    open: usize,
    name: &str,
    cache: &mut Vec<(String, i64)>,
) -> Result<i64, String> {
    if let Some((_, c)) = cache.iter().find(|(n, _)| n == name) {
        return Ok(*c);
    }
    let mut c = i64::MAX;
    for s in 0..8 {
        let p = SolverParams {
            mode: Mode::Slow,
            seed: 1000 + s,
            open: Some(open),
            ..SolverParams::default()
        };
        c = c.min(checked(inst, &p)?.cost);
    }
    cache.push((name.to_string(), c));
    Ok(c)
}

fn mission(a: &Args) -> Result<(), String> {
    println!(
        "{:<12} {:>4} {:>6} {:>8} {:>9} {:>8} {:>8} {:>9} {:>9}",
        "instance",
        "sets",
        "start",
        "budget",
        "reference",
        "t_min_ms",
        "t_mean",
        "gap_mean",
        "gap_max"
    );
    let mut cache: Vec<(String, i64)> = a
        .references
        .as_ref()
        .and_then(|f| std::fs::read_to_string(f).ok())
        .map(|text| {
            text.lines()
                .filter_map(|l| {
                    let (n, c) = l.split_once(',')?;
                    Some((n.to_string(), c.trim().parse().ok()?))
                })
                .collect()
        })
        .unwrap_or_default();
    let (mut worst_gap, mut worst_t) = (0.0f64, 0.0f64);
    // Over the warm-started mission-budget rows: (instances, Σ mean time, Σ mean gap, over 0.1 %).
    let mut summary = (0usize, 0.0f64, 0.0f64, 0usize);
    for (name, sets, _) in references(a)? {
        let inst = read(&a.dir, &name)?;
        let open = inst.sets[0][0];
        // The instance before the newest goal (the last set) appeared.
        let mut before = inst.clone();
        before.sets.pop();
        let reference = reference_cost(&inst, open, &name, &mut cache)?;
        let starts: &[(bool, bool)] = if a.warm_only {
            &[(true, false)]
        } else {
            &[(true, false), (false, false), (true, true)]
        };
        for &(warm, preset) in starts {
            let (mut t, mut g) = (Vec::new(), Vec::new());
            for k in 0..a.runs {
                let seed = a.seed.wrapping_add(k);
                let prev = if warm {
                    Some(checked(&before, &mission_params(a, seed, open, None, preset))?.tour)
                } else {
                    None
                };
                let sol = checked(&inst, &mission_params(a, seed, open, prev, preset))?;
                t.push(sol.time_s * 1e3);
                g.push(100.0 * (sol.cost - reference) as f64 / reference.max(1) as f64);
            }
            let n = a.runs as f64;
            let gmax = g.iter().cloned().fold(f64::NEG_INFINITY, f64::max);
            let tmean = t.iter().sum::<f64>() / n;
            let gmean = g.iter().sum::<f64>() / n;
            worst_gap = worst_gap.max(gmax);
            worst_t = worst_t.max(tmean);
            if warm && !preset {
                summary.0 += 1;
                summary.1 += tmean;
                summary.2 += gmean;
                summary.3 += usize::from(gmean > 0.1);
            }
            println!(
                "{name:<12} {sets:>4} {:>6} {:>8} {reference:>9} {:>8.2} {tmean:>8.2} {gmean:>9.4} {gmax:>9.4}",
                if warm { "warm" } else { "cold" },
                if preset { "default" } else { "mission" },
                t.iter().cloned().fold(f64::INFINITY, f64::min),
            );
        }
    }
    let n = summary.0.max(1) as f64;
    println!(
        "mission_warm: instances={} mean_time_ms={:.2} mean_gap_pct={:.4} over_0.1pct={}",
        summary.0,
        summary.1 / n,
        summary.2 / n,
        summary.3
    );
    println!("worst_mean_time_ms={worst_t:.2} worst_gap_pct={worst_gap:.4}");
    if let Some(f) = &a.references {
        let text: String = cache.iter().map(|(n, c)| format!("{n},{c}\n")).collect();
        std::fs::write(f, text).map_err(|e| format!("cannot write {}: {e}", f.display()))?;
    }
    Ok(())
}

fn main() -> ExitCode {
    let mut args = std::env::args().skip(1);
    let run = match args.next().as_deref() {
        Some("gtsplib") => parse(args, 89, 3).and_then(|a| gtsplib(&a)),
        Some("mission") => parse(args, 40, 5).and_then(|a| mission(&a)),
        _ => Err("usage: gtsp_small_bench gtsplib|mission [--dir D] [--min-sets K] …".into()),
    };
    match run {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("gtsp_small_bench: {e}");
            ExitCode::from(2)
        }
    }
}
