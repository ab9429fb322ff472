//! `strider bench table5`: the mission-level reproduction of `001` Table 5.
//!
//! Every block of the table is rebuilt from independent trials in the simulator:
//!
//! * small tours 1 and 2 with the three navigation modes, after a `gtsp` exploration of
//!   `courtyard-small` (one exploration per trial, the three modes on its map and models);
//! * small exploration time, `gtsp` against `greedy`;
//! * the large tour in the `learned` mode after a `gtsp` exploration ("proposed") against the
//!   same after a `spatial-only` exploration, and the two exploration times, on
//!   `courtyard-large`.
//!
//! Trial i (0-based) of a row runs on world seed 1 + (i mod K) with mission seed 1 + i, so the
//! trials of a row cover K random worlds and the rows that are compared (gtsp/greedy, and the
//! modes of one exploration) are paired by trial. Trials run in parallel on a pool of `--jobs`
//! threads; each trial is deterministic, so the table does not depend on the job count.
//! Statistics: mean ± std, paired win fractions and two-sided and one-sided Mann–Whitney U
//! ([`strider_explore::stats`]).

use std::fmt::Write as _;
use std::fs;
use std::path::Path;
use std::time::Instant;

use anyhow::{Context, Result, bail};
use rayon::prelude::*;
use serde::Serialize;
use serde_json::json;
use strider_explore::Strategy;
use strider_explore::evaluate::NavigationMode;
use strider_explore::stats::{MannWhitney, Summary, mann_whitney_u, paired_win_fraction};

use crate::cmd_scenario::load;
use strider_cli::trial::{mission_params, run_mission, run_mission_recorded, run_tours};

/// Options of `strider bench table5`.
pub struct Table5Options {
    /// Trials per row of the small world.
    pub trials: usize,
    /// Trials per row of the large world.
    pub large_trials: usize,
    /// Number of random worlds the trials cycle through.
    pub world_seeds: u64,
    /// Parallel trials.
    pub jobs: usize,
    /// Mission time limit override, simulated seconds.
    pub time_limit: Option<f64>,
    /// Record every trial's mission to `DIR/<scenario>-<strategy>-w<world>-s<seed>.mcap`.
    pub mcap_dir: Option<std::path::PathBuf>,
}

/// One experiment to run: a world, a strategy, a seed, and which tour modes to drive after.
#[derive(Clone, Debug)]
struct Task {
    scenario: &'static str,
    strategy: Strategy,
    world_seed: u64,
    seed: u64,
    modes: Vec<NavigationMode>,
}

/// What one trial measured.
#[derive(Clone, Debug, Serialize)]
struct TrialResult {
    scenario: String,
    strategy: String,
    world_seed: u64,
    seed: u64,
    termination: String,
    exploration_time_s: f64,
    observed_cells: usize,
    /// Per benchmark tour (scenario order) and navigation mode: (tour, mode, total_s,
    /// completed).
    tours: Vec<Vec<(String, String, f64, bool)>>,
    replan_ms_median: f64,
    replan_ms_max: f64,
    wall_s: f64,
}

impl TrialResult {
    /// (total_s, completed) of the scenario's `index`-th tour driven in `mode`.
    fn tour(&self, index: usize, mode: NavigationMode) -> Option<(f64, bool)> {
        self.tours
            .get(index)?
            .iter()
            .find(|t| t.1 == mode.name())
            .map(|t| (t.2, t.3))
    }
}

fn run_task(task: &Task, time_limit: Option<f64>, mcap_dir: Option<&Path>) -> Result<TrialResult> {
    let wall = Instant::now();
    let sc = load(task.scenario, task.world_seed)?;
    let mut params = mission_params(&sc, task.strategy, task.seed)?;
    if let Some(t) = time_limit {
        params.time_limit_s = t;
    }
    let (mission, log) = match mcap_dir {
        None => run_mission(&sc, params, task.seed, |_| {})?,
        Some(dir) => {
            let file = dir.join(format!(
                "{}-{}-w{}-s{}.mcap",
                task.scenario,
                task.strategy.name(),
                task.world_seed,
                task.seed
            ));
            let (m, l, _) = run_mission_recorded(&sc, params, task.seed, |_| {}, &file)?;
            (m, l)
        }
    };
    let tours = if task.modes.is_empty() {
        Vec::new()
    } else {
        run_tours(&sc, &mission, task.seed, &task.modes, |_, _| {})?
    };
    let mut replan = log.replan_ms.clone();
    replan.sort_by(f64::total_cmp);
    Ok(TrialResult {
        scenario: task.scenario.to_string(),
        strategy: task.strategy.name().to_string(),
        world_seed: task.world_seed,
        seed: task.seed,
        termination: format!("{:?}", mission.record().termination),
        exploration_time_s: mission.record().exploration_time_s,
        observed_cells: mission.body().map().observed_count(),
        tours: tours
            .iter()
            .map(|(name, rs)| {
                rs.iter()
                    .map(|r| {
                        (
                            name.clone(),
                            r.mode.name().to_string(),
                            r.total_s,
                            r.completed,
                        )
                    })
                    .collect()
            })
            .collect(),
        replan_ms_median: replan.get(replan.len() / 2).copied().unwrap_or(0.0),
        replan_ms_max: replan.last().copied().unwrap_or(0.0),
        wall_s: wall.elapsed().as_secs_f64(),
    })
}

