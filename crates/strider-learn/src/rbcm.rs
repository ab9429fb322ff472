//! The robust Bayesian committee machine of GP experts (Prágr19 Eq. 7–9, decision 15).
//!
//! Training points fill experts in arrival order, each up to `m_max` points; only the newest
//! expert changes (an O(m_max²) insertion), so learning stays cheap however long the robot runs.
//! A prediction combines the experts with at least `m_min` points. With μ_i, σ_i² the mean and
//! latent variance of expert i at x*, K** the shared kernel's prior variance and m the prior mean:
//!
//! * precision σ⁻² = Σ β_i σ_i⁻² + (1 − Σ β_i) K**⁻¹  (Eq. 8; Eq. 7 is β_i = 1, the BCM),
//! * mean μ = σ² (Σ β_i σ_i⁻² μ_i + (1 − Σ β_i) K**⁻¹ m),
//! * β_i = ½ (ln K** − ln σ_i²), clamped at ≥ 0 (Eq. 9; the difference of differential entropies
//!   of prior and posterior).
//!
//! The paper's experts have a zero prior mean, where the prior's term in the mean vanishes. With a
//! prior mean m the prior is one more "expert" (μ = m, σ² = K**) of weight (1 − Σ β_i), which
//! keeps the committee shift-equivariant (adding c to every y and to m adds c to μ). With no
//! expert of ≥ m_min points the prediction is the prior.
//!
//! # Hyperparameters per expert
//! [`Rbcm::push`] keeps the shared hyperparameters. [`Rbcm::push_fitted`] is the Prágr19 §V-A
//! setup (each GPy expert optimised by L-BFGS-B, ≤ 200 steps): after the insertion the newest
//! expert's lengthscale, σ_s² and σ_n² are refitted by [`fit_hyperparameters`] (bounded,
//! warm-started from its previous values; a new expert starts from the shared ones). Experts then
//! have their own prior variances K**_i: β_i uses the expert's own K**_i, and the prior's term
//! (1 − Σ β_i) K**⁻¹ uses K** = max_i K**_i over the experts taking part. That choice keeps the
//! precision positive whatever Σ β_i is (Σ β_i/σ_i² ≥ Σ β_i/K** since σ_i² ≤ K**_i ≤ K**), and
//! with shared hyperparameters it is exactly Eq. 8. The prior mean stays the shared one.

use crate::gp::{Gp, GpError, GpParams, HyperBounds, Prediction, fit_hyperparameters};

/// How experts are weighted.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum RbcmVariant {
    /// The robust BCM: β_i = ½ (ln K** − ln σ_i²) ≥ 0 (Prágr19 Eq. 8–9).
    Robust,
    /// The plain BCM: β_i = 1 (Prágr19 Eq. 7).
    Bcm,
}

/// Committee parameters.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct RbcmParams {
    /// Points per expert; a new expert starts when the newest has this many (≥ 1).
    pub m_max: usize,
    /// Experts with fewer points take no part in predictions (Prágr19: small experts are noisy).
    pub m_min: usize,
    /// Robust (default in Prágr19) or plain BCM weights.
    pub variant: RbcmVariant,
}

/// Latent variances are floored at this fraction of K** before inverting them.
const VAR_FLOOR: f64 = 1e-12;

/// A committee of exact GP experts sharing one kernel.
#[derive(Clone, Debug)]
pub struct Rbcm {
    dim: usize,
    params: GpParams,
    rbcm: RbcmParams,
    experts: Vec<Gp>,
}

impl Rbcm {
    /// An empty committee (it predicts the prior).
    pub fn new(dim: usize, params: GpParams, rbcm: RbcmParams) -> Result<Rbcm, GpError> {
        if rbcm.m_max == 0 {
            return Err(GpError::BadHyperparameter(
                "m_max must be at least 1".into(),
            ));
        }
        // Validates dim and the hyperparameters.
        Gp::new(dim, params.clone())?;
        Ok(Rbcm {
            dim,
            params,
            rbcm,
            experts: Vec::new(),
        })
    }

