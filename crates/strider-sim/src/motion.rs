//! The robot's motion along a commanded polyline, judged against the world.
//!
//! Each integration step of length h:
//!
//! 1. Waypoints within half a cell of the centre count as reached and are dropped.
//! 2. With the heading error to the next waypoint above [`MotionParams::turn_in_place_deg`], the
//!    robot turns in place at `turn_rate`; otherwise it turns by at most `turn_rate · h` and walks
//!    forward (never past the waypoint).
//! 3. Speed v = v_max(gait) · f · (1 + N(0, speed_noise)), clamped ≥ 0, where f is the speed
//!    factor of the gait on the terrain under the centre. On `stuck` terrain f is
//!    [`MotionParams::stuck_speed_fraction`] and v never exceeds 2 % of v_max. While pushing
//!    through a pushable obstacle f is multiplied by [`MotionParams::push_speed_factor`].
//! 4. Every cell the centre would cross is checked: a cell outside the world, or whose step from
//!    the ground the robot stands on exceeds `max_step_m`, is refused (the robot does not move and
//!    reports *blocked*) unless its terrain's `push_force_n` is at most the robot's
//!    `max_push_force_n` (Prágr23 curtains): then the robot pushes through it, still standing on
//!    the ground it came from.
//!
//! Contact force (read by a bumper): the obstacle's `push_force_n` while pushing through it; the
//! robot's `max_push_force_n` while pressing in vain against a rigid obstacle or one that needs
//! more force than the robot has (it pushes as hard as it can); none when free or at the edge of
//! the world.
//!
//! The body stands on the terrain under its centre (z = that cell's elevation; inside a pushable
//! obstacle, the ground it came from). Only the centre is checked against steps: the map's
//! configuration-space inflation keeps the footprint clear, the simulator only judges the centre.

use rand::RngExt;
use rand::rngs::ChaCha8Rng;
use rand_distr::StandardNormal;
use strider_core::geom::wrap_angle;
use strider_core::grid::CellRay;
use strider_core::{Cell, Point2, Pose2};
use strider_scenario::{RobotProfile, World};

use crate::heightfield::Heightfield;
use crate::terrain::TerrainTable;

/// Tunable constants of the motion model (the scenario format has no place for them yet).
#[derive(Clone, Debug, PartialEq)]
pub struct MotionParams {
    /// Heading error above which the robot turns in place, degrees.
    pub turn_in_place_deg: f64,
    /// Nominal speed on stuck terrain as a fraction of the gait's maximum (before noise; the
    /// result is clamped to ≤ 2 %).
    pub stuck_speed_fraction: f64,
    /// Speed-factor multiplier while pushing through a pushable obstacle.
    pub push_speed_factor: f64,
}

impl Default for MotionParams {
    fn default() -> Self {
        Self {
            turn_in_place_deg: 20.0,
            stuck_speed_fraction: 0.015,
            push_speed_factor: 0.3,
        }
    }
}

/// Hard ceiling of the speed on stuck terrain, fraction of the gait's maximum (a property of the
/// simulated world, not of any method).
pub const STUCK_SPEED_CEILING: f64 = 0.02;

/// Everything the motion model reads from the world (borrowed for one step).
#[derive(Clone, Copy)]
pub struct MotionContext<'a> {
    /// The world layers (terrain index per cell).
    pub world: &'a World,
    /// The elevation as columns.
    pub heightfield: &'a Heightfield,
    /// Resolved terrain table.
    pub terrain: &'a TerrainTable,
    /// The robot profile (gaits, turn rate, max step, push force, footprint).
    pub robot: &'a RobotProfile,
    /// Multiplicative speed noise, standard deviation.
    pub speed_noise: f64,
    /// Motion constants.
    pub params: &'a MotionParams,
}

/// What happened during one integration step.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct StepReport {
    /// Duration of the step, seconds.
    pub dt: f64,
    /// Distance the centre moved, metres.
    pub distance: f64,
    /// The legs were cycling (walking, turning, pushing, stuck, or pressing on an obstacle).
    pub active: bool,
    /// The robot refused to enter a cell.
    pub blocked: bool,
    /// Nominal force on the front of the robot, newtons (push force of the obstacle being pushed
    /// through, or the robot's maximum push force against one it cannot pass); `None` when
    /// nothing is touched.
    pub contact_force: Option<f64>,
    /// Terrain index under the centre at the end of the step.
    pub terrain: u8,
}

