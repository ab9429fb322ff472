//! `strider gtsp …`: solve one GTSPLIB/TSPLIB instance, or benchmark a folder of them against
//! their best-known values.

use std::fs;
use std::path::Path;

use anyhow::{Context, Result, bail};
use serde_json::json;
use strider_experiments::gtsp;
use strider_plan::{Instance, Mode, Solution, SolverParams};

use strider_experiments::stats;

use crate::args::{GtspBenchArgs, SolveArgs};
use crate::ranges::{MAX_RUNS, check_count, check_time_limit, show};

/// Parses a solver mode name (`--mode`).
fn parse_mode(s: &str) -> Result<Mode> {
    gtsp::parse_mode(s).map_err(|e| anyhow::anyhow!("--mode: {e}"))
}

fn params(time_limit: f64, seed: u64, mode: Mode, target: Option<i64>) -> Result<SolverParams> {
    check_time_limit(time_limit)
        .map_err(|e| anyhow::anyhow!("--time-limit {}: {e}", show(time_limit)))?;
    Ok(SolverParams {
        mode,
        time_limit_s: time_limit,
        seed,
        target_cost: target,
        ..SolverParams::default()
    })
}

fn read_instance(path: &Path) -> Result<Instance> {
    gtsp::read_instance(path)
}

fn solve_checked(inst: &Instance, p: &SolverParams, path: &Path) -> Result<Solution> {
    gtsp::solve_checked(inst, p, &path.display().to_string())
}

/// Runs `strider gtsp solve`.
pub fn solve(a: &SolveArgs) -> Result<()> {
    let p = params(a.time_limit, a.seed, parse_mode(&a.mode)?, a.target)?;
    solve_file(&a.file, &p, a.json)
}

fn solve_file(file: &Path, p: &SolverParams, as_json: bool) -> Result<()> {
    let inst = read_instance(file)?;
    let sol = solve_checked(&inst, p, file)?;
    // Vertex ids as in the file (1-based).
    let tour: Vec<usize> = sol.tour.iter().map(|v| v + 1).collect();
    if as_json {
        println!(
            "{}",
            json!({"cost": sol.cost, "tour": tour, "time_s": sol.time_s})
        );
    } else {
        println!(
            "instance {} ({} sets, {} vertices)",
            inst.name,
            inst.sets.len(),
            inst.n
        );
        println!("cost {}", sol.cost);
        println!(
            "tour {}",
            tour.iter()
                .map(|v| v.to_string())
                .collect::<Vec<_>>()
                .join(" ")
        );
        println!("time_s {:.3}", sol.time_s);
    }
    Ok(())
}

/// One row of a reference table: instance name, set count and best-known cost.
struct Reference {
    name: String,
    sets: usize,
    best_known: i64,
    file: String,
}

/// Reads `DIR/best_known.csv` (GTSPLIB: instance,sets,vertices,best_known,…) or, failing that,
/// `DIR/optima.csv` (TSPLIB: instance,dimension,edge_weight_type,optimal_length,…).
fn references(dir: &Path) -> Result<Vec<Reference>> {
    let (csv, tsp) = if dir.join("best_known.csv").is_file() {
        (dir.join("best_known.csv"), false)
    } else if dir.join("optima.csv").is_file() {
        (dir.join("optima.csv"), true)
    } else {
        bail!(
            "{}: no best_known.csv (GTSPLIB) or optima.csv (TSPLIB) in this folder",
            dir.display()
        );
    };
    let text =
        fs::read_to_string(&csv).with_context(|| format!("{}: cannot read", csv.display()))?;
    let mut out = Vec::new();
    for (ln, line) in text.lines().enumerate().skip(1) {
        if line.trim().is_empty() {
            continue;
        }
        let f: Vec<&str> = line.split(',').collect();
        let bad = || {
            format!(
                "{}:{}: expected instance,count,…,best value",
                csv.display(),
                ln + 1
            )
        };
        if f.len() < 4 {
            bail!(bad());
        }
        let count: usize = f[1].trim().parse().with_context(bad)?;
        let best_known: i64 = f[3].trim().parse().with_context(bad)?;
        if best_known <= 0 {
            // Gaps are relative to it.
            bail!(
                "{}:{}: best value {best_known} must be > 0",
                csv.display(),
                ln + 1
            );
        }
        let name = f[0].trim().to_string();
        let file = if tsp {
            format!("{name}.tsp")
        } else {
            format!("{name}.gtsp")
        };
        // A TSP instance has one set per vertex.
        out.push(Reference {
            sets: count,
            best_known,
            file,
            name,
        });
    }
    Ok(out)
}

