//! The hyperparameters of a GP, its predictive distribution and its errors.

use super::kernel::Kernel;

/// Hyperparameters of a GP: kernel, noise variance σ_n² and constant prior mean m.
#[derive(Clone, Debug, PartialEq)]
pub struct GpParams {
    /// The covariance function.
    pub kernel: Kernel,
    /// The observation noise variance σ_n² (decision 10: σ_ε = 0.5, so 0.25).
    pub noise_variance: f64,
    /// The constant prior mean m (decision 12: costs are modelled as y − 1 with m = 0, which is the
    /// same as m = 1 on y).
    pub prior_mean: f64,
}

impl Default for GpParams {
    /// Decisions 10 and 13: SE kernel, l = 0.4, σ_s² = 1, σ_n² = 0.25, m = 0.
    fn default() -> Self {
        GpParams {
            kernel: Kernel::default_se(),
            noise_variance: 0.25,
            prior_mean: 0.0,
        }
    }
}

impl GpParams {
    pub(super) fn validate(&self, dim: usize) -> Result<(), GpError> {
        if dim == 0 {
            return Err(GpError::BadDimension(
                "input dimension must be at least 1".into(),
            ));
        }
        self.kernel.validate(dim)?;
        if !(self.noise_variance.is_finite() && self.noise_variance >= 0.0) {
            return Err(GpError::BadHyperparameter(format!(
                "noise variance {} is not a non-negative finite number",
                self.noise_variance
            )));
        }
        if !self.prior_mean.is_finite() {
            return Err(GpError::BadHyperparameter(format!(
                "prior mean {} is not finite",
                self.prior_mean
            )));
        }
        Ok(())
    }
}

/// A predictive distribution at one input: the mean and the latent variance (without noise).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Prediction {
    /// The predictive mean μ(x*) (Prágr22 Eq. 15: the cost estimate).
    pub mean: f64,
    /// The latent variance σ²(x*) of f(x*), without the observation noise (decision 14); ≥ 0.
    pub latent_variance: f64,
}

impl Prediction {
    /// The variance of a new noisy observation y(x*): latent variance + σ_n² (decision 14: the
    /// novelty gate's 2σ interval uses this).
    pub fn noisy_variance(&self, noise_variance: f64) -> f64 {
        self.latent_variance + noise_variance
    }

    /// The differential entropy of the latent prediction, ½ ln(2πe σ²) (Prágr22 Eq. 16); −∞ for a
    /// zero variance.
    pub fn entropy(&self) -> f64 {
        differential_entropy(self.latent_variance)
    }
}

/// The differential entropy of a normal distribution with the given variance, ½ ln(2πe σ²)
/// (Prágr22 Eq. 16). −∞ for σ² = 0, NaN for a negative or NaN variance.
pub fn differential_entropy(variance: f64) -> f64 {
    0.5 * (2.0 * std::f64::consts::PI * std::f64::consts::E * variance).ln()
}

/// Errors of GP construction, updates and fitting.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum GpError {
    /// An input of the wrong length, a zero input dimension, or output buffers of the wrong size.
    #[error("bad dimension: {0}")]
    BadDimension(String),
    /// A non-finite input coordinate or target (rejected, never stored).
    #[error("{what} is not finite")]
    NonFinite {
        /// What was not finite, e.g. "x\[3\] of point 7" or "y of point 7".
        what: String,
    },
    /// A target so far from the prior mean that solving with it could overflow
    /// (|y − m| > [`MAX_TARGET_DEVIATION`](super::MAX_TARGET_DEVIATION)).
    #[error(
        "y of point {point} = {value:e} is more than 1e100 from the prior mean {prior_mean}; rescale the targets"
    )]
    TargetTooLarge {
        /// The point's index.
        point: usize,
        /// Its target.
        value: f64,
        /// The GP's prior mean.
        prior_mean: f64,
    },
    /// Hyperparameters or bounds out of their domain.
    #[error("bad hyperparameter: {0}")]
    BadHyperparameter(String),
    /// A training-point index ≥ the number of points.
    #[error("index {index} out of range for {len} training points")]
    IndexOutOfRange {
        /// The index asked for.
        index: usize,
        /// The number of training points.
        len: usize,
    },
    /// K + σ_n² I stayed numerically indefinite up to the largest jitter.
    #[error("kernel matrix not positive definite even with jitter {jitter:e} on the diagonal")]
    NotPositiveDefinite {
        /// The largest jitter tried.
        jitter: f64,
    },
}
