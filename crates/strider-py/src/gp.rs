//! `strider.GP`: exact GP regression (strider-learn's `Gp`, as `strider gp predict` uses it).

use numpy::{IntoPyArray, PyArray1, PyReadonlyArray1, PyReadonlyArray2};
use pyo3::prelude::*;
use strider_learn::gp::{
    Gp as RustGp, GpError, GpParams, HyperBounds, Kernel, KernelKind, fit_hyperparameters,
};

use strider_learn::gp_csv::MAX_TRAIN_ROWS;

use crate::errors::msg;

/// Exact Gaussian-process regression with an isotropic kernel.
///
/// `GP(kernel="se", lengthscale=0.4, signal_variance=1.0, noise_variance=0.25, prior_mean=0.0)`;
/// kernels: `se` (squared exponential), `exp`, `matern32`, `matern52`. `fit(X, y)` conditions on
/// the rows of X (n × d), `predict(Q)` returns the mean and the latent variance (without the
/// noise) at the rows of Q.
#[pyclass(name = "GP", module = "strider")]
pub struct Gp {
    params: GpParams,
    gp: Option<RustGp>,
}

/// A prediction's mean and latent variance, one value per query.
pub(crate) type MeanVariance<'py> = (Bound<'py, PyArray1<f64>>, Bound<'py, PyArray1<f64>>);

pub(crate) fn kernel_kind(s: &str) -> PyResult<KernelKind> {
    Ok(match s {
        "se" => KernelKind::SquaredExponential,
        "exp" => KernelKind::Exponential,
        "matern32" => KernelKind::Matern32,
        "matern52" => KernelKind::Matern52,
        _ => {
            return Err(msg(format!(
                "unknown kernel {s:?}: use se, exp, matern32 or matern52"
            )));
        }
    })
}

pub(crate) fn check(name: &str, v: f64, zero_ok: bool) -> PyResult<f64> {
    if v.is_finite() && (v > 0.0 || (zero_ok && v == 0.0)) {
        return Ok(v);
    }
    let want = if zero_ok { "≥ 0" } else { "> 0" };
    Err(msg(format!("{name} {v}: must be a finite number {want}")))
}

/// The rows of a 2-D array as one row-major vector, with their count and width.
pub(crate) fn rows(a: &PyReadonlyArray2<f64>, what: &str) -> PyResult<(Vec<f64>, usize, usize)> {
    let v = a.as_array();
    let (n, d) = v.dim();
    let flat: Vec<f64> = v.iter().copied().collect();
    if flat.iter().any(|x| !x.is_finite()) {
        return Err(msg(format!("{what}: every value must be finite")));
    }
    Ok((flat, n, d))
}

/// `predict` over the rows of `q`, which must have `dim` columns (`dim.1` names whose inputs):
/// the mean and latent variance arrays.
pub(crate) fn predict_rows<'py>(
    py: Python<'py>,
    q: &PyReadonlyArray2<'py, f64>,
    dim: (usize, &str),
    predict: impl FnOnce(&[f64], &mut [f64], &mut [f64]) -> Result<(), GpError> + Send,
) -> PyResult<MeanVariance<'py>> {
    let (qs, m, d) = rows(q, "Q")?;
    if d != dim.0 {
        return Err(msg(format!(
            "Q has {d} columns, {} inputs {}",
            dim.1, dim.0
        )));
    }
    let (mut mean, mut var) = (vec![0.0; m], vec![0.0; m]);
    py.detach(|| predict(&qs, &mut mean, &mut var))
        .map_err(|e| msg(e.to_string()))?;
    Ok((mean.into_pyarray(py), var.into_pyarray(py)))
}

/// GP hyperparameters from the Python keywords, each checked.
pub(crate) fn gp_params(
    kernel: &str,
    lengthscale: f64,
    signal_variance: f64,
    noise_variance: f64,
    prior_mean: f64,
) -> PyResult<GpParams> {
    let kind = kernel_kind(kernel)?;
    check("lengthscale", lengthscale, false)?;
    check("signal_variance", signal_variance, false)?;
    check("noise_variance", noise_variance, true)?;
    if !prior_mean.is_finite() {
        return Err(msg(format!(
            "prior_mean {prior_mean}: must be a finite number"
        )));
    }
    Ok(GpParams {
        kernel: Kernel {
            kind,
            lengthscales: vec![lengthscale],
            signal_variance,
        },
        noise_variance,
        prior_mean,
    })
}

impl Gp {
    fn fitted(&self) -> PyResult<&RustGp> {
        self.gp
            .as_ref()
            .ok_or_else(|| msg("the GP has no data: call fit(X, y) first"))
    }
}

#[pymethods]
impl Gp {
    #[new]
    #[pyo3(signature = (kernel = "se", lengthscale = 0.4, signal_variance = 1.0, noise_variance = 0.25, prior_mean = 0.0))]
    fn new(
        kernel: &str,
        lengthscale: f64,
        signal_variance: f64,
        noise_variance: f64,
        prior_mean: f64,
    ) -> PyResult<Self> {
        Ok(Self {
            params: gp_params(
                kernel,
                lengthscale,
                signal_variance,
                noise_variance,
                prior_mean,
            )?,
            gp: None,
        })
    }

