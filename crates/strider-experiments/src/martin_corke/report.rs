//! The reports of `strider tours`: per seed `tours.json`, `tours.md` and `energy_per_tour.json`;
//! over several seeds `summary.json` and `summary.md`.

use std::fmt::Write as _;
use std::path::Path;

use serde::Serialize;
use strider_explore::energy_tours::{EnergyTourParams, FitSummary, PlannedTour, TourRecord};
use strider_scenario::Scenario;

use super::metrics::{Acceptance, SeedFigures, tour_or_never};
use super::{
    PUBLISHED_CONVERGED_J, PUBLISHED_CONVERGENCE, PUBLISHED_CUMULATIVE_7, PUBLISHED_FIRST_J,
    PUBLISHED_OVERTAKE, SeedRun,
};
use crate::io::{write_json, write_text};

/// The loop's parameters as run.
#[derive(Clone, Debug, Serialize)]
pub struct ParamsReport {
    waypoints: Vec<[f64; 2]>,
    closed: bool,
    speed_mps: f64,
    hotel_load_w: f64,
    hotel_per_m_j: f64,
    cell_size_m: f64,
    bin_size_m: f64,
    pose_rate_hz: f64,
    power_rate_hz: f64,
    pose_sigma_xy_m: f64,
    power_noise: f64,
    energy_window_s: f64,
    pose_smoothing_s: f64,
    turn_rate_threshold: f64,
    lengthscale_bounds_m: (f64, f64),
    signal_variance_bounds: (f64, f64),
    noise_variance_bounds: (f64, f64),
    unchanged_tolerance_m: f64,
}

/// Cumulative energy after some tours, J.
#[derive(Clone, Copy, Debug, Serialize)]
pub struct Cumulative {
    exploring: f64,
    always_shortest: f64,
}

/// The published figures.
#[derive(Clone, Debug, Serialize)]
pub struct PublishedReport {
    first_tour_j: f64,
    converged_j: f64,
    drop: f64,
    convergence_tour: &'static str,
    overtaking_tour: usize,
    cumulative_after_7_tours_j: Cumulative,
}

/// Our figures.
#[derive(Clone, Debug, Serialize)]
pub struct SeedSummary {
    first_tour_j: f64,
    convergence_tour: Option<usize>,
    converged_j: f64,
    converged_from_tour: usize,
    drop: f64,
    drop_vs_always_shortest: f64,
    first_tour_motive_j: f64,
    converged_motive_j: f64,
    motive_drop: f64,
    overtaking_tour: Option<usize>,
    first_tour_is_shortest: bool,
    always_shortest_mean_j: f64,
    known_costs_mean_j: f64,
    known_costs_drop: f64,
    known_costs_path_length_m: f64,
    shortest_path_length_m: Option<f64>,
    cumulative_after_7_tours_j: Option<Cumulative>,
    cumulative_exploring_j: Option<f64>,
    cumulative_always_shortest_j: Option<f64>,
    acceptance: Acceptance,
}

/// One exploring tour.
#[derive(Clone, Debug, Serialize)]
pub struct TourReport {
    tour: usize,
    energy_j: f64,
    motive_energy_j: f64,
    duration_s: f64,
    driven_m: f64,
    planned_length_m: f64,
    predicted_energy_j: f64,
    order: Vec<usize>,
    path: Vec<[f64; 2]>,
    samples: usize,
    turn_rejected_windows: usize,
    slow_rejected_windows: u64,
    mean_motive_j_per_m: Option<f64>,
    max_waypoint_miss_m: f64,
    learned: bool,
    fit: Option<FitSummary>,
    next_changed: Option<bool>,
    next_deviation_m: Option<f64>,
}

impl From<&TourRecord> for TourReport {
    fn from(x: &TourRecord) -> Self {
        let m = &x.measured;
        Self {
            tour: x.tour,
            energy_j: m.energy_j,
            motive_energy_j: m.motive_energy_j,
            duration_s: m.duration_s,
            driven_m: m.driven_m,
            planned_length_m: x.plan.length_m,
            predicted_energy_j: x.plan.predicted_energy_j,
            order: x.plan.order.clone(),
            path: x.plan.path.iter().map(|p| [p.x, p.y]).collect(),
            samples: m.samples,
            turn_rejected_windows: m.turn_rejected,
            slow_rejected_windows: m.slow_rejected,
            mean_motive_j_per_m: m.mean_motive_j_per_m,
            max_waypoint_miss_m: m.max_waypoint_miss_m,
            learned: x.learned,
            fit: x.fit.clone(),
            next_changed: x.next_changed,
            next_deviation_m: x.next_deviation_m,
        }
    }
}

