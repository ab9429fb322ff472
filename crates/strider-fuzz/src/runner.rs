//! The fuzz loop: replay the regressions and the seeds, then mutate for a number of cases or a
//! time budget, and report every failure with the file that holds its input.

use std::fs;
use std::panic::{self, AssertUnwindSafe};
use std::path::{Path, PathBuf};
use std::sync::Mutex;
use std::time::{Duration, Instant};

use rand::rngs::ChaCha8Rng;
use rand::{RngExt, SeedableRng};

use crate::alloc::CappedAlloc;
use crate::corpus;
use crate::input::FuzzInput;
use crate::watchdog::Watchdog;

/// What a target's check says of one input.
#[derive(Debug)]
pub enum Outcome {
    /// The input was accepted and every invariant held.
    Accepted,
    /// The input was refused with this error message.
    Rejected(String),
}

/// How long and how hard to fuzz one target; see the crate docs for the environment variables.
#[derive(Clone, Debug)]
pub struct Config {
    /// Target name: the folder of its regressions and failures.
    pub name: String,
    /// Mutated cases in the deterministic (default) mode.
    pub cases: usize,
    /// Time budget, seconds (`FUZZ_SECONDS`); replaces `cases` when set.
    pub seconds: Option<f64>,
    /// Seed of the mutation sequence (`FUZZ_SEED`).
    pub seed: u64,
    /// Longest a case may run before it counts as a hang (`FUZZ_CASE_SECONDS`).
    pub case_limit: Duration,
    /// Heap cap, MiB (`FUZZ_MEMORY_MB`).
    pub memory_mb: usize,
    manifest_dir: PathBuf,
    tmp_dir: PathBuf,
}

/// The [`Config`] of target `$name` from the environment, for a test of this crate.
#[macro_export]
macro_rules! config {
    ($name:expr, $cases:expr) => {
        $crate::Config::from_env(
            $name,
            $cases,
            env!("CARGO_MANIFEST_DIR"),
            env!("CARGO_TARGET_TMPDIR"),
        )
    };
}

impl Config {
    /// Reads `FUZZ_SECONDS`, `FUZZ_SEED`, `FUZZ_CASE_SECONDS` and `FUZZ_MEMORY_MB`. Without
    /// `FUZZ_SECONDS` the run is `cases` cases from seed 0; with it, the seed defaults to the
    /// clock so that each long run explores anew (it is printed, to rerun a run exactly).
    pub fn from_env(name: &str, cases: usize, manifest_dir: &str, tmp_dir: &str) -> Self {
        let num = |k: &str| {
            std::env::var(k)
                .ok()
                .and_then(|v| v.trim().parse::<f64>().ok())
        };
        let seconds = num("FUZZ_SECONDS").filter(|s| s.is_finite() && *s > 0.0);
        let clock = || {
            std::time::SystemTime::now()
                .duration_since(std::time::UNIX_EPOCH)
                .map_or(0, |d| d.as_nanos() as u64)
        };
        let seed = match std::env::var("FUZZ_SEED").ok().and_then(|v| v.parse().ok()) {
            Some(s) => s,
            None if seconds.is_some() => clock(),
            None => 0,
        };
        let case_limit = num("FUZZ_CASE_SECONDS")
            .filter(|s| s.is_finite() && *s > 0.0)
            .unwrap_or(30.0);
        Self {
            name: name.to_string(),
            cases,
            seconds,
            seed,
            case_limit: Duration::from_secs_f64(case_limit),
            memory_mb: num("FUZZ_MEMORY_MB")
                .filter(|m| m.is_finite() && *m >= 64.0)
                .map_or(CappedAlloc::DEFAULT_MB, |m| m as usize),
            manifest_dir: PathBuf::from(manifest_dir),
            tmp_dir: PathBuf::from(tmp_dir),
        }
    }
}

/// Counts of one run.
#[derive(Debug, Default)]
struct Tally {
    cases: usize,
    accepted: usize,
    rejected: usize,
    failures: Vec<String>,
}

/// Accepted mutants kept as further starting points: a cheap stand-in for coverage feedback that
/// lets mutations pile up on inputs that still parse.
const POOL_SIZE: usize = 64;

static PANIC_MESSAGE: Mutex<String> = Mutex::new(String::new());

/// Fuzzes one target: `seeds` are valid inputs, `dictionary` the format's keywords, `check`
/// parses an input and checks the invariants of what it accepted. Panics at the end, listing
/// the failures, if there were any.
pub fn fuzz<I: FuzzInput>(
    cfg: Config,
    alloc: &CappedAlloc,
    seeds: Vec<I>,
    dictionary: &[&str],
    check: impl Fn(&I) -> Result<Outcome, String>,
) {
    assert!(!seeds.is_empty(), "fuzz {}: no seed inputs", cfg.name);
    alloc.set_cap_mb(cfg.memory_mb);
    let dir = corpus::work_dir(&cfg.tmp_dir, &cfg.name);
    let current = dir.join("current");
    eprintln!(
        "fuzz {}: the case in progress is kept in {} (an abort leaves it there)",
        cfg.name,
        current.display()
    );
    let watchdog = Watchdog::start(&cfg.name, cfg.case_limit, current.display().to_string());
    panic::set_hook(Box::new(|info| {
        if let Ok(mut m) = PANIC_MESSAGE.lock() {
            *m = info.to_string().replace('\n', " ");
        }
    }));
    let mut run = Run {
        input: std::marker::PhantomData,
        tally: Tally::default(),
        dir: &dir,
        current: &current,
        watchdog: &watchdog,
        check: &check,
    };
    for (name, bytes) in corpus::regressions(&cfg.manifest_dir, &cfg.name) {
        match I::from_bytes(&bytes) {
            Some(input) => {
                run.case(&input, &format!("regression {name}"));
            }
            None => run
                .tally
                .failures
                .push(format!("regression {name}: not a stored input")),
        }
    }
    for (k, seed) in seeds.iter().enumerate() {
        run.case(seed, &format!("seed {k}"));
    }
    let started = Instant::now();
    mutate_until_done(&cfg, &mut run, &seeds, dictionary, started);
    let _ = panic::take_hook();
    report(&cfg, run.tally, started.elapsed());
}

