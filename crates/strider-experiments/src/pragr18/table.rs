//! Prágr18 Table I: the cells (learner × descriptor) computed from the trials, the published
//! values, `c1_table.json` and `c1_table.md`.

use std::fmt;
use std::time::Instant;

use anyhow::{Context, Result};
use rayon::prelude::*;
use serde::Serialize;
use strider_learn::bench::{DataScale, LearnerSpec, c1_errors};
use strider_learn::gp::KernelKind;
use strider_learn::igmn::IgmnParams;
use strider_learn::regression_tree::TreeParams;
use strider_map::c1_descriptors::{C1Features, ColorFeature, GeomFeature};
use strider_scenario::Scenario;

use super::{C1Options, C1Trial};
use crate::stats::{mean, mean_population_variance};

/// Prágr18 Table I as published (OCR-reconstructed decimals), IGMN and regression tree rows:
/// (learner, colour, geometry, mean, variance).
pub const PUBLISHED_C1: [(&str, &str, &str, f64, f64); 30] = [
    ("igmn", "None", "Ori", 8.7, 57.4),
    ("igmn", "RGB-M", "None", 5.7, 44.5),
    ("igmn", "RGB-M", "Height", 6.6, 39.0),
    ("igmn", "RGB-M", "Ori", 5.8, 43.6),
    ("igmn", "RGB-M", "Set", 7.8, 38.9),
    ("igmn", "RGB-M", "Shape", 5.7, 38.4),
    ("igmn", "RGB-P", "None", 7.3, 59.4),
    ("igmn", "RGB-P", "Shape", 6.7, 40.4),
    ("igmn", "None", "Set", 9.0, 58.5),
    ("igmn", "None", "Shape", 8.4, 44.9),
    ("igmn", "None", "Height", 9.0, 37.9),
    ("igmn", "Lab-M", "None", 5.7, 38.3),
    ("igmn", "Lab-M", "Shape", 9.4, 147.2),
    ("igmn", "Lab-P", "None", 7.5, 39.6),
    ("igmn", "Lab-P", "Shape", 7.2, 67.6),
    ("tree", "Lab-P", "None", 6.4, 37.9),
    ("tree", "Lab-P", "Shape", 7.1, 70.9),
    ("tree", "None", "Ori", 8.1, 60.3),
    ("tree", "None", "Set", 7.9, 59.0),
    ("tree", "None", "Shape", 6.9, 77.2),
    ("tree", "RGB-M", "None", 6.3, 51.5),
    ("tree", "RGB-M", "Height", 6.4, 48.4),
    ("tree", "RGB-M", "Ori", 5.8, 47.5),
    ("tree", "RGB-M", "Set", 6.8, 63.3),
    ("tree", "RGB-M", "Shape", 5.9, 49.6),
    ("tree", "None", "Height", 7.3, 58.6),
    ("tree", "RGB-P", "None", 6.2, 41.5),
    ("tree", "Lab-M", "None", 6.9, 66.6),
    ("tree", "RGB-P", "Shape", 6.6, 58.7),
    ("tree", "Lab-M", "Shape", 6.1, 46.0),
];

/// The paper's best cell: (learner, colour, geometry, mean, variance).
const PUBLISHED_BEST: (&str, &str, &str, f64, f64) = ("igmn", "RGB-M", "Shape", 5.7, 38.4);

/// The learners of the table.
fn learners() -> Vec<LearnerSpec> {
    vec![
        LearnerSpec::Igmn(IgmnParams::default()),
        LearnerSpec::Tree(TreeParams::default()),
        LearnerSpec::Gp {
            kernel: KernelKind::Exponential,
            fit: true,
        },
        LearnerSpec::Rbcm {
            kernel: KernelKind::Exponential,
            m_max: 50,
            m_min: 25,
            fit: true,
        },
    ]
}

/// A published mean and variance of |ŷ − y|.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct MeanVariance {
    /// Mean.
    pub mean: f64,
    /// Variance.
    pub variance: f64,
}

/// One cell of the table.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct C1Cell {
    /// The learner.
    pub learner: String,
    /// Colour feature.
    #[serde(rename = "color")]
    pub colour: &'static str,
    /// Geometry feature.
    pub geometry: &'static str,
    /// Mean |ŷ − y| over the pooled errors.
    pub mean: Option<f64>,
    /// Their population variance.
    pub variance: Option<f64>,
    /// Errors pooled.
    pub n: usize,
    /// Samples without the descriptor's parts.
    pub dropped_samples: usize,
    /// The published figure.
    pub published: Option<MeanVariance>,
}

