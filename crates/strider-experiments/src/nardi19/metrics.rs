//! The Nardi19 metrics: a model's accuracy against the true field, convergence to the
//! least-cost path, and the per-site aggregation over seeds.

use strider_explore::navigate::{ModelField, ModelKind, NavigationLog, Objective};
use strider_plan::grid::lcb::Rectifier;

use super::{Config, Group, Task, WITHIN};
use crate::stats::mean;

/// (RMSE, Mahalanobis distance) of a model field against the truth over admissible cells.
pub(crate) fn accuracy(field: &ModelField, truth: &[f64], admissible: &[bool]) -> (f64, f64) {
    let (mut se, mut m2, mut n) = (0.0, 0.0, 0usize);
    for k in 0..truth.len() {
        if !admissible[k] || !truth[k].is_finite() {
            continue;
        }
        let e = field.mean[k] as f64 - truth[k];
        let s = field.std[k] as f64;
        se += e * e;
        m2 += e * e / (s * s).max(1e-12);
        n += 1;
    }
    if n == 0 {
        return (f64::NAN, f64::NAN);
    }
    ((se / n as f64).sqrt(), m2.sqrt())
}

/// First run from which every run stays within [`WITHIN`] of the least-cost path's drive.
pub(crate) fn converged_run(costs: &[f64], least: f64) -> Option<usize> {
    let ok = |c: f64| c <= (1.0 + WITHIN) * least;
    let mut first = None;
    for (r, &c) in costs.iter().enumerate() {
        if ok(c) {
            first.get_or_insert(r + 1);
        } else {
            first = None;
        }
    }
    first
}

/// The configuration's name in tables: the model, and `(relu)` for the ReLU rectifier.
pub(crate) fn config_name(c: &Config) -> String {
    match c.rectifier {
        Rectifier::Softplus => c.model.name().to_string(),
        Rectifier::Relu => format!("{} (relu)", c.model.name()),
    }
}

/// The experienced cost of every run.
pub(crate) fn costs(log: &NavigationLog) -> Vec<f64> {
    log.runs.iter().map(|r| r.drive.experienced_cost).collect()
}

/// Per (site, task, objective, config): the seeds' final figures.
pub(crate) struct Agg {
    pub(crate) rmse: Vec<f64>,
    pub(crate) mahal: Vec<f64>,
    pub(crate) visited: Vec<f64>,
    pub(crate) ratio: Vec<f64>,
    pub(crate) ratio_last5: Vec<f64>,
    pub(crate) converged: Vec<Option<usize>>,
    pub(crate) run1_ratio: Vec<f64>,
}

/// The seeds' figures of configuration `name` on (site, task, objective); `None` without any.
pub(crate) fn aggregate(
    groups: &[Group],
    site: u64,
    task: Task,
    objective: Objective,
    name: &str,
) -> Option<Agg> {
    let mut a = Agg {
        rmse: vec![],
        mahal: vec![],
        visited: vec![],
        ratio: vec![],
        ratio_last5: vec![],
        converged: vec![],
        run1_ratio: vec![],
    };
    for g in groups
        .iter()
        .filter(|g| g.site == site && g.task == task && g.objective == objective)
    {
        let lc = g.least_cost.1.experienced_cost;
        for (_, log, metrics) in g.configs.iter().filter(|(c, ..)| config_name(c) == name) {
            let cs = costs(log);
            if let Some(m) = metrics.last() {
                a.rmse.push(m.0);
                a.mahal.push(m.1);
            }
            if let Some(r) = log.runs.last() {
                a.visited.push(r.visited_cells as f64);
            }
            if let Some(&c) = cs.last() {
                a.ratio.push(c / lc);
            }
            let tail = &cs[cs.len().saturating_sub(5)..];
            a.ratio_last5.push(mean(tail).unwrap_or(0.0) / lc);
            if let Some(&c) = cs.first() {
                a.run1_ratio.push(c / lc);
            }
            a.converged.push(converged_run(&cs, lc));
        }
    }
    (!a.rmse.is_empty()).then_some(a)
}

/// Every configuration's name, in table order.
pub(crate) fn all_names() -> Vec<String> {
    let mut v: Vec<String> = ModelKind::ALL
        .iter()
        .map(|m| m.name().to_string())
        .collect();
    v.push(format!("{} (relu)", ModelKind::GpMixtureAerial.name()));
    v
}

/// The distinct values of `it` in their first order.
pub(crate) fn distinct<T: PartialEq + Copy>(it: impl Iterator<Item = T>) -> Vec<T> {
    let mut v = Vec::new();
    for x in it {
        if !v.contains(&x) {
            v.push(x);
        }
    }
    v
}
