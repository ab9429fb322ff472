//! The simulator: a [`Robot`] driven by a [`Scenario`].
//!
//! Time is simulated. [`Simulator::advance`] integrates the motion model on the grid
//! `k · sim.dt` (cut additionally at every message time) and emits, in time order, the pose stream
//! (`pose_rate_hz`), proprioception (`proprio_rate_hz`) and one cloud per sensor at its `rate_hz`;
//! messages due at the same instant come as pose, proprioception, then clouds in sensor order.
//! Stream `n` of rate f is due at time n / f, starting with the messages of time 0.
//!
//! Noise: the pose stream adds N(0, pose_sigma_xy) to x and y and N(0, pose_sigma_yaw) to the
//! heading; clouds are taken from the true pose. Motion, proprioception, pose noise and each scan
//! draw from separate seeded streams (see the crate docs), so the run is a pure function of the
//! scenario, the seed and the sequence of commands.

use rand::RngExt;
use rand::rngs::ChaCha8Rng;
use rand_distr::StandardNormal;
use strider_core::geom::wrap_angle;
use strider_core::interface::{MotionState, Robot, SensorSink};
use strider_core::{GaitId, Point2, Point3, PointCloud, Pose2, PoseStamped};
use strider_scenario::validate::{WORLD_RESOLUTION, check_world_size};
use strider_scenario::{RobotProfile, Scenario, SimParams, World};

use crate::error::{SimError, check};
use crate::heightfield::Heightfield;
use crate::motion::{MotionContext, MotionModel, MotionParams, StepReport};
use crate::proprio::{ProprioModel, ProprioParams};
use crate::seed::{key, stream};
use crate::sensor::{RangeSensor, ScanNoise};
use crate::terrain::TerrainTable;

/// Times closer than this are the same instant, seconds.
const TIME_EPS: f64 = 1e-9;

/// Constants of the simulator's models that the scenario format does not carry.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct ModelParams {
    /// Motion model constants.
    pub motion: MotionParams,
    /// Proprioception model constants.
    pub proprio: ProprioParams,
}

/// What the simulation runs in and never changes: the world, the robot, the parameters and
/// the models derived from them.
#[derive(Debug)]
struct Stage {
    world: World,
    robot: RobotProfile,
    sim: SimParams,
    params: ModelParams,
    heightfield: Heightfield,
    terrain: TerrainTable,
}

impl Stage {
    /// What the motion model reads.
    fn motion(&self) -> MotionContext<'_> {
        MotionContext {
            world: &self.world,
            heightfield: &self.heightfield,
            terrain: &self.terrain,
            robot: &self.robot,
            speed_noise: self.sim.speed_noise,
            params: &self.params.motion,
        }
    }
}

/// The simulated robot in its world.
#[derive(Debug)]
pub struct Simulator {
    stage: Stage,
    seed: u64,
    sensors: Vec<RangeSensor>,
    noise: ScanNoise,
    motion: MotionModel,
    proprio: ProprioModel,
    last_step: StepReport,
    motion_rng: ChaCha8Rng,
    pose_rng: ChaCha8Rng,
    time: f64,
    pose_ticks: u64,
    proprio_ticks: u64,
    sensor_ticks: Vec<u64>,
    scan_counter: u64,
}

impl Simulator {
    /// A simulator of `scenario` with noise seed `seed`, the robot standing at the start pose.
    pub fn new(scenario: &Scenario, seed: u64) -> Result<Self, SimError> {
        Self::with_params(scenario, seed, ModelParams::default())
    }

    /// [`Self::new`] with explicit model constants.
    pub fn with_params(
        scenario: &Scenario,
        seed: u64,
        params: ModelParams,
    ) -> Result<Self, SimError> {
        let world = &scenario.world;
        let robot = &scenario.robot;
        let sim = &scenario.sim;
        validate(scenario)?;
        let heightfield = Heightfield::from_world(world)?;
        let start = scenario.start;
        let ground = heightfield.elevation_at(start.position()).ok_or_else(|| {
            SimError::StartOutsideWorld {
                x: start.x,
                y: start.y,
                rect: describe_rect(world),
            }
        })?;
        let sensors = robot
            .sensors
            .iter()
            .enumerate()
            .map(|(i, s)| RangeSensor::new(s, &format!("robot.sensors[{i}]")))
            .collect::<Result<Vec<_>, _>>()?;
        Ok(Self {
            sensor_ticks: vec![0; sensors.len()],
            sensors,
            noise: ScanNoise::from_params(sim),
            motion: MotionModel::new(Pose2::new(start.x, start.y, wrap_angle(start.yaw)), ground),
            proprio: ProprioModel::new(params.proprio.clone(), stream(seed, &[key::PROPRIO])),
            last_step: StepReport::default(),
            motion_rng: stream(seed, &[key::MOTION]),
            pose_rng: stream(seed, &[key::POSE]),
            time: 0.0,
            pose_ticks: 0,
            proprio_ticks: 0,
            scan_counter: 0,
            stage: Stage {
                world: world.clone(),
                robot: robot.clone(),
                sim: sim.clone(),
                params,
                heightfield,
                terrain: TerrainTable::new(world, robot),
            },
            seed,
        })
    }

