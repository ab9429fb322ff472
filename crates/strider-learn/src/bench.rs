//! The learner benchmark harness of Prágr19 §V-A and Prágr18: one interface over every
//! traversal-cost regressor, and the two evaluation protocols, independent of where the data
//! come from.
//!
//! * [`IncrementalLearner`]: learn one (descriptor, cost) pair, predict many. Implemented by the
//!   exact GP ([`GpLearner`]: refitted on all data at every step, as Prágr19 describes its "pure
//!   GP"), the RBCM of GP experts ([`RbcmLearner`], Prágr19 Eq. 7–9), the IGMN ([`IgmnLearner`],
//!   [`crate::igmn`]) and the CART tree ([`TreeLearner`], [`crate::regression_tree`], refitted
//!   at every step). [`LearnerSpec`] names a configuration and builds it.
//! * [`run_stream`] (Prágr19 §V-A, Fig. 5): add the pairs one at a time in their recorded order
//!   and, after each addition, predict *all* pairs; record the wall time of the learning step and
//!   of the prediction, the RMSE against the recorded costs (the paper treats the noisy
//!   measurements as the ground truth) and the mean predictive standard deviation (latent,
//!   decision 14).
//! * [`c1_errors`] (Prágr18 §III-C, §IV-C): learn on the first pass, predict the second.
//!   Batch learners (GP, tree) are fitted once on the first pass and predict the second.
//!   Incremental learners (RBCM, IGMN) "first query the model, then learn" every pair of both
//!   passes, and their errors include the first pass's predictions (as Prágr18 reports them).
//!   The error of a prediction is |ŷ − y|; the table reports the mean and the population variance
//!   of these errors.
//!
//! The learners only ever see descriptors and *measured* costs; a benchmark's costs are at most
//! its evaluation target. Data scales ([`DataScale`]: the descriptors' standard deviations, the
//! cost's mean and standard deviation) size the IGMN's new components (δ × std, as in the IGMN
//! papers) and the GP hyperparameters' initial values and bounds; they are the first two moments
//! of the benchmark's data set, given to every learner alike.

use std::time::Instant;

use thiserror::Error;

use crate::gp::{Gp, GpError, GpParams, HyperBounds, Kernel, KernelKind, fit_hyperparameters};
use crate::igmn::{Igmn, IgmnError, IgmnParams};
use crate::rbcm::{Rbcm, RbcmParams, RbcmVariant};
use crate::regression_tree::{RegressionTree, TreeError, TreeParams};
use crate::training_data::first_non_finite;

