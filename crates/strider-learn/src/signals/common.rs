//! What every estimator shares: parameter checks and their error, ring sizing, the counts of
//! skipped samples and the cost sample a signal emits.

use strider_core::geom::Point3;
use strider_core::msg::GaitId;
use thiserror::Error;

#[cfg(doc)]
use super::{InverseVelocityCost, RATIO_CAP, RollVarianceCost};

/// Errors of the signal estimators (invalid construction parameters).
#[derive(Clone, Debug, Error, PartialEq)]
pub enum SignalError {
    /// A parameter is non-finite or outside its valid range.
    #[error("invalid parameter {name} = {value}: {reason}")]
    InvalidParameter {
        /// The parameter's name.
        name: &'static str,
        /// The offending value.
        value: f64,
        /// What was expected.
        reason: &'static str,
    },
}

pub(super) fn check_positive(name: &'static str, value: f64) -> Result<f64, SignalError> {
    if value.is_finite() && value > 0.0 {
        Ok(value)
    } else {
        Err(SignalError::InvalidParameter {
            name,
            value,
            reason: "must be finite and > 0",
        })
    }
}

pub(super) fn check_non_negative(name: &'static str, value: f64) -> Result<f64, SignalError> {
    if value.is_finite() && value >= 0.0 {
        Ok(value)
    } else {
        Err(SignalError::InvalidParameter {
            name,
            value,
            reason: "must be finite and >= 0",
        })
    }
}

/// Ring capacity for a window of `window_s` seconds at up to `rate_hz` samples per second: the
/// window's samples, one before it, and a 25 % margin for rate jitter.
pub(super) fn ring_capacity(window_s: f64, rate_hz: f64) -> usize {
    let n = (window_s * rate_hz * 1.25).ceil();
    // Parameters are validated finite and positive; bound the size against absurd values.
    (n.min(1e7) as usize) + 4
}

/// Counts of input samples an estimator skipped, by reason.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct SkipCounts {
    /// Samples with a non-finite stamp, position or value.
    pub non_finite: u64,
    /// Samples whose stamp did not increase over the previous accepted one.
    pub out_of_order: u64,
    /// Poses of a gait with no configured v_max ([`InverseVelocityCost`] only).
    pub unknown_gait: u64,
    /// Samples that arrived faster than the configured rate and pushed the oldest window sample
    /// out of its ring (the window is then short and nothing is emitted until it refills).
    pub overrun: u64,
}

impl SkipCounts {
    /// Total number of samples that were not used (overruns are used, so not counted here).
    pub fn skipped(&self) -> u64 {
        self.non_finite + self.out_of_order + self.unknown_gait
    }
}

/// A cost measurement attributed to a place: the output of [`InverseVelocityCost`] and
/// [`RollVarianceCost`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CostSample {
    /// Stamp of the pose the value is attributed to (the window's middle pose).
    pub stamp: f64,
    /// Position of that pose; the caller maps it to a cell.
    pub position: Point3,
    /// The gait used throughout the window.
    pub gait: GaitId,
    /// The cost: c of Eq. 20 for [`InverseVelocityCost`], the roll variance (rad²) for
    /// [`RollVarianceCost`].
    pub cost: f64,
    /// The untransformed measurement: the smoothed speed ratio v⁻¹ / v_max⁻¹ for
    /// [`InverseVelocityCost`] (capped at [`RATIO_CAP`]), the roll variance for
    /// [`RollVarianceCost`].
    pub raw: f64,
}
