//! Type-II maximum likelihood: the log marginal likelihood's analytic gradient in log-space and a
//! bounded projected quasi-Newton (L-BFGS-B-style) maximiser (decision 13, for Prágr19 and
//! Nardi19).
//!
//! With α = K⁻¹(y − m) (K including σ_n²), ∂ ln p(y|X) / ∂θ = ½ tr((ααᵀ − K⁻¹) ∂K/∂θ)
//! (Rasmussen & Williams Eq. 5.9). The parameters are θ = (ln l₁ … ln l_k, ln σ_s², ln σ_n²),
//! with k = 1 (isotropic) or k = dim (ARD), as in the initial kernel.

use faer::dyn_stack::{MemBuffer, MemStack};
use faer::linalg::cholesky::llt::inverse::{inverse, inverse_scratch};
use faer::linalg::triangular_solve::solve_upper_triangular_in_place;
use faer::{Mat, Par};
use rayon::prelude::*;

use super::kernel::{g_of_r2, k_of_r2};
use super::{Gp, GpError, GpParams};

/// Box bounds (in natural units; all > 0) for [`fit_hyperparameters`], and its iteration limit.
/// A parameter with equal lower and upper bounds is held fixed.
#[derive(Clone, Debug, PartialEq)]
pub struct HyperBounds {
    /// Bounds of every lengthscale.
    pub lengthscale: (f64, f64),
    /// Bounds of the signal variance σ_s².
    pub signal_variance: (f64, f64),
    /// Bounds of the noise variance σ_n².
    pub noise_variance: (f64, f64),
    /// The most quasi-Newton iterations.
    pub max_iterations: usize,
}

impl Default for HyperBounds {
    /// Lengthscales in [10⁻², 10²], σ_s² in [10⁻³, 10³], σ_n² in [10⁻⁶, 10²], 200 iterations.
    fn default() -> Self {
        HyperBounds {
            lengthscale: (1e-2, 1e2),
            signal_variance: (1e-3, 1e3),
            noise_variance: (1e-6, 1e2),
            max_iterations: 200,
        }
    }
}

fn theta_of(p: &GpParams) -> Vec<f64> {
    let mut t: Vec<f64> = p.kernel.lengthscales.iter().map(|l| l.ln()).collect();
    t.push(p.kernel.signal_variance.ln());
    t.push(p.noise_variance.ln());
    t
}

fn params_of(theta: &[f64], base: &GpParams) -> GpParams {
    let k = theta.len() - 2;
    let mut p = base.clone();
    p.kernel.lengthscales = theta[..k].iter().map(|t| t.exp()).collect();
    p.kernel.signal_variance = theta[k].exp();
    p.noise_variance = theta[k + 1].exp();
    p
}

/// The log marginal likelihood of `params` on (x, y) and its gradient with respect to
/// (ln l₁ … ln l_k, ln σ_s², ln σ_n²). O(n³) (an inverse of K) plus O(n² dim).
pub fn log_marginal_likelihood_gradient(
    dim: usize,
    params: &GpParams,
    x: &[f64],
    y: &[f64],
) -> Result<(f64, Vec<f64>), GpError> {
    let gp = Gp::fit(dim, params.clone(), x, y)?;
    let lml = gp.log_marginal_likelihood();
    let n = gp.len();
    let nl = params.kernel.lengthscales.len();
    let mut grad = vec![0.0; nl + 2];
    if n == 0 {
        return Ok((lml, grad));
    }
    let l = gp.factor.view();
    let par = Par::rayon(0);
    // α = L⁻ᵀ w, K⁻¹ = L⁻ᵀ L⁻¹ (lower triangle).
    let mut alpha = Mat::<f64>::from_fn(n, 1, |i, _| gp.w[i]);
    solve_upper_triangular_in_place(l.transpose(), alpha.as_mut(), par);
    let mut kinv = Mat::<f64>::zeros(n, n);
    let mut buf = MemBuffer::new(inverse_scratch::<f64>(n, par));
    inverse(kinv.as_mut(), l, par, MemStack::new(&mut buf));
    let kind = params.kernel.kind;
    let s2 = params.kernel.signal_variance;
    let xs = &gp.xs;
    let d = dim;
    let kinv = &kinv;
    let alpha = &alpha;
    // Per-row partial sums, combined in row order (deterministic).
    let partial: Vec<Vec<f64>> = (0..n)
        .into_par_iter()
        .map(|i| {
            let mut g = vec![0.0; nl + 2];
            let xi = &xs[i * d..(i + 1) * d];
            for j in 0..=i {
                let wij = alpha[(i, 0)] * alpha[(j, 0)] - kinv[(i, j)];
                let f = if i == j { 0.5 } else { 1.0 }; // symmetric pair counted twice
                let xj = &xs[j * d..(j + 1) * d];
                let mut r2 = 0.0;
                for (a, b) in xi.iter().zip(xj) {
                    r2 += (a - b) * (a - b);
                }
                let kv = k_of_r2(kind, s2, r2);
                g[nl] += f * wij * kv;
                if i == j {
                    g[nl + 1] += f * wij * params.noise_variance;
                } else {
                    let gv = g_of_r2(kind, s2, r2);
                    if nl == 1 {
                        g[0] += f * wij * gv * r2;
                    } else {
                        for (k, (a, b)) in xi.iter().zip(xj).enumerate() {
                            g[k] += f * wij * gv * (a - b) * (a - b);
                        }
                    }
                }
            }
            g
        })
        .collect();
    for g in partial {
        for (a, b) in grad.iter_mut().zip(g) {
            *a += b;
        }
    }
    Ok((lml, grad))
}

