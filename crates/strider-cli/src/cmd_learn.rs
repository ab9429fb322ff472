//! `strider learn bench`: the learner benchmarks of `000` §V-A (Fig. 5) and thesis C1 (Table I).
//!
//! **stream** (`000` §V-A). A stream of (descriptor, cost) pairs is recorded by driving the
//! hexapod over `lab-track` in the simulator, two passes of the scenario's `patches` tour in the
//! adaptive gait, as an operator would: the robot's own RGB-D scans build its map, the roll
//! variance over 10 s (`000`) is the cost, attributed to the window's middle pose, and the 5-D
//! descriptor (`000` Eq. 10) of that cell is taken from the map at that moment. Pairs are kept
//! every `(path length − 0.5 m) / --pairs` metres (≈ 300 pairs, the paper had 292). `--streams`
//! K streams are recorded (simulator seeds `--seed` … `--seed + K − 1`); repetition r runs each
//! learner on stream r mod K with [`run_stream`]: learn one pair, predict all pairs, RMSE against
//! the recorded costs. `000` repeated one data set 100 times to average its timings; repeating
//! each of K streams does the same, and the K streams give the RMSE curve a spread.
//! Learners: RBCM (m_max 50, m_min 25) with the exponential, Matérn 3/2, Matérn 5/2 and RBF
//! kernels, the exponential RBCM without m_min (m_min 1), the full GP (exponential), all with
//! per-expert / per-step hyperparameter fitting (bounded, ≤ 200 iterations), the IGMN and the
//! regression tree. Per step the mean over repetitions of the learning time, inference time,
//! RMSE (and its spread) and mean predictive std go to `learn_bench.json`, the four curves to
//! `learn_bench.png` (like `000` Fig. 5; times on a log scale).
//!
//! **c1** (thesis C1 §III-C, §IV). On `cot-track` the robot walks the lane once (pass 1) building
//! its map with its own camera and measuring the cost of transport P/(m g v) over 3 s windows
//! (a pair every 0.1 m; C1 features of the cell from the robot's map); then a second trial
//! (pass 2, another simulator seed) measures the CoT along the same lane while the descriptors
//! come from an elevated "aerial" scan of the track (a downward camera 2 m up, noisier depth,
//! a 0.9 colour gain for its other white balance). Every learner × descriptor combination (IGMN,
//! regression tree, full GP, RBCM × 24 colour/geometry combinations) learns on pass 1 and
//! predicts pass 2 ([`c1_errors`]); the errors of `--c1-runs` independent trials are pooled into
//! the mean and variance of |ŷ − y| per cell, written to `c1_table.md` and `c1_table.json`.
//!
//! The GP-family prior mean is 0 in the stream protocol (`000`'s zero-mean experts; roll
//! variances are small and positive) and the mean CoT of pass 1 in the C1 protocol (a CoT of 0
//! is meaningless, and pass 1 is what the robot has learned from).
//!
//! The learners see only descriptors and measured costs; the simulator's terrain table is never
//! read here (the recorded costs are both the teaching signal and, as in both papers, the
//! evaluation target). Everything but wall times is a function of `--seed`.

use std::fs;
use std::path::{Path, PathBuf};
use std::time::Instant;

use anyhow::{Context, Result, bail};
use clap::Args;
use rayon::prelude::*;
use serde_json::{Value, json};
use strider_core::interface::{Robot, SensorSink};
use strider_core::{GaitId, Point2, Point3, PointCloud, PoseStamped, Proprioception};
use strider_learn::bench::{
    DataScale, LearnerSpec, StreamTrace, c1_errors, finite_pairs, mean_variance, run_stream,
};
use strider_learn::gp::KernelKind;
use strider_learn::igmn::IgmnParams;
use strider_learn::regression_tree::TreeParams;
use strider_learn::signals::{EnergyCost, EnergyParams, RollVarianceCost, RollVarianceParams};
use strider_map::ElevationMap;
use strider_map::c1_descriptors::{C1Features, C1Params, ColorFeature, GeomFeature, c1_features};
use strider_map::descriptors::shape_lab_descriptor;
use strider_scenario::{Scenario, SensorKind, SensorSpec, SimParams};
use strider_sim::{Heightfield, RangeSensor, ScanNoise, Simulator};

use crate::render::{Canvas, compose, label, line_chart, palette};

/// Arguments of `strider learn bench`.
#[derive(Args, Debug)]
pub struct LearnBenchArgs {
    /// Which protocol: stream (`000` §V-A), c1 (thesis C1 Table I) or all.
    #[arg(long, default_value = "all")]
    pub protocol: String,
    /// Repetitions of the stream protocol (`000`: 100), each on its own recorded stream.
    #[arg(long, default_value_t = 100)]
    pub reps: usize,
    /// Distinct recorded streams (simulator seeds `--seed` … `--seed + K − 1`); repetition r runs
    /// on stream r mod K, so repetitions of one stream repeat its timings (`000`'s 100 trials)
    /// and the K streams give the RMSE its spread.
    #[arg(long, default_value_t = 10)]
    pub streams: usize,
    /// Pairs per stream (`000`: 292 from two passes).
    #[arg(long, default_value_t = 300)]
    pub pairs: usize,
    /// Independent trials (pass 1 + aerial-view pass 2) pooled per C1 cell.
    #[arg(long, default_value_t = 3)]
    pub c1_runs: usize,
    /// Pairs per C1 pass (0: the whole lane, the thesis protocol); fewer cut both passes short
    /// (quick runs and tests).
    #[arg(long, default_value_t = 0)]
    pub c1_pairs: usize,
    /// Seed of the simulator's noise (stream i and C1 trial i use seed + i).
    #[arg(long, default_value_t = 1)]
    pub seed: u64,
    /// Work run in parallel (default: the number of CPUs). Timings are wall-clock per thread.
    #[arg(long)]
    pub jobs: Option<usize>,
    /// Output directory (created if missing).
    #[arg(long, short = 'o', default_value = "out/learn")]
    pub out: PathBuf,
}

