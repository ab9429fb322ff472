//! The comparison's table: per scenario × strategy the summaries over trials, the pairwise
//! Mann–Whitney tests, and `compare.md`.

use std::collections::BTreeMap;

use strider_core::snapshot::Quantity;

use super::{CompareCell, CompareTrial, Comparison, PairTest};
use crate::stats::{Summary, mann_whitney_u};

pub(super) fn summarise(
    scenario: &str,
    strategy: &str,
    skipped: Option<String>,
    trials: &[&CompareTrial],
) -> CompareCell {
    let of = |v: Vec<f64>| Summary::of(&v).ok();
    let mut rmse: BTreeMap<String, Vec<f64>> = BTreeMap::new();
    for t in trials {
        for e in &t.cost_error {
            if e.rmse.is_finite() {
                rmse.entry(e.model.clone()).or_default().push(e.rmse);
            }
        }
    }
    CompareCell {
        scenario: scenario.to_string(),
        strategy: strategy.to_string(),
        skipped,
        exploration_time_s: of(trials.iter().map(|t| t.trial.exploration_time_s).collect()),
        observed_cells: of(trials
            .iter()
            .map(|t| t.trial.observed_cells as f64)
            .collect()),
        cost_rmse: rmse
            .into_iter()
            .filter_map(|(m, v)| Some((m, Summary::of(&v).ok()?)))
            .collect(),
        tour_time_s: of(trials
            .iter()
            .filter_map(|t| completed_tour_time(t))
            .collect()),
        tours_completed: trials
            .iter()
            .filter(|t| t.tour_completed == Some(true))
            .count(),
    }
}

/// The tour time of a trial whose tour completed.
fn completed_tour_time(t: &CompareTrial) -> Option<f64> {
    t.tour_time_s.filter(|_| t.tour_completed == Some(true))
}

/// A per-trial figure the pairwise tests compare.
type Measure = fn(&CompareTrial) -> Option<f64>;

pub(super) fn pair_tests(
    scenarios: &[String],
    names: &[String],
    trials: &[CompareTrial],
) -> Vec<PairTest> {
    let series = |sc: &str, st: &str, f: Measure| -> Vec<f64> {
        trials
            .iter()
            .filter(|t| t.trial.scenario == sc && t.trial.strategy == st)
            .filter_map(f)
            .collect()
    };
    let measures: [(&str, Measure); 2] = [
        ("exploration_time_s", |t| Some(t.trial.exploration_time_s)),
        ("tour_time_s", completed_tour_time),
    ];
    let mut out = Vec::new();
    for sc in scenarios {
        for (i, a) in names.iter().enumerate() {
            for b in &names[i + 1..] {
                for (measure, f) in measures {
                    let (x, y) = (series(sc, a, f), series(sc, b, f));
                    if let Ok(u) = mann_whitney_u(&x, &y) {
                        out.push(PairTest {
                            scenario: sc.clone(),
                            a: a.clone(),
                            b: b.clone(),
                            measure: measure.to_string(),
                            p_two_sided: u.p_two_sided,
                            p_a_less: u.p_less,
                        });
                    }
                }
            }
        }
    }
    out
}

/// median [min–max] of a summary, with `digits` decimals.
fn range(s: &Option<Summary>, digits: usize) -> String {
    s.as_ref().map_or_else(
        || "–".to_string(),
        |s| {
            format!(
                "{:.*} [{:.*}–{:.*}]",
                digits, s.median, digits, s.min, digits, s.max
            )
        },
    )
}

/// The unit of model `model`'s cost in the trials of `strategy` (empty for a dimensionless one).
fn unit_of(c: &Comparison, strategy: &str, model: &str) -> &'static str {
    let q = c
        .trials
        .iter()
        .filter(|t| t.trial.strategy == strategy)
        .flat_map(|t| &t.cost_error)
        .find(|e| e.model == model)
        .map(|e| e.quantity);
    match q {
        Some(Quantity::RollVariance) => " rad²",
        Some(Quantity::PushForce) => " N",
        _ => "",
    }
}

/// The tables of `compare.md`.
pub fn markdown(c: &Comparison, command: &str) -> String {
    use std::fmt::Write;
    let mut m = String::new();
    let _ = writeln!(m, "# Strategies compared on the same worlds\n");
    let _ = writeln!(
        m,
        "Produced by `{command}`: {} trials per scenario and strategy over {} world seeds. Medians with [min–max] over trials. Cost RMSE: each model's planning cost (a model without data plans with its prior) against the terrain table in its own quantity (inverse-velocity cost, dimensionless; roll variance, rad²; push force, N), over the cells that strategy's map observed and that are traversable in truth. Tour: the scenario's first benchmark tour with learned navigation on the Prágr22 models a passive learner fitted to the data the strategy collected; times over the trials whose tour completed.\n",
        c.trials_per_cell, c.world_seeds
    );
    let mut scenarios: Vec<&str> = c.cells.iter().map(|x| x.scenario.as_str()).collect();
    scenarios.dedup();
    for sc in scenarios {
        let _ = writeln!(m, "## {sc}\n");
        let _ = writeln!(
            m,
            "| strategy | exploration s | observed cells | learned cost RMSE | tour s (completed) | tours completed |"
        );
        let _ = writeln!(m, "|---|---|---|---|---|---|");
        for cell in c.cells.iter().filter(|x| x.scenario == sc) {
            if let Some(why) = &cell.skipped {
                let _ = writeln!(m, "| {} | cannot run: {why} | | | | |", cell.strategy);
                continue;
            }
            let rmse: Vec<String> = cell
                .cost_rmse
                .iter()
                .map(|(k, s)| format!("{k} {:.3}{}", s.median, unit_of(c, &cell.strategy, k)))
                .collect();
            let n = cell.exploration_time_s.as_ref().map_or(0, |s| s.n);
            let _ = writeln!(
                m,
                "| {} | {} | {} | {} | {} | {}/{} |",
                cell.strategy,
                range(&cell.exploration_time_s, 0),
                range(&cell.observed_cells, 0),
                if rmse.is_empty() {
                    "–".into()
                } else {
                    rmse.join(", ")
                },
                range(&cell.tour_time_s, 0),
                cell.tours_completed,
                n
            );
        }
        let tests: Vec<&PairTest> = c.tests.iter().filter(|t| t.scenario == sc).collect();
        if !tests.is_empty() {
            let _ = writeln!(
                m,
                "\nMann–Whitney U (two-sided p; p that the first is less):\n"
            );
            let _ = writeln!(m, "| pair | measure | p | p(first less) |");
            let _ = writeln!(m, "|---|---|---|---|");
            for t in tests {
                let _ = writeln!(
                    m,
                    "| {} vs {} | {} | {:.3} | {:.3} |",
                    t.a, t.b, t.measure, t.p_two_sided, t.p_a_less
                );
            }
        }
        let _ = writeln!(m);
    }
    m
}
