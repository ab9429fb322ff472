//! # strider
//!
//! The command-line entry point. Every subcommand is a thin layer over the library crates: it
//! loads a scenario, wires the simulator to the algorithms through the robot interface, and
//! writes figures and JSON. Errors end in one line on stderr and exit code 1.

mod cmd_bench;
mod cmd_compare;
mod cmd_gp;
mod cmd_gtsp;
mod cmd_learn;
mod cmd_map;
mod cmd_navigate;
mod cmd_replay;
mod cmd_run;
mod cmd_run_escape;
mod cmd_run_rbcm;
mod cmd_scenario;
mod cmd_strategies;
mod cmd_tours;
mod render;
mod run_support;

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
    /// Run an exploration mission: the robot explores a scenario in the simulator with the
    /// strategy chosen, learns traversal costs as it goes, and a report is written.
    Run {
        #[command(flatten)]
        scenario: ScenarioArg,
        /// Exploration strategy (`strider strategies` lists them with their papers and
        /// parameters): gtsp, greedy, spatial-only, rbcm-greedy, escape, rigid.
        #[arg(long, default_value = "gtsp")]
        strategy: String,
        /// Set a strategy parameter, overriding the scenario's `[strategy.<name>]` section
        /// (repeatable), e.g. `--set c_loss=7.5`.
        #[arg(long = "set", value_name = "KEY=VALUE")]
        sets: Vec<String>,
        /// Shorthand for `--set gait=NAME` (the gait rbcm-greedy walks).
        #[arg(long)]
        gait: Option<String>,
        /// Seed of the mission and the simulator's noise.
        #[arg(long, default_value_t = 1)]
        seed: u64,
        /// Mission time limit in simulated seconds (default: the scenario's).
        #[arg(long)]
        time_limit: Option<f64>,
        /// Output directory (created if missing).
        #[arg(long, short = 'o', default_value = "out/run")]
        out: PathBuf,
        /// Also record the mission to this MCAP file: the sensor stream as ROS 2 messages
        /// (replayable with `strider replay`) and the map, costs, goals, tour and path with
        /// Foxglove's schemas (open it in Foxglove).
        #[arg(long, value_name = "FILE")]
        mcap: Option<PathBuf>,
    },
    /// List every exploration strategy with its paper, its parameters, their defaults and
    /// units.
    Strategies,
    /// Map and learn from a recorded ROS 2 log (MCAP: sensor_msgs/PointCloud2 with x, y, z and
    /// rgb, nav_msgs/Odometry or tf2_msgs/TFMessage poses, the gait) with the mission's own
    /// mapping and learning code; writes the report of `strider run` without the tours.
    Replay {
        /// The MCAP file.
        log: PathBuf,
        /// Replay configuration (TOML): topics, frames, gait source and the robot's
        /// parameters; see `strider_log::config`. For a log of `strider run --mcap` a
        /// `[mission]` table naming the scenario suffices.
        #[arg(long)]
        config: PathBuf,
        /// Output directory (created if missing).
        #[arg(long, short = 'o', default_value = "out/replay")]
        out: PathBuf,
    },
    /// Built-in and file scenarios: list, render to PNG, export as editable files.
    #[command(subcommand)]
    Scenario(ScenarioCommand),
    /// The colored 2.5D elevation map.
    #[command(subcommand)]
    Map(MapCommand),
    /// The Generalized TSP solver that orders exploration goals, on GTSPLIB/TSPLIB files.
    #[command(subcommand)]
    Gtsp(GtspCommand),
    /// Exact Gaussian-process regression (the traversal-cost model) on CSV files.
    #[command(subcommand)]
    Gp(GpCommand),
    /// `003`: energy-optimal repeated tours on `energy-arena` — learn a zero-mean GP map of energy
    /// per metre while driving the same waypoints again and again, re-planning the tour each time.
    Tours(cmd_tours::ToursArgs),
    /// `004`: repeated start–goal navigation on `bonn-paths` with a GP mixture model (mean-shift
    /// gating, optionally aerial-image gating classifiers) and a softplus lower-confidence-bound cost.
    Navigate(cmd_navigate::NavigateArgs),
    /// Mission-level benchmarks that reproduce the papers' tables.
    #[command(subcommand)]
    Bench(BenchCommand),
    /// Traversal-cost learners (GP, RBCM, IGMN, regression tree) and their benchmarks.
    #[command(subcommand)]
    Learn(LearnCommand),
}

