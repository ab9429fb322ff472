//! The results of the Prágr19 stream benchmark: per-learner curves, the findings the paper
//! reports, `learn_bench.json` and the figure `learn_bench.png` (Prágr19 Fig. 5).

use std::fmt;
use std::path::Path;

use anyhow::Result;
use serde::Serialize;
use strider_learn::bench::{LearnerSpec, StreamTrace};
use strider_scenario::Scenario;

use super::StreamOptions;
use crate::io::ordered_map;
use crate::render::{Canvas, compose, label, line_chart, palette};
use crate::stats::{column_means, column_stds, max};

/// Stream sizes at which the report gives the per-step times.
pub const REPORT_AT: [usize; 3] = [50, 150, 300];

/// A learner's per-step means over the repetitions.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Curve {
    /// The learner.
    #[serde(skip)]
    pub label: String,
    /// Learning time of step k, s.
    #[serde(rename = "learn_s")]
    pub learn: Vec<f64>,
    /// Inference time after step k, s.
    #[serde(rename = "infer_s")]
    pub infer: Vec<f64>,
    /// RMSE after step k.
    pub rmse: Vec<f64>,
    /// Its standard deviation over repetitions.
    pub rmse_std: Vec<f64>,
    /// Mean predictive standard deviation (`None` without confidence).
    pub mean_std: Option<Vec<f64>>,
}

impl Curve {
    /// Learner `i`'s curves over the repetitions `reps`, cut at `n` steps.
    pub(crate) fn of(
        label: String,
        reps: &[(Vec<StreamTrace>, usize)],
        i: usize,
        n: usize,
    ) -> Self {
        let col = |f: &dyn Fn(&StreamTrace) -> &Vec<f64>| -> Vec<Vec<f64>> {
            reps.iter().map(|r| f(&r.0[i])[..n].to_vec()).collect()
        };
        let rmse_rows = col(&|t| &t.rmse);
        let mean_std = reps[0].0[i].mean_std.as_ref().map(|_| {
            let rows: Vec<Vec<f64>> = reps
                .iter()
                .map(|r| {
                    r.0[i]
                        .mean_std
                        .as_ref()
                        .map_or(Vec::new(), |v| v[..n].to_vec())
                })
                .collect();
            column_means(&rows)
        });
        Self {
            label,
            learn: column_means(&col(&|t| &t.learn_s)),
            infer: column_means(&col(&|t| &t.infer_s)),
            rmse: column_means(&rmse_rows),
            rmse_std: column_stds(&rmse_rows),
            mean_std,
        }
    }
}

/// Learning time, inference time and RMSE at one stream size.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct AtStep {
    /// Learning time, s.
    pub learn_s: f64,
    /// Inference time, s.
    pub infer_s: f64,
    /// RMSE.
    pub rmse: f64,
}

/// One learner in `learn_bench.json`.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct LearnerReport {
    /// The largest one-step rise of the mean RMSE.
    pub max_rmse_rise: f64,
    /// The step it happened at.
    pub max_rmse_rise_at: usize,
    /// The sum of all rises (an expert that starts voting shows as a rise).
    pub sum_rmse_rises: f64,
    /// The per-step curves.
    #[serde(flatten)]
    pub curve: Curve,
    /// The figures at the stream sizes of [`REPORT_AT`].
    #[serde(serialize_with = "ordered_map")]
    pub at: Vec<(String, AtStep)>,
    /// RMSE after the last step.
    pub final_rmse: Option<f64>,
    /// RBCMs: the largest RMSE rise within 10 steps after a new expert starts.
    pub rmse_spike_after_new_experts: Option<f64>,
    /// Total learning time, s.
    pub total_learn_s: f64,
}