    /// The true pose (for the judge and test harnesses only; the autonomy stack sees the pose
    /// stream).
    pub fn pose(&self) -> Pose2 {
        self.motion.pose()
    }

    /// Elevation of the ground under the body, metres.
    pub fn body_z(&self) -> f64 {
        self.motion.ground_z()
    }

    /// Distance walked so far (true), metres.
    pub fn odometer_m(&self) -> f64 {
        self.motion.odometer_m()
    }

    /// The gait in use.
    pub fn gait(&self) -> GaitId {
        GaitId(self.motion.gait() as u8)
    }

    /// The motion state now (as the last [`Robot::advance`] returned it).
    pub fn motion_state(&self) -> MotionState {
        MotionState {
            idle: self.motion.is_idle(),
            blocked: self.motion.is_blocked(),
        }
    }

    /// The waypoints of the commanded path not reached yet.
    pub fn remaining_path(&self) -> &[Point2] {
        self.motion.remaining_path()
    }

    /// The simulated world.
    pub fn world(&self) -> &World {
        &self.stage.world
    }

    /// The robot profile.
    pub fn robot(&self) -> &RobotProfile {
        &self.stage.robot
    }

    /// The world's elevation as ray-castable columns.
    pub fn heightfield(&self) -> &Heightfield {
        &self.stage.heightfield
    }

    /// The range sensors, in profile order.
    pub fn sensors(&self) -> &[RangeSensor] {
        &self.sensors
    }

    /// The model constants in use.
    pub fn params(&self) -> &ModelParams {
        &self.stage.params
    }

    /// Takes one scan per sensor at the current pose and time without moving (advances the scan
    /// counter, so later scans draw fresh noise).
    pub fn scan_now(&mut self) -> Vec<PointCloud> {
        (0..self.sensors.len())
            .map(|i| self.scan(i, self.time))
            .collect()
    }

    /// Scan of sensor `i` at the current pose, stamped `stamp`.
    fn scan(&mut self, i: usize, stamp: f64) -> PointCloud {
        let pose = self.motion.pose();
        let sensor = &self.sensors[i];
        let origin: Point3 = sensor.origin(pose, self.motion.ground_z());
        let mut cloud = sensor.scan(
            &self.stage.heightfield,
            &self.stage.world.color,
            origin,
            pose.yaw,
            &self.noise,
            stamp,
            self.seed,
            self.scan_counter,
        );
        cloud.sensor = i as u8;
        self.scan_counter += 1;
        cloud
    }

    fn pose_message(&mut self, stamp: f64) -> PoseStamped {
        let pose = self.motion.pose();
        let pitch = self.motion.pitch(&self.stage.motion());
        let mut noise = |sigma: f64| {
            if sigma > 0.0 {
                let e: f64 = self.pose_rng.sample(StandardNormal);
                sigma * e
            } else {
                0.0
            }
        };
        let (nx, ny) = (
            noise(self.stage.sim.pose_sigma_xy),
            noise(self.stage.sim.pose_sigma_xy),
        );
        let nyaw = noise(self.stage.sim.pose_sigma_yaw);
        PoseStamped {
            stamp,
            position: Point3::new(pose.x + nx, pose.y + ny, self.motion.ground_z()),
            roll: self.proprio.roll(),
            pitch,
            yaw: wrap_angle(pose.yaw + nyaw),
            gait: self.gait(),
        }
    }

    /// Emits every message due at or before the current time, in stream order, each stamped
    /// with its exact due time.
    fn emit_due(&mut self, sink: &mut dyn SensorSink) {
        let now = self.time + TIME_EPS;
        while self.pose_ticks as f64 / self.stage.sim.pose_rate_hz <= now {
            let msg = self.pose_message(self.pose_ticks as f64 / self.stage.sim.pose_rate_hz);
            sink.on_pose(&msg);
            self.pose_ticks += 1;
        }
        while self.proprio_ticks as f64 / self.stage.sim.proprio_rate_hz <= now {
            let msg = self.proprio.reading(
                self.proprio_ticks as f64 / self.stage.sim.proprio_rate_hz,
                &self.last_step,
                &self.stage.terrain,
                self.motion.gait(),
                self.stage.robot.hotel_load_w,
                self.stage.robot.bumper,
                self.stage.sim.proprio_noise,
            );
            sink.on_proprioception(&msg);
            self.proprio_ticks += 1;
        }
        for i in 0..self.sensors.len() {
            while self.sensor_ticks[i] as f64 / self.sensors[i].spec().rate_hz <= now {
                if sink.wants_cloud(i as u8) {
                    let cloud = self.scan(
                        i,
                        self.sensor_ticks[i] as f64 / self.sensors[i].spec().rate_hz,
                    );
                    sink.on_cloud(&cloud);
                }
                self.sensor_ticks[i] += 1;
            }
        }
    }

