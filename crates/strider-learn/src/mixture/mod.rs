//! The GP mixture model of Nardi19 (§IV): a place-dependent model
//! of a phenomenon that affects navigation (vibration, energy per metre) learned from the
//! robot's own observations, with the terrain-dependent modes found by mean-shift and the
//! gating function learned by GP regressions on position and, optionally, aerial-image colour.
//!
//! * **Clustering** (Nardi19 §IV-B, Alg. 1 line 6): 1-D mean-shift ([`mean_shift_1d`], Fukunaga
//!   & Hostetler) on the observed values gives the centroids C_1 … C_m. The bandwidth is given
//!   or Silverman's rule ([`silverman_bandwidth`]); modes closer than one bandwidth merge, and
//!   clusters with too few members are dropped (their points are shared out by Eq. 5).
//! * **Gating of the data points** (Eq. 5 with decision 20's restored minus sign):
//!   φ_i(x_j) = softmax_i(−|y_j − C_i| / τ), τ = the bandwidth by default
//!   ([`responsibilities`]).
//! * **Gating function over the map** (§IV-B/C, Eq. 6, decision 20): for each component a GP
//!   regresses logit φ_i on the gating features (standardised x, y — or x, y, r, g, b with the
//!   aerial image) with an ARD squared-exponential kernel; at a query the logistic function
//!   squashes each regression and the m values are normalised to sum to 1. The regressions'
//!   prior mean is logit(1/m): far from every observation the gate says "any component".
//! * **Components** (Eq. 2 and 4): GP_i is trained on *all* observations with the noise of
//!   point j scaled by Ψ_jj = 1/max(φ_i(x_j), φ_min) ([`Gp::fit_heteroscedastic`]), prior mean
//!   the φ_i-weighted mean of y. Its hyperparameters (isotropic SE: l, σ_f², σ_n²) maximise the
//!   marginal likelihood of the component's own members (the points whose largest φ is φ_i),
//!   which is what the Ψ-weighted likelihood reduces to when the other points' noise is ~1/φ_min
//!   times larger.
//! * **Mixing** (Eq. 3): μ = Σ φ_i μ_i, σ² = Σ φ_i (σ_i² + (μ_i − μ)²).
//!
//! With `max_components = 1` the model is the single GP of Nardi19 §III: one component, φ ≡ 1,
//! Ψ = I, prior mean the mean of y — exactly [`Gp::fit`] with the fitted hyperparameters.
//!
//! Hyperparameters are fitted by [`fit_hyperparameters`] (bounded L-BFGS, decision 13) on at
//! most [`MixtureParams::fit_points`] evenly spaced points of the training order (the fit is
//! O(n³) per iteration), warm-started from the previous model's component with the nearest
//! centroid when one is given. Everything is deterministic.
//!
//! Files: `clustering` (bandwidth, mean-shift, mode selection, Eq. 5), `components` (the fit of
//! one component and its gate); this file holds the parameters, the model and its predictions.

mod clustering;
mod components;

pub use clustering::{Mode, mean_shift_1d, responsibilities, silverman_bandwidth};

use rayon::prelude::*;
use thiserror::Error;

#[cfg(doc)]
use crate::gp::fit_hyperparameters;
use crate::gp::{Gp, GpError, Prediction};
use clustering::select_modes;
use components::ComponentFit;

