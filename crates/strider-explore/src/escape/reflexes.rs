//! The two haptic reflexes of Prágr23 (thesis C4) §5.1.
//!
//! 1. **Push**: when the robot comes within `approach_m` (0.25 m) of an apparent obstacle it
//!    means to pass or sample, it walks straight forward to push through it. The push ends
//!    `leave_s` (10 s) after the robot left the obstacle's vicinity, at the end of the forward
//!    stroke, or by the second reflex.
//! 2. **Sample and retreat**: when the bumper reports more than F_trav (or the robot is refused
//!    before the filtered reading has settled), the robot keeps
//!    pressing for `sample_s` (2 s) so the reading is "not an outlier caused by bumper motion",
//!    then walks backwards for `retreat_s` (8 s) to clear the obstacle.
//!
//! Where the thesis is silent: the forward stroke is `push_length_m` long; a push that is
//! refused without a bumper reading (nothing to press on) or lasts `push_timeout_s` retreats;
//! the retreat target lies v_max · retreat_s behind the robot, and a robot that must turn to walk
//! there (our walking model turns towards its waypoints) is given `retreat_timeout_s` in all.

use strider_core::{Point2, Pose2};

/// Parameters of the reflexes (C4 §5.1).
#[derive(Clone, Debug, PartialEq)]
pub struct ReflexParams {
    /// Distance from the bumper at which the push starts, m (C4: 0.25).
    pub approach_m: f64,
    /// The push ends this long after leaving the obstacle's vicinity, s (C4: 10).
    pub leave_s: f64,
    /// Pressing time before retreating, s (C4: 2).
    pub sample_s: f64,
    /// Backward walking time, s (C4: 8).
    pub retreat_s: f64,
    /// Length of the forward stroke, m.
    pub push_length_m: f64,
    /// A push lasting this long retreats, s.
    pub push_timeout_s: f64,
    /// A retreat ends after this long at the latest, s.
    pub retreat_timeout_s: f64,
    /// Half the bumper's width, m (the corridor ahead in which an obstacle triggers a push).
    pub bumper_half_width: f64,
    /// Half-width of the corridor ahead whose obstacle cells a bumper reading is assigned to,
    /// m: the cells straight ahead of the body, so that a wall beside a curtain being pushed
    /// through is not credited with the curtain's force.
    pub contact_half_width: f64,
}

impl Default for ReflexParams {
    fn default() -> Self {
        Self {
            approach_m: 0.25,
            leave_s: 10.0,
            sample_s: 2.0,
            retreat_s: 8.0,
            push_length_m: 1.0,
            push_timeout_s: 120.0,
            retreat_timeout_s: 30.0,
            bumper_half_width: 0.2,
            contact_half_width: 0.05,
        }
    }
}

/// The phase of a running reflex.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Phase {
    /// Walking forward through the obstacle.
    Push {
        /// Start time, s.
        since: f64,
        /// Last time an obstacle was within reach, s.
        last_near: f64,
    },
    /// Pressing on an obstacle that needs more than F_trav.
    Sample {
        /// End of the sampling, s.
        until: f64,
    },
    /// Walking away.
    Retreat {
        /// Timeout, s.
        until: f64,
    },
}

/// What the robot reports to the reflex each control tick.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ReflexInput {
    /// Robot time, s.
    pub t: f64,
    /// Robot pose.
    pub pose: Pose2,
    /// The filtered bumper force exceeds F_trav.
    pub hard_contact: bool,
    /// An apparent obstacle is within reach ahead (or the bumper is touching one).
    pub near: bool,
    /// The commanded path is finished.
    pub idle: bool,
    /// The robot refused to move on.
    pub blocked: bool,
}

/// What the mission should do.
#[derive(Clone, Debug, PartialEq)]
pub enum ReflexAction {
    /// Keep going.
    Continue,
    /// Follow this path from now on.
    Follow(Vec<Point2>),
    /// The reflex is over; the mission decides again.
    Finished {
        /// The robot pressed on something harder than F_trav.
        sampled: bool,
    },
}

/// The reflex state machine.
#[derive(Clone, Debug, Default)]
pub struct Reflex {
    params: ReflexParams,
    phase: Option<Phase>,
    sampled: bool,
}

impl Reflex {
    /// No reflex running.
    pub fn new(params: ReflexParams) -> Self {
        Self {
            params,
            phase: None,
            sampled: false,
        }
    }

    /// The parameters.
    pub fn params(&self) -> &ReflexParams {
        &self.params
    }

    /// The running phase.
    pub fn phase(&self) -> Option<Phase> {
        self.phase
    }

    /// Whether a reflex runs.
    pub fn is_active(&self) -> bool {
        self.phase.is_some()
    }

    /// Starts a push at `t`; returns the forward stroke to follow.
    pub fn start_push(&mut self, t: f64, pose: Pose2) -> Vec<Point2> {
        self.phase = Some(Phase::Push {
            since: t,
            last_near: t,
        });
        self.sampled = false;
        let (s, c) = pose.yaw.sin_cos();
        let l = self.params.push_length_m;
        vec![pose.position(), Point2::new(pose.x + l * c, pose.y + l * s)]
    }