/// A compared pair of samples, index-paired by trial (same world and mission seed): ratio of
/// means, paired wins of `a` over `b` and the Mann–Whitney test of `a` against `b`.
fn compare(a: &[f64], b: &[f64]) -> serde_json::Value {
    let (Ok(sa), Ok(sb)) = (Summary::of(a), Summary::of(b)) else {
        return json!({"ratio_of_means": null, "paired_win_fraction": null, "mann_whitney": null});
    };
    let mw: Option<MannWhitney> = mann_whitney_u(a, b).ok();
    let wins = paired_win_fraction(a, b).ok();
    json!({
        "ratio_of_means": sa.mean / sb.mean,
        "paired_win_fraction": wins,
        "mann_whitney": mw.map(|m| json!({
            "u_a": m.u_a, "p_two_sided": m.p_two_sided, "p_less": m.p_less,
            "p_greater": m.p_greater, "method": format!("{:?}", m.method),
            "effect_size": m.effect_size,
        })),
    })
}

fn summary_json(x: &[f64]) -> serde_json::Value {
    match Summary::of(x) {
        Ok(s) => json!({"n": s.n, "mean": s.mean, "std": s.std, "median": s.median,
                        "min": s.min, "max": s.max}),
        Err(_) => serde_json::Value::Null,
    }
}

fn fmt_ms(x: &[f64]) -> String {
    match Summary::of(x) {
        Ok(s) => format!("{:.1} ± {:.1} (n={})", s.mean, s.std, s.n),
        Err(_) => "–".into(),
    }
}