/// Thesis C1 Table I as published (OCR-reconstructed decimals), IGMN and regression tree rows:
/// (learner, colour, geometry, mean, variance).
const PUBLISHED_C1: [(&str, &str, &str, f64, f64); 30] = [
    ("igmn", "None", "Ori", 8.7, 57.4),
    ("igmn", "RGB-M", "None", 5.7, 44.5),
    ("igmn", "RGB-M", "Height", 6.6, 39.0),
    ("igmn", "RGB-M", "Ori", 5.8, 43.6),
    ("igmn", "RGB-M", "Set", 7.8, 38.9),
    ("igmn", "RGB-M", "Shape", 5.7, 38.4),
    ("igmn", "RGB-P", "None", 7.3, 59.4),
    ("igmn", "RGB-P", "Shape", 6.7, 40.4),
    ("igmn", "None", "Set", 9.0, 58.5),
    ("igmn", "None", "Shape", 8.4, 44.9),
    ("igmn", "None", "Height", 9.0, 37.9),
    ("igmn", "Lab-M", "None", 5.7, 38.3),
    ("igmn", "Lab-M", "Shape", 9.4, 147.2),
    ("igmn", "Lab-P", "None", 7.5, 39.6),
    ("igmn", "Lab-P", "Shape", 7.2, 67.6),
    ("tree", "Lab-P", "None", 6.4, 37.9),
    ("tree", "Lab-P", "Shape", 7.1, 70.9),
    ("tree", "None", "Ori", 8.1, 60.3),
    ("tree", "None", "Set", 7.9, 59.0),
    ("tree", "None", "Shape", 6.9, 77.2),
    ("tree", "RGB-M", "None", 6.3, 51.5),
    ("tree", "RGB-M", "Height", 6.4, 48.4),
    ("tree", "RGB-M", "Ori", 5.8, 47.5),
    ("tree", "RGB-M", "Set", 6.8, 63.3),
    ("tree", "RGB-M", "Shape", 5.9, 49.6),
    ("tree", "None", "Height", 7.3, 58.6),
    ("tree", "RGB-P", "None", 6.2, 41.5),
    ("tree", "Lab-M", "None", 6.9, 66.6),
    ("tree", "RGB-P", "Shape", 6.6, 58.7),
    ("tree", "Lab-M", "Shape", 6.1, 46.0),
];

/// Stream sizes at which the summary reports the per-step times.
const REPORT_AT: [usize; 3] = [50, 150, 300];

/// Runs `strider learn bench`.
pub fn bench(args: &LearnBenchArgs) -> Result<()> {
    let wall = Instant::now();
    let (stream, c1) = match args.protocol.as_str() {
        "stream" => (true, false),
        "c1" => (false, true),
        "all" => (true, true),
        p => bail!("--protocol must be stream, c1 or all, got {p:?}"),
    };
    if stream && (args.reps == 0 || args.streams == 0 || args.pairs < 2) {
        bail!("--reps and --streams must be at least 1 and --pairs at least 2");
    }
    if c1 && args.c1_runs == 0 {
        bail!("--c1-runs must be at least 1");
    }
    fs::create_dir_all(&args.out)
        .with_context(|| format!("{}: cannot create directory", args.out.display()))?;
    let threads = args
        .jobs
        .unwrap_or_else(|| std::thread::available_parallelism().map_or(1, |n| n.get()))
        .max(1);
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .context("cannot start the thread pool")?;
    let mut summary = Vec::new();
    if stream {
        let t = Instant::now();
        let s = pool.install(|| stream_bench(args))?;
        summary.push(format!("{s} ({:.0} s)", t.elapsed().as_secs_f64()));
    }
    if c1 {
        let t = Instant::now();
        let s = pool.install(|| c1_bench(args))?;
        summary.push(format!("{s} ({:.0} s)", t.elapsed().as_secs_f64()));
    }
    println!(
        "learn bench: {}; {:.1} s wall -> {}",
        summary.join("; "),
        wall.elapsed().as_secs_f64(),
        args.out.display()
    );
    Ok(())
}

// ---------------------------------------------------------------------------------------------
// Recording pairs in the simulator.

/// The cost estimator of a drive.
enum Probe {
    /// `000`: roll variance.
    Roll(RollVarianceCost),
    /// Thesis C1: cost of transport.
    Energy(EnergyCost),
}

