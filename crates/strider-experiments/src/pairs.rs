//! Recording (descriptor, cost) pairs in the simulator for the learner benchmarks: the robot
//! drives a path, its own scans build its map, a cost signal turns the proprioceptive stream
//! into costs, and every `spacing` metres a sample is kept with its cell's descriptor.

use anyhow::Result;
use strider_core::interface::{Robot, SensorSink};
use strider_core::{GaitId, Point2, PointCloud, PoseStamped, Proprioception};
use strider_learn::signals::{EnergyCost, RollVarianceCost};
use strider_map::ElevationMap;
use strider_scenario::Scenario;
use strider_sim::Simulator;

/// The cost estimator of a drive.
pub(crate) enum Probe {
    /// Prágr19: roll variance.
    Roll(RollVarianceCost),
    /// Prágr18: cost of transport.
    Energy(EnergyCost),
}

/// Describes the cell at a position on a map (`None`: not describable yet).
pub(crate) type Describe<D> = Box<dyn Fn(&ElevationMap, Point2) -> Option<D>>;

/// A recorded pair before its descriptor is attached: attributed position and measured cost.
pub(crate) struct Sample<D> {
    pub position: Point2,
    pub cost: f64,
    pub descriptor: Option<D>,
}

/// Seconds between the scans fused into the robot's map: every second scan of the 5 Hz camera
/// (the hexapod moves 2 cm meanwhile), which halves the simulation cost and still observes
/// every cell many times before the robot walks over it.
const SCAN_INTERVAL_S: f64 = 0.4;

/// Fuses the clouds into the robot's map (when `fuse`), turns the proprioceptive stream into
/// costs and keeps one sample every `spacing` metres of attributed position, describing its
/// cell with `describe` on the map as it is at that moment.
pub(crate) struct PairSink<D> {
    map: ElevationMap,
    fuse: bool,
    probe: Probe,
    spacing: f64,
    last: Option<Point2>,
    describe: Describe<D>,
    pub samples: Vec<Sample<D>>,
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
pub(crate) fn gait_index(sc: &Scenario, name: &str) -> GaitId {
    GaitId(
        sc.robot
            .gaits
            .iter()
            .position(|g| g.name == name)
            .unwrap_or(0) as u8,
    )
}

pub(crate) fn path_length(path: &[Point2]) -> f64 {
    path.windows(2).map(|w| w[0].dist(w[1])).sum()
}

/// Drives `path` in `gait` with simulator seed `seed`, feeding `sink`, until the path is done or
/// `sink` holds `stop_after` samples.
pub(crate) fn drive<D>(
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

pub(crate) fn new_sink<D>(
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
