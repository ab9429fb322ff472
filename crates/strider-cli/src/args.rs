//! The command line: every subcommand, flag and default of `strider`.

use std::net::SocketAddr;
use std::path::PathBuf;

use clap::{Args, Parser, Subcommand};
use strider_experiments::pace::Rate;

use crate::flags;

/// Strider: a robot that explores unknown terrain and learns how hard it is to traverse.
///
/// Everything runs in Strider's own 2.5D simulator on built-in scenarios (or your own scenario
/// files). Start with `strider scenario list`, look at a world with `strider scenario render`, and
/// build a map of it with `strider map build`.
#[derive(Parser, Debug)]
#[command(name = "strider", version, about, long_about, propagate_version = true)]
pub struct Cli {
    #[command(subcommand)]
    pub command: Command,
}

#[derive(Subcommand, Debug)]
pub enum Command {
    /// Run an exploration mission: the robot explores a scenario in the simulator with the
    /// strategy chosen, learns traversal costs as it goes, and a report is written.
    Run(RunArgs),
    /// List every exploration strategy with its paper, its parameters, their defaults and
    /// units.
    Strategies,
    /// Map and learn from a recorded ROS 2 log (MCAP: sensor_msgs/PointCloud2 with x, y, z and
    /// rgb, nav_msgs/Odometry or tf2_msgs/TFMessage poses, the gait) with the mission's own
    /// mapping and learning code; writes the report of `strider run` without the tours.
    Replay(ReplayArgs),
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
    /// MartinCorke: energy-optimal repeated tours on `energy-arena` — learn a zero-mean GP map
    /// of energy per metre while driving the same waypoints again and again, re-planning the
    /// tour each time.
    Tours(ToursArgs),
    /// Nardi19: repeated start–goal navigation on `bonn-paths` with a GP mixture model
    /// (mean-shift gating, optionally aerial-image gating classifiers) and a softplus
    /// lower-confidence-bound cost.
    Navigate(NavigateArgs),
    /// Mission-level benchmarks that reproduce the papers' tables.
    #[command(subcommand)]
    Bench(BenchCommand),
    /// Traversal-cost learners (GP, RBCM, IGMN, regression tree) and their benchmarks.
    #[command(subcommand)]
    Learn(LearnCommand),
}

#[derive(Subcommand, Debug)]
pub enum LearnCommand {
    /// Learner benchmarks: Prágr19 §V-A (incremental stream on lab-track: learning and inference
    /// time per step, RMSE and predictive std over n, for RBCM with four kernels, the full GP,
    /// IGMN and a regression tree; DIR/learn_bench.json, .md and .png) and Prágr18 Table I (cost of
    /// transport learned on one pass of cot-track and predicted from an aerial view, per learner ×
    /// descriptor; DIR/c1_table.md and .json).
    Bench(LearnBenchArgs),
    /// Prágr23 §5.3 (Table 5): the GP force predictor on four outdoor terrains with the 8-bin
    /// histogram, presented in three orders; prints the test entropies and writes
    /// DIR/c4_vegetation.md and .json.
    C4Vegetation(VegetationArgs),
}

#[derive(Subcommand, Debug)]
pub enum BenchCommand {
    /// Reproduce Prágr22 Table 5: small tours 1 and 2 in three navigation modes, small
    /// exploration GTSP vs greedy, large tour and exploration proposed vs spatial-only; writes
    /// DIR/table5.json and DIR/table5.md with our figures beside the published ones.
    Table5(Table5Args),
    /// Compare strategies from different papers on the same worlds: exploration time, observed
    /// cells, the learned cost's error against the terrain table, and the benchmark-tour time
    /// with learned navigation, with Mann-Whitney U between each pair; writes DIR/compare.json
    /// and DIR/compare.md.
    Compare(CompareArgs),
    /// Merge the shards of a comparison or of Table 5 (`bench compare --shard K/N`, `bench
    /// table5 --shard K/N`, each in its own folder) into what the unsharded command writes:
    /// DIR/compare.json and DIR/compare.md, or DIR/table5.json and DIR/table5.md.
    Merge(MergeArgs),
    /// Invariants at scale: seeded missions of every strategy on every built-in world it runs
    /// on (random world and mission seeds, a short time limit per world), each checked against
    /// the simulator's ground truth (the robot's centre never in an inadmissible cell, plans
    /// inside the world, missions that end, valid reports); writes DIR/soak.json and
    /// DIR/soak.md and fails when any invariant broke.
    Soak(SoakArgs),
    /// Exploration at scale: one mission on a large world (default `campus`, 200 × 200 m)
    /// sampled over simulated time: cells observed, real-time factor, replanning and new data
    /// to new tour latency (median, p95, max) and peak memory; writes DIR/scale.json,
    /// DIR/scale.md and DIR/scale.png (latency against cells observed).
    Scale(ScaleArgs),
}

