//! `strider tours`: `003` energy-optimal repeated tours in the simulator.
//!
//! For each noise seed, three runs of the scenario's first tour, each in a fresh simulator with
//! that seed:
//!
//! * **exploring** — [`run_energy_tours`]: tour 1 is the shortest tour, then every tour plans on
//!   the zero-mean GP of energy per metre learnt so far (plus the hotel load per metre), until
//!   the plan stops changing; the robot then keeps driving the converged tour;
//! * **always-shortest** — the baseline of `003` §5: tour 1's plan, driven every time;
//! * **known costs** — a harness figure, not an algorithm: the tour the same planner picks on
//!   the simulator's true energy per metre, driven every time. It bounds what learning can gain
//!   on this world.
//!
//! Writes `tours.json` and `tours.md` (per tour and summary, with the published figures of
//! `003` beside ours), `energy_per_tour.json`, the figures `energy_per_tour.png`,
//! `cumulative_energy.png` and `cumulative_difference.png`, and the learnt maps after tours 1,
//! 5, 10, 25 and at convergence (`map_after_tour_NN.png`, `map_convergence.png`) beside the
//! true map (`map_truth.png`). With `--seeds K > 1` each seed goes to `DIR/seed-N/` and
//! `DIR/summary.{json,md}` counts the seeds meeting each acceptance criterion.
//!
//! The scenario's `[strategy]` table may set `n_tours`, `bin_size_m`, `lengthscale_min_m`,
//! `lengthscale_max_m` and `unchanged_tolerance_m`; everything else comes from its first tour,
//! bounds, map cell size, robot profile and simulator rates.

use std::fmt::Write as _;
use std::fs;
use std::path::{Path, PathBuf};

use anyhow::{Context, Result, bail};
use clap::Args;
use rayon::prelude::*;
use serde_json::{Value, json};
use strider_core::{CellRect, GaitId};
use strider_explore::energy_tours::{
    EnergyMap, EnergyTourParams, PlannedTour, TourPlanner, TourRecord, ToursOutcome,
    drive_fixed_tour, plan_shortest, run_energy_tours,
};
use strider_scenario::Scenario;
use strider_sim::Simulator;
use strider_sim::motion::STUCK_SPEED_CEILING;
use strider_sim::terrain::TerrainTable;

use crate::cmd_scenario::load;
use crate::render::{Canvas, line_chart, scalar_canvas};

/// Arguments of `strider tours`.
#[derive(Args, Debug)]
pub struct ToursArgs {
    /// Built-in scenario name or scenario `.toml` file.
    #[arg(long, short = 's', default_value = "energy-arena")]
    pub scenario: String,
    /// Seed of the procedural world family (built-ins only; 1 is the reference world).
    #[arg(long, default_value_t = 1)]
    pub world_seed: u64,
    /// Seed of the simulator's noise.
    #[arg(long, default_value_t = 1)]
    pub seed: u64,
    /// Run this many noise seeds (seed, seed + 1, …) and count the acceptance criteria.
    #[arg(long, default_value_t = 1)]
    pub seeds: u64,
    /// Number of tours (default: the scenario's `n_tours`, 25 on energy-arena).
    #[arg(long)]
    pub tours: Option<usize>,
    /// Output directory (created if missing).
    #[arg(long, short = 'o', default_value = "out/tours")]
    pub out: PathBuf,
}

/// `003`'s published figures (BENCHMARKS.md).
const PUBLISHED_FIRST_J: f64 = 28.7;
const PUBLISHED_CONVERGED_J: f64 = 16.0;
const PUBLISHED_CONVERGENCE: &str = "~8–10 (simulation: 10)";
const PUBLISHED_OVERTAKE: usize = 8;
/// `003` §5: exploring cost 206 J over the first 7 tours against 201 J for the shortest path.
const PUBLISHED_CUMULATIVE_7: (f64, f64) = (206.0, 201.0);

/// Acceptance thresholds of the issue: the energy falls by at least this fraction, converges
/// and overtakes within these tours.
const MIN_DROP: f64 = 0.30;
const MAX_CONVERGENCE_TOUR: usize = 10;
const OVERTAKE_BEFORE: usize = 10;

/// Tours whose learnt maps are drawn (plus the convergence tour).
const MAP_TOURS: [usize; 4] = [1, 5, 10, 25];

