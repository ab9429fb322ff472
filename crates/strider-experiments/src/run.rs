//! `strider run`: one exploration mission of any registered strategy on a scenario in the
//! simulator, and its report. The strategy decides which paper's experiment this is: Prágr22
//! (`gtsp`, `greedy`, `spatial-only`), Prágr19 (`rbcm-greedy`) or Prágr23 (`escape`, `rigid`).

use std::fmt;
use std::path::{Path, PathBuf};

use anyhow::Result;
use strider_explore::registry::Configured;
use strider_log::writer::WriteSummary;

use crate::io::create_dir;
use crate::parallel::on_worker;
use crate::progress::Progress;
use crate::trial::{configure, load};
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

/// A finished `strider run`; its `Display` is the summary for the terminal.
#[derive(Debug)]
pub enum RunOutcome {
    /// A Prágr22 mission.
    Tour(Box<pragr22::TourRun>),
    /// A Prágr19 mission.
    Rbcm(Box<pragr19::RbcmRun>),
    /// A Prágr23 mission.
    Escape(Box<pragr23::EscapeRun>),
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

/// Creates the output directory and announces a mission of `limit_s` simulated seconds.
pub(crate) fn start(out: &Path, limit_s: f64, progress: &dyn Progress) -> Result<()> {
    create_dir(out)?;
    progress.start(limit_s.max(1.0) as u64);
    Ok(())
}
