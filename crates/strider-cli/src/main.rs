//! # strider
//!
//! The command-line entry point. Every subcommand is a thin layer over the library crates: it
//! loads a scenario, wires the simulator to the algorithms through the robot interface, and
//! writes figures and JSON. Errors end in one line on stderr and exit code 1.

mod cmd_map;
mod cmd_scenario;
mod render;

use std::path::PathBuf;
use std::process::ExitCode;

use clap::{Args, Parser, Subcommand};

/// Strider: a robot that explores unknown terrain and learns how hard it is to traverse.
///
/// Everything runs in Strider's own 2.5D simulator on built-in scenarios (or your own scenario
/// files). Start with `strider scenario list`, look at a world with `strider scenario render`, and
/// build a map of it with `strider map build`.
#[derive(Parser, Debug)]
#[command(name = "strider", version, about, long_about, propagate_version = true)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand, Debug)]
enum Command {
    /// Built-in and file scenarios: list, render to PNG, export as editable files.
    #[command(subcommand)]
    Scenario(ScenarioCommand),
    /// The colored 2.5D elevation map.
    #[command(subcommand)]
    Map(MapCommand),
}

/// Which scenario to use: a built-in name or a path to a scenario TOML file.
#[derive(Args, Debug, Clone)]
struct ScenarioArg {
    /// Built-in scenario name (see `strider scenario list`) or path to a scenario `.toml` file.
    #[arg(long, short = 's', default_value = "courtyard-small")]
    scenario: String,
    /// Seed of the procedural world family (built-ins only; 1 is the reference world).
    #[arg(long, default_value_t = 1)]
    world_seed: u64,
}

#[derive(Subcommand, Debug)]
enum ScenarioCommand {
    /// List the built-in scenarios with a one-line description each.
    List,
    /// Render a scenario's world to PNG: color, elevation, terrain, ground-truth passability, tours.
    Render {
        /// Built-in scenario name or path to a scenario `.toml` file.
        name: String,
        /// Seed of the procedural world family (built-ins only).
        #[arg(long, default_value_t = 1)]
        world_seed: u64,
        /// Output directory (created if missing).
        #[arg(long, short = 'o')]
        out: PathBuf,
    },
    /// Write a scenario as an editable TOML file plus its PNG layers.
    Export {
        /// Built-in scenario name or path to a scenario `.toml` file.
        name: String,
        /// Seed of the procedural world family (built-ins only).
        #[arg(long, default_value_t = 1)]
        world_seed: u64,
        /// Output directory (created if missing); the TOML is `DIR/scenario.toml`.
        #[arg(long, short = 'o')]
        out: PathBuf,
    },
}

#[derive(Subcommand, Debug)]
enum MapCommand {
    /// Drive a scripted coverage path through the simulator, fuse the sensor stream into the map,
    /// and write the map layers as PNG plus `map_stats.json` (accuracy against ground truth and
    /// fusion speed).
    Build {
        #[command(flatten)]
        scenario: ScenarioArg,
        /// Seed of the simulator's noise.
        #[arg(long, default_value_t = 1)]
        seed: u64,
        /// Spacing of the coverage lanes, metres (default: 0.4 × sensor range).
        #[arg(long)]
        lane_spacing: Option<f64>,
        /// Stop driving after this many simulated seconds (default: when the path is done).
        #[arg(long)]
        time_limit: Option<f64>,
        /// Output directory (created if missing).
        #[arg(long, short = 'o')]
        out: PathBuf,
    },
}

fn main() -> ExitCode {
    let cli = Cli::parse();
    let result = match cli.command {
        Command::Scenario(ScenarioCommand::List) => cmd_scenario::list(),
        Command::Scenario(ScenarioCommand::Render {
            name,
            world_seed,
            out,
        }) => cmd_scenario::render(&name, world_seed, &out),
        Command::Scenario(ScenarioCommand::Export {
            name,
            world_seed,
            out,
        }) => cmd_scenario::export(&name, world_seed, &out),
        Command::Map(MapCommand::Build {
            scenario,
            seed,
            lane_spacing,
            time_limit,
            out,
        }) => cmd_map::build(
            &scenario.scenario,
            scenario.world_seed,
            seed,
            lane_spacing,
            time_limit,
            &out,
        ),
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            // One line: the context chain joined by ": ".
            eprintln!("error: {}", format!("{e:#}").replace('\n', " "));
            ExitCode::FAILURE
        }
    }
}