#[derive(Subcommand, Debug)]
pub enum GpCommand {
    /// Fit a GP with fixed hyperparameters to a training CSV (header; features then y per row)
    /// and write the predictive mean and latent variance (without noise) for every row of a
    /// query CSV (header; features) as `mean,variance`.
    Predict(PredictArgs),
}

#[derive(Subcommand, Debug)]
pub enum GtspCommand {
    /// Solve one GTSPLIB (.gtsp) or TSPLIB (.tsp/.atsp) instance: prints the cost and the tour
    /// (1-based vertex ids as in the file, one per set, in visiting order).
    Solve(SolveArgs),
    /// Solve every instance listed in DIR/best_known.csv (or a TSPLIB DIR/optima.csv) and print
    /// per-instance cost, gap to the best-known value and time, then a summary line.
    Bench(GtspBenchArgs),
}

/// Which scenario to use: a built-in name or a path to a scenario TOML file.
#[derive(Args, Debug, Clone)]
pub struct ScenarioArg {
    /// Built-in scenario name (see `strider scenario list`) or path to a scenario `.toml` file.
    #[arg(long, short = 's', default_value = "courtyard-small")]
    pub scenario: String,
    /// Seed of the procedural world family (built-ins only; 1 is the reference world).
    #[arg(long, value_parser = flags::seed, allow_negative_numbers = true, default_value_t = 1)]
    pub world_seed: u64,
}

#[derive(Subcommand, Debug)]
pub enum ScenarioCommand {
    /// List the built-in scenarios with a one-line description each.
    List,
    /// Render a scenario's world to PNG: color, elevation, terrain, ground-truth passability, tours.
    Render(RenderArgs),
    /// Write a scenario as an editable TOML file plus its PNG layers.
    Export(ExportArgs),
}

#[derive(Subcommand, Debug)]
pub enum MapCommand {
    /// Drive a scripted coverage path through the simulator, fuse the sensor stream into the map,
    /// and write the map layers as PNG plus `map_stats.json` (accuracy against ground truth and
    /// fusion speed).
    Build(MapBuildArgs),
}

#[derive(Args, Debug)]
pub struct RunArgs {
    #[command(flatten)]
    pub scenario: ScenarioArg,
    /// Exploration strategy (`strider strategies` lists them with their papers and
    /// parameters): gtsp, greedy, spatial-only, rbcm-greedy, escape, rigid.
    #[arg(long, default_value = "gtsp")]
    pub strategy: String,
    /// Set a strategy parameter, overriding the scenario's `[strategy.<name>]` section
    /// (repeatable), e.g. `--set c_loss=7.5`.
    #[arg(long = "set", value_name = "KEY=VALUE")]
    pub sets: Vec<String>,
    /// Shorthand for `--set gait=NAME` (the gait rbcm-greedy walks).
    #[arg(long)]
    pub gait: Option<String>,
    /// Seed of the mission and the simulator's noise.
    #[arg(long, value_parser = flags::seed, allow_negative_numbers = true, default_value_t = 1)]
    pub seed: u64,
    /// Mission time limit in simulated seconds (default: the scenario's); > 0 and ≤ 10⁶.
    #[arg(long, value_name = "SECONDS", value_parser = flags::time_limit, allow_negative_numbers = true)]
    pub time_limit: Option<f64>,
    /// Output directory (created if missing).
    #[arg(long, short = 'o', default_value = "out/run")]
    pub out: PathBuf,
    /// Also record the mission to this MCAP file: the sensor stream as ROS 2 messages
    /// (replayable with `strider replay`) and the map, costs, goals, tour and path with
    /// Foxglove's schemas (open it in Foxglove). It is written as FILE.part and renamed to
    /// FILE once finished, also when the mission is interrupted (Ctrl-C).
    #[arg(long, value_name = "FILE")]
    pub mcap: Option<PathBuf>,
    /// Serve the mission live to Foxglove over its WebSocket protocol on ADDR (IP:PORT,
    /// default 127.0.0.1:8765): in Foxglove, Open connection → Foxglove WebSocket →
    /// ws://ADDR. The channels are those of an MCAP recording. A bare --live goes after
    /// the other arguments (or write --live=ADDR); the server stops when the command ends.
    #[arg(long, value_name = "ADDR", num_args = 0..=1, default_missing_value = "127.0.0.1:8765", value_parser = flags::live_addr)]
    pub live: Option<SocketAddr>,
    /// Pace the mission at R times real time (1 = simulated speed), e.g. to watch it with
    /// --live; without it, it runs as fast as it can. Results are the same. 0.01 to 10000.
    #[arg(long, value_name = "R", value_parser = flags::rate, allow_negative_numbers = true)]
    pub rate: Option<Rate>,
}