impl LearnerReport {
    fn new(spec: &LearnerSpec, c: &Curve) -> Self {
        let n = c.rmse.len();
        let at = REPORT_AT
            .iter()
            .filter(|&&k| k <= n)
            .map(|&k| {
                let step = AtStep {
                    learn_s: c.learn[k - 1],
                    infer_s: c.infer[k - 1],
                    rmse: c.rmse[k - 1],
                };
                (k.to_string(), step)
            })
            .collect();
        let (max_rmse_rise, max_rmse_rise_at) = c
            .rmse
            .windows(2)
            .enumerate()
            .map(|(k, w)| (w[1] - w[0], k + 2))
            .fold((0.0f64, 0usize), |a, b| if b.0 > a.0 { b } else { a });
        Self {
            max_rmse_rise,
            max_rmse_rise_at,
            sum_rmse_rises: c.rmse.windows(2).map(|w| (w[1] - w[0]).max(0.0)).sum(),
            curve: c.clone(),
            at,
            final_rmse: c.rmse.last().copied(),
            rmse_spike_after_new_experts: match spec {
                LearnerSpec::Rbcm { m_max, .. } => Some(spike_after_new_experts(&c.rmse, *m_max)),
                _ => None,
            },
            total_learn_s: c.learn.iter().sum::<f64>(),
        }
    }
}

/// The largest rise of `rmse` within 10 steps after a new expert starts (steps 51, 101, …)
/// over its value just before (Prágr19: "peaks when small experts join").
fn spike_after_new_experts(rmse: &[f64], m_max: usize) -> f64 {
    let mut worst = 0.0f64;
    let mut start = m_max; // 0-based index of step m_max + 1
    while start < rmse.len() {
        let before = rmse[start - 1];
        let peak = max(&rmse[start..(start + 10).min(rmse.len())]).unwrap_or(f64::NEG_INFINITY);
        worst = worst.max(peak - before);
        start += m_max;
    }
    worst
}

/// What the paper reports, measured.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Findings {
    /// Learning time of the exponential RBCM at the last step over at step 50.
    pub rbcm_exp_learn_ratio_last_over_50: f64,
    /// The same for the full GP.
    pub gp_exp_learn_ratio_last_over_50: f64,
    /// RMSE spike after new experts with m_min 25.
    pub rmse_spike_with_m_min_25: f64,
    /// RMSE spike after new experts with m_min 1.
    pub rmse_spike_with_m_min_1: f64,
    /// The learner with the least total learning time.
    pub fastest_learner_total_learning_time: String,
    /// Learners without a predictive confidence.
    pub learners_without_confidence: Vec<String>,
}

/// `learn_bench.json`.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct StreamReport {
    /// The protocol.
    pub protocol: &'static str,
    /// Scenario.
    pub scenario: String,
    /// World seed.
    pub world_seed: u64,
    /// Seed of the first stream.
    pub seed: u64,
    /// Repetitions.
    pub reps: usize,
    /// Distinct streams.
    pub streams: usize,
    /// Pairs asked for.
    pub pairs_target: usize,
    /// Pairs every repetition has (the curves' length).
    pub pairs: usize,
    /// Pairs per repetition.
    pub pairs_per_rep: Vec<usize>,
    /// How to read the figures.
    pub note: &'static str,
    /// What the paper reports, measured.
    pub findings: Findings,
    /// Per learner.
    #[serde(serialize_with = "ordered_map")]
    pub learners: Vec<(String, LearnerReport)>,
}

impl StreamReport {
    pub(crate) fn new(
        sc: &Scenario,
        o: &StreamOptions,
        streams: usize,
        pairs_per_rep: Vec<usize>,
        specs: &[LearnerSpec],
        curves: &[Curve],
    ) -> Self {
        let learners: Vec<(String, LearnerReport)> = specs
            .iter()
            .zip(curves)
            .map(|(spec, c)| (c.label.clone(), LearnerReport::new(spec, c)))
            .collect();
        let mut r = Self {
            protocol: "Prágr19 §V-A incremental stream",
            scenario: sc.name.clone(),
            world_seed: sc.world_seed,
            seed: o.seed,
            reps: o.reps,
            streams,
            pairs_target: o.pairs,
            pairs: pairs_per_rep.iter().copied().min().unwrap_or(0),
            pairs_per_rep,
            note: "per-step means over repetitions; times are wall-clock seconds per thread; RMSE against the recorded costs",
            findings: Findings {
                rbcm_exp_learn_ratio_last_over_50: 0.0,
                gp_exp_learn_ratio_last_over_50: 0.0,
                rmse_spike_with_m_min_25: 0.0,
                rmse_spike_with_m_min_1: 0.0,
                fastest_learner_total_learning_time: String::new(),
                learners_without_confidence: Vec::new(),
            },
            learners,
        };
        r.findings = r.measure_findings();
        r
    }