/// Loop parameters from a scenario: its first tour, bounds and map cell size, the robot's first
/// gait, speed, hotel load and mass, its streams' rates, and the optional `[strategy]` keys of
/// the module docs.
pub fn tour_params(sc: &Scenario, n_tours: Option<usize>) -> Result<EnergyTourParams> {
    let Some(tour) = sc.tours.first() else {
        bail!("scenario {} has no tour to drive", sc.name);
    };
    let Some(gait) = sc.robot.gaits.first() else {
        bail!(
            "scenario {}: robot profile {} has no gait",
            sc.name,
            sc.robot.name
        );
    };
    let mut p = EnergyTourParams::new(
        tour.waypoints.clone(),
        tour.closed,
        sc.bounds.min,
        sc.bounds.max,
        sc.map.cell_size,
        GaitId(0),
        gait.max_speed,
        sc.robot.hotel_load_w,
        sc.robot.mass_kg,
    );
    let table = strider_cli::trial::section(sc, "tours")?
        .cloned()
        .unwrap_or_default();
    let from_table = table.get("n_tours").and_then(|v| v.as_integer());
    p.n_tours = match (n_tours, from_table) {
        (Some(n), _) => n,
        (None, Some(n)) if n > 0 => n as usize,
        (None, Some(n)) => bail!(
            "scenario {}: strategy.n_tours = {n} must be positive",
            sc.name
        ),
        (None, None) => 25,
    };
    p.pose_rate_hz = sc.sim.pose_rate_hz;
    p.power_rate_hz = sc.sim.proprio_rate_hz;
    // Optional overrides from the scenario's [strategy] table.
    let num = |key: &str| {
        let v = table.get(key);
        v.and_then(|v| v.as_float())
            .or_else(|| v.and_then(|v| v.as_integer()).map(|i| i as f64))
    };
    if let Some(v) = num("bin_size_m") {
        p.bin_size_m = v;
    }
    if let Some(v) = num("lengthscale_min_m") {
        p.hyper_bounds.lengthscale.0 = v;
    }
    if let Some(v) = num("lengthscale_max_m") {
        p.hyper_bounds.lengthscale.1 = v;
    }
    if let Some(v) = num("unchanged_tolerance_m") {
        p.unchanged_tolerance_m = v;
    }
    p.validate()?;
    Ok(p)
}

/// The simulator's true motive energy per metre at the centres of `rect` (harness only): the
/// terrain's power for the gait over the speed it reaches there, minus nothing but the hotel load
/// at the commanded speed (which the planner adds back), so the planner sees the true J/m.
fn truth_map(sc: &Scenario, p: &EnergyTourParams, rect: CellRect) -> EnergyMap {
    let table = TerrainTable::new(&sc.world, &sc.robot);
    let hotel = p.hotel_per_m();
    let mean = rect
        .cells()
        .map(|c| {
            let at = c.center(p.cell_size);
            let Some(k) = sc.world.index_at(at) else {
                return f32::NAN;
            };
            let r = table.response(sc.world.terrain[k], p.gait.0 as usize);
            let f = if r.stuck {
                STUCK_SPEED_CEILING
            } else {
                r.speed_factor
            };
            if f <= 0.0 {
                return f32::NAN;
            }
            let v = p.speed_mps * f;
            ((r.power_w + p.hotel_load_w) / v - hotel) as f32
        })
        .collect::<Vec<f32>>();
    let mean = mean
        .iter()
        .map(|&m| if m.is_finite() { m } else { 1e4 })
        .collect::<Vec<_>>();
    EnergyMap {
        rect,
        cell_size: p.cell_size,
        variance: vec![0.0; rect.len()],
        mean,
        bins: Vec::new(),
    }
}

/// Everything measured for one seed.
struct SeedRun {
    seed: u64,
    outcome: ToursOutcome,
    shortest: Vec<TourRecord>,
    known: Vec<TourRecord>,
    known_plan: PlannedTour,
    truth: EnergyMap,
}

