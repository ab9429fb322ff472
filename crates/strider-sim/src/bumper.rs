//! The haptic bumper of Prágr23 (§5.1, Table 4): a servomotor on a parallelogram hinge that
//! reports *torque*, turned into force by a calibration table interpolated with a cubic spline.
//!
//! The simulator reproduces that chain so the autonomy stack sees what the real bumper reports:
//! the motion model's contact force F (the terrain table's `push_force_n` while pushing through,
//! the robot's maximum push force against a rigid obstacle) is turned into the servo torque
//! τ = s⁻¹(F) through the calibration spline s, the servo's measurement noise is applied to τ
//! (multiplicative, the proprioception noise fraction), and the reading is F̂ = s(τ̂), clamped ≥ 0.
//! Optionally a fraction of readings are spikes (the hinge bouncing, Prágr23 §5.1 "an outlier
//! caused by bumper motion") or NaN (a dropped servo packet), for testing the consumers'
//! robustness.
//!
//! The spline is the monotone piecewise-cubic Hermite interpolant (Fritsch–Carlson) of Table 4:
//! a calibration must be monotone to be inverted, and the natural cubic spline through Table 4
//! overshoots next to the steep limit segment (0.79 → 10 N·m), where it is not.

use serde::{Deserialize, Serialize};

/// Prágr23 Table 4: servo torque (N·m) of the calibration points.
pub const C4_TABLE4_TORQUE_NM: [f64; 7] = [0.0, 0.17, 0.34, 0.51, 0.60, 0.79, 10.0];
/// Prágr23 Table 4: force (N) of the calibration points (the last pair is the table's limit value
/// "used in interpolation; not actually measured").
pub const C4_TABLE4_FORCE_N: [f64; 7] = [0.0, 1.05, 2.02, 3.10, 4.09, 6.34, 100.0];

/// Why a calibration table was rejected.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum CalibrationError {
    /// Fewer than two points, or torque and force columns of different length.
    #[error("a calibration needs at least two (torque, force) pairs of equal count")]
    TooFewPoints,
    /// A value is not finite, or torques/forces are not strictly increasing.
    #[error("calibration torques and forces must be finite and strictly increasing")]
    NotMonotone,
}

/// A monotone cubic calibration spline force = s(torque) and its inverse.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct BumperCalibration {
    torque: Vec<f64>,
    force: Vec<f64>,
    /// Hermite tangents ds/dτ at the knots.
    slope: Vec<f64>,
}

impl Default for BumperCalibration {
    /// Prágr23 Table 4.
    fn default() -> Self {
        Self::c4_table4()
    }
}

impl BumperCalibration {
    /// The calibration of Prágr23 Table 4.
    pub fn c4_table4() -> Self {
        Self::new(&C4_TABLE4_TORQUE_NM, &C4_TABLE4_FORCE_N)
            .unwrap_or_else(|_| unreachable!("Table 4 is monotone"))
    }

    /// A calibration through `(torque[i], force[i])`, both strictly increasing.
    pub fn new(torque: &[f64], force: &[f64]) -> Result<Self, CalibrationError> {
        let n = torque.len();
        if n < 2 || force.len() != n {
            return Err(CalibrationError::TooFewPoints);
        }
        let ok = torque.iter().chain(force).all(|v| v.is_finite())
            && torque.windows(2).all(|w| w[1] > w[0])
            && force.windows(2).all(|w| w[1] > w[0]);
        if !ok {
            return Err(CalibrationError::NotMonotone);
        }
        // Fritsch–Carlson tangents: harmonic mean of the neighbouring secants inside, one-sided
        // three-point estimate at the ends, limited to 3× the secant so the cubic stays monotone.
        let h: Vec<f64> = torque.windows(2).map(|w| w[1] - w[0]).collect();
        let d: Vec<f64> = (0..n - 1)
            .map(|i| (force[i + 1] - force[i]) / h[i])
            .collect();
        let mut m = vec![0.0; n];
        if n == 2 {
            m = vec![d[0], d[0]];
        } else {
            for i in 1..n - 1 {
                let (w1, w2) = (2.0 * h[i] + h[i - 1], h[i] + 2.0 * h[i - 1]);
                m[i] = (w1 + w2) / (w1 / d[i - 1] + w2 / d[i]);
            }
            let end = |h0: f64, h1: f64, d0: f64, d1: f64| {
                let v = ((2.0 * h0 + h1) * d0 - h0 * d1) / (h0 + h1);
                v.clamp(0.0, 3.0 * d0)
            };
            m[0] = end(h[0], h[1], d[0], d[1]);
            m[n - 1] = end(h[n - 2], h[n - 3], d[n - 2], d[n - 3]);
        }
        for i in 0..n - 1 {
            m[i] = m[i].min(3.0 * d[i]);
            m[i + 1] = m[i + 1].min(3.0 * d[i]);
        }
        Ok(Self {
            torque: torque.to_vec(),
            force: force.to_vec(),
            slope: m,
        })
    }

