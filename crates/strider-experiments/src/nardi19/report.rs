//! The reports of `strider navigate`: the typed `navigate.json`, `navigate.md` with Nardi19
//! Table I beside ours, and the summary lines for the terminal.

use std::fmt::Write as _;

use serde::Serialize;

use super::metrics::{aggregate, all_names, converged_run, costs, distinct};
use super::{Config, Group, NavigateOptions, Task, WITHIN};
use crate::stats::{MeanStd, mean_std_finite};
use strider_explore::navigate::{NavigationLog, Objective};

/// Published Nardi19 Table I: (RMS error, Mahalanobis distance) per model, site 1 then site 2.
const PUBLISHED: [(&str, [(f64, f64); 2]); 3] = [
    ("single-gp", [(16.15, 265.84), (15.364, 316.28)]),
    ("gp-mixture", [(9.29, 132.52), (9.43, 150.24)]),
    ("gp-mixture-aerial", [(4.96, 79.17), (6.91, 151.42)]),
];

/// How the figures of the report are defined.
#[derive(Clone, Debug, Serialize)]
pub struct Definitions {
    experienced_cost: &'static str,
    rmse: &'static str,
    mahalanobis: &'static str,
    aggregation: &'static str,
    converged_run: &'static str,
    visited_cells: &'static str,
}

const DEFINITIONS: Definitions = Definitions {
    experienced_cost: "vibration: integral of the measured vibration over the driven distance (m/s^2 * m); energy: measured energy (J)",
    rmse: "sqrt(mean over admissible cells of (mu - f)^2), model after the run",
    mahalanobis: "sqrt(sum over admissible cells of (mu - f)^2 / sigma^2), sigma^2 the mixture's latent variance (Eq. 3)",
    aggregation: "per site: mean and sample standard deviation over seeds",
    converged_run: "first run from which every later run experiences at most 1.1 x the least-cost path's drive",
    visited_cells: "cells with an averaged observation (the training set) after the last run",
};

/// RMSE and Mahalanobis distance.
#[derive(Clone, Copy, Debug, Serialize)]
pub struct Accuracy {
    rmse: f64,
    mahalanobis: f64,
}

/// One model of the published Table I.
#[derive(Clone, Debug, Serialize)]
pub struct PublishedRow {
    model: &'static str,
    site_1: Accuracy,
    site_2: Accuracy,
}

/// A configuration's figures over the seeds of a site.
#[derive(Clone, Debug, Serialize)]
pub struct SummaryRow {
    site: u64,
    task: &'static str,
    objective: &'static str,
    config: String,
    seeds: usize,
    rmse: MeanStd,
    mahalanobis: MeanStd,
    visited_cells: MeanStd,
    final_ratio_to_least_cost: MeanStd,
    last5_ratio_to_least_cost: MeanStd,
    run1_ratio_to_least_cost: MeanStd,
    converged_seeds: usize,
    converged_run_of_converged: MeanStd,
}

/// A baseline's drive.
#[derive(Clone, Debug, Serialize)]
pub struct ShortestReport {
    planned_length_m: f64,
    experienced_cost: f64,
    distance_m: f64,
    reached: bool,
}

/// The least-cost baseline's drive.
#[derive(Clone, Debug, Serialize)]
pub struct LeastCostReport {
    planned_cost: f64,
    experienced_cost: f64,
    distance_m: f64,
    reached: bool,
}

/// A configuration after its last run.
#[derive(Clone, Debug, Serialize)]
pub struct FinalReport {
    rmse: Option<f64>,
    mahalanobis: Option<f64>,
    visited_cells: Option<usize>,
    experienced_cost: Option<f64>,
    ratio_to_least_cost: Option<f64>,
    converged_run: Option<usize>,
    components: Option<usize>,
}

