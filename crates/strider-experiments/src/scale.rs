//! `strider bench scale`: one exploration of a large world (default `campus`, 200 × 200 m),
//! sampled over simulated time: cells observed, real-time factor, replanning latency and the
//! latency from new data to a new tour (median, p95, max per window and over the mission), and
//! the process's peak memory. The figure plots the latencies against the cells observed, so a
//! planner whose work grows with the explored area rather than with the frontier shows it.

use std::fmt::Write as _;
use std::path::Path;
use std::time::Instant;

use anyhow::{Result, bail};
use serde::Serialize;
use strider_explore::Strategy;

use crate::cancel::Cancel;
use crate::io::{create_dir, write_json, write_text};
use crate::parallel::on_worker;
use crate::progress::Progress;
use crate::render::line_chart;
use crate::trial::{checked_time_limit, load, mission_params, run_mission, termination};

/// Options of `strider bench scale`.
#[derive(Clone, Debug, Serialize)]
pub struct ScaleOptions {
    /// Built-in scenario name or scenario file.
    pub scenario: String,
    /// World seed.
    pub world_seed: u64,
    /// Mission seed.
    pub seed: u64,
    /// Exploration strategy (a Prágr22 explorer).
    pub strategy: String,
    /// Mission time limit override, simulated seconds.
    pub time_limit: Option<f64>,
    /// Length of a sampling window, simulated seconds.
    pub window_s: f64,
    /// Stops the mission early; the report then covers the part run.
    #[serde(skip)]
    pub cancel: Cancel,
}

/// Median, 95th percentile (nearest rank) and maximum of a sample.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct Quantiles {
    /// Values in the sample.
    pub count: usize,
    /// Median.
    pub median: f64,
    /// 95th percentile, nearest rank.
    pub p95: f64,
    /// Maximum.
    pub max: f64,
}

impl Quantiles {
    /// The quantiles of the finite values of `xs`; `None` when there are none.
    pub fn of(xs: &[f64]) -> Option<Self> {
        let mut v: Vec<f64> = xs.iter().copied().filter(|x| x.is_finite()).collect();
        if v.is_empty() {
            return None;
        }
        v.sort_by(f64::total_cmp);
        let n = v.len();
        let rank = |q: f64| v[((q * n as f64).ceil() as usize).clamp(1, n) - 1];
        let median = if n % 2 == 1 {
            v[n / 2]
        } else {
            0.5 * (v[n / 2 - 1] + v[n / 2])
        };
        Some(Self {
            count: n,
            median,
            p95: rank(0.95),
            max: v[n - 1],
        })
    }
}

/// One window of simulated time.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct ScaleWindow {
    /// Simulated time at the window's end, s.
    pub t_end_s: f64,
    /// Cells observed at the window's end.
    pub observed_cells: usize,
    /// Simulated over wall time within the window.
    pub real_time_factor: f64,
    /// Replanning latency of the replans in the window, ms.
    pub replan_ms: Option<Quantiles>,
    /// New data to new tour (the latest spatial and learning updates plus the replan), ms.
    pub data_to_tour_ms: Option<Quantiles>,
    /// Median vertices of the window's GTSP instances (the robot and the goal sites).
    pub vertices_median: Option<f64>,
    /// Median all-pairs site-cost time of the window's replans, ms.
    pub all_pairs_ms_median: Option<f64>,
    /// Median planning-view build time of the window's replans, ms.
    pub view_ms_median: Option<f64>,
    /// Median cells of the planning views the window's tours were planned on.
    pub view_cells_median: Option<f64>,
    /// Median GTSP solve time of the window's replans, ms.
    pub gtsp_ms_median: Option<f64>,
    /// Replans that found no near goal reachable within the horizon's window and planned every
    /// goal on the whole map, and their latency, ms.
    pub whole_map_replans: usize,
    pub whole_map_replan_ms: Option<Quantiles>,
    /// The window's learning updates, ms.
    pub learning_ms: Option<Quantiles>,
}

/// How one gait's class maps were brought up to date over the mission.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct Classification {
    /// Learning updates that classified every described cell.
    pub full: u64,
    /// Learning updates that classified only the cells that may have changed class.
    pub partial: u64,
    /// Cells classified, over all updates.
    pub cells: u64,
}