#[derive(Args, Debug)]
pub struct ReplayArgs {
    /// The MCAP file.
    pub log: PathBuf,
    /// Replay configuration (TOML): topics, frames, gait source and the robot's
    /// parameters; see `strider_log::config`. For a log of `strider run --mcap` a
    /// `[mission]` table naming the scenario suffices.
    #[arg(long)]
    pub config: PathBuf,
    /// Output directory (created if missing).
    #[arg(long, short = 'o', default_value = "out/replay")]
    pub out: PathBuf,
    /// Serve the replay live to Foxglove over its WebSocket protocol on ADDR (IP:PORT,
    /// default 127.0.0.1:8765): in Foxglove, Open connection → Foxglove WebSocket →
    /// ws://ADDR. The channels are those of an MCAP recording. A bare --live goes after
    /// the other arguments (or write --live=ADDR); the server stops when the command ends.
    #[arg(long, value_name = "ADDR", num_args = 0..=1, default_missing_value = "127.0.0.1:8765", value_parser = flags::live_addr)]
    pub live: Option<SocketAddr>,
    /// Pace the replay at R times real time (1 = recorded speed), e.g. to watch it with
    /// --live; without it, it runs as fast as it can. Results are the same. 0.01 to 10000.
    #[arg(long, value_name = "R", value_parser = flags::rate, allow_negative_numbers = true)]
    pub rate: Option<Rate>,
}

#[derive(Args, Debug)]
pub struct Table5Args {
    /// Trials per row on courtyard-small (mission seeds 1..=N); 1 to 10000.
    #[arg(long, default_value_t = 25, value_parser = flags::trials, allow_negative_numbers = true)]
    pub trials: usize,
    /// Trials per row on courtyard-large (default: --trials); 0 (no large-world rows) to 10000.
    #[arg(long, value_parser = flags::large_trials, allow_negative_numbers = true)]
    pub large_trials: Option<usize>,
    /// Random worlds the trials cycle through (world seeds 1..=K); 1 to 10⁶.
    #[arg(long, default_value_t = 5, value_parser = flags::world_seeds, allow_negative_numbers = true)]
    pub world_seeds: u64,
    /// Trials run in parallel (default: the number of CPUs); 1 to 256, more than
    /// the CPUs run as many threads as there are CPUs.
    #[arg(long, value_parser = flags::jobs, allow_negative_numbers = true)]
    pub jobs: Option<usize>,
    /// Override the scenarios' mission time limit, simulated seconds (for quick runs); > 0 and
    /// ≤ 10⁶.
    #[arg(long, value_name = "SECONDS", value_parser = flags::time_limit, allow_negative_numbers = true)]
    pub time_limit: Option<f64>,
    /// Also record each trial's mission as MCAP (`strider run --mcap`) into this directory.
    #[arg(long)]
    pub mcap_dir: Option<PathBuf>,
    /// Output directory (created if missing). Every finished trial is kept in DIR/trials as it
    /// finishes.
    #[arg(long, short = 'o', default_value = "out/table5")]
    pub out: PathBuf,
    /// Continue an earlier run with the same options (e.g. one interrupted with Ctrl-C): reuse
    /// the trials kept in DIR/trials and run only the missing ones. Without it, a run starts
    /// afresh and removes the trial files of earlier runs in DIR/trials.
    #[arg(long)]
    pub resume: bool,
    /// Run only shard K of N (1-based): the trials whose index in the table's order is K − 1
    /// modulo N, for batch schedulers; `strider bench merge` joins the shards' folders.
    #[arg(long, value_name = "K/N")]
    pub shard: Option<String>,
    /// Set a strategy parameter of every trial (repeatable), e.g. `--set look_around=false`
    /// for an ablation; `strider strategies` lists the parameters.
    #[arg(long = "set", value_name = "KEY=VALUE")]
    pub sets: Vec<String>,
}

