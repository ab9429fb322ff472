//! Hang detection: a thread that aborts the process when one case runs too long. A hang cannot
//! be caught any other way, and the input is already on disk in `current`.

use std::sync::Arc;
use std::sync::atomic::{AtomicU64, Ordering};
use std::time::{Duration, Instant};

/// Shared clock of the case in progress: milliseconds since the watchdog started at which the
/// case began, or `IDLE`.
pub(crate) struct Watchdog {
    started_ms: Arc<AtomicU64>,
    origin: Instant,
}

const IDLE: u64 = u64::MAX;

impl Watchdog {
    /// Starts the watchdog thread for target `name`; `limit` is the longest a case may run and
    /// `current` the file that holds the case's input.
    pub(crate) fn start(name: &str, limit: Duration, current: String) -> Self {
        let started_ms = Arc::new(AtomicU64::new(IDLE));
        let origin = Instant::now();
        let watched = Arc::clone(&started_ms);
        let name = name.to_string();
        std::thread::spawn(move || {
            loop {
                std::thread::sleep(Duration::from_millis(200));
                let s = watched.load(Ordering::Relaxed);
                let now = origin.elapsed().as_millis() as u64;
                if s != IDLE && now.saturating_sub(s) > limit.as_millis() as u64 {
                    eprintln!(
                        "fuzz {name}: a case ran longer than {:.0} s (a hang); its input is in {current}",
                        limit.as_secs_f64()
                    );
                    std::process::abort();
                }
            }
        });
        Self { started_ms, origin }
    }

    pub(crate) fn begin(&self) {
        let now = self.origin.elapsed().as_millis() as u64;
        self.started_ms.store(now, Ordering::Relaxed);
    }

    pub(crate) fn end(&self) {
        self.started_ms.store(IDLE, Ordering::Relaxed);
    }
}
