//! `strider run` and `strider replay`.

use std::net::SocketAddr;

use anyhow::{Result, bail};
use strider_experiments::live::{LiveServer, Watch};
use strider_experiments::replay::replay as replay_log;
use strider_experiments::run::{RunRequest, run as run_mission};

use crate::args::{ReplayArgs, RunArgs};
use crate::interrupt;
use crate::progress::Bar;

/// `KEY=VALUE` pairs of `--set`, then `--gait` as `gait=NAME`.
pub(crate) fn parse_sets(sets: &[String], gait: Option<&str>) -> Result<Vec<(String, String)>> {
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

/// The live view of `--live`, if asked for, and where to open it. It serves until dropped:
/// when the command ends, also after Ctrl-C (the mission winds down, then the server stops).
fn live_view(addr: Option<SocketAddr>) -> Result<Option<LiveServer>> {
    let Some(addr) = addr else {
        return Ok(None);
    };
    let server = LiveServer::start(addr)?;
    eprintln!(
        "live view on {0}: in Foxglove, Open connection → Foxglove WebSocket → {0}",
        server.url()
    );
    Ok(Some(server))
}

/// `strider run`: one mission and its report.
pub fn run(a: &RunArgs) -> Result<()> {
    let sets = parse_sets(&a.sets, a.gait.as_deref())?;
    // Ctrl-C winds down from the moment the live view is announced.
    let cancel = interrupt::winds_down();
    let live = live_view(a.live)?;
    let req = RunRequest {
        scenario: &a.scenario.scenario,
        world_seed: a.scenario.world_seed,
        strategy: &a.strategy,
        sets: &sets,
        seed: a.seed,
        time_limit: a.time_limit,
        out: &a.out,
        mcap: a.mcap.as_deref(),
        live: live.as_ref(),
        rate: a.rate,
        cancel,
    };
    let bar = Bar::new("{spinner} exploring {pos}/{len} s simulated ({elapsed}) {msg}");
    let outcome = run_mission(&req, &bar)?;
    drop(bar);
    if let Some(l) = live {
        l.stop();
    }
    println!("{outcome}");
    match outcome.interrupted() {
        Some(i) => Err(i.into()),
        None => Ok(()),
    }
}

/// `strider replay`: a recorded log through the mission's mapping and learning.
pub fn replay(a: &ReplayArgs) -> Result<()> {
    let cancel = interrupt::winds_down();
    let live = live_view(a.live)?;
    let watch = Watch {
        mcap: None,
        live: live.as_ref(),
        rate: a.rate,
        cancel,
    };
    let bar = Bar::new("{spinner} replaying {pos}/{len} s recorded ({elapsed}) {msg}");
    let replay = replay_log((&a.log, &a.config), &a.out, watch, &bar)?;
    drop(bar);
    if let Some(l) = live {
        l.stop();
    }
    println!("{replay}");
    match replay.interrupted() {
        Some(i) => Err(i.into()),
        None => Ok(()),
    }
}