/// The robot's kinematic state and the path it follows.
#[derive(Clone, Debug)]
pub struct MotionModel {
    pose: Pose2,
    /// Elevation of the ground the robot stands on (the last non-obstacle cell entered).
    ground_z: f64,
    path: Vec<Point2>,
    next: usize,
    gait: usize,
    blocked: bool,
    odometer: f64,
}

impl MotionModel {
    /// A robot standing still at `pose` on ground of elevation `ground_z`.
    pub fn new(pose: Pose2, ground_z: f64) -> Self {
        Self {
            pose,
            ground_z,
            path: Vec::new(),
            next: 0,
            gait: 0,
            blocked: false,
            odometer: 0.0,
        }
    }

    /// True pose.
    pub fn pose(&self) -> Pose2 {
        self.pose
    }

    /// Elevation of the ground under the body, metres.
    pub fn ground_z(&self) -> f64 {
        self.ground_z
    }

    /// Index of the gait in use.
    pub fn gait(&self) -> usize {
        self.gait
    }

    /// Selects the gait (index into the profile's gaits; the caller validates it).
    pub fn set_gait(&mut self, gait: usize) {
        self.gait = gait;
    }

    /// Replaces the path (an empty path stops the robot) and clears the blocked flag.
    pub fn follow(&mut self, path: &[Point2]) {
        self.path = path.iter().copied().filter(|p| p.is_finite()).collect();
        self.next = 0;
        self.blocked = false;
    }

    /// The waypoints not reached yet.
    pub fn remaining_path(&self) -> &[Point2] {
        &self.path[self.next.min(self.path.len())..]
    }

    /// No waypoint left to reach.
    pub fn is_idle(&self) -> bool {
        self.next >= self.path.len()
    }

    /// The last step refused to enter a cell.
    pub fn is_blocked(&self) -> bool {
        self.blocked
    }

    /// Distance walked so far, metres.
    pub fn odometer_m(&self) -> f64 {
        self.odometer
    }

    /// Terrain index under `p`; `None` outside the world.
    fn terrain_at(ctx: &MotionContext, p: Point2) -> Option<u8> {
        ctx.world.index_at(p).map(|k| ctx.world.terrain[k])
    }

    /// Push force of the cell containing `p` when it is an obstacle (relative to the ground the
    /// robot stands on) that this robot can push through.
    fn pushable_obstacle(&self, ctx: &MotionContext, p: Point2) -> Option<f64> {
        let c = Cell::containing(p.x, p.y, ctx.heightfield.resolution())?;
        let k = ctx.world.rect.index(c)?;
        let z = ctx.heightfield.cell_elevation(c)?;
        let f = can_push(ctx, ctx.world.terrain[k])?;
        ((z - self.ground_z).abs() > ctx.robot.max_step_m).then_some(f)
    }

    /// The front bumper point (the footprint's edge straight ahead).
    fn bumper_point(&self, ctx: &MotionContext) -> Point2 {
        let r = ctx.robot.footprint_radius.max(0.0);
        Point2::new(
            self.pose.x + r * self.pose.yaw.cos(),
            self.pose.y + r * self.pose.yaw.sin(),
        )
    }

    /// Push force while the centre or the bumper is inside a pushable obstacle.
    fn pushing(&self, ctx: &MotionContext) -> Option<f64> {
        self.pushable_obstacle(ctx, self.pose.position())
            .or_else(|| self.pushable_obstacle(ctx, self.bumper_point(ctx)))
    }

