//! Prágr18 (thesis contribution C1): the cost of transport learned on one pass of a track and
//! predicted from an aerial view, per learner × descriptor (Table I, §III-C, §IV).
//!
//! On `cot-track` the robot walks the lane once (pass 1) building its map with its own camera
//! and measuring the cost of transport P/(m g v) over 3 s windows (a pair every 0.1 m; C1
//! features of the cell from the robot's map); then a second trial (pass 2, another simulator
//! seed) measures the CoT along the same lane while the descriptors come from an elevated
//! "aerial" scan of the track (a downward camera 2 m up, noisier depth, a 0.9 colour gain for
//! its other white balance). Every learner × descriptor combination (IGMN, regression tree,
//! full GP, RBCM × 24 colour/geometry combinations) learns on pass 1 and predicts pass 2
//! ([`c1_errors`](strider_learn::bench::c1_errors)); the errors of `runs` independent trials are
//! pooled into the mean and variance of |ŷ − y| per cell, written to `c1_table.md` and
//! `c1_table.json`.
//!
//! The GP-family prior mean is the mean CoT of pass 1 (a CoT of 0 is meaningless, and pass 1
//! is what the robot has learned from). The learners see only descriptors and measured costs;
//! the simulator's terrain table is never read here (the recorded costs are both the teaching
//! signal and, as in the paper, the evaluation target). Everything but wall times is a function
//! of the seed.

mod table;

use std::path::PathBuf;
use std::time::Instant;

use anyhow::{Result, bail};
use rayon::prelude::*;
use strider_core::{Point2, Point3};
use strider_learn::signals::{EnergyCost, EnergyParams};
use strider_map::ElevationMap;
use strider_map::c1_descriptors::{C1Features, C1Params, c1_features};
use strider_scenario::{Scenario, SensorKind, SensorSpec, SimParams};
use strider_sim::{Heightfield, RangeSensor, ScanNoise};

use crate::io::{write_json, write_text};
use crate::pairs::{Probe, drive, gait_index, new_sink};
use crate::stats::max;
use crate::trial::section;
pub use table::{C1Best, C1Cell, C1Report, PUBLISHED_C1, PassPairs};

/// The most C1 trials pooled per cell (`--c1-runs`; 3 by default): each is two drives of the
/// lane recorded in memory.
pub const MAX_C1_RUNS: usize = 1000;

/// The most pairs per C1 pass (`--c1-pairs`): the whole lane of cot-track yields far fewer, so
/// larger counts mean the whole lane.
pub const MAX_C1_PAIRS: usize = 100_000;

/// Options of the C1 protocol.
#[derive(Clone, Debug)]
pub struct C1Options {
    /// Independent trials (pass 1 + aerial-view pass 2) pooled per cell.
    pub runs: usize,
    /// Pairs per pass (0: the whole lane, the paper's protocol); fewer cut both passes short.
    pub pairs: usize,
    /// Simulator seed of the first trial (trial i uses seed + i).
    pub seed: u64,
    /// Output directory.
    pub out: PathBuf,
}

impl C1Options {
    /// The command that reproduces the table.
    pub fn command(&self) -> String {
        let pairs = if self.pairs == 0 {
            String::new()
        } else {
            format!(" --c1-pairs {}", self.pairs)
        };
        format!(
            "strider learn bench --protocol c1 --c1-runs {}{pairs} --seed {}",
            self.runs, self.seed
        )
    }

    /// Checks the options before anything runs.
    pub fn check(&self) -> Result<()> {
        if !(1..=MAX_C1_RUNS).contains(&self.runs) {
            bail!(
                "--c1-runs {}: must be an integer from 1 to {MAX_C1_RUNS}",
                self.runs
            );
        }
        if self.pairs > MAX_C1_PAIRS {
            bail!(
                "--c1-pairs {}: must be an integer from 0 (the whole lane) to {MAX_C1_PAIRS}",
                self.pairs
            );
        }
        if self.seed.checked_add(self.runs as u64).is_none() {
            bail!(
                "--seed {} with --c1-runs {}: the last trial's seed would pass {}",
                self.seed,
                self.runs,
                u64::MAX
            );
        }
        Ok(())
    }
}

/// One C1 trial: pass-1 features (robot's map) and costs, pass-2 features (aerial map) and
/// costs.
pub(crate) struct C1Trial {
    pub(crate) train: Vec<(C1Features, f64)>,
    pub(crate) test: Vec<(C1Features, f64)>,
}

/// Runs the C1 protocol; writes `c1_table.md` and `c1_table.json` into `o.out` and returns the
/// report.
pub fn c1_bench(o: &C1Options) -> Result<C1Report> {
    o.check()?;
    let t0 = Instant::now();
    let sc = Scenario::from_name_or_file("cot-track", 1)?;
    let stop = if o.pairs == 0 { usize::MAX } else { o.pairs };
    let trials: Vec<C1Trial> = (0..o.runs)
        .into_par_iter()
        .map(|r| record_c1(&sc, o.seed + r as u64, stop))
        .collect::<Result<_>>()?;
    let record_s = t0.elapsed().as_secs_f64();
    let cells = table::cells(&trials)?;
    let report = C1Report::new(&sc, o, &trials, cells, record_s, t0);
    write_text(&o.out.join("c1_table.md"), &report.markdown(&o.command()))?;
    write_json(&o.out.join("c1_table.json"), &report)?;
    Ok(report)
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

/// The cost-of-transport probe of the scenario's robot over `window` seconds.
fn energy_probe(sc: &Scenario, window: f64) -> Result<Probe> {
    let mut p = EnergyParams::new(window, sc.robot.mass_kg, sc.robot.hotel_load_w);
    p.rate_hz = sc.sim.proprio_rate_hz;
    p.pose_rate_hz = sc.sim.pose_rate_hz;
    Ok(Probe::Energy(EnergyCost::new(p)?))
}

/// Records one C1 trial on `sc` (module docs) with simulator seeds derived from `seed`; each
/// pass stops after `stop_after` pairs.
fn record_c1(sc: &Scenario, seed: u64, stop_after: usize) -> Result<C1Trial> {
    let Some(tour) = sc.tours.first() else {
        bail!("scenario {} has no tour to drive", sc.name);
    };
    let mut path = vec![sc.start.position()];
    path.extend(tour.waypoints.iter().copied());
    let window = section(sc, "learn-bench")?
        .and_then(|t| t.get("cost_window_s"))
        .and_then(|v| v.as_float())
        .unwrap_or(3.0);
    let params = C1Params::default();
    let gait = gait_index(sc, "adaptive");
    // Pass 1: the robot's own view.
    let describe = Box::new(move |m: &ElevationMap, p: Point2| {
        let c = m.cell_at(p.x, p.y)?;
        Some(c1_features(m, c, &params))
    });
    let mut s1 = new_sink(sc, true, energy_probe(sc, window)?, 0.1, describe);
    drive(sc, seed, &path, gait, &mut s1, stop_after)?;
    // Pass 2: another trial, CoT measured while walking, features from the aerial scan.
    let none = Box::new(|_: &ElevationMap, _: Point2| None::<C1Features>);
    let mut s2 = new_sink(sc, false, energy_probe(sc, window)?, 0.1, none);
    let pass2_seed = seed.wrapping_add(1_000_003);
    drive(sc, pass2_seed, &path, gait, &mut s2, stop_after)?;
    let xs: Vec<f64> = s2.samples.iter().map(|s| s.position.x).collect();
    let x_max = max(&xs).unwrap_or(f64::NEG_INFINITY);
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
