//! Threads for experiments: the pool trials run on side by side, and running one mission on a
//! pool thread.

use anyhow::{Context, Result};

/// The most threads a `--jobs` may ask for (more than any machine here has cores).
pub const MAX_JOBS: usize = 256;

/// The number of CPUs (1 when unknown, at most [`MAX_JOBS`]): the default of every `--jobs`.
pub fn available_jobs() -> usize {
    std::thread::available_parallelism().map_or(1, |n| n.get().min(MAX_JOBS))
}

/// The threads a pool asked for `jobs` runs: at least one, at most [`available_jobs`]. The work
/// is CPU-bound, so threads beyond the cores gain nothing, while each reserves its own stack
/// and allocator arena (thousands of them exhaust the address space) and holds a whole
/// mission or navigation while it works.
pub fn threads(jobs: usize) -> usize {
    jobs.clamp(1, available_jobs())
}

/// A pool of [`threads`]`(jobs)` threads for trials run side by side.
pub fn pool(jobs: usize) -> Result<rayon::ThreadPool> {
    rayon::ThreadPoolBuilder::new()
        .num_threads(threads(jobs))
        .build()
        .context("cannot start the trial thread pool")
}

/// Runs `work` on a thread of rayon's global pool while the caller waits (directly when the
/// caller is already one of its threads).
///
/// A mission loop is sequential with parallel parts (ray casting, fusion, all-pairs, the
/// learning update). Run from the main thread, each parallel part is handed to the pool while
/// the main thread sleeps, and between the parts the pool's idle threads spin on the cores the
/// main thread needs: on two cores, three busy threads. On a pool thread, the loop does its
/// share of every parallel part and the pool keeps one thread per core. Measured on the default
/// `strider run` (interleaved, three pairs): 445–470× real time from the main thread, 508–537×
/// on a pool thread, with identical missions.
pub fn on_worker<T: Send>(work: impl FnOnce() -> T + Send) -> T {
    // `rayon::scope` runs its closure on a pool thread (injecting it when called from outside
    // the pool) and returns once the closure and everything it spawned are done.
    rayon::scope(|_| work())
}