fn mutate_until_done<I: FuzzInput>(
    cfg: &Config,
    run: &mut Run<'_, I, impl Fn(&I) -> Result<Outcome, String>>,
    seeds: &[I],
    dictionary: &[&str],
    started: Instant,
) {
    let mut rng = ChaCha8Rng::seed_from_u64(cfg.seed);
    let mut pool: Vec<I> = Vec::new();
    let mut k = 0usize;
    loop {
        let done = match cfg.seconds {
            Some(s) => started.elapsed().as_secs_f64() >= s,
            None => k >= cfg.cases,
        };
        if done {
            break;
        }
        let from_pool = !pool.is_empty() && rng.random_range(0..3) == 0;
        let mut input = if from_pool {
            pool[rng.random_range(0..pool.len())].clone()
        } else {
            seeds[rng.random_range(0..seeds.len())].clone()
        };
        let n = 1 + rng.random_range(0..4usize).min(rng.random_range(0..4usize));
        for _ in 0..n {
            input.mutate(&mut rng, dictionary);
        }
        if run.case(&input, &format!("case {k}")) {
            if pool.len() < POOL_SIZE {
                pool.push(input);
            } else {
                let slot = rng.random_range(0..POOL_SIZE);
                pool[slot] = input;
            }
        }
        k += 1;
    }
}

struct Run<'a, I, C> {
    input: std::marker::PhantomData<fn(&I)>,
    tally: Tally,
    dir: &'a Path,
    current: &'a Path,
    watchdog: &'a Watchdog,
    check: &'a C,
}

impl<I: FuzzInput, C: Fn(&I) -> Result<Outcome, String>> Run<'_, I, C> {
    /// Runs one case; true when the input was accepted.
    fn case(&mut self, input: &I, label: &str) -> bool {
        let bytes = input.to_bytes();
        let _ = fs::write(self.current, &bytes);
        self.tally.cases += 1;
        self.watchdog.begin();
        let result = panic::catch_unwind(AssertUnwindSafe(|| (self.check)(input)));
        self.watchdog.end();
        let failure = match result {
            Ok(Ok(Outcome::Accepted)) => {
                self.tally.accepted += 1;
                return true;
            }
            Ok(Ok(Outcome::Rejected(msg))) => {
                self.tally.rejected += 1;
                unclean_message(&msg)
            }
            Ok(Err(broken)) => Some(format!("invariant broken: {broken}")),
            Err(_) => Some(format!(
                "panic: {}",
                PANIC_MESSAGE.lock().map(|m| m.clone()).unwrap_or_default()
            )),
        };
        if let Some(what) = failure {
            let path = corpus::save_failure(self.dir, &bytes);
            self.tally
                .failures
                .push(format!("{label}: {what} (input: {})", path.display()));
        }
        false
    }
}

/// Why an error message is not one clean line, if it is not: users read these.
fn unclean_message(msg: &str) -> Option<String> {
    if msg.trim().is_empty() {
        return Some("rejected with an empty message".into());
    }
    if msg.chars().any(|c| c.is_control() && c != '\t') {
        return Some(format!(
            "rejected with a message holding control characters: {msg:?}"
        ));
    }
    None
}

fn report(cfg: &Config, t: Tally, elapsed: Duration) {
    eprintln!(
        "fuzz {}: {} cases ({} accepted, {} rejected) in {:.1} s from seed {}, {} failures",
        cfg.name,
        t.cases,
        t.accepted,
        t.rejected,
        elapsed.as_secs_f64(),
        cfg.seed,
        t.failures.len()
    );
    if !t.failures.is_empty() {
        let shown: Vec<&str> = t.failures.iter().take(20).map(String::as_str).collect();
        panic!(
            "fuzz {}: {} failures (seed {}):\n{}",
            cfg.name,
            t.failures.len(),
            cfg.seed,
            shown.join("\n")
        );
    }
}

#[cfg(test)]
mod tests {
    use super::unclean_message;

    #[test]
    fn messages_must_be_one_plain_line() {
        assert!(unclean_message("line 3: DIMENSION 0 must be ≥ 1").is_none());
        assert!(unclean_message("a\nb").is_some());
        assert!(unclean_message("\u{1b}[31merror").is_some());
        assert!(unclean_message("  ").is_some());
    }
}