#[derive(Subcommand, Debug)]
enum LearnCommand {
    /// Learner benchmarks: `000` §V-A (incremental stream on lab-track: learning and inference
    /// time per step, RMSE and predictive std over n, for RBCM with four kernels, the full GP,
    /// IGMN and a regression tree; DIR/learn_bench.json and .png) and thesis C1 Table I (cost of
    /// transport learned on one pass of cot-track and predicted from an aerial view, per learner ×
    /// descriptor; DIR/c1_table.md and .json).
    Bench(cmd_learn::LearnBenchArgs),
    /// Thesis C4 §5.3 (Table 5): the GP force predictor on four outdoor terrains with the 8-bin
    /// histogram, presented in three orders; prints the test entropies and writes
    /// DIR/c4_vegetation.md and .json.
    C4Vegetation {
        /// Output directory (created if missing).
        #[arg(long, short = 'o', default_value = "out/c4-vegetation")]
        out: PathBuf,
    },
}

#[derive(Subcommand, Debug)]
enum BenchCommand {
    /// Reproduce `001` Table 5: small tours 1 and 2 in three navigation modes, small
    /// exploration GTSP vs greedy, large tour and exploration proposed vs spatial-only; writes
    /// DIR/table5.json and DIR/table5.md with our figures beside the published ones.
    Table5 {
        /// Trials per row on courtyard-small (mission seeds 1..=N).
        #[arg(long, default_value_t = 25)]
        trials: usize,
        /// Trials per row on courtyard-large (default: --trials).
        #[arg(long)]
        large_trials: Option<usize>,
        /// Random worlds the trials cycle through (world seeds 1..=K).
        #[arg(long, default_value_t = 5)]
        world_seeds: u64,
        /// Trials run in parallel (default: the number of CPUs).
        #[arg(long)]
        jobs: Option<usize>,
        /// Override the scenarios' mission time limit, simulated seconds (for quick runs).
        #[arg(long)]
        time_limit: Option<f64>,
        /// Also record each trial's mission as MCAP (`strider run --mcap`) into this directory.
        #[arg(long)]
        mcap_dir: Option<PathBuf>,
        /// Output directory (created if missing).
        #[arg(long, short = 'o', default_value = "out/table5")]
        out: PathBuf,
    },
    /// Compare strategies from different papers on the same worlds: exploration time, observed
    /// cells, the learned cost's error against the terrain table, and the benchmark-tour time
    /// with learned navigation, with Mann-Whitney U between each pair; writes DIR/compare.json
    /// and DIR/compare.md.
    Compare {
        /// Scenarios, comma-separated (built-in names or files).
        #[arg(
            long,
            value_delimiter = ',',
            default_value = "courtyard-small,lab-track"
        )]
        scenarios: Vec<String>,
        /// Strategies, comma-separated (`strider strategies` lists them).
        #[arg(
            long,
            value_delimiter = ',',
            default_value = "gtsp,greedy,spatial-only,rbcm-greedy"
        )]
        strategies: Vec<String>,
        /// Trials per scenario and strategy (mission seeds 1..=N).
        #[arg(long, default_value_t = 5)]
        trials: usize,
        /// Random worlds the trials cycle through (world seeds 1..=K).
        #[arg(long, default_value_t = 5)]
        world_seeds: u64,
        /// Trials run in parallel (default: the number of CPUs).
        #[arg(long)]
        jobs: Option<usize>,
        /// Override the scenarios' mission time limit, simulated seconds.
        #[arg(long)]
        time_limit: Option<f64>,
        /// Output directory (created if missing).
        #[arg(long, short = 'o', default_value = "out/compare")]
        out: PathBuf,
    },
}

