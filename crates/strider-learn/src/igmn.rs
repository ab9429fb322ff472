//! The Incremental Gaussian Mixture Network (IGMN) regressor of the Prágr18 learner benchmark
//! and of the Prágr19 §V-A comparison (Heinen, Engel & Pinto 2011; Pinto & Engel 2015, "A Fast
//! Incremental Gaussian Mixture Model").
//!
//! # Variant
//!
//! A Gaussian mixture over the *joint* space z = (x, y) ∈ ℝ^D, D = dim + 1, learned one pair at a
//! time in a single pass. Per component j: mean μ_j, full covariance C_j, age v_j and accumulated
//! posterior sp_j. For a new z:
//!
//! 1. **Novelty** (IGMN's χ² criterion): z is novel when its squared Mahalanobis distance
//!    d²_j = (z − μ_j)ᵀ C_j⁻¹ (z − μ_j) reaches the χ²_{D, 1−β} quantile for every component.
//!    A novel z creates a component μ = z, C = diag((δ σ_k)²), v = 1, sp = 1, where σ_k is the
//!    data's standard deviation in dimension k (given at construction) and δ the scaling factor —
//!    unless the cap of K components is reached, in which case z updates the mixture as in 2.
//! 2. **Update** of every component with its posterior p(j|z) ∝ N(z; μ_j, C_j) · sp_j:
//!    v_j += 1, sp_j += p(j|z), ω_j = p(j|z)/sp_j, Δμ_j = ω_j (z − μ_j), μ_j += Δμ_j,
//!    e*_j = z − μ_j, C_j ← (1 − ω_j) C_j + ω_j e*_j e*_jᵀ − Δμ_j Δμ_jᵀ.
//! 3. **Pruning** (Fast-IGMN): a component with v_j > v_min and sp_j < sp_min is removed (never the
//!    last one).
//!
//! **Recall** (prediction) of y from x: with each component split into input (a) and target (b)
//! blocks, p(j|x) ∝ N(x; μ_a,j, C_aa,j) · sp_j and ŷ = Σ_j p(j|x) (μ_b,j + C_ba,j C_aa,j⁻¹ (x − μ_a,j)).
//! All likelihoods are handled in log space (log-sum-exp), so a query far from every component
//! still gets a finite convex combination of the components' regressions. As in the papers the
//! IGMN gives no model confidence: [`Igmn::predict`] returns the mean only.
//!
//! # Parameters (Prágr18 §III-B.3)
//! K = 10 components, grace period v_min = 100, sp_min = 3, δ = 1 ([`IgmnParams::default`]); the
//! novelty level β = 0.1 is not given in Prágr18 (0.1 is the value of Heinen et al.).
//!
//! # Why covariances rather than Fast-IGMN's precision matrices
//! Fast-IGMN keeps C⁻¹ and |C| by two rank-one (Sherman–Morrison) updates, O(K D²) per point. The
//! second one is a *downdate* (− Δμ Δμᵀ) that drifts away from positive definiteness in floating
//! point, and our descriptors are often degenerate (decision 7: a flat patch has constant shape
//! features, a missing colour constant appearance features). This module keeps C_j and
//! re-factorises it (Cholesky, O(D³)) after each update instead, with every variance floored at
//! (10⁻³ δ σ_k)² and a jitter ladder as a last resort. For D ≤ 15 that is a few microseconds per
//! point and per component, so the learner stays the fastest of the benchmark (Prágr19 Fig. 5a).
//!
//! The χ² quantile uses the Wilson–Hilferty approximation (≈ 1 % accurate for D ≥ 2).

use thiserror::Error;

/// Errors of the IGMN.
#[derive(Clone, Debug, Error, PartialEq)]
pub enum IgmnError {
    /// A parameter out of its domain.
    #[error("bad IGMN parameter: {0}")]
    BadParameter(String),
    /// An input of the wrong length.
    #[error("input of length {got} for dimension {want}")]
    BadDimension {
        /// The length given.
        got: usize,
        /// The expected length.
        want: usize,
    },
    /// A non-finite input or target (rejected, never stored).
    #[error("{0} is not finite")]
    NonFinite(String),
}

/// IGMN parameters (Prágr18 §III-B.3).
#[derive(Clone, Debug, PartialEq)]
pub struct IgmnParams {
    /// Cap K on the number of components (≥ 1).
    pub max_components: usize,
    /// Grace period v_min: a component older than this with sp < sp_min is pruned.
    pub v_min: u64,
    /// Minimal accumulated posterior sp_min.
    pub sp_min: f64,
    /// Scaling factor δ of a new component's standard deviations (δ × the data's std).
    pub delta: f64,
    /// Novelty level β: z is novel beyond the χ²_{D,1−β} quantile of every component.
    pub beta: f64,
}