    /// The input dimension.
    pub fn dim(&self) -> usize {
        self.dim
    }

    /// The shared GP hyperparameters.
    pub fn params(&self) -> &GpParams {
        &self.params
    }

    /// The committee parameters.
    pub fn rbcm_params(&self) -> &RbcmParams {
        &self.rbcm
    }

    /// The experts, oldest first.
    pub fn experts(&self) -> &[Gp] {
        &self.experts
    }

    /// The number of training points over all experts.
    pub fn len(&self) -> usize {
        self.experts.iter().map(Gp::len).sum()
    }

    /// True without training points.
    pub fn is_empty(&self) -> bool {
        self.experts.is_empty()
    }

    /// Adds a training point to the newest expert, starting a new expert when the newest is full.
    /// On error (wrong dimension, non-finite value) nothing changes.
    pub fn push(&mut self, x: &[f64], y: f64) -> Result<(), GpError> {
        let full = self
            .experts
            .last()
            .is_none_or(|e| e.len() >= self.rbcm.m_max);
        if full {
            let mut e = Gp::new(self.dim, self.params.clone())?;
            e.push(x, y)?;
            self.experts.push(e);
            Ok(())
        } else {
            let last = self.experts.len() - 1;
            self.experts[last].push(x, y)
        }
    }

    /// [`Rbcm::push`], then refits the newest expert's hyperparameters within `bounds` (at most
    /// `bounds.max_iterations` quasi-Newton steps, warm-started) and rebuilds it: O(m_max³) per
    /// iteration, independent of the committee's size. A fit that fails (non-finite likelihood)
    /// leaves the expert with its previous hyperparameters; the point is kept either way.
    pub fn push_fitted(&mut self, x: &[f64], y: f64, bounds: &HyperBounds) -> Result<(), GpError> {
        self.push(x, y)?;
        let last = self.experts.len() - 1;
        let e = &self.experts[last];
        let n = e.len();
        let mut xs = Vec::with_capacity(n * self.dim);
        let mut ys = Vec::with_capacity(n);
        for i in 0..n {
            xs.extend_from_slice(e.x(i));
            ys.push(e.y(i));
        }
        if let Ok(p) = fit_hyperparameters(self.dim, &xs, &ys, e.params().clone(), bounds)
            && let Ok(g) = Gp::fit(self.dim, p, &xs, &ys)
        {
            self.experts[last] = g;
        }
        Ok(())
    }

    /// The committee prediction at `x` (Prágr19 Eq. 7–9).
    ///
    /// # Panics
    /// If `x.len() != dim()`.
    pub fn predict(&self, x: &[f64]) -> Prediction {
        assert_eq!(x.len(), self.dim, "query of the wrong dimension");
        let mut scratch = Vec::new();
        self.combine(self.experts.iter().filter(|e| self.qualifies(e)).map(|e| {
            (
                e.predict_with(x, &mut scratch),
                e.params().kernel.prior_variance(),
            )
        }))
    }

    /// Predictions at many inputs (`xs` q × dim row-major); each expert predicts the batch with
    /// [`Gp::predict_batch`], then the committee combines per query.
    pub fn predict_batch(
        &self,
        xs: &[f64],
        mean: &mut [f64],
        latent_var: &mut [f64],
    ) -> Result<(), GpError> {
        let q = mean.len();
        let qualifying: Vec<&Gp> = self.experts.iter().filter(|e| self.qualifies(e)).collect();
        let mut means = vec![0.0; q * qualifying.len()];
        let mut vars = vec![0.0; q * qualifying.len()];
        if qualifying.is_empty() {
            // Still validate the shapes.
            Gp::new(self.dim, self.params.clone())?.predict_batch(xs, mean, latent_var)?;
            return Ok(());
        }
        for ((e, mc), vc) in qualifying
            .iter()
            .zip(means.chunks_exact_mut(q))
            .zip(vars.chunks_exact_mut(q))
        {
            e.predict_batch(xs, mc, vc)?;
        }
        let priors: Vec<f64> = qualifying
            .iter()
            .map(|e| e.params().kernel.prior_variance())
            .collect();
        for j in 0..q {
            let p = self.combine((0..qualifying.len()).map(|i| {
                (
                    Prediction {
                        mean: means[i * q + j],
                        latent_variance: vars[i * q + j],
                    },
                    priors[i],
                )
            }));
            mean[j] = p.mean;
            latent_var[j] = p.latent_variance;
        }
        Ok(())
    }

