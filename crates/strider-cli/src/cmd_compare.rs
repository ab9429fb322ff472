//! `strider bench compare`: the registry's strategies on the same worlds, the table no paper
//! has (see [`strider_cli::compare`]).

use anyhow::{Result, bail};
use std::path::Path;

/// `strider bench compare`: the registry's strategies `names` on the same worlds (see
/// [`strider_cli::compare`]).
pub fn compare(
    o: &strider_cli::compare::CompareOptions,
    names: &[String],
    out: &Path,
) -> Result<()> {
    use strider_cli::compare::{self, Entrant};
    if let Some(t) = o.time_limit {
        crate::run_support::checked_time_limit(t)?;
    }
    if o.jobs > 256 || o.trials > 100_000 {
        bail!("--jobs must be at most 256 and --trials at most 100000");
    }
    let entrants = names
        .iter()
        .map(|n| Entrant::registered(n))
        .collect::<Result<Vec<_>>>()?;
    let total = o.scenarios.len() * entrants.len() * o.trials;
    let bar = indicatif::ProgressBar::new(total as u64);
    bar.set_style(
        indicatif::ProgressStyle::with_template(
            "{spinner} compare: {pos}/{len} trials ({elapsed}, eta {eta})",
        )
        .unwrap_or_else(|_| indicatif::ProgressStyle::default_spinner()),
    );
    let wall = std::time::Instant::now();
    let result = compare::run(o, &entrants, || bar.inc(1))?;
    bar.finish_and_clear();
    let command = format!(
        "strider bench compare --scenarios {} --strategies {} --trials {} --world-seeds {}{}",
        o.scenarios.join(","),
        names.join(","),
        o.trials,
        o.world_seeds,
        o.time_limit
            .map_or_else(String::new, |t| format!(" --time-limit {t}"))
    );
    compare::write(out, &result, &command)?;
    print!("{}", compare::markdown(&result, &command));
    println!(
        "{} trials in {:.0} s wall -> {}",
        result.trials.len(),
        wall.elapsed().as_secs_f64(),
        out.join("compare.md").display()
    );
    Ok(())
}