/// Options of `strider gtsp bench`.
struct BenchOptions {
    /// Time limit per run, seconds.
    pub time_limit: f64,
    /// Runs per instance (seeds seed, seed+1, …, wrapping after 2⁶⁴−1).
    pub runs: usize,
    /// First seed.
    pub seed: u64,
    /// Effort preset.
    pub mode: Mode,
    /// Only instances with at least this many sets.
    pub min_sets: usize,
    /// Only instances with at most this many sets.
    pub max_sets: usize,
    /// Stop each run at the instance's best-known value.
    pub stop_at_best_known: bool,
}

/// Runs `strider gtsp bench`.
pub fn bench(a: &GtspBenchArgs) -> Result<()> {
    let o = BenchOptions {
        time_limit: a.time_limit,
        runs: a.runs,
        seed: a.seed,
        mode: parse_mode(&a.mode)?,
        min_sets: a.min_sets,
        max_sets: a.max_sets,
        stop_at_best_known: a.stop_at_best_known,
    };
    bench_dir(&a.dir, &o, a.json.as_deref())
}

fn bench_dir(dir: &Path, o: &BenchOptions, json_out: Option<&Path>) -> Result<()> {
    check_count(o.runs, 1, MAX_RUNS).map_err(|e| anyhow::anyhow!("--runs {}: {e}", o.runs))?;
    let tl = o.time_limit;
    check_time_limit(tl).map_err(|e| anyhow::anyhow!("--time-limit {}: {e}", show(tl)))?;
    if o.min_sets > o.max_sets {
        bail!(
            "--min-sets {} is more than --max-sets {}: no instance can match",
            o.min_sets,
            o.max_sets
        );
    }
    let refs = references(dir)?;
    println!(
        "{:<12} {:>5} {:>5} {:>10} {:>10} {:>9} {:>9} {:>8}",
        "instance", "sets", "n", "best_known", "best_cost", "gap_pct", "max_gap", "time_s"
    );
    let (mut gaps, mut total_s, mut rows) = (Vec::new(), 0.0, Vec::new());
    for r in refs
        .iter()
        .filter(|r| r.sets >= o.min_sets && r.sets <= o.max_sets)
    {
        let path = dir.join(&r.file);
        let inst = read_instance(&path)?;
        let (mut best, mut time) = (i64::MAX, 0.0);
        let (mut costs, mut run_gaps, mut iterations) = (Vec::new(), Vec::new(), Vec::new());
        for k in 0..o.runs {
            let sol = solve_checked(
                &inst,
                &params(
                    o.time_limit,
                    o.seed.wrapping_add(k as u64),
                    o.mode,
                    o.stop_at_best_known.then_some(r.best_known),
                )?,
                &path,
            )?;
            run_gaps.push(100.0 * (sol.cost - r.best_known) as f64 / r.best_known as f64);
            best = best.min(sol.cost);
            time += sol.time_s;
            costs.push(sol.cost);
            iterations.push(sol.iterations);
        }
        let mean_gap = stats::mean(&run_gaps).unwrap_or(f64::NAN);
        let max_gap = stats::max(&run_gaps).unwrap_or(f64::NEG_INFINITY);
        gaps.extend(run_gaps);
        total_s += time;
        println!(
            "{:<12} {:>5} {:>5} {:>10} {:>10} {:>9.4} {:>9.4} {:>8.3}",
            r.name,
            inst.sets.len(),
            inst.n,
            r.best_known,
            best,
            mean_gap,
            max_gap,
            time / o.runs as f64
        );
        rows.push(json!({
            "instance": r.name, "sets": inst.sets.len(), "vertices": inst.n,
            "best_known": r.best_known, "costs": costs, "best_cost": best,
            "iterations": iterations,
            "mean_gap_pct": mean_gap, "max_gap_pct": max_gap, "mean_time_s": time / o.runs as f64,
        }));
    }
    let n = rows.len();
    let mean = stats::mean(&gaps).unwrap_or(0.0);
    let max = stats::max(&gaps).unwrap_or(0.0).max(0.0);
    println!("instances={n} mean_gap_pct={mean:.4} max_gap_pct={max:.4} total_s={total_s:.2}");
    if let Some(out) = json_out {
        let doc = json!({
            "dir": dir.display().to_string(),
            "time_limit_s": o.time_limit, "runs": o.runs, "seed": o.seed,
            "stop_at_best_known": o.stop_at_best_known,
            "instances": rows,
            "summary": {"instances": n, "mean_gap_pct": mean, "max_gap_pct": max, "total_s": total_s},
        });
        fs::write(out, serde_json::to_string_pretty(&doc)? + "\n")
            .with_context(|| format!("{}: cannot write", out.display()))?;
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A folder with one 10-vertex, 2-set instance and a best-known table.
    fn bench_folder(name: &str, best_known: &str) -> std::path::PathBuf {
        let dir = std::env::temp_dir().join(format!("strider-gtsp-{name}-{}", std::process::id()));
        fs::create_dir_all(&dir).unwrap();
        let mut g = String::from(
            "NAME: g\nTYPE: GTSP\nDIMENSION: 4\nGTSP_SETS: 2\nEDGE_WEIGHT_TYPE: EUC_2D\n\
             NODE_COORD_SECTION\n1 0 0\n2 3 4\n3 1 1\n4 0 2.5\n",
        );
        g.push_str("GTSP_SET_SECTION\n1 1 2 -1\n2 3 4 -1\nEOF\n");
        fs::write(dir.join("g.gtsp"), g).unwrap();
        fs::write(
            dir.join("best_known.csv"),
            format!("instance,sets,vertices,best_known\ng,2,4,{best_known}\n"),
        )
        .unwrap();
        dir
    }

    fn options(runs: usize, seed: u64, min_sets: usize, max_sets: usize) -> BenchOptions {
        BenchOptions {
            time_limit: 0.01,
            runs,
            seed,
            mode: Mode::Fast,
            min_sets,
            max_sets,
            stop_at_best_known: false,
        }
    }

    fn bench_err(dir: &Path, o: &BenchOptions) -> String {
        format!("{:#}", bench_dir(dir, o, None).unwrap_err())
    }

    #[test]
    fn bench_counts_and_bounds_are_checked() {
        let dir = bench_folder("counts", "2");
        assert_eq!(
            bench_err(&dir, &options(usize::MAX, 1, 0, usize::MAX)),
            format!("--runs {}: must be an integer from 1 to 1000", usize::MAX)
        );
        assert_eq!(
            bench_err(&dir, &options(0, 1, 0, usize::MAX)),
            "--runs 0: must be an integer from 1 to 1000"
        );
        assert_eq!(
            bench_err(&dir, &options(1, 1, 5, 1)),
            "--min-sets 5 is more than --max-sets 1: no instance can match"
        );
        // Seeds wrap instead of overflowing.
        assert!(bench_dir(&dir, &options(2, u64::MAX, 0, usize::MAX), None).is_ok());
        let _ = fs::remove_dir_all(dir);
    }

    /// A folder with a 120-vertex, 30-set random Euclidean instance (large enough for the
    /// heuristic) and a best-known table claiming `best_known`.
    fn heuristic_folder(name: &str, best_known: i64) -> std::path::PathBuf {
        let dir = std::env::temp_dir().join(format!("strider-gtsp-{name}-{}", std::process::id()));
        fs::create_dir_all(&dir).unwrap();
        let mut g = String::from(
            "NAME: h\nTYPE: GTSP\nDIMENSION: 120\nGTSP_SETS: 30\nEDGE_WEIGHT_TYPE: EUC_2D\n\
             NODE_COORD_SECTION\n",
        );
        let mut state = 12345u64;
        let mut next = || {
            state = state
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            (state >> 33) % 1000
        };
        for v in 1..=120 {
            g.push_str(&format!("{v} {} {}\n", next(), next()));
        }
        g.push_str("GTSP_SET_SECTION\n");
        for s in 0..30 {
            let members: Vec<String> = (0..4).map(|k| (s * 4 + k + 1).to_string()).collect();
            g.push_str(&format!("{} {} -1\n", s + 1, members.join(" ")));
        }
        g.push_str("EOF\n");
        fs::write(dir.join("h.gtsp"), g).unwrap();
        fs::write(
            dir.join("best_known.csv"),
            format!("instance,sets,vertices,best_known\nh,30,120,{best_known}\n"),
        )
        .unwrap();
        dir
    }

    /// One bench run of the folder's instance: (best cost, iterations of the run).
    fn bench_once(dir: &Path, stop_at_best_known: bool) -> (i64, u64) {
        let json_out = dir.join("out.json");
        let o = BenchOptions {
            time_limit: 600.0,
            mode: Mode::Default,
            stop_at_best_known,
            ..options(1, 3, 0, usize::MAX)
        };
        bench_dir(dir, &o, Some(&json_out)).unwrap();
        let doc: serde_json::Value =
            serde_json::from_str(&fs::read_to_string(&json_out).unwrap()).unwrap();
        assert_eq!(doc["stop_at_best_known"], stop_at_best_known);
        let row = &doc["instances"][0];
        (
            row["best_cost"].as_i64().unwrap(),
            row["iterations"][0].as_u64().unwrap(),
        )
    }

    #[test]
    fn the_bench_stops_at_the_best_known_value_when_asked() {
        // The whole search first, then one told that its result is the best known: it ends
        // where it found that tour, before the stall that confirmed it.
        let dir = heuristic_folder("target", 1);
        let (best, all) = bench_once(&dir, false);
        let _ = fs::remove_dir_all(&dir);
        let dir = heuristic_folder("target", best);
        let (reached, stopped) = bench_once(&dir, true);
        let _ = fs::remove_dir_all(dir);
        assert_eq!(reached, best);
        assert!(
            stopped < all,
            "{stopped} iterations with the target, {all} without"
        );
    }

    #[test]
    fn a_best_known_value_that_is_not_positive_is_refused() {
        let dir = bench_folder("best0", "0");
        let e = bench_err(&dir, &options(1, 1, 0, usize::MAX));
        assert!(
            e.ends_with("best_known.csv:2: best value 0 must be > 0"),
            "{e}"
        );
        let _ = fs::remove_dir_all(dir);
    }

    #[test]
    fn time_limits_out_of_range_name_the_flag() {
        for (t, shown) in [
            (-1.0, "-1"),
            (0.0, "0"),
            (f64::NAN, "NaN"),
            (1e300, "1e300"),
        ] {
            let e = params(t, 1, Mode::Fast, None).unwrap_err().to_string();
            assert_eq!(
                e,
                format!(
                    "--time-limit {shown}: must be a finite number of seconds > 0 and ≤ 604800 \
                     (one week)"
                )
            );
        }
    }
}
