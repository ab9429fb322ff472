//! When the robot counts as turning, and when as stuck: shared by the missions and the
//! benchmark tours.

use crate::kernel::MissionError;
use crate::params::MissionParams;
use strider_learn::signals::{FallbackTimer, InverseVelocityCost, TurningTime};

/// Heading rate, rad/s, above which a pose tick counts as turning ([`TurningTime`]): cost
/// samples whose support saw turning measure the path's turns rather than the terrain and are
/// not stored, and windows that saw turning do not trigger the stuck reflex. Well below the
/// profiles' turn rates (0.3–0.5 rad/s), well above the heading drift of straight walking.
pub(crate) const TURNING_RATE: f64 = 0.1;

/// The stuck reflex's test (decision 9), shared by missions and benchmark tours: the signal
/// is stuck over its window and the window saw no turning, since a turn on the spot makes no
/// headway but is the commanded turn's slowness, not the terrain's.
pub(crate) fn reflex_stuck(signal: &InverseVelocityCost, turns: &TurningTime) -> bool {
    signal.is_stuck() && turns.in_window() == 0.0
}

/// The cost signal, the turning time and the stuck reflex's timer of `params`; the turning
/// time covers the stuck test's window and `support_s`, the span a cost sample depends on.
pub(crate) fn stuck_signals(
    params: &MissionParams,
    support_s: f64,
) -> Result<(InverseVelocityCost, TurningTime, FallbackTimer), MissionError> {
    let iv = params.inverse_velocity();
    let turns = TurningTime::new(
        iv.window_s,
        support_s,
        iv.rate_hz,
        TURNING_RATE,
        params.turning_baseline_s,
    )
    .map_err(MissionError::params)?;
    let signal = InverseVelocityCost::new(iv).map_err(MissionError::params)?;
    let fallback = FallbackTimer::new(params.dt_fallback).map_err(MissionError::params)?;
    Ok((signal, turns, fallback))
}
