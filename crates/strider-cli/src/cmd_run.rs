//! `strider run` and `strider replay`.

use anyhow::{Result, bail};
use strider_experiments::replay::replay as replay_log;
use strider_experiments::run::{RunRequest, run as run_mission};

use crate::args::{ReplayArgs, RunArgs};
use crate::interrupt;
use crate::progress::Bar;

/// `KEY=VALUE` pairs of `--set`, then `--gait` as `gait=NAME`.
fn parse_sets(sets: &[String], gait: Option<&str>) -> Result<Vec<(String, String)>> {
    let mut out = Vec::with_capacity(sets.len() + 1);
    for s in sets {
        let Some((k, v)) = s.split_once('=') else {
            bail!("--set {s:?}: expected KEY=VALUE, e.g. --set c_loss=7.5");
        };
        out.push((k.trim().to_string(), v.trim().to_string()));
    }
    if let Some(g) = gait {
        out.push(("gait".to_string(), g.to_string()));
    }
    Ok(out)
}

/// `strider run`: one mission and its report.
pub fn run(a: &RunArgs) -> Result<()> {
    let sets = parse_sets(&a.sets, a.gait.as_deref())?;
    let req = RunRequest {
        scenario: &a.scenario.scenario,
        world_seed: a.scenario.world_seed,
        strategy: &a.strategy,
        sets: &sets,
        seed: a.seed,
        time_limit: a.time_limit,
        out: &a.out,
        mcap: a.mcap.as_deref(),
        cancel: interrupt::winds_down(),
    };
    let bar = Bar::new("{spinner} exploring {pos}/{len} s simulated ({elapsed}) {msg}");
    let outcome = run_mission(&req, &bar)?;
    drop(bar);
    println!("{outcome}");
    match outcome.interrupted() {
        Some(i) => Err(i.into()),
        None => Ok(()),
    }
}

/// `strider replay`: a recorded log through the mission's mapping and learning.
pub fn replay(a: &ReplayArgs) -> Result<()> {
    let bar = Bar::new("{spinner} replaying {pos}/{len} s recorded ({elapsed}) {msg}");
    let cancel = interrupt::winds_down();
    let replay = replay_log((&a.log, &a.config), &a.out, cancel, &bar)?;
    drop(bar);
    println!("{replay}");
    match replay.interrupted() {
        Some(i) => Err(i.into()),
        None => Ok(()),
    }
}