#[derive(Subcommand, Debug)]
enum GpCommand {
    /// Fit a GP with fixed hyperparameters to a training CSV (header; features then y per row)
    /// and write the predictive mean and latent variance (without noise) for every row of a
    /// query CSV (header; features) as `mean,variance`.
    Predict {
        /// Training CSV: a header line, then the features and y on each row.
        #[arg(long)]
        train: PathBuf,
        /// Query CSV: a header line, then the features on each row.
        #[arg(long)]
        query: PathBuf,
        /// Kernel: se (squared exponential), exp, matern32 or matern52.
        #[arg(long, default_value = "se")]
        kernel: String,
        /// Isotropic lengthscale l.
        #[arg(long, default_value_t = 0.4)]
        lengthscale: f64,
        /// Signal variance σ_s².
        #[arg(long, default_value_t = 1.0)]
        signal_variance: f64,
        /// Noise variance σ_n² (σ_ε = 0.5).
        #[arg(long, default_value_t = 0.25)]
        noise_variance: f64,
        /// Constant prior mean.
        #[arg(long, default_value_t = 0.0, allow_negative_numbers = true)]
        prior_mean: f64,
        /// Output CSV with the header `mean,variance`, one row per query, full precision.
        #[arg(long, short = 'o')]
        out: PathBuf,
        /// Also write {"n_train", "n_query", "fit_s", "predict_s"} (measured in-process) here.
        #[arg(long)]
        timing_json: Option<PathBuf>,
    },
}

