//! What every `strider run` strategy path shares: the request, its checks, the output
//! directory and progress bar, and the latency summaries of the reports.

use std::fs;
use std::path::Path;

use anyhow::{Context, Result, bail};

/// What `strider run` was asked to do.
#[derive(Clone, Copy, Debug)]
pub struct RunRequest<'a> {
    /// Scenario name or file.
    pub scenario: &'a str,
    /// World seed of a built-in scenario.
    pub world_seed: u64,
    /// Strategy name.
    pub strategy: &'a str,
    /// Parameter overrides (key, value), in order.
    pub sets: &'a [(String, String)],
    /// Mission and simulator seed.
    pub seed: u64,
    /// Time limit override, simulated seconds.
    pub time_limit: Option<f64>,
    /// Output directory.
    pub out: &'a Path,
    /// MCAP recording file.
    pub mcap: Option<&'a Path>,
}

/// (median, max) of `v` (the upper median for an even count; (0, 0) when empty).
pub(crate) fn median_max(v: &[f64]) -> (f64, f64) {
    if v.is_empty() {
        return (0.0, 0.0);
    }
    let mut s = v.to_vec();
    s.sort_by(f64::total_cmp);
    (s[s.len() / 2], s[s.len() - 1])
}

/// Validates a `--time-limit` override.
pub(crate) fn checked_time_limit(t: f64) -> Result<f64> {
    if !(t.is_finite() && t > 0.0) {
        bail!("--time-limit must be a positive number of seconds, got {t}");
    }
    Ok(t)
}

/// Creates the output directory and the progress bar of a mission of `limit_s` simulated
/// seconds (on stderr, hidden when stderr is not a terminal).
pub(crate) fn start_run(out: &Path, limit_s: f64) -> Result<indicatif::ProgressBar> {
    fs::create_dir_all(out)
        .with_context(|| format!("{}: cannot create directory", out.display()))?;
    let bar = indicatif::ProgressBar::new(limit_s.max(1.0) as u64);
    bar.set_style(
        indicatif::ProgressStyle::with_template(
            "{spinner} exploring {pos}/{len} s simulated ({elapsed}) {msg}",
        )
        .unwrap_or_else(|_| indicatif::ProgressStyle::default_spinner()),
    );
    Ok(bar)
}