fn run_seed(sc: &Scenario, p: &EnergyTourParams, seed: u64) -> Result<SeedRun> {
    let sim = || Simulator::new(sc, seed).context("cannot start the simulator");
    let outcome = run_energy_tours(&mut sim()?, p, |_| {})
        .with_context(|| format!("seed {seed}: exploring tours"))?;
    let shortest_plan = plan_shortest(p)?;
    let shortest = drive_fixed_tour(&mut sim()?, p, &shortest_plan, |_| {})
        .with_context(|| format!("seed {seed}: always-shortest tours"))?;
    let mut planner = TourPlanner::new(p)?;
    let truth = truth_map(sc, p, planner.rect());
    let known_plan = planner.plan(&planner.cost_grid(&truth, p)?)?;
    let known = drive_fixed_tour(&mut sim()?, p, &known_plan, |_| {})
        .with_context(|| format!("seed {seed}: known-cost tours"))?;
    Ok(SeedRun {
        seed,
        outcome,
        shortest,
        known,
        known_plan,
        truth,
    })
}

/// Figures of one seed derived from its runs.
#[derive(Clone, Debug)]
struct Summary {
    first_j: f64,
    first_motive_j: f64,
    converged_j: f64,
    converged_motive_j: f64,
    drop_vs_shortest: f64,
    converged_from: usize,
    converged: Option<usize>,
    drop: f64,
    overtake: Option<usize>,
    first_is_shortest: bool,
    shortest_mean_j: f64,
    known_mean_j: f64,
    known_drop: f64,
    cumulative: Vec<(f64, f64)>,
}

fn mean(v: impl Iterator<Item = f64>) -> f64 {
    let (s, n) = v.fold((0.0, 0usize), |(s, n), x| (s + x, n + 1));
    if n == 0 { f64::NAN } else { s / n as f64 }
}

fn summarize(r: &SeedRun) -> Summary {
    let t = &r.outcome.tours;
    let e: Vec<f64> = t.iter().map(|x| x.measured.energy_j).collect();
    let s: Vec<f64> = r.shortest.iter().map(|x| x.measured.energy_j).collect();
    let n = e.len();
    // Converged: the tours from convergence on drive one plan; without convergence, the last
    // five tours stand in.
    let from = r
        .outcome
        .convergence_tour
        .unwrap_or(n.saturating_sub(4).max(1));
    let converged_j = mean(e[from - 1..].iter().copied());
    let converged_motive_j = mean(t[from - 1..].iter().map(|x| x.measured.motive_energy_j));
    let mut cumulative = Vec::with_capacity(n);
    let (mut a, mut b) = (0.0, 0.0);
    for k in 0..n {
        a += e[k];
        b += s[k];
        cumulative.push((a, b));
    }
    // The first tour from which exploring stays strictly cheaper in total to the end.
    let mut overtake = None;
    for k in (0..n).rev() {
        if cumulative[k].0 < cumulative[k].1 {
            overtake = Some(k + 1);
        } else {
            break;
        }
    }
    let first_is_shortest = t
        .first()
        .zip(r.shortest.first())
        .is_some_and(|(x, y)| x.plan == y.plan);
    let known_mean_j = mean(r.known.iter().map(|x| x.measured.energy_j));
    let shortest_mean_j = mean(s.iter().copied());
    Summary {
        first_j: e[0],
        first_motive_j: t[0].measured.motive_energy_j,
        converged_j,
        converged_motive_j,
        drop_vs_shortest: 1.0 - converged_j / shortest_mean_j,
        converged_from: from,
        converged: r.outcome.convergence_tour,
        drop: 1.0 - converged_j / e[0],
        overtake,
        first_is_shortest,
        shortest_mean_j,
        known_mean_j,
        known_drop: 1.0 - known_mean_j / shortest_mean_j,
        cumulative,
    }
}

fn acceptance(s: &Summary) -> Value {
    json!({
        "first_tour_is_shortest": s.first_is_shortest,
        "drop_at_least_30_percent": s.drop >= MIN_DROP,
        "converged_within_10_tours": s.converged.is_some_and(|c| c <= MAX_CONVERGENCE_TOUR),
        "overtakes_before_tour_10": s.overtake.is_some_and(|k| k < OVERTAKE_BEFORE),
    })
}

fn opt(v: Option<usize>) -> String {
    v.map_or("never".into(), |k| k.to_string())
}

