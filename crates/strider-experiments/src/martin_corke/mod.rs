//! MartinCorke: energy-optimal repeated tours in the simulator (`strider tours`).
//!
//! For each noise seed, three runs of the scenario's first tour, each in a fresh simulator with
//! that seed:
//!
//! * **exploring** — [`run_energy_tours`]: tour 1 is the shortest tour, then every tour plans on
//!   the zero-mean GP of energy per metre learnt so far (plus the hotel load per metre), until
//!   the plan stops changing; the robot then keeps driving the converged tour;
//! * **always-shortest** — the baseline of MartinCorke §5: tour 1's plan, driven every time;
//! * **known costs** — a harness figure, not an algorithm: the tour the same planner picks on
//!   the simulator's true energy per metre, driven every time. It bounds what learning can gain
//!   on this world.
//!
//! Writes `tours.json` and `tours.md` (per tour and summary, with the published figures beside
//! ours), `energy_per_tour.json`, the figures `energy_per_tour.png`, `cumulative_energy.png` and
//! `cumulative_difference.png`, and the learnt maps after tours 1, 5, 10, 25 and at convergence
//! (`map_after_tour_NN.png`, `map_convergence.png`) beside the true map (`map_truth.png`). With
//! several seeds each seed goes to `DIR/seed-N/` and `DIR/summary.{json,md}` counts the seeds
//! meeting each acceptance criterion.
//!
//! The scenario's `[strategy.tours]` section may set `n_tours`, `bin_size_m`,
//! `lengthscale_min_m`, `lengthscale_max_m` and `unchanged_tolerance_m`; everything else comes
//! from its first tour, bounds, map cell size, robot profile and simulator rates.

mod figures;
mod metrics;
mod report;
mod worlds;

use std::fmt;
use std::path::{Path, PathBuf};

use anyhow::{Context, Result, bail};
use rayon::prelude::*;
use strider_core::{CellRect, GaitId};
use strider_explore::energy_tours::{
    EnergyMap, EnergyTourParams, PlannedTour, TourPlanner, TourRecord, ToursOutcome,
    drive_fixed_tour, plan_shortest, run_energy_tours,
};
use strider_scenario::Scenario;
use strider_sim::Simulator;
use strider_sim::motion::STUCK_SPEED_CEILING;
use strider_sim::terrain::TerrainTable;

use crate::io::create_dir;
use crate::trial::{load, section};
pub use metrics::SeedFigures;
pub use report::{SummaryReport, ToursReport};
pub use worlds::WorldsReport;

/// MartinCorke's published figures.
pub(crate) const PUBLISHED_FIRST_J: f64 = 28.7;
pub(crate) const PUBLISHED_CONVERGED_J: f64 = 16.0;
pub(crate) const PUBLISHED_CONVERGENCE: &str = "~8–10 (simulation: 10)";
pub(crate) const PUBLISHED_OVERTAKE: usize = 8;
/// MartinCorke §5: exploring cost 206 J over the first 7 tours against 201 J for the shortest
/// path.
pub(crate) const PUBLISHED_CUMULATIVE_7: (f64, f64) = (206.0, 201.0);

/// Acceptance thresholds: the energy falls by at least this fraction, converges and overtakes
/// within these tours.
pub(crate) const MIN_DROP: f64 = 0.30;
pub(crate) const MAX_CONVERGENCE_TOUR: usize = 10;
pub(crate) const OVERTAKE_BEFORE: usize = 10;

/// The most noise seeds `strider tours` runs (`--seeds`): each seed is three full tour series
/// with their figures; 1000 is far beyond an acceptance sweep (10) and keeps a mistyped count
/// from queueing (and allocating for) billions of runs.
pub const MAX_SEEDS: u64 = 1000;

/// The most world seeds `strider tours` runs (`--world-seeds`), and the most runs (world seeds
/// × noise seeds) in one call: 100 × 100 runs is far beyond the acceptance sweep (10 × 10).
pub const MAX_WORLDS: u64 = 1000;
pub const MAX_RUNS: u64 = 10_000;

/// The most tours per series (`--tours`, `n_tours`): MartinCorke drives 25; every tour is a
/// drive of the whole route and a GP refit, and the series is held in memory.
pub const MAX_TOURS: usize = 10_000;

/// Options of `strider tours`.
#[derive(Clone, Debug)]
pub struct ToursOptions {
    /// Built-in scenario name or scenario file.
    pub scenario: String,
    /// First world seed.
    pub world_seed: u64,
    /// World seeds (world_seed, world_seed + 1, …).
    pub world_seeds: u64,
    /// First noise seed.
    pub seed: u64,
    /// Noise seeds (seed, seed + 1, …).
    pub seeds: u64,
    /// Number of tours (default: the scenario's).
    pub tours: Option<usize>,
    /// Output directory.
    pub out: PathBuf,
}

