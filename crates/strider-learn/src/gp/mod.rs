//! Exact Gaussian-process regression with O(n²) insertion and removal of training points.
//!
//! The model is Prágr22 Eq. 14–16 with the kernel of Eq. 21 (and Prágr19 Eq. 5–6, the same
//! predictive equations): for a training set (X, y), prior mean m, kernel k and noise variance
//! σ_n²,
//!
//! * mean μ(x*) = m + k*ᵀ (K + σ_n² I)⁻¹ (y − m)  (Eq. 15: the cost estimate is the mean),
//! * latent variance σ²(x*) = k** − k*ᵀ (K + σ_n² I)⁻¹ k*  (decision 14: without σ_n²),
//! * entropy H = ½ ln(2πe σ²)  (Eq. 16, [`differential_entropy`]).
//!
//! # Why our own
//! The learning set changes one cell at a time (a cell's Kalman estimate changes, a novel
//! measurement arrives), so the model must take one insertion or removal in O(n²) instead of an
//! O(n³) refit, and it must predict whole cost maps fast. No crate offers both: `friedrich`
//! refits (and is a test oracle only), the Python stacks refit as well (DEPENDENCIES.md). So the
//! model keeps, on `faer`:
//!
//! * L, the lower Cholesky factor of K + (σ_n² + jitter) I (row-major with spare rows), and
//! * w = L⁻¹ (y − m).
//!
//! Then μ = m + vᵀw and σ² = k** − vᵀv with v = L⁻¹k*: a prediction is one forward
//! substitution, and so is an insertion ([`Gp::push`]: the new row of L is L⁻¹k_new, its pivot
//! √(k_nn + σ_n² − ‖L⁻¹k_new‖²), and one more entry of w). A removal ([`Gp::remove`]) deletes a
//! row and column of L and applies a rank-1 update to the trailing block (stable: it only adds),
//! then re-solves the tail of w. A change of y alone ([`Gp::set_y`]) leaves L alone and
//! re-solves w from that point on. Batch work ([`Gp::fit`], [`Gp::predict_batch`]) uses faer's
//! blocked Cholesky and triangular solves, in parallel on rayon's pool.
//!
//! # Numerics
//! If K + σ_n² I is not numerically positive definite (duplicate inputs with σ_n² = 0, for
//! instance) a jitter of 10⁻¹⁰ σ_s², 10⁻⁹ σ_s², …, 10⁻⁴ σ_s² is added to the diagonal, the first
//! that works is kept ([`Gp::jitter`]) and later insertions use it too; beyond 10⁻⁴ σ_s² the
//! operation fails with [`GpError::NotPositiveDefinite`] and changes nothing. Latent variances
//! are clamped at ≥ 0. Everything is deterministic: parallel work is split into fixed pieces whose
//! results are combined in a fixed order (faer's parallel factorisation depends on the size of
//! rayon's pool, so results can differ in the last bits between pool sizes).
//!
//! Inputs and targets that are not finite are rejected with an error and never stored.
//!
//! # Per-point noise (Nardi19 Eq. 4)
//! [`Gp::fit_heteroscedastic`] scales the noise of each training point: the diagonal becomes
//! K + σ_n² Ψ with Ψ = diag(ψ_j), ψ_j > 0, which is the component GP of a GP mixture when
//! ψ_j = 1/φ_i(x_j). Every other constructor and [`Gp::push`] use ψ = 1 (the homoscedastic
//! model); [`Gp::replace`] keeps the point's ψ.

//!
//! Files: `params` (hyperparameters, prediction, errors), `update` (changes of the training set
//! and the factorisation), `predict`, `factor` (the Cholesky factor with spare rows), `kernel`,
//! `hyper` (type-II maximum likelihood); this file holds the model, its constructors and
//! accessors.

mod factor;
mod hyper;
mod kernel;
mod params;
mod predict;
mod update;

pub use hyper::{HyperBounds, fit_hyperparameters, log_marginal_likelihood_gradient};
pub use kernel::{Kernel, KernelKind};
pub use params::{GpError, GpParams, Prediction, differential_entropy};

use factor::{Factor, dot};

/// Jitter ladder, in units of σ_s² (the first step is no jitter).
const JITTER_STEPS: [f64; 8] = [0.0, 1e-10, 1e-9, 1e-8, 1e-7, 1e-6, 1e-5, 1e-4];

/// Below this size the batch factorisation runs on one thread.
const PAR_MIN_N: usize = 192;

/// Query columns per block of [`Gp::predict_batch`].
const QUERY_BLOCK: usize = 256;

