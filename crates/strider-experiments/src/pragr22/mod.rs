//! Prágr22: autonomous exploration with simultaneous environment and traversability models
//! learning (`gtsp`, `greedy`, `spatial-only`): one mission with its benchmark tours and report
//! ([`run_tour`]), and the Table 5 reproduction ([`table5()`]).

mod figures;
pub mod report;
mod run;
pub(crate) use run::report as mission_report;
mod table5;
mod table5_merge;
mod table5_report;
mod table5_segments;
mod table5_trials;

pub use figures::write_figures;
pub use run::{TourRun, run_tour};
pub use table5::{Table5, assemble, run_trial, table5, trial_count, write as write_table5};
pub use table5_merge::merge_table5;
pub use table5_report::{LargeReplanMs, MannWhitneyReport, Relation, Row, Table5Report, markdown};
pub use table5_segments::SegmentRow;
pub use table5_trials::{Table5Options, TrialResult};