/// One run of a configuration.
#[derive(Clone, Debug, Serialize)]
pub struct RunReport {
    run: usize,
    experienced_cost: f64,
    distance_m: f64,
    time_s: f64,
    reached: bool,
    new_cells: usize,
    visited_cells: usize,
    centroids: Vec<f64>,
    rmse: f64,
    mahalanobis: f64,
    plan_ms: f64,
    update_ms: f64,
}

/// One configuration of a group.
#[derive(Clone, Debug, Serialize)]
pub struct ConfigReport {
    model: &'static str,
    rectifier: &'static str,
    #[serde(rename = "final")]
    last: FinalReport,
    runs: Vec<RunReport>,
}

/// One (site, seed, task, objective) group.
#[derive(Clone, Debug, Serialize)]
pub struct GroupReport {
    site: u64,
    seed: u64,
    task: &'static str,
    objective: &'static str,
    shortest: ShortestReport,
    least_cost: LeastCostReport,
    configs: Vec<ConfigReport>,
}

/// `navigate.json`.
#[derive(Clone, Debug, Serialize)]
pub struct NavigateReport {
    scenario: String,
    sites: Vec<u64>,
    seeds: Vec<u64>,
    runs: usize,
    lambda: f64,
    definitions: Definitions,
    published_table_1: Vec<PublishedRow>,
    summary: Vec<SummaryRow>,
    groups: Vec<GroupReport>,
    wall_s: f64,
}

impl NavigateReport {
    pub(crate) fn new(o: &NavigateOptions, groups: &[Group], wall_s: f64) -> Self {
        let acc = |(rmse, mahalanobis): (f64, f64)| Accuracy { rmse, mahalanobis };
        Self {
            scenario: o.scenario.clone(),
            sites: o.sites.clone(),
            seeds: (o.seed..=o.seed + (o.seeds - 1)).collect(),
            runs: o.runs,
            lambda: o.lambda,
            definitions: DEFINITIONS,
            published_table_1: PUBLISHED
                .iter()
                .map(|(model, s)| PublishedRow {
                    model,
                    site_1: acc(s[0]),
                    site_2: acc(s[1]),
                })
                .collect(),
            summary: summary(groups),
            groups: groups.iter().map(group_report).collect(),
            wall_s,
        }
    }
}

fn group_report(g: &Group) -> GroupReport {
    let lc = g.least_cost.1.experienced_cost;
    GroupReport {
        site: g.site,
        seed: g.seed,
        task: g.task.name(),
        objective: g.objective.name(),
        shortest: ShortestReport {
            planned_length_m: g.shortest.0,
            experienced_cost: g.shortest.1.experienced_cost,
            distance_m: g.shortest.1.distance_m,
            reached: g.shortest.1.reached,
        },
        least_cost: LeastCostReport {
            planned_cost: g.least_cost.0,
            experienced_cost: lc,
            distance_m: g.least_cost.1.distance_m,
            reached: g.least_cost.1.reached,
        },
        configs: g
            .configs
            .iter()
            .map(|(c, log, metrics)| config_report(c, log, metrics, lc))
            .collect(),
    }
}

fn config_report(c: &Config, log: &NavigationLog, metrics: &[(f64, f64)], lc: f64) -> ConfigReport {
    let last = log.runs.last();
    ConfigReport {
        model: c.model.name(),
        rectifier: c.rectifier.name(),
        last: FinalReport {
            rmse: metrics.last().map(|m| m.0),
            mahalanobis: metrics.last().map(|m| m.1),
            visited_cells: last.map(|r| r.visited_cells),
            experienced_cost: last.map(|r| r.drive.experienced_cost),
            ratio_to_least_cost: last.map(|r| r.drive.experienced_cost / lc),
            converged_run: converged_run(&costs(log), lc),
            components: log.model.as_ref().map(|m| m.components().len()),
        },
        runs: log
            .runs
            .iter()
            .zip(metrics)
            .map(|(r, m)| RunReport {
                run: r.run,
                experienced_cost: r.drive.experienced_cost,
                distance_m: r.drive.distance_m,
                time_s: r.drive.time_s,
                reached: r.drive.reached,
                new_cells: r.new_cells,
                visited_cells: r.visited_cells,
                centroids: r.centroids.clone(),
                rmse: m.0,
                mahalanobis: m.1,
                plan_ms: r.plan_ms,
                update_ms: r.update_ms,
            })
            .collect(),
    }
}