/// An exact GP regressor with O(n²) insertion, removal and replacement of training points.
///
/// Training points are addressed by index `0..len()`, in insertion order; [`Gp::remove`] shifts
/// the later indices down by one (like `Vec::remove`) and [`Gp::replace`] keeps the index.
#[derive(Clone, Debug)]
pub struct Gp {
    dim: usize,
    params: GpParams,
    inv_l: Vec<f64>,
    /// Raw inputs, storage order (n × dim, row-major).
    x: Vec<f64>,
    /// Inputs divided by the lengthscales, storage order.
    xs: Vec<f64>,
    /// Targets, storage order.
    y: Vec<f64>,
    /// Per-point noise multipliers ψ (σ_n² ψ_j on the diagonal), storage order; 1 unless fitted
    /// with [`Gp::fit_heteroscedastic`].
    psi: Vec<f64>,
    /// Index → storage row (identity until a `replace` moves a point to the last row).
    perm: Vec<usize>,
    factor: Factor,
    /// L⁻¹ (y − m), storage order.
    w: Vec<f64>,
    /// The absolute jitter on the diagonal.
    jitter: f64,
}

impl Gp {
    /// An empty GP over `dim`-dimensional inputs: it predicts the prior (mean m, variance σ_s²).
    pub fn new(dim: usize, params: GpParams) -> Result<Gp, GpError> {
        params.validate(dim)?;
        Ok(Gp {
            dim,
            inv_l: params.kernel.inverse_lengthscales(dim),
            params,
            x: Vec::new(),
            xs: Vec::new(),
            y: Vec::new(),
            psi: Vec::new(),
            perm: Vec::new(),
            factor: Factor::with_capacity(0),
            w: Vec::new(),
            jitter: 0.0,
        })
    }

    /// Fits a GP to n points at once: `x` is n × dim row-major, `y` has n targets. Builds K in
    /// parallel and factorises it with faer's blocked Cholesky (O(n³)).
    pub fn fit(dim: usize, params: GpParams, x: &[f64], y: &[f64]) -> Result<Gp, GpError> {
        Gp::fit_heteroscedastic(dim, params, x, y, &vec![1.0; y.len()])
    }

    /// As [`Gp::fit`] with the noise variance of point j scaled by `noise_scale[j]` = ψ_j > 0:
    /// K + σ_n² Ψ (Nardi19 Eq. 4, where ψ_j = 1/φ_i(x_j) for mixture component i). With every
    /// ψ_j = 1 this is exactly [`Gp::fit`].
    pub fn fit_heteroscedastic(
        dim: usize,
        params: GpParams,
        x: &[f64],
        y: &[f64],
        noise_scale: &[f64],
    ) -> Result<Gp, GpError> {
        let mut gp = Gp::new(dim, params)?;
        if noise_scale.len() != y.len() {
            return Err(GpError::BadDimension(format!(
                "{} noise multipliers for {} targets",
                noise_scale.len(),
                y.len()
            )));
        }
        if let Some(j) = noise_scale
            .iter()
            .position(|v| !(v.is_finite() && *v > 0.0))
        {
            return Err(GpError::BadHyperparameter(format!(
                "noise multiplier {} of point {j} is not a positive finite number",
                noise_scale[j]
            )));
        }
        if x.len() != y.len() * dim {
            return Err(GpError::BadDimension(format!(
                "{} input values for {} targets of dimension {dim}",
                x.len(),
                y.len()
            )));
        }
        for (i, p) in x.chunks_exact(dim).enumerate() {
            check_point(p, i)?;
        }
        for (i, v) in y.iter().enumerate() {
            check_y(*v, gp.params.prior_mean, i)?;
        }
        let n = y.len();
        gp.x = x.to_vec();
        gp.xs = scale_points(x, &gp.inv_l);
        gp.y = y.to_vec();
        gp.psi = noise_scale.to_vec();
        gp.perm = (0..n).collect();
        // Spare rows so that the first insertions after a fit do not move the factor.
        gp.factor = Factor::with_capacity(n + (n / 8).max(32));
        gp.factor.n = n;
        gp.refactor(0)?;
        Ok(gp)
    }

    /// Makes room for `additional` more points, so that the next insertions never move the
    /// factor (it otherwise grows by a quarter when full, an O(n²) copy).
    pub fn reserve(&mut self, additional: usize) {
        let want = self.len() + additional;
        if want > self.factor.ld {
            let n = self.factor.n;
            let mut f = Factor::with_capacity(want);
            f.n = n;
            for j in 0..n {
                f.data[j * want + j..j * want + n].copy_from_slice(self.factor.col_below(j));
            }
            self.factor = f;
        }
    }

