//! Stopping long work early: a flag the caller sets from another thread (the `strider` binary
//! sets it on Ctrl-C), which missions, trial loops and replays check; and the error an
//! interrupted command ends with, saying what it kept.
//!
//! Interrupted work winds down instead of vanishing: a mission stops at its next control tick
//! and its report is written marked `"complete": false, "interrupted": true`; an MCAP recording
//! is finished (summary and footer written); a bench keeps every trial finished so far and can
//! be resumed from them.

use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};

use strider_explore::{Mission, MissionStrategy};

/// A cancellation flag shared by the caller (who requests) and the work (which checks). Clones
/// share the flag; the default is a flag nobody has requested yet.
#[derive(Clone, Debug, Default)]
pub struct Cancel(Arc<AtomicBool>);

impl Cancel {
    /// A flag not requested yet.
    pub fn new() -> Self {
        Self::default()
    }

    /// Asks the work to stop (callable from any thread, e.g. a signal handler's).
    pub fn request(&self) {
        self.0.store(true, Ordering::Relaxed);
    }

    /// Whether stopping was requested.
    pub fn requested(&self) -> bool {
        self.0.load(Ordering::Relaxed)
    }

    /// Makes `mission` stop at its next control tick once stopping is requested.
    pub fn watch<S: MissionStrategy>(&self, mission: &mut Mission<S>) {
        mission.cancel_on(self.0.clone());
    }
}

/// The error of a command that was interrupted after keeping what it had finished: `kept` says
/// what that is and how to continue. The `strider` binary prints it and exits with 130.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
#[error("interrupted: {kept}")]
pub struct Interrupted {
    /// What was kept, and how to continue.
    pub kept: String,
}

impl Interrupted {
    /// An interruption that kept `kept`.
    pub fn new(kept: impl Into<String>) -> Self {
        Self { kept: kept.into() }
    }
}

/// Whether a mission stopped for the cancellation flag, and whether its report is therefore
/// partial; flattened into every mission report as `"complete"` and `"interrupted"`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
pub struct Completion {
    /// The work ran to its end (time limit, or the strategy ended it) and everything the
    /// report describes was done.
    pub complete: bool,
    /// The work was stopped early by the cancellation flag (Ctrl-C).
    pub interrupted: bool,
}

impl Completion {
    /// Complete unless `interrupted`.
    pub fn of(interrupted: bool) -> Self {
        Self {
            complete: !interrupted,
            interrupted,
        }
    }
}