/// Describes the cell at a position on a map (`None`: not describable yet).
type Describe<D> = Box<dyn Fn(&ElevationMap, Point2) -> Option<D>>;

/// A recorded pair before its descriptor is attached: attributed position and measured cost.
struct Sample<D> {
    position: Point2,
    cost: f64,
    descriptor: Option<D>,
}

/// Seconds between the scans fused into the robot's map: every second scan of the 5 Hz camera
/// (the hexapod moves 2 cm meanwhile), which halves the simulation cost and still observes
/// every cell many times before the robot walks over it.
const SCAN_INTERVAL_S: f64 = 0.4;

/// Fuses the clouds into the robot's map (when `fuse`), turns the proprioceptive stream into
/// costs and keeps one sample every `spacing` metres of attributed position, describing its
/// cell with `describe` on the map as it is at that moment.
struct PairSink<D> {
    map: ElevationMap,
    fuse: bool,
    probe: Probe,
    spacing: f64,
    last: Option<Point2>,
    describe: Describe<D>,
    samples: Vec<Sample<D>>,
    undescribed: usize,
    /// The latest pose stamp and the stamp of the last fused scan.
    now: f64,
    last_scan: f64,
}

impl<D> SensorSink for PairSink<D> {
    fn on_pose(&mut self, pose: &PoseStamped) {
        self.now = pose.stamp;
        match &mut self.probe {
            Probe::Roll(r) => r.push_pose(pose),
            Probe::Energy(e) => e.push_pose(pose),
        }
    }
    fn on_cloud(&mut self, cloud: &PointCloud) {
        if self.fuse {
            self.map.fuse(cloud);
            self.last_scan = cloud.stamp;
        }
    }
    fn wants_cloud(&self, _sensor: u8) -> bool {
        self.fuse && self.now - self.last_scan >= SCAN_INTERVAL_S - 1e-6
    }
    fn on_proprioception(&mut self, p: &Proprioception) {
        let s = match &mut self.probe {
            Probe::Roll(r) => r.push(p).map(|s| (s.position, s.cost)),
            Probe::Energy(e) => e.push(p).map(|s| (s.position, s.cost_of_transport)),
        };
        let Some((pos, cost)) = s else { return };
        let pos = Point2::new(pos.x, pos.y);
        if !cost.is_finite() || self.last.is_some_and(|q| q.dist(pos) < self.spacing) {
            return;
        }
        let descriptor = if self.fuse {
            match (self.describe)(&self.map, pos) {
                Some(d) => Some(d),
                None => {
                    // Not described yet (unknown neighbourhood): try the next sample.
                    self.undescribed += 1;
                    return;
                }
            }
        } else {
            None
        };
        self.last = Some(pos);
        self.samples.push(Sample {
            position: pos,
            cost,
            descriptor,
        });
    }
}

/// Index of the gait named `name` (the first gait when there is none).
fn gait_index(sc: &Scenario, name: &str) -> GaitId {
    GaitId(
        sc.robot
            .gaits
            .iter()
            .position(|g| g.name == name)
            .unwrap_or(0) as u8,
    )
}

fn path_length(path: &[Point2]) -> f64 {
    path.windows(2).map(|w| w[0].dist(w[1])).sum()
}

/// Drives `path` in `gait` with simulator seed `seed`, feeding `sink`, until the path is done or
/// `sink` holds `stop_after` samples.
fn drive<D>(
    sc: &Scenario,
    seed: u64,
    path: &[Point2],
    gait: GaitId,
    sink: &mut PairSink<D>,
    stop_after: usize,
) -> Result<()> {
    let mut sim = Simulator::new(sc, seed)?;
    sim.set_gait(gait);
    sim.follow(path);
    let v = sc
        .robot
        .gaits
        .get(gait.0 as usize)
        .map_or(0.05, |g| g.max_speed)
        .max(1e-6);
    let limit = 60.0 + 10.0 * path_length(path) / v;
    while sim.now() < limit {
        let st = sim.advance(1.0, sink)?;
        if st.idle || sink.samples.len() >= stop_after {
            break;
        }
        if st.blocked {
            // Skip a waypoint the motion judge refuses rather than push forever.
            let rest: Vec<Point2> = sim.remaining_path().iter().skip(1).copied().collect();
            sim.follow(&rest);
        }
    }
    Ok(())
}

fn new_sink<D>(
    sc: &Scenario,
    fuse: bool,
    probe: Probe,
    spacing: f64,
    describe: Describe<D>,
) -> PairSink<D> {
    PairSink {
        map: ElevationMap::new(sc.map.clone()),
        fuse,
        probe,
        spacing,
        last: None,
        describe,
        samples: Vec::new(),
        undescribed: 0,
        now: 0.0,
        last_scan: f64::NEG_INFINITY,
    }
}

// ---------------------------------------------------------------------------------------------
// The stream protocol.

