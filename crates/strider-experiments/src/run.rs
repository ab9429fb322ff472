//! `strider run`: one exploration mission of any registered strategy on a scenario in the
//! simulator, and its report. The strategy decides which paper's experiment this is: Prágr22
//! (`gtsp`, `greedy`, `spatial-only`), Prágr19 (`rbcm-greedy`) or Prágr23 (`escape`, `rigid`).

use std::fmt;
use std::path::{Path, PathBuf};

use anyhow::Result;
use serde::Serialize;
use strider_core::snapshot::Snapshot;
use strider_explore::registry::Configured;
use strider_explore::{Mission, MissionProgress, MissionStrategy};
use strider_log::writer::WriteSummary;
use strider_scenario::Scenario;

use crate::cancel::{Cancel, Completion, Interrupted};
use crate::io::create_dir;
use crate::live::{LiveServer, Watch};
use crate::pace::Rate;
use crate::parallel::on_worker;
use crate::progress::Progress;
use crate::trial::{checked_time_limit, configure, load, termination};
use crate::{pragr19, pragr22, pragr23};

/// What `strider run` was asked to do.
#[derive(Clone, Copy, Debug)]
pub struct RunRequest<'a> {
    /// Scenario name or file.
    pub scenario: &'a str,
    /// World seed of a built-in scenario.
    pub world_seed: u64,
    /// Strategy name.
    pub strategy: &'a str,
    /// Parameter overrides (key, value), in order.
    pub sets: &'a [(String, String)],
    /// Mission and simulator seed.
    pub seed: u64,
    /// Time limit override, simulated seconds.
    pub time_limit: Option<f64>,
    /// Output directory.
    pub out: &'a Path,
    /// MCAP recording file.
    pub mcap: Option<&'a Path>,
    /// The live view to publish the mission on.
    pub live: Option<&'a LiveServer>,
    /// Pacing to the wall clock (`--rate`); none runs as fast as it can.
    pub rate: Option<Rate>,
    /// Stops the mission early when requested; the report is then written marked incomplete.
    pub cancel: &'a Cancel,
}

impl RunRequest<'_> {
    /// How the mission is watched: recording, live view, pace, cancellation.
    pub(crate) fn watch(&self) -> Watch<'_> {
        Watch {
            mcap: self.mcap,
            live: self.live,
            rate: self.rate,
            cancel: self.cancel,
        }
    }
}

/// A mission recorded to MCAP: how many messages went to which file.
#[derive(Clone, Debug, PartialEq)]
pub struct Recorded {
    /// Messages written.
    pub messages: u64,
    /// The file.
    pub file: PathBuf,
}

impl Recorded {
    /// What was written to `file`, if anything was.
    pub fn of(written: Option<&WriteSummary>, file: Option<&Path>) -> Option<Self> {
        Some(Self {
            messages: written?.total(),
            file: file?.to_path_buf(),
        })
    }
}

impl fmt::Display for Recorded {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{} messages -> {}", self.messages, self.file.display())
    }
}

/// Which mission a report is about.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct MissionId {
    /// Scenario name.
    pub scenario: String,
    /// World seed.
    pub world_seed: u64,
    /// Mission seed.
    pub seed: u64,
    /// Strategy name.
    pub strategy: &'static str,
}

impl MissionId {
    pub(crate) fn of(sc: &Scenario, req: &RunRequest, strategy: &'static str) -> Self {
        Self {
            scenario: sc.name.clone(),
            world_seed: req.world_seed,
            seed: req.seed,
            strategy,
        }
    }
}

/// How a mission's exploration ended.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Explored {
    /// Whether the mission ran to its end or was interrupted (then the report describes the
    /// mission up to the interruption, without the work that follows it, e.g. the tours).
    #[serde(flatten)]
    pub completion: Completion,
    /// Why the exploration stopped (`Interrupted` when it was).
    pub termination: String,
    /// Exploration time, simulated s.
    pub exploration_time_s: f64,
    /// Distance driven, m.
    pub driven_m: f64,
    /// Observed map cells.
    pub observed_cells: usize,
}

