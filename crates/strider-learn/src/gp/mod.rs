//! Exact Gaussian-process regression with O(n²) insertion and removal of training points.
//!
//! The model is `001` Eq. 14–16 with the kernel of Eq. 21 (and `000` Eq. 5–6, the same
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
//! # Per-point noise (`004` Eq. 4)
//! [`Gp::fit_heteroscedastic`] scales the noise of each training point: the diagonal becomes
//! K + σ_n² Ψ with Ψ = diag(ψ_j), ψ_j > 0, which is the component GP of a GP mixture when
//! ψ_j = 1/φ_i(x_j). Every other constructor and [`Gp::push`] use ψ = 1 (the homoscedastic
//! model); [`Gp::replace`] keeps the point's ψ.

mod factor;
mod hyper;
mod kernel;

pub use hyper::{HyperBounds, fit_hyperparameters, log_marginal_likelihood_gradient};
pub use kernel::{Kernel, KernelKind};

use factor::{Factor, dot};
use faer::Par;
use faer::linalg::triangular_solve::solve_lower_triangular_in_place;
use kernel::{k_of_r2, sq_dist};
use rayon::prelude::*;

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
    fn validate(&self, dim: usize) -> Result<(), GpError> {
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
    /// The predictive mean μ(x*) (`001` Eq. 15: the cost estimate).
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

    /// The differential entropy of the latent prediction, ½ ln(2πe σ²) (`001` Eq. 16); −∞ for a
    /// zero variance.
    pub fn entropy(&self) -> f64 {
        differential_entropy(self.latent_variance)
    }
}