/// A fixed tour driven: its energy and duration.
#[derive(Clone, Debug, Serialize)]
pub struct FixedTour {
    tour: usize,
    energy_j: f64,
    duration_s: f64,
}

fn fixed(v: &[TourRecord]) -> Vec<FixedTour> {
    v.iter()
        .map(|x| FixedTour {
            tour: x.tour,
            energy_j: x.measured.energy_j,
            duration_s: x.measured.duration_s,
        })
        .collect()
}

/// The tours on the true costs.
#[derive(Clone, Debug, Serialize)]
pub struct KnownCosts {
    plan: PlannedTour,
    tours: Vec<FixedTour>,
}

/// `tours.json` of one seed.
#[derive(Clone, Debug, Serialize)]
pub struct ToursReport {
    scenario: String,
    world_seed: u64,
    seed: u64,
    n_tours: usize,
    params: ParamsReport,
    published: PublishedReport,
    summary: SeedSummary,
    tours: Vec<TourReport>,
    always_shortest: Vec<FixedTour>,
    known_costs: KnownCosts,
}

/// `energy_per_tour.json`: the series of the figures.
#[derive(Clone, Debug, Serialize)]
pub struct EnergyPerTour {
    tour: Vec<usize>,
    exploring_j: Vec<f64>,
    always_shortest_j: Vec<f64>,
    known_costs_j: Vec<f64>,
    cumulative_exploring_j: Vec<f64>,
    cumulative_always_shortest_j: Vec<f64>,
}

fn energies(v: &[TourRecord]) -> Vec<f64> {
    v.iter().map(|x| x.measured.energy_j).collect()
}

fn params_report(sc: &Scenario, p: &EnergyTourParams) -> ParamsReport {
    ParamsReport {
        waypoints: p.waypoints.iter().map(|w| [w.x, w.y]).collect(),
        closed: p.closed,
        speed_mps: p.speed_mps,
        hotel_load_w: p.hotel_load_w,
        hotel_per_m_j: p.hotel_per_m(),
        cell_size_m: p.cell_size,
        bin_size_m: p.bin_size_m,
        pose_rate_hz: p.pose_rate_hz,
        power_rate_hz: p.power_rate_hz,
        pose_sigma_xy_m: sc.sim.pose_sigma_xy,
        power_noise: sc.sim.proprio_noise,
        energy_window_s: p.energy_window_s,
        pose_smoothing_s: p.pose_smoothing_s,
        turn_rate_threshold: p.turn_rate_threshold,
        lengthscale_bounds_m: p.hyper_bounds.lengthscale,
        signal_variance_bounds: p.hyper_bounds.signal_variance,
        noise_variance_bounds: p.hyper_bounds.noise_variance,
        unchanged_tolerance_m: p.unchanged_tolerance_m,
    }
}

fn published() -> PublishedReport {
    PublishedReport {
        first_tour_j: PUBLISHED_FIRST_J,
        converged_j: PUBLISHED_CONVERGED_J,
        drop: 1.0 - PUBLISHED_CONVERGED_J / PUBLISHED_FIRST_J,
        convergence_tour: PUBLISHED_CONVERGENCE,
        overtaking_tour: PUBLISHED_OVERTAKE,
        cumulative_after_7_tours_j: Cumulative {
            exploring: PUBLISHED_CUMULATIVE_7.0,
            always_shortest: PUBLISHED_CUMULATIVE_7.1,
        },
    }
}