#[derive(Args, Debug)]
pub struct CompareArgs {
    /// Scenarios, comma-separated (built-in names or files).
    #[arg(
        long,
        value_delimiter = ',',
        default_value = "courtyard-small,lab-track"
    )]
    pub scenarios: Vec<String>,
    /// Strategies, comma-separated (`strider strategies` lists them).
    #[arg(
        long,
        value_delimiter = ',',
        default_value = "gtsp,greedy,spatial-only,rbcm-greedy"
    )]
    pub strategies: Vec<String>,
    /// Trials per scenario and strategy (mission seeds 1..=N); 1 to 10000.
    #[arg(long, default_value_t = 5, value_parser = flags::trials, allow_negative_numbers = true)]
    pub trials: usize,
    /// Random worlds the trials cycle through (world seeds 1..=K); 1 to 10⁶.
    #[arg(long, default_value_t = 5, value_parser = flags::world_seeds, allow_negative_numbers = true)]
    pub world_seeds: u64,
    /// Trials run in parallel (default: the number of CPUs); 1 to 256, more than
    /// the CPUs run as many threads as there are CPUs.
    #[arg(long, value_parser = flags::jobs, allow_negative_numbers = true)]
    pub jobs: Option<usize>,
    /// Override the scenarios' mission time limit, simulated seconds; > 0 and ≤ 10⁶.
    #[arg(long, value_name = "SECONDS", value_parser = flags::time_limit, allow_negative_numbers = true)]
    pub time_limit: Option<f64>,
    /// Run only shard K of N (1-based): the trials whose index in the comparison's order is
    /// K − 1 modulo N, for batch schedulers; `strider bench merge` joins the shards' folders.
    #[arg(long, value_name = "K/N")]
    pub shard: Option<String>,
    /// Output directory (created if missing).
    #[arg(long, short = 'o', default_value = "out/compare")]
    pub out: PathBuf,
}

#[derive(Args, Debug)]
pub struct MergeArgs {
    /// The shards' output folders (each with the compare.json of `bench compare --shard` or
    /// the table5.json of `bench table5 --shard`).
    #[arg(required = true)]
    pub dirs: Vec<PathBuf>,
    /// Output directory (created if missing).
    #[arg(long, short = 'o', default_value = "out/compare")]
    pub out: PathBuf,
}

#[derive(Args, Debug)]
pub struct PredictArgs {
    /// Training CSV: a header line, then the features and y on each row.
    #[arg(long)]
    pub train: PathBuf,
    /// Query CSV: a header line, then the features on each row.
    #[arg(long)]
    pub query: PathBuf,
    /// Kernel: se (squared exponential), exp, matern32 or matern52.
    #[arg(long, default_value = "se")]
    pub kernel: String,
    /// Isotropic lengthscale l.
    #[arg(long, default_value_t = 0.4, allow_negative_numbers = true)]
    pub lengthscale: f64,
    /// Signal variance σ_s².
    #[arg(long, default_value_t = 1.0, allow_negative_numbers = true)]
    pub signal_variance: f64,
    /// Noise variance σ_n² (σ_ε = 0.5).
    #[arg(long, default_value_t = 0.25, allow_negative_numbers = true)]
    pub noise_variance: f64,
    /// Constant prior mean.
    #[arg(long, default_value_t = 0.0, allow_negative_numbers = true)]
    pub prior_mean: f64,
    /// Output CSV with the header `mean,variance`, one row per query, full precision.
    #[arg(long, short = 'o')]
    pub out: PathBuf,
    /// Also write {"n_train", "n_query", "fit_s", "predict_s"} (measured in-process) here.
    #[arg(long)]
    pub timing_json: Option<PathBuf>,
}