/// The learners of the stream protocol.
fn stream_learners() -> Vec<LearnerSpec> {
    let rbcm = |kernel, m_min| LearnerSpec::Rbcm {
        kernel,
        m_max: 50,
        m_min,
        fit: true,
    };
    vec![
        rbcm(KernelKind::Exponential, 25),
        rbcm(KernelKind::Matern32, 25),
        rbcm(KernelKind::Matern52, 25),
        rbcm(KernelKind::SquaredExponential, 25),
        rbcm(KernelKind::Exponential, 1),
        LearnerSpec::Gp {
            kernel: KernelKind::Exponential,
            fit: true,
        },
        LearnerSpec::Igmn(IgmnParams::default()),
        LearnerSpec::Tree(TreeParams::default()),
    ]
}

/// One recorded stream: 5-D descriptors (row-major) and roll-variance costs, in order.
struct Stream {
    x: Vec<f64>,
    y: Vec<f64>,
}

/// Records the `000` stream on `lab-track` (module docs) with simulator seed `seed`.
fn record_stream(sc: &Scenario, seed: u64, pairs: usize) -> Result<Stream> {
    let Some(tour) = sc.tours.first() else {
        bail!("scenario {} has no tour to drive", sc.name);
    };
    let mut path = vec![sc.start.position()];
    for _ in 0..2 {
        path.extend(tour.waypoints.iter().copied());
        if tour.closed
            && let Some(&w0) = tour.waypoints.first()
        {
            path.push(w0);
        }
    }
    // A little denser than 300 over the two passes (the first 10 s window yields nothing), then
    // cut at `pairs`: fewer pairs are the stream's beginning (the drive stops once they are in),
    // more pairs a denser sampling of the same passes.
    let spacing = ((path_length(&path) - 1.0) / (1.05 * pairs.max(300) as f64)).max(0.01);
    // The `000` explorer's descriptor neighbourhood and cost window on this scenario.
    let rbcm = strider_explore::registry::find("rbcm-greedy")?
        .configure(strider_cli::trial::section(sc, "rbcm-greedy")?, &[])?;
    let strider_explore::registry::Configured::Rbcm(rbcm) = rbcm else {
        bail!("rbcm-greedy is not configured as the 000 explorer");
    };
    let delta = rbcm.delta_desc;
    let params = RollVarianceParams {
        window_s: rbcm.cost_window_s,
        rate_hz: sc.sim.proprio_rate_hz,
        pose_rate_hz: sc.sim.pose_rate_hz,
    };
    let probe = Probe::Roll(RollVarianceCost::new(params)?);
    let describe = Box::new(move |m: &ElevationMap, p: Point2| {
        let c = m.cell_at(p.x, p.y)?;
        shape_lab_descriptor(m, c, delta).map(|d| d.map(f64::from))
    });
    let mut sink = new_sink(sc, true, probe, spacing, describe);
    drive(
        sc,
        seed,
        &path,
        gait_index(sc, "adaptive"),
        &mut sink,
        pairs,
    )?;
    let mut s = Stream {
        x: Vec::new(),
        y: Vec::new(),
    };
    for p in sink.samples.iter().take(pairs) {
        if let Some(d) = &p.descriptor {
            s.x.extend_from_slice(d);
            s.y.push(p.cost);
        }
    }
    let (x, y, _) = finite_pairs(5, &s.x, &s.y);
    Ok(Stream { x, y })
}

/// Mean of equal-length rows (truncated to the shortest).
fn mean_rows(rows: &[Vec<f64>]) -> Vec<f64> {
    let n = rows.iter().map(Vec::len).min().unwrap_or(0);
    (0..n)
        .map(|k| rows.iter().map(|r| r[k]).sum::<f64>() / rows.len() as f64)
        .collect()
}

/// Sample standard deviation across rows per position (0 for one row).
fn std_rows(rows: &[Vec<f64>]) -> Vec<f64> {
    let m = mean_rows(rows);
    if rows.len() < 2 {
        return vec![0.0; m.len()];
    }
    (0..m.len())
        .map(|k| {
            (rows.iter().map(|r| (r[k] - m[k]).powi(2)).sum::<f64>() / (rows.len() - 1) as f64)
                .sqrt()
        })
        .collect()
}

/// The largest rise of `rmse` within 10 steps after a new expert starts (steps 51, 101, …)
/// over its value just before (`000`: "peaks when small experts join").
fn spike_after_new_experts(rmse: &[f64], m_max: usize) -> f64 {
    let mut worst = 0.0f64;
    let mut start = m_max; // 0-based index of step m_max + 1
    while start < rmse.len() {
        let before = rmse[start - 1];
        let peak = rmse[start..(start + 10).min(rmse.len())]
            .iter()
            .fold(f64::NEG_INFINITY, |a, &b| a.max(b));
        worst = worst.max(peak - before);
        start += m_max;
    }
    worst
}

