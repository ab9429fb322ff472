//! Errors of the simulator: what is wrong and where.

use thiserror::Error;

/// Everything that can go wrong when building or running the simulator.
#[derive(Debug, Error, Clone, PartialEq)]
pub enum SimError {
    /// The robot profile lists no gait.
    #[error("robot profile `{profile}` has no gait; the simulator needs at least one")]
    NoGait {
        /// Profile name.
        profile: String,
    },
    /// The start pose is not on a world cell.
    #[error("start pose ({x:.3}, {y:.3}) lies outside the world (cells {rect})")]
    StartOutsideWorld {
        /// Start x, metres.
        x: f64,
        /// Start y, metres.
        y: f64,
        /// The world's cell rectangle, printed.
        rect: String,
    },
    /// A parameter is not finite or out of its valid range.
    #[error("invalid parameter `{name}` = {value}: {requirement}")]
    InvalidParameter {
        /// Dotted parameter name, e.g. `sim.dt` or `robot.sensors[1].range`.
        name: String,
        /// The offending value.
        value: f64,
        /// What the value must satisfy.
        requirement: &'static str,
    },
    /// A scenario parameter is outside its documented range.
    #[error(transparent)]
    Param(#[from] strider_map::ParamError),
    /// A world layer does not have one entry per cell.
    #[error("world layer `{layer}` has {len} entries, expected {expected} (one per cell)")]
    LayerSize {
        /// Layer name.
        layer: &'static str,
        /// Entries found.
        len: usize,
        /// Cells in the world rectangle.
        expected: usize,
    },
    /// `advance` was asked to run for a negative or non-finite duration.
    #[error("cannot advance by {0} s: the duration must be finite and non-negative")]
    InvalidDuration(f64),
}

/// Checks that `value` is finite and satisfies `ok`, naming it in the error otherwise.
pub(crate) fn check(
    name: impl Into<String>,
    value: f64,
    ok: impl Fn(f64) -> bool,
    requirement: &'static str,
) -> Result<(), SimError> {
    if value.is_finite() && ok(value) {
        Ok(())
    } else {
        Err(SimError::InvalidParameter {
            name: name.into(),
            value,
            requirement,
        })
    }
}