/// `scale.json`.
#[derive(Clone, Debug, Serialize)]
pub struct ScaleReport {
    /// The options.
    #[serde(flatten)]
    pub options: ScaleOptions,
    /// Why the mission stopped.
    pub termination: String,
    /// Simulated time of the exploration, s.
    pub exploration_time_s: f64,
    /// Wall time of the mission, s.
    pub wall_s: f64,
    /// Simulated over wall time, whole mission.
    pub real_time_factor: f64,
    /// Cells observed at the end.
    pub observed_cells: usize,
    /// The process's peak resident memory, MiB (Linux; `None` elsewhere).
    pub peak_rss_mib: Option<f64>,
    /// Replanning latency over the mission, ms.
    pub replan_ms: Option<Quantiles>,
    /// New data to new tour over the mission, ms.
    pub data_to_tour_ms: Option<Quantiles>,
    /// Spatial goal identification, ms.
    pub spatial_goal_ms: Option<Quantiles>,
    /// Learning updates, ms.
    pub learning_ms: Option<Quantiles>,
    /// Wall time per part of the mission loop, s.
    pub phase_wall_s: strider_explore::PhaseWall,
    /// Per gait: how its class maps were brought up to date (every cell, or only the cells
    /// that may have changed class) and the cells classified in all.
    pub classification: Vec<Classification>,
    /// The windows, in time order.
    pub windows: Vec<ScaleWindow>,
}

/// A progress sample: simulated time, wall time since the start, cells observed.
#[derive(Clone, Copy)]
struct Sample {
    t: f64,
    wall: f64,
    cells: usize,
}

/// One replan: its robot time, latencies, GTSP vertices and all-pairs time.
#[derive(Clone, Copy)]
struct Replan {
    t: f64,
    replan_ms: f64,
    data_to_tour_ms: f64,
    vertices: usize,
    all_pairs_ms: f64,
    view_ms: f64,
    gtsp_ms: f64,
    whole_map: bool,
    view_cells: usize,
}

fn check(o: &ScaleOptions) -> Result<Strategy> {
    if !(o.window_s.is_finite() && o.window_s >= 1.0 && o.window_s <= 1e6) {
        bail!(
            "--window {}: must be a number of simulated seconds from 1 to 1e6",
            o.window_s
        );
    }
    if let Some(t) = o.time_limit {
        checked_time_limit(t)?;
    }
    match Strategy::parse(&o.strategy) {
        Some(s) => Ok(s),
        None => bail!(
            "--strategy {:?}: the scale bench runs a Prágr22 explorer: gtsp, greedy or spatial-only",
            o.strategy
        ),
    }
}

/// Runs the bench and writes `scale.json`, `scale.md` and `scale.png` into `out`.
pub fn scale(o: &ScaleOptions, out: &Path, progress: &dyn Progress) -> Result<ScaleReport> {
    let strategy = check(o)?;
    let sc = load(&o.scenario, o.world_seed)?;
    let mut params = mission_params(&sc, strategy, o.seed)?;
    if let Some(t) = o.time_limit {
        params.time_limit_s = t;
    }
    progress.start(params.time_limit_s.ceil() as u64);
    let wall = Instant::now();
    let mut samples = vec![Sample {
        t: 0.0,
        wall: 0.0,
        cells: 0,
    }];
    let watch = (None, &o.cancel);
    // On a pool thread, as `strider run` runs its mission (see `on_worker`): the loop does its
    // share of every parallel part instead of a third thread waking and sleeping beside the
    // pool's.
    let (mission, log, _) = on_worker(|| {
        run_mission(&sc, params, o.seed, watch, |p| {
            samples.push(Sample {
                t: p.time_s,
                wall: wall.elapsed().as_secs_f64(),
                cells: p.observed_cells,
            });
            progress.at(
                p.time_s as u64,
                &format!("{} cells observed", p.observed_cells),
            );
        })
    })?;
    let wall_s = wall.elapsed().as_secs_f64();
    let replans: Vec<Replan> = log
        .replan_parts
        .iter()
        .zip(&log.replan_ms)
        .zip(&log.goals_to_tour_ms)
        .map(|((p, &r), &g)| Replan {
            t: p.t,
            replan_ms: r,
            data_to_tour_ms: g,
            vertices: p.vertices,
            all_pairs_ms: p.all_pairs_ms,
            view_ms: p.view_ms,
            gtsp_ms: p.gtsp_ms,
            whole_map: p.whole_map,
            view_cells: p.view_cells,
        })
        .collect();
    let record = mission.record();
    let report = ScaleReport {
        options: o.clone(),
        termination: termination(&mission),
        exploration_time_s: record.exploration_time_s,
        wall_s,
        real_time_factor: record.exploration_time_s / wall_s.max(1e-9),
        observed_cells: mission.body().map().observed_count(),
        peak_rss_mib: peak_rss_mib(),
        replan_ms: Quantiles::of(&log.replan_ms),
        data_to_tour_ms: Quantiles::of(&log.goals_to_tour_ms),
        spatial_goal_ms: Quantiles::of(&log.spatial_goal_ms),
        learning_ms: Quantiles::of(&log.learning_ms),
        phase_wall_s: log.phase_wall_s,
        classification: mission
            .strategy()
            .models()
            .iter()
            .map(|m| {
                let c = m.classification_counts();
                Classification {
                    full: c.full,
                    partial: c.partial,
                    cells: c.cells,
                }
            })
            .collect(),
        windows: windows(
            &samples,
            &replans,
            &learning_updates(&log.learning_at_s, &log.learning_ms),
            o.window_s,
        ),
    };
    create_dir(out)?;
    write_json(&out.join("scale.json"), &report)?;
    write_text(&out.join("scale.md"), &markdown(&report))?;
    latency_chart(&samples, &replans).save(&out.join("scale.png"))?;
    Ok(report)
}

