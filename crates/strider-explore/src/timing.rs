//! Wall-clock latencies as the logs report them.

use std::time::Instant;

/// Milliseconds of wall time since `start`.
pub(crate) fn ms_since(start: Instant) -> f64 {
    start.elapsed().as_secs_f64() * 1e3
}