#[derive(Args, Debug)]
pub struct SolveArgs {
    /// The instance file.
    pub file: PathBuf,
    /// Wall-clock limit, seconds.
    #[arg(long, default_value_t = 60.0, allow_negative_numbers = true)]
    pub time_limit: f64,
    /// Random seed (same seed and limits: same tour, unless the time limit cuts the search).
    #[arg(long, default_value_t = 1)]
    pub seed: u64,
    /// Effort preset: fast, default or slow.
    #[arg(long, default_value = "default")]
    pub mode: String,
    /// Stop as soon as a tour costing at most this is found (e.g. a known optimum; GLNS calls
    /// it the budget). Until then the search is the one without a target.
    #[arg(long, allow_negative_numbers = true)]
    pub target: Option<i64>,
    /// Print exactly one JSON object {"cost", "tour", "time_s"}.
    #[arg(long)]
    pub json: bool,
}

#[derive(Args, Debug)]
pub struct GtspBenchArgs {
    /// Folder with the instances and best_known.csv / optima.csv.
    pub dir: PathBuf,
    /// Wall-clock limit per run, seconds.
    #[arg(long, default_value_t = 60.0, allow_negative_numbers = true)]
    pub time_limit: f64,
    /// Runs per instance (seeds seed, seed+1, …).
    #[arg(long, default_value_t = 1)]
    pub runs: usize,
    /// First seed.
    #[arg(long, default_value_t = 1)]
    pub seed: u64,
    /// Effort preset: fast, default or slow.
    #[arg(long, default_value = "default")]
    pub mode: String,
    /// Only instances with at least this many sets.
    #[arg(long, default_value_t = 0)]
    pub min_sets: usize,
    /// Only instances with at most this many sets.
    #[arg(long, default_value_t = usize::MAX)]
    pub max_sets: usize,
    /// Stop each run as soon as it finds a tour at the instance's best-known value (its
    /// `--target`); a run that never reaches it runs its whole search.
    #[arg(long)]
    pub stop_at_best_known: bool,
    /// Also write per-instance results and the summary as JSON to this file.
    #[arg(long)]
    pub json: Option<PathBuf>,
}

#[derive(Args, Debug)]
pub struct RenderArgs {
    /// Built-in scenario name or path to a scenario `.toml` file.
    pub name: String,
    /// Seed of the procedural world family (built-ins only).
    #[arg(long, value_parser = flags::seed, allow_negative_numbers = true, default_value_t = 1)]
    pub world_seed: u64,
    /// Output directory (created if missing).
    #[arg(long, short = 'o')]
    pub out: PathBuf,
}

#[derive(Args, Debug)]
pub struct ExportArgs {
    /// Built-in scenario name or path to a scenario `.toml` file.
    pub name: String,
    /// Seed of the procedural world family (built-ins only).
    #[arg(long, value_parser = flags::seed, allow_negative_numbers = true, default_value_t = 1)]
    pub world_seed: u64,
    /// Output directory (created if missing); the TOML is `DIR/scenario.toml`.
    #[arg(long, short = 'o')]
    pub out: PathBuf,
}

#[derive(Args, Debug)]
pub struct MapBuildArgs {
    #[command(flatten)]
    pub scenario: ScenarioArg,
    /// Seed of the simulator's noise.
    #[arg(long, value_parser = flags::seed, allow_negative_numbers = true, default_value_t = 1)]
    pub seed: u64,
    /// Spacing of the coverage lanes, metres (default: 0.4 × sensor range); > 0 and ≤ 1000,
    /// and at most the world's longer side (wider lanes are one lane).
    #[arg(long, value_name = "METRES", value_parser = flags::lane_spacing, allow_negative_numbers = true)]
    pub lane_spacing: Option<f64>,
    /// Stop driving after this many simulated seconds (default: when the path is done); > 0
    /// and ≤ 10⁶.
    #[arg(long, value_name = "SECONDS", value_parser = flags::time_limit, allow_negative_numbers = true)]
    pub time_limit: Option<f64>,
    /// Output directory (created if missing).
    #[arg(long, short = 'o')]
    pub out: PathBuf,
}

#[derive(Args, Debug)]
pub struct VegetationArgs {
    /// Output directory (created if missing).
    #[arg(long, short = 'o', default_value = "out/c4-vegetation")]
    pub out: PathBuf,
}

