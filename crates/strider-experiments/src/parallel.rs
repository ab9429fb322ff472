//! Threads for experiments: the pool trials run on side by side, and running one mission on a
//! pool thread.

use anyhow::{Context, Result};

/// The number of CPUs (1 when unknown): the default of every `--jobs`.
pub fn available_jobs() -> usize {
    std::thread::available_parallelism().map_or(1, |n| n.get())
}

/// A pool of `jobs` threads (at least one) for trials run side by side.
pub fn pool(jobs: usize) -> Result<rayon::ThreadPool> {
    rayon::ThreadPoolBuilder::new()
        .num_threads(jobs.max(1))
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