fn seed_summary(r: &SeedRun, s: &SeedFigures) -> SeedSummary {
    let cumulative = |c: &(f64, f64)| Cumulative {
        exploring: c.0,
        always_shortest: c.1,
    };
    SeedSummary {
        first_tour_j: s.first_j,
        convergence_tour: s.converged,
        converged_j: s.converged_j,
        converged_from_tour: s.converged_from,
        drop: s.drop,
        drop_vs_always_shortest: s.drop_vs_shortest,
        first_tour_motive_j: s.first_motive_j,
        converged_motive_j: s.converged_motive_j,
        motive_drop: 1.0 - s.converged_motive_j / s.first_motive_j,
        overtaking_tour: s.overtake,
        first_tour_is_shortest: s.first_is_shortest,
        always_shortest_mean_j: s.shortest_mean_j,
        known_costs_mean_j: s.known_mean_j,
        known_costs_drop: s.known_drop,
        known_costs_path_length_m: r.known_plan.length_m,
        shortest_path_length_m: r.shortest.first().map(|x| x.plan.length_m),
        cumulative_after_7_tours_j: s.cumulative.get(6).map(cumulative),
        cumulative_exploring_j: s.cumulative.last().map(|c| c.0),
        cumulative_always_shortest_j: s.cumulative.last().map(|c| c.1),
        acceptance: s.acceptance(),
    }
}

/// Writes `energy_per_tour.json`, `tours.json` and `tours.md` (produced by `command`) of one
/// seed into `dir`.
pub(crate) fn write_seed(
    sc: &Scenario,
    p: &EnergyTourParams,
    (r, s): (&SeedRun, &SeedFigures),
    command: &str,
    dir: &Path,
) -> anyhow::Result<()> {
    let t = &r.outcome.tours;
    let series = EnergyPerTour {
        tour: (1..=t.len()).collect(),
        exploring_j: energies(t),
        always_shortest_j: energies(&r.shortest),
        known_costs_j: energies(&r.known),
        cumulative_exploring_j: s.cumulative.iter().map(|c| c.0).collect(),
        cumulative_always_shortest_j: s.cumulative.iter().map(|c| c.1).collect(),
    };
    write_json(&dir.join("energy_per_tour.json"), &series)?;
    let report = ToursReport {
        scenario: sc.name.clone(),
        world_seed: sc.world_seed,
        seed: r.seed,
        n_tours: p.n_tours,
        params: params_report(sc, p),
        published: published(),
        summary: seed_summary(r, s),
        tours: t.iter().map(TourReport::from).collect(),
        always_shortest: fixed(&r.shortest),
        known_costs: KnownCosts {
            plan: r.known_plan.clone(),
            tours: fixed(&r.known),
        },
    };
    write_json(&dir.join("tours.json"), &report)?;
    write_text(&dir.join("tours.md"), &markdown(sc, r, s, command))
}

/// `tours.md`: our figures beside the published ones, then every tour.
fn markdown(sc: &Scenario, r: &SeedRun, s: &SeedFigures, command: &str) -> String {
    let mut m = String::new();
    let _ = writeln!(
        m,
        "# MartinCorke repeated tours: {} (world seed {}, seed {})\n\nProduced by `{command}`.\n",
        sc.name, sc.world_seed, r.seed
    );
    let _ = writeln!(m, "| figure | ours | published (MartinCorke) |");
    let _ = writeln!(m, "|---|---|---|");
    let mut row = |figure: &str, ours: String, published: String| {
        let _ = writeln!(m, "| {figure} | {ours} | {published} |");
    };
    row(
        "first tour (shortest path)",
        format!("{:.1} J", s.first_j),
        format!("{PUBLISHED_FIRST_J} J"),
    );
    row(
        "converged tour",
        format!(
            "{:.1} J (mean of tours {}–{})",
            s.converged_j,
            s.converged_from,
            r.outcome.tours.len()
        ),
        format!("≈{PUBLISHED_CONVERGED_J} J"),
    );
    row(
        "energy drop from tour 1 (negative: a rise)",
        format!("{:.1} %", 100.0 * s.drop),
        format!(
            "{:.1} %",
            100.0 * (1.0 - PUBLISHED_CONVERGED_J / PUBLISHED_FIRST_J)
        ),
    );
    row(
        "converged tour vs always-shortest (mean of its tours)",
        format!(
            "{:.1} J vs {:.1} J ({:+.1} %)",
            s.converged_j,
            s.shortest_mean_j,
            -100.0 * s.drop_vs_shortest
        ),
        "–".into(),
    );
    row(
        "motive energy only (E_t − P_h·T): tour 1 → converged",
        format!(
            "{:.1} J → {:.1} J ({:.1} %)",
            s.first_motive_j,
            s.converged_motive_j,
            100.0 * (1.0 - s.converged_motive_j / s.first_motive_j)
        ),
        "–".into(),
    );
    row(
        "convergence tour (plan unchanged)",
        tour_or_never(s.converged),
        PUBLISHED_CONVERGENCE.into(),
    );
    row(
        "cumulative energy overtakes always-shortest at tour",
        tour_or_never(s.overtake),
        PUBLISHED_OVERTAKE.to_string(),
    );
    if let Some(c) = s.cumulative.get(6) {
        row(
            "cumulative energy after 7 tours: exploring vs always-shortest",
            format!("{:.0} J vs {:.0} J", c.0, c.1),
            format!(
                "{:.0} J vs {:.0} J",
                PUBLISHED_CUMULATIVE_7.0, PUBLISHED_CUMULATIVE_7.1
            ),
        );
    }
    row(
        "first tour equals the shortest path",
        if s.first_is_shortest { "yes" } else { "no" }.into(),
        "yes".into(),
    );
    row(
        "tour on the true costs (harness)",
        format!(
            "{:.1} J ({:.1} % below always-shortest)",
            s.known_mean_j,
            100.0 * s.known_drop
        ),
        "–".into(),
    );
    tour_table(&mut m, r, s);
    m
}

