//! `strider strategies`: every exploration strategy of the registry with its paper, what it
//! needs of the robot, and its parameters with their defaults and units.

use anyhow::Result;
use std::io::Write;
use strider_explore::registry::{STRATEGIES, StrategyInfo};

/// Prints the registry (a closed pipe, e.g. `| head`, ends the listing quietly).
pub fn list() -> Result<()> {
    let mut out = std::io::stdout().lock();
    for s in STRATEGIES {
        match write_strategy(&mut out, s) {
            Err(e) if e.kind() == std::io::ErrorKind::BrokenPipe => return Ok(()),
            r => r?,
        }
    }
    Ok(())
}

fn write_strategy(out: &mut impl Write, s: &StrategyInfo) -> std::io::Result<()> {
    writeln!(out, "{}", s.name)?;
    writeln!(out, "  {}", s.summary)?;
    writeln!(out, "  paper [{}]: {}", s.key, s.paper)?;
    if s.needs_bumper {
        writeln!(out, "  needs: a haptic bumper")?;
    }
    writeln!(
        out,
        "  parameters ([strategy.{}] in a scenario, or --set key=value):",
        s.name
    )?;
    let rows = s.params();
    let w = rows.iter().map(|(d, _)| d.key.len()).max().unwrap_or(0);
    let wv = rows.iter().map(|(_, v)| v.len()).max().unwrap_or(0).min(24);
    for (d, default) in rows {
        writeln!(
            out,
            "    {:<w$}  {:<wv$} {:<6} {}",
            d.key, default, d.unit, d.doc
        )?;
    }
    writeln!(out)
}
