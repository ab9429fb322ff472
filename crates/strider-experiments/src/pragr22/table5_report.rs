//! The reproduced Prágr22 Table 5 beside the published one: its rows, the relations the paper
//! reports with their tests, `table5.json` and `table5.md`.

use std::fmt::Write as _;

use serde::Serialize;

use strider_explore::Strategy;
use strider_explore::evaluate::NavigationMode;

use super::table5_segments::{SegmentRow, segment_rows, segments_markdown};
use super::table5_trials::{Table5Options, TrialResult};
use crate::cancel::Completion;
use crate::stats::{MeanStd, Summary, mann_whitney_u, max, median_max, paired_win_fraction};

/// Published values (Prágr22 Table 5): row, mean, std.
const PUBLISHED: &[(&str, f64, f64)] = &[
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

/// The relations the paper reports, each as "a < b": (relation, row a, row b).
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

/// One row of the table: our trials' values beside the published figure.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Row {
    /// The row's name.
    pub row: String,
    /// Summary of our values (`null` without any).
    pub ours: Option<Summary>,
    /// Tours that did not reach every waypoint (their times are in the values).
    pub incomplete_tours: usize,
    /// The published figure.
    pub published: Option<MeanStd>,
    /// Our values, one per trial.
    pub values: Vec<f64>,
}

impl Row {
    pub(crate) fn new(row: String, values: Vec<f64>, incomplete_tours: usize) -> Self {
        let published = PUBLISHED.iter().find(|p| p.0 == row).map(|p| MeanStd {
            mean: p.1,
            std: p.2,
        });
        Self {
            ours: Summary::of(&values).ok(),
            row,
            incomplete_tours,
            published,
            values,
        }
    }
}

/// The Mann–Whitney test of a relation.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct MannWhitneyReport {
    /// U of the first sample.
    pub u_a: f64,
    /// Two-sided p.
    pub p_two_sided: f64,
    /// p of "a is less than b".
    pub p_less: f64,
    /// p of "a is greater than b".
    pub p_greater: f64,
    /// Exact or normal.
    pub method: String,
    /// Common-language effect size.
    pub effect_size: f64,
}

/// A relation "a < b" between two rows, index-paired by trial (same world and mission seed):
/// ratio of means, paired wins of `a` over `b` and the Mann–Whitney test of `a` against `b`.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Relation {
    /// Mean of a over mean of b.
    pub ratio_of_means: Option<f64>,
    /// Fraction of trials in which a was less than b.
    pub paired_win_fraction: Option<f64>,
    /// The test.
    pub mann_whitney: Option<MannWhitneyReport>,
    /// The relation.
    pub relation: &'static str,
    /// Row a.
    pub a: &'static str,
    /// Row b.
    pub b: &'static str,
}

/// The relations of the paper between `rows`.
pub(crate) fn relations(rows: &[Row]) -> Vec<Relation> {
    let row = |name: &str| -> &[f64] {
        rows.iter()
            .find(|r| r.row == name)
            .map_or(&[][..], |r| &r.values[..])
    };
    RELATIONS
        .iter()
        .map(|&(relation, a, b)| {
            let (xa, xb) = (row(a), row(b));
            let summaries = Summary::of(xa).ok().zip(Summary::of(xb).ok());
            Relation {
                ratio_of_means: summaries.map(|(sa, sb)| sa.mean / sb.mean),
                paired_win_fraction: summaries.and(paired_win_fraction(xa, xb).ok()),
                mann_whitney: summaries.and(mann_whitney_u(xa, xb).ok()).map(|m| {
                    MannWhitneyReport {
                        u_a: m.u_a,
                        p_two_sided: m.p_two_sided,
                        p_less: m.p_less,
                        p_greater: m.p_greater,
                        method: format!("{:?}", m.method),
                        effect_size: m.effect_size,
                    }
                }),
                relation,
                a,
                b,
            }
        })
        .collect()
}

