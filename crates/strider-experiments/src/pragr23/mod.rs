//! Prágr23 (thesis contribution C4): learning traversable yet visually rigid obstacles. The
//! `escape` mission and its `rigid` baseline with their report ([`run()`]), one evaluated trial
//! ([`trial`]), and the offline force-predictor bench of §5.3 ([`vegetation`]).

mod figures;
mod run;
pub mod trial;
pub mod vegetation;

pub(crate) use run::escape_report;
pub use run::{CellStateSample, EscapeReport, EscapeRun, HapticReport, run};