fn stream_bench(args: &LearnBenchArgs) -> Result<String> {
    let sc = Scenario::from_name_or_file("lab-track", 1)?;
    let specs = stream_learners();
    let k = args.streams.min(args.reps);
    let streams: Vec<Stream> = (0..k)
        .into_par_iter()
        .map(|i| record_stream(&sc, args.seed + i as u64, args.pairs))
        .collect::<Result<_>>()?;
    if let Some((i, s)) = streams.iter().enumerate().find(|(_, s)| s.y.len() < 2) {
        bail!("stream {i}: the drive produced only {} pairs", s.y.len());
    }
    // Every repetition: every learner on its stream, in order, on one thread.
    let reps: Vec<(Vec<StreamTrace>, usize)> = (0..args.reps)
        .into_par_iter()
        .map(|r| -> Result<(Vec<StreamTrace>, usize)> {
            let s = &streams[r % k];
            let scale = DataScale::of(5, &s.x, &s.y, 0.0);
            let mut traces = Vec::new();
            for spec in &specs {
                let mut l = spec.build(5, &scale)?;
                traces.push(
                    run_stream(l.as_mut(), &s.x, &s.y)
                        .with_context(|| format!("repetition {r}, {}", spec.label()))?,
                );
            }
            Ok((traces, s.y.len()))
        })
        .collect::<Result<_>>()?;
    let lengths: Vec<usize> = reps.iter().map(|r| r.1).collect();
    let n = lengths.iter().copied().min().unwrap_or(0);
    let mut learners = serde_json::Map::new();
    let mut curves: Vec<Curve> = Vec::new();
    for (i, spec) in specs.iter().enumerate() {
        let col = |f: &dyn Fn(&StreamTrace) -> &Vec<f64>| -> Vec<Vec<f64>> {
            reps.iter().map(|r| f(&r.0[i])[..n].to_vec()).collect()
        };
        let learn = mean_rows(&col(&|t| &t.learn_s));
        let infer = mean_rows(&col(&|t| &t.infer_s));
        let rmse_rows = col(&|t| &t.rmse);
        let rmse = mean_rows(&rmse_rows);
        let rmse_std = std_rows(&rmse_rows);
        let mean_std = reps[0].0[i].mean_std.as_ref().map(|_| {
            let rows: Vec<Vec<f64>> = reps
                .iter()
                .map(|r| {
                    r.0[i]
                        .mean_std
                        .as_ref()
                        .map_or(Vec::new(), |v| v[..n].to_vec())
                })
                .collect();
            mean_rows(&rows)
        });
        let mut at = serde_json::Map::new();
        for &k in &REPORT_AT {
            if k <= n {
                at.insert(
                    k.to_string(),
                    json!({"learn_s": learn[k - 1], "infer_s": infer[k - 1], "rmse": rmse[k - 1]}),
                );
            }
        }
        let spike = match spec {
            LearnerSpec::Rbcm { m_max, .. } => Some(spike_after_new_experts(&rmse, *m_max)),
            _ => None,
        };
        // The largest one-step rise of the mean RMSE (and its step), and the sum of all rises:
        // an expert that starts voting shows as a rise, wherever it happens.
        let (rise, rise_at) = rmse
            .windows(2)
            .enumerate()
            .map(|(k, w)| (w[1] - w[0], k + 2))
            .fold((0.0f64, 0usize), |a, b| if b.0 > a.0 { b } else { a });
        let rises: f64 = rmse.windows(2).map(|w| (w[1] - w[0]).max(0.0)).sum();
        learners.insert(
            spec.label(),
            json!({
                "max_rmse_rise": rise, "max_rmse_rise_at": rise_at, "sum_rmse_rises": rises,
                "learn_s": learn, "infer_s": infer, "rmse": rmse, "rmse_std": rmse_std,
                "mean_std": mean_std, "at": at, "final_rmse": rmse.last(),
                "rmse_spike_after_new_experts": spike,
                "total_learn_s": learn.iter().sum::<f64>(),
            }),
        );
        curves.push((spec.label(), learn, infer, rmse, mean_std));
    }
    let get = |label: &str, k: usize, f: usize| -> f64 {
        curves
            .iter()
            .find(|c| c.0 == label)
            .and_then(|c| [&c.1, &c.2, &c.3][f].get(k.min(n) - 1).copied())
            .unwrap_or(f64::NAN)
    };
    let spike = |label: &str| {
        learners
            .get(label)
            .and_then(|v| v["rmse_spike_after_new_experts"].as_f64())
            .unwrap_or(f64::NAN)
    };
    let total = |label: &str| {
        learners
            .get(label)
            .and_then(|v| v["total_learn_s"].as_f64())
            .unwrap_or(f64::NAN)
    };
    let fastest = curves
        .iter()
        .min_by(|a, b| total(&a.0).total_cmp(&total(&b.0)))
        .map_or(String::new(), |c| c.0.clone());
    let findings = json!({
        "rbcm_exp_learn_ratio_last_over_50": get("rbcm-exp", n, 0) / get("rbcm-exp", 50, 0),
        "gp_exp_learn_ratio_last_over_50": get("gp-exp", n, 0) / get("gp-exp", 50, 0),
        "rmse_spike_with_m_min_25": spike("rbcm-exp"),
        "rmse_spike_with_m_min_1": spike("rbcm-exp-mmin1"),
        "fastest_learner_total_learning_time": fastest,
        "learners_without_confidence": curves.iter().filter(|c| c.4.is_none()).map(|c| c.0.clone()).collect::<Vec<_>>(),
    });
    let report = json!({
        "protocol": "000 §V-A incremental stream",
        "scenario": sc.name, "world_seed": sc.world_seed,
        "seed": args.seed, "reps": args.reps, "streams": k, "pairs_target": args.pairs,
        "pairs": n, "pairs_per_rep": lengths,
        "note": "per-step means over repetitions; times are wall-clock seconds per thread; RMSE against the recorded costs",
        "findings": findings, "learners": learners,
    });
    let p = args.out.join("learn_bench.json");
    fs::write(&p, serde_json::to_string_pretty(&report)? + "\n")
        .with_context(|| format!("{}: cannot write", p.display()))?;
    stream_figure(&curves, &args.out.join("learn_bench.png"))?;
    let ms = |v: f64| v * 1e3;
    let mut s = format!(
        "stream ({} reps on {k} streams, {n} pairs): learn ms/step at n=",
        args.reps
    );
    let ks: Vec<usize> = REPORT_AT.iter().copied().filter(|&k| k <= n).collect();
    s.push_str(
        &ks.iter()
            .map(|k| k.to_string())
            .collect::<Vec<_>>()
            .join("/"),
    );
    for l in ["gp-exp", "rbcm-exp", "igmn"] {
        let v: Vec<String> = ks
            .iter()
            .map(|&k| format!("{:.3}", ms(get(l, k, 0))))
            .collect();
        s.push_str(&format!(" {l} {}", v.join("/")));
    }
    s.push_str(&format!(
        "; RMSE spike after new experts m_min 1 {:.4} vs m_min 25 {:.4}; fastest {fastest}",
        spike("rbcm-exp-mmin1"),
        spike("rbcm-exp")
    ));
    Ok(s)
}