/// Replanning latency on `courtyard-large`, ms.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct LargeReplanMs {
    /// Median of the per-mission medians.
    pub median_of_medians: Option<f64>,
    /// Worst replan of any mission.
    pub max: f64,
}

/// `table5.json`.
#[derive(Clone, Debug, Serialize)]
pub struct Table5Report {
    /// Whether every trial finished, or the bench was interrupted (then the rows hold the
    /// trials finished so far; `--resume` completes them).
    #[serde(flatten)]
    pub completion: Completion,
    /// The options the table was run with.
    #[serde(flatten)]
    pub options: Table5Options,
    /// The rows.
    pub rows: Vec<Row>,
    /// The relations.
    pub relations: Vec<Relation>,
    /// Small tour 1 segment by segment, in every navigation mode.
    pub tour1_segments: Vec<SegmentRow>,
    /// Replanning latency on the large world.
    pub large_replan_ms: LargeReplanMs,
    /// Wall time, s.
    pub wall_s: f64,
    /// Every trial.
    pub trial_results: Vec<TrialResult>,
}

impl Table5Report {
    pub(crate) fn new(
        o: &Table5Options,
        trials: Vec<TrialResult>,
        wall_s: f64,
        completion: Completion,
    ) -> Self {
        let rows = rows(&trials);
        let large: Vec<&TrialResult> = trials
            .iter()
            .filter(|t| t.trial.scenario == "courtyard-large" && t.trial.strategy == "gtsp")
            .collect();
        let medians: Vec<f64> = large.iter().map(|t| t.replan_ms_median).collect();
        let worst: Vec<f64> = large.iter().map(|t| t.replan_ms_max).collect();
        Self {
            completion,
            options: o.clone(),
            relations: relations(&rows),
            tour1_segments: segment_rows(&trials),
            rows,
            large_replan_ms: LargeReplanMs {
                median_of_medians: (!medians.is_empty()).then(|| median_max(&medians).0),
                max: max(&worst).unwrap_or(0.0).max(0.0),
            },
            wall_s,
            trial_results: trials,
        }
    }
}

/// `table5.md`: the rows beside the published figures, then the relations.
pub fn markdown(r: &Table5Report) -> String {
    let mut md = String::new();
    let o = &r.options;
    let _ = writeln!(
        md,
        "# Prágr22 Table 5 reproduction\n\n{} small and {} large trials per row over {} world seeds \
         (`strider bench table5 --trials {} --large-trials {} --world-seeds {}`), {:.0} s wall on \
         {} jobs. Times in simulated seconds, mean ± std. Our simulator is not the paper's: the \
         orderings and rough ratios are what should reproduce.\n",
        o.trials,
        o.large_trials,
        o.world_seeds,
        o.trials,
        o.large_trials,
        o.world_seeds,
        r.wall_s,
        o.jobs
    );
    if !o.sets.is_empty() {
        let sets: Vec<String> = o
            .sets
            .iter()
            .map(|(k, v)| format!("--set {k}={v}"))
            .collect();
        let _ = writeln!(
            md,
            "Strategy parameters set for every trial: `{}`.\n",
            sets.join(" ")
        );
    }
    if let Some(s) = o.shard {
        let _ = writeln!(
            md,
            "**Shard {}/{}** of the trials: `strider bench merge` joins the shards' folders into \
             the whole table.\n",
            s.k, s.n
        );
    }
    if r.completion.interrupted {
        let _ = writeln!(
            md,
            "**Incomplete**: interrupted after {} trials; `--resume` runs the rest.\n",
            r.trial_results.len()
        );
    }
    let _ = writeln!(md, "| experiment | ours | published | incomplete tours |");
    let _ = writeln!(md, "|---|---|---|---|");
    for row in &r.rows {
        let p = row
            .published
            .map_or("–".into(), |p| format!("{:.2} ± {:.2}", p.mean, p.std));
        let ours = row.ours.map_or("–".into(), |s| {
            format!("{:.1} ± {:.1} (n={})", s.mean, s.std, s.n)
        });
        let _ = writeln!(
            md,
            "| {} | {ours} | {p} | {} |",
            row.row, row.incomplete_tours
        );
    }
    relations_markdown(&mut md, &r.relations);
    segments_markdown(&mut md, &r.tour1_segments);
    let l = &r.large_replan_ms;
    let large_trials = r
        .trial_results
        .iter()
        .any(|t| t.trial.scenario == "courtyard-large" && t.trial.strategy == "gtsp");
    let _ = writeln!(
        md,
        "\nReplanning latency on courtyard-large (goal identification is separate): median of \
         per-mission medians {} ms, worst {} ms.",
        l.median_of_medians
            .map_or("–".into(), |x| format!("{x:.1}")),
        if large_trials {
            format!("{:.1}", l.max)
        } else {
            "–".to_string()
        }
    );
    md
}