/// Every exploring tour beside always-shortest, and the figures' legend.
fn tour_table(m: &mut String, r: &SeedRun, s: &SeedFigures) {
    let _ = writeln!(
        m,
        "\n| tour | exploring J | always-shortest J | cumulative exploring J | cumulative shortest J | length m | plan changed after | samples | l m | σ_f² | σ_n² |"
    );
    let _ = writeln!(m, "|---|---|---|---|---|---|---|---|---|---|---|");
    for (k, x) in r.outcome.tours.iter().enumerate() {
        let fit = x.fit.as_ref();
        let f = |v: Option<f64>, p: usize| v.map_or("–".into(), |v| format!("{v:.p$}"));
        let _ = writeln!(
            m,
            "| {} | {:.2} | {:.2} | {:.1} | {:.1} | {:.2} | {} | {} | {} | {} | {} |",
            x.tour,
            x.measured.energy_j,
            r.shortest[k].measured.energy_j,
            s.cumulative[k].0,
            s.cumulative[k].1,
            x.plan.length_m,
            x.next_changed
                .map_or("–".into(), |c| if c { "yes" } else { "no" }.to_string()),
            x.measured.samples,
            f(fit.map(|v| v.lengthscale), 3),
            f(fit.map(|v| v.signal_variance), 1),
            f(fit.map(|v| v.noise_variance), 3),
        );
    }
    let _ = writeln!(
        m,
        "\nFigures: `energy_per_tour.png` (blue: exploring, orange: always-shortest, green: tour on \
the true costs; x: tour, y: J), `cumulative_energy.png` (blue: exploring, orange: always-shortest), \
`cumulative_difference.png` (cumulative exploring minus always-shortest, J; below zero exploring has \
paid off), \
`map_after_tour_NN.png` / `map_convergence.png` (learnt motive J/m, same colour scale as \
`map_truth.png`; white: the tour planned after that tour, magenta: the tour driven, squares: waypoints)."
    );
}

/// One seed in `summary.json`.
#[derive(Clone, Debug, Serialize)]
pub struct PerSeed {
    seed: u64,
    first_tour_j: f64,
    converged_j: f64,
    drop: f64,
    convergence_tour: Option<usize>,
    overtaking_tour: Option<usize>,
    known_costs_mean_j: f64,
    known_costs_drop: f64,
    acceptance: Acceptance,
}

/// Seeds meeting each acceptance criterion.
#[derive(Clone, Copy, Debug, Serialize)]
pub struct Counts {
    first_tour_is_shortest: usize,
    drop_at_least_30_percent: usize,
    converged_within_10_tours: usize,
    overtakes_before_tour_10: usize,
    of: usize,
}

/// The published figures the summary compares with.
#[derive(Clone, Debug, Serialize)]
pub struct PublishedSummary {
    first_tour_j: f64,
    converged_j: f64,
    convergence_tour: &'static str,
    overtaking_tour: usize,
}

/// `summary.json` over several seeds.
#[derive(Clone, Debug, Serialize)]
pub struct SummaryReport {
    scenario: String,
    world_seed: u64,
    seeds: Vec<u64>,
    per_seed: Vec<PerSeed>,
    counts: Counts,
    published: PublishedSummary,
}