    fn learner(&self, label: &str) -> Option<&LearnerReport> {
        self.learners.iter().find(|l| l.0 == label).map(|l| &l.1)
    }

    /// Learning time of `label` at step `k` (the last step when beyond), s.
    fn learn_at(&self, label: &str, k: usize) -> f64 {
        self.learner(label)
            .and_then(|l| l.curve.learn.get(k.min(self.pairs) - 1).copied())
            .unwrap_or(f64::NAN)
    }

    fn spike(&self, label: &str) -> f64 {
        self.learner(label)
            .and_then(|l| l.rmse_spike_after_new_experts)
            .unwrap_or(f64::NAN)
    }

    fn measure_findings(&self) -> Findings {
        let n = self.pairs;
        let total = |l: &LearnerReport| l.total_learn_s;
        Findings {
            rbcm_exp_learn_ratio_last_over_50: self.learn_at("rbcm-exp", n)
                / self.learn_at("rbcm-exp", 50),
            gp_exp_learn_ratio_last_over_50: self.learn_at("gp-exp", n)
                / self.learn_at("gp-exp", 50),
            rmse_spike_with_m_min_25: self.spike("rbcm-exp"),
            rmse_spike_with_m_min_1: self.spike("rbcm-exp-mmin1"),
            fastest_learner_total_learning_time: self
                .learners
                .iter()
                .min_by(|a, b| total(&a.1).total_cmp(&total(&b.1)))
                .map_or(String::new(), |c| c.0.clone()),
            learners_without_confidence: self
                .learners
                .iter()
                .filter(|l| l.1.curve.mean_std.is_none())
                .map(|l| l.0.clone())
                .collect(),
        }
    }
}

impl StreamReport {
    /// The command that reproduces the report.
    pub fn command(&self) -> String {
        format!(
            "strider learn bench --protocol stream --reps {} --streams {} --pairs {} --seed {}",
            self.reps, self.streams, self.pairs_target, self.seed
        )
    }

    /// `learn_bench.md`: per learner the figures at the report's stream sizes, then the
    /// findings of Prágr19 §V-A measured.
    pub fn markdown(&self) -> String {
        let ks: Vec<usize> = REPORT_AT
            .iter()
            .copied()
            .filter(|&k| k <= self.pairs)
            .collect();
        let at = ks
            .iter()
            .map(|k| k.to_string())
            .collect::<Vec<_>>()
            .join(" / ");
        let mut m = format!(
            "# Prágr19 §V-A: incremental learners on `{}` (Fig. 5)\n\n\
             Produced by `{}`: {} repetitions on {} recorded streams of {} (descriptor, roll \
             variance) pairs. Per-step means over the repetitions; times are wall-clock per \
             thread, so they depend on the machine. The four curves of Fig. 5 are in \
             `learn_bench.png`, every step in `learn_bench.json`.\n\n\
             | learner | learn ms at n = {at} | infer ms at n = {at} | RMSE at n = {at} | final RMSE | RMSE spike after new experts | total learning s |\n\
             |---|---|---|---|---|---|---|\n",
            self.scenario,
            self.command(),
            self.reps,
            self.streams,
            self.pairs
        );
        for (label, l) in &self.learners {
            let row = |f: fn(&AtStep) -> f64, scale: f64, digits: usize| {
                l.at.iter()
                    .map(|(_, a)| format!("{:.digits$}", f(a) * scale))
                    .collect::<Vec<_>>()
                    .join(" / ")
            };
            let opt = |v: Option<f64>| v.map_or("–".into(), |v| format!("{v:.5}"));
            m.push_str(&format!(
                "| {label} | {} | {} | {} | {} | {} | {:.2} |\n",
                row(|a| a.learn_s, 1e3, 3),
                row(|a| a.infer_s, 1e3, 3),
                row(|a| a.rmse, 1.0, 5),
                opt(l.final_rmse),
                opt(l.rmse_spike_after_new_experts),
                l.total_learn_s
            ));
        }
        let f = &self.findings;
        m.push_str(&format!(
            "\n| finding (Prágr19 §V-A) | ours |\n|---|---|\n\
             | RBCM (exponential) learning time, last step over step 50 | {:.2} |\n\
             | full GP learning time, last step over step 50 | {:.2} |\n\
             | RMSE spike after new experts, m_min 25 / m_min 1 | {:.5} / {:.5} |\n\
             | fastest learner (total learning time) | {} |\n\
             | learners without a predictive confidence | {} |\n",
            f.rbcm_exp_learn_ratio_last_over_50,
            f.gp_exp_learn_ratio_last_over_50,
            f.rmse_spike_with_m_min_25,
            f.rmse_spike_with_m_min_1,
            f.fastest_learner_total_learning_time,
            f.learners_without_confidence.join(", ")
        ));
        m
    }
}

