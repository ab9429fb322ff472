//! The learner benchmark of Prágr19 §V-A (Fig. 5): an incremental stream on `lab-track`.
//!
//! A stream of (descriptor, cost) pairs is recorded by driving the hexapod over `lab-track` in
//! the simulator, two passes of the scenario's `patches` tour in the adaptive gait, as an
//! operator would: the robot's own RGB-D scans build its map, the roll variance over 10 s
//! (Prágr19) is the cost, attributed to the window's middle pose, and the 5-D descriptor
//! (Prágr19 Eq. 10) of that cell is taken from the map at that moment. Pairs are kept every
//! `(path length − 0.5 m) / pairs` metres (≈ 300 pairs, the paper had 292). K streams are
//! recorded (simulator seeds `seed` … `seed + K − 1`); repetition r runs each learner on stream
//! r mod K with [`run_stream`]: learn one pair, predict all pairs, RMSE against the recorded
//! costs. Prágr19 repeated one data set 100 times to average its timings; repeating each of K
//! streams does the same, and the K streams give the RMSE curve a spread.
//!
//! Learners: RBCM (m_max 50, m_min 25) with the exponential, Matérn 3/2, Matérn 5/2 and RBF
//! kernels, the exponential RBCM without m_min (m_min 1), the full GP (exponential), all with
//! per-expert / per-step hyperparameter fitting (bounded, ≤ 200 iterations), the IGMN and the
//! regression tree. Per step the mean over repetitions of the learning time, inference time,
//! RMSE (and its spread) and mean predictive std go to `learn_bench.json`, the figures at 50,
//! 150 and 300 pairs with the findings of §V-A to `learn_bench.md`, the four curves to
//! `learn_bench.png` (like Prágr19 Fig. 5; times on a log scale). The GP-family prior mean is 0
//! (Prágr19's zero-mean experts; roll variances are small and positive).

use anyhow::{Context, Result, bail};
use rayon::prelude::*;
use strider_core::Point2;
use strider_learn::bench::{DataScale, LearnerSpec, StreamTrace, finite_pairs, run_stream};
use strider_learn::gp::KernelKind;
use strider_learn::igmn::IgmnParams;
use strider_learn::regression_tree::TreeParams;
use strider_learn::signals::{RollVarianceCost, RollVarianceParams};
use strider_map::ElevationMap;
use strider_map::descriptors::shape_lab_descriptor;
use strider_scenario::Scenario;

use super::StreamOptions;
use super::stream_report::{Curve, StreamReport};
use crate::io::{write_json, write_text};
use crate::pairs::{Probe, drive, gait_index, new_sink, path_length};
use crate::trial::section;

/// The learners of the stream protocol.
fn learners() -> Vec<LearnerSpec> {
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

/// Two passes of the scenario's first tour from its start.
fn two_passes(sc: &Scenario) -> Result<Vec<Point2>> {
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
    Ok(path)
}

/// Records the stream on `lab-track` (module docs) with simulator seed `seed`.
fn record_stream(sc: &Scenario, seed: u64, pairs: usize) -> Result<Stream> {
    let path = two_passes(sc)?;
    // A little denser than 300 over the two passes (the first 10 s window yields nothing), then
    // cut at `pairs`: fewer pairs are the stream's beginning (the drive stops once they are in),
    // more pairs a denser sampling of the same passes.
    let spacing = ((path_length(&path) - 1.0) / (1.05 * pairs.max(300) as f64)).max(0.01);
    // The Prágr19 explorer's descriptor neighbourhood and cost window on this scenario.
    let rbcm = strider_explore::registry::find("rbcm-greedy")?
        .configure(section(sc, "rbcm-greedy")?, &[])?;
    let strider_explore::registry::Configured::Rbcm(rbcm) = rbcm else {
        bail!("rbcm-greedy is not configured as the Prágr19 explorer");
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
    let gait = gait_index(sc, "adaptive");
    drive(sc, seed, &path, gait, &mut sink, pairs)?;
    let (mut x, mut y) = (Vec::new(), Vec::new());
    for p in sink.samples.iter().take(pairs) {
        if let Some(d) = &p.descriptor {
            x.extend_from_slice(d);
            y.push(p.cost);
        }
    }
    let (x, y, _) = finite_pairs(5, &x, &y);
    Ok(Stream { x, y })
}

/// Every repetition: every learner on its stream, in order, on one thread; with the stream's
/// length.
fn run_reps(
    specs: &[LearnerSpec],
    streams: &[Stream],
    reps: usize,
) -> Result<Vec<(Vec<StreamTrace>, usize)>> {
    (0..reps)
        .into_par_iter()
        .map(|r| -> Result<(Vec<StreamTrace>, usize)> {
            let s = &streams[r % streams.len()];
            let scale = DataScale::of(5, &s.x, &s.y, 0.0);
            let mut traces = Vec::new();
            for spec in specs {
                let mut l = spec.build(5, &scale)?;
                traces.push(
                    run_stream(l.as_mut(), &s.x, &s.y)
                        .with_context(|| format!("repetition {r}, {}", spec.label()))?,
                );
            }
            Ok((traces, s.y.len()))
        })
        .collect()
}

/// Runs the stream protocol; writes `learn_bench.json`, `learn_bench.md` and `learn_bench.png`
/// into `o.out` and returns the report.
pub fn stream_bench(o: &StreamOptions) -> Result<StreamReport> {
    o.check()?;
    let sc = Scenario::from_name_or_file("lab-track", 1)?;
    let specs = learners();
    let k = o.streams.min(o.reps);
    let streams: Vec<Stream> = (0..k)
        .into_par_iter()
        .map(|i| record_stream(&sc, o.seed + i as u64, o.pairs))
        .collect::<Result<_>>()?;
    if let Some((i, s)) = streams.iter().enumerate().find(|(_, s)| s.y.len() < 2) {
        bail!("stream {i}: the drive produced only {} pairs", s.y.len());
    }
    let reps = run_reps(&specs, &streams, o.reps)?;
    let lengths: Vec<usize> = reps.iter().map(|r| r.1).collect();
    let n = lengths.iter().copied().min().unwrap_or(0);
    let curves: Vec<Curve> = specs
        .iter()
        .enumerate()
        .map(|(i, spec)| Curve::of(spec.label(), &reps, i, n))
        .collect();
    let report = StreamReport::new(&sc, o, k, lengths, &specs, &curves);
    write_json(&o.out.join("learn_bench.json"), &report)?;
    write_text(&o.out.join("learn_bench.md"), &report.markdown())?;
    super::stream_report::figure(&curves, &o.out.join("learn_bench.png"))?;
    Ok(report)
}