impl Explored {
    pub(crate) fn of<S: MissionStrategy>(mission: &Mission<S>) -> Self {
        let record = mission.record();
        Self {
            completion: Completion::of(mission.interrupted()),
            termination: termination(mission),
            exploration_time_s: record.exploration_time_s,
            driven_m: record.driven_m,
            observed_cells: mission.body().map().observed_count(),
        }
    }
}

/// A finished mission of `strider run`: its report, where it was written and what was
/// recorded. Its `Display` is the summary for the terminal.
#[derive(Debug)]
pub struct MissionRun<R> {
    /// The report written.
    pub report: R,
    /// Where `report.json` is.
    pub path: PathBuf,
    /// What was recorded to MCAP, if asked.
    pub recorded: Option<Recorded>,
    /// The mission's state at its end, with the map and model layers (for language bindings:
    /// the report holds figures, not rasters).
    pub last: Snapshot,
}

/// A finished `strider run`; its `Display` is the summary for the terminal.
#[derive(Debug)]
pub enum RunOutcome {
    /// A Prágr22 mission.
    Tour(Box<MissionRun<pragr22::report::RunReport>>),
    /// A Prágr19 mission.
    Rbcm(Box<MissionRun<pragr19::report::RbcmReport>>),
    /// A Prágr23 mission.
    Escape(Box<MissionRun<pragr23::EscapeReport>>),
}

impl RunOutcome {
    /// Whether the mission was interrupted, and if so what was kept (for the terminal).
    pub fn interrupted(&self) -> Option<Interrupted> {
        let (explored, path, recorded) = match self {
            RunOutcome::Tour(r) => (&r.report.explored, &r.path, &r.recorded),
            RunOutcome::Rbcm(r) => (&r.report.explored, &r.path, &r.recorded),
            RunOutcome::Escape(r) => (&r.report.explored, &r.path, &r.recorded),
        };
        if !explored.completion.interrupted {
            return None;
        }
        let mcap = recorded.as_ref().map_or(String::new(), |r| {
            format!(" and the recording {} (finished)", r.file.display())
        });
        Some(Interrupted::new(format!(
            "kept the report of the first {:.0} s simulated, {} (marked \"complete\": false){mcap}; run the command again for a whole mission",
            explored.exploration_time_s,
            path.display()
        )))
    }
}

impl fmt::Display for RunOutcome {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            RunOutcome::Tour(r) => r.fmt(f),
            RunOutcome::Rbcm(r) => r.fmt(f),
            RunOutcome::Escape(r) => r.fmt(f),
        }
    }
}

/// Runs `strider run` (on a pool thread, see [`on_worker`]).
pub fn run(req: &RunRequest, progress: &dyn Progress) -> Result<RunOutcome> {
    on_worker(|| {
        let sc = load(req.scenario, req.world_seed)?;
        let (_, configured) = configure(&sc, req.strategy, req.sets)?;
        Ok(match &configured {
            Configured::Tour(..) => RunOutcome::Tour(Box::new(pragr22::run_tour(
                &sc,
                req,
                &configured,
                progress,
            )?)),
            Configured::Rbcm(table) => {
                RunOutcome::Rbcm(Box::new(pragr19::run(&sc, req, table, progress)?))
            }
            Configured::Escape(mode, table) => {
                RunOutcome::Escape(Box::new(pragr23::run(&sc, req, *mode, table, progress)?))
            }
        })
    })
}

/// Applies the request's time limit to a mission's `limit_s`, creates the output directory
/// and announces the mission's length.
pub(crate) fn start(req: &RunRequest, limit_s: &mut f64, progress: &dyn Progress) -> Result<()> {
    if let Some(t) = req.time_limit {
        *limit_s = checked_time_limit(t)?;
    }
    create_dir(req.out)?;
    progress.start(limit_s.max(1.0) as u64);
    Ok(())
}

/// The progress line of a mission that maps and learns.
pub(crate) fn learning_message(p: &MissionProgress) -> String {
    format!(
        "{} cells mapped, {} learning pairs",
        p.observed_cells, p.learning_set
    )
}
