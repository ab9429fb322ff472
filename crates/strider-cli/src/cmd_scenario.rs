//! `strider scenario …` (list, render, export) and `strider map build`.

use anyhow::Result;
use strider_experiments::io::write_staged;
use strider_experiments::map_build::{MapBuildOptions, build};
use strider_experiments::scenario_figures::render as render_scenario;
use strider_experiments::trial::load;
use strider_scenario::builtin;

use crate::args::{ExportArgs, MapBuildArgs, RenderArgs};

/// Prints the built-in scenarios.
pub fn list() -> Result<()> {
    for name in builtin::names() {
        println!("{name:<18} {}", builtin::describe(name).unwrap_or_default());
    }
    Ok(())
}

/// Writes color, elevation, terrain, ground-truth passability and tour PNGs plus `render.json`.
pub fn render(a: &RenderArgs) -> Result<()> {
    let sc = render_scenario(&a.name, a.world_seed, &a.out)?;
    println!(
        "rendered {} (world seed {}) to {}: color.png elevation.png terrain.png passability.png tours.png render.json",
        sc.name,
        sc.world_seed,
        a.out.display()
    );
    Ok(())
}

/// Writes the scenario as TOML + PNG layers.
pub fn export(a: &ExportArgs) -> Result<()> {
    let sc = load(&a.name, a.world_seed)?;
    write_staged(&a.out, |dir| Ok(sc.save(dir).map(|_| ())?))?;
    println!(
        "wrote {} to {}",
        sc.name,
        a.out.join("scenario.toml").display()
    );
    Ok(())
}

/// `strider map build`: a coverage drive, the map and its score against ground truth.
pub fn map_build(a: &MapBuildArgs) -> Result<()> {
    let done = build(&MapBuildOptions {
        scenario: a.scenario.scenario.clone(),
        world_seed: a.scenario.world_seed,
        seed: a.seed,
        lane_spacing: a.lane_spacing,
        time_limit: a.time_limit,
        out: a.out.clone(),
    })?;
    println!("{done}");
    Ok(())
}
