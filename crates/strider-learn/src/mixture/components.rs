//! The fit of one component of the mixture (Nardi19 Alg. 1 lines 9–10): its GP on every
//! observation with the noise scaled by 1/φ_i (Eq. 4) and, with several components, its gating
//! regression of logit φ_i on the gating features; hyperparameters by type-II maximum likelihood
//! on a subset of the points.

use crate::gp::{Gp, GpParams, HyperBounds, Kernel, KernelKind, fit_hyperparameters};

use super::clustering::nearest;
use super::{Component, MixtureError, MixtureModel, MixtureParams, TrainingSet};

/// What the fits of all components of one mixture share.
pub(super) struct ComponentFit<'a> {
    pub(super) train: TrainingSet<'a>,
    pub(super) params: &'a MixtureParams,
    /// A previous model whose hyperparameters start the fits.
    pub(super) warm: Option<&'a MixtureModel>,
    /// The centroids C_i, ascending.
    pub(super) centroids: &'a [f64],
    /// φ_i(x_j) by Eq. 5, row-major n × m.
    pub(super) phi: &'a [f64],
    /// The scale of σ_f² and σ_n² (the variance of the observations, floored).
    pub(super) vscale: f64,
}

impl ComponentFit<'_> {
    /// Fits component `i` (Alg. 1 lines 9–10) and, with more than one component, its gate.
    pub(super) fn fit(&self, i: usize) -> Result<(Component, Option<Gp>), MixtureError> {
        let (y, m) = (self.train.y, self.centroids.len());
        let n = y.len();
        let w: Vec<f64> = (0..n).map(|j| self.phi[j * m + i]).collect();
        let sw: f64 = w.iter().sum();
        let prior_mean = w.iter().zip(y).map(|(a, b)| a * b).sum::<f64>() / sw;
        let members: Vec<usize> = (0..n).filter(|&j| self.owner(j) == i).collect();
        let prev = self.warm_start(self.centroids[i]);
        let init = match prev {
            Some((w, k)) => GpParams {
                prior_mean,
                ..w.components[k].gp.params().clone()
            },
            None => GpParams {
                kernel: Kernel {
                    kind: KernelKind::SquaredExponential,
                    lengthscales: vec![self.params.value_lengthscale_init],
                    signal_variance: self.vscale,
                },
                noise_variance: 0.01 * self.vscale,
                prior_mean,
            },
        };
        let mx = rows(self.train.positions, 2, &members);
        let my: Vec<f64> = members.iter().map(|&j| y[j]).collect();
        let vp = fit_on(
            2,
            &mx,
            &my,
            init,
            &self.value_bounds(),
            self.params.fit_points,
        )?;
        let psi: Vec<f64> = w.iter().map(|p| 1.0 / p.max(self.params.phi_min)).collect();
        let gp = Gp::fit_heteroscedastic(2, vp, self.train.positions, y, &psi)?;
        let gate = if m == 1 {
            None
        } else {
            Some(self.gate(&w, prev)?)
        };
        Ok((
            Component {
                centroid: self.centroids[i],
                members: members.len(),
                gp,
            },
            gate,
        ))
    }

    /// The gating regression of a component with responsibilities `w`: a GP on logit φ_i with
    /// the prior mean logit(1/m), so that far from every observation the gate says "any
    /// component" (decision 20).
    fn gate(&self, w: &[f64], prev: Option<(&MixtureModel, usize)>) -> Result<Gp, MixtureError> {
        let (train, m) = (&self.train, self.centroids.len());
        let lo = self.params.phi_min;
        let t: Vec<f64> = w
            .iter()
            .map(|p| {
                let p = p.clamp(lo, 1.0 - lo);
                (p / (1.0 - p)).ln()
            })
            .collect();
        let p0 = 1.0 / m as f64;
        let prior = (p0 / (1.0 - p0)).ln();
        let ginit = match prev.and_then(|(w, k)| w.gates.get(k)) {
            Some(g) if g.dim() == train.gate_dim => GpParams {
                prior_mean: prior,
                ..g.params().clone()
            },
            _ => GpParams {
                kernel: Kernel {
                    kind: KernelKind::SquaredExponential,
                    lengthscales: vec![1.0; train.gate_dim],
                    signal_variance: 10.0,
                },
                noise_variance: 0.1,
                prior_mean: prior,
            },
        };
        let gp_params = fit_on(
            train.gate_dim,
            train.gate_features,
            &t,
            ginit,
            &self.gate_bounds(),
            self.params.fit_points,
        )?;
        Ok(Gp::fit(train.gate_dim, gp_params, train.gate_features, &t)?)
    }

    /// The component whose φ is largest at observation `j` (ties: the lower index).
    fn owner(&self, j: usize) -> usize {
        let m = self.centroids.len();
        let row = &self.phi[j * m..(j + 1) * m];
        (0..m).fold(0, |b, i| if row[i] > row[b] { i } else { b })
    }

    /// The previous model and its component with the centroid nearest `c`, if there is one.
    fn warm_start(&self, c: f64) -> Option<(&MixtureModel, usize)> {
        let w = self.warm?;
        let cs: Vec<f64> = w.components.iter().map(|k| k.centroid).collect();
        (!cs.is_empty()).then(|| (w, nearest(&cs, c)))
    }

    /// Bounds of the components' hyperparameters, σ_f² and σ_n² in units of the data.
    fn value_bounds(&self) -> HyperBounds {
        let (p, vscale) = (self.params, self.vscale);
        HyperBounds {
            lengthscale: p.value_lengthscale,
            signal_variance: (
                p.value_signal_variance.0 * vscale,
                p.value_signal_variance.1 * vscale,
            ),
            noise_variance: (
                p.value_noise_variance.0 * vscale,
                p.value_noise_variance.1 * vscale,
            ),
            max_iterations: p.max_iterations,
        }
    }

    /// Bounds of the gating regressions' hyperparameters.
    fn gate_bounds(&self) -> HyperBounds {
        let p = self.params;
        HyperBounds {
            lengthscale: p.gate_lengthscale,
            signal_variance: p.gate_signal_variance,
            noise_variance: p.gate_noise_variance,
            max_iterations: p.max_iterations,
        }
    }
}