/// (robot time s, latency ms) of each learning update.
fn learning_updates(at: &[f64], ms: &[f64]) -> Vec<(f64, f64)> {
    at.iter().copied().zip(ms.iter().copied()).collect()
}

/// The windows of `window_s` simulated seconds: cells, real-time factor, the replans'
/// latencies and the learning updates' (robot time s, ms).
fn windows(
    samples: &[Sample],
    replans: &[Replan],
    learning: &[(f64, f64)],
    window_s: f64,
) -> Vec<ScaleWindow> {
    let Some(last) = samples.last() else {
        return Vec::new();
    };
    let n = (last.t / window_s).ceil().max(1.0) as usize;
    let mut out = Vec::with_capacity(n);
    let mut prev = samples[0];
    for k in 1..=n {
        let t_end = (k as f64 * window_s).min(last.t);
        let end = samples
            .iter()
            .rev()
            .find(|s| s.t <= t_end + 1e-9)
            .copied()
            .unwrap_or(prev);
        let inside: Vec<&Replan> = replans
            .iter()
            .filter(|r| r.t > prev.t && r.t <= end.t + 1e-9)
            .collect();
        let of = |f: fn(&Replan) -> f64| inside.iter().map(|r| f(r)).collect::<Vec<f64>>();
        out.push(ScaleWindow {
            t_end_s: end.t,
            observed_cells: end.cells,
            real_time_factor: (end.t - prev.t) / (end.wall - prev.wall).max(1e-9),
            replan_ms: Quantiles::of(&of(|r| r.replan_ms)),
            data_to_tour_ms: Quantiles::of(&of(|r| r.data_to_tour_ms)),
            vertices_median: Quantiles::of(&of(|r| r.vertices as f64)).map(|q| q.median),
            all_pairs_ms_median: Quantiles::of(&of(|r| r.all_pairs_ms)).map(|q| q.median),
            view_ms_median: Quantiles::of(&of(|r| r.view_ms)).map(|q| q.median),
            view_cells_median: Quantiles::of(&of(|r| r.view_cells as f64)).map(|q| q.median),
            gtsp_ms_median: Quantiles::of(&of(|r| r.gtsp_ms)).map(|q| q.median),
            whole_map_replans: inside.iter().filter(|r| r.whole_map).count(),
            whole_map_replan_ms: Quantiles::of(
                &inside
                    .iter()
                    .filter(|r| r.whole_map)
                    .map(|r| r.replan_ms)
                    .collect::<Vec<f64>>(),
            ),
            learning_ms: Quantiles::of(
                &learning
                    .iter()
                    .filter(|(t, _)| *t > prev.t && *t <= end.t + 1e-9)
                    .map(|&(_, ms)| ms)
                    .collect::<Vec<f64>>(),
            ),
        });
        prev = end;
    }
    out
}