/// Runs `strider tours`.
pub fn run(args: &ToursArgs) -> Result<()> {
    if args.seeds == 0 {
        bail!("--seeds must be at least 1");
    }
    if args.tours == Some(0) {
        bail!("--tours must be at least 1");
    }
    let sc = load(&args.scenario, args.world_seed)?;
    let p = tour_params(&sc, args.tours).with_context(|| format!("scenario {}", sc.name))?;
    // Bad waypoints are reported before any simulation.
    TourPlanner::new(&p)
        .with_context(|| format!("scenario {}, tour {}", sc.name, sc.tours[0].name))?;
    fs::create_dir_all(&args.out)
        .with_context(|| format!("{}: cannot create directory", args.out.display()))?;
    let seeds: Vec<u64> = (0..args.seeds).map(|i| args.seed + i).collect();
    let runs: Vec<SeedRun> = seeds
        .par_iter()
        .map(|&s| run_seed(&sc, &p, s))
        .collect::<Result<_>>()?;
    let mut rows = Vec::new();
    for r in &runs {
        let dir = if runs.len() == 1 {
            args.out.clone()
        } else {
            args.out.join(format!("seed-{}", r.seed))
        };
        fs::create_dir_all(&dir)
            .with_context(|| format!("{}: cannot create directory", dir.display()))?;
        let s = summarize(r);
        write_seed(&sc, &p, r, &s, &dir)?;
        println!(
            "{} (world seed {}, seed {}): tour 1 {:.1} J, converged {} at {:.1} J ({:+.0} %), overtakes always-shortest at tour {}; known costs {:.1} J ({:+.0} %) -> {}",
            sc.name,
            sc.world_seed,
            r.seed,
            s.first_j,
            opt(s.converged),
            s.converged_j,
            -100.0 * s.drop,
            opt(s.overtake),
            s.known_mean_j,
            -100.0 * s.known_drop,
            dir.join("tours.json").display()
        );
        rows.push((r.seed, s));
    }
    if runs.len() > 1 {
        write_summary(&sc, args, &rows)?;
    }
    Ok(())
}

fn write(path: &Path, text: &str) -> Result<()> {
    fs::write(path, text).with_context(|| format!("{}: cannot write", path.display()))
}

fn tour_json(x: &TourRecord) -> Value {
    json!({
        "tour": x.tour,
        "energy_j": x.measured.energy_j,
        "motive_energy_j": x.measured.motive_energy_j,
        "duration_s": x.measured.duration_s,
        "driven_m": x.measured.driven_m,
        "planned_length_m": x.plan.length_m,
        "predicted_energy_j": x.plan.predicted_energy_j,
        "order": x.plan.order,
        "path": x.plan.path.iter().map(|p| [p.x, p.y]).collect::<Vec<_>>(),
        "samples": x.measured.samples,
        "turn_rejected_windows": x.measured.turn_rejected,
        "slow_rejected_windows": x.measured.slow_rejected,
        "mean_motive_j_per_m": x.measured.mean_motive_j_per_m,
        "max_waypoint_miss_m": x.measured.max_waypoint_miss_m,
        "learned": x.learned,
        "fit": x.fit,
        "next_changed": x.next_changed,
        "next_deviation_m": x.next_deviation_m,
    })
}

