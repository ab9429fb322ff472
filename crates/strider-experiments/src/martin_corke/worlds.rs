//! `strider tours --world-seeds K`: the runs of every world seed and noise seed pooled into
//! `worlds.json` and `worlds.md` — the drop from tour 1 to the converged tour, the tour at which
//! the cumulative energy overtakes always-shortest, and the tour on the true costs, each beside
//! MartinCorke's figures, then one row per world.

use std::collections::BTreeMap;
use std::fmt::Write as _;
use std::path::Path;

use serde::Serialize;

use super::metrics::SeedFigures;
use super::{MAX_CONVERGENCE_TOUR, PUBLISHED_CONVERGED_J, PUBLISHED_FIRST_J, PUBLISHED_OVERTAKE};
use crate::io::{write_json, write_text};
use crate::stats::{mean_std_finite, median};

/// One run: a world seed, a noise seed, its figures and the lengths of two of its plans.
pub(crate) struct WorldRun<'a> {
    pub world: u64,
    pub seed: u64,
    pub figures: &'a SeedFigures,
    /// Length of the shortest tour, metres.
    pub shortest_m: f64,
    /// Length of the tour planned on the true costs, metres.
    pub known_m: f64,
}

/// Mean and sample standard deviation.
#[derive(Clone, Copy, Debug, Serialize)]
pub struct MeanStd {
    mean: f64,
    std: f64,
}

impl MeanStd {
    fn of(xs: impl Iterator<Item = f64>) -> Self {
        let (mean, std) = mean_std_finite(&xs.collect::<Vec<f64>>());
        Self { mean, std }
    }

    fn show(&self, digits: usize, unit: &str) -> String {
        format!("{:.*} ± {:.*}{unit}", digits, self.mean, digits, self.std)
    }
}

/// When the cumulative energy of exploring overtakes always-shortest.
#[derive(Clone, Debug, Serialize)]
pub struct Overtaking {
    /// Runs that overtake within the series.
    runs: usize,
    /// Their overtaking tour: mean ± std and median.
    tour: MeanStd,
    median_tour: Option<f64>,
    /// Runs per overtaking tour.
    histogram: BTreeMap<usize, usize>,
    /// Runs that never overtake.
    never: usize,
}

/// The tour planned on the true costs.
#[derive(Clone, Copy, Debug, Serialize)]
pub struct Bound {
    j: MeanStd,
    length_m: MeanStd,
    /// Below tour 1, fraction.
    drop_from_first: MeanStd,
    /// Below the always-shortest mean, fraction.
    drop_vs_shortest: MeanStd,
}

/// One world's runs.
#[derive(Clone, Debug, Serialize)]
pub struct WorldRow {
    world_seed: u64,
    runs: usize,
    shortest_m: f64,
    first_tour_j: f64,
    converged_j: f64,
    drop: f64,
    overtaking_runs: usize,
    median_overtaking_tour: Option<f64>,
    known_costs_j: f64,
    known_costs_m: f64,
    known_drop_from_first: f64,
}

/// `worlds.json`.
#[derive(Clone, Debug, Serialize)]
pub struct WorldsReport {
    scenario: String,
    world_seeds: Vec<u64>,
    seeds: Vec<u64>,
    runs: usize,
    first_tour_j: MeanStd,
    converged_j: MeanStd,
    /// Tour 1 minus the converged tour, J.
    drop_j: MeanStd,
    /// The same as a fraction of tour 1.
    drop: MeanStd,
    /// Runs whose plan stopped changing within 10 tours.
    converged_within_10_tours: usize,
    overtaking: Overtaking,
    known_costs: Bound,
    per_world: Vec<WorldRow>,
    published_first_tour_j: f64,
    published_converged_j: f64,
    published_overtaking_tour: usize,
}