/// A learner's per-step curves: label, learning time, inference time, RMSE, mean std.
type Curve = (String, Vec<f64>, Vec<f64>, Vec<f64>, Option<Vec<f64>>);

/// The four panels of `000` Fig. 5 plus a legend.
fn stream_figure(curves: &[Curve], path: &Path) -> Result<()> {
    let log_us =
        |v: &[f64]| -> Vec<f64> { v.iter().map(|s| (s * 1e6).max(1e-3).log10()).collect() };
    let series = |f: &dyn Fn(&Curve) -> Option<Vec<f64>>| -> Vec<(Vec<f64>, [u8; 3])> {
        curves
            .iter()
            .enumerate()
            .filter_map(|(k, c)| f(c).map(|v| (v, palette(k))))
            .collect()
    };
    let a = line_chart(&series(&|c| Some(log_us(&c.1))), &[], "N", "LOG10 LEARN US");
    let b = line_chart(&series(&|c| Some(log_us(&c.2))), &[], "N", "LOG10 INFER US");
    let c = line_chart(&series(&|c| Some(c.3.clone())), &[], "N", "RMSE");
    let d = line_chart(&series(&|c| c.4.clone()), &[], "N", "MEAN STD");
    let rect = strider_core::CellRect::new(strider_core::Cell::new(0, 0), 1440, 40);
    let mut legend = Canvas::new(rect, 1.0, 1);
    legend.fill(|_| Some([255, 255, 255]));
    for (k, c) in curves.iter().enumerate() {
        let x = 20.0 + (k % 8) as f64 * 175.0;
        label(&mut legend, x, 15.0, &c.0, palette(k));
    }
    compose(&[compose(&[a, b, c, d], 2), legend], 1).save(path)
}

// ---------------------------------------------------------------------------------------------
// The C1 protocol.

/// The learners of the C1 table.
fn c1_learners() -> Vec<LearnerSpec> {
    vec![
        LearnerSpec::Igmn(IgmnParams::default()),
        LearnerSpec::Tree(TreeParams::default()),
        LearnerSpec::Gp {
            kernel: KernelKind::Exponential,
            fit: true,
        },
        LearnerSpec::Rbcm {
            kernel: KernelKind::Exponential,
            m_max: 50,
            m_min: 25,
            fit: true,
        },
    ]
}

/// One C1 trial: pass-1 features (robot's map) and costs, pass-2 features (aerial map) and
/// costs, and how many samples lacked a descriptor.
struct C1Trial {
    train: Vec<(C1Features, f64)>,
    test: Vec<(C1Features, f64)>,
}

/// The aerial scan of the track up to `x_max`: a downward RGB-D camera 2 m above the floor
/// every 0.4 m along the lane's centre line, fused into a fresh map.
fn aerial_map(sc: &Scenario, seed: u64, x_max: f64) -> Result<ElevationMap> {
    let world = &sc.world;
    let hf = Heightfield::from_world(world)?;
    let spec = SensorSpec {
        kind: SensorKind::RgbD {
            hfov_deg: 70.0,
            vfov_deg: 50.0,
            width: 120,
            height: 90,
            tilt_deg: 90.0,
        },
        range: 4.0,
        height: 2.0,
        yaw_deg: 0.0,
        rate_hz: 1.0,
    };
    let sensor = RangeSensor::new(&spec, "aerial")?;
    let noise = ScanNoise::from_params(&SimParams {
        depth_sigma: 0.005,
        depth_k: 0.002,
        color_sigma: 6.0,
        ..sc.sim.clone()
    });
    let ext = world.extent();
    let y = 0.5 * (ext.min.y + ext.max.y);
    let mut map = ElevationMap::new(sc.map.clone());
    let mut x = ext.min.x + 0.2;
    let mut i = 0u64;
    while x < ext.max.x.min(x_max + 1.5) {
        let origin = Point3::new(x, y, 2.0);
        let mut cloud = sensor.scan(&hf, &world.color, origin, 0.0, &noise, i as f64, seed, i);
        // The elevated camera's other white balance.
        for p in &mut cloud.points {
            p.rgb = p.rgb.map(|v| (v as f64 * 0.9).round() as u8);
        }
        map.fuse(&cloud);
        x += 0.4;
        i += 1;
    }
    Ok(map)
}