/// Arguments of `strider tours`.
#[derive(Args, Debug)]
pub struct ToursArgs {
    /// Built-in scenario name or scenario `.toml` file.
    #[arg(long, short = 's', default_value = "energy-arena")]
    pub scenario: String,
    /// Seed of the procedural world family (built-ins only; 1 is the reference world).
    #[arg(long, value_parser = flags::seed, allow_negative_numbers = true, default_value_t = 1)]
    pub world_seed: u64,
    /// Run this many world seeds (world-seed, world-seed + 1, …), each with every noise seed,
    /// and pool the runs into `worlds.{json,md}`; 1 to 1000, at most 10000 runs in all.
    #[arg(long, default_value_t = 1, value_parser = flags::tour_worlds, allow_negative_numbers = true)]
    pub world_seeds: u64,
    /// Seed of the simulator's noise.
    #[arg(long, value_parser = flags::seed, allow_negative_numbers = true, default_value_t = 1)]
    pub seed: u64,
    /// Run this many noise seeds (seed, seed + 1, …) and count the acceptance criteria; 1 to
    /// 1000.
    #[arg(long, default_value_t = 1, value_parser = flags::tour_seeds, allow_negative_numbers = true)]
    pub seeds: u64,
    /// Number of tours (default: the scenario's `n_tours`, 25 on energy-arena); 1 to 10000.
    #[arg(long, value_parser = flags::tours, allow_negative_numbers = true)]
    pub tours: Option<usize>,
    /// Output directory (created if missing).
    #[arg(long, short = 'o', default_value = "out/tours")]
    pub out: PathBuf,
}

/// Arguments of `strider navigate`.
#[derive(Args, Debug)]
pub struct NavigateArgs {
    /// Built-in scenario name or scenario `.toml` file.
    #[arg(long, short = 's', default_value = "bonn-paths")]
    pub scenario: String,
    /// Seed of the simulator's noise (the first of `--seeds` consecutive seeds).
    #[arg(long, value_parser = flags::seed, allow_negative_numbers = true, default_value_t = 1)]
    pub seed: u64,
    /// Output directory (created if missing).
    #[arg(long, short = 'o', default_value = "out/navigate")]
    pub out: PathBuf,
    /// Sites: comma-separated world seeds of the scenario family (e.g. `1,2`).
    #[arg(long, default_value = "1")]
    pub sites: String,
    /// Number of consecutive seeds per site, from `--seed` (the acceptance sweep uses 10); 1 to
    /// 1000.
    #[arg(long, default_value_t = 1, value_parser = flags::navigate_seeds, allow_negative_numbers = true)]
    pub seeds: u64,
    /// Runs per task (Nardi19: 25); 1 to 1000.
    #[arg(long, default_value_t = 25, value_parser = flags::runs, allow_negative_numbers = true)]
    pub runs: usize,
    /// Objectives of the start-goal experiment: comma-separated `vibration`, `energy`.
    #[arg(long, default_value = "vibration,energy")]
    pub objectives: String,
    /// λ of the lower confidence bound μ − λσ (decision 26); 0 to 100.
    #[arg(long, default_value_t = 1.0, value_parser = flags::lambda, allow_negative_numbers = true)]
    pub lambda: f64,
    /// Run the whole experiment once per λ in this comma-separated list (e.g. `0.5,1,2,3`,
    /// decision 29) into `DIR/lambda-X/`, and compare softplus with ReLU over λ in
    /// `DIR/lambdas.md`; replaces `--lambda`.
    #[arg(long, conflicts_with = "lambda")]
    pub lambdas: Option<String>,
    /// An aerial image (8-bit RGB PNG, north up, one pixel per grid cell) replacing the
    /// scenario's colour layer.
    #[arg(long)]
    pub aerial: Option<PathBuf>,
    /// Navigations run in parallel (default: the number of CPUs); 1 to 256, more than
    /// the CPUs run as many threads as there are CPUs.
    #[arg(long, value_parser = flags::jobs, allow_negative_numbers = true)]
    pub jobs: Option<usize>,
}