/// The differential entropy of a normal distribution with the given variance, ½ ln(2πe σ²)
/// (`001` Eq. 16). −∞ for σ² = 0, NaN for a negative or NaN variance.
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
    /// K + σ_n² Ψ (`004` Eq. 4, where ψ_j = 1/φ_i(x_j) for mixture component i). With every
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
            check_y(*v, i)?;
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

    /// Adds a training point in O(n²): one forward substitution extends L by a row and w by an
    /// entry. If the new pivot is not positive the jitter escalates and the factor is rebuilt
    /// (O(n³), rare); if that fails too, nothing changes and the error is returned.
    pub fn push(&mut self, x: &[f64], y: f64) -> Result<(), GpError> {
        self.check_dim(x)?;
        check_point(x, self.len())?;
        check_y(y, self.len())?;
        self.push_storage(x, y, 1.0)?;
        self.perm.push(self.len() - 1);
        Ok(())
    }

    /// Adds training points (`xs`: k × dim row-major, `ys`: k targets) in order, as k calls of
    /// [`Gp::push`] would, but with one blocked triangular solve V = L⁻¹K(X, X_new) for all of
    /// them (compute-bound, where k separate forward substitutions each stream L through
    /// memory) and a k × k Cholesky of the Schur complement for their own rows. A point whose
    /// pivot is not positive, and every later one, goes through [`Gp::push`] (jitter
    /// escalation). Atomic: on a bad point or length, or when even the jitter ladder cannot
    /// make a point fit, nothing changes (callers keep their own index of the points).
    pub fn extend(&mut self, xs: &[f64], ys: &[f64]) -> Result<(), GpError> {
        let (d, n, k) = (self.dim, self.len(), ys.len());
        if xs.len() != k * d {
            return Err(GpError::BadDimension(format!(
                "{} input values for {} targets of dimension {}",
                xs.len(),
                k,
                d
            )));
        }
        for (j, (x, &y)) in xs.chunks_exact(d).zip(ys).enumerate() {
            check_point(x, n + j)?;
            check_y(y, n + j)?;
        }
        if k == 0 {
            return Ok(());
        }
        let kind = self.params.kernel.kind;
        let s2 = self.params.kernel.signal_variance;
        let new_q = scale_points(xs, &self.inv_l);
        // V = L⁻¹ K(X, X_new), column-major n × k.
        let mut v = vec![0.0; n * k];
        if n > 0 {
            v.par_chunks_mut(n)
                .zip(new_q.par_chunks(d))
                .for_each(|(col, qj)| {
                    for (c, xi) in col.iter_mut().zip(self.xs.chunks_exact(d)) {
                        *c = k_of_r2(kind, s2, sq_dist(xi, qj));
                    }
                });
            let vm = faer::MatMut::from_column_major_slice_mut(&mut v, n, k);
            solve_lower_triangular_in_place(self.factor.view(), vm, Par::rayon(0));
        }
        // Rows of the new points, one at a time: row j = [V[:, j], L22[j, ..j]] and its pivot,
        // exactly the forward substitution a push would do.
        let sn2 = self.params.noise_variance;
        let min_pivot2 = self.min_pivot2();
        let mut l22: Vec<Vec<f64>> = Vec::with_capacity(k);
        for j in 0..k {
            let vj = &v[j * n..(j + 1) * n];
            let qj = &new_q[j * d..(j + 1) * d];
            let mut tail = Vec::with_capacity(j + 1);
            for (i, li) in l22.iter().enumerate() {
                let vi = &v[i * n..(i + 1) * n];
                let kij = k_of_r2(kind, s2, sq_dist(&new_q[i * d..(i + 1) * d], qj));
                let r = (kij - dot(vi, vj) - dot(&li[..i], &tail[..i])) / li[i];
                tail.push(r);
            }
            let pivot2 = s2 + sn2 + self.jitter - dot(vj, vj) - dot(&tail, &tail);
            if !(pivot2.is_finite() && pivot2 > min_pivot2) {
                // Commit the rows so far, then the rest one by one (jitter escalation). Rare:
                // the copy that keeps a failure atomic is affordable here.
                let saved = self.clone();
                self.commit_rows(&v, n, &l22, &xs[..j * d], &ys[..j], &new_q[..j * d]);
                for (x, &y) in xs[j * d..].chunks_exact(d).zip(&ys[j..]) {
                    if let Err(e) = self.push(x, y) {
                        *self = saved;
                        return Err(e);
                    }
                }
                return Ok(());
            }
            tail.push(pivot2.sqrt());
            l22.push(tail);
        }
        self.commit_rows(&v, n, &l22, xs, ys, &new_q);
        Ok(())
    }

    /// Appends the rows computed by [`Gp::extend`] (V's columns and L22's rows) with their
    /// points, extending w by forward substitution.
    fn commit_rows(
        &mut self,
        v: &[f64],
        n: usize,
        l22: &[Vec<f64>],
        xs: &[f64],
        ys: &[f64],
        new_q: &[f64],
    ) {
        let m = self.params.prior_mean;
        let mut row = Vec::with_capacity(n + l22.len());
        for (j, (lj, &y)) in l22.iter().zip(ys).enumerate() {
            row.clear();
            row.extend_from_slice(&v[j * n..(j + 1) * n]);
            row.extend_from_slice(&lj[..j]);
            let piv = lj[j];
            let wn = (y - m - dot(&row, &self.w)) / piv;
            self.factor.push_row(&row, piv);
            self.w.push(wn);
            self.y.push(y);
            self.psi.push(1.0);
            self.perm.push(self.len() - 1);
        }
        let k = l22.len();
        self.x.extend_from_slice(&xs[..k * self.dim]);
        self.xs.extend_from_slice(&new_q[..k * self.dim]);
    }

    /// Removes training point `i` in O(n²) (rank-1 update of the trailing block of L); the later
    /// indices shift down by one.
    pub fn remove(&mut self, i: usize) -> Result<(), GpError> {
        self.check_index(i)?;
        let p = self.perm.remove(i);
        for q in &mut self.perm {
            if *q > p {
                *q -= 1;
            }
        }
        self.remove_storage(p);
        Ok(())
    }

    /// Replaces training point `i` (same index afterwards). A change of `y` alone is
    /// [`Gp::set_y`]; otherwise a removal and an insertion, O(n²) together. On error nothing
    /// changes.
    pub fn replace(&mut self, i: usize, x: &[f64], y: f64) -> Result<(), GpError> {
        self.check_index(i)?;
        self.check_dim(x)?;
        check_point(x, i)?;
        check_y(y, i)?;
        if self.x(i) == x {
            return self.set_y(i, y);
        }
        let p = self.perm[i];
        let old_x = self.x(i).to_vec();
        let old_y = self.y[p];
        let psi = self.psi[p];
        for q in &mut self.perm {
            if *q > p {
                *q -= 1;
            }
        }
        self.remove_storage(p);
        let last = self.len();
        match self.push_storage(x, y, psi) {
            Ok(()) => {
                self.perm[i] = last;
                Ok(())
            }
            Err(e) => {
                // Put the old point back (it fitted before, with the same jitter).
                self.push_storage(&old_x, old_y, psi)?;
                self.perm[i] = last;
                Err(e)
            }
        }
    }

    /// Changes the target of training point `i`: L stays, w is re-solved from that row on
    /// (O((n − row)²), no kernel evaluations).
    pub fn set_y(&mut self, i: usize, y: f64) -> Result<(), GpError> {
        self.check_index(i)?;
        check_y(y, i)?;
        let p = self.perm[i];
        self.y[p] = y;
        self.resolve_w_from(p);
        Ok(())
    }

    /// Changes the targets of several training points at once: L stays, w is re-solved once
    /// from the lowest storage row touched (one O(n²) solve instead of one per point). Atomic:
    /// on an invalid index or target nothing changes.
    pub fn set_ys(&mut self, changes: &[(usize, f64)]) -> Result<(), GpError> {
        for &(i, y) in changes {
            self.check_index(i)?;
            check_y(y, i)?;
        }
        let mut lowest = usize::MAX;
        for &(i, y) in changes {
            let p = self.perm[i];
            self.y[p] = y;
            lowest = lowest.min(p);
        }
        if lowest != usize::MAX {
            self.resolve_w_from(lowest);
        }
        Ok(())
    }

    /// Predicts at one input (allocates a scratch vector of n; see [`Gp::predict_with`]).
    ///
    /// # Panics
    /// If `x.len() != dim()`.
    pub fn predict(&self, x: &[f64]) -> Prediction {
        let mut scratch = Vec::new();
        self.predict_with(x, &mut scratch)
    }

    /// Predicts at one input without allocating once `scratch` has grown to n + dim: the caller
    /// keeps the scratch (one per thread), so the model itself stays `Sync` and immutable. One
    /// forward substitution, O(n²). A non-finite input gives a NaN prediction.
    ///
    /// # Panics
    /// If `x.len() != dim()`.
    pub fn predict_with(&self, x: &[f64], scratch: &mut Vec<f64>) -> Prediction {
        assert_eq!(x.len(), self.dim, "query of the wrong dimension");
        let n = self.len();
        let s2 = self.params.kernel.signal_variance;
        let m = self.params.prior_mean;
        if n == 0 {
            return Prediction {
                mean: m,
                latent_variance: s2,
            };
        }
        scratch.clear();
        scratch.resize(n + self.dim, 0.0);
        let (v, q) = scratch.split_at_mut(n);
        for ((qk, xk), il) in q.iter_mut().zip(x).zip(&self.inv_l) {
            *qk = xk * il;
        }
        let kind = self.params.kernel.kind;
        for (vi, xi) in v.iter_mut().zip(self.xs.chunks_exact(self.dim)) {
            *vi = k_of_r2(kind, s2, sq_dist(xi, q));
        }
        self.factor.forward_solve_from(v, 0);
        Prediction {
            mean: m + dot(v, &self.w),
            latent_variance: (s2 - dot(v, v)).max(0.0),
        }
    }

    /// Predicts at many inputs: `xs` is q × dim row-major, `mean` and `latent_var` have q entries.
    /// Queries are cut into blocks of 256; per block (in parallel on rayon's pool) the n × 256
    /// cross-covariance block is built and one blocked faer triangular solve gives V = L⁻¹K*.
    pub fn predict_batch(
        &self,
        xs: &[f64],
        mean: &mut [f64],
        latent_var: &mut [f64],
    ) -> Result<(), GpError> {
        let q = mean.len();
        if latent_var.len() != q || xs.len() != q * self.dim {
            return Err(GpError::BadDimension(format!(
                "{} query values, {} mean and {} variance slots for dimension {}",
                xs.len(),
                q,
                latent_var.len(),
                self.dim
            )));
        }
        check_queries(xs, self.dim)?;
        let n = self.len();
        let s2 = self.params.kernel.signal_variance;
        let m = self.params.prior_mean;
        if n == 0 {
            mean.fill(m);
            latent_var.fill(s2);
            return Ok(());
        }
        let d = self.dim;
        let kind = self.params.kernel.kind;
        let l = self.factor.view();
        mean.par_chunks_mut(QUERY_BLOCK)
            .zip(latent_var.par_chunks_mut(QUERY_BLOCK))
            .zip(xs.par_chunks(QUERY_BLOCK * d))
            .for_each(|((mc, vc), qx)| {
                let b = mc.len();
                let qs = scale_points(qx, &self.inv_l);
                let mut kstar = vec![0.0; n * b];
                for (col, qj) in kstar.chunks_exact_mut(n).zip(qs.chunks_exact(d)) {
                    for (c, xi) in col.iter_mut().zip(self.xs.chunks_exact(d)) {
                        *c = k_of_r2(kind, s2, sq_dist(xi, qj));
                    }
                }
                let kmat = faer::MatMut::from_column_major_slice_mut(&mut kstar, n, b);
                solve_lower_triangular_in_place(l, kmat, Par::Seq);
                for ((col, mj), vj) in kstar.chunks_exact(n).zip(mc).zip(vc) {
                    *mj = m + dot(col, &self.w);
                    *vj = (s2 - dot(col, col)).max(0.0);
                }
            });
        Ok(())
    }

    /// Predicts only the mean at many inputs (`xs` is q × dim row-major, `mean` has q entries):
    /// μ = m + k*ᵀα with α = L⁻ᵀw solved once, so a query costs O(n·dim) instead of the O(n²)
    /// of a variance. For GPs whose variance is not needed (the gating regressions of `004`).
    pub fn predict_mean_batch(&self, xs: &[f64], mean: &mut [f64]) -> Result<(), GpError> {
        let q = mean.len();
        if xs.len() != q * self.dim {
            return Err(GpError::BadDimension(format!(
                "{} query values and {} mean slots for dimension {}",
                xs.len(),
                q,
                self.dim
            )));
        }
        check_queries(xs, self.dim)?;
        let n = self.len();
        let m = self.params.prior_mean;
        if n == 0 {
            mean.fill(m);
            return Ok(());
        }
        let alpha = self.alpha();
        mean.par_chunks_mut(QUERY_BLOCK)
            .zip(xs.par_chunks(QUERY_BLOCK * self.dim))
            .for_each(|(mc, qx)| {
                let mut q = vec![0.0; self.dim];
                for (mj, xq) in mc.iter_mut().zip(qx.chunks_exact(self.dim)) {
                    *mj = self.mean_with_alpha(&alpha, xq, &mut q);
                }
            });
        Ok(())
    }

    /// α = K_y⁻¹(y − m) = L⁻ᵀw (one O(n²) triangular solve), with which a mean costs O(n·dim):
    /// [`Gp::mean_with_alpha`]. Valid until the training set changes.
    pub fn alpha(&self) -> Vec<f64> {
        let n = self.len();
        if n == 0 {
            return Vec::new();
        }
        let mut alpha = faer::Mat::<f64>::from_fn(n, 1, |i, _| self.w[i]);
        faer::linalg::triangular_solve::solve_upper_triangular_in_place(
            self.factor.view().transpose(),
            alpha.as_mut(),
            Par::Seq,
        );
        (0..n).map(|i| alpha[(i, 0)]).collect()
    }

    /// The predictive mean m + k*ᵀα at `x` from `alpha` = [`Gp::alpha`] of this training set;
    /// `scratch` holds the scaled query (resized to `dim`).
    ///
    /// # Panics
    /// If `x.len() != dim()` or `alpha` is not of length `len()`.
    pub fn mean_with_alpha(&self, alpha: &[f64], x: &[f64], scratch: &mut Vec<f64>) -> f64 {
        assert_eq!(x.len(), self.dim, "query of the wrong dimension");
        assert_eq!(alpha.len(), self.len(), "alpha of another training set");
        scratch.clear();
        scratch.extend(x.iter().zip(&self.inv_l).map(|(xk, il)| xk * il));
        let kind = self.params.kernel.kind;
        let s2 = self.params.kernel.signal_variance;
        let mut acc = 0.0;
        for (xi, a) in self.xs.chunks_exact(self.dim).zip(alpha) {
            acc += a * k_of_r2(kind, s2, sq_dist(xi, scratch));
        }
        self.params.prior_mean + acc
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

    /// Builds and factorises K + (σ_n² + jitter) I for the stored points, trying the jitter
    /// ladder from step `from`. `self.factor.n` must already be the point count. On failure the
    /// jitter is left at the last value tried and the factor is garbage (callers restore).
    fn refactor(&mut self, from: usize) -> Result<(), GpError> {
        let n = self.len();
        let s2 = self.params.kernel.signal_variance;
        let par = if n >= PAR_MIN_N {
            Par::rayon(0)
        } else {
            Par::Seq
        };
        for &step in &JITTER_STEPS[from..] {
            self.jitter = step * s2;
            self.fill_kernel_matrix();
            if self.factor.factorize(self.min_pivot2(), par) {
                self.resolve_w_from(0);
                return Ok(());
            }
        }
        Err(GpError::NotPositiveDefinite {
            jitter: self.jitter,
        })
    }

    /// Writes the lower triangle of K + σ_n² Ψ + jitter I into the factor, columns in parallel.
    fn fill_kernel_matrix(&mut self) {
        let n = self.len();
        let d = self.dim;
        let kind = self.params.kernel.kind;
        let s2 = self.params.kernel.signal_variance;
        let (sn2, jitter) = (self.params.noise_variance, self.jitter);
        let ld = self.factor.ld;
        let xs = &self.xs;
        let psi = &self.psi;
        self.factor.n = n;
        if n == 0 {
            return;
        }
        self.factor.data[..n * ld]
            .par_chunks_mut(ld)
            .enumerate()
            .for_each(|(j, col)| {
                let xj = &xs[j * d..(j + 1) * d];
                col[j] = s2 + sn2 * psi[j] + jitter;
                for (i, c) in col[j + 1..n].iter_mut().enumerate() {
                    let i = i + j + 1;
                    *c = k_of_r2(kind, s2, sq_dist(&xs[i * d..(i + 1) * d], xj));
                }
            });
    }

    /// w[p..] = L⁻¹(y − m) from row p on (rows before p are unchanged).
    fn resolve_w_from(&mut self, p: usize) {
        let n = self.len();
        let m = self.params.prior_mean;
        self.w.resize(n, 0.0);
        for k in p..n {
            self.w[k] = self.y[k] - m;
        }
        self.factor.forward_solve_from(&mut self.w, p);
    }

    /// Appends a (checked) point with noise multiplier `psi` as the last storage row; atomic on
    /// error.
    fn push_storage(&mut self, x: &[f64], y: f64, psi: f64) -> Result<(), GpError> {
        let n = self.len();
        let d = self.dim;
        let kind = self.params.kernel.kind;
        let s2 = self.params.kernel.signal_variance;
        let xq = scale_points(x, &self.inv_l);
        let mut row: Vec<f64> = self
            .xs
            .chunks_exact(d)
            .map(|xi| k_of_r2(kind, s2, sq_dist(xi, &xq)))
            .collect();
        self.factor.forward_solve_from(&mut row, 0);
        let pivot2 =
            self.params.kernel.signal_variance + self.params.noise_variance * psi + self.jitter
                - dot(&row, &row);
        if pivot2.is_finite() && pivot2 > self.min_pivot2() {
            let piv = pivot2.sqrt();
            let wn = (y - self.params.prior_mean - dot(&row, &self.w)) / piv;
            self.factor.push_row(&row, piv);
            self.x.extend_from_slice(x);
            self.xs.extend_from_slice(&xq);
            self.y.push(y);
            self.psi.push(psi);
            self.w.push(wn);
            return Ok(());
        }
        // Escalate the jitter and rebuild (rare): keep the old state to restore on failure.
        let saved = (self.factor.clone(), self.w.clone(), self.jitter);
        self.x.extend_from_slice(x);
        self.xs.extend_from_slice(&xq);
        self.y.push(y);
        self.psi.push(psi);
        self.factor.reserve_one();
        self.factor.n = n + 1;
        let from = JITTER_STEPS
            .iter()
            .position(|&s| s * s2 > self.jitter)
            .unwrap_or(JITTER_STEPS.len());
        match self.refactor(from) {
            Ok(()) => Ok(()),
            Err(e) => {
                self.x.truncate(n * d);
                self.xs.truncate(n * d);
                self.y.truncate(n);
                self.psi.truncate(n);
                (self.factor, self.w, self.jitter) = saved;
                Err(e)
            }
        }
    }

    fn remove_storage(&mut self, p: usize) {
        let d = self.dim;
        self.factor.remove(p);
        self.x.drain(p * d..(p + 1) * d);
        self.xs.drain(p * d..(p + 1) * d);
        self.y.remove(p);
        self.psi.remove(p);
        self.w.truncate(p);
        self.resolve_w_from(p);
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

fn check_y(y: f64, i: usize) -> Result<(), GpError> {
    if !y.is_finite() {
        return Err(GpError::NonFinite {
            what: format!("y of point {i}"),
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