/// Records one C1 trial on `sc` (module docs) with simulator seeds derived from `seed`; each
/// pass stops after `stop_after` pairs.
fn record_c1(sc: &Scenario, seed: u64, stop_after: usize) -> Result<C1Trial> {
    let Some(tour) = sc.tours.first() else {
        bail!("scenario {} has no tour to drive", sc.name);
    };
    let mut path = vec![sc.start.position()];
    path.extend(tour.waypoints.iter().copied());
    let window = strider_cli::trial::section(sc, "learn-bench")?
        .and_then(|t| t.get("cost_window_s"))
        .and_then(|v| v.as_float())
        .unwrap_or(3.0);
    let energy = || -> Result<Probe> {
        let mut p = EnergyParams::new(window, sc.robot.mass_kg, sc.robot.hotel_load_w);
        p.rate_hz = sc.sim.proprio_rate_hz;
        p.pose_rate_hz = sc.sim.pose_rate_hz;
        Ok(Probe::Energy(EnergyCost::new(p)?))
    };
    let params = C1Params::default();
    let gait = gait_index(sc, "adaptive");
    // Pass 1: the robot's own view.
    let describe = Box::new(move |m: &ElevationMap, p: Point2| {
        let c = m.cell_at(p.x, p.y)?;
        Some(c1_features(m, c, &params))
    });
    let mut s1 = new_sink(sc, true, energy()?, 0.1, describe);
    drive(sc, seed, &path, gait, &mut s1, stop_after)?;
    // Pass 2: another trial, CoT measured while walking, features from the aerial scan.
    let none = Box::new(|_: &ElevationMap, _: Point2| None::<C1Features>);
    let mut s2 = new_sink(sc, false, energy()?, 0.1, none);
    drive(
        sc,
        seed.wrapping_add(1_000_003),
        &path,
        gait,
        &mut s2,
        stop_after,
    )?;
    let x_max = s2
        .samples
        .iter()
        .map(|s| s.position.x)
        .fold(f64::NEG_INFINITY, f64::max);
    let aerial = aerial_map(sc, seed.wrapping_add(2_000_003), x_max)?;
    let train = s1
        .samples
        .iter()
        .filter_map(|s| s.descriptor.map(|d| (d, s.cost)))
        .collect();
    let test = s2
        .samples
        .iter()
        .filter_map(|s| {
            let c = aerial.cell_at(s.position.x, s.position.y)?;
            Some((c1_features(&aerial, c, &params), s.cost))
        })
        .collect();
    Ok(C1Trial { train, test })
}

/// Rows of (descriptor, cost) of one combination; samples missing a part are dropped.
fn c1_rows(
    pairs: &[(C1Features, f64)],
    color: ColorFeature,
    geom: GeomFeature,
) -> (usize, Vec<f64>, Vec<f64>, usize) {
    let (mut x, mut y, mut dim, mut dropped) = (Vec::new(), Vec::new(), 0, 0);
    for (f, c) in pairs {
        match f.descriptor(color, geom) {
            Some(d) => {
                dim = d.len();
                x.extend(d);
                y.push(*c);
            }
            None => dropped += 1,
        }
    }
    (dim, x, y, dropped)
}

/// One cell of the C1 table.
struct TableCell {
    learner: String,
    color: ColorFeature,
    geom: GeomFeature,
    stats: Option<(f64, f64)>,
    n: usize,
    dropped: usize,
}