/// Errors of the benchmark learners.
#[derive(Clone, Debug, Error, PartialEq)]
pub enum LearnError {
    /// From a GP or the RBCM.
    #[error(transparent)]
    Gp(#[from] GpError),
    /// From the IGMN.
    #[error(transparent)]
    Igmn(#[from] IgmnError),
    /// From the regression tree.
    #[error(transparent)]
    Tree(#[from] TreeError),
    /// Inconsistent data shapes or non-finite data given to a protocol.
    #[error("bad data: {0}")]
    BadData(String),
}

/// Predictions at a batch of queries.
#[derive(Clone, Debug, PartialEq)]
pub struct Predictions {
    /// The predicted cost per query.
    pub mean: Vec<f64>,
    /// The latent predictive standard deviation per query, for learners with a model confidence
    /// (GP, RBCM); `None` for IGMN and the tree.
    pub std: Option<Vec<f64>>,
}

/// A traversal-cost regressor that learns one pair at a time.
pub trait IncrementalLearner: Send {
    /// The input dimension.
    fn dim(&self) -> usize;
    /// Learns one pair. Non-finite values are refused with an error and change nothing.
    fn learn(&mut self, x: &[f64], y: f64) -> Result<(), LearnError>;
    /// Learns many pairs (`x` n × dim row-major). Batch learners fit once instead of n times.
    fn learn_batch(&mut self, x: &[f64], y: &[f64]) -> Result<(), LearnError> {
        check_data(self.dim(), x, y)?;
        for (xi, &yi) in x.chunks_exact(self.dim()).zip(y) {
            self.learn(xi, yi)?;
        }
        Ok(())
    }
    /// Predicts at q queries (`xs` q × dim row-major). Before the first pair every learner
    /// predicts its prior mean.
    fn predict(&self, xs: &[f64]) -> Result<Predictions, LearnError>;
}

/// Checks shapes and finiteness of a data set.
fn check_data(dim: usize, x: &[f64], y: &[f64]) -> Result<(), LearnError> {
    if dim == 0 || x.len() != y.len() * dim {
        return Err(LearnError::BadData(format!(
            "{} input values for {} targets of dimension {dim}",
            x.len(),
            y.len()
        )));
    }
    if let Some(what) = first_non_finite(dim, x, y, "pair") {
        return Err(LearnError::BadData(format!("{what} is not finite")));
    }
    Ok(())
}

/// Drops the pairs with a non-finite descriptor component or cost; returns the kept pairs and
/// the number dropped.
pub fn finite_pairs(dim: usize, x: &[f64], y: &[f64]) -> (Vec<f64>, Vec<f64>, usize) {
    let (mut xo, mut yo) = (Vec::new(), Vec::new());
    let mut dropped = 0;
    for (xi, &yi) in x.chunks_exact(dim.max(1)).zip(y) {
        if yi.is_finite() && xi.iter().all(|v| v.is_finite()) {
            xo.extend_from_slice(xi);
            yo.push(yi);
        } else {
            dropped += 1;
        }
    }
    (xo, yo, dropped)
}

/// The first two moments of a benchmark's data set (module docs).
#[derive(Clone, Debug, PartialEq)]
pub struct DataScale {
    /// Standard deviation of every descriptor component.
    pub x_std: Vec<f64>,
    /// Mean of the costs.
    pub y_mean: f64,
    /// Standard deviation of the costs (> 0: a constant cost gets a tenth of its magnitude, or 1).
    pub y_std: f64,
    /// The prior mean of the GP learners and the answer of every learner before its first pair.
    pub prior_mean: f64,
}

impl DataScale {
    /// The moments of (x, y) (`x` n × dim row-major; non-finite pairs are ignored), with the
    /// given prior mean.
    pub fn of(dim: usize, x: &[f64], y: &[f64], prior_mean: f64) -> DataScale {
        let (x, y, _) = finite_pairs(dim, x, y);
        let n = y.len().max(1) as f64;
        let std = |vals: &mut dyn Iterator<Item = f64>| {
            let v: Vec<f64> = vals.collect();
            let m = v.iter().sum::<f64>() / n;
            (
                m,
                (v.iter().map(|a| (a - m).powi(2)).sum::<f64>() / n).sqrt(),
            )
        };
        let x_std = (0..dim)
            .map(|k| std(&mut x.iter().skip(k).step_by(dim).copied()).1)
            .collect();
        let (y_mean, y_std) = std(&mut y.iter().copied());
        let y_std = if y_std > 0.0 {
            y_std
        } else if y_mean != 0.0 {
            0.1 * y_mean.abs()
        } else {
            1.0
        };
        DataScale {
            x_std,
            y_mean,
            y_std,
            prior_mean: if prior_mean.is_finite() {
                prior_mean
            } else {
                0.0
            },
        }
    }

    /// Initial GP hyperparameters: an isotropic `kind` kernel with lengthscale 0.5, σ_s² = σ_y²,
    /// σ_n² = 0.1 σ_y², the prior mean.
    pub fn gp_params(&self, kind: KernelKind) -> GpParams {
        let v = self.y_std * self.y_std;
        GpParams {
            kernel: Kernel {
                kind,
                lengthscales: vec![0.5],
                signal_variance: v,
            },
            noise_variance: 0.1 * v,
            prior_mean: self.prior_mean,
        }
    }

    /// Hyperparameter bounds: lengthscale in [10⁻², 10²] (descriptors are unit-scaled),
    /// σ_s² in [10⁻² σ_y², 10² σ_y²] (a committee's K** must cover the costs' spread),
    /// σ_n² in [10⁻⁴ σ_y², σ_y²]; at most `max_iterations` (≤ 200, Prágr19 §V-A) steps.
    pub fn hyper_bounds(&self, max_iterations: usize) -> HyperBounds {
        let v = self.y_std * self.y_std;
        HyperBounds {
            lengthscale: (1e-2, 1e2),
            signal_variance: (1e-2 * v, 1e2 * v),
            noise_variance: (1e-4 * v, v),
            max_iterations: max_iterations.min(200),
        }
    }
}

/// A learner configuration of the benchmarks.
#[derive(Clone, Debug, PartialEq)]
pub enum LearnerSpec {
    /// The exact GP on all data, refitted (hyperparameters when `fit`, then the factor) at every
    /// step.
    Gp {
        /// Kernel shape.
        kernel: KernelKind,
        /// Fit the hyperparameters at every step (warm-started).
        fit: bool,
    },
    /// The RBCM of GP experts (Prágr19).
    Rbcm {
        /// Kernel shape.
        kernel: KernelKind,
        /// Points per expert.
        m_max: usize,
        /// Smallest expert taking part in predictions.
        m_min: usize,
        /// Fit the newest expert's hyperparameters after every insertion.
        fit: bool,
    },
    /// The IGMN.
    Igmn(IgmnParams),
    /// The CART tree, refitted at every step.
    Tree(TreeParams),
}

/// Short kernel name: exp, m32, m52, rbf.
pub fn kernel_name(k: KernelKind) -> &'static str {
    match k {
        KernelKind::Exponential => "exp",
        KernelKind::Matern32 => "m32",
        KernelKind::Matern52 => "m52",
        KernelKind::SquaredExponential => "rbf",
    }
}

impl LearnerSpec {
    /// A short, unique label, e.g. `rbcm-exp`, `rbcm-exp-mmin1`, `gp-exp`, `igmn`, `tree`.
    pub fn label(&self) -> String {
        match self {
            LearnerSpec::Gp { kernel, fit } => {
                format!(
                    "gp-{}{}",
                    kernel_name(*kernel),
                    if *fit { "" } else { "-fixed" }
                )
            }
            LearnerSpec::Rbcm {
                kernel,
                m_max,
                m_min,
                fit,
            } => {
                let mut s = format!("rbcm-{}", kernel_name(*kernel));
                if *m_max != 50 {
                    s.push_str(&format!("-mmax{m_max}"));
                }
                if *m_min != 25 {
                    s.push_str(&format!("-mmin{m_min}"));
                }
                if !fit {
                    s.push_str("-fixed");
                }
                s
            }
            LearnerSpec::Igmn(_) => "igmn".into(),
            LearnerSpec::Tree(_) => "tree".into(),
        }
    }

    /// True for the learners that query-then-learn every pair in the Prágr18 protocol.
    pub fn is_incremental(&self) -> bool {
        matches!(self, LearnerSpec::Rbcm { .. } | LearnerSpec::Igmn(_))
    }

    /// Builds the learner for `dim`-dimensional descriptors.
    pub fn build(
        &self,
        dim: usize,
        scale: &DataScale,
    ) -> Result<Box<dyn IncrementalLearner>, LearnError> {
        if scale.x_std.len() != dim {
            return Err(LearnError::BadData(format!(
                "{} descriptor scales for dimension {dim}",
                scale.x_std.len()
            )));
        }
        let bounds = scale.hyper_bounds(200);
        Ok(match self {
            LearnerSpec::Gp { kernel, fit } => {
                let params = scale.gp_params(*kernel);
                Box::new(GpLearner {
                    gp: Gp::new(dim, params.clone())?,
                    params,
                    bounds: fit.then_some(bounds),
                    x: Vec::new(),
                    y: Vec::new(),
                })
            }
            LearnerSpec::Rbcm {
                kernel,
                m_max,
                m_min,
                fit,
            } => Box::new(RbcmLearner {
                rbcm: Rbcm::new(
                    dim,
                    scale.gp_params(*kernel),
                    RbcmParams {
                        m_max: *m_max,
                        m_min: *m_min,
                        variant: RbcmVariant::Robust,
                    },
                )?,
                bounds: fit.then_some(bounds),
            }),
            LearnerSpec::Igmn(p) => {
                let mut s = scale.x_std.clone();
                s.push(scale.y_std);
                Box::new(IgmnLearner {
                    igmn: Igmn::new(dim, p.clone(), &s)?,
                    prior: scale.prior_mean,
                })
            }
            LearnerSpec::Tree(p) => {
                // Validate the parameters now rather than at the first fit.
                RegressionTree::fit(1, &[0.0], &[0.0], p)?;
                Box::new(TreeLearner {
                    dim,
                    params: p.clone(),
                    x: Vec::new(),
                    y: Vec::new(),
                    tree: None,
                    prior: scale.prior_mean,
                })
            }
        })
    }
}

/// The exact GP, refitted on all pairs at every step (Prágr19's "pure GP", O(n³) per step).
pub struct GpLearner {
    gp: Gp,
    params: GpParams,
    bounds: Option<HyperBounds>,
    x: Vec<f64>,
    y: Vec<f64>,
}

impl GpLearner {
    fn refit(&mut self) -> Result<(), LearnError> {
        if let Some(b) = &self.bounds
            && let Ok(p) =
                fit_hyperparameters(self.gp.dim(), &self.x, &self.y, self.params.clone(), b)
        {
            self.params = p;
        }
        self.gp = Gp::fit(self.gp.dim(), self.params.clone(), &self.x, &self.y)?;
        Ok(())
    }
}

impl IncrementalLearner for GpLearner {
    fn dim(&self) -> usize {
        self.gp.dim()
    }
    fn learn(&mut self, x: &[f64], y: f64) -> Result<(), LearnError> {
        self.learn_batch(x, &[y])
    }
    fn learn_batch(&mut self, x: &[f64], y: &[f64]) -> Result<(), LearnError> {
        check_data(self.dim(), x, y)?;
        let (nx, ny) = (self.x.len(), self.y.len());
        self.x.extend_from_slice(x);
        self.y.extend_from_slice(y);
        if let Err(e) = self.refit() {
            self.x.truncate(nx);
            self.y.truncate(ny);
            return Err(e);
        }
        Ok(())
    }
    fn predict(&self, xs: &[f64]) -> Result<Predictions, LearnError> {
        gp_like_predict(xs, self.dim(), |xs, m, v| self.gp.predict_batch(xs, m, v))
    }
}

fn gp_like_predict(
    xs: &[f64],
    dim: usize,
    f: impl Fn(&[f64], &mut [f64], &mut [f64]) -> Result<(), GpError>,
) -> Result<Predictions, LearnError> {
    let q = xs.len() / dim;
    let (mut mean, mut var) = (vec![0.0; q], vec![0.0; q]);
    f(xs, &mut mean, &mut var)?;
    Ok(Predictions {
        mean,
        std: Some(var.into_iter().map(|v| v.max(0.0).sqrt()).collect()),
    })
}

/// Predictions without a model confidence: `f` at each of the `dim`-dimensional queries `xs`.
fn point_predictions(
    xs: &[f64],
    dim: usize,
    f: impl Fn(&[f64]) -> f64,
) -> Result<Predictions, LearnError> {
    if !xs.len().is_multiple_of(dim) {
        return Err(LearnError::BadData(format!(
            "{} query values for dimension {dim}",
            xs.len()
        )));
    }
    Ok(Predictions {
        mean: xs.chunks_exact(dim).map(f).collect(),
        std: None,
    })
}

/// The RBCM of GP experts; with `bounds` the newest expert's hyperparameters are refitted after
/// every insertion ([`Rbcm::push_fitted`]).
pub struct RbcmLearner {
    rbcm: Rbcm,
    bounds: Option<HyperBounds>,
}

impl RbcmLearner {
    /// The committee.
    pub fn rbcm(&self) -> &Rbcm {
        &self.rbcm
    }
}

impl IncrementalLearner for RbcmLearner {
    fn dim(&self) -> usize {
        self.rbcm.dim()
    }
    fn learn(&mut self, x: &[f64], y: f64) -> Result<(), LearnError> {
        check_data(self.dim(), x, &[y])?;
        match &self.bounds {
            Some(b) => self.rbcm.push_fitted(x, y, b)?,
            None => self.rbcm.push(x, y)?,
        }
        Ok(())
    }
    fn predict(&self, xs: &[f64]) -> Result<Predictions, LearnError> {
        gp_like_predict(xs, self.dim(), |xs, m, v| self.rbcm.predict_batch(xs, m, v))
    }
}

/// The IGMN (no model confidence).
pub struct IgmnLearner {
    igmn: Igmn,
    prior: f64,
}

impl IgmnLearner {
    /// The network.
    pub fn igmn(&self) -> &Igmn {
        &self.igmn
    }
}

impl IncrementalLearner for IgmnLearner {
    fn dim(&self) -> usize {
        self.igmn.dim()
    }
    fn learn(&mut self, x: &[f64], y: f64) -> Result<(), LearnError> {
        Ok(self.igmn.learn(x, y)?)
    }
    fn predict(&self, xs: &[f64]) -> Result<Predictions, LearnError> {
        point_predictions(xs, self.dim(), |q| {
            self.igmn.predict(q).unwrap_or(self.prior)
        })
    }
}

/// The CART tree, refitted on all pairs at every step.
pub struct TreeLearner {
    dim: usize,
    params: TreeParams,
    x: Vec<f64>,
    y: Vec<f64>,
    tree: Option<RegressionTree>,
    prior: f64,
}

impl IncrementalLearner for TreeLearner {
    fn dim(&self) -> usize {
        self.dim
    }
    fn learn(&mut self, x: &[f64], y: f64) -> Result<(), LearnError> {
        self.learn_batch(x, &[y])
    }
    fn learn_batch(&mut self, x: &[f64], y: &[f64]) -> Result<(), LearnError> {
        check_data(self.dim, x, y)?;
        self.x.extend_from_slice(x);
        self.y.extend_from_slice(y);
        self.tree = Some(RegressionTree::fit(
            self.dim,
            &self.x,
            &self.y,
            &self.params,
        )?);
        Ok(())
    }
    fn predict(&self, xs: &[f64]) -> Result<Predictions, LearnError> {
        point_predictions(xs, self.dim, |q| {
            self.tree.as_ref().map_or(self.prior, |t| t.predict(q))
        })
    }
}

/// Per-step figures of one pass of [`run_stream`].
#[derive(Clone, Debug, PartialEq)]
pub struct StreamTrace {
    /// Wall time of learning pair k, seconds.
    pub learn_s: Vec<f64>,
    /// Wall time of predicting all pairs after learning pair k, seconds.
    pub infer_s: Vec<f64>,
    /// RMSE of those predictions against the recorded costs.
    pub rmse: Vec<f64>,
    /// Mean latent predictive standard deviation over all pairs (`None` without confidence).
    pub mean_std: Option<Vec<f64>>,
}

/// The Prágr19 §V-A protocol on one stream (`x` n × dim row-major, `y` the recorded costs, in
/// recording order): learn pair k, predict every pair, for k = 1 … n (module docs).
pub fn run_stream(
    learner: &mut dyn IncrementalLearner,
    x: &[f64],
    y: &[f64],
) -> Result<StreamTrace, LearnError> {
    let d = learner.dim();
    check_data(d, x, y)?;
    let n = y.len();
    let mut t = StreamTrace {
        learn_s: Vec::with_capacity(n),
        infer_s: Vec::with_capacity(n),
        rmse: Vec::with_capacity(n),
        mean_std: None,
    };
    let mut stds: Option<Vec<f64>> = None;
    for (k, &yk) in y.iter().enumerate() {
        let t0 = Instant::now();
        learner.learn(&x[k * d..(k + 1) * d], yk)?;
        t.learn_s.push(t0.elapsed().as_secs_f64());
        let t1 = Instant::now();
        let p = learner.predict(x)?;
        t.infer_s.push(t1.elapsed().as_secs_f64());
        let se: f64 = p.mean.iter().zip(y).map(|(a, b)| (a - b).powi(2)).sum();
        t.rmse.push((se / n as f64).sqrt());
        if let Some(s) = p.std {
            stds.get_or_insert_with(Vec::new)
                .push(s.iter().sum::<f64>() / n as f64);
        }
    }
    t.mean_std = stds;
    Ok(t)
}

/// The Prágr18 protocol (module docs): the absolute errors |ŷ − y| of `spec` learning on the
/// first pass (`train_x`, `train_y`) and predicting the second (`test_x`, `test_y`, descriptors
/// from the aerial view). Batch learners: errors on the second pass only; incremental learners:
/// query-then-learn over both passes (a query before the first learned pair is not scored).
pub fn c1_errors(
    spec: &LearnerSpec,
    dim: usize,
    scale: &DataScale,
    train: (&[f64], &[f64]),
    test: (&[f64], &[f64]),
) -> Result<Vec<f64>, LearnError> {
    check_data(dim, train.0, train.1)?;
    check_data(dim, test.0, test.1)?;
    let mut l = spec.build(dim, scale)?;
    let mut errors = Vec::new();
    if spec.is_incremental() {
        let mut learned = 0usize;
        for (xs, ys) in [train, test] {
            for (xi, &yi) in xs.chunks_exact(dim).zip(ys) {
                if learned > 0 {
                    errors.push((l.predict(xi)?.mean[0] - yi).abs());
                }
                l.learn(xi, yi)?;
                learned += 1;
            }
        }
    } else {
        if !train.1.is_empty() {
            l.learn_batch(train.0, train.1)?;
        }
        let p = l.predict(test.0)?;
        errors.extend(p.mean.iter().zip(test.1).map(|(a, b)| (a - b).abs()));
    }
    Ok(errors)
}

/// Mean and population variance of `v`; `None` when empty.
pub fn mean_variance(v: &[f64]) -> Option<(f64, f64)> {
    if v.is_empty() {
        return None;
    }
    let n = v.len() as f64;
    let m = v.iter().sum::<f64>() / n;
    Some((m, v.iter().map(|a| (a - m).powi(2)).sum::<f64>() / n))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn all_specs() -> Vec<LearnerSpec> {
        let mut v = vec![
            LearnerSpec::Gp {
                kernel: KernelKind::Exponential,
                fit: true,
            },
            LearnerSpec::Gp {
                kernel: KernelKind::SquaredExponential,
                fit: false,
            },
            LearnerSpec::Igmn(IgmnParams::default()),
            LearnerSpec::Tree(TreeParams::default()),
        ];
        for kernel in [
            KernelKind::Exponential,
            KernelKind::Matern32,
            KernelKind::Matern52,
            KernelKind::SquaredExponential,
        ] {
            v.push(LearnerSpec::Rbcm {
                kernel,
                m_max: 6,
                m_min: 3,
                fit: true,
            });
        }
        v
    }

    /// Decision 7's degenerate Prágr19 descriptors: a flat patch gives shape (0, 0, 1) on every
    /// cell, a missing colour a constant appearance; with constant or varying costs every learner
    /// stays finite, and a stream is a function of its data (timings aside).
    #[test]
    fn degenerate_descriptors_and_constant_costs_stay_finite_and_deterministic() {
        let mut x = Vec::new();
        let mut y = Vec::new();
        for k in 0..20 {
            let flat = k % 2 == 0;
            let shape = if flat {
                [0.0, 0.0, 1.0]
            } else {
                [0.1, 0.5, 0.4]
            };
            x.extend_from_slice(&shape);
            x.extend_from_slice(&[0.0, 0.0]); // no colour information at all
            y.push(if flat { 0.005 } else { 0.03 });
        }
        for constant in [false, true] {
            let y: Vec<f64> = if constant { vec![0.01; 20] } else { y.clone() };
            let scale = DataScale::of(5, &x, &y, 0.0);
            assert!(scale.y_std > 0.0 && scale.x_std.iter().all(|s| s.is_finite()));
            for spec in all_specs() {
                let run = || {
                    let mut l = spec.build(5, &scale).unwrap();
                    run_stream(l.as_mut(), &x, &y).unwrap()
                };
                let (a, b) = (run(), run());
                assert!(a.rmse.iter().all(|v| v.is_finite()), "{}", spec.label());
                assert_eq!(a.rmse, b.rmse, "{}", spec.label());
                assert_eq!(a.mean_std, b.mean_std, "{}", spec.label());
                if let Some(s) = &a.mean_std {
                    assert!(s.iter().all(|v| v.is_finite() && *v >= 0.0));
                }
                assert_eq!(
                    a.mean_std.is_some(),
                    matches!(spec, LearnerSpec::Gp { .. } | LearnerSpec::Rbcm { .. })
                );
            }
        }
    }

    #[test]
    fn bad_data_empty_training_sets_and_errors() {
        let scale = DataScale::of(2, &[0.0, 1.0, 1.0, 0.0], &[1.0, 2.0], 1.5);
        for spec in all_specs() {
            let mut l = spec.build(2, &scale).unwrap();
            // Before any pair: the prior mean.
            let p = l.predict(&[0.3, 0.3]).unwrap();
            assert_eq!(p.mean, vec![1.5], "{}", spec.label());
            // Non-finite pairs are refused and change nothing.
            assert!(l.learn(&[f64::NAN, 0.0], 1.0).is_err());
            assert!(l.learn(&[0.0, 0.0], f64::INFINITY).is_err());
            assert_eq!(l.predict(&[0.3, 0.3]).unwrap().mean, vec![1.5]);
            // Prágr18's protocol with an empty first pass: batch learners predict the prior,
            // incremental ones still learn the second pass.
            let e = c1_errors(
                &spec,
                2,
                &scale,
                (&[], &[]),
                (&[0.0, 1.0, 1.0, 0.0], &[1.0, 2.0]),
            )
            .unwrap();
            assert!(
                !e.is_empty() && e.iter().all(|v| v.is_finite()),
                "{}",
                spec.label()
            );
        }
        assert!(matches!(
            run_stream(
                LearnerSpec::Igmn(IgmnParams::default())
                    .build(2, &scale)
                    .unwrap()
                    .as_mut(),
                &[0.0, f64::NAN],
                &[1.0]
            ),
            Err(LearnError::BadData(_))
        ));
        assert!(
            LearnerSpec::Igmn(IgmnParams::default())
                .build(3, &scale)
                .is_err()
        );
        let (x, y, dropped) = finite_pairs(1, &[0.0, f64::NAN, 2.0], &[1.0, 1.0, f64::NAN]);
        assert_eq!((x, y, dropped), (vec![0.0], vec![1.0], 2));
        assert_eq!(mean_variance(&[]), None);
        assert_eq!(mean_variance(&[1.0, 3.0]), Some((2.0, 1.0)));
    }

    /// Per-expert fitting: experts get their own hyperparameters, the committee stays a proper
    /// distribution (positive variance) and predicts sensibly near the data.
    #[test]
    fn fitted_committee_has_own_expert_hyperparameters() {
        let scale = DataScale {
            x_std: vec![1.0],
            y_mean: 0.0,
            y_std: 1.0,
            prior_mean: 0.0,
        };
        let mut r = Rbcm::new(
            1,
            scale.gp_params(KernelKind::Exponential),
            RbcmParams {
                m_max: 15,
                m_min: 5,
                variant: RbcmVariant::Robust,
            },
        )
        .unwrap();
        for i in 0..45 {
            let x = i as f64 / 10.0;
            let y = if i < 15 {
                0.1 * x
            } else {
                3.0 + (3.0 * x).sin()
            };
            r.push_fitted(&[x], y, &scale.hyper_bounds(200)).unwrap();
        }
        assert_eq!(r.experts().len(), 3);
        assert_ne!(r.experts()[0].params(), r.experts()[1].params());
        for q in [0.5, 2.0, 3.5, 10.0] {
            let p = r.predict(&[q]);
            assert!(p.mean.is_finite() && p.latent_variance > 0.0, "{q}: {p:?}");
        }
        assert!((r.predict(&[0.5]).mean - 0.05).abs() < 0.3);
    }
}
