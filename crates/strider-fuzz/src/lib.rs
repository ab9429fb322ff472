//! # strider-fuzz
//!
//! Structure-aware fuzzing of Strider's input surfaces. The stable Rust toolchain has no
//! coverage-guided fuzzer (`cargo fuzz` needs nightly's `-Zsanitizer`), so the targets mutate
//! valid inputs with operators that know the formats' shapes — numbers replaced by extremes,
//! keywords swapped, lines deleted, duplicated or moved, binary fields overwritten with boundary
//! integers, truncation, splicing — which reaches the parsers' validation paths far more often
//! than random bytes would.
//!
//! Each target is one test in `tests/`:
//! - `cargo test -p strider-fuzz` runs every target for a fixed number of cases from a fixed
//!   seed (deterministic, a few seconds each), after replaying its regression inputs;
//! - `FUZZ_SECONDS=600 cargo test --release -p strider-fuzz --test tsplib` runs one target for
//!   ten minutes from seed `FUZZ_SEED` (default: the clock, printed at the start).
//!
//! A case fails when the target panics, when its check returns an error (a broken invariant on
//! an accepted input), when it runs longer than `FUZZ_CASE_SECONDS` (a hang: the process aborts)
//! or when the process holds more than `FUZZ_MEMORY_MB` of heap (the [`CappedAlloc`] installed by
//! the target refuses the allocation and the process aborts). The input of every failure is
//! written under `target/fuzz/<target>/`; the case being run is always in
//! `target/fuzz/<target>/current`, so an abort leaves it behind. Keep a failing input by copying
//! it into `regressions/<target>/`: every test run replays that folder.

mod alloc;
mod corpus;
mod input;
mod mutate;
mod runner;
mod watchdog;

pub use alloc::CappedAlloc;
pub use input::{Binary, Bundle, FuzzInput, Text};
pub use runner::{Config, Outcome, fuzz};