/// Cells observed at robot time `t` (the last progress sample at or before it).
fn cells_at(samples: &[Sample], t: f64) -> usize {
    let k = samples.partition_point(|s| s.t <= t);
    samples[k.saturating_sub(1)].cells
}

/// Replanning and data-to-tour latency (median and p95) per bucket of cells observed: a
/// planner whose work follows the frontier draws flat lines.
fn latency_chart(samples: &[Sample], replans: &[Replan]) -> crate::render::Canvas {
    let most = samples.last().map_or(0, |s| s.cells).max(1);
    let bucket = nice_bucket(most);
    let buckets = most.div_ceil(bucket);
    // Per bucket: the replans' latencies and their data-to-tour latencies.
    let mut replan: Vec<Vec<f64>> = vec![Vec::new(); buckets];
    let mut to_tour: Vec<Vec<f64>> = vec![Vec::new(); buckets];
    for r in replans {
        let b = (cells_at(samples, r.t) / bucket).min(buckets - 1);
        replan[b].push(r.replan_ms);
        to_tour[b].push(r.data_to_tour_ms);
    }
    let q = |by: &[Vec<f64>], f: fn(Quantiles) -> f64| -> Vec<f64> {
        by.iter()
            .map(|b| Quantiles::of(b).map_or(f64::NAN, f))
            .collect()
    };
    let series = [
        (q(&replan, |x| x.median), [30, 90, 200]),
        (q(&replan, |x| x.p95), [140, 170, 230]),
        (q(&to_tour, |x| x.median), [200, 60, 40]),
    ];
    let x_label = format!("CELLS {}K", bucket / 1000);
    line_chart(&series, &[(100.0, [120, 120, 120])], &x_label, "MS")
}

/// A round bucket of cells (1, 2 or 5 × 10^k thousand) giving at most 40 buckets.
fn nice_bucket(most: usize) -> usize {
    let mut b = 1000usize;
    loop {
        for m in [1, 2, 5] {
            if most.div_ceil(b * m) <= 40 {
                return b * m;
            }
        }
        b = b.saturating_mul(10);
    }
}

/// VmHWM of `/proc/self/status`, MiB.
fn peak_rss_mib() -> Option<f64> {
    let status = std::fs::read_to_string("/proc/self/status").ok()?;
    let line = status.lines().find(|l| l.starts_with("VmHWM:"))?;
    let kib: f64 = line.split_whitespace().nth(1)?.parse().ok()?;
    Some(kib / 1024.0)
}

fn fmt_q(q: &Option<Quantiles>) -> String {
    q.map_or("–".into(), |q| {
        format!("{:.0} / {:.0} / {:.0}", q.median, q.p95, q.max)
    })
}