impl Default for IgmnParams {
    /// K = 10, v_min = 100, sp_min = 3, δ = 1 (Prágr18), β = 0.1 (Heinen et al.).
    fn default() -> Self {
        IgmnParams {
            max_components: 10,
            v_min: 100,
            sp_min: 3.0,
            delta: 1.0,
            beta: 0.1,
        }
    }
}

/// One Gaussian component over the joint space.
#[derive(Clone, Debug)]
struct Component {
    mean: Vec<f64>,
    /// Full covariance, D × D row-major.
    cov: Vec<f64>,
    /// Lower Cholesky factor of `cov`.
    chol: Vec<f64>,
    /// ln |C|.
    log_det: f64,
    /// Lower Cholesky factor of the input block C_aa (dim × dim).
    chol_aa: Vec<f64>,
    /// ln |C_aa|.
    log_det_aa: f64,
    /// Regression weights C_aa⁻¹ C_ab (dim).
    w: Vec<f64>,
    /// Age v (points seen since creation).
    v: u64,
    /// Accumulated posterior sp.
    sp: f64,
}

/// An incremental Gaussian mixture network regressor over `dim` inputs and one target.
#[derive(Clone, Debug)]
pub struct Igmn {
    dim: usize,
    params: IgmnParams,
    /// δ σ_k per joint dimension (the initial standard deviations).
    sigma_ini: Vec<f64>,
    /// Floors of the joint variances.
    var_floor: Vec<f64>,
    /// χ²_{D,1−β}.
    chi2: f64,
    comps: Vec<Component>,
    created: u64,
    pruned: u64,
    seen: u64,
}

impl Igmn {
    /// An empty network for `dim` inputs. `scale` holds dim + 1 standard deviations of the data
    /// (inputs, then the target) that size new components (× δ). Zero or non-finite entries (a
    /// constant feature) are replaced by the largest valid entry (or 1): a constant dimension
    /// carries no information, so any positive width works.
    pub fn new(dim: usize, params: IgmnParams, scale: &[f64]) -> Result<Igmn, IgmnError> {
        if dim == 0 {
            return Err(IgmnError::BadParameter(
                "input dimension must be ≥ 1".into(),
            ));
        }
        if params.max_components == 0 {
            return Err(IgmnError::BadParameter("max_components must be ≥ 1".into()));
        }
        if !(params.delta.is_finite() && params.delta > 0.0) {
            return Err(IgmnError::BadParameter(format!(
                "delta {} must be positive",
                params.delta
            )));
        }
        if !(params.beta.is_finite() && params.beta > 0.0 && params.beta < 1.0) {
            return Err(IgmnError::BadParameter(format!(
                "beta {} must lie in (0, 1)",
                params.beta
            )));
        }
        if !(params.sp_min.is_finite() && params.sp_min >= 0.0) {
            return Err(IgmnError::BadParameter(format!(
                "sp_min {} must be non-negative",
                params.sp_min
            )));
        }
        if scale.len() != dim + 1 {
            return Err(IgmnError::BadDimension {
                got: scale.len(),
                want: dim + 1,
            });
        }
        let valid = |s: f64| s.is_finite() && s > 0.0;
        let largest = scale
            .iter()
            .copied()
            .filter(|s| valid(*s))
            .fold(0.0, f64::max);
        let fallback = if largest > 0.0 { largest } else { 1.0 };
        let sigma_ini: Vec<f64> = scale
            .iter()
            .map(|&s| {
                params.delta
                    * if valid(s) && s > 1e-9 * fallback {
                        s
                    } else {
                        fallback
                    }
            })
            .collect();
        let var_floor = sigma_ini.iter().map(|s| (1e-3 * s).powi(2)).collect();
        let chi2 = chi2_quantile(dim + 1, 1.0 - params.beta);
        Ok(Igmn {
            dim,
            params,
            sigma_ini,
            var_floor,
            chi2,
            comps: Vec::new(),
            created: 0,
            pruned: 0,
            seen: 0,
        })
    }

    /// The input dimension.
    pub fn dim(&self) -> usize {
        self.dim
    }

    /// The parameters.
    pub fn params(&self) -> &IgmnParams {
        &self.params
    }

    /// The number of live components.
    pub fn components(&self) -> usize {
        self.comps.len()
    }

    /// Components created and pruned so far.
    pub fn created_pruned(&self) -> (u64, u64) {
        (self.created, self.pruned)
    }