fn write_seed(
    sc: &Scenario,
    p: &EnergyTourParams,
    r: &SeedRun,
    s: &Summary,
    dir: &Path,
) -> Result<()> {
    let t = &r.outcome.tours;
    let n = t.len();
    let series = json!({
        "tour": (1..=n).collect::<Vec<_>>(),
        "exploring_j": t.iter().map(|x| x.measured.energy_j).collect::<Vec<_>>(),
        "always_shortest_j": r.shortest.iter().map(|x| x.measured.energy_j).collect::<Vec<_>>(),
        "known_costs_j": r.known.iter().map(|x| x.measured.energy_j).collect::<Vec<_>>(),
        "cumulative_exploring_j": s.cumulative.iter().map(|c| c.0).collect::<Vec<_>>(),
        "cumulative_always_shortest_j": s.cumulative.iter().map(|c| c.1).collect::<Vec<_>>(),
    });
    write(
        &dir.join("energy_per_tour.json"),
        &serde_json::to_string_pretty(&series)?,
    )?;
    let report = json!({
        "scenario": sc.name,
        "world_seed": sc.world_seed,
        "seed": r.seed,
        "n_tours": p.n_tours,
        "params": {
            "waypoints": p.waypoints.iter().map(|w| [w.x, w.y]).collect::<Vec<_>>(),
            "closed": p.closed,
            "speed_mps": p.speed_mps,
            "hotel_load_w": p.hotel_load_w,
            "hotel_per_m_j": p.hotel_per_m(),
            "cell_size_m": p.cell_size,
            "bin_size_m": p.bin_size_m,
            "pose_rate_hz": p.pose_rate_hz,
            "power_rate_hz": p.power_rate_hz,
            "pose_sigma_xy_m": sc.sim.pose_sigma_xy,
            "power_noise": sc.sim.proprio_noise,
            "energy_window_s": p.energy_window_s,
            "pose_smoothing_s": p.pose_smoothing_s,
            "turn_rate_threshold": p.turn_rate_threshold,
            "lengthscale_bounds_m": p.hyper_bounds.lengthscale,
            "signal_variance_bounds": p.hyper_bounds.signal_variance,
            "noise_variance_bounds": p.hyper_bounds.noise_variance,
            "unchanged_tolerance_m": p.unchanged_tolerance_m,
        },
        "published": {
            "first_tour_j": PUBLISHED_FIRST_J,
            "converged_j": PUBLISHED_CONVERGED_J,
            "drop": 1.0 - PUBLISHED_CONVERGED_J / PUBLISHED_FIRST_J,
            "convergence_tour": PUBLISHED_CONVERGENCE,
            "overtaking_tour": PUBLISHED_OVERTAKE,
            "cumulative_after_7_tours_j": {
                "exploring": PUBLISHED_CUMULATIVE_7.0,
                "always_shortest": PUBLISHED_CUMULATIVE_7.1,
            },
        },
        "summary": {
            "first_tour_j": s.first_j,
            "convergence_tour": s.converged,
            "converged_j": s.converged_j,
            "converged_from_tour": s.converged_from,
            "drop": s.drop,
            "drop_vs_always_shortest": s.drop_vs_shortest,
            "first_tour_motive_j": s.first_motive_j,
            "converged_motive_j": s.converged_motive_j,
            "motive_drop": 1.0 - s.converged_motive_j / s.first_motive_j,
            "overtaking_tour": s.overtake,
            "first_tour_is_shortest": s.first_is_shortest,
            "always_shortest_mean_j": s.shortest_mean_j,
            "known_costs_mean_j": s.known_mean_j,
            "known_costs_drop": s.known_drop,
            "known_costs_path_length_m": r.known_plan.length_m,
            "shortest_path_length_m": r.shortest.first().map(|x| x.plan.length_m),
            "cumulative_after_7_tours_j": s.cumulative.get(6).map(|c| json!({"exploring": c.0, "always_shortest": c.1})),
            "cumulative_exploring_j": s.cumulative.last().map(|c| c.0),
            "cumulative_always_shortest_j": s.cumulative.last().map(|c| c.1),
            "acceptance": acceptance(s),
        },
        "tours": t.iter().map(tour_json).collect::<Vec<_>>(),
        "always_shortest": r.shortest.iter().map(|x| json!({
            "tour": x.tour, "energy_j": x.measured.energy_j, "duration_s": x.measured.duration_s,
        })).collect::<Vec<_>>(),
        "known_costs": {
            "plan": r.known_plan,
            "tours": r.known.iter().map(|x| json!({
                "tour": x.tour, "energy_j": x.measured.energy_j, "duration_s": x.measured.duration_s,
            })).collect::<Vec<_>>(),
        },
    });
    write(
        &dir.join("tours.json"),
        &serde_json::to_string_pretty(&report)?,
    )?;
    write(&dir.join("tours.md"), &markdown(sc, r, s))?;
    figures(r, s, dir)
}