impl C1Cell {
    fn label(&self) -> String {
        format!("{} {} + {}", self.learner, self.colour, self.geometry)
    }
}

/// Rows of (descriptor, cost) of one combination; samples missing a part are dropped.
fn rows(
    pairs: &[(C1Features, f64)],
    color: ColorFeature,
    geom: GeomFeature,
) -> (usize, Vec<f64>, Vec<f64>, usize) {
    let (mut x, mut y, mut dim, mut dropped) = (Vec::new(), Vec::new(), 0, 0);
    for (f, c) in pairs {
        match f.descriptor(color, geom) {
            Some(d) => {
                dim = d.len();
                x.extend(d);
                y.push(*c);
            }
            None => dropped += 1,
        }
    }
    (dim, x, y, dropped)
}

/// The pooled errors of `spec` on one descriptor over the trials, and the dropped samples.
fn errors(
    trials: &[C1Trial],
    spec: &LearnerSpec,
    color: ColorFeature,
    geom: GeomFeature,
) -> Result<(Vec<f64>, usize)> {
    let (mut errors, mut dropped) = (Vec::new(), 0);
    for t in trials {
        let (d1, x1, y1, k1) = rows(&t.train, color, geom);
        let (d2, x2, y2, k2) = rows(&t.test, color, geom);
        dropped += k1 + k2;
        let dim = d1.max(d2);
        if dim == 0 || y2.is_empty() {
            continue;
        }
        let xa = [&x1[..], &x2[..]].concat();
        let ya = [&y1[..], &y2[..]].concat();
        let scale = DataScale::of(dim, &xa, &ya, mean(&y1).unwrap_or(0.0));
        errors.extend(
            c1_errors(spec, dim, &scale, (&x1, &y1), (&x2, &y2))
                .with_context(|| format!("{} {} {}", spec.label(), color.label(), geom.label()))?,
        );
    }
    Ok((errors, dropped))
}

/// Every cell of the table: each learner on every combination but (None, None).
pub(crate) fn cells(trials: &[C1Trial]) -> Result<Vec<C1Cell>> {
    let mut units = Vec::new();
    for spec in learners() {
        for &color in &ColorFeature::ALL {
            for &geom in &GeomFeature::ALL {
                if !(color == ColorFeature::None && geom == GeomFeature::None) {
                    units.push((spec.clone(), color, geom));
                }
            }
        }
    }
    units
        .par_iter()
        .map(|(spec, color, geom)| -> Result<C1Cell> {
            let (errors, dropped) = errors(trials, spec, *color, *geom)?;
            let stats = mean_population_variance(&errors);
            let learner = spec.label();
            let published = PUBLISHED_C1
                .iter()
                .find(|p| p.0 == learner && p.1 == color.label() && p.2 == geom.label())
                .map(|p| MeanVariance {
                    mean: p.3,
                    variance: p.4,
                });
            Ok(C1Cell {
                learner,
                colour: color.label(),
                geometry: geom.label(),
                mean: stats.map(|s| s.0),
                variance: stats.map(|s| s.1),
                n: errors.len(),
                dropped_samples: dropped,
                published,
            })
        })
        .collect()
}

/// Pairs recorded in the two passes of a trial.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct PassPairs {
    /// Pass 1 (robot's view).
    pub pass1: usize,
    /// Pass 2 (aerial view).
    pub pass2: usize,
}

/// The best cell (or the paper's).
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct C1Best {
    /// The learner.
    pub learner: String,
    /// Colour feature.
    pub color: String,
    /// Geometry feature.
    pub geometry: String,
    /// Mean.
    pub mean: Option<f64>,
    /// Variance.
    pub variance: Option<f64>,
}

/// `c1_table.json`.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct C1Report {
    /// The protocol.
    pub protocol: &'static str,
    /// Scenario.
    pub scenario: String,
    /// World seed.
    pub world_seed: u64,
    /// Seed of the first trial.
    pub seed: u64,
    /// Trials pooled.
    pub runs: usize,
    /// Pairs per trial.
    pub pairs_per_run: Vec<PassPairs>,
    /// The cells.
    pub cells: Vec<C1Cell>,
    /// Cells with a figure.
    pub filled_cells: usize,
    /// All cells.
    pub total_cells: usize,
    /// Our best cell (least mean, then least variance).
    pub best: Option<C1Best>,
    /// The paper's best cell.
    pub published_best: C1Best,
    /// Recording time, s.
    pub record_s: f64,
    /// Wall time, s.
    pub wall_s: f64,
}