#[derive(Subcommand, Debug)]
enum GtspCommand {
    /// Solve one GTSPLIB (.gtsp) or TSPLIB (.tsp/.atsp) instance: prints the cost and the tour
    /// (1-based vertex ids as in the file, one per set, in visiting order).
    Solve {
        /// The instance file.
        file: PathBuf,
        /// Wall-clock limit, seconds.
        #[arg(long, default_value_t = 60.0)]
        time_limit: f64,
        /// Random seed (same seed and limits: same tour, unless the time limit cuts the search).
        #[arg(long, default_value_t = 1)]
        seed: u64,
        /// Effort preset: fast, default or slow.
        #[arg(long, default_value = "default")]
        mode: String,
        /// Print exactly one JSON object {"cost", "tour", "time_s"}.
        #[arg(long)]
        json: bool,
    },
    /// Solve every instance listed in DIR/best_known.csv (or a TSPLIB DIR/optima.csv) and print
    /// per-instance cost, gap to the best-known value and time, then a summary line.
    Bench {
        /// Folder with the instances and best_known.csv / optima.csv.
        dir: PathBuf,
        /// Wall-clock limit per run, seconds.
        #[arg(long, default_value_t = 60.0)]
        time_limit: f64,
        /// Runs per instance (seeds seed, seed+1, …).
        #[arg(long, default_value_t = 1)]
        runs: usize,
        /// First seed.
        #[arg(long, default_value_t = 1)]
        seed: u64,
        /// Effort preset: fast, default or slow.
        #[arg(long, default_value = "default")]
        mode: String,
        /// Only instances with at least this many sets.
        #[arg(long, default_value_t = 0)]
        min_sets: usize,
        /// Only instances with at most this many sets.
        #[arg(long, default_value_t = usize::MAX)]
        max_sets: usize,
        /// Also write per-instance results and the summary as JSON to this file.
        #[arg(long)]
        json: Option<PathBuf>,
    },
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

/// `KEY=VALUE` pairs of `--set`, then `--gait` as `gait=NAME`.
fn parse_sets(sets: &[String], gait: Option<&str>) -> anyhow::Result<Vec<(String, String)>> {
    let mut out = Vec::with_capacity(sets.len() + 1);
    for s in sets {
        let Some((k, v)) = s.split_once('=') else {
            anyhow::bail!("--set {s:?}: expected KEY=VALUE, e.g. --set c_loss=7.5");
        };
        out.push((k.trim().to_string(), v.trim().to_string()));
    }
    if let Some(g) = gait {
        out.push(("gait".to_string(), g.to_string()));
    }
    Ok(out)
}

fn main() -> ExitCode {
    let cli = Cli::parse();
    let result = match cli.command {
        Command::Run {
            scenario,
            strategy,
            seed,
            time_limit,
            out,
            mcap,
            gait,
            sets,
        } => parse_sets(&sets, gait.as_deref()).and_then(|sets| {
            cmd_run::run(&run_support::RunRequest {
                scenario: &scenario.scenario,
                world_seed: scenario.world_seed,
                strategy: &strategy,
                sets: &sets,
                seed,
                time_limit,
                out: &out,
                mcap: mcap.as_deref(),
            })
        }),
        Command::Strategies => cmd_strategies::list(),
        Command::Replay { log, config, out } => cmd_replay::run(&log, &config, &out),
        Command::Tours(args) => cmd_tours::run(&args),
        Command::Navigate(args) => cmd_navigate::run(&args),
        Command::Learn(LearnCommand::Bench(args)) => cmd_learn::bench(&args),
        Command::Learn(LearnCommand::C4Vegetation { out }) => cmd_run_escape::vegetation(&out),
        Command::Bench(BenchCommand::Table5 {
            trials,
            large_trials,
            world_seeds,
            jobs,
            time_limit,
            mcap_dir,
            out,
        }) => cmd_bench::table5(
            &cmd_bench::Table5Options {
                trials,
                large_trials: large_trials.unwrap_or(trials),
                world_seeds,
                jobs: jobs
                    .unwrap_or_else(|| std::thread::available_parallelism().map_or(1, |n| n.get())),
                time_limit,
                mcap_dir,
            },
            &out,
        ),
        Command::Bench(BenchCommand::Compare {
            scenarios,
            strategies,
            trials,
            world_seeds,
            jobs,
            time_limit,
            out,
        }) => cmd_compare::compare(
            &strider_cli::compare::CompareOptions {
                scenarios,
                trials,
                world_seeds,
                jobs: jobs
                    .unwrap_or_else(|| std::thread::available_parallelism().map_or(1, |n| n.get())),
                time_limit,
            },
            &strategies,
            &out,
        ),
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
        Command::Gtsp(GtspCommand::Solve {
            file,
            time_limit,
            seed,
            mode,
            json,
        }) => cmd_gtsp::parse_mode(&mode)
            .and_then(|m| cmd_gtsp::solve_file(&file, time_limit, seed, m, json)),
        Command::Gtsp(GtspCommand::Bench {
            dir,
            time_limit,
            runs,
            seed,
            mode,
            min_sets,
            max_sets,
            json,
        }) => cmd_gtsp::parse_mode(&mode).and_then(|mode| {
            let o = cmd_gtsp::BenchOptions {
                time_limit,
                runs,
                seed,
                mode,
                min_sets,
                max_sets,
            };
            cmd_gtsp::bench(&dir, &o, json.as_deref())
        }),
        Command::Gp(GpCommand::Predict {
            train,
            query,
            kernel,
            lengthscale,
            signal_variance,
            noise_variance,
            prior_mean,
            out,
            timing_json,
        }) => cmd_gp::predict(&cmd_gp::PredictOptions {
            train: &train,
            query: &query,
            kernel: &kernel,
            lengthscale,
            signal_variance,
            noise_variance,
            prior_mean,
            out: &out,
            timing_json: timing_json.as_deref(),
        }),
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {}", one_line(&e));
            ExitCode::FAILURE
        }
    }
}

/// The error and its causes on one line, joined by ": ". A cause whose text the line already
/// holds is skipped (library errors often embed their source in their own message).
fn one_line(e: &anyhow::Error) -> String {
    let mut line = e.to_string();
    for cause in e.chain().skip(1) {
        let c = cause.to_string();
        if !line.contains(&c) {
            line.push_str(": ");
            line.push_str(&c);
        }
    }
    line.replace('\n', " ")
}

#[cfg(test)]
mod tests {
    use super::one_line;
    use anyhow::Context;

    #[test]
    fn causes_already_in_the_message_are_not_repeated() {
        let io = std::io::Error::new(std::io::ErrorKind::NotFound, "no such file");
        let e = anyhow::Error::new(io).context("cannot read a.gtsp: no such file");
        assert_eq!(one_line(&e), "cannot read a.gtsp: no such file");
        let r: Result<(), _> = Err(anyhow::anyhow!("line 3: bad value")).context("a.gtsp");
        assert_eq!(one_line(&r.unwrap_err()), "a.gtsp: line 3: bad value");
    }
}
