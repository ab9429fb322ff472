//! What every strategy's robot does the same way: modules that run at a rate, manoeuvres that
//! run to a deadline, and the look-around at a reached spatial goal.

use super::body::Body;
use super::strategy::Actuators;
use strider_core::interface::MotionState;
use strider_core::{Point2, PoseStamped};

/// A module that runs at a fixed rate of robot time.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Every {
    next: f64,
    period: f64,
}

impl Every {
    /// A module at `hz`, first due at `t0`.
    pub fn new(hz: f64, t0: f64) -> Self {
        Self {
            next: t0,
            period: 1.0 / hz,
        }
    }

    /// True when the module is due at `t`.
    pub fn is_due(&self, t: f64) -> bool {
        t >= self.next
    }

    /// The module ran at `t`: next due one period later.
    pub fn ran(&mut self, t: f64) {
        self.next = t + self.period;
    }

    /// True (and the next run scheduled) when the module is due at `t`.
    pub fn due(&mut self, t: f64) -> bool {
        let due = self.is_due(t);
        if due {
            self.ran(t);
        }
        due
    }
}

/// A manoeuvre in progress (a look-around, a sampling walk): it runs without planning until
/// the robot finishes or refuses its path, or its deadline passes.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Manoeuvre {
    /// Deadline, robot time, s.
    pub until: f64,
}

impl Manoeuvre {
    /// True while the manoeuvre still runs at `t` in motion state `state`.
    pub fn runs(&self, t: f64, state: MotionState) -> bool {
        t < self.until && !state.idle && !state.blocked
    }
}

/// Deadline of a look-around, s after its start: a full turn at the slowest plausible rate,
/// plus the short steps.
pub const LOOK_AROUND_S: f64 = 60.0;

/// The look-around at a reached spatial goal: four waypoints 0.75 cells around the robot, a
/// quarter turn apart, so the robot turns once on the spot. Eq. 11 counts every observable
/// cell within r_sensor whatever the heading, which a sensor with a limited field of view only
/// honours if it looks around.
pub fn look_around(pose: &PoseStamped, cell_size: f64) -> Vec<Point2> {
    let r = 0.75 * cell_size;
    (1..=4)
        .map(|k| {
            let a = pose.yaw + k as f64 * std::f64::consts::FRAC_PI_2;
            Point2::new(pose.position.x + r * a.cos(), pose.position.y + r * a.sin())
        })
        .collect()
}

/// Starts the look-around at a reached spatial goal ([`look_around`]) for a robot whose sensors
/// do not see all around: the manoeuvre, or `None` when the robot sees all around (or has no
/// pose) and nothing was commanded.
pub fn start_look_around(body: &Body, robot: &mut dyn Actuators, t: f64) -> Option<Manoeuvre> {
    if body.sees_all_around() {
        return None;
    }
    let pose = body.pose()?;
    robot.follow(&look_around(&pose, body.map().cell_size()));
    Some(Manoeuvre {
        until: t + LOOK_AROUND_S,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use strider_core::{GaitId, Point3};

    #[test]
    fn every_runs_once_per_period() {
        let mut e = Every::new(2.0, 10.0);
        assert!(!e.due(9.9));
        assert!(e.due(10.0));
        assert!(!e.due(10.4));
        assert!(e.due(10.5));
    }

    #[test]
    fn look_around_circles_the_robot() {
        let pose = PoseStamped {
            stamp: 0.0,
            position: Point3::new(1.0, 2.0, 0.0),
            roll: 0.0,
            pitch: 0.0,
            yaw: 0.3,
            gait: GaitId(0),
        };
        let pts = look_around(&pose, 0.1);
        assert_eq!(pts.len(), 4);
        for p in &pts {
            assert!(((p.x - 1.0).hypot(p.y - 2.0) - 0.075).abs() < 1e-12);
        }
        let m = Manoeuvre { until: 5.0 };
        let moving = MotionState {
            idle: false,
            blocked: false,
        };
        assert!(m.runs(4.9, moving));
        assert!(!m.runs(5.0, moving));
        assert!(!m.runs(
            1.0,
            MotionState {
                idle: true,
                blocked: false
            }
        ));
    }
}