    /// Experts that can no longer change: all but a newest one that still has room (only the
    /// newest expert is ever updated, decision 15). A caller may cache their predictions.
    pub fn frozen_experts(&self) -> usize {
        match self.experts.last() {
            Some(e) if e.len() < self.rbcm.m_max => self.experts.len() - 1,
            _ => self.experts.len(),
        }
    }

    /// True when expert `i` takes part in predictions (it has at least m_min points).
    pub fn takes_part(&self, i: usize) -> bool {
        self.experts.get(i).is_some_and(|e| self.qualifies(e))
    }

    /// True for an expert with at least m_min points: it takes part in predictions.
    fn qualifies(&self, e: &Gp) -> bool {
        e.len() >= self.rbcm.m_min.max(1)
    }

    /// The committee's combination (Eq. 7–9) of expert predictions made elsewhere, e.g. cached
    /// predictions of frozen experts: `experts` yields (prediction, that expert's prior variance
    /// K**_i) for exactly the experts that take part ([`Rbcm::takes_part`]). Given the same
    /// expert predictions it equals [`Rbcm::predict`].
    pub fn combine_predictions(
        &self,
        experts: impl Iterator<Item = (Prediction, f64)>,
    ) -> Prediction {
        self.combine(experts)
    }

    /// β for one expert variance (Prágr19 Eq. 9, clamped; 1 for the BCM), with the shared K**.
    pub fn beta(&self, expert_variance: f64) -> f64 {
        self.beta_with(self.params.kernel.prior_variance(), expert_variance)
    }

    /// β for an expert of prior variance `kss` and latent variance `expert_variance`.
    fn beta_with(&self, kss: f64, expert_variance: f64) -> f64 {
        match self.rbcm.variant {
            RbcmVariant::Bcm => 1.0,
            RbcmVariant::Robust => {
                let v = expert_variance.max(VAR_FLOOR * kss);
                (0.5 * (kss.ln() - v.ln())).max(0.0)
            }
        }
    }