fn summary(groups: &[Group]) -> Vec<SummaryRow> {
    let mut out = Vec::new();
    for site in distinct(groups.iter().map(|g| g.site)) {
        for (task, objective) in distinct(groups.iter().map(|g| (g.task, g.objective))) {
            for name in all_names() {
                let Some(a) = aggregate(groups, site, task, objective, &name) else {
                    continue;
                };
                let conv: Vec<f64> = a
                    .converged
                    .iter()
                    .map(|c| c.map_or(f64::NAN, |r| r as f64))
                    .collect();
                out.push(SummaryRow {
                    site,
                    task: task.name(),
                    objective: objective.name(),
                    config: name,
                    seeds: a.rmse.len(),
                    rmse: MeanStd::of_finite(&a.rmse),
                    mahalanobis: MeanStd::of_finite(&a.mahal),
                    visited_cells: MeanStd::of_finite(&a.visited),
                    final_ratio_to_least_cost: MeanStd::of_finite(&a.ratio),
                    last5_ratio_to_least_cost: MeanStd::of_finite(&a.ratio_last5),
                    run1_ratio_to_least_cost: MeanStd::of_finite(&a.run1_ratio),
                    converged_seeds: a.converged.iter().filter(|c| c.is_some()).count(),
                    converged_run_of_converged: MeanStd::of_finite(&conv),
                });
            }
        }
    }
    out
}

/// mean ± std of the finite values with `digits` decimals ("–" without any).
fn pm(v: &[f64], digits: usize) -> String {
    let (m, s) = mean_std_finite(v);
    if m.is_nan() {
        return "–".into();
    }
    format!("{m:.digits$} ± {s:.digits$}")
}

/// `navigate.md`: Table I beside the published one, then per task and objective the
/// experienced cost against the least-cost path.
pub(crate) fn markdown(o: &NavigateOptions, groups: &[Group], wall_s: f64) -> String {
    let mut md = String::new();
    let _ = write!(
        md,
        "# Nardi19 navigation on {} (sites = world seeds {:?}, seeds {}..={}, {} runs, λ = {})\n\n",
        o.scenario,
        o.sites,
        o.seed,
        o.seed + o.seeds - 1,
        o.runs,
        o.lambda
    );
    let _ = write!(md, "Produced by `{}`. ", o.command());
    md.push_str(
        "Figures are mean ± sample std over seeds. RMSE = √(mean over admissible cells of \
         (μ − f)²) and Mahalanobis D = √(Σ over admissible cells of (μ − f)²/σ²) of the model \
         after the last run against the true field f (terrain vibration, m/s²). Published: \
         Nardi19 Table I (real data, their units), beside ours for the ordering.\n\n",
    );
    table_1(&mut md, &o.sites, groups);
    for (task, objective) in distinct(groups.iter().map(|g| (g.task, g.objective))) {
        cost_table(&mut md, &o.sites, groups, task, objective);
    }
    let _ = writeln!(
        md,
        "Runs within {:.0} % of LC: a configuration converges at the first run from which every \
         later run experiences at most {:.2} × the least-cost path's drive; \"converged run\" \
         averages the seeds that converged. Wall time {wall_s:.1} s.",
        WITHIN * 100.0,
        1.0 + WITHIN
    );
    md
}