/// Maximises the log marginal likelihood over the lengthscales, σ_s² and σ_n² within `bounds`,
/// starting from `init` (whose prior mean and kernel kind are kept, and whose lengthscale count
/// decides isotropic vs ARD). A projected L-BFGS in log-space: variables at a bound whose gradient
/// points outwards are frozen for the step, the quasi-Newton direction (memory 10) is taken on the
/// rest, and a backtracking Armijo search runs along the projected path. Deterministic; one start.
pub fn fit_hyperparameters(
    dim: usize,
    x: &[f64],
    y: &[f64],
    init: GpParams,
    bounds: &HyperBounds,
) -> Result<GpParams, GpError> {
    init.validate(dim)?;
    check_bounds(bounds)?;
    let region = LogBox::new(init.kernel.lengthscales.len(), bounds);
    // Minimise f = −lml.
    let eval = |t: &[f64]| -> Option<(f64, Vec<f64>)> {
        let p = params_of(t, &init);
        match log_marginal_likelihood_gradient(dim, &p, x, y) {
            Ok((l, g)) if l.is_finite() && g.iter().all(|v| v.is_finite()) => {
                Some((-l, g.into_iter().map(|v| -v).collect()))
            }
            _ => None,
        }
    };
    let mut theta = theta_of(&init);
    region.project(&mut theta);
    let Some((mut f, mut g)) = eval(&theta) else {
        // The start itself fails: report why.
        let p = params_of(&theta, &init);
        Gp::fit(dim, p, x, y)?;
        return Err(GpError::BadHyperparameter(
            "log marginal likelihood not finite at the initial hyperparameters".into(),
        ));
    };
    let mut memory = Lbfgs::new(10);
    for _ in 0..bounds.max_iterations {
        let free = region.free_variables(&theta, &g);
        let pg: Vec<f64> = (0..theta.len())
            .map(|i| if free[i] { g[i] } else { 0.0 })
            .collect();
        if pg.iter().fold(0.0f64, |m, v| m.max(v.abs())) < 1e-6 {
            break;
        }
        let dir = memory.direction(&pg, &free);
        let t = first_step(&dir, memory.is_empty());
        let Some((cand, step, fc, gc)) = line_search(&theta, &dir, t, f, &g, &region, &eval) else {
            break;
        };
        let yv: Vec<f64> = gc.iter().zip(&g).map(|(a, b)| a - b).collect();
        memory.remember(step, yv);
        let done = (f - fc).abs() <= 1e-12 * f.abs().max(1.0);
        theta = cand;
        f = fc;
        g = gc;
        if done {
            break;
        }
    }
    Ok(params_of(&theta, &init))
}

/// Every bound finite, positive and ordered.
fn check_bounds(bounds: &HyperBounds) -> Result<(), GpError> {
    for (name, (lo, hi)) in [
        ("lengthscale", bounds.lengthscale),
        ("signal variance", bounds.signal_variance),
        ("noise variance", bounds.noise_variance),
    ] {
        if !(lo.is_finite() && hi.is_finite() && lo > 0.0 && lo <= hi) {
            return Err(GpError::BadHyperparameter(format!(
                "{name} bounds ({lo}, {hi}) must be finite, positive and ordered"
            )));
        }
    }
    Ok(())
}

/// The bounds in log-space, per variable θ = (ln l₁ … ln l_k, ln σ_s², ln σ_n²).
struct LogBox {
    lo: Vec<f64>,
    hi: Vec<f64>,
}

impl LogBox {
    /// The box of `bounds` for `nl` lengthscales.
    fn new(nl: usize, bounds: &HyperBounds) -> Self {
        let mut lo = vec![bounds.lengthscale.0.ln(); nl];
        let mut hi = vec![bounds.lengthscale.1.ln(); nl];
        lo.push(bounds.signal_variance.0.ln());
        hi.push(bounds.signal_variance.1.ln());
        lo.push(bounds.noise_variance.0.ln());
        hi.push(bounds.noise_variance.1.ln());
        LogBox { lo, hi }
    }

    /// Moves `t` into the box.
    fn project(&self, t: &mut [f64]) {
        for ((v, a), b) in t.iter_mut().zip(&self.lo).zip(&self.hi) {
            *v = v.clamp(*a, *b);
        }
    }