fn overtaking(runs: &[&WorldRun<'_>]) -> Overtaking {
    let tours: Vec<f64> = runs
        .iter()
        .filter_map(|r| r.figures.overtake.map(|k| k as f64))
        .collect();
    let mut histogram = BTreeMap::new();
    for r in runs {
        if let Some(k) = r.figures.overtake {
            *histogram.entry(k).or_insert(0) += 1;
        }
    }
    Overtaking {
        runs: tours.len(),
        tour: MeanStd::of(tours.iter().copied()),
        median_tour: median(&tours),
        histogram,
        never: runs.len() - tours.len(),
    }
}

fn world_row(world: u64, runs: &[&WorldRun<'_>]) -> WorldRow {
    let m = |f: &dyn Fn(&WorldRun<'_>) -> f64| MeanStd::of(runs.iter().map(|r| f(r))).mean;
    let o = overtaking(runs);
    WorldRow {
        world_seed: world,
        runs: runs.len(),
        shortest_m: m(&|r| r.shortest_m),
        first_tour_j: m(&|r| r.figures.first_j),
        converged_j: m(&|r| r.figures.converged_j),
        drop: m(&|r| r.figures.drop),
        overtaking_runs: o.runs,
        median_overtaking_tour: o.median_tour,
        known_costs_j: m(&|r| r.figures.known_mean_j),
        known_costs_m: m(&|r| r.known_m),
        known_drop_from_first: m(&|r| 1.0 - r.figures.known_mean_j / r.figures.first_j),
    }
}

impl WorldsReport {
    pub(crate) fn new(scenario: &str, runs: &[WorldRun<'_>]) -> Self {
        let all: Vec<&WorldRun<'_>> = runs.iter().collect();
        let of = |f: &dyn Fn(&WorldRun<'_>) -> f64| MeanStd::of(runs.iter().map(f));
        let mut world_seeds: Vec<u64> = runs.iter().map(|r| r.world).collect();
        world_seeds.dedup();
        let mut seeds: Vec<u64> = runs.iter().map(|r| r.seed).collect();
        seeds.sort_unstable();
        seeds.dedup();
        let per_world = world_seeds
            .iter()
            .map(|&w| {
                let these: Vec<&WorldRun<'_>> = runs.iter().filter(|r| r.world == w).collect();
                world_row(w, &these)
            })
            .collect();
        Self {
            scenario: scenario.into(),
            world_seeds,
            seeds,
            runs: runs.len(),
            first_tour_j: of(&|r| r.figures.first_j),
            converged_j: of(&|r| r.figures.converged_j),
            drop_j: of(&|r| r.figures.first_j - r.figures.converged_j),
            drop: of(&|r| r.figures.drop),
            converged_within_10_tours: runs
                .iter()
                .filter(|r| {
                    r.figures
                        .converged
                        .is_some_and(|c| c <= MAX_CONVERGENCE_TOUR)
                })
                .count(),
            overtaking: overtaking(&all),
            known_costs: Bound {
                j: of(&|r| r.figures.known_mean_j),
                length_m: of(&|r| r.known_m),
                drop_from_first: of(&|r| 1.0 - r.figures.known_mean_j / r.figures.first_j),
                drop_vs_shortest: of(&|r| r.figures.known_drop),
            },
            per_world,
            published_first_tour_j: PUBLISHED_FIRST_J,
            published_converged_j: PUBLISHED_CONVERGED_J,
            published_overtaking_tour: PUBLISHED_OVERTAKE,
        }
    }

    /// `worlds.md`: the pooled figures beside the published ones, the overtaking tours, then one
    /// row per world.
    pub(crate) fn markdown(&self, command: &str) -> String {
        let mut m = String::new();
        let (n, w) = (self.runs, self.world_seeds.len());
        let pct = |x: &MeanStd| MeanStd {
            mean: 100.0 * x.mean,
            std: 100.0 * x.std,
        };
        let o = &self.overtaking;
        let k = &self.known_costs;
        let published_drop = PUBLISHED_FIRST_J - PUBLISHED_CONVERGED_J;
        let _ = writeln!(
            m,
            "# MartinCorke repeated tours over {w} worlds × {} noise seeds ({n} runs): {}\n\nProduced by `{command}`. Mean ± sample standard deviation over the runs.\n",
            self.seeds.len(),
            self.scenario
        );
        let _ = writeln!(
            m,
            "| figure | ours | published (MartinCorke) |\n|---|---|---|"
        );
        let rows = [
            (
                "tour 1 (shortest tour)".to_string(),
                self.first_tour_j.show(1, " J"),
                format!("{PUBLISHED_FIRST_J} J"),
            ),
            (
                "converged tour".into(),
                self.converged_j.show(1, " J"),
                format!("≈{PUBLISHED_CONVERGED_J} J"),
            ),
            (
                "drop from tour 1 to the converged tour".into(),
                format!(
                    "{} ({})",
                    self.drop_j.show(1, " J"),
                    pct(&self.drop).show(1, " %")
                ),
                format!(
                    "{published_drop:.1} J ({:.1} %)",
                    100.0 * published_drop / PUBLISHED_FIRST_J
                ),
            ),
            (
                "plan converged within 10 tours".into(),
                format!("{} of {n}", self.converged_within_10_tours),
                "yes (≈8–10)".into(),
            ),
            (
                "cumulative energy overtakes always-shortest".into(),
                format!(
                    "{} of {n} runs, at tour {} (median {})",
                    o.runs,
                    o.tour.show(1, ""),
                    o.median_tour.map_or("–".into(), |t| format!("{t:.1}"))
                ),
                format!("by tour {PUBLISHED_OVERTAKE}"),
            ),
            (
                "tour on the true costs (bound)".into(),
                format!(
                    "{}, {} long; {} below tour 1, {} below always-shortest",
                    k.j.show(1, " J"),
                    k.length_m.show(2, " m"),
                    pct(&k.drop_from_first).show(1, " %"),
                    pct(&k.drop_vs_shortest).show(1, " %")
                ),
                "–".into(),
            ),
        ];
        for (a, b, c) in rows {
            let _ = writeln!(m, "| {a} | {b} | {c} |");
        }
        let _ = writeln!(
            m,
            "\nOvertaking tour over the {n} runs: {}never {}.\n",
            o.histogram
                .iter()
                .map(|(t, c)| format!("tour {t}: {c}; "))
                .collect::<String>(),
            o.never
        );
        let _ = writeln!(
            m,
            "| world | runs | shortest tour m | tour 1 J | converged J | drop | overtakes (runs) | median overtaking tour | true-cost tour J | its length m | its drop from tour 1 |\n|---|---|---|---|---|---|---|---|---|---|---|"
        );
        for r in &self.per_world {
            let _ = writeln!(
                m,
                "| {} | {} | {:.2} | {:.1} | {:.1} | {:.1} % | {} | {} | {:.1} | {:.2} | {:.1} % |",
                r.world_seed,
                r.runs,
                r.shortest_m,
                r.first_tour_j,
                r.converged_j,
                100.0 * r.drop,
                r.overtaking_runs,
                r.median_overtaking_tour
                    .map_or("never".into(), |t| format!("{t:.1}")),
                r.known_costs_j,
                r.known_costs_m,
                100.0 * r.known_drop_from_first
            );
        }
        m
    }
}

/// Writes `worlds.json` and `worlds.md` (produced by `command`) into `out`.
pub(crate) fn write(
    scenario: &str,
    out: &Path,
    runs: &[WorldRun<'_>],
    command: &str,
) -> anyhow::Result<()> {
    let report = WorldsReport::new(scenario, runs);
    write_json(&out.join("worlds.json"), &report)?;
    write_text(&out.join("worlds.md"), &report.markdown(command))
}
