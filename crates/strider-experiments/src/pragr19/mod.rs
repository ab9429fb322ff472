//! Prágr19: online incremental learning of the terrain traversal cost in autonomous
//! exploration: the `rbcm-greedy` mission and its report ([`run()`]), and the learner benchmark
//! of its Fig. 5 ([`stream_bench`]).

pub mod report;
mod run;
mod stream;
mod stream_report;

pub use run::{RbcmRun, run, terrain_check};
pub use stream::stream_bench;
pub use stream_report::{AtStep, Curve, Findings, LearnerReport, REPORT_AT, StreamReport};

use std::path::PathBuf;

use anyhow::{Result, bail};

/// Options of the stream protocol.
#[derive(Clone, Debug)]
pub struct StreamOptions {
    /// Repetitions (Prágr19: 100), each on one of the recorded streams.
    pub reps: usize,
    /// Distinct recorded streams; repetition r runs on stream r mod K.
    pub streams: usize,
    /// Pairs per stream (Prágr19: 292 from two passes).
    pub pairs: usize,
    /// Simulator seed of the first stream (stream i uses seed + i).
    pub seed: u64,
    /// Output directory.
    pub out: PathBuf,
}

impl StreamOptions {
    /// Checks the options before anything runs.
    pub fn check(&self) -> Result<()> {
        if self.reps == 0 || self.streams == 0 || self.pairs < 2 {
            bail!("--reps and --streams must be at least 1 and --pairs at least 2");
        }
        Ok(())
    }
}