impl ToursOptions {
    /// The command that reproduces the tours of world `world` and noise seed `seed` (`None`:
    /// of every world and seed).
    pub fn command(&self, run: Option<(u64, u64)>) -> String {
        let tours = self
            .tours
            .map_or(String::new(), |n| format!(" --tours {n}"));
        let (world, seed, counts) = match run {
            Some((w, s)) => (w, s, String::new()),
            None => {
                let worlds = if self.world_seeds > 1 {
                    format!(" --world-seeds {}", self.world_seeds)
                } else {
                    String::new()
                };
                (
                    self.world_seed,
                    self.seed,
                    format!("{worlds} --seeds {}", self.seeds),
                )
            }
        };
        format!(
            "strider tours --scenario {} --world-seed {world} --seed {seed}{counts}{tours}",
            self.scenario
        )
    }

    /// The command that reproduces world `world`'s tours (every noise seed).
    fn world_command(&self, world: u64) -> String {
        let tours = self
            .tours
            .map_or(String::new(), |n| format!(" --tours {n}"));
        format!(
            "strider tours --scenario {} --world-seed {world} --seed {} --seeds {}{tours}",
            self.scenario, self.seed, self.seeds
        )
    }
}

/// Loop parameters from a scenario: its first tour, bounds and map cell size, the robot's first
/// gait, speed, hotel load and mass, its streams' rates, and the optional keys of its
/// `[strategy.tours]` section (module docs).
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
    let table = section(sc, "tours")?.cloned().unwrap_or_default();
    let from_table = table.get("n_tours").and_then(|v| v.as_integer());
    p.n_tours = match (n_tours, from_table) {
        (Some(n), _) if (1..=MAX_TOURS).contains(&n) => n,
        (Some(n), _) => bail!("--tours {n}: must be an integer from 1 to {MAX_TOURS}"),
        (None, Some(n)) if (1..=MAX_TOURS as i64).contains(&n) => n as usize,
        (None, Some(n)) => bail!(
            "scenario {}: strategy.tours.n_tours = {n}: must be an integer from 1 to {MAX_TOURS}",
            sc.name
        ),
        (None, None) => 25,
    };
    p.pose_rate_hz = sc.sim.pose_rate_hz;
    p.power_rate_hz = sc.sim.proprio_rate_hz;
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
            let Some(k) = sc.world.index_at(c.center(p.cell_size)) else {
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
        .map(|m| if m.is_finite() { m } else { 1e4 })
        .collect::<Vec<f32>>();
    EnergyMap {
        rect,
        cell_size: p.cell_size,
        variance: vec![0.0; rect.len()],
        mean,
        bins: Vec::new(),
    }
}

/// Everything measured for one seed.
pub struct SeedRun {
    /// The noise seed.
    pub seed: u64,
    /// The exploring tours.
    pub outcome: ToursOutcome,
    /// The always-shortest tours.
    pub shortest: Vec<TourRecord>,
    /// The tours on the true costs.
    pub known: Vec<TourRecord>,
    /// Their plan.
    pub known_plan: PlannedTour,
    /// The true energy map.
    pub truth: EnergyMap,
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

/// One seed's line for the terminal.
pub struct SeedLine {
    scenario: String,
    world_seed: u64,
    seed: u64,
    figures: SeedFigures,
    report: PathBuf,
}

impl fmt::Display for SeedLine {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let s = &self.figures;
        write!(
            f,
            "{} (world seed {}, seed {}): tour 1 {:.1} J, converged {} at {:.1} J ({:+.0} %), overtakes always-shortest at tour {}; known costs {:.1} J ({:+.0} %) -> {}",
            self.scenario,
            self.world_seed,
            self.seed,
            s.first_j,
            metrics::tour_or_never(s.converged),
            s.converged_j,
            -100.0 * s.drop,
            metrics::tour_or_never(s.overtake),
            s.known_mean_j,
            -100.0 * s.known_drop,
            self.report.display()
        )
    }
}

/// One world of the call: its scenario and loop parameters.
struct WorldTask {
    sc: Scenario,
    p: EnergyTourParams,
}