impl fmt::Display for StreamReport {
    /// The one-line summary for the terminal.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let n = self.pairs;
        let ks: Vec<usize> = REPORT_AT.iter().copied().filter(|&k| k <= n).collect();
        let list: Vec<String> = ks.iter().map(|k| k.to_string()).collect();
        write!(
            f,
            "stream ({} reps on {} streams, {n} pairs): learn ms/step at n={}",
            self.reps,
            self.streams,
            list.join("/")
        )?;
        for l in ["gp-exp", "rbcm-exp", "igmn"] {
            let v: Vec<String> = ks
                .iter()
                .map(|&k| format!("{:.3}", self.learn_at(l, k) * 1e3))
                .collect();
            write!(f, " {l} {}", v.join("/"))?;
        }
        write!(
            f,
            "; RMSE spike after new experts m_min 1 {:.4} vs m_min 25 {:.4}; fastest {}",
            self.spike("rbcm-exp-mmin1"),
            self.spike("rbcm-exp"),
            self.findings.fastest_learner_total_learning_time
        )
    }
}

/// The four panels of Prágr19 Fig. 5 plus a legend.
pub(crate) fn figure(curves: &[Curve], path: &Path) -> Result<()> {
    let log_us =
        |v: &[f64]| -> Vec<f64> { v.iter().map(|s| (s * 1e6).max(1e-3).log10()).collect() };
    let series = |f: &dyn Fn(&Curve) -> Option<Vec<f64>>| -> Vec<(Vec<f64>, [u8; 3])> {
        curves
            .iter()
            .enumerate()
            .filter_map(|(k, c)| f(c).map(|v| (v, palette(k))))
            .collect()
    };
    let a = line_chart(
        &series(&|c| Some(log_us(&c.learn))),
        &[],
        "N",
        "LOG10 LEARN US",
    );
    let b = line_chart(
        &series(&|c| Some(log_us(&c.infer))),
        &[],
        "N",
        "LOG10 INFER US",
    );
    let c = line_chart(&series(&|c| Some(c.rmse.clone())), &[], "N", "RMSE");
    let d = line_chart(&series(&|c| c.mean_std.clone()), &[], "N", "MEAN STD");
    let rect = strider_core::CellRect::new(strider_core::Cell::new(0, 0), 1440, 40);
    let mut legend = Canvas::new(rect, 1.0, 1);
    legend.fill(|_| Some([255, 255, 255]));
    for (k, c) in curves.iter().enumerate() {
        let x = 20.0 + (k % 8) as f64 * 175.0;
        label(&mut legend, x, 15.0, &c.label, palette(k));
    }
    compose(&[compose(&[a, b, c, d], 2), legend], 1).save(path)
}