fn markdown(sc: &Scenario, r: &SeedRun, s: &Summary) -> String {
    let mut m = String::new();
    let _ = writeln!(
        m,
        "# `003` repeated tours: {} (world seed {}, seed {})\n",
        sc.name, sc.world_seed, r.seed
    );
    let _ = writeln!(m, "| figure | ours | published (`003`) |");
    let _ = writeln!(m, "|---|---|---|");
    let _ = writeln!(
        m,
        "| first tour (shortest path) | {:.1} J | {PUBLISHED_FIRST_J} J |",
        s.first_j
    );
    let _ = writeln!(
        m,
        "| converged tour | {:.1} J (mean of tours {}–{}) | ≈{PUBLISHED_CONVERGED_J} J |",
        s.converged_j,
        s.converged_from,
        r.outcome.tours.len()
    );
    let _ = writeln!(
        m,
        "| energy drop from tour 1 (negative: a rise) | {:.1} % | {:.1} % |",
        100.0 * s.drop,
        100.0 * (1.0 - PUBLISHED_CONVERGED_J / PUBLISHED_FIRST_J)
    );
    let _ = writeln!(
        m,
        "| converged tour vs always-shortest (mean of its tours) | {:.1} J vs {:.1} J ({:+.1} %) | – |",
        s.converged_j,
        s.shortest_mean_j,
        -100.0 * s.drop_vs_shortest
    );
    let _ = writeln!(
        m,
        "| motive energy only (E_t − P_h·T): tour 1 → converged | {:.1} J → {:.1} J ({:.1} %) | – |",
        s.first_motive_j,
        s.converged_motive_j,
        100.0 * (1.0 - s.converged_motive_j / s.first_motive_j)
    );
    let _ = writeln!(
        m,
        "| convergence tour (plan unchanged) | {} | {PUBLISHED_CONVERGENCE} |",
        opt(s.converged)
    );
    let _ = writeln!(
        m,
        "| cumulative energy overtakes always-shortest at tour | {} | {PUBLISHED_OVERTAKE} |",
        opt(s.overtake)
    );
    if let Some(c) = s.cumulative.get(6) {
        let _ = writeln!(
            m,
            "| cumulative energy after 7 tours: exploring vs always-shortest | {:.0} J vs {:.0} J | {:.0} J vs {:.0} J |",
            c.0, c.1, PUBLISHED_CUMULATIVE_7.0, PUBLISHED_CUMULATIVE_7.1
        );
    }
    let _ = writeln!(
        m,
        "| first tour equals the shortest path | {} | yes |",
        if s.first_is_shortest { "yes" } else { "no" }
    );
    let _ = writeln!(
        m,
        "| tour on the true costs (harness) | {:.1} J ({:.1} % below always-shortest) | – |",
        s.known_mean_j,
        100.0 * s.known_drop
    );
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
    m
}

fn write_summary(sc: &Scenario, args: &ToursArgs, rows: &[(u64, Summary)]) -> Result<()> {
    let count = |f: &dyn Fn(&Summary) -> bool| rows.iter().filter(|(_, s)| f(s)).count();
    let n = rows.len();
    let c_short = count(&|s| s.first_is_shortest);
    let c_drop = count(&|s| s.drop >= MIN_DROP);
    let c_conv = count(&|s| s.converged.is_some_and(|c| c <= MAX_CONVERGENCE_TOUR));
    let c_over = count(&|s| s.overtake.is_some_and(|k| k < OVERTAKE_BEFORE));
    let v = json!({
        "scenario": sc.name,
        "world_seed": sc.world_seed,
        "seeds": rows.iter().map(|(s, _)| s).collect::<Vec<_>>(),
        "per_seed": rows.iter().map(|(seed, s)| json!({
            "seed": seed,
            "first_tour_j": s.first_j,
            "converged_j": s.converged_j,
            "drop": s.drop,
            "convergence_tour": s.converged,
            "overtaking_tour": s.overtake,
            "known_costs_mean_j": s.known_mean_j,
            "known_costs_drop": s.known_drop,
            "acceptance": acceptance(s),
        })).collect::<Vec<_>>(),
        "counts": {
            "first_tour_is_shortest": c_short,
            "drop_at_least_30_percent": c_drop,
            "converged_within_10_tours": c_conv,
            "overtakes_before_tour_10": c_over,
            "of": n,
        },
        "published": {
            "first_tour_j": PUBLISHED_FIRST_J,
            "converged_j": PUBLISHED_CONVERGED_J,
            "convergence_tour": PUBLISHED_CONVERGENCE,
            "overtaking_tour": PUBLISHED_OVERTAKE,
        },
    });
    write(
        &args.out.join("summary.json"),
        &serde_json::to_string_pretty(&v)?,
    )?;
    let mut m = String::new();
    let _ = writeln!(
        m,
        "# `003` repeated tours over {n} seeds: {} (world seed {})\n",
        sc.name, sc.world_seed
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
            opt(s.converged),
            opt(s.overtake),
            s.known_mean_j,
            100.0 * s.known_drop
        );
    }
    let _ = writeln!(
        m,
        "| published | {PUBLISHED_FIRST_J} | ≈{PUBLISHED_CONVERGED_J} | {:.1} % | {PUBLISHED_CONVERGENCE} | {PUBLISHED_OVERTAKE} | – | – |",
        100.0 * (1.0 - PUBLISHED_CONVERGED_J / PUBLISHED_FIRST_J)
    );
    let _ = writeln!(m, "\n| criterion | seeds |\n|---|---|");
    let _ = writeln!(
        m,
        "| first tour equals the shortest path | {c_short} of {n} |"
    );
    let _ = writeln!(m, "| energy falls by ≥ 30 % | {c_drop} of {n} |");
    let _ = writeln!(m, "| converges within 10 tours | {c_conv} of {n} |");
    let _ = writeln!(
        m,
        "| cumulative energy overtakes always-shortest before tour 10 | {c_over} of {n} |"
    );
    write(&args.out.join("summary.md"), &m)
}