impl C1Report {
    pub(crate) fn new(
        sc: &Scenario,
        o: &C1Options,
        trials: &[C1Trial],
        cells: Vec<C1Cell>,
        record_s: f64,
        t0: Instant,
    ) -> Self {
        let (l, c, g, m, v) = PUBLISHED_BEST;
        let mut r = Self {
            protocol: "Prágr18 Table I (learn on pass 1, predict pass 2 from the aerial view)",
            scenario: sc.name.clone(),
            world_seed: sc.world_seed,
            seed: o.seed,
            runs: o.runs,
            pairs_per_run: trials
                .iter()
                .map(|t| PassPairs {
                    pass1: t.train.len(),
                    pass2: t.test.len(),
                })
                .collect(),
            filled_cells: cells.iter().filter(|c| c.mean.is_some()).count(),
            total_cells: cells.len(),
            cells,
            best: None,
            published_best: C1Best {
                learner: l.into(),
                color: c.into(),
                geometry: g.into(),
                mean: Some(m),
                variance: Some(v),
            },
            record_s,
            wall_s: t0.elapsed().as_secs_f64(),
        };
        r.best = r.best_cell().map(|b| C1Best {
            learner: b.learner.clone(),
            color: b.colour.into(),
            geometry: b.geometry.into(),
            mean: b.mean,
            variance: b.variance,
        });
        r
    }

    /// The cell with the least mean, then the least variance.
    fn best_cell(&self) -> Option<&C1Cell> {
        self.cells
            .iter()
            .filter(|c| c.mean.is_some())
            .min_by(|a, b| {
                let key = |c: &C1Cell| (c.mean.unwrap_or_default(), c.variance.unwrap_or_default());
                let (x, y) = (key(a), key(b));
                x.0.total_cmp(&y.0).then(x.1.total_cmp(&y.1))
            })
    }

    /// `c1_table.md`: every cell beside the published one, the best in bold; `command` is what
    /// produced it.
    pub fn markdown(&self, command: &str) -> String {
        let mut md = format!(
            "# Prágr18 Table I on `cot-track`: |CoT error| per learner × descriptor\n\n\
Produced by `{command}`. Learned on pass 1 (robot's view), predicted on pass 2 (aerial view); incremental learners (IGMN, \
RBCM) also score their query-before-learning predictions on pass 1, as in Prágr18.\n\n\
| learner | colour | geometry | mean | variance | n | published mean / variance |\n|---|---|---|---:|---:|---:|---|\n",
        );
        let best = self.best_cell();
        for c in &self.cells {
            let b = if best.is_some_and(|b| std::ptr::eq(b, c)) {
                "**"
            } else {
                ""
            };
            let (m, v) = c
                .mean
                .zip(c.variance)
                .map_or(("—".into(), "—".into()), |(m, v)| {
                    (format!("{m:.2}"), format!("{v:.1}"))
                });
            md.push_str(&format!(
                "| {b}{}{b} | {} | {} | {b}{m}{b} | {b}{v}{b} | {} | {} |\n",
                c.learner,
                c.colour,
                c.geometry,
                c.n,
                c.published
                    .map_or(String::new(), |p| format!("{} / {}", p.mean, p.variance))
            ));
        }
        if let Some(b) = best {
            md.push_str(&format!(
                "\nBest: **{}**, mean {:.2}, variance {:.1} (Prágr18: IGMN RGB-M + Shape, 5.7 / 38.4).\n",
                b.label(),
                b.mean.unwrap_or_default(),
                b.variance.unwrap_or_default()
            ));
        }
        md
    }
}

impl fmt::Display for C1Report {
    /// The one-line summary for the terminal.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self.best_cell() {
            Some(b) => write!(
                f,
                "C1 ({}/{} cells, {} runs): best {} mean {:.2} var {:.1} (paper IGMN RGB-M + Shape 5.7 / 38.4)",
                self.filled_cells,
                self.total_cells,
                self.runs,
                b.label(),
                b.mean.unwrap_or_default(),
                b.variance.unwrap_or_default()
            ),
            None => write!(
                f,
                "C1: no cell could be filled ({} cells)",
                self.total_cells
            ),
        }
    }
}