    /// The variables that may move: not held fixed, and not at a bound with the gradient `g` of
    /// the minimised function pushing outwards.
    fn free_variables(&self, theta: &[f64], g: &[f64]) -> Vec<bool> {
        let (lo, hi) = (&self.lo, &self.hi);
        (0..theta.len())
            .map(|i| {
                !(lo[i] == hi[i]
                    || (theta[i] <= lo[i] && g[i] > 0.0)
                    || (theta[i] >= hi[i] && g[i] < 0.0))
            })
            .collect()
    }
}

fn dotv(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).map(|(p, q)| p * q).sum::<f64>()
}

/// The L-BFGS memory: the last steps s and gradient changes y, oldest first.
struct Lbfgs {
    ss: Vec<Vec<f64>>,
    ys: Vec<Vec<f64>>,
    len: usize,
}

impl Lbfgs {
    fn new(len: usize) -> Self {
        Lbfgs {
            ss: Vec::new(),
            ys: Vec::new(),
            len,
        }
    }

    fn is_empty(&self) -> bool {
        self.ss.is_empty()
    }

    /// The quasi-Newton descent direction for the projected gradient `pg` on the `free`
    /// variables (the two-loop recursion); when that is no descent direction, steepest descent,
    /// and the memory is forgotten.
    fn direction(&mut self, pg: &[f64], free: &[bool]) -> Vec<f64> {
        let (ss, ys) = (&self.ss, &self.ys);
        let mut q = pg.to_vec();
        let mut alphas = Vec::with_capacity(ss.len());
        for (s, yv) in ss.iter().zip(ys).rev() {
            let rho = 1.0 / dotv(s, yv);
            let a = rho * dotv(s, &q);
            for (qi, (yi, fi)) in q.iter_mut().zip(yv.iter().zip(free)) {
                if *fi {
                    *qi -= a * yi;
                }
            }
            alphas.push((a, rho));
        }
        if let (Some(s), Some(yv)) = (ss.last(), ys.last()) {
            let gamma = dotv(s, yv) / dotv(yv, yv);
            q.iter_mut().for_each(|v| *v *= gamma);
        }
        for ((s, yv), (a, rho)) in ss.iter().zip(ys).zip(alphas.into_iter().rev()) {
            let b = rho * dotv(yv, &q);
            for (qi, (si, fi)) in q.iter_mut().zip(s.iter().zip(free)) {
                if *fi {
                    *qi += (a - b) * si;
                }
            }
        }
        let dir: Vec<f64> = (0..pg.len())
            .map(|i| if free[i] { -q[i] } else { 0.0 })
            .collect();
        if dotv(&dir, pg) >= 0.0 {
            self.ss.clear();
            self.ys.clear();
            return pg.iter().map(|v| -v).collect();
        }
        dir
    }

    /// Keeps the pair (step, gradient change) when its curvature is positive enough, dropping
    /// the oldest beyond the memory's length.
    fn remember(&mut self, step: Vec<f64>, yv: Vec<f64>) {
        let sy = dotv(&step, &yv);
        if sy > 1e-10 * dotv(&step, &step).sqrt() * dotv(&yv, &yv).sqrt() {
            self.ss.push(step);
            self.ys.push(yv);
            if self.ss.len() > self.len {
                self.ss.remove(0);
                self.ys.remove(0);
            }
        }
    }
}

/// The first step length along `dir`: at most 2 in log-space per coordinate (a factor e²), and
/// without a memory a unit step of the largest coordinate.
fn first_step(dir: &[f64], no_memory: bool) -> f64 {
    let dmax = dir.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    let mut t = if no_memory {
        (1.0 / dmax).min(1.0)
    } else {
        1.0
    };
    if dmax * t > 2.0 {
        t = 2.0 / dmax;
    }
    t
}

/// A candidate θ, its step from the current θ, and f and its gradient there.
type Accepted = (Vec<f64>, Vec<f64>, f64, Vec<f64>);

/// Backtracking Armijo search along the projected path θ + t·dir, halving t up to 40 times;
/// `None` when no step decreases f enough.
fn line_search(
    theta: &[f64],
    dir: &[f64],
    mut t: f64,
    f: f64,
    g: &[f64],
    region: &LogBox,
    eval: &impl Fn(&[f64]) -> Option<(f64, Vec<f64>)>,
) -> Option<Accepted> {
    for _ in 0..40 {
        let mut cand: Vec<f64> = theta.iter().zip(dir).map(|(a, b)| a + t * b).collect();
        region.project(&mut cand);
        let step: Vec<f64> = cand.iter().zip(theta).map(|(a, b)| a - b).collect();
        if let Some((fc, gc)) = eval(&cand)
            && fc <= f + 1e-4 * dotv(g, &step)
        {
            return Some((cand, step, fc, gc));
        }
        t *= 0.5;
    }
    None
}
