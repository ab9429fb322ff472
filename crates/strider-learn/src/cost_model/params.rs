//! The parameters of a gait cost model and its errors.

use crate::gp::{GpError, GpParams, Kernel, KernelKind};
use crate::igng::IgngParams;

/// Parameters of a gait cost model (Prágr22 Tbl. 3; defaults: the real/small-simulation column).
#[derive(Clone, Debug, PartialEq)]
pub struct CostModelParams {
    /// GP of the regressor R (default: SE, l = 0.4, σ_s² = 1, σ_ε² = 0.25, prior mean 1).
    pub gp: GpParams,
    /// σ_sense², variance of one cost measurement in the cell Kalman filter (Eq. 22).
    pub sigma_sense2: f64,
    /// σ_0², initial variance of a cell's cost filter.
    pub sigma0_2: f64,
    /// n_L^min, learning-set size from which the regressor exists.
    pub n_min: usize,
    /// m_T, learning cells a class needs (strictly more) to count as ground truth (Eq. 24).
    pub m_t: usize,
    /// d_S, cell size of the sampling lattice, metres.
    pub d_s: f64,
    /// c_max, the planning cost of unclassified cells and the upper clamp of predictions.
    pub c_max: f64,
    ///     /// IGNG parameters, including n^IGNG (`batch`); σ^IGNG = 2l is set from the kernel by
    /// [`CostModelParams::new`].
    pub igng: IgngParams,
    /// n_erode^steps, erosion passes (Eq. 25).
    pub erode_steps: usize,
    /// n_dilate^steps, dilation passes (Eq. 26).
    pub dilate_steps: usize,
    /// n_dilate^size, half-width of the dilation window (Eq. 26).
    pub dilate_size: usize,
    /// The most learning pairs the regressor R trains on: the newest ones (by when their cell
    /// was first measured). `None`: all of L, as in Prágr22. The GP's memory grows with the
    /// square of its training set, so a long mission needs a bound; the class counts of
    /// Eq. 24 still count all of L.
    pub max_learning_pairs: Option<usize>,
}

impl Default for CostModelParams {
    fn default() -> Self {
        Self::new(GpParams {
            kernel: Kernel {
                kind: KernelKind::SquaredExponential,
                lengthscales: vec![0.4],
                signal_variance: 1.0,
            },
            noise_variance: 0.25,
            prior_mean: 1.0,
        })
    }
}

impl CostModelParams {
    /// Tbl. 3 defaults around the given GP; σ^IGNG = 2l (decision 17) from its first
    /// lengthscale.
    pub fn new(gp: GpParams) -> Self {
        let l = gp.kernel.lengthscales.first().copied().unwrap_or(0.4);
        let igng = IgngParams::from_lengthscale(l);
        Self {
            gp,
            sigma_sense2: 0.10,
            sigma0_2: 1.0,
            n_min: 25,
            m_t: 10,
            d_s: 0.44,
            c_max: 20.0,
            igng,
            erode_steps: 2,
            dilate_steps: 3,
            dilate_size: 2,
            max_learning_pairs: None,
        }
    }
}

/// Errors of the cost model.
#[derive(Debug, thiserror::Error)]
pub enum CostModelError {
    /// A measured cost that is NaN or infinite.
    #[error("cost measurement {value} at cell ({i}, {j}) is not finite")]
    NonFiniteCost {
        /// The value received.
        value: f64,
        /// Cell column.
        i: i32,
        /// Cell row.
        j: i32,
    },
    /// A descriptor field of another dimension than the model's.
    #[error("descriptor dimension {got} does not match the model's {expected}")]
    Dimension {
        /// The model's dimension.
        expected: usize,
        /// The field's dimension.
        got: usize,
    },
    /// Invalid parameters.
    #[error("invalid cost model parameter: {0}")]
    Params(String),
    /// The GP refused an update.
    #[error(transparent)]
    Gp(#[from] GpError),
}