    /// The next instant something happens after the current time (motion grid or a message).
    fn next_stop(&self, t_end: f64) -> f64 {
        let dt = self.stage.sim.dt;
        let mut next = ((self.time + TIME_EPS) / dt).floor() * dt + dt;
        next = next.min((self.pose_ticks as f64) / self.stage.sim.pose_rate_hz);
        next = next.min((self.proprio_ticks as f64) / self.stage.sim.proprio_rate_hz);
        for (s, &n) in self.sensors.iter().zip(&self.sensor_ticks) {
            next = next.min(n as f64 / s.spec().rate_hz);
        }
        next.min(t_end).max(self.time)
    }
}

impl Robot for Simulator {
    type Error = SimError;

    fn now(&self) -> f64 {
        self.time
    }

    fn follow(&mut self, path: &[Point2]) {
        self.motion.follow(path);
    }

    /// Selects `gait`; an index outside the profile's gait list is ignored.
    fn set_gait(&mut self, gait: GaitId) {
        if (gait.0 as usize) < self.stage.robot.gaits.len() {
            self.motion.set_gait(gait.0 as usize);
        }
    }

    fn advance(&mut self, dt: f64, sink: &mut dyn SensorSink) -> Result<MotionState, SimError> {
        if !(dt.is_finite() && dt >= 0.0) {
            return Err(SimError::InvalidDuration(dt));
        }
        let t_end = self.time + dt;
        loop {
            self.emit_due(sink);
            if self.time >= t_end - TIME_EPS {
                break;
            }
            let next = self.next_stop(t_end);
            let h = next - self.time;
            if h > 0.0 {
                let ctx = self.stage.motion();
                self.last_step = self.motion.step(&ctx, &mut self.motion_rng, h);
                self.proprio
                    .update(&self.last_step, &self.stage.terrain, self.motion.gait());
            }
            self.time = next;
        }
        self.time = self.time.max(t_end);
        Ok(self.motion_state())
    }
}

/// Checks a scenario before simulating it: each part against its documented ranges (the
/// scenario's own checks; a scenario built in code has not passed [`Scenario::validate`]), one
/// entry per cell in every layer, and the start on the world.
fn validate(s: &Scenario) -> Result<(), SimError> {
    if s.robot.gaits.is_empty() {
        return Err(SimError::NoGait {
            profile: s.robot.name.clone(),
        });
    }
    validate_layers(&s.world)?;
    s.robot.validate()?;
    s.sim.validate()?;
    for t in &s.world.terrains {
        t.validate()?;
    }
    let st = s.start;
    check("start.yaw", st.yaw, |_| true, "must be finite")?;
    let inside = Point2::new(st.x, st.y).is_finite() && s.world.index_at(st.position()).is_some();
    if !inside {
        return Err(SimError::StartOutsideWorld {
            x: st.x,
            y: st.y,
            rect: describe_rect(&s.world),
        });
    }
    Ok(())
}

/// A resolution within its range, a world within the cell limit and one entry per cell in
/// every layer.
fn validate_layers(w: &World) -> Result<(), SimError> {
    WORLD_RESOLUTION.check("world.resolution", w.resolution)?;
    check_world_size(w.rect.width, w.rect.height)?;
    for (layer, len) in [
        ("elevation", w.elevation.len()),
        ("color", w.color.len()),
        ("terrain", w.terrain.len()),
    ] {
        if len != w.rect.len() {
            return Err(SimError::LayerSize {
                layer,
                len,
                expected: w.rect.len(),
            });
        }
    }
    Ok(())
}

/// The world's extent for error messages: cells and metres.
fn describe_rect(w: &World) -> String {
    let r = w.rect;
    let d = w.resolution;
    format!(
        "({}, {})..({}, {}), x {:.3}..{:.3} m, y {:.3}..{:.3} m",
        r.min.i,
        r.min.j,
        r.min.i as i64 + r.width as i64,
        r.min.j as i64 + r.height as i64,
        r.min.i as f64 * d,
        (r.min.i as f64 + r.width as f64) * d,
        r.min.j as f64 * d,
        (r.min.j as f64 + r.height as f64) * d,
    )
}
