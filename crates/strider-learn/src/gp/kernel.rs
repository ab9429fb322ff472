//! Stationary covariance functions of the scaled distance r (Prágr22 Eq. 21 and the Matérn family).

use super::GpError;

/// The shape of a stationary kernel k(r), with r = ‖(a − b) / l‖ the lengthscale-scaled distance.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum KernelKind {
    /// Squared exponential σ_s² exp(−r²/2) (Prágr22 Eq. 21; decision 13: the default).
    SquaredExponential,
    /// Exponential (Matérn 1/2) σ_s² exp(−r).
    Exponential,
    /// Matérn 3/2: σ_s² (1 + √3 r) exp(−√3 r).
    Matern32,
    /// Matérn 5/2: σ_s² (1 + √5 r + 5r²/3) exp(−√5 r).
    Matern52,
}

/// A stationary kernel: its shape, lengthscales and signal (output) variance σ_s².
#[derive(Clone, Debug, PartialEq)]
pub struct Kernel {
    /// The shape.
    pub kind: KernelKind,
    /// One lengthscale (isotropic) or one per input dimension (ARD).
    pub lengthscales: Vec<f64>,
    /// The signal variance σ_s², the kernel's value at r = 0.
    pub signal_variance: f64,
}

impl Kernel {
    /// The decision-13 default: squared exponential, l = 0.4, σ_s² = 1.
    pub fn default_se() -> Kernel {
        Kernel {
            kind: KernelKind::SquaredExponential,
            lengthscales: vec![0.4],
            signal_variance: 1.0,
        }
    }

    /// k(a, b).
    ///
    /// # Panics
    /// If `a` and `b` differ in length, or the kernel is ARD with a lengthscale count other than
    /// `a.len()`.
    pub fn eval(&self, a: &[f64], b: &[f64]) -> f64 {
        assert_eq!(a.len(), b.len(), "kernel inputs of different dimension");
        let r2 = if self.lengthscales.len() == 1 {
            let inv = 1.0 / self.lengthscales[0];
            a.iter()
                .zip(b)
                .map(|(p, q)| {
                    let t = (p - q) * inv;
                    t * t
                })
                .sum()
        } else {
            assert_eq!(
                self.lengthscales.len(),
                a.len(),
                "ARD kernel with a lengthscale count other than the input dimension"
            );
            a.iter()
                .zip(b)
                .zip(&self.lengthscales)
                .map(|((p, q), l)| {
                    let t = (p - q) / l;
                    t * t
                })
                .sum()
        };
        k_of_r2(self.kind, self.signal_variance, r2)
    }

    /// The prior variance k(x, x) = σ_s² (the same everywhere: the kernels are stationary). This is
    /// K** of the RBCM (Prágr19 Eq. 8–9, decision 15).
    pub fn prior_variance(&self) -> f64 {
        self.signal_variance
    }

    /// Checks the hyperparameters against an input dimension.
    pub(crate) fn validate(&self, dim: usize) -> Result<(), GpError> {
        let n = self.lengthscales.len();
        if n != 1 && n != dim {
            return Err(GpError::BadHyperparameter(format!(
                "{n} lengthscales for input dimension {dim} (use 1 or {dim})"
            )));
        }
        if let Some(l) = self
            .lengthscales
            .iter()
            .find(|l| !(l.is_finite() && **l > 0.0))
        {
            return Err(GpError::BadHyperparameter(format!(
                "lengthscale {l} is not a positive finite number"
            )));
        }
        if !(self.signal_variance.is_finite() && self.signal_variance > 0.0) {
            return Err(GpError::BadHyperparameter(format!(
                "signal variance {} is not a positive finite number",
                self.signal_variance
            )));
        }
        Ok(())
    }

    /// 1 / lengthscale for every input dimension.
    pub(crate) fn inverse_lengthscales(&self, dim: usize) -> Vec<f64> {
        if self.lengthscales.len() == 1 {
            vec![1.0 / self.lengthscales[0]; dim]
        } else {
            self.lengthscales.iter().map(|l| 1.0 / l).collect()
        }
    }
}

/// k as a function of the squared scaled distance r².
#[inline]
pub(crate) fn k_of_r2(kind: KernelKind, s2: f64, r2: f64) -> f64 {
    match kind {
        KernelKind::SquaredExponential => s2 * (-0.5 * r2).exp(),
        KernelKind::Exponential => s2 * (-r2.sqrt()).exp(),
        KernelKind::Matern32 => {
            let a = 3f64.sqrt() * r2.sqrt();
            s2 * (1.0 + a) * (-a).exp()
        }
        KernelKind::Matern52 => {
            let a = 5f64.sqrt() * r2.sqrt();
            s2 * (1.0 + a + 5.0 / 3.0 * r2) * (-a).exp()
        }
    }
}

/// g(r²) = −2 ∂k/∂(r²), so that ∂k/∂ln l_j = g · Δ_j² / l_j² (and g · r² for an isotropic l).
/// For the exponential kernel at r = 0 (not differentiable there) it returns 0: every Δ_j is 0
/// and the product vanishes in the limit.
#[inline]
pub(crate) fn g_of_r2(kind: KernelKind, s2: f64, r2: f64) -> f64 {
    match kind {
        KernelKind::SquaredExponential => s2 * (-0.5 * r2).exp(),
        KernelKind::Exponential => {
            let r = r2.sqrt();
            if r > 0.0 { s2 * (-r).exp() / r } else { 0.0 }
        }
        KernelKind::Matern32 => {
            let a = 3f64.sqrt() * r2.sqrt();
            s2 * 3.0 * (-a).exp()
        }
        KernelKind::Matern52 => {
            let a = 5f64.sqrt() * r2.sqrt();
            s2 * 5.0 / 3.0 * (1.0 + a) * (-a).exp()
        }
    }
}

/// Squared distance of two already scaled points.
#[inline]
pub(crate) fn sq_dist(a: &[f64], b: &[f64]) -> f64 {
    let mut s = 0.0;
    for (p, q) in a.iter().zip(b) {
        let t = p - q;
        s += t * t;
    }
    s
}