    /// Advances the state machine; `v_max` sizes the retreat.
    pub fn step(&mut self, i: ReflexInput, v_max: f64) -> ReflexAction {
        let p = &self.params;
        let Some(phase) = self.phase else {
            return ReflexAction::Continue;
        };
        match phase {
            Phase::Push { since, last_near } => {
                if i.hard_contact || i.blocked {
                    // Refused or pressing hard: sample before retreating.
                    self.sampled |= i.hard_contact;
                    self.phase = Some(Phase::Sample {
                        until: i.t + p.sample_s,
                    });
                    ReflexAction::Continue
                } else if i.t - since > p.push_timeout_s {
                    self.retreat(i, v_max)
                } else if i.idle || (!i.near && i.t - last_near > p.leave_s) {
                    self.finish()
                } else {
                    if i.near {
                        self.phase = Some(Phase::Push {
                            since,
                            last_near: i.t,
                        });
                    }
                    ReflexAction::Continue
                }
            }
            Phase::Sample { until } => {
                self.sampled |= i.hard_contact;
                if i.t >= until {
                    self.retreat(i, v_max)
                } else {
                    ReflexAction::Continue
                }
            }
            Phase::Retreat { until } => {
                if i.idle || i.blocked || i.t >= until {
                    self.finish()
                } else {
                    ReflexAction::Continue
                }
            }
        }
    }

    fn retreat(&mut self, i: ReflexInput, v_max: f64) -> ReflexAction {
        let l = v_max.max(0.0) * self.params.retreat_s;
        let (s, c) = i.pose.yaw.sin_cos();
        self.phase = Some(Phase::Retreat {
            until: i.t + self.params.retreat_timeout_s,
        });
        ReflexAction::Follow(vec![Point2::new(i.pose.x - l * c, i.pose.y - l * s)])
    }

    fn finish(&mut self) -> ReflexAction {
        self.phase = None;
        ReflexAction::Finished {
            sampled: self.sampled,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn input(t: f64) -> ReflexInput {
        ReflexInput {
            t,
            pose: Pose2::new(1.0, 1.0, 0.0),
            hard_contact: false,
            near: true,
            idle: false,
            blocked: false,
        }
    }

    #[test]
    fn hard_contact_samples_two_seconds_then_retreats_and_finishes() {
        let mut r = Reflex::new(ReflexParams::default());
        let stroke = r.start_push(0.0, Pose2::new(1.0, 1.0, 0.0));
        assert_eq!(stroke[1], Point2::new(2.0, 1.0));
        assert_eq!(r.step(input(0.1), 0.05), ReflexAction::Continue);
        let hard = ReflexInput {
            hard_contact: true,
            blocked: true,
            ..input(5.0)
        };
        assert_eq!(r.step(hard, 0.05), ReflexAction::Continue);
        assert!(matches!(r.phase(), Some(Phase::Sample { .. })));
        assert_eq!(r.step(input(6.9), 0.05), ReflexAction::Continue);
        let ReflexAction::Follow(back) = r.step(input(7.0), 0.05) else {
            panic!("expected the retreat");
        };
        // 8 s at 0.05 m/s behind the robot.
        assert!((back[0].x - 0.6).abs() < 1e-12 && (back[0].y - 1.0).abs() < 1e-12);
        let done = ReflexInput {
            idle: true,
            ..input(20.0)
        };
        assert_eq!(r.step(done, 0.05), ReflexAction::Finished { sampled: true });
        assert!(!r.is_active());
    }

    #[test]
    fn a_soft_push_ends_ten_seconds_after_leaving_the_obstacle() {
        let mut r = Reflex::new(ReflexParams::default());
        r.start_push(0.0, Pose2::new(0.0, 0.0, 0.0));
        assert_eq!(r.step(input(30.0), 0.05), ReflexAction::Continue);
        let away = |t| ReflexInput {
            near: false,
            ..input(t)
        };
        assert_eq!(r.step(away(35.0), 0.05), ReflexAction::Continue);
        assert_eq!(
            r.step(away(40.1), 0.05),
            ReflexAction::Finished { sampled: false }
        );
    }

    #[test]
    fn a_refused_push_samples_then_retreats() {
        let mut r = Reflex::new(ReflexParams::default());
        r.start_push(0.0, Pose2::new(0.0, 0.0, 0.0));
        let blocked = ReflexInput {
            blocked: true,
            ..input(1.0)
        };
        assert_eq!(r.step(blocked, 0.05), ReflexAction::Continue);
        assert!(matches!(r.phase(), Some(Phase::Sample { .. })));
        assert!(matches!(r.step(input(3.0), 0.05), ReflexAction::Follow(_)));
        assert!(matches!(r.phase(), Some(Phase::Retreat { .. })));
        let done = ReflexInput {
            idle: true,
            ..input(9.0)
        };
        // Nothing above F_trav was felt: not a sampling.
        assert_eq!(
            r.step(done, 0.05),
            ReflexAction::Finished { sampled: false }
        );
    }
}
