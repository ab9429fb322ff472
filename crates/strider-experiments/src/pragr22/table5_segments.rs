//! Small tour 1 of Prágr22 Table 5 segment by segment: the mean time of each segment per
//! navigation mode beside the published one, and the learned mode's gain over flat navigation
//! per segment. The paper's gain is made on segment 2, where the learned robot takes "a longer
//! path over the pavement" instead of the direct route over the turf.

use std::fmt::Write as _;

use serde::Serialize;
use strider_explore::Strategy;
use strider_explore::evaluate::NavigationMode;

use super::table5_trials::TrialResult;
use crate::stats::{MeanStd, Summary};

/// Published segment times of small tour 1 (Prágr22 Table 5), s: per navigation mode (flat is
/// the paper's baseline, learned its proposed method), mean and std of segments 1–4.
const PUBLISHED: [(NavigationMode, [(f64, f64); 4]); 3] = [
    (
        NavigationMode::Flat,
        [
            (79.99, 0.00),
            (239.59, 6.62),
            (133.20, 6.76),
            (177.59, 13.04),
        ],
    ),
    (
        NavigationMode::GaitSelection,
        [
            (80.00, 0.00),
            (275.00, 8.06),
            (125.49, 7.39),
            (164.00, 7.39),
        ],
    ),
    (
        NavigationMode::Learned,
        [
            (80.00, 0.00),
            (119.99, 0.00),
            (112.40, 4.27),
            (142.40, 4.27),
        ],
    ),
];

/// Tour 1's segments: the four corners counter-clockwise from the bottom-left start.
const NAMES: [&str; 4] = [
    "start → bottom-right",
    "bottom-right → top-right",
    "top-right → top-left",
    "top-left → start",
];

/// One segment of small tour 1 in one navigation mode.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct SegmentRow {
    /// Segment number, from 1 (start → first waypoint).
    pub segment: usize,
    /// Navigation mode.
    pub mode: &'static str,
    /// Summary of our times, s (`null` without any).
    pub ours: Option<Summary>,
    /// The published time, s.
    pub published: Option<MeanStd>,
    /// Our times, one per trial, s.
    pub values: Vec<f64>,
}

/// The segment rows of small tour 1 from the `gtsp` trials on `courtyard-small`: every
/// segment in every navigation mode, segment by segment.
pub(crate) fn segment_rows(trials: &[TrialResult]) -> Vec<SegmentRow> {
    let small: Vec<&TrialResult> = trials
        .iter()
        .filter(|t| {
            t.trial.scenario == "courtyard-small" && t.trial.strategy == Strategy::Gtsp.name()
        })
        .collect();
    let n = small
        .iter()
        .flat_map(|t| NavigationMode::ALL.map(|m| t.segments(0, m).map_or(0, <[f64]>::len)))
        .max()
        .unwrap_or(0);
    let mut rows = Vec::new();
    for k in 0..n {
        for m in NavigationMode::ALL {
            let values: Vec<f64> = small
                .iter()
                .filter_map(|t| t.segments(0, m)?.get(k).copied())
                .collect();
            let published = PUBLISHED
                .iter()
                .find(|p| p.0 == m)
                .and_then(|p| p.1.get(k))
                .map(|&(mean, std)| MeanStd { mean, std });
            rows.push(SegmentRow {
                segment: k + 1,
                mode: m.name(),
                ours: Summary::of(&values).ok(),
                published,
                values,
            });
        }
    }
    rows
}

