//! The stuck reflex's timer.

use super::common::{SignalError, check_positive};

/// The stuck reflex's timer (decision 9): once stuck is detected, the rough-terrain gait is used
/// for Δt_fallback seconds. A stuck report while the fallback is active does not extend it (the
/// fallback gait gets exactly Δt_fallback); if the robot is still stuck when it expires, the next
/// stuck report re-arms it.
#[derive(Clone, Debug, PartialEq)]
pub struct FallbackTimer {
    dt_fallback: f64,
    until: Option<f64>,
    triggers: u64,
}

impl FallbackTimer {
    /// A disarmed timer with duration `dt_fallback` seconds (Prágr22 Table 3 `dt_fallback`: 30 s
    /// small sim, 3 s real robot).
    pub fn new(dt_fallback: f64) -> Result<Self, SignalError> {
        check_positive("dt_fallback", dt_fallback)?;
        Ok(Self {
            dt_fallback,
            until: None,
            triggers: 0,
        })
    }

    /// Updates with the stuck flag at time `now`; returns true while the fallback is active.
    /// A non-finite `now` changes nothing.
    pub fn update(&mut self, now: f64, stuck: bool) -> bool {
        if !now.is_finite() {
            return self.until.is_some();
        }
        if self.until.is_some_and(|u| now >= u) {
            self.until = None;
        }
        if stuck && self.until.is_none() {
            self.until = Some(now + self.dt_fallback);
            self.triggers += 1;
        }
        self.until.is_some()
    }

    /// True while the fallback is active at `now`.
    pub fn is_active(&self, now: f64) -> bool {
        self.until.is_some_and(|u| now < u)
    }

    /// How many times the fallback was armed.
    pub fn triggers(&self) -> u64 {
        self.triggers
    }
}
