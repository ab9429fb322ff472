//! `strider navigate --lambdas 0.5,1,2,3`: the experiment once per λ of the lower confidence
//! bound μ − λσ (decision 29: the paper gives no λ), each into `DIR/lambda-X/`, then
//! `DIR/lambdas.{json,md}`: per λ, site and start-goal objective, the aerial mixture with
//! softplus against the same with ReLU, and whether each relation Nardi19 reports holds —
//! softplus converges in fewer runs, and ReLU explores more (visits more cells).

use std::fmt::Write as _;

use anyhow::{Result, bail};
use serde::Serialize;
use strider_explore::navigate::ModelKind;

use super::metrics::{aggregate, distinct};
use super::{Group, MAX_LAMBDA, NavigateOptions, Navigation, Task, run_groups};
use crate::io::{write_json, write_text};
use crate::progress::Progress;
use crate::stats::mean;

/// The most λ values in one sweep.
const MAX_LAMBDAS: usize = 16;

/// One rectifier's figures over the seeds.
#[derive(Clone, Copy, Debug, Serialize)]
pub struct Side {
    /// Seeds that converged to within 10 % of the least-cost path.
    converged: usize,
    seeds: usize,
    /// Mean run of convergence, a seed that never converged counting as one run past the last.
    convergence_run: f64,
    /// Mean cells visited over all runs.
    visited_cells: f64,
}

/// One (λ, site, objective) row.
#[derive(Clone, Debug, Serialize)]
pub struct LambdaRow {
    lambda: f64,
    site: u64,
    objective: &'static str,
    softplus: Side,
    relu: Side,
    /// Softplus converges in fewer runs than ReLU (Nardi19).
    softplus_converges_sooner: bool,
    /// ReLU visits more cells than softplus (Nardi19).
    relu_explores_more: bool,
}

fn side(
    groups: &[Group],
    site: u64,
    objective: super::Objective,
    name: &str,
    runs: usize,
) -> Option<Side> {
    let a = aggregate(groups, site, Task::StartGoal, objective, name)?;
    let run: Vec<f64> = a
        .converged
        .iter()
        .map(|c| c.map_or(runs as f64 + 1.0, |r| r as f64))
        .collect();
    Some(Side {
        converged: a.converged.iter().flatten().count(),
        seeds: a.converged.len(),
        convergence_run: mean(&run).unwrap_or(f64::NAN),
        visited_cells: mean(&a.visited).unwrap_or(f64::NAN),
    })
}

fn rows(lambda: f64, groups: &[Group], runs: usize) -> Vec<LambdaRow> {
    let name = ModelKind::GpMixtureAerial.name();
    let relu = format!("{name} (relu)");
    let mut out = Vec::new();
    for site in distinct(groups.iter().map(|g| g.site)) {
        let objectives = distinct(
            groups
                .iter()
                .filter(|g| g.task == Task::StartGoal)
                .map(|g| g.objective),
        );
        for objective in objectives {
            let (Some(s), Some(r)) = (
                side(groups, site, objective, name, runs),
                side(groups, site, objective, &relu, runs),
            ) else {
                continue;
            };
            out.push(LambdaRow {
                lambda,
                site,
                objective: objective.name(),
                softplus: s,
                relu: r,
                softplus_converges_sooner: s.convergence_run < r.convergence_run,
                relu_explores_more: r.visited_cells > s.visited_cells,
            });
        }
    }
    out
}

/// `lambdas.json`.
#[derive(Clone, Debug, Serialize)]
pub struct LambdaSweep {
    command: String,
    runs: usize,
    rows: Vec<LambdaRow>,
}

fn markdown(s: &LambdaSweep) -> String {
    let mut m = String::new();
    let _ = writeln!(
        m,
        "# Nardi19 softplus against ReLU over λ (start-goal, aerial GP mixture)\n\nProduced by `{}`. Per λ: the seeds converged to within 10 % of the least-cost path, the mean run of convergence (a seed that never converged counts as run {}), and the cells visited by the end; each λ's full tables are in `lambda-X/navigate.md`. Nardi19: softplus converges sooner, ReLU explores more.\n",
        s.command,
        s.runs + 1
    );
    m.push_str("| λ | site | objective | softplus converged | softplus run | softplus cells | ReLU converged | ReLU run | ReLU cells | softplus sooner | ReLU explores more |\n|---|---|---|---|---|---|---|---|---|---|---|\n");
    let yes = |b: bool| if b { "yes" } else { "no" };
    for r in &s.rows {
        let _ = writeln!(
            m,
            "| {} | {} | {} | {}/{} | {:.1} | {:.0} | {}/{} | {:.1} | {:.0} | {} | {} |",
            r.lambda,
            r.site,
            r.objective,
            r.softplus.converged,
            r.softplus.seeds,
            r.softplus.convergence_run,
            r.softplus.visited_cells,
            r.relu.converged,
            r.relu.seeds,
            r.relu.convergence_run,
            r.relu.visited_cells,
            yes(r.softplus_converges_sooner),
            yes(r.relu_explores_more)
        );
    }
    m
}

/// Runs the experiment of `o` once per λ in `lambdas` (into `o.out/lambda-X/`) and writes
/// `lambdas.{json,md}` into `o.out`; returns each λ's summary.
pub fn sweep_lambdas(
    o: &NavigateOptions,
    lambdas: &[f64],
    progress: &dyn Progress,
) -> Result<Vec<Navigation>> {
    if lambdas.is_empty() || lambdas.len() > MAX_LAMBDAS {
        bail!(
            "--lambdas lists {} values: give 1 to {MAX_LAMBDAS}",
            lambdas.len()
        );
    }
    if let Some(l) = lambdas
        .iter()
        .find(|l| !(l.is_finite() && (0.0..=MAX_LAMBDA).contains(*l)))
    {
        bail!("--lambdas {l}: each must be a finite number from 0 to {MAX_LAMBDA}");
    }
    let mut done = Vec::new();
    let mut all = Vec::new();
    for &lambda in lambdas {
        let one = NavigateOptions {
            lambda,
            out: o.out.join(format!("lambda-{lambda}")),
            ..o.clone()
        };
        let (nav, groups) = run_groups(&one, progress)?;
        all.extend(rows(lambda, &groups, o.runs));
        done.push(nav);
    }
    let list: Vec<String> = lambdas.iter().map(|l| l.to_string()).collect();
    let command = o.command().replace(
        &format!(" --lambda {}", o.lambda),
        &format!(" --lambdas {}", list.join(",")),
    );
    let sweep = LambdaSweep {
        command,
        runs: o.runs,
        rows: all,
    };
    write_json(&o.out.join("lambdas.json"), &sweep)?;
    write_text(&o.out.join("lambdas.md"), &markdown(&sweep))?;
    Ok(done)
}