fn c1_bench(args: &LearnBenchArgs) -> Result<String> {
    let t0 = Instant::now();
    let sc = Scenario::from_name_or_file("cot-track", 1)?;
    let trials: Vec<C1Trial> = (0..args.c1_runs)
        .into_par_iter()
        .map(|r| {
            let stop = if args.c1_pairs == 0 {
                usize::MAX
            } else {
                args.c1_pairs
            };
            record_c1(&sc, args.seed + r as u64, stop)
        })
        .collect::<Result<_>>()?;
    let record_s = t0.elapsed().as_secs_f64();
    let mut units = Vec::new();
    for spec in c1_learners() {
        for &color in &ColorFeature::ALL {
            for &geom in &GeomFeature::ALL {
                if !(color == ColorFeature::None && geom == GeomFeature::None) {
                    units.push((spec.clone(), color, geom));
                }
            }
        }
    }
    let cells: Vec<TableCell> = units
        .par_iter()
        .map(|(spec, color, geom)| -> Result<TableCell> {
            let (mut errors, mut dropped) = (Vec::new(), 0);
            for t in &trials {
                let (d1, x1, y1, k1) = c1_rows(&t.train, *color, *geom);
                let (d2, x2, y2, k2) = c1_rows(&t.test, *color, *geom);
                dropped += k1 + k2;
                let dim = d1.max(d2);
                if dim == 0 || y2.is_empty() {
                    continue;
                }
                let mut xa = x1.clone();
                xa.extend_from_slice(&x2);
                let mut ya = y1.clone();
                ya.extend_from_slice(&y2);
                let prior = if y1.is_empty() {
                    0.0
                } else {
                    y1.iter().sum::<f64>() / y1.len() as f64
                };
                let scale = DataScale::of(dim, &xa, &ya, prior);
                errors.extend(
                    c1_errors(spec, dim, &scale, (&x1, &y1), (&x2, &y2)).with_context(|| {
                        format!("{} {} {}", spec.label(), color.label(), geom.label())
                    })?,
                );
            }
            Ok(TableCell {
                learner: spec.label(),
                color: *color,
                geom: *geom,
                stats: mean_variance(&errors),
                n: errors.len(),
                dropped,
            })
        })
        .collect::<Result<_>>()?;
    let published = |c: &TableCell| {
        PUBLISHED_C1
            .iter()
            .find(|p| p.0 == c.learner && p.1 == c.color.label() && p.2 == c.geom.label())
            .map(|p| (p.3, p.4))
    };
    let best = cells.iter().filter(|c| c.stats.is_some()).min_by(|a, b| {
        let (x, y) = (a.stats.unwrap_or_default(), b.stats.unwrap_or_default());
        x.0.total_cmp(&y.0).then(x.1.total_cmp(&y.1))
    });
    let filled = cells.iter().filter(|c| c.stats.is_some()).count();
    // Markdown.
    let mut md = String::from(
        "# Thesis C1 Table I on `cot-track`: |CoT error| per learner × descriptor\n\n\
Learned on pass 1 (robot's view), predicted on pass 2 (aerial view); incremental learners (IGMN, \
RBCM) also score their query-before-learning predictions on pass 1, as in the thesis.\n\n\
| learner | colour | geometry | mean | variance | n | published mean / variance |\n|---|---|---|---:|---:|---:|---|\n",
    );
    for c in &cells {
        let is_best = best.is_some_and(|b| std::ptr::eq(b, c));
        let (m, v) = c.stats.map_or(("—".into(), "—".into()), |(m, v)| {
            (format!("{m:.2}"), format!("{v:.1}"))
        });
        let b = if is_best { "**" } else { "" };
        md.push_str(&format!(
            "| {b}{}{b} | {} | {} | {b}{m}{b} | {b}{v}{b} | {} | {} |\n",
            c.learner,
            c.color.label(),
            c.geom.label(),
            c.n,
            published(c).map_or(String::new(), |(m, v)| format!("{m} / {v}"))
        ));
    }
    if let Some(b) = best {
        let (m, v) = b.stats.unwrap_or_default();
        md.push_str(&format!(
            "\nBest: **{} {} + {}**, mean {m:.2}, variance {v:.1} (thesis: IGMN RGB-M + Shape, 5.7 / 38.4).\n",
            b.learner,
            b.color.label(),
            b.geom.label()
        ));
    }
    fs::write(args.out.join("c1_table.md"), md).context("cannot write c1_table.md")?;
    let rows: Vec<Value> = cells
        .iter()
        .map(|c| {
            json!({
                "learner": c.learner, "color": c.color.label(), "geometry": c.geom.label(),
                "mean": c.stats.map(|s| s.0), "variance": c.stats.map(|s| s.1),
                "n": c.n, "dropped_samples": c.dropped,
                "published": published(c).map(|(m, v)| json!({"mean": m, "variance": v})),
            })
        })
        .collect();
    let best_json = best.map(|b| {
        json!({"learner": b.learner, "color": b.color.label(), "geometry": b.geom.label(),
               "mean": b.stats.map(|s| s.0), "variance": b.stats.map(|s| s.1)})
    });
    let report = json!({
        "protocol": "thesis C1 Table I (learn on pass 1, predict pass 2 from the aerial view)",
        "scenario": sc.name, "world_seed": sc.world_seed, "seed": args.seed,
        "runs": args.c1_runs,
        "pairs_per_run": trials.iter().map(|t| json!({"pass1": t.train.len(), "pass2": t.test.len()})).collect::<Vec<_>>(),
        "cells": rows, "filled_cells": filled, "total_cells": cells.len(),
        "best": best_json, "published_best": {"learner": "igmn", "color": "RGB-M", "geometry": "Shape", "mean": 5.7, "variance": 38.4},
        "record_s": record_s, "wall_s": t0.elapsed().as_secs_f64(),
    });
    fs::write(
        args.out.join("c1_table.json"),
        serde_json::to_string_pretty(&report)? + "\n",
    )
    .context("cannot write c1_table.json")?;
    Ok(match best {
        Some(b) => {
            let (m, v) = b.stats.unwrap_or_default();
            format!(
                "C1 ({filled}/{} cells, {} runs): best {} {} + {} mean {m:.2} var {v:.1} (paper IGMN RGB-M + Shape 5.7 / 38.4)",
                cells.len(),
                args.c1_runs,
                b.learner,
                b.color.label(),
                b.geom.label()
            )
        }
        None => format!("C1: no cell could be filled ({} cells)", cells.len()),
    })
}