    /// The largest torque of the table (readings are clamped to it).
    pub fn max_torque(&self) -> f64 {
        self.torque[self.torque.len() - 1]
    }

    /// Force (N) for a servo torque (N·m); clamped to the table's range, NaN stays NaN.
    pub fn force(&self, torque: f64) -> f64 {
        if torque.is_nan() {
            return f64::NAN;
        }
        let n = self.torque.len();
        let t = torque.clamp(self.torque[0], self.torque[n - 1]);
        let i = self.torque.partition_point(|&x| x <= t).clamp(1, n - 1) - 1;
        let h = self.torque[i + 1] - self.torque[i];
        let s = (t - self.torque[i]) / h;
        let (s2, s3) = (s * s, s * s * s);
        (2.0 * s3 - 3.0 * s2 + 1.0) * self.force[i]
            + (s3 - 2.0 * s2 + s) * h * self.slope[i]
            + (-2.0 * s3 + 3.0 * s2) * self.force[i + 1]
            + (s3 - s2) * h * self.slope[i + 1]
    }

    /// Servo torque (N·m) that reads as `force` (N): the inverse of the monotone spline by
    /// bisection, clamped to the table's range.
    pub fn torque(&self, force: f64) -> f64 {
        if force.is_nan() {
            return f64::NAN;
        }
        let n = self.torque.len();
        let (mut lo, mut hi) = (self.torque[0], self.torque[n - 1]);
        if force <= self.force[0] {
            return lo;
        }
        if force >= self.force[n - 1] {
            return hi;
        }
        // 64 halvings of a ≤ 10 N·m interval reach the last bit.
        for _ in 0..64 {
            let mid = 0.5 * (lo + hi);
            if self.force(mid) < force {
                lo = mid;
            } else {
                hi = mid;
            }
        }
        0.5 * (lo + hi)
    }
}

/// Noise and faults of the simulated bumper.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct BumperParams {
    /// The servo's torque→force calibration.
    pub calibration: BumperCalibration,
    /// Probability that a reading in contact is a spike (the servo reports `spike_torque_nm`).
    pub spike_probability: f64,
    /// Torque of a spike, N·m.
    pub spike_torque_nm: f64,
    /// Probability that a reading is NaN (a lost servo packet).
    pub nan_probability: f64,
}

impl Default for BumperParams {
    /// Prágr23 Table 4, no faults.
    fn default() -> Self {
        Self {
            calibration: BumperCalibration::c4_table4(),
            spike_probability: 0.0,
            spike_torque_nm: 2.0,
            nan_probability: 0.0,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    #[test]
    fn table4_knots_are_interpolated_exactly() {
        let c = BumperCalibration::c4_table4();
        for (t, f) in C4_TABLE4_TORQUE_NM.iter().zip(C4_TABLE4_FORCE_N) {
            assert!((c.force(*t) - f).abs() < 1e-9, "s({t}) = {}", c.force(*t));
        }
        // The Prágr23 threshold F_trav = 2 N sits near 0.34 N·m.
        assert!((c.torque(2.02) - 0.34).abs() < 1e-9);
    }

    #[test]
    fn bad_tables_are_rejected() {
        assert_eq!(
            BumperCalibration::new(&[0.0], &[0.0]),
            Err(CalibrationError::TooFewPoints)
        );
        assert_eq!(
            BumperCalibration::new(&[0.0, 1.0, 0.5], &[0.0, 1.0, 2.0]),
            Err(CalibrationError::NotMonotone)
        );
        assert_eq!(
            BumperCalibration::new(&[0.0, f64::NAN], &[0.0, 1.0]),
            Err(CalibrationError::NotMonotone)
        );
        assert!(BumperCalibration::c4_table4().force(f64::NAN).is_nan());
    }

    proptest! {
        #[test]
        fn spline_is_monotone_and_invertible(a in 0.0f64..10.0, b in 0.0f64..10.0) {
            let c = BumperCalibration::c4_table4();
            let (lo, hi) = if a <= b { (a, b) } else { (b, a) };
            prop_assert!(c.force(lo) <= c.force(hi) + 1e-12);
            let f = c.force(a);
            prop_assert!((c.torque(f) - a).abs() < 1e-6, "τ(s({a})) = {}", c.torque(f));
        }
    }
}