/// Evenly spaced indices into 0..n, at most `k` of them (all when n ≤ k).
fn spaced(n: usize, k: usize) -> Vec<usize> {
    if n <= k {
        return (0..n).collect();
    }
    (0..k).map(|t| t * n / k).collect()
}

/// Gathers rows `idx` of a row-major matrix with `dim` columns.
fn rows(data: &[f64], dim: usize, idx: &[usize]) -> Vec<f64> {
    idx.iter()
        .flat_map(|&i| data[i * dim..(i + 1) * dim].iter().copied())
        .collect()
}

/// `init` moved into the box `bounds` (a warm start may come from other bounds).
fn clamp_params(mut p: GpParams, b: &HyperBounds) -> GpParams {
    for l in &mut p.kernel.lengthscales {
        *l = l.clamp(b.lengthscale.0, b.lengthscale.1);
    }
    p.kernel.signal_variance = p
        .kernel
        .signal_variance
        .clamp(b.signal_variance.0, b.signal_variance.1);
    p.noise_variance = p
        .noise_variance
        .clamp(b.noise_variance.0, b.noise_variance.1);
    p
}

/// Fits the hyperparameters on at most `fit_points` of the given points; with fewer than 3
/// points there is nothing to fit and `init` is kept.
fn fit_on(
    dim: usize,
    x: &[f64],
    y: &[f64],
    init: GpParams,
    bounds: &HyperBounds,
    fit_points: usize,
) -> Result<GpParams, MixtureError> {
    let init = clamp_params(init, bounds);
    if y.len() < 3 {
        return Ok(init);
    }
    let idx = spaced(y.len(), fit_points.max(3));
    let xs = rows(x, dim, &idx);
    let ys: Vec<f64> = idx.iter().map(|&i| y[i]).collect();
    Ok(fit_hyperparameters(dim, &xs, &ys, init, bounds)?)
}