fn world_task(o: &ToursOptions, world_seed: u64) -> Result<WorldTask> {
    let sc = load(&o.scenario, world_seed)?;
    let p = tour_params(&sc, o.tours).with_context(|| format!("scenario {}", sc.name))?;
    // Bad waypoints are reported before any simulation.
    TourPlanner::new(&p)
        .with_context(|| format!("scenario {}, tour {}", sc.name, sc.tours[0].name))?;
    Ok(WorldTask { sc, p })
}

/// Checks `--world-seed W --world-seeds K` and the number of runs.
fn check_worlds(o: &ToursOptions) -> Result<()> {
    if !(1..=MAX_WORLDS).contains(&o.world_seeds) {
        bail!(
            "--world-seeds {}: must be an integer from 1 to {MAX_WORLDS}",
            o.world_seeds
        );
    }
    if o.world_seed.checked_add(o.world_seeds - 1).is_none() {
        bail!(
            "--world-seed {} with --world-seeds {}: the last world seed would pass {}",
            o.world_seed,
            o.world_seeds,
            u64::MAX
        );
    }
    if o.world_seeds.saturating_mul(o.seeds) > MAX_RUNS {
        bail!(
            "--world-seeds {} × --seeds {}: at most {MAX_RUNS} runs in one call",
            o.world_seeds,
            o.seeds
        );
    }
    Ok(())
}

/// Runs `strider tours`; returns one line per world and seed. With several world seeds each
/// world goes to `DIR/world-W/` and `DIR/worlds.{json,md}` pools every run.
pub fn tours(o: &ToursOptions) -> Result<Vec<SeedLine>> {
    crate::trial::check_seed_range(o.seed, o.seeds, MAX_SEEDS)?;
    check_worlds(o)?;
    let worlds: Vec<WorldTask> = (0..o.world_seeds)
        .map(|i| world_task(o, o.world_seed + i))
        .collect::<Result<_>>()?;
    create_dir(&o.out)?;
    let jobs: Vec<(usize, u64)> = (0..worlds.len())
        .flat_map(|w| (0..o.seeds).map(move |i| (w, o.seed + i)))
        .collect();
    // One flat list, so that a few slow worlds do not leave cores idle.
    let runs: Vec<SeedRun> = jobs
        .par_iter()
        .map(|&(w, s)| run_seed(&worlds[w].sc, &worlds[w].p, s))
        .collect::<Result<_>>()?;
    let mut lines = Vec::new();
    let per_world = o.seeds as usize;
    for (w, task) in worlds.iter().enumerate() {
        let dir = if worlds.len() == 1 {
            o.out.clone()
        } else {
            o.out.join(format!("world-{}", task.sc.world_seed))
        };
        let these = &runs[w * per_world..(w + 1) * per_world];
        lines.extend(write_world(o, task, these, &dir)?);
    }
    if worlds.len() > 1 {
        let pooled: Vec<worlds::WorldRun<'_>> = lines
            .iter()
            .zip(&runs)
            .map(|(l, r)| worlds::WorldRun {
                world: l.world_seed,
                seed: l.seed,
                figures: &l.figures,
                shortest_m: r.shortest.first().map_or(f64::NAN, |t| t.plan.length_m),
                known_m: r.known_plan.length_m,
            })
            .collect();
        worlds::write(&worlds[0].sc.name, &o.out, &pooled, &o.command(None))?;
    }
    Ok(lines)
}

/// Writes one world's reports and figures into `dir` (per seed into `dir/seed-N/` when there
/// are several, with `summary.{json,md}`); returns one line per seed.
fn write_world(
    o: &ToursOptions,
    task: &WorldTask,
    runs: &[SeedRun],
    dir: &Path,
) -> Result<Vec<SeedLine>> {
    let sc = &task.sc;
    create_dir(dir)?;
    let mut lines = Vec::new();
    for r in runs {
        let seed_dir = if runs.len() == 1 {
            dir.to_path_buf()
        } else {
            dir.join(format!("seed-{}", r.seed))
        };
        create_dir(&seed_dir)?;
        let figures = SeedFigures::of(r);
        let command = o.command(Some((sc.world_seed, r.seed)));
        report::write_seed(sc, &task.p, (r, &figures), &command, &seed_dir)?;
        figures::write(r, &figures, &seed_dir)?;
        lines.push(SeedLine {
            scenario: sc.name.clone(),
            world_seed: sc.world_seed,
            seed: r.seed,
            figures,
            report: seed_dir.join("tours.json"),
        });
    }
    if runs.len() > 1 {
        let rows: Vec<(u64, &SeedFigures)> = lines.iter().map(|l| (l.seed, &l.figures)).collect();
        report::write_summary(sc, dir, &rows, &o.world_command(sc.world_seed))?;
    }
    Ok(lines)
}