    /// Conditions the GP on the rows of `X` (n × d, float64) and the targets `y` (n); replaces
    /// any earlier data. Returns the GP.
    fn fit<'py>(
        mut slf: PyRefMut<'py, Self>,
        x: PyReadonlyArray2<'py, f64>,
        y: PyReadonlyArray1<'py, f64>,
    ) -> PyResult<PyRefMut<'py, Self>> {
        let (xs, n, d) = rows(&x, "X")?;
        let ys = y.as_slice()?.to_vec();
        if ys.len() != n || n == 0 {
            return Err(msg(format!(
                "X has {n} rows and y {} values: need the same number, at least one",
                ys.len()
            )));
        }
        if ys.iter().any(|v| !v.is_finite()) {
            return Err(msg("y: every value must be finite"));
        }
        if n > MAX_TRAIN_ROWS {
            return Err(msg(format!(
                "{n} training rows, more than an exact GP fit takes ({MAX_TRAIN_ROWS}: an n × n \
                 factor and O(n³) time): subsample the training data"
            )));
        }
        let gp = RustGp::fit(d, slf.params.clone(), &xs, &ys).map_err(|e| msg(e.to_string()))?;
        slf.gp = Some(gp);
        Ok(slf)
    }

    /// The predictive mean and latent variance at the rows of `Q` (m × d): two float64 arrays.
    fn predict<'py>(
        &self,
        py: Python<'py>,
        q: PyReadonlyArray2<'py, f64>,
    ) -> PyResult<MeanVariance<'py>> {
        let gp = self.fitted()?;
        predict_rows(py, &q, (gp.dim(), "the GP's"), |qs, mean, var| {
            gp.predict_batch(qs, mean, var)
        })
    }

    /// Adds one point `x` (d values) with target `y` (an incremental update of the factor).
    fn add_point(&mut self, x: Vec<f64>, y: f64) -> PyResult<()> {
        if x.iter().any(|v| !v.is_finite()) || !y.is_finite() {
            return Err(msg("add_point: x and y must be finite"));
        }
        match self.gp.as_mut() {
            Some(gp) => {
                if x.len() != gp.dim() {
                    return Err(msg(format!(
                        "x has {} values, the GP's inputs {}",
                        x.len(),
                        gp.dim()
                    )));
                }
                gp.push(&x, y).map_err(|e| msg(e.to_string()))
            }
            None => {
                let gp = RustGp::fit(x.len(), self.params.clone(), &x, &[y])
                    .map_err(|e| msg(e.to_string()))?;
                self.gp = Some(gp);
                Ok(())
            }
        }
    }

    /// Removes the point at `index` (in the order the points were added).
    fn remove_point(&mut self, index: usize) -> PyResult<()> {
        let gp = self.gp.as_mut().ok_or_else(|| msg("the GP has no data"))?;
        if index >= gp.len() {
            return Err(msg(format!(
                "index {index} out of range: the GP has {} points",
                gp.len()
            )));
        }
        gp.remove(index).map_err(|e| msg(e.to_string()))
    }

    /// Fits lengthscale, signal and noise variance by maximising the log marginal likelihood on
    /// the GP's data (L-BFGS in log space within fixed bounds, deterministic), then refits.
    fn fit_hyperparameters(&mut self) -> PyResult<()> {
        let gp = self.fitted()?;
        let (n, d) = (gp.len(), gp.dim());
        let xs: Vec<f64> = (0..n).flat_map(|i| gp.x(i).to_vec()).collect();
        let ys: Vec<f64> = (0..n).map(|i| gp.y(i)).collect();
        let p = fit_hyperparameters(d, &xs, &ys, self.params.clone(), &HyperBounds::default())
            .map_err(|e| msg(e.to_string()))?;
        let gp = RustGp::fit(d, p.clone(), &xs, &ys).map_err(|e| msg(e.to_string()))?;
        self.params = p;
        self.gp = Some(gp);
        Ok(())
    }

    /// The log marginal likelihood of the data under the current hyperparameters.
    fn log_marginal_likelihood(&self) -> PyResult<f64> {
        Ok(self.fitted()?.log_marginal_likelihood())
    }

    /// The number of points the GP is conditioned on.
    fn __len__(&self) -> usize {
        self.gp.as_ref().map_or(0, RustGp::len)
    }

    /// The lengthscale.
    #[getter]
    fn lengthscale(&self) -> f64 {
        self.params.kernel.lengthscales[0]
    }

    /// The signal variance σ_s².
    #[getter]
    fn signal_variance(&self) -> f64 {
        self.params.kernel.signal_variance
    }

    /// The noise variance σ_n².
    #[getter]
    fn noise_variance(&self) -> f64 {
        self.params.noise_variance
    }

    fn __repr__(&self) -> String {
        format!(
            "GP(lengthscale={}, signal_variance={}, noise_variance={}, points={})",
            self.lengthscale(),
            self.signal_variance(),
            self.noise_variance(),
            self.__len__()
        )
    }
}