/// Arguments of `strider learn bench`.
#[derive(Args, Debug)]
pub struct LearnBenchArgs {
    /// Which protocol: stream (Prágr19 §V-A), c1 (Prágr18 Table I) or all.
    #[arg(long, default_value = "all")]
    pub protocol: String,
    /// Repetitions of the stream protocol (Prágr19: 100), each on its own recorded stream; 1 to
    /// 1000.
    #[arg(long, default_value_t = 100, value_parser = flags::reps, allow_negative_numbers = true)]
    pub reps: usize,
    /// Distinct recorded streams (simulator seeds `--seed` … `--seed + K − 1`); repetition r runs
    /// on stream r mod K, so repetitions of one stream repeat its timings (Prágr19's 100 trials)
    /// and the K streams give the RMSE its spread. 1 to 1000.
    #[arg(long, default_value_t = 10, value_parser = flags::streams, allow_negative_numbers = true)]
    pub streams: usize,
    /// Pairs per stream (Prágr19: 292 from two passes); 2 to 2000.
    #[arg(long, default_value_t = 300, value_parser = flags::pairs, allow_negative_numbers = true)]
    pub pairs: usize,
    /// Independent trials (pass 1 + aerial-view pass 2) pooled per C1 cell; 1 to 1000.
    #[arg(long, default_value_t = 3, value_parser = flags::c1_runs, allow_negative_numbers = true)]
    pub c1_runs: usize,
    /// Pairs per C1 pass (0: the whole lane, Prágr18's protocol); fewer cut both passes short
    /// (quick runs and tests). 0 to 100000.
    #[arg(long, default_value_t = 0, value_parser = flags::c1_pairs, allow_negative_numbers = true)]
    pub c1_pairs: usize,
    /// Seed of the simulator's noise (stream i and C1 trial i use seed + i).
    #[arg(long, value_parser = flags::seed, allow_negative_numbers = true, default_value_t = 1)]
    pub seed: u64,
    /// Work run in parallel (default: the number of CPUs); 1 to 256, more than
    /// the CPUs run as many threads as there are CPUs. Timings are wall-clock
    /// per thread.
    #[arg(long, value_parser = flags::jobs, allow_negative_numbers = true)]
    pub jobs: Option<usize>,
    /// Output directory (created if missing).
    #[arg(long, short = 'o', default_value = "out/learn")]
    pub out: PathBuf,
}

/// Arguments of `strider bench scale`.
#[derive(Args, Debug)]
pub struct ScaleArgs {
    /// Built-in scenario name or scenario file.
    #[arg(long, short = 's', default_value = "campus")]
    pub scenario: String,
    /// World seed of a built-in scenario.
    #[arg(long, default_value_t = 1, value_parser = flags::seed)]
    pub world_seed: u64,
    /// Mission seed.
    #[arg(long, default_value_t = 1, value_parser = flags::seed)]
    pub seed: u64,
    /// Exploration strategy: gtsp, greedy or spatial-only.
    #[arg(long, default_value = "gtsp")]
    pub strategy: String,
    /// Override the scenario's mission time limit, simulated seconds; > 0 and ≤ 10⁶.
    #[arg(long, value_name = "SECONDS", value_parser = flags::time_limit, allow_negative_numbers = true)]
    pub time_limit: Option<f64>,
    /// Sampling window, simulated seconds (1 to 10⁶).
    #[arg(long, default_value_t = 600.0, allow_negative_numbers = true)]
    pub window: f64,
    /// Output directory (created if missing).
    #[arg(long, short = 'o', default_value = "out/scale")]
    pub out: PathBuf,
}

/// Arguments of `strider bench soak`.
#[derive(Args, Debug)]
pub struct SoakArgs {
    /// Missions to run (strategies in turn, each cycling through its worlds).
    #[arg(long, default_value_t = 500)]
    pub missions: usize,
    /// Seed of the world and mission seeds (same seed: same missions and results).
    #[arg(long, default_value_t = 1)]
    pub seed: u64,
    /// Missions run in parallel (default: the number of CPUs).
    #[arg(long)]
    pub jobs: Option<usize>,
    /// Simulated time limit of every mission, seconds (default: per world, 45–90 s).
    #[arg(long)]
    pub time_limit: Option<f64>,
    /// Run one mission alone, as a violation names it: STRATEGY@SCENARIO:WORLD_SEED:SEED.
    #[arg(long, value_name = "KEY")]
    pub rerun: Option<String>,
    /// Output directory (created if missing).
    #[arg(long, short = 'o', default_value = "out/soak")]
    pub out: PathBuf,
}