impl SummaryReport {
    fn new(sc: &Scenario, rows: &[(u64, &SeedFigures)]) -> Self {
        let count = |f: &dyn Fn(&Acceptance) -> bool| {
            rows.iter().filter(|(_, s)| f(&s.acceptance())).count()
        };
        Self {
            scenario: sc.name.clone(),
            world_seed: sc.world_seed,
            seeds: rows.iter().map(|(s, _)| *s).collect(),
            per_seed: rows
                .iter()
                .map(|&(seed, s)| PerSeed {
                    seed,
                    first_tour_j: s.first_j,
                    converged_j: s.converged_j,
                    drop: s.drop,
                    convergence_tour: s.converged,
                    overtaking_tour: s.overtake,
                    known_costs_mean_j: s.known_mean_j,
                    known_costs_drop: s.known_drop,
                    acceptance: s.acceptance(),
                })
                .collect(),
            counts: Counts {
                first_tour_is_shortest: count(&|a| a.first_tour_is_shortest),
                drop_at_least_30_percent: count(&|a| a.drop_at_least_30_percent),
                converged_within_10_tours: count(&|a| a.converged_within_10_tours),
                overtakes_before_tour_10: count(&|a| a.overtakes_before_tour_10),
                of: rows.len(),
            },
            published: PublishedSummary {
                first_tour_j: PUBLISHED_FIRST_J,
                converged_j: PUBLISHED_CONVERGED_J,
                convergence_tour: PUBLISHED_CONVERGENCE,
                overtaking_tour: PUBLISHED_OVERTAKE,
            },
        }
    }

    /// `summary.md`: one row per seed beside the published figures, then the counts.
    fn markdown(&self, rows: &[(u64, &SeedFigures)], command: &str) -> String {
        let mut m = String::new();
        let n = self.counts.of;
        let _ = writeln!(
            m,
            "# MartinCorke repeated tours over {n} seeds: {} (world seed {})\n\nProduced by `{command}`.\n",
            self.scenario, self.world_seed
        );
        let _ = writeln!(
            m,
            "| seed | tour 1 J | converged J | drop | convergence tour | overtakes at | true-cost tour J | its drop |"
        );
        let _ = writeln!(m, "|---|---|---|---|---|---|---|---|");
        for (seed, s) in rows {
            let _ = writeln!(
                m,
                "| {seed} | {:.1} | {:.1} | {:.1} % | {} | {} | {:.1} | {:.1} % |",
                s.first_j,
                s.converged_j,
                100.0 * s.drop,
                tour_or_never(s.converged),
                tour_or_never(s.overtake),
                s.known_mean_j,
                100.0 * s.known_drop
            );
        }
        let _ = writeln!(
            m,
            "| published | {PUBLISHED_FIRST_J} | ≈{PUBLISHED_CONVERGED_J} | {:.1} % | {PUBLISHED_CONVERGENCE} | {PUBLISHED_OVERTAKE} | – | – |",
            100.0 * (1.0 - PUBLISHED_CONVERGED_J / PUBLISHED_FIRST_J)
        );
        let c = &self.counts;
        let _ = writeln!(m, "\n| criterion | seeds |\n|---|---|");
        for (criterion, k) in [
            (
                "first tour equals the shortest path",
                c.first_tour_is_shortest,
            ),
            ("energy falls by ≥ 30 %", c.drop_at_least_30_percent),
            ("converges within 10 tours", c.converged_within_10_tours),
            (
                "cumulative energy overtakes always-shortest before tour 10",
                c.overtakes_before_tour_10,
            ),
        ] {
            let _ = writeln!(m, "| {criterion} | {k} of {n} |");
        }
        m
    }
}

/// Writes `summary.json` and `summary.md` (produced by `command`) over the seeds `rows` into
/// `out`.
pub(crate) fn write_summary(
    sc: &Scenario,
    out: &Path,
    rows: &[(u64, &SeedFigures)],
    command: &str,
) -> anyhow::Result<()> {
    let report = SummaryReport::new(sc, rows);
    write_json(&out.join("summary.json"), &report)?;
    write_text(&out.join("summary.md"), &report.markdown(rows, command))
}
