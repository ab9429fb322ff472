//! Prágr19: online incremental learning of the terrain traversal cost in autonomous
//! exploration: the `rbcm-greedy` mission and its report ([`run()`]), and the learner benchmark
//! of its Fig. 5 ([`stream_bench`]).

pub mod report;
mod run;
mod stream;
mod stream_report;

pub use run::{RbcmRun, run, terrain_check};
pub use stream::{StreamOptions, stream_bench};
pub use stream_report::{AtStep, Curve, Findings, LearnerReport, REPORT_AT, StreamReport};
