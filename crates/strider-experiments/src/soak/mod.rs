//! `strider bench soak`: invariants at scale. Seeded missions of every registered strategy on
//! every built-in world it can run on (random world seeds of each family, random mission
//! seeds, a short time limit per world), each checked against the simulator's ground truth:
//!
//! * **pose**: the robot's true centre, judged at every pose tick, never leaves the world nor
//!   stands in a cell the simulator's own rule forbids ([`judge`]);
//! * **plan**: every commanded waypoint lies in the world, every tour site (the goals the
//!   strategy drives to) in the exploration bounds, every goal site is finite, every commanded
//!   gait exists;
//! * **termination**: the mission ends within its time limit plus one control step, and
//!   returns within its wall-clock bound ([`mission::wall_bound`]; a watchdog abandons one
//!   that does not, [`runner`]);
//! * **report**: the report `strider run` writes for it serialises to JSON and parses back,
//!   every number in it is finite and its counts agree ([`reports`]);
//! * **crash**: the mission returns no error and does not panic.
//!
//! The soak is an experiment, not an algorithm: it reads the simulator's truth, the strategies
//! never do. The same seed gives the same missions and results, apart from wall-clock fields,
//! whatever `--jobs`. Each violation names the mission (strategy, world, world seed, mission
//! seed) and the command that runs it again alone.

pub mod finite;
pub mod judge;
pub mod mission;
pub mod plan;
pub mod reports;
pub mod robot;
pub mod runner;
mod table;
pub mod violation;

use std::path::Path;
use std::sync::Arc;
use std::time::{Duration, Instant};

use anyhow::{Result, bail};
use serde::Serialize;

use crate::io::{create_dir, write_json, write_text};
use crate::progress::Progress;
use crate::trial::checked_time_limit;
pub use mission::MissionResult;
pub use plan::{Coverage, Task};
pub use table::{CellSummary, markdown};

/// Most missions one soak runs: each keeps a result of about a kilobyte, and 100 000 missions
/// already take days.
pub const MAX_MISSIONS: usize = 100_000;

/// Most missions run side by side (each is one thread; more than the cores only slows them).
pub const MAX_JOBS: usize = 256;

/// Longest simulated time limit of a soak mission, s (a soak is many short missions).
pub const MAX_TIME_LIMIT_S: f64 = 86_400.0;

/// What to soak.
#[derive(Clone, Debug)]
pub struct SoakOptions {
    /// Missions.
    pub missions: usize,
    /// Seed of the world and mission seeds.
    pub seed: u64,
    /// Missions run side by side.
    pub jobs: usize,
    /// Simulated time limit of every mission, s (default: per world).
    pub time_limit: Option<f64>,
    /// Run only this mission (`STRATEGY@SCENARIO:WORLD_SEED:SEED`).
    pub rerun: Option<String>,
}

impl SoakOptions {
    /// Checks every option against its range.
    pub fn validate(&self) -> Result<()> {
        if !(1..=MAX_MISSIONS).contains(&self.missions) {
            bail!(
                "--missions = {}: must be 1 to {MAX_MISSIONS}",
                self.missions
            );
        }
        if !(1..=MAX_JOBS).contains(&self.jobs) {
            bail!("--jobs = {}: must be 1 to {MAX_JOBS}", self.jobs);
        }
        if let Some(t) = self.time_limit {
            checked_time_limit(t)?;
            if t > MAX_TIME_LIMIT_S {
                bail!("--time-limit = {t}: must be at most {MAX_TIME_LIMIT_S} s for a soak");
            }
        }
        Ok(())
    }

    /// The command line that runs this soak again.
    pub fn command(&self) -> String {
        let mut c = match &self.rerun {
            Some(key) => format!("strider bench soak --rerun {key}"),
            None => format!(
                "strider bench soak --missions {} --seed {}",
                self.missions, self.seed
            ),
        };
        if let Some(t) = self.time_limit {
            c.push_str(&format!(" --time-limit {t}"));
        }
        c
    }
}

/// A finished soak.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Soak {
    /// The command that runs it again.
    pub command: String,
    /// `"N missions, V invariant violations"`.
    pub summary: String,
    /// Missions run.
    pub missions: usize,
    /// Invariants broken, one per kind and mission.
    pub violations: usize,
    /// Which strategy ran on which worlds, and why not on the others.
    pub coverage: Vec<Coverage>,
    /// Per strategy × world.
    pub cells: Vec<CellSummary>,
    /// Every mission, in order.
    pub results: Vec<MissionResult>,
    /// Wall time of the soak, s.
    pub wall_s: f64,
}

impl Soak {
    /// The missions that broke an invariant.
    pub fn failures(&self) -> impl Iterator<Item = &MissionResult> {
        self.results.iter().filter(|r| !r.violations.is_empty())
    }
}

/// Runs the soak; `progress` counts missions and is warned of each violation as it is found.
pub fn run(o: &SoakOptions, progress: &dyn Progress) -> Result<Soak> {
    o.validate()?;
    let wall = Instant::now();
    let coverage = plan::coverage()?;
    let tasks = match &o.rerun {
        Some(key) => {
            let t = Task::parse(key, o.time_limit)?;
            let fits = coverage
                .iter()
                .find(|c| c.strategy == t.strategy)
                .and_then(|c| c.skipped.iter().find(|(w, _)| *w == t.scenario));
            if let Some((_, why)) = fits {
                bail!("--rerun {key}: {why}");
            }
            vec![t]
        }
        None => plan::tasks(&coverage, o.missions, o.seed, o.time_limit),
    };
    if tasks.is_empty() {
        bail!("no strategy runs on any built-in world");
    }
    progress.start(tasks.len() as u64);
    let results = runner::run_all(
        &tasks,
        (
            o.jobs.min(tasks.len()),
            Duration::from_secs_f64(runner::GRACE_S),
        ),
        |t| mission::wall_bound(t.time_limit_s),
        Arc::new(mission::run),
        |r| {
            progress.inc();
            for v in &r.violations {
                progress.warn(&format!(
                    "{}: {} ×{}: {}",
                    r.task,
                    v.kind.name(),
                    v.count,
                    v.examples.join("; ")
                ));
            }
        },
    );
    let violations = results.iter().map(|r| r.violations.len()).sum();
    Ok(Soak {
        command: o.command(),
        summary: format!(
            "{} missions, {violations} invariant violations",
            results.len()
        ),
        missions: results.len(),
        violations,
        cells: table::cells(&coverage, &results),
        coverage,
        results,
        wall_s: wall.elapsed().as_secs_f64(),
    })
}

/// Writes `soak.json` (everything) and `soak.md` (the tables) into `out`.
pub fn write(out: &Path, soak: &Soak) -> Result<()> {
    create_dir(out)?;
    write_json(&out.join("soak.json"), soak)?;
    write_text(&out.join("soak.md"), &markdown(soak))
}
