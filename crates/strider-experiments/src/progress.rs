//! What a long experiment tells its caller while it works. The library never draws: the
//! `strider` binary shows these calls as progress bars and lines on stderr.

/// Receives an experiment's progress. Every method does nothing by default.
pub trait Progress: Sync {
    /// The work is `total` units long (simulated seconds, trials or runs).
    fn start(&self, _total: u64) {}
    /// `done` units are done; `message` says what is happening.
    fn at(&self, _done: u64, _message: &str) {}
    /// One more unit is done.
    fn inc(&self) {}
    /// A phase whose length is not known (e.g. the benchmark tours after a mission).
    fn phase(&self, _message: &str) {}
    /// A warning for the user.
    fn warn(&self, _text: &str) {}
}

/// Progress that goes nowhere.
#[derive(Clone, Copy, Debug, Default)]
pub struct Silent;

impl Progress for Silent {}