/// Runs `strider bench table5`.
pub fn table5(o: &Table5Options, out: &Path) -> Result<()> {
    if o.trials == 0 || o.world_seeds == 0 || o.jobs == 0 {
        bail!("--trials, --world-seeds and --jobs must be at least 1");
    }
    if let Some(t) = o.time_limit
        && !(t.is_finite() && t > 0.0)
    {
        bail!("--time-limit must be a positive number of seconds, got {t}");
    }
    fs::create_dir_all(out)
        .with_context(|| format!("{}: cannot create directory", out.display()))?;
    if let Some(dir) = &o.mcap_dir {
        fs::create_dir_all(dir)
            .with_context(|| format!("{}: cannot create directory", dir.display()))?;
    }
    let wall = Instant::now();
    let mut tasks = Vec::new();
    let world = |i: usize| 1 + (i as u64 % o.world_seeds);
    for i in 0..o.trials {
        tasks.push(Task {
            scenario: "courtyard-small",
            strategy: Strategy::Gtsp,
            world_seed: world(i),
            seed: 1 + i as u64,
            modes: NavigationMode::ALL.to_vec(),
        });
        tasks.push(Task {
            scenario: "courtyard-small",
            strategy: Strategy::Greedy,
            world_seed: world(i),
            seed: 1 + i as u64,
            modes: Vec::new(),
        });
    }
    for i in 0..o.large_trials {
        for strategy in [Strategy::Gtsp, Strategy::SpatialOnly] {
            tasks.push(Task {
                scenario: "courtyard-large",
                strategy,
                world_seed: world(i),
                seed: 1 + i as u64,
                modes: vec![NavigationMode::Learned],
            });
        }
    }
    // Longest first (large worlds), so the pool does not end on one long trial.
    tasks.sort_by_key(|t| (t.scenario != "courtyard-large", t.seed));
    let bar = indicatif::ProgressBar::new(tasks.len() as u64);
    bar.set_style(
        indicatif::ProgressStyle::with_template(
            "{spinner} table 5: {pos}/{len} trials ({elapsed}, eta {eta})",
        )
        .unwrap_or_else(|_| indicatif::ProgressStyle::default_spinner()),
    );
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(o.jobs)
        .build()
        .context("cannot start the trial thread pool")?;
    let results: Vec<Result<TrialResult>> = pool.install(|| {
        tasks
            .par_iter()
            .with_max_len(1)
            .map(|t| {
                let r = run_task(t, o.time_limit, o.mcap_dir.as_deref()).with_context(|| {
                    format!(
                        "trial {} {} world seed {} seed {}",
                        t.scenario,
                        t.strategy.name(),
                        t.world_seed,
                        t.seed
                    )
                });
                bar.inc(1);
                r
            })
            .collect()
    });
    bar.finish_and_clear();
    let mut trials = Vec::new();
    for r in results {
        trials.push(r?);
    }
    trials.sort_by(|a, b| {
        (&a.scenario, &a.strategy, a.seed).cmp(&(&b.scenario, &b.strategy, b.seed))
    });
    let select = |sc: &str, st: Strategy| -> Vec<&TrialResult> {
        trials
            .iter()
            .filter(|t| t.scenario == sc && t.strategy == st.name())
            .collect()
    };
    let small = select("courtyard-small", Strategy::Gtsp);
    let greedy = select("courtyard-small", Strategy::Greedy);
    let large = select("courtyard-large", Strategy::Gtsp);
    let spatial = select("courtyard-large", Strategy::SpatialOnly);
    let tour_times = |set: &[&TrialResult], k: usize, m: NavigationMode| -> Vec<f64> {
        set.iter()
            .filter_map(|t| t.tour(k, m).map(|x| x.0))
            .collect()
    };
    let incomplete = |set: &[&TrialResult], k: usize, m: NavigationMode| -> usize {
        set.iter()
            .filter(|t| t.tour(k, m).is_some_and(|x| !x.1))
            .count()
    };
    let expl =
        |set: &[&TrialResult]| -> Vec<f64> { set.iter().map(|t| t.exploration_time_s).collect() };

    // Published values (`001` Table 5, BENCHMARKS.md §1): mean, std.
    const PUB: &[(&str, f64, f64)] = &[
        ("small tour 1 flat", 630.39, 21.06),
        ("small tour 1 gait-selection", 644.50, 7.34),
        ("small tour 1 learned", 454.80, 4.27),
        ("small tour 2 flat", 2748.00, 30.59),
        ("small tour 2 gait-selection", 2523.12, 39.48),
        ("small tour 2 learned", 2271.99, 33.38),
        ("small exploration gtsp", 1382.68, 241.47),
        ("small exploration greedy", 1547.16, 203.71),
        ("large tour proposed", 554.00, 13.56),
        ("large tour spatial-only", 859.99, 156.02),
        ("large exploration proposed", 1167.15, 163.69),
        ("large exploration spatial-only", 545.40, 137.43),
    ];
    let published = |name: &str| PUB.iter().find(|p| p.0 == name).map(|p| (p.1, p.2));
    let mut rows: Vec<(String, Vec<f64>, usize)> = Vec::new();
    for k in 0..2 {
        for m in NavigationMode::ALL {
            rows.push((
                format!("small tour {} {}", k + 1, m.name()),
                tour_times(&small, k, m),
                incomplete(&small, k, m),
            ));
        }
    }
    rows.push(("small exploration gtsp".into(), expl(&small), 0));
    rows.push(("small exploration greedy".into(), expl(&greedy), 0));
    rows.push((
        "large tour proposed".into(),
        tour_times(&large, 0, NavigationMode::Learned),
        incomplete(&large, 0, NavigationMode::Learned),
    ));
    rows.push((
        "large tour spatial-only".into(),
        tour_times(&spatial, 0, NavigationMode::Learned),
        incomplete(&spatial, 0, NavigationMode::Learned),
    ));
    rows.push(("large exploration proposed".into(), expl(&large), 0));
    rows.push(("large exploration spatial-only".into(), expl(&spatial), 0));
    let row = |name: &str| -> &[f64] {
        rows.iter()
            .find(|r| r.0 == name)
            .map_or(&[][..], |r| &r.1[..])
    };

    // The relations the paper reports, each as "a < b" with its test.
    const RELATIONS: [(&str, &str, &str); 7] = [
        (
            "tour 1: learned < flat",
            "small tour 1 learned",
            "small tour 1 flat",
        ),
        (
            "tour 1: learned < gait-selection",
            "small tour 1 learned",
            "small tour 1 gait-selection",
        ),
        (
            "tour 2: learned < flat",
            "small tour 2 learned",
            "small tour 2 flat",
        ),
        (
            "tour 2: learned < gait-selection",
            "small tour 2 learned",
            "small tour 2 gait-selection",
        ),
        (
            "small exploration: gtsp < greedy",
            "small exploration gtsp",
            "small exploration greedy",
        ),
        (
            "large tour: proposed < spatial-only",
            "large tour proposed",
            "large tour spatial-only",
        ),
        (
            "large exploration: spatial-only < proposed",
            "large exploration spatial-only",
            "large exploration proposed",
        ),
    ];
    let rel_json: Vec<_> = RELATIONS
        .iter()
        .map(|(name, a, b)| {
            let mut v = compare(row(a), row(b));
            if let Some(obj) = v.as_object_mut() {
                obj.insert("relation".into(), json!(name));
                obj.insert("a".into(), json!(a));
                obj.insert("b".into(), json!(b));
            }
            v
        })
        .collect();
    let rows_json: Vec<_> = rows
        .iter()
        .map(|(name, xs, inc)| {
            json!({
                "row": name,
                "ours": summary_json(xs),
                "incomplete_tours": inc,
                "published": published(name).map(|(m, s)| json!({"mean": m, "std": s})),
                "values": xs,
            })
        })
        .collect();
    let mut replan_med: Vec<f64> = large.iter().map(|t| t.replan_ms_median).collect();
    replan_med.sort_by(f64::total_cmp);
    let replan_max = large.iter().map(|t| t.replan_ms_max).fold(0.0f64, f64::max);
    let wall_s = wall.elapsed().as_secs_f64();
    let report = json!({
        "trials": o.trials,
        "large_trials": o.large_trials,
        "world_seeds": o.world_seeds,
        "jobs": o.jobs,
        "time_limit_s": o.time_limit,
        "rows": rows_json,
        "relations": rel_json,
        "large_replan_ms": {"median_of_medians": replan_med.get(replan_med.len() / 2), "max": replan_max},
        "wall_s": wall_s,
        "trial_results": trials,
    });
    let path = out.join("table5.json");
    fs::write(&path, serde_json::to_string_pretty(&report)?)
        .with_context(|| format!("{}: cannot write", path.display()))?;

    let mut md = String::new();
    let _ = writeln!(
        md,
        "# `001` Table 5 reproduction\n\n{} small and {} large trials per row over {} world seeds \
         (`strider bench table5 --trials {} --large-trials {} --world-seeds {}`), {:.0} s wall on \
         {} jobs. Times in simulated seconds, mean ± std. Our simulator is not the paper's: the \
         orderings and rough ratios are what should reproduce.\n",
        o.trials,
        o.large_trials,
        o.world_seeds,
        o.trials,
        o.large_trials,
        o.world_seeds,
        wall_s,
        o.jobs
    );
    let _ = writeln!(md, "| experiment | ours | published | incomplete tours |");
    let _ = writeln!(md, "|---|---|---|---|");
    for (name, xs, inc) in &rows {
        let p = published(name).map_or("–".into(), |(m, s)| format!("{m:.2} ± {s:.2}"));
        let _ = writeln!(md, "| {name} | {} | {p} | {inc} |", fmt_ms(xs));
    }
    let _ = writeln!(
        md,
        "\n| relation (a < b) | ratio of means a/b | paired wins of a | Mann–Whitney p (a < b) | p two-sided |"
    );
    let _ = writeln!(md, "|---|---|---|---|---|");
    for v in &rel_json {
        let get = |k: &str| v.get(k).and_then(|x| x.as_f64());
        let mw = v.get("mann_whitney");
        let p = |k: &str| mw.and_then(|m| m.get(k)).and_then(|x| x.as_f64());
        let f = |x: Option<f64>, digits: usize| x.map_or("–".into(), |x| format!("{x:.digits$}"));
        let _ = writeln!(
            md,
            "| {} | {} | {} | {} | {} |",
            v.get("relation").and_then(|x| x.as_str()).unwrap_or(""),
            f(get("ratio_of_means"), 3),
            f(get("paired_win_fraction"), 2),
            p("p_less").map_or("–".into(), |x| format!("{x:.2e}")),
            p("p_two_sided").map_or("–".into(), |x| format!("{x:.2e}")),
        );
    }
    let _ = writeln!(
        md,
        "\nReplanning latency on courtyard-large (goal identification is separate): median of \
         per-mission medians {} ms, worst {} ms.",
        replan_med
            .get(replan_med.len() / 2)
            .map_or("–".into(), |x| format!("{x:.1}")),
        if large.is_empty() {
            "–".to_string()
        } else {
            format!("{replan_max:.1}")
        }
    );
    let mdp = out.join("table5.md");
    fs::write(&mdp, &md).with_context(|| format!("{}: cannot write", mdp.display()))?;
    print!("{md}");
    println!("-> {} and {}", path.display(), mdp.display());
    Ok(())
}