/// The segment table of `rows` (nothing without rows): per segment each mode's mean ± std with
/// the published mean in brackets, and the learned mode's change against flat navigation.
pub(crate) fn segments_markdown(md: &mut String, rows: &[SegmentRow]) {
    let Some(n) = rows.iter().map(|r| r.segment).max() else {
        return;
    };
    let _ = writeln!(
        md,
        "\nSmall tour 1 per segment, simulated seconds, mean ± std (published mean in brackets; \
         the paper's baseline is flat, its proposed method learned):\n"
    );
    let _ = writeln!(
        md,
        "| segment | flat | gait-selection | learned | learned vs flat | published learned vs flat |"
    );
    let _ = writeln!(md, "|---|---|---|---|---|---|");
    for k in 1..=n {
        let row = |m: NavigationMode| rows.iter().find(|r| r.segment == k && r.mode == m.name());
        let cell = |m: NavigationMode| {
            let r = row(m);
            let ours = r
                .and_then(|r| r.ours)
                .map_or("–".into(), |s| format!("{:.1} ± {:.1}", s.mean, s.std));
            match r.and_then(|r| r.published) {
                Some(p) => format!("{ours} ({:.1})", p.mean),
                None => ours,
            }
        };
        let change = |a: Option<f64>, b: Option<f64>| match (a, b) {
            (Some(a), Some(b)) if b > 0.0 => {
                format!("{:+.0} %", 100.0 * (a / b - 1.0)).replace('-', "−")
            }
            _ => "–".into(),
        };
        let (learned, flat) = (row(NavigationMode::Learned), row(NavigationMode::Flat));
        let ours = change(
            learned.and_then(|r| r.ours).map(|s| s.mean),
            flat.and_then(|r| r.ours).map(|s| s.mean),
        );
        let paper = change(
            learned.and_then(|r| r.published).map(|p| p.mean),
            flat.and_then(|r| r.published).map(|p| p.mean),
        );
        let name = NAMES.get(k - 1).map_or(String::new(), |s| format!(" {s}"));
        let _ = writeln!(
            md,
            "| {k}{name} | {} | {} | {} | {ours} | {paper} |",
            cell(NavigationMode::Flat),
            cell(NavigationMode::GaitSelection),
            cell(NavigationMode::Learned),
        );
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A small-world `gtsp` trial whose tour 1 took `segments[m]` in mode m (flat,
    /// gait-selection, learned); `None`: a trial kept without segment times.
    fn trial(segments: Option<[[f64; 4]; 3]>) -> TrialResult {
        let modes = NavigationMode::ALL.map(|m| m.name());
        let tours: Vec<_> = modes
            .iter()
            .enumerate()
            .map(|(i, m)| {
                let total: f64 = segments.map_or(0.0, |s| s[i].iter().sum());
                serde_json::json!(["tour-1", m, total, true])
            })
            .collect();
        let mut v = serde_json::json!({
            "scenario": "courtyard-small", "strategy": "gtsp", "world_seed": 1, "seed": 1,
            "termination": "goals", "exploration_time_s": 1.0, "observed_cells": 1,
            "tours": [tours], "replan_ms_median": 0.0, "replan_ms_max": 0.0, "wall_s": 0.0,
        });
        if let Some(s) = segments {
            v["segments_s"] = serde_json::json!([s]);
        }
        serde_json::from_value(v).unwrap()
    }

    #[test]
    fn segments_are_summarised_per_mode_beside_the_published_times() {
        let a = [
            [80.0, 240.0, 130.0, 180.0],
            [80.0, 270.0, 120.0, 160.0],
            [80.0, 150.0, 110.0, 140.0],
        ];
        let mut b = a;
        b[2][1] = 130.0;
        let rows = segment_rows(&[trial(Some(a)), trial(Some(b)), trial(None)]);
        assert_eq!(rows.len(), 12);
        let learned2 = rows
            .iter()
            .find(|r| r.segment == 2 && r.mode == "learned")
            .unwrap();
        assert_eq!(learned2.values, [150.0, 130.0]);
        assert_eq!(learned2.ours.unwrap().mean, 140.0);
        assert_eq!(learned2.published.unwrap().mean, 119.99);
        let mut md = String::new();
        segments_markdown(&mut md, &rows);
        // Learned 140 against flat 240 on segment 2; the paper's 119.99 against 239.59.
        assert!(
            md.contains("| 2 bottom-right → top-right | 240.0 ± 0.0 (239.6) |"),
            "{md}"
        );
        assert!(md.contains("| −42 % | −50 % |"), "{md}");
    }

    #[test]
    fn trials_without_segment_times_give_no_table() {
        let rows = segment_rows(&[trial(None)]);
        assert!(rows.is_empty());
        let mut md = String::new();
        segments_markdown(&mut md, &rows);
        assert!(md.is_empty());
    }
}