/// Errors of the mixture model.
#[derive(Debug, Clone, PartialEq, Error)]
pub enum MixtureError {
    /// No training points.
    #[error("the mixture model needs at least one observation")]
    Empty,
    /// Inputs of inconsistent sizes.
    #[error("bad dimension: {0}")]
    BadDimension(String),
    /// A non-finite input or target.
    #[error("{0} is not finite")]
    NonFinite(String),
    /// A parameter out of its domain.
    #[error("bad mixture parameter: {0}")]
    BadParameter(String),
    /// A GP of the mixture failed.
    #[error("GP of the mixture: {0}")]
    Gp(#[from] GpError),
}

/// Parameters of [`MixtureModel::fit`].
#[derive(Clone, Debug, PartialEq)]
pub struct MixtureParams {
    /// The most components; 1 is the single GP of Nardi19 §III.
    pub max_components: usize,
    /// Mean-shift bandwidth in units of y; `None`: Silverman's rule on the observations.
    pub bandwidth: Option<f64>,
    /// Temperature τ of Eq. 5; `None`: the bandwidth (decision 20).
    pub temperature: Option<f64>,
    /// Smallest φ used in Ψ = diag(1/φ) and in the gating logits (decision 20: 10⁻³).
    pub phi_min: f64,
    /// A cluster needs at least this many members …
    pub min_cluster_size: usize,
    /// … and at least this fraction of the observations, or it is dropped.
    pub min_cluster_fraction: f64,
    /// Bounds of the components' (isotropic) lengthscale, in the units of the positions.
    pub value_lengthscale: (f64, f64),
    /// Initial lengthscale of the components.
    pub value_lengthscale_init: f64,
    /// Bounds of the components' σ_f² and σ_n², as multiples of the variance of all
    /// observations (so the model is the same in any unit of y).
    pub value_signal_variance: (f64, f64),
    /// See [`MixtureParams::value_signal_variance`].
    pub value_noise_variance: (f64, f64),
    /// Bounds of every ARD lengthscale of the gating regressions (features are standardised).
    pub gate_lengthscale: (f64, f64),
    /// Bounds of the gating regressions' σ_f² (logit units).
    pub gate_signal_variance: (f64, f64),
    /// Bounds of the gating regressions' σ_n² (logit units).
    pub gate_noise_variance: (f64, f64),
    /// The most points a hyperparameter fit sees (evenly spaced over the training order).
    pub fit_points: usize,
    /// The most L-BFGS iterations per fit.
    pub max_iterations: usize,
}

impl Default for MixtureParams {
    /// Up to 6 components, Silverman bandwidth, τ = bandwidth, φ_min = 10⁻³, clusters of ≥ 5
    /// points and ≥ 2 %; component lengthscale in [0.5, 100] (start 5), σ_f² in
    /// [10⁻⁴, 10]·var(y), σ_n² in [10⁻⁶, 1]·var(y); gating lengthscales in [0.05, 20]
    /// (standardised features), σ_f² in [0.1, 100], σ_n² in [10⁻³, 10]; fits on ≤ 200 points,
    /// ≤ 100 iterations.
    fn default() -> Self {
        MixtureParams {
            max_components: 6,
            bandwidth: None,
            temperature: None,
            phi_min: 1e-3,
            min_cluster_size: 5,
            min_cluster_fraction: 0.02,
            value_lengthscale: (0.5, 100.0),
            value_lengthscale_init: 5.0,
            value_signal_variance: (1e-4, 10.0),
            value_noise_variance: (1e-6, 1.0),
            gate_lengthscale: (0.05, 20.0),
            gate_signal_variance: (0.1, 100.0),
            gate_noise_variance: (1e-3, 10.0),
            fit_points: 200,
            max_iterations: 100,
        }
    }
}

impl MixtureParams {
    fn validate(&self) -> Result<(), MixtureError> {
        let bad = |s: String| Err(MixtureError::BadParameter(s));
        if self.max_components == 0 {
            return bad("max_components must be at least 1".into());
        }
        for (name, v) in [
            ("bandwidth", self.bandwidth),
            ("temperature", self.temperature),
        ] {
            if let Some(v) = v
                && !(v.is_finite() && v > 0.0)
            {
                return bad(format!("{name} {v} is not a positive finite number"));
            }
        }
        if !(self.phi_min > 0.0 && self.phi_min < 0.5) {
            return bad(format!("phi_min {} must lie in (0, 0.5)", self.phi_min));
        }
        if !(0.0..1.0).contains(&self.min_cluster_fraction) {
            return bad(format!(
                "min_cluster_fraction {} must lie in [0, 1)",
                self.min_cluster_fraction
            ));
        }
        for (name, (lo, hi)) in [
            ("value_lengthscale", self.value_lengthscale),
            ("value_signal_variance", self.value_signal_variance),
            ("value_noise_variance", self.value_noise_variance),
            ("gate_lengthscale", self.gate_lengthscale),
            ("gate_signal_variance", self.gate_signal_variance),
            ("gate_noise_variance", self.gate_noise_variance),
        ] {
            if !(lo.is_finite() && hi.is_finite() && lo > 0.0 && lo <= hi) {
                return bad(format!(
                    "{name} bounds ({lo}, {hi}) must be finite, positive and ordered"
                ));
            }
        }
        if !(self.value_lengthscale_init.is_finite() && self.value_lengthscale_init > 0.0) {
            return bad("value_lengthscale_init must be positive".into());
        }
        Ok(())
    }
}

/// The observations a mixture is fitted to: n points with a 2-D position (for the component
/// GPs), a value y and a gating feature vector of `gate_dim` entries (for the gating
/// regressions), all row-major.
#[derive(Clone, Copy, Debug)]
pub struct TrainingSet<'a> {
    /// Positions, n × 2 (metres).
    pub positions: &'a [f64],
    /// Observed values, n.
    pub y: &'a [f64],
    /// Gating features, n × `gate_dim` (e.g. standardised x, y or x, y, r, g, b).
    pub gate_features: &'a [f64],
    /// Length of one gating feature vector.
    pub gate_dim: usize,
}