    /// The number of pairs learned.
    pub fn len(&self) -> u64 {
        self.seen
    }

    /// True before the first pair.
    pub fn is_empty(&self) -> bool {
        self.seen == 0
    }

    /// The joint mean (inputs then target) of component `j`.
    ///
    /// # Panics
    /// If `j >= components()`.
    pub fn component_mean(&self, j: usize) -> &[f64] {
        &self.comps[j].mean
    }

    /// The joint covariance (D × D row-major) of component `j`.
    ///
    /// # Panics
    /// If `j >= components()`.
    pub fn component_covariance(&self, j: usize) -> &[f64] {
        &self.comps[j].cov
    }

    /// Learns one pair (steps 1–3 of the module docs). On error nothing changes.
    pub fn learn(&mut self, x: &[f64], y: f64) -> Result<(), IgmnError> {
        if x.len() != self.dim {
            return Err(IgmnError::BadDimension {
                got: x.len(),
                want: self.dim,
            });
        }
        if let Some(k) = x.iter().position(|v| !v.is_finite()) {
            return Err(IgmnError::NonFinite(format!("x[{k}]")));
        }
        if !y.is_finite() {
            return Err(IgmnError::NonFinite("y".into()));
        }
        let mut z = x.to_vec();
        z.push(y);
        self.seen += 1;
        let d2: Vec<f64> = self
            .comps
            .iter()
            .map(|c| mahalanobis2(&c.chol, &c.mean, &z))
            .collect();
        let novel = d2.iter().all(|&d| d.is_nan() || d >= self.chi2);
        if novel && self.comps.len() < self.params.max_components {
            self.create(z);
        } else {
            self.update(&z, &d2);
        }
        self.prune();
        Ok(())
    }

    /// The predicted target at `x` (the recall of the module docs); `None` before the first pair.
    ///
    /// # Panics
    /// If `x.len() != dim()`.
    pub fn predict(&self, x: &[f64]) -> Option<f64> {
        assert_eq!(x.len(), self.dim, "query of the wrong dimension");
        if self.comps.is_empty() {
            return None;
        }
        let d = self.dim;
        let total_sp: f64 = self.comps.iter().map(|c| c.sp).sum();
        let mut logw = Vec::with_capacity(self.comps.len());
        let mut est = Vec::with_capacity(self.comps.len());
        for c in &self.comps {
            let d2 = mahalanobis2(&c.chol_aa, &c.mean[..d], x);
            logw.push(-0.5 * d2 - 0.5 * c.log_det_aa + (c.sp / total_sp).ln());
            let yj = c.mean[d]
                + c.w
                    .iter()
                    .zip(x)
                    .zip(&c.mean)
                    .map(|((w, xk), m)| w * (xk - m))
                    .sum::<f64>();
            est.push(yj);
        }
        let post = softmax(&logw);
        let y: f64 = post.iter().zip(&est).map(|(p, e)| p * e).sum();
        // A non-finite query gives NaN weights; fall back to the sp-weighted component means.
        Some(if y.is_finite() {
            y
        } else {
            self.comps.iter().map(|c| c.sp * c.mean[d]).sum::<f64>() / total_sp
        })
    }

    fn create(&mut self, z: Vec<f64>) {
        let n = self.dim + 1;
        let mut cov = vec![0.0; n * n];
        for k in 0..n {
            cov[k * n + k] = self.sigma_ini[k] * self.sigma_ini[k];
        }
        let mut c = Component {
            mean: z,
            cov,
            chol: Vec::new(),
            log_det: 0.0,
            chol_aa: Vec::new(),
            log_det_aa: 0.0,
            w: Vec::new(),
            v: 1,
            sp: 1.0,
        };
        self.refresh(&mut c);
        self.comps.push(c);
        self.created += 1;
    }

    fn update(&mut self, z: &[f64], d2: &[f64]) {
        let n = self.dim + 1;
        let total_sp: f64 = self.comps.iter().map(|c| c.sp).sum();
        let logp: Vec<f64> = self
            .comps
            .iter()
            .zip(d2)
            .map(|(c, &d)| -0.5 * d - 0.5 * c.log_det + (c.sp / total_sp).ln())
            .collect();
        let post = softmax(&logp);
        let mut comps = std::mem::take(&mut self.comps);
        for (c, &p) in comps.iter_mut().zip(&post) {
            c.v += 1;
            c.sp += p;
            let omega = p / c.sp;
            if omega <= 0.0 {
                continue;
            }
            let dmu: Vec<f64> = (0..n).map(|k| omega * (z[k] - c.mean[k])).collect();
            for (m, dm) in c.mean.iter_mut().zip(&dmu) {
                *m += dm;
            }
            let e: Vec<f64> = (0..n).map(|k| z[k] - c.mean[k]).collect();
            for a in 0..n {
                for b in 0..n {
                    c.cov[a * n + b] =
                        (1.0 - omega) * c.cov[a * n + b] + omega * e[a] * e[b] - dmu[a] * dmu[b];
                }
            }
            self.refresh(c);
        }
        self.comps = comps;
    }