/// Table I: model accuracy after the last run of the locations task.
fn table_1(md: &mut String, sites: &[u64], groups: &[Group]) {
    md.push_str("## Table I: model accuracy after the last run (locations A→B→C→D, vibration)\n\n");
    md.push_str("| model | site | RMSE (ours) | Mahalanobis (ours) | visited cells | RMSE / Mahal. (published) |\n|---|---|---|---|---|---|\n");
    for (k, site) in sites.iter().enumerate() {
        for (name, publ) in PUBLISHED {
            let Some(a) = aggregate(groups, *site, Task::Locations, Objective::Vibration, name)
            else {
                continue;
            };
            let p = publ
                .get(k)
                .map_or("–".into(), |(r, m)| format!("{r} / {m}"));
            let _ = writeln!(
                md,
                "| {name} | {site} | {} | {} | {} | {p} |",
                pm(&a.rmse, 3),
                pm(&a.mahal, 1),
                pm(&a.visited, 1)
            );
        }
    }
    md.push_str("\nPublished site k is compared with our k-th site; Nardi19 also reports about 20 % fewer visited locations with the aerial image.\n\n");
}

/// The experienced cost of every configuration against the least-cost path.
fn cost_table(md: &mut String, sites: &[u64], groups: &[Group], task: Task, objective: Objective) {
    let _ = write!(
        md,
        "## {} minimising {}: experienced cost against the least-cost path\n\n",
        task.name(),
        objective.name()
    );
    md.push_str("| config | site | run 1 / LC | run 25 / LC | last 5 / LC | converged (seeds) | converged run | visited cells | RMSE | Mahalanobis |\n|---|---|---|---|---|---|---|---|---|---|\n");
    for site in sites {
        for name in all_names() {
            let Some(a) = aggregate(groups, *site, task, objective, &name) else {
                continue;
            };
            let conv: Vec<f64> = a.converged.iter().flatten().map(|&r| r as f64).collect();
            let _ = writeln!(
                md,
                "| {name} | {site} | {} | {} | {} | {}/{} | {} | {} | {} | {} |",
                pm(&a.run1_ratio, 3),
                pm(&a.ratio, 3),
                pm(&a.ratio_last5, 3),
                conv.len(),
                a.converged.len(),
                pm(&conv, 1),
                pm(&a.visited, 1),
                pm(&a.rmse, 3),
                pm(&a.mahal, 1)
            );
        }
        let sel: Vec<&Group> = groups
            .iter()
            .filter(|g| g.site == *site && g.task == task && g.objective == objective)
            .collect();
        let sp: Vec<f64> = sel
            .iter()
            .map(|g| g.shortest.1.experienced_cost / g.least_cost.1.experienced_cost)
            .collect();
        let lc: Vec<f64> = sel
            .iter()
            .map(|g| g.least_cost.1.experienced_cost)
            .collect();
        let _ = write!(
            md,
            "| shortest path | {site} | {} | | | | | | | |\n| least-cost path (LC, experienced {}) | {site} | 1 | | | | | | | |\n",
            pm(&sp, 3),
            pm(&lc, 1)
        );
    }
    md.push('\n');
}

/// One-line summaries for the terminal.
pub(crate) fn summary_lines(groups: &[Group]) -> Vec<String> {
    let mut out = Vec::new();
    for site in distinct(groups.iter().map(|g| g.site)) {
        for (task, objective) in distinct(groups.iter().map(|g| (g.task, g.objective))) {
            let mut parts = Vec::new();
            for name in all_names() {
                if let Some(a) = aggregate(groups, site, task, objective, &name) {
                    let (r, _) = mean_std_finite(&a.rmse);
                    let (q, _) = mean_std_finite(&a.ratio);
                    let (v, _) = mean_std_finite(&a.visited);
                    parts.push(format!(
                        "{name}: RMSE {r:.3}, run-{} cost {q:.3}×LC, {v:.0} cells",
                        groups[0].configs.first().map_or(0, |c| c.1.runs.len())
                    ));
                }
            }
            out.push(format!(
                "site {site} {} {}: {}",
                task.name(),
                objective.name(),
                parts.join("; ")
            ));
        }
    }
    out
}
