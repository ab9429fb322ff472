//! Proprioceptive signals: body roll, power draw, vibration and bumper force.
//!
//! * **Roll** follows a zero-mean Gaussian AR(1) (Ornstein–Uhlenbeck) process updated every
//!   motion step h: φ ← a·φ + sqrt(1 − a²)·σ·ε with a = exp(−h/τ). Its stationary variance is σ²,
//!   the terrain's per-gait `roll_variance` while the legs cycle and 0 at rest, so the variance of
//!   a 10-s window of roll samples estimates the terrain's value (Prágr19 cost).
//! * **Power** = (hotel load + P_gait) · (1 + N(0, proprio_noise)), clamped ≥ 0, where P_gait is
//!   the terrain's per-gait `power_w` whenever the legs cycle and 0 at rest. The draw does *not*
//!   scale with the achieved speed: the legs cycle at the gait's cadence whatever the ground lets
//!   the body make of it, so energy per metre grows as 1/speed and a stuck robot burns energy for
//!   no distance (Prágr18 cost of transport, MartinCorke energy).
//! * **Vibration** = terrain `vibration` · (1 + N(0, proprio_noise)), clamped ≥ 0, while the body
//!   moves; 0 when it does not (Nardi19).
//! * **Bumper force** (bumper robots only): the contact force of the motion model (the obstacle's
//!   push force while pushing through it, the robot's maximum push force against an obstacle it
//!   cannot pass) as the Prágr23 bumper reports it ([`crate::bumper`]): servo torque τ = s⁻¹(F)
//!   of the Table 4 calibration spline s, τ · (1 + N(0, proprio_noise)) clamped ≥ 0, reported as
//!   s(τ);
//!   with the configured probabilities a reading in contact is a spike or NaN; 0 when nothing is
//!   touched (Prágr23).

use rand::RngExt;
use rand::rngs::ChaCha8Rng;
use rand_distr::StandardNormal;
use strider_core::Proprioception;

use crate::bumper::BumperParams;
use crate::motion::StepReport;
use crate::terrain::TerrainTable;

/// Tunable constants of the proprioception model.
#[derive(Clone, Debug, PartialEq)]
pub struct ProprioParams {
    /// Correlation time τ of the roll process, seconds.
    pub roll_correlation_s: f64,
    /// The bumper's calibration and faults (Prágr23).
    pub bumper: BumperParams,
}

impl Default for ProprioParams {
    fn default() -> Self {
        Self {
            roll_correlation_s: 0.1,
            bumper: BumperParams::default(),
        }
    }
}

/// The proprioceptive state (the roll process) and its noise stream.
#[derive(Debug)]
pub struct ProprioModel {
    params: ProprioParams,
    roll: f64,
    rng: ChaCha8Rng,
}

impl ProprioModel {
    /// A robot at rest (zero roll) drawing noise from `rng`.
    pub fn new(params: ProprioParams, rng: ChaCha8Rng) -> Self {
        Self {
            params,
            roll: 0.0,
            rng,
        }
    }

    /// Current body roll, radians.
    pub fn roll(&self) -> f64 {
        self.roll
    }

    /// Advances the roll process over the step described by `step` for gait `gait`.
    pub fn update(&mut self, step: &StepReport, table: &TerrainTable, gait: usize) {
        let var = if step.active {
            table.response(step.terrain, gait).roll_variance.max(0.0)
        } else {
            0.0
        };
        let tau = self.params.roll_correlation_s;
        let a = if tau > 0.0 {
            (-step.dt / tau).exp()
        } else {
            0.0
        };
        let e: f64 = self.rng.sample(StandardNormal);
        self.roll = a * self.roll + (1.0 - a * a).sqrt() * var.sqrt() * e;
    }

    /// The readings at time `stamp` after the step `step`.
    #[allow(clippy::too_many_arguments)]
    pub fn reading(
        &mut self,
        stamp: f64,
        step: &StepReport,
        table: &TerrainTable,
        gait: usize,
        hotel_load_w: f64,
        bumper: bool,
        noise: f64,
    ) -> Proprioception {
        let mut noisy = |v: f64| {
            let e: f64 = self.rng.sample(StandardNormal);
            (v * (1.0 + noise * e)).max(0.0)
        };
        let gait_power = if step.active {
            table.response(step.terrain, gait).power_w
        } else {
            0.0
        };
        let power_w = noisy(hotel_load_w + gait_power);
        let vibration = if step.distance > 0.0 {
            noisy(table.vibration(step.terrain))
        } else {
            0.0
        };
        let bumper_force = match step.contact_force {
            Some(f) if bumper => self.bumper_reading(f, noise),
            _ => 0.0,
        };
        Proprioception {
            stamp,
            roll: self.roll,
            power_w,
            vibration,
            bumper_force,
        }
    }

    /// The bumper's report of contact force `f` (see the module docs): through the servo
    /// torque, with multiplicative torque noise and the configured faults. The fault draws are
    /// made only when a fault probability is set, so fault-free runs keep their noise streams.
    fn bumper_reading(&mut self, f: f64, noise: f64) -> f64 {
        let b = &self.params.bumper;
        let cal = &b.calibration;
        let e: f64 = self.rng.sample(StandardNormal);
        let mut tau = (cal.torque(f) * (1.0 + noise * e)).max(0.0);
        if b.nan_probability > 0.0 && self.rng.random_bool(b.nan_probability.clamp(0.0, 1.0)) {
            return f64::NAN;
        }
        if b.spike_probability > 0.0 && self.rng.random_bool(b.spike_probability.clamp(0.0, 1.0)) {
            tau = b.spike_torque_nm.max(0.0);
        }
        cal.force(tau).max(0.0)
    }
}