    fn prune(&mut self) {
        let (v_min, sp_min) = (self.params.v_min, self.params.sp_min);
        let doomed = |c: &Component| c.v > v_min && c.sp < sp_min;
        if self.comps.iter().all(doomed) {
            return; // never remove the last component
        }
        let before = self.comps.len();
        self.comps.retain(|c| !doomed(c));
        self.pruned += (before - self.comps.len()) as u64;
    }

    /// Symmetrises and floors the covariance, then recomputes the factors and the recall weights.
    fn refresh(&self, c: &mut Component) {
        let n = self.dim + 1;
        for a in 0..n {
            for b in 0..a {
                let m = 0.5 * (c.cov[a * n + b] + c.cov[b * n + a]);
                c.cov[a * n + b] = m;
                c.cov[b * n + a] = m;
            }
            let v = &mut c.cov[a * n + a];
            if v.is_nan() || *v < self.var_floor[a] {
                *v = self.var_floor[a];
            }
        }
        let (chol, log_det) = cholesky_jitter(&c.cov, n, &self.var_floor);
        c.chol = chol;
        c.log_det = log_det;
        let d = self.dim;
        let mut aa = vec![0.0; d * d];
        for a in 0..d {
            for b in 0..d {
                aa[a * d + b] = c.cov[a * n + b];
            }
        }
        let (chol_aa, log_det_aa) = cholesky_jitter(&aa, d, &self.var_floor[..d]);
        let ab: Vec<f64> = (0..d).map(|a| c.cov[a * n + d]).collect();
        c.w = chol_solve(&chol_aa, d, &ab);
        c.chol_aa = chol_aa;
        c.log_det_aa = log_det_aa;
    }
}

/// Softmax of log weights (max-shifted); uniform when all are −∞ or NaN.
fn softmax(logw: &[f64]) -> Vec<f64> {
    let m = logw
        .iter()
        .copied()
        .filter(|v| v.is_finite())
        .fold(f64::NEG_INFINITY, f64::max);
    if !m.is_finite() {
        return vec![1.0 / logw.len() as f64; logw.len()];
    }
    let w: Vec<f64> = logw
        .iter()
        .map(|&l| if l.is_finite() { (l - m).exp() } else { 0.0 })
        .collect();
    let s: f64 = w.iter().sum();
    w.into_iter().map(|v| v / s).collect()
}

/// Cholesky factor (lower, row-major) and ln-determinant of the SPD `a` (n × n); if `a` is not
/// numerically positive definite, `floor`-scaled jitter (1, 10, 100, … × floor) is added to the
/// diagonal until it is. As the last resort the diagonal of `a` alone is used.
fn cholesky_jitter(a: &[f64], n: usize, floor: &[f64]) -> (Vec<f64>, f64) {
    let mut scale = 0.0;
    for _ in 0..12 {
        let mut m = a.to_vec();
        for k in 0..n {
            m[k * n + k] += scale * floor[k];
        }
        if let Some(r) = cholesky(&m, n) {
            return r;
        }
        scale = if scale == 0.0 { 1.0 } else { scale * 10.0 };
    }
    let mut l = vec![0.0; n * n];
    let mut log_det = 0.0;
    for k in 0..n {
        let v = a[k * n + k].max(floor[k]).max(f64::MIN_POSITIVE);
        l[k * n + k] = v.sqrt();
        log_det += v.ln();
    }
    (l, log_det)
}

fn cholesky(a: &[f64], n: usize) -> Option<(Vec<f64>, f64)> {
    let mut l = vec![0.0; n * n];
    let mut log_det = 0.0;
    for i in 0..n {
        for j in 0..=i {
            let mut s = a[i * n + j];
            for k in 0..j {
                s -= l[i * n + k] * l[j * n + k];
            }
            if i == j {
                if !(s > 0.0 && s.is_finite()) {
                    return None;
                }
                let r = s.sqrt();
                l[i * n + i] = r;
                log_det += 2.0 * r.ln();
            } else {
                l[i * n + j] = s / l[j * n + j];
            }
        }
    }
    Some((l, log_det))
}

