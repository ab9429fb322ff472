//! `strider tours`: `003` energy-optimal repeated tours (work in progress).

use std::path::PathBuf;

use anyhow::{Result, bail};
use clap::Args;

/// Arguments of `strider tours`.
#[derive(Args, Debug)]
pub struct ToursArgs {
    /// Built-in scenario name or scenario `.toml` file.
    #[arg(long, short = 's', default_value = "energy-arena")]
    pub scenario: String,
    /// Seed of the simulator's noise.
    #[arg(long, default_value_t = 1)]
    pub seed: u64,
    /// Output directory (created if missing).
    #[arg(long, short = 'o', default_value = "out/tours")]
    pub out: PathBuf,
}

/// Runs `strider tours`.
pub fn run(args: &ToursArgs) -> Result<()> {
    bail!("strider tours on {} is not implemented yet", args.scenario)
}
