//! `strider.RBCM`: the robust Bayesian committee machine of GP experts (strider-learn's
//! `Rbcm`, Prágr19's cost model).

use numpy::{PyReadonlyArray1, PyReadonlyArray2};
use pyo3::prelude::*;
use strider_learn::gp::HyperBounds;
use strider_learn::gp_csv::MAX_TRAIN_ROWS;
use strider_learn::rbcm::{Rbcm as RustRbcm, RbcmParams, RbcmVariant};

use crate::errors::msg;
use crate::gp::{MeanVariance, gp_params, predict_rows, rows};

/// A committee of exact GP experts (Prágr19 Eq. 7–9).
///
/// `RBCM(kernel="se", lengthscale=0.4, signal_variance=1.0, noise_variance=0.25,
/// prior_mean=0.0, m_max=50, m_min=25, variant="robust", fit_experts=False)`: training points
/// fill experts in arrival order, `m_max` points each; experts with fewer than `m_min` points
/// take no part in predictions. `variant="bcm"` gives every expert weight 1 (Eq. 7) instead of
/// the robust weights (Eq. 9). With `fit_experts=True` the newest expert's hyperparameters are
/// refitted at each insertion, as Prágr19 does.
#[pyclass(name = "RBCM", module = "strider")]
pub struct Rbcm {
    rbcm: RustRbcm,
    fit_experts: bool,
}

fn variant(s: &str) -> PyResult<RbcmVariant> {
    match s {
        "robust" => Ok(RbcmVariant::Robust),
        "bcm" => Ok(RbcmVariant::Bcm),
        _ => Err(msg(format!("variant {s:?}: use \"robust\" or \"bcm\""))),
    }
}

impl Rbcm {
    fn insert(&mut self, x: &[f64], y: f64) -> PyResult<()> {
        let r = if self.fit_experts {
            self.rbcm.push_fitted(x, y, &HyperBounds::default())
        } else {
            self.rbcm.push(x, y)
        };
        r.map_err(|e| msg(e.to_string()))
    }
}

#[pymethods]
impl Rbcm {
    #[new]
    #[pyo3(signature = (dim, kernel = "se", lengthscale = 0.4, signal_variance = 1.0, noise_variance = 0.25, prior_mean = 0.0, m_max = 50, m_min = 25, variant = "robust", fit_experts = false))]
    #[allow(clippy::too_many_arguments)]
    fn new(
        dim: usize,
        kernel: &str,
        lengthscale: f64,
        signal_variance: f64,
        noise_variance: f64,
        prior_mean: f64,
        m_max: usize,
        m_min: usize,
        variant: &str,
        fit_experts: bool,
    ) -> PyResult<Self> {
        let params = gp_params(
            kernel,
            lengthscale,
            signal_variance,
            noise_variance,
            prior_mean,
        )?;
        if !(1..=MAX_TRAIN_ROWS).contains(&m_max) || m_min > m_max {
            return Err(msg(format!(
                "m_max {m_max}, m_min {m_min}: need 1 ≤ m_max ≤ {MAX_TRAIN_ROWS} and m_min ≤ m_max"
            )));
        }
        if dim == 0 || dim > 4096 {
            return Err(msg(format!("dim {dim}: must be from 1 to 4096")));
        }
        let committee = RbcmParams {
            m_max,
            m_min,
            variant: self::variant(variant)?,
        };
        let rbcm = RustRbcm::new(dim, params, committee).map_err(|e| msg(e.to_string()))?;
        Ok(Self { rbcm, fit_experts })
    }

    /// Adds the rows of `X` (n × dim) with targets `y` (n) in order. Returns the committee.
    fn add<'py>(
        mut slf: PyRefMut<'py, Self>,
        x: PyReadonlyArray2<'py, f64>,
        y: PyReadonlyArray1<'py, f64>,
    ) -> PyResult<PyRefMut<'py, Self>> {
        let (xs, n, d) = rows(&x, "X")?;
        let ys = y.as_slice()?;
        if ys.len() != n || d != slf.rbcm.dim() {
            return Err(msg(format!(
                "X is {n} × {d} and y has {} values: need n × {} and n values",
                ys.len(),
                slf.rbcm.dim()
            )));
        }
        if ys.iter().any(|v| !v.is_finite()) {
            return Err(msg("y: every value must be finite"));
        }
        for (x, &y) in xs.chunks_exact(d).zip(ys) {
            slf.insert(x, y)?;
        }
        Ok(slf)
    }

    /// The committee's mean and latent variance at the rows of `Q` (m × dim).
    fn predict<'py>(
        &self,
        py: Python<'py>,
        q: PyReadonlyArray2<'py, f64>,
    ) -> PyResult<MeanVariance<'py>> {
        let rbcm = &self.rbcm;
        predict_rows(py, &q, (rbcm.dim(), "the committee's"), |qs, mean, var| {
            rbcm.predict_batch(qs, mean, var)
        })
    }

    /// The number of training points.
    fn __len__(&self) -> usize {
        self.rbcm.len()
    }

    /// The number of experts, and how many take part in predictions (≥ m_min points).
    #[getter]
    fn experts(&self) -> (usize, usize) {
        let all = self.rbcm.experts().len();
        let taking_part = (0..all).filter(|&i| self.rbcm.takes_part(i)).count();
        (all, taking_part)
    }

    fn __repr__(&self) -> String {
        let (all, part) = self.experts();
        format!(
            "RBCM(points={}, experts={all}, taking_part={part})",
            self.rbcm.len()
        )
    }
}