impl TrainingSet<'_> {
    fn validate(&self) -> Result<usize, MixtureError> {
        let n = self.y.len();
        if n == 0 {
            return Err(MixtureError::Empty);
        }
        if self.gate_dim == 0 {
            return Err(MixtureError::BadDimension(
                "gating features need at least one dimension".into(),
            ));
        }
        if self.positions.len() != 2 * n || self.gate_features.len() != self.gate_dim * n {
            return Err(MixtureError::BadDimension(format!(
                "{} position values and {} gating values for {n} observations of gating \
                 dimension {}",
                self.positions.len(),
                self.gate_features.len(),
                self.gate_dim
            )));
        }
        check_finite("an observed value", self.y)?;
        check_finite("a position", self.positions)?;
        check_finite("a gating feature", self.gate_features)?;
        Ok(n)
    }
}

fn check_finite(what: &str, v: &[f64]) -> Result<(), MixtureError> {
    match v.iter().position(|x| !x.is_finite()) {
        Some(k) => Err(MixtureError::NonFinite(format!("{what} (entry {k})"))),
        None => Ok(()),
    }
}

/// One component GP_i of the mixture.
#[derive(Clone, Debug)]
pub struct Component {
    /// The mean-shift centroid C_i.
    pub centroid: f64,
    /// Observations whose largest responsibility is this component's.
    pub members: usize,
    /// The component GP (trained on every observation with noise σ_n²/φ_i, Eq. 4).
    pub gp: Gp,
}

/// A fitted GP mixture (Nardi19 Eq. 3–6); see the module docs.
#[derive(Clone, Debug)]
pub struct MixtureModel {
    components: Vec<Component>,
    /// One gating regression per component (empty for a single component).
    gates: Vec<Gp>,
    gate_dim: usize,
    bandwidth: f64,
    temperature: f64,
}

/// The mixture's prediction over a set of query points.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct FieldPrediction {
    /// μ_mix per query (Eq. 3).
    pub mean: Vec<f64>,
    /// σ²_mix per query (Eq. 3), from the components' latent variances.
    pub variance: Vec<f64>,
    /// The gating φ_i per query, row-major q × m.
    pub gates: Vec<f64>,
}

impl MixtureModel {
    /// Fits the mixture to `train` (Alg. 1 lines 6–10). `warm`: a previous model whose
    /// hyperparameters start the fits (component and gate of the nearest centroid).
    pub fn fit(
        train: &TrainingSet<'_>,
        params: &MixtureParams,
        warm: Option<&MixtureModel>,
    ) -> Result<MixtureModel, MixtureError> {
        params.validate()?;
        let n = train.validate()?;
        let y = train.y;
        let mean_y = y.iter().sum::<f64>() / n as f64;
        let var_y = y.iter().map(|v| (v - mean_y) * (v - mean_y)).sum::<f64>() / n as f64;
        // The bounds of σ_f² and σ_n² scale with the data, so units do not matter; the floor
        // keeps them positive when every value is the same.
        let vscale = var_y.max(1e-6 * (1.0 + mean_y * mean_y));
        let bandwidth = params.bandwidth.unwrap_or_else(|| silverman_bandwidth(y));
        let temperature = params.temperature.unwrap_or(bandwidth);

        // Alg. 1 line 6: centroids. A single-component model skips the clustering (one
        // centroid, the mean), so it is the single GP whatever the data.
        let centroids: Vec<f64> = if params.max_components == 1 {
            vec![mean_y]
        } else {
            let modes = mean_shift_1d(y, bandwidth)?;
            select_modes(&modes, y, params)
        };
        let m = centroids.len();
        // Line 8: φ_i(x_j) by Eq. 5 (all ones for one component).
        let phi = if m == 1 {
            vec![1.0; n]
        } else {
            responsibilities(y, &centroids, temperature)?
        };
        // Lines 9–10, one component (and its gate) per task.
        let fit = ComponentFit {
            train: *train,
            params,
            warm,
            centroids: &centroids,
            phi: &phi,
            vscale,
        };
        let fitted: Vec<(Component, Option<Gp>)> = (0..m)
            .into_par_iter()
            .map(|i| fit.fit(i))
            .collect::<Result<_, _>>()?;
        let mut components = Vec::with_capacity(m);
        let mut gates = Vec::new();
        for (c, g) in fitted {
            components.push(c);
            gates.extend(g);
        }
        Ok(MixtureModel {
            components,
            gates,
            gate_dim: train.gate_dim,
            bandwidth,
            temperature,
        })
    }