    /// Body pitch from the terrain slope along the heading, radians (positive: nose down),
    /// measured over the footprint diameter; obstacle cells (steps above `max_step_m`) and cells
    /// outside the world count as the ground under the body.
    pub fn pitch(&self, ctx: &MotionContext) -> f64 {
        let l = ctx.robot.footprint_radius.max(ctx.heightfield.resolution());
        let (s, c) = self.pose.yaw.sin_cos();
        let z = |sign: f64| {
            let p = Point2::new(self.pose.x + sign * l * c, self.pose.y + sign * l * s);
            match ctx.heightfield.elevation_at(p) {
                Some(z) if (z - self.ground_z).abs() <= ctx.robot.max_step_m => z,
                _ => self.ground_z,
            }
        };
        -((z(1.0) - z(-1.0)) / (2.0 * l)).atan()
    }

    /// Integrates one step of `h` seconds.
    pub fn step(&mut self, ctx: &MotionContext, rng: &mut ChaCha8Rng, h: f64) -> StepReport {
        let d = ctx.heightfield.resolution();
        let mut report = StepReport {
            dt: h,
            terrain: Self::terrain_at(ctx, self.pose.position()).unwrap_or(0),
            ..StepReport::default()
        };
        while self.next < self.path.len()
            && self.pose.position().dist(self.path[self.next]) <= d / 2.0
        {
            self.next += 1;
        }
        if self.is_idle() {
            self.blocked = false;
            return report;
        }
        report.active = true;
        let target = self.path[self.next];
        let pos = self.pose.position();
        let bearing = (target.y - pos.y).atan2(target.x - pos.x);
        let err = wrap_angle(bearing - self.pose.yaw);
        let max_turn = ctx.robot.turn_rate.max(0.0) * h;
        self.pose.yaw = wrap_angle(self.pose.yaw + err.clamp(-max_turn, max_turn));
        if err.abs() > ctx.params.turn_in_place_deg.to_radians() {
            self.blocked = false;
            report.contact_force = self.pushing(ctx);
            return report;
        }

        // Speed on the terrain under the centre.
        let gait = &ctx.robot.gaits[self.gait.min(ctx.robot.gaits.len() - 1)];
        let resp = ctx.terrain.response(report.terrain, self.gait);
        let push = self.pushing(ctx);
        let mut factor = if resp.stuck {
            ctx.params.stuck_speed_fraction
        } else {
            resp.speed_factor
        };
        if push.is_some() {
            factor *= ctx.params.push_speed_factor;
        }
        let e: f64 = rng.sample(StandardNormal);
        let mut v = (gait.max_speed * factor * (1.0 + ctx.speed_noise * e)).max(0.0);
        if resp.stuck {
            v = v.min(STUCK_SPEED_CEILING * gait.max_speed);
        }
        let s = (v * h).min(pos.dist(target));
        if s.is_nan() || s <= 0.0 {
            report.contact_force = push;
            return report;
        }
        let (sy, cy) = self.pose.yaw.sin_cos();
        let new = Point2::new(pos.x + s * cy, pos.y + s * sy);

        // Judge every cell the centre crosses.
        let mut ground = self.ground_z;
        for c in CellRay::new(pos, new, d).skip(1) {
            let refused = match (ctx.world.rect.index(c), ctx.heightfield.cell_elevation(c)) {
                (Some(k), Some(z)) => {
                    if (z - ground).abs() <= ctx.robot.max_step_m {
                        ground = z;
                        None
                    } else if can_push(ctx, ctx.world.terrain[k]).is_some() {
                        None // pushed through, still standing on `ground`
                    } else {
                        Some(Some(ctx.robot.max_push_force_n.max(0.0)))
                    }
                }
                _ => Some(None), // the edge of the world (or a hole): nothing to press on
            };
            if let Some(force) = refused {
                self.blocked = true;
                report.blocked = true;
                report.contact_force = force;
                return report;
            }
        }
        self.blocked = false;
        self.pose.x = new.x;
        self.pose.y = new.y;
        self.ground_z = ground;
        self.odometer += s;
        report.distance = s;
        report.terrain = Self::terrain_at(ctx, new).unwrap_or(report.terrain);
        report.contact_force = self.pushing(ctx);
        report
    }
}

/// The push force of terrain `t` when the robot is strong enough to push through it.
fn can_push(ctx: &MotionContext, t: u8) -> Option<f64> {
    ctx.terrain
        .push_force(t)
        .filter(|&f| f <= ctx.robot.max_push_force_n)
}
