//! Predictions of a GP: at one input by a forward substitution, at many in parallel blocks, and
//! the mean alone through α = K_y⁻¹(y − m).

use faer::Par;
use faer::linalg::triangular_solve::solve_lower_triangular_in_place;
use rayon::prelude::*;

use super::factor::dot;
use super::kernel::{k_of_r2, sq_dist};
use super::{Gp, GpError, Prediction, QUERY_BLOCK, check_queries, scale_points};

impl Gp {
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
    /// of a variance. For GPs whose variance is not needed (the gating regressions of Nardi19).
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
}