    /// The components, in ascending order of centroid.
    pub fn components(&self) -> &[Component] {
        &self.components
    }

    /// The gating regressions (one per component; none for a single component).
    pub fn gates(&self) -> &[Gp] {
        &self.gates
    }

    /// The mean-shift bandwidth used.
    pub fn bandwidth(&self) -> f64 {
        self.bandwidth
    }

    /// The temperature τ of Eq. 5 used.
    pub fn temperature(&self) -> f64 {
        self.temperature
    }

    /// The gating function φ(x) at q queries (row-major q × m, rows sum to 1): each gating
    /// regression squashed by the logistic function, then normalised (decision 20).
    pub fn gating(&self, gate_features: &[f64]) -> Result<Vec<f64>, MixtureError> {
        let m = self.components.len();
        if !gate_features.len().is_multiple_of(self.gate_dim) {
            return Err(MixtureError::BadDimension(format!(
                "{} gating values for gating dimension {}",
                gate_features.len(),
                self.gate_dim
            )));
        }
        let q = gate_features.len() / self.gate_dim;
        if m == 1 {
            return Ok(vec![1.0; q]);
        }
        let logits: Vec<Vec<f64>> = self
            .gates
            .par_iter()
            .map(|g| {
                let mut out = vec![0.0; q];
                g.predict_mean_batch(gate_features, &mut out).map(|()| out)
            })
            .collect::<Result<_, _>>()?;
        let mut phi = vec![0.0; q * m];
        for (k, row) in phi.chunks_exact_mut(m).enumerate() {
            let mut s = 0.0;
            for (i, r) in row.iter_mut().enumerate() {
                *r = 1.0 / (1.0 + (-logits[i][k]).exp());
                s += *r;
            }
            for r in row.iter_mut() {
                *r /= s;
            }
        }
        Ok(phi)
    }

    /// Predicts over q queries (`positions` q × 2, `gate_features` q × gate dimension) by
    /// Eq. 3, into `out` (its vectors are reused).
    pub fn predict(
        &self,
        positions: &[f64],
        gate_features: &[f64],
        out: &mut FieldPrediction,
    ) -> Result<(), MixtureError> {
        if !positions.len().is_multiple_of(2)
            || positions.len() / 2 * self.gate_dim != gate_features.len()
        {
            return Err(MixtureError::BadDimension(format!(
                "{} position values and {} gating values for gating dimension {}",
                positions.len(),
                gate_features.len(),
                self.gate_dim
            )));
        }
        check_finite("a query position", positions)?;
        check_finite("a query gating feature", gate_features)?;
        let q = positions.len() / 2;
        let m = self.components.len();
        let gates = self.gating(gate_features)?;
        let preds: Vec<(Vec<f64>, Vec<f64>)> = self
            .components
            .par_iter()
            .map(|c| {
                let (mut mu, mut var) = (vec![0.0; q], vec![0.0; q]);
                c.gp.predict_batch(positions, &mut mu, &mut var)
                    .map(|()| (mu, var))
            })
            .collect::<Result<_, _>>()?;
        out.mean.clear();
        out.mean.resize(q, 0.0);
        out.variance.clear();
        out.variance.resize(q, 0.0);
        for k in 0..q {
            let row = &gates[k * m..(k + 1) * m];
            let mu: f64 = row.iter().zip(&preds).map(|(p, c)| p * c.0[k]).sum();
            let var: f64 = row
                .iter()
                .zip(&preds)
                .map(|(p, c)| p * (c.1[k] + (c.0[k] - mu) * (c.0[k] - mu)))
                .sum();
            out.mean[k] = mu;
            out.variance[k] = var.max(0.0);
        }
        out.gates = gates;
        Ok(())
    }

    /// Predicts at one query by Eq. 3 (mean and latent variance of the mixture).
    pub fn predict_one(
        &self,
        position: [f64; 2],
        gate_features: &[f64],
    ) -> Result<Prediction, MixtureError> {
        let mut out = FieldPrediction::default();
        self.predict(&position, gate_features, &mut out)?;
        Ok(Prediction {
            mean: out.mean[0],
            latent_variance: out.variance[0],
        })
    }
}