fn relations_markdown(md: &mut String, relations: &[Relation]) {
    let _ = writeln!(
        md,
        "\n| relation (a < b) | ratio of means a/b | paired wins of a | Mann–Whitney p (a < b) | p two-sided |"
    );
    let _ = writeln!(md, "|---|---|---|---|---|");
    let finite = |x: Option<f64>| x.filter(|x| x.is_finite());
    let f =
        |x: Option<f64>, digits: usize| finite(x).map_or("–".into(), |x| format!("{x:.digits$}"));
    let e = |x: Option<f64>| finite(x).map_or("–".into(), |x| format!("{x:.2e}"));
    for v in relations {
        let mw = v.mann_whitney.as_ref();
        let _ = writeln!(
            md,
            "| {} | {} | {} | {} | {} |",
            v.relation,
            f(v.ratio_of_means, 3),
            f(v.paired_win_fraction, 2),
            e(mw.map(|m| m.p_less)),
            e(mw.map(|m| m.p_two_sided)),
        );
    }
}

/// The rows of the table from the trials (see [`Row`]).
pub(crate) fn rows(trials: &[TrialResult]) -> Vec<Row> {
    let select = |sc: &str, st: Strategy| -> Vec<&TrialResult> {
        trials
            .iter()
            .filter(|t| t.trial.scenario == sc && t.trial.strategy == st.name())
            .collect()
    };
    let small = select("courtyard-small", Strategy::Gtsp);
    let greedy = select("courtyard-small", Strategy::Greedy);
    let large = select("courtyard-large", Strategy::Gtsp);
    let spatial = select("courtyard-large", Strategy::SpatialOnly);
    let tour = |name: String, set: &[&TrialResult], k: usize, m: NavigationMode| {
        let driven: Vec<(f64, bool)> = set.iter().filter_map(|t| t.tour(k, m)).collect();
        Row::new(
            name,
            driven.iter().map(|x| x.0).collect(),
            driven.iter().filter(|x| !x.1).count(),
        )
    };
    let expl = |name: &str, set: &[&TrialResult]| {
        Row::new(
            name.to_string(),
            set.iter().map(|t| t.trial.exploration_time_s).collect(),
            0,
        )
    };
    let mut rows = Vec::new();
    for k in 0..2 {
        for m in NavigationMode::ALL {
            rows.push(tour(
                format!("small tour {} {}", k + 1, m.name()),
                &small,
                k,
                m,
            ));
        }
    }
    rows.push(expl("small exploration gtsp", &small));
    rows.push(expl("small exploration greedy", &greedy));
    let learned = NavigationMode::Learned;
    rows.push(tour("large tour proposed".into(), &large, 0, learned));
    rows.push(tour("large tour spatial-only".into(), &spatial, 0, learned));
    rows.push(expl("large exploration proposed", &large));
    rows.push(expl("large exploration spatial-only", &spatial));
    rows
}
