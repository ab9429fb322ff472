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

/// The most repetitions of the stream protocol (`--reps`; Prágr19: 100). Every repetition's
/// learning curves are kept for the report.
pub const MAX_REPS: usize = 1000;

/// The most recorded streams (`--streams`); each is a simulated drive held in memory.
pub const MAX_STREAMS: usize = 1000;

/// The most pairs per stream (`--pairs`; Prágr19: 292). The full GP of the benchmark costs
/// O(n²) memory and O(n³) time over a stream of n pairs: 2000 pairs take about a minute.
pub const MAX_PAIRS: usize = 2000;

impl StreamOptions {
    /// Checks the options before anything runs.
    pub fn check(&self) -> Result<()> {
        let ranges = [
            ("--reps", self.reps, 1, MAX_REPS),
            ("--streams", self.streams, 1, MAX_STREAMS),
            ("--pairs", self.pairs, 2, MAX_PAIRS),
        ];
        for (flag, v, lo, hi) in ranges {
            if !(lo..=hi).contains(&v) {
                bail!("{flag} {v}: must be an integer from {lo} to {hi}");
            }
        }
        if self.seed.checked_add(self.streams as u64).is_none() {
            bail!(
                "--seed {} with --streams {}: the last stream's seed would pass {}",
                self.seed,
                self.streams,
                u64::MAX
            );
        }
        Ok(())
    }
}