    /// Combines (prediction, prior variance K**_i) of the experts taking part (module docs).
    fn combine(&self, experts: impl Iterator<Item = (Prediction, f64)>) -> Prediction {
        let m = self.params.prior_mean;
        let mut prec = 0.0;
        let mut weighted = 0.0;
        let mut beta_sum = 0.0;
        let mut kss_max: Option<f64> = None;
        for (p, kss) in experts {
            let v = p.latent_variance.max(VAR_FLOOR * kss);
            let b = self.beta_with(kss, p.latent_variance);
            prec += b / v;
            weighted += b / v * p.mean;
            beta_sum += b;
            kss_max = Some(kss_max.map_or(kss, |k: f64| k.max(kss)));
        }
        let kss = kss_max.unwrap_or_else(|| self.params.kernel.prior_variance());
        prec += (1.0 - beta_sum) / kss;
        weighted += (1.0 - beta_sum) / kss * m;
        let var = 1.0 / prec;
        Prediction {
            mean: var * weighted,
            latent_variance: var.max(0.0),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::gp::{Kernel, KernelKind};

    fn params(prior_mean: f64) -> GpParams {
        GpParams {
            kernel: Kernel {
                kind: KernelKind::SquaredExponential,
                lengthscales: vec![1.0],
                signal_variance: 1.0,
            },
            noise_variance: 0.25,
            prior_mean,
        }
    }

    fn two_experts(variant: RbcmVariant, prior_mean: f64) -> Rbcm {
        // Expert 1: one point (0, 1); expert 2: one point (1, 2). 1-D, SE, l = 1, σ_s² = 1,
        // σ_n² = 0.25.
        two_experts_with_targets(variant, prior_mean, [1.0, 2.0])
    }

    /// One expert per point: (0, `y[0]`) and (1, `y[1]`).
    fn two_experts_with_targets(variant: RbcmVariant, prior_mean: f64, y: [f64; 2]) -> Rbcm {
        let mut r = Rbcm::new(
            1,
            params(prior_mean),
            RbcmParams {
                m_max: 1,
                m_min: 1,
                variant,
            },
        )
        .unwrap();
        r.push(&[0.0], y[0]).unwrap();
        r.push(&[1.0], y[1]).unwrap();
        r
    }

    // Hand computation at x* = 0.5 (python: math.exp(-0.125) = 0.8824969025845955):
    //   k = exp(-0.125) = 0.8824969025845955 for both experts.
    //   expert 1: μ1 = m + k (1 − m) / 1.25, σ1² = 1 − k²/1.25 = 0.37696
    //             (k²/1.25 = 0.7788007830714049/1.25 = 0.6230406264571239, σ1² = 0.3769593735428761)
    //   expert 2: μ2 = m + k (2 − m) / 1.25, σ2² = σ1².
    //   β = ½ (ln 1 − ln 0.3769593735428761) = 0.4878089299133301
    //   precision = 2β/σ1² + (1 − 2β)/1 = 2.6125068249563586, σ² = 0.38277411964912467
    //   mean (m = 0) = σ² β/σ1² (μ1 + μ2) = σ² β/σ1² · 3k/1.25 = 1.0491128272686068
    #[test]
    fn robust_two_experts_match_hand_computation() {
        let r = two_experts(RbcmVariant::Robust, 0.0);
        let k = (-0.125f64).exp();
        let s = 1.0 - k * k / 1.25;
        assert!((s - 0.3769593735428761).abs() < 1e-15);
        let beta = -0.5 * s.ln();
        assert!((beta - 0.4878089299133301).abs() < 1e-14, "{beta}");
        let (mu1, mu2) = (k / 1.25, 2.0 * k / 1.25);
        // precision = 2β/σ² + (1 − 2β)/1
        let prec = 2.0 * beta / s + (1.0 - 2.0 * beta);
        let mean = (beta / s * (mu1 + mu2)) / prec;
        let p = r.predict(&[0.5]);
        assert!((p.latent_variance - 1.0 / prec).abs() < 1e-12);
        assert!((p.mean - mean).abs() < 1e-12);
        assert!((p.latent_variance - 0.38277411964912467).abs() < 1e-14);
        assert!((p.mean - 1.0491128272686068).abs() < 1e-14);
    }

    #[test]
    fn bcm_two_experts_match_hand_computation() {
        let r = two_experts(RbcmVariant::Bcm, 0.0);
        let k = (-0.125f64).exp();
        let s = 1.0 - k * k / 1.25;
        // precision = 2/σ1² + (1 − 2)/1 = 2/0.3769593735428761 − 1 = 4.305611533685649
        let prec = 2.0 / s - 1.0;
        assert!((prec - 4.305611533685649).abs() < 1e-12, "{prec}");
        let mean = (k / 1.25 + 2.0 * k / 1.25) / s / prec;
        let p = r.predict(&[0.5]);
        assert!((p.latent_variance - 1.0 / prec).abs() < 1e-12);
        assert!((p.mean - mean).abs() < 1e-12);
    }

    #[test]
    fn prior_mean_shift_equivariance() {
        // Adding c to every target and to the prior mean adds c to the committee mean.
        for variant in [RbcmVariant::Robust, RbcmVariant::Bcm] {
            let a = two_experts(variant, 0.0);
            let b = two_experts_with_targets(variant, 3.0, [4.0, 5.0]);
            for x in [-2.0, 0.0, 0.3, 0.5, 1.0, 4.0] {
                let (pa, pb) = (a.predict(&[x]), b.predict(&[x]));
                assert!((pa.mean + 3.0 - pb.mean).abs() < 1e-12, "{variant:?} {x}");
                assert!((pa.latent_variance - pb.latent_variance).abs() < 1e-12);
            }
            // Far from the data every expert is the prior: β = 0 and the mean is m.
            assert!((b.predict(&[50.0]).mean - 3.0).abs() < 1e-12);
        }
    }

    #[test]
    fn beta_is_never_negative() {
        let r = two_experts(RbcmVariant::Robust, 0.0);
        for v in [0.0, 1e-30, 0.1, 0.999, 1.0, 1.5, 100.0] {
            assert!(r.beta(v) >= 0.0, "{v}");
        }
        assert_eq!(r.beta(2.0), 0.0);
    }

    #[test]
    fn prior_when_no_expert_qualifies() {
        let mut r = Rbcm::new(
            1,
            params(0.7),
            RbcmParams {
                m_max: 10,
                m_min: 3,
                variant: RbcmVariant::Robust,
            },
        )
        .unwrap();
        assert_eq!(r.predict(&[0.1]).mean, 0.7);
        r.push(&[0.0], 1.0).unwrap();
        r.push(&[0.1], 1.0).unwrap();
        let p = r.predict(&[0.1]);
        assert_eq!((p.mean, p.latent_variance), (0.7, 1.0));
        r.push(&[0.2], 1.0).unwrap();
        assert!(r.predict(&[0.1]).latent_variance < 0.5);
    }

    #[test]
    fn experts_fill_in_arrival_order() {
        let mut r = Rbcm::new(
            1,
            params(0.0),
            RbcmParams {
                m_max: 3,
                m_min: 1,
                variant: RbcmVariant::Robust,
            },
        )
        .unwrap();
        for i in 0..7 {
            r.push(&[i as f64], i as f64).unwrap();
        }
        let sizes: Vec<usize> = r.experts().iter().map(Gp::len).collect();
        assert_eq!(sizes, vec![3, 3, 1]);
        assert_eq!(r.experts()[1].x(0), &[3.0]);
        assert!(r.push(&[f64::NAN], 1.0).is_err());
        assert_eq!(r.len(), 7);
        let xs = [0.5, 2.5, 6.0];
        let (mut m, mut v) = ([0.0; 3], [0.0; 3]);
        r.predict_batch(&xs, &mut m, &mut v).unwrap();
        for (j, x) in xs.iter().enumerate() {
            let p = r.predict(&[*x]);
            assert!((p.mean - m[j]).abs() < 1e-12 && (p.latent_variance - v[j]).abs() < 1e-12);
        }
    }

    #[test]
    fn cached_expert_predictions_combine_like_predict() {
        let mut r = Rbcm::new(
            1,
            params(0.3),
            RbcmParams {
                m_max: 3,
                m_min: 2,
                variant: RbcmVariant::Robust,
            },
        )
        .unwrap();
        for k in 0..8 {
            r.push(&[k as f64 * 0.4], (k as f64).sin()).unwrap();
        }
        // 8 points in experts of 3, 3, 2: the first two are frozen, the third still grows.
        assert_eq!(r.frozen_experts(), 2);
        assert!(r.takes_part(2) && !r.takes_part(3));
        let x = [1.1];
        let parts = (0..r.experts().len())
            .filter(|&i| r.takes_part(i))
            .map(|i| {
                let e = &r.experts()[i];
                (e.predict(&x), e.params().kernel.prior_variance())
            });
        let a = r.combine_predictions(parts);
        let b = r.predict(&x);
        assert!((a.mean - b.mean).abs() < 1e-12);
        assert!((a.latent_variance - b.latent_variance).abs() < 1e-12);
        r.push(&[9.0], 0.0).unwrap();
        assert_eq!(r.frozen_experts(), 3);
    }
}