    /// The number of training points.
    pub fn len(&self) -> usize {
        self.y.len()
    }

    /// True without training points.
    pub fn is_empty(&self) -> bool {
        self.y.is_empty()
    }

    /// The input dimension.
    pub fn dim(&self) -> usize {
        self.dim
    }

    /// The hyperparameters.
    pub fn params(&self) -> &GpParams {
        &self.params
    }

    /// The jitter currently added to the diagonal (0 unless K + σ_n² I needed it).
    pub fn jitter(&self) -> f64 {
        self.jitter
    }

    /// The input of training point `i`.
    ///
    /// # Panics
    /// If `i >= len()`.
    pub fn x(&self, i: usize) -> &[f64] {
        let p = self.perm[i];
        &self.x[p * self.dim..(p + 1) * self.dim]
    }

    /// The target of training point `i`.
    ///
    /// # Panics
    /// If `i >= len()`.
    pub fn y(&self, i: usize) -> f64 {
        self.y[self.perm[i]]
    }

    /// The noise multiplier ψ of training point `i` (its noise variance is σ_n² ψ; 1 unless set
    /// by [`Gp::fit_heteroscedastic`]).
    ///
    /// # Panics
    /// If `i >= len()`.
    pub fn noise_scale(&self, i: usize) -> f64 {
        self.psi[self.perm[i]]
    }

    /// The log marginal likelihood ln p(y | X) = −½ wᵀw − Σ ln L_ii − (n/2) ln 2π (0 for n = 0).
    pub fn log_marginal_likelihood(&self) -> f64 {
        let n = self.len();
        let logdet: f64 = (0..n).map(|i| self.factor.diag(i).ln()).sum();
        -0.5 * dot(&self.w, &self.w) - logdet - 0.5 * n as f64 * (2.0 * std::f64::consts::PI).ln()
    }

    // ---- internals ----

    fn check_dim(&self, x: &[f64]) -> Result<(), GpError> {
        if x.len() != self.dim {
            return Err(GpError::BadDimension(format!(
                "input of length {} for dimension {}",
                x.len(),
                self.dim
            )));
        }
        Ok(())
    }

    fn check_index(&self, i: usize) -> Result<(), GpError> {
        if i >= self.len() {
            return Err(GpError::IndexOutOfRange {
                index: i,
                len: self.len(),
            });
        }
        Ok(())
    }

    fn diag_value(&self) -> f64 {
        self.params.kernel.signal_variance + self.params.noise_variance + self.jitter
    }

    fn min_pivot2(&self) -> f64 {
        f64::EPSILON * self.diag_value()
    }
}

fn check_point(x: &[f64], i: usize) -> Result<(), GpError> {
    if let Some(k) = x.iter().position(|v| !v.is_finite()) {
        return Err(GpError::NonFinite {
            what: format!("x[{k}] of point {i}"),
        });
    }
    Ok(())
}

/// The largest |y − m| a target may deviate from the prior mean. Solves with K + σ_n² I can
/// amplify a target by up to ~10¹⁶ (a jittered, nearly singular K) and predictions sum n such
/// terms, so 10¹⁰⁰ keeps every intermediate finite with room to spare, while no physical
/// cost, energy or elevation comes near it.
pub const MAX_TARGET_DEVIATION: f64 = 1e100;

fn check_y(y: f64, prior_mean: f64, i: usize) -> Result<(), GpError> {
    if !y.is_finite() {
        return Err(GpError::NonFinite {
            what: format!("y of point {i}"),
        });
    }
    let deviation = (y - prior_mean).abs();
    if deviation.is_nan() || deviation > MAX_TARGET_DEVIATION {
        return Err(GpError::TargetTooLarge {
            point: i,
            value: y,
            prior_mean,
        });
    }
    Ok(())
}

/// Every coordinate of the q × `dim` row-major queries `xs` is finite; otherwise the error names
/// the first bad coordinate and its query.
fn check_queries(xs: &[f64], dim: usize) -> Result<(), GpError> {
    for (j, p) in xs.chunks_exact(dim).enumerate() {
        if let Some(k) = p.iter().position(|v| !v.is_finite()) {
            return Err(GpError::NonFinite {
                what: format!("x[{k}] of query {j}"),
            });
        }
    }
    Ok(())
}

/// Points divided by the lengthscales (row-major, dim = inv_l.len()).
fn scale_points(x: &[f64], inv_l: &[f64]) -> Vec<f64> {
    x.chunks_exact(inv_l.len())
        .flat_map(|p| p.iter().zip(inv_l).map(|(v, il)| v * il))
        .collect()
}

#[cfg(test)]
mod tests;
