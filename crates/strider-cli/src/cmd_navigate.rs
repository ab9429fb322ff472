//! `strider navigate`: `004` GP-mixture navigation with aerial-image gating (work in progress).

use std::path::PathBuf;

use anyhow::{Result, bail};
use clap::Args;

/// Arguments of `strider navigate`.
#[derive(Args, Debug)]
pub struct NavigateArgs {
    /// Built-in scenario name or scenario `.toml` file.
    #[arg(long, short = 's', default_value = "bonn-paths")]
    pub scenario: String,
    /// Seed of the simulator's noise.
    #[arg(long, default_value_t = 1)]
    pub seed: u64,
    /// Output directory (created if missing).
    #[arg(long, short = 'o', default_value = "out/navigate")]
    pub out: PathBuf,
}

/// Runs `strider navigate`.
pub fn run(args: &NavigateArgs) -> Result<()> {
    bail!("strider navigate on {} is not implemented yet", args.scenario)
}