/// `scale.md`: the summary and the windows.
pub fn markdown(r: &ScaleReport) -> String {
    let o = &r.options;
    let mut md = String::new();
    let _ = writeln!(
        md,
        "# Exploration at scale\n\n`strider bench scale --scenario {} --world-seed {} --seed {} \
         --strategy {} --window {}`{}\n",
        o.scenario,
        o.world_seed,
        o.seed,
        o.strategy,
        o.window_s,
        o.time_limit
            .map_or(String::new(), |t| format!(" with `--time-limit {t}`"))
    );
    let _ = writeln!(
        md,
        "- termination {}, {:.0} s simulated in {:.0} s wall: **{:.1}× real time**, {} cells observed",
        r.termination, r.exploration_time_s, r.wall_s, r.real_time_factor, r.observed_cells
    );
    let _ = writeln!(
        md,
        "- replan median / p95 / max: **{} ms**; new data → new tour: **{} ms**",
        fmt_q(&r.replan_ms),
        fmt_q(&r.data_to_tour_ms)
    );
    let _ = writeln!(
        md,
        "- spatial goals: {} ms; learning: {} ms; peak memory {}\n",
        fmt_q(&r.spatial_goal_ms),
        fmt_q(&r.learning_ms),
        r.peak_rss_mib
            .map_or("not measured".into(), |m| format!("{m:.0} MiB"))
    );
    let p = &r.phase_wall_s;
    let _ = writeln!(
        md,
        "- wall time by part, s: robot (simulator, with mapping) {:.0}, mapping {:.0}, spatial \
         goals {:.0}, learning {:.0}, planning {:.0}, gait {:.0}",
        p.robot, p.mapping, p.spatial, p.learning, p.planning, p.gait
    );
    for (g, c) in r.classification.iter().enumerate() {
        let _ = writeln!(
            md,
            "- gait {g}: {} learning updates classified every cell, {} only the cells that may \
             have changed class; {} cells classified in all",
            c.full, c.partial, c.cells
        );
    }
    if !r.classification.is_empty() {
        md.push('\n');
    }
    let _ = writeln!(
        md,
        "`scale.png`: per bucket of cells observed (x: bucket number × the bucket size in its \
         label), the replan median (dark blue) and p95 (light blue) and the new data → new tour \
         median (red), ms; the grey line is 100 ms.\n"
    );
    let _ = writeln!(
        md,
        "| simulated time | cells observed | real-time factor | replan ms (median / p95 / max) | new data → new tour ms | learning ms | GTSP vertices (median) | view cells (median) | view / all-pairs / GTSP ms (medians) | whole-map replans: count, ms |\n|---|---|---|---|---|---|---|---|---|---|"
    );
    for w in &r.windows {
        let opt = |v: Option<f64>| v.map_or("–".into(), |v| format!("{v:.0}"));
        let _ = writeln!(
            md,
            "| {:.0} s | {} | {:.0}× | {} | {} | {} | {} | {} | {} / {} / {} | {}: {} |",
            w.t_end_s,
            w.observed_cells,
            w.real_time_factor,
            fmt_q(&w.replan_ms),
            fmt_q(&w.data_to_tour_ms),
            fmt_q(&w.learning_ms),
            opt(w.vertices_median),
            opt(w.view_cells_median),
            opt(w.view_ms_median),
            opt(w.all_pairs_ms_median),
            opt(w.gtsp_ms_median),
            w.whole_map_replans,
            fmt_q(&w.whole_map_replan_ms)
        );
    }
    md
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn quantiles_take_the_nearest_rank_and_skip_non_finite_values() {
        let xs: Vec<f64> = (1..=20).map(f64::from).chain([f64::NAN]).collect();
        let q = Quantiles::of(&xs).unwrap();
        assert_eq!((q.count, q.median, q.p95, q.max), (20, 10.5, 19.0, 20.0));
        assert_eq!(Quantiles::of(&[f64::NAN]), None);
        assert_eq!(Quantiles::of(&[3.0]).unwrap().p95, 3.0);
    }

    #[test]
    fn windows_split_the_samples_and_replans_by_simulated_time() {
        let samples: Vec<Sample> = (0..=10)
            .map(|k| Sample {
                t: k as f64 * 10.0,
                wall: k as f64 * 0.5,
                cells: k * 100,
            })
            .collect();
        let replans: Vec<Replan> = (1..=10)
            .map(|k| Replan {
                t: k as f64 * 10.0 - 5.0,
                replan_ms: k as f64,
                data_to_tour_ms: 2.0 * k as f64,
                vertices: k,
                all_pairs_ms: 1.0,
                view_ms: 1.0,
                gtsp_ms: 1.0,
                whole_map: k == 7,
                view_cells: 100 * k,
            })
            .collect();
        let learning = [(12.0, 3.0), (48.0, 5.0), (71.0, 9.0)];
        let w = windows(&samples, &replans, &learning, 50.0);
        assert_eq!(w.len(), 2);
        assert_eq!((w[0].t_end_s, w[0].observed_cells), (50.0, 500));
        assert!((w[0].real_time_factor - 20.0).abs() < 1e-9);
        assert_eq!(w[0].replan_ms.unwrap().count, 5);
        assert_eq!(w[1].replan_ms.unwrap().max, 10.0);
        assert_eq!(w[0].learning_ms.unwrap().count, 2);
        assert_eq!(w[1].learning_ms.unwrap().median, 9.0);
        assert_eq!((w[0].whole_map_replans, w[1].whole_map_replans), (0, 1));
        assert_eq!(w[1].view_cells_median, Some(800.0));
        assert!(w[0].whole_map_replan_ms.is_none());
        assert_eq!(w[1].whole_map_replan_ms.unwrap().median, 7.0);
        assert_eq!(cells_at(&samples, 35.0), 300);
        assert_eq!(nice_bucket(4_000_000), 100_000);
        assert_eq!(nice_bucket(500), 1000);
    }
}