/// L⁻¹ (x − μ) by forward substitution, then its squared norm.
fn mahalanobis2(l: &[f64], mean: &[f64], x: &[f64]) -> f64 {
    let n = mean.len();
    let mut v = vec![0.0; n];
    let mut s2 = 0.0;
    for i in 0..n {
        let mut s = x[i] - mean[i];
        for k in 0..i {
            s -= l[i * n + k] * v[k];
        }
        v[i] = s / l[i * n + i];
        s2 += v[i] * v[i];
    }
    s2
}

/// Solves (L Lᵀ) w = b.
fn chol_solve(l: &[f64], n: usize, b: &[f64]) -> Vec<f64> {
    let mut v = vec![0.0; n];
    for i in 0..n {
        let mut s = b[i];
        for k in 0..i {
            s -= l[i * n + k] * v[k];
        }
        v[i] = s / l[i * n + i];
    }
    for i in (0..n).rev() {
        let mut s = v[i];
        for k in i + 1..n {
            s -= l[k * n + i] * v[k];
        }
        v[i] = s / l[i * n + i];
    }
    v
}

/// The p-quantile of χ² with `k` degrees of freedom by Wilson–Hilferty:
/// k (1 − 2/(9k) + z_p √(2/(9k)))³ with z_p the standard normal quantile.
pub fn chi2_quantile(k: usize, p: f64) -> f64 {
    let k = k as f64;
    let a = 2.0 / (9.0 * k);
    let t = 1.0 - a + normal_quantile(p) * a.sqrt();
    (k * t * t * t).max(0.0)
}

/// The standard normal quantile (Acklam's rational approximation, relative error < 1.2e-9),
/// for p in (0, 1); ±∞ at the ends.
pub fn normal_quantile(p: f64) -> f64 {
    const A: [f64; 6] = [
        -3.969683028665376e1,
        2.209460984245205e2,
        -2.759285104469687e2,
        1.383_577_518_672_69e2,
        -3.066479806614716e1,
        2.506628277459239,
    ];
    const B: [f64; 5] = [
        -5.447609879822406e1,
        1.615858368580409e2,
        -1.556989798598866e2,
        6.680131188771972e1,
        -1.328068155288572e1,
    ];
    const C: [f64; 6] = [
        -7.784894002430293e-3,
        -3.223964580411365e-1,
        -2.400758277161838,
        -2.549732539343734,
        4.374664141464968,
        2.938163982698783,
    ];
    const D: [f64; 4] = [
        7.784695709041462e-3,
        3.224671290700398e-1,
        2.445134137142996,
        3.754408661907416,
    ];
    if p.is_nan() {
        return f64::NAN;
    }
    if p <= 0.0 {
        return f64::NEG_INFINITY;
    }
    if p >= 1.0 {
        return f64::INFINITY;
    }
    let lo = 0.02425;
    if p < lo {
        let q = (-2.0 * p.ln()).sqrt();
        (((((C[0] * q + C[1]) * q + C[2]) * q + C[3]) * q + C[4]) * q + C[5])
            / ((((D[0] * q + D[1]) * q + D[2]) * q + D[3]) * q + 1.0)
    } else if p <= 1.0 - lo {
        let q = p - 0.5;
        let r = q * q;
        (((((A[0] * r + A[1]) * r + A[2]) * r + A[3]) * r + A[4]) * r + A[5]) * q
            / (((((B[0] * r + B[1]) * r + B[2]) * r + B[3]) * r + B[4]) * r + 1.0)
    } else {
        -normal_quantile(1.0 - p)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn quantiles_match_tables() {
        assert!((normal_quantile(0.975) - 1.959963985).abs() < 1e-6);
        assert!((normal_quantile(0.5)).abs() < 1e-12);
        // χ²_{6, 0.9} = 10.6446, χ²_{2, 0.9} = 4.6052 (tables).
        assert!((chi2_quantile(6, 0.9) - 10.6446).abs() < 0.05);
        assert!((chi2_quantile(2, 0.9) - 4.6052).abs() < 0.1);
    }

    #[test]
    fn cholesky_solve_roundtrip() {
        let a = [4.0, 2.0, 2.0, 3.0];
        let (l, ld) = cholesky(&a, 2).unwrap();
        assert!((ld - 8f64.ln()).abs() < 1e-12);
        let w = chol_solve(&l, 2, &[2.0, 1.0]);
        assert!((4.0 * w[0] + 2.0 * w[1] - 2.0).abs() < 1e-12);
        assert!((2.0 * w[0] + 3.0 * w[1] - 1.0).abs() < 1e-12);
    }
}