// ---------------------------------------------------------------------------------------------
// Figures.

const WHITE: [u8; 3] = [255, 255, 255];
const BLUE: [u8; 3] = [31, 119, 180];
const ORANGE: [u8; 3] = [255, 127, 14];
const GREEN: [u8; 3] = [44, 160, 44];
const MAGENTA: [u8; 3] = [255, 0, 255];

fn figures(r: &SeedRun, s: &Summary, dir: &Path) -> Result<()> {
    let e = |v: &[TourRecord]| -> Vec<f64> { v.iter().map(|x| x.measured.energy_j).collect() };
    let chart = |series: &[(Vec<f64>, [u8; 3])], name: &str| {
        line_chart(series, &[], "TOUR", "J").save(&dir.join(name))
    };
    chart(
        &[
            (e(&r.outcome.tours), BLUE),
            (e(&r.shortest), ORANGE),
            (e(&r.known), GREEN),
        ],
        "energy_per_tour.png",
    )?;
    chart(
        &[
            (s.cumulative.iter().map(|c| c.0).collect(), BLUE),
            (s.cumulative.iter().map(|c| c.1).collect(), ORANGE),
        ],
        "cumulative_energy.png",
    )?;
    // The same as one curve: below zero, exploring has cost less in total so far.
    chart(
        &[(s.cumulative.iter().map(|c| c.0 - c.1).collect(), BLUE)],
        "cumulative_difference.png",
    )?;
    // One colour scale for the truth and every learnt map.
    let hi = r
        .truth
        .mean
        .iter()
        .chain(r.outcome.maps.iter().flat_map(|(_, m)| m.mean.iter()))
        .filter(|v| v.is_finite() && **v < 1e3)
        .fold(1.0f32, |a, &b| a.max(b));
    let range = (0.0, hi);
    let tours = &r.outcome.tours;
    let draw = |map: &EnergyMap,
                planned: Option<&PlannedTour>,
                driven: Option<&TourRecord>,
                path: &Path|
     -> Result<()> {
        let scale = Canvas::auto_scale(map.rect, 640);
        let (mut c, _) = scalar_canvas(map.rect, map.cell_size, scale, &map.mean, Some(range));
        if let Some(t) = driven {
            c.polyline(&t.measured.trajectory, MAGENTA, 1);
        }
        if let Some(pl) = planned {
            c.polyline(&pl.path, WHITE, 2);
        }
        if let Some(t) = tours.first() {
            for w in &t.plan.path {
                c.marker(*w, WHITE, 3);
            }
        }
        c.save(path)
    };
    draw(
        &r.truth,
        Some(&r.known_plan),
        None,
        &dir.join("map_truth.png"),
    )?;
    // The map after tour k is the last one learnt at or before k (learning stops at
    // convergence).
    let map_after = |k: usize| r.outcome.maps.iter().rev().find(|(t, _)| *t <= k);
    let plan_after = |k: usize| {
        tours
            .get(k)
            .map(|x| &x.plan)
            .or(tours.last().map(|x| &x.plan))
    };
    for k in MAP_TOURS {
        if k > tours.len() {
            continue;
        }
        if let Some((_, m)) = map_after(k) {
            draw(
                m,
                plan_after(k),
                tours.get(k - 1),
                &dir.join(format!("map_after_tour_{k:02}.png")),
            )?;
        }
    }
    if let Some(k) = r.outcome.convergence_tour
        && let Some((_, m)) = map_after(k)
    {
        draw(
            m,
            plan_after(k),
            tours.get(k - 1),
            &dir.join("map_convergence.png"),
        )?;
    }
    Ok(())
}
