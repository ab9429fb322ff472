//! The sensor/actuator interface between the autonomy stack and a robot.
//!
//! The stack commands a path and a gait and lets time pass; the robot reports what its sensors
//! produced meanwhile through a [`SensorSink`]. The simulator implements [`Robot`]; so does a
//! replayed log (with commands ignored). Time is the robot's time (simulated or recorded), never
//! wall time.

use crate::geom::Point2;
use crate::msg::{GaitId, PointCloud, PoseStamped, Proprioception};

/// Receives the robot's sensor stream. Every method has an empty default so a consumer
/// implements only what it needs.
pub trait SensorSink {
    /// A pose of the 20 Hz pose stream.
    fn on_pose(&mut self, _pose: &PoseStamped) {}
    /// An RGB-D (or omnidirectional) scan.
    fn on_cloud(&mut self, _cloud: &PointCloud) {}
    /// Whether the consumer wants the next scan of sensor `sensor`. A hint: a simulator skips
    /// producing scans nobody wants (it costs most of a simulation's time), a recorded log or a
    /// real robot may ignore it and deliver every scan. Default: every scan.
    fn wants_cloud(&self, _sensor: u8) -> bool {
        true
    }
    /// Proprioceptive readings.
    fn on_proprioception(&mut self, _p: &Proprioception) {}
}

/// A sink that drops everything.
impl SensorSink for () {}

/// What the robot is doing after a call to [`Robot::advance`].
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct MotionState {
    /// The commanded path has been followed to its end (or no path is commanded).
    pub idle: bool,
    /// The robot refused to enter the next cell of its path (an obstacle it cannot pass).
    pub blocked: bool,
}

/// A robot as the autonomy stack sees it.
pub trait Robot {
    /// What can go wrong while advancing (e.g. a corrupt log).
    type Error: std::error::Error + Send + Sync + 'static;
    /// Current robot time, seconds.
    fn now(&self) -> f64;
    /// Replaces the path being followed (world waypoints, first one nearest the robot).
    fn follow(&mut self, path: &[Point2]);
    /// Selects the gait used from now on.
    fn set_gait(&mut self, gait: GaitId);
    /// Lets `dt` seconds of robot time pass, reporting every message produced meanwhile.
    fn advance(&mut self, dt: f64, sink: &mut dyn SensorSink) -> Result<MotionState, Self::Error>;
}
