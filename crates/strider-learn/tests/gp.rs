//! The GP against direct dense solves, refits and hand-computed values.

use proptest::prelude::*;
use rand::rngs::ChaCha8Rng;
use rand::{RngExt, SeedableRng};
use strider_learn::gp::{
    Gp, GpError, GpParams, HyperBounds, Kernel, KernelKind, fit_hyperparameters,
    log_marginal_likelihood_gradient,
};

const KINDS: [KernelKind; 4] = [
    KernelKind::SquaredExponential,
    KernelKind::Exponential,
    KernelKind::Matern32,
    KernelKind::Matern52,
];

fn params(kind: KernelKind, ls: Vec<f64>, s2: f64, noise: f64, m: f64) -> GpParams {
    GpParams {
        kernel: Kernel {
            kind,
            lengthscales: ls,
            signal_variance: s2,
        },
        noise_variance: noise,
        prior_mean: m,
    }
}

/// Solves A z = b by Gaussian elimination with partial pivoting (the naive O(n³) oracle).
fn dense_solve(mut a: Vec<Vec<f64>>, mut b: Vec<f64>) -> Vec<f64> {
    let n = b.len();
    for c in 0..n {
        let p = (c..n)
            .max_by(|&i, &j| a[i][c].abs().total_cmp(&a[j][c].abs()))
            .unwrap();
        a.swap(c, p);
        b.swap(c, p);
        let pivot_row = a[c].clone();
        for r in c + 1..n {
            let f = a[r][c] / pivot_row[c];
            for (v, pv) in a[r][c..].iter_mut().zip(&pivot_row[c..]) {
                *v -= f * pv;
            }
            b[r] -= f * b[c];
        }
    }
    let mut z = vec![0.0; n];
    for r in (0..n).rev() {
        let s: f64 = (r + 1..n).map(|k| a[r][k] * z[k]).sum();
        z[r] = (b[r] - s) / a[r][r];
    }
    z
}

/// (mean, latent variance) by direct dense solves of (K + σ_n² I).
fn naive_predict(p: &GpParams, d: usize, x: &[f64], y: &[f64], q: &[f64]) -> (f64, f64) {
    let n = y.len();
    let k = &p.kernel;
    let pt = |i: usize| &x[i * d..(i + 1) * d];
    let a: Vec<Vec<f64>> = (0..n)
        .map(|i| {
            (0..n)
                .map(|j| k.eval(pt(i), pt(j)) + if i == j { p.noise_variance } else { 0.0 })
                .collect()
        })
        .collect();
    let ks: Vec<f64> = (0..n).map(|i| k.eval(pt(i), q)).collect();
    let alpha = dense_solve(a.clone(), y.iter().map(|v| v - p.prior_mean).collect());
    let u = dense_solve(a, ks.clone());
    let mean = p.prior_mean + ks.iter().zip(&alpha).map(|(a, b)| a * b).sum::<f64>();
    let var = k.prior_variance() - ks.iter().zip(&u).map(|(a, b)| a * b).sum::<f64>();
    (mean, var.max(0.0))
}

/// A GP with the points of (`x`, `y`) pushed one at a time.
fn pushed_one_by_one(d: usize, p: &GpParams, x: &[f64], y: &[f64]) -> Gp {
    let mut gp = Gp::new(d, p.clone()).unwrap();
    for (xi, &yi) in x.chunks_exact(d).zip(y) {
        gp.push(xi, yi).unwrap();
    }
    gp
}

fn random_data(rng: &mut ChaCha8Rng, n: usize, d: usize) -> (Vec<f64>, Vec<f64>) {
    let x: Vec<f64> = (0..n * d).map(|_| rng.random_range(-1.0..1.0)).collect();
    let y: Vec<f64> = (0..n)
        .map(|i| (3.0 * x[i * d]).sin() + rng.random_range(-0.3..0.3))
        .collect();
    (x, y)
}

fn assert_close(a: (f64, f64), b: (f64, f64), tol: f64, what: &str) {
    assert!(
        (a.0 - b.0).abs() <= tol * (1.0 + b.0.abs())
            && (a.1 - b.1).abs() <= tol * (1.0 + b.1.abs()),
        "{what}: {a:?} vs {b:?}"
    );
}

fn pred(gp: &Gp, q: &[f64]) -> (f64, f64) {
    let p = gp.predict(q);
    (p.mean, p.latent_variance)
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(48))]

    /// Points pushed one by one give the same model as a batch fit and as a dense solve.
    #[test]
    fn push_equals_fit_and_dense_solve(
        seed in 0u64..1_000_000,
        n in 1usize..28,
        d in 1usize..4,
        kind in 0usize..4,
        ard in any::<bool>(),
        noise in 0.01f64..1.0,
        m in -1.0f64..1.0,
    ) {
        let mut rng = ChaCha8Rng::seed_from_u64(seed);
        let (x, y) = random_data(&mut rng, n, d);
        let ls = if ard { (0..d).map(|_| rng.random_range(0.2..2.0)).collect() } else { vec![0.6] };
        let p = params(KINDS[kind], ls, rng.random_range(0.5..2.0), noise, m);
        let fitted = Gp::fit(d, p.clone(), &x, &y).unwrap();
        let pushed = pushed_one_by_one(d, &p, &x, &y);
        prop_assert_eq!(pushed.len(), n);
        prop_assert!((pushed.log_marginal_likelihood() - fitted.log_marginal_likelihood()).abs() < 1e-8);
        let queries: Vec<f64> = (0..5 * d).map(|_| rng.random_range(-1.5..1.5)).collect();
        let mut mb = vec![0.0; 5];
        let mut vb = vec![0.0; 5];
        fitted.predict_batch(&queries, &mut mb, &mut vb).unwrap();
        for (j, q) in queries.chunks_exact(d).chain(x.chunks_exact(d).take(3)).enumerate() {
            let naive = naive_predict(&p, d, &x, &y, q);
            assert_close(pred(&pushed, q), naive, 1e-8, "pushed vs naive");
            assert_close(pred(&fitted, q), naive, 1e-8, "fitted vs naive");
            if j < 5 {
                assert_close((mb[j], vb[j]), naive, 1e-8, "batch vs naive");
            }
        }
    }

    /// Points added by `extend` in two blocks (the second extending a non-empty GP) give the
    /// model of a dense solve, and the same as pushing them one by one.
    #[test]
    fn extend_equals_push_and_dense_solve(
        seed in 0u64..1_000_000,
        n0 in 0usize..12,
        k in 0usize..20,
        d in 1usize..4,
        kind in 0usize..4,
        noise in 0.01f64..1.0,
        m in -1.0f64..1.0,
    ) {
        let mut rng = ChaCha8Rng::seed_from_u64(seed);
        let n = n0 + k;
        let (x, y) = random_data(&mut rng, n, d);
        let p = params(KINDS[kind], vec![0.6], rng.random_range(0.5..2.0), noise, m);
        let pushed = pushed_one_by_one(d, &p, &x, &y);
        let mut extended = Gp::new(d, p.clone()).unwrap();
        extended.extend(&x[..n0 * d], &y[..n0]).unwrap();
        extended.extend(&x[n0 * d..], &y[n0..]).unwrap();
        prop_assert_eq!(extended.len(), n);
        for i in 0..n {
            prop_assert_eq!(extended.x(i), &x[i * d..(i + 1) * d]);
            prop_assert_eq!(extended.y(i), y[i]);
        }
        prop_assert!((extended.log_marginal_likelihood() - pushed.log_marginal_likelihood()).abs() < 1e-8);
        let queries: Vec<f64> = (0..5 * d).map(|_| rng.random_range(-1.5..1.5)).collect();
        for q in queries.chunks_exact(d) {
            let naive = naive_predict(&p, d, &x, &y, q);
            assert_close(pred(&extended, q), naive, 1e-8, "extended vs naive");
            assert_close(pred(&extended, q), pred(&pushed, q), 1e-10, "extended vs pushed");
        }
    }

    /// Removing or replacing points and changing targets (one or several at once) equals a
    /// refit of the remaining set.
    #[test]
    fn remove_and_replace_equal_a_refit(
        seed in 0u64..1_000_000,
        n in 2usize..24,
        d in 1usize..4,
        kind in 0usize..4,
        ops in proptest::collection::vec((0usize..4, 0usize..1000), 1..8),
    ) {
        let mut rng = ChaCha8Rng::seed_from_u64(seed);
        let (x, y) = random_data(&mut rng, n, d);
        let p = params(KINDS[kind], vec![0.7], 1.3, 0.1, 0.2);
        let mut gp = Gp::fit(d, p.clone(), &x, &y).unwrap();
        let mut xs: Vec<Vec<f64>> = x.chunks_exact(d).map(|c| c.to_vec()).collect();
        let mut ys = y.clone();
        for (op, r) in ops {
            if xs.is_empty() {
                break;
            }
            let i = r % xs.len();
            match op {
                0 => {
                    gp.remove(i).unwrap();
                    xs.remove(i);
                    ys.remove(i);
                }
                1 => {
                    let nx: Vec<f64> = (0..d).map(|_| rng.random_range(-1.0..1.0)).collect();
                    let ny = rng.random_range(-1.0..1.0);
                    gp.replace(i, &nx, ny).unwrap();
                    xs[i] = nx;
                    ys[i] = ny;
                }
                2 => {
                    let ny = rng.random_range(-1.0..1.0);
                    gp.set_y(i, ny).unwrap();
                    ys[i] = ny;
                }
                _ => {
                    // Several targets at once (indices may repeat: the last one wins).
                    let j = (i * 7 + 3) % xs.len();
                    let (a, b) = (rng.random_range(-1.0..1.0), rng.random_range(-1.0..1.0));
                    gp.set_ys(&[(i, a), (j, b)]).unwrap();
                    ys[i] = a;
                    ys[j] = b;
                }
            }
            prop_assert_eq!(gp.len(), xs.len());
            for (k, xk) in xs.iter().enumerate() {
                prop_assert_eq!(gp.x(k), &xk[..]);
                prop_assert_eq!(gp.y(k), ys[k]);
            }
        }
        let flat: Vec<f64> = xs.concat();
        let refit = Gp::fit(d, p.clone(), &flat, &ys).unwrap();
        prop_assert!((gp.log_marginal_likelihood() - refit.log_marginal_likelihood()).abs() < 1e-8);
        for _ in 0..5 {
            let q: Vec<f64> = (0..d).map(|_| rng.random_range(-1.5..1.5)).collect();
            assert_close(pred(&gp, &q), pred(&refit, &q), 1e-8, "updated vs refit");
        }
    }
}

#[test]
fn empty_gp_predicts_the_prior() {
    let gp = Gp::new(3, params(KernelKind::Matern52, vec![0.4], 2.5, 0.25, 1.0)).unwrap();
    assert!(gp.is_empty());
    let p = gp.predict(&[0.1, 0.2, 0.3]);
    assert_eq!((p.mean, p.latent_variance), (1.0, 2.5));
    let (mut m, mut v) = ([0.0; 2], [0.0; 2]);
    gp.predict_batch(&[0.0; 6], &mut m, &mut v).unwrap();
    assert_eq!((m, v), ([1.0; 2], [2.5; 2]));
    assert_eq!(gp.log_marginal_likelihood(), 0.0);
    let fitted = Gp::fit(3, gp.params().clone(), &[], &[]).unwrap();
    assert_eq!(fitted.predict(&[0.0; 3]).latent_variance, 2.5);
}

#[test]
fn duplicate_inputs_work_with_and_without_noise() {
    let x = [0.1, 0.1, 0.1, 0.5, 0.9];
    let y = [1.0, 1.2, 0.8, 0.0, -1.0];
    // With noise: plain PD; the duplicates average.
    let p = params(KernelKind::SquaredExponential, vec![0.3], 1.0, 0.25, 0.0);
    let gp = Gp::fit(1, p.clone(), &x, &y).unwrap();
    assert_eq!(gp.jitter(), 0.0);
    assert_close(
        pred(&gp, &[0.1]),
        naive_predict(&p, 1, &x, &y, &[0.1]),
        1e-10,
        "dup",
    );
    // Without noise: the jitter ladder makes it PD, predictions stay finite and close to the mean
    // of the duplicates.
    let p0 = params(KernelKind::SquaredExponential, vec![0.3], 1.0, 0.0, 0.0);
    let gp0 = Gp::fit(1, p0.clone(), &x, &y).unwrap();
    assert!(gp0.jitter() > 0.0 && gp0.jitter() <= 1e-4);
    let pr = gp0.predict(&[0.1]);
    assert!(
        pr.mean.is_finite() && (pr.mean - 1.0).abs() < 1e-3,
        "{pr:?}"
    );
    assert!(pr.latent_variance >= 0.0 && pr.latent_variance < 1e-3);
    // Pushing a duplicate one by one escalates the jitter as well.
    let mut gp1 = Gp::new(1, p0).unwrap();
    for (xi, yi) in x.iter().zip(&y) {
        gp1.push(&[*xi], *yi).unwrap();
    }
    assert!(gp1.jitter() > 0.0);
    assert!((gp1.predict(&[0.1]).mean - 1.0).abs() < 1e-3);
}

#[test]
fn extend_escalates_the_jitter_on_duplicates_and_rejects_bad_input_atomically() {
    let x = [0.1, 0.5, 0.1, 0.1, 0.9];
    let y = [1.0, 0.0, 1.2, 0.8, -1.0];
    let p0 = params(KernelKind::SquaredExponential, vec![0.3], 1.0, 0.0, 0.0);
    // Noise-free duplicates: the block stops at the third point and the rest is pushed with
    // the jitter ladder, as pushing one by one does.
    let mut ext = Gp::new(1, p0.clone()).unwrap();
    ext.extend(&x, &y).unwrap();
    let mut pushed = Gp::new(1, p0).unwrap();
    for (xi, yi) in x.iter().zip(&y) {
        pushed.push(&[*xi], *yi).unwrap();
    }
    assert_eq!(ext.len(), 5);
    assert_eq!(ext.jitter(), pushed.jitter());
    assert!(ext.jitter() > 0.0);
    for q in [0.1, 0.3, 0.9] {
        assert_close(pred(&ext, &[q]), pred(&pushed, &[q]), 1e-8, "duplicates");
    }
    // A non-finite value or a length mismatch changes nothing.
    let before = pred(&ext, &[0.3]);
    assert!(matches!(
        ext.extend(&[0.2, f64::NAN], &[1.0, 2.0]),
        Err(GpError::NonFinite { .. })
    ));
    assert!(ext.extend(&[0.2, 0.3], &[1.0]).is_err());
    assert_eq!(ext.len(), 5);
    assert_eq!(pred(&ext, &[0.3]), before);
}

#[test]
fn non_finite_values_are_rejected_and_not_stored() {
    let p = GpParams::default();
    let mut gp = Gp::fit(2, p.clone(), &[0.0, 0.0, 1.0, 1.0], &[1.0, 2.0]).unwrap();
    let before = pred(&gp, &[0.5, 0.5]);
    for bad in [f64::NAN, f64::INFINITY, f64::NEG_INFINITY] {
        assert!(matches!(
            gp.push(&[bad, 0.0], 1.0),
            Err(GpError::NonFinite { .. })
        ));
        assert!(matches!(
            gp.push(&[0.3, 0.0], bad),
            Err(GpError::NonFinite { .. })
        ));
        assert!(gp.replace(0, &[0.0, bad], 1.0).is_err());
        assert!(gp.replace(1, &[0.2, 0.2], bad).is_err());
        assert!(gp.set_y(0, bad).is_err());
        assert!(Gp::fit(2, p.clone(), &[0.0, bad], &[1.0]).is_err());
        assert!(Gp::fit(2, p.clone(), &[0.0, 0.0], &[bad]).is_err());
        let (mut m, mut v) = ([0.0], [0.0]);
        assert!(gp.predict_batch(&[bad, 0.0], &mut m, &mut v).is_err());
    }
    assert_eq!(gp.len(), 2);
    assert_eq!((gp.x(0), gp.y(0)), (&[0.0, 0.0][..], 1.0));
    assert_eq!(pred(&gp, &[0.5, 0.5]), before);
    assert!(matches!(
        gp.push(&[0.0], 1.0),
        Err(GpError::BadDimension(_))
    ));
    assert!(matches!(
        gp.remove(2),
        Err(GpError::IndexOutOfRange { index: 2, len: 2 })
    ));
    assert!(matches!(
        gp.set_y(5, 1.0),
        Err(GpError::IndexOutOfRange { .. })
    ));
    let mut bad = p.clone();
    bad.kernel.lengthscales = vec![0.0];
    assert!(matches!(
        Gp::new(2, bad.clone()),
        Err(GpError::BadHyperparameter(_))
    ));
    bad.kernel.lengthscales = vec![1.0, 1.0, 1.0];
    assert!(matches!(
        Gp::new(2, bad),
        Err(GpError::BadHyperparameter(_))
    ));
    let mut bad = p.clone();
    bad.noise_variance = -1.0;
    assert!(Gp::new(2, bad).is_err());
    assert!(matches!(Gp::new(0, p), Err(GpError::BadDimension(_))));
}

#[test]
fn ard_with_equal_lengthscales_is_isotropic_and_a_long_one_ignores_its_dimension() {
    let mut rng = ChaCha8Rng::seed_from_u64(7);
    let (x, y) = random_data(&mut rng, 20, 2);
    for kind in KINDS {
        let iso = Gp::fit(2, params(kind, vec![0.5], 1.0, 0.1, 0.0), &x, &y).unwrap();
        let ard = Gp::fit(2, params(kind, vec![0.5, 0.5], 1.0, 0.1, 0.0), &x, &y).unwrap();
        for q in [[0.1, 0.2], [-0.7, 0.9]] {
            assert_close(pred(&iso, &q), pred(&ard, &q), 1e-12, "iso vs ard");
        }
        // Lengthscale 1e9 on dimension 1: the model depends on dimension 0 only.
        let long = params(kind, vec![0.5, 1e9], 1.0, 0.1, 0.0);
        let gp = Gp::fit(2, long.clone(), &x, &y).unwrap();
        let x0: Vec<f64> = x.chunks_exact(2).map(|c| c[0]).collect();
        let oned = Gp::fit(1, params(kind, vec![0.5], 1.0, 0.1, 0.0), &x0, &y).unwrap();
        assert_close(pred(&gp, &[0.3, 5.0]), pred(&oned, &[0.3]), 1e-6, "long ls");
        assert_eq!(
            long.kernel.eval(&[0.0, 0.0], &[1.0, 0.0]),
            params(kind, vec![0.5], 1.0, 0.1, 0.0)
                .kernel
                .eval(&[0.0], &[1.0])
        );
    }
}

#[test]
fn kernels_at_zero_and_at_a_hand_computed_distance() {
    // ARD l = (1, 2), σ_s² = 2, a − b = (0.6, 0.8): r² = 0.36 + 0.16 = 0.52, r = 0.7211102550927979.
    // python: 2*exp(-0.26) = 1.5421031716071325, 2*exp(-r) = 0.9724242733588688,
    //         2*(1+√3 r) exp(-√3 r) = 1.2899882062090395,
    //         2*(1+√5 r+5r²/3) exp(-√5 r) = 1.3874596795963383.
    let r = 0.52f64.sqrt();
    let want = [
        2.0 * (-0.26f64).exp(),
        2.0 * (-r).exp(),
        2.0 * (1.0 + 3f64.sqrt() * r) * (-(3f64.sqrt()) * r).exp(),
        2.0 * (1.0 + 5f64.sqrt() * r + 5.0 * 0.52 / 3.0) * (-(5f64.sqrt()) * r).exp(),
    ];
    let numbers = [
        1.5421031716071325,
        0.9724242733588688,
        1.2899882062090395,
        1.3874596795963383,
    ];
    for ((kind, w), num) in KINDS.into_iter().zip(want).zip(numbers) {
        let k = params(kind, vec![1.0, 2.0], 2.0, 0.0, 0.0).kernel;
        assert_eq!(k.eval(&[0.3, -0.2], &[0.3, -0.2]), 2.0);
        assert!((k.eval(&[0.0, 0.0], &[0.6, 0.8]) - w).abs() < 1e-14);
        assert!((w - num).abs() < 1e-14, "{kind:?}: {w}");
    }
}

#[test]
fn lml_gradient_matches_finite_differences() {
    let mut rng = ChaCha8Rng::seed_from_u64(3);
    let d = 2;
    let (x, y) = random_data(&mut rng, 25, d);
    for kind in KINDS {
        for ls in [vec![0.6], vec![0.5, 0.9]] {
            let p = params(kind, ls.clone(), 1.4, 0.2, 0.3);
            let (lml, g) = log_marginal_likelihood_gradient(d, &p, &x, &y).unwrap();
            let gp = Gp::fit(d, p.clone(), &x, &y).unwrap();
            assert!((lml - gp.log_marginal_likelihood()).abs() < 1e-12);
            let nl = ls.len();
            let h = 1e-5;
            for (k, gk) in g.iter().enumerate() {
                let at = |delta: f64| {
                    let mut q = p.clone();
                    if k < nl {
                        q.kernel.lengthscales[k] *= delta.exp();
                    } else if k == nl {
                        q.kernel.signal_variance *= delta.exp();
                    } else {
                        q.noise_variance *= delta.exp();
                    }
                    Gp::fit(d, q, &x, &y).unwrap().log_marginal_likelihood()
                };
                let fd = (at(h) - at(-h)) / (2.0 * h);
                assert!(
                    (fd - gk).abs() < 1e-6 * (1.0 + fd.abs()),
                    "{kind:?} {ls:?} param {k}: analytic {gk} vs fd {fd}"
                );
            }
        }
    }
}

#[test]
fn hyperparameter_fit_recovers_a_lengthscale_and_respects_bounds() {
    // A sample of a 1-D SE GP with l = 0.3, σ_s² = 1, plus noise 0.01.
    let n = 120;
    let mut rng = ChaCha8Rng::seed_from_u64(11);
    let x: Vec<f64> = (0..n).map(|_| rng.random_range(0.0..4.0)).collect();
    let truth = params(KernelKind::SquaredExponential, vec![0.3], 1.0, 1e-8, 0.0);
    let k = faer::Mat::<f64>::from_fn(n, n, |i, j| {
        truth.kernel.eval(&[x[i]], &[x[j]]) + if i == j { 1e-8 } else { 0.0 }
    });
    let l = k.llt(faer::Side::Lower).unwrap();
    let z: Vec<f64> = (0..n)
        .map(|_| {
            // Box–Muller
            let (u1, u2): (f64, f64) = (rng.random_range(1e-12..1.0), rng.random_range(0.0..1.0));
            (-2.0 * u1.ln()).sqrt() * (2.0 * std::f64::consts::PI * u2).cos()
        })
        .collect();
    let lm = l.L();
    let y: Vec<f64> = (0..n)
        .map(|i| (0..=i).map(|j| lm[(i, j)] * z[j]).sum::<f64>() + 0.1 * z[(i * 7 + 3) % n])
        .collect();
    let init = params(KernelKind::SquaredExponential, vec![1.0], 0.5, 0.1, 0.0);
    let fitted = fit_hyperparameters(1, &x, &y, init.clone(), &HyperBounds::default()).unwrap();
    let lf = fitted.kernel.lengthscales[0];
    assert!((0.2..0.45).contains(&lf), "fitted lengthscale {lf}");
    let before = Gp::fit(1, init.clone(), &x, &y)
        .unwrap()
        .log_marginal_likelihood();
    let after = Gp::fit(1, fitted.clone(), &x, &y)
        .unwrap()
        .log_marginal_likelihood();
    assert!(after > before);
    // Tight bounds are respected.
    let bounds = HyperBounds {
        lengthscale: (0.6, 2.0),
        signal_variance: (0.5, 0.8),
        noise_variance: (0.05, 0.05),
        max_iterations: 100,
    };
    let b = fit_hyperparameters(1, &x, &y, init, &bounds).unwrap();
    let lb = b.kernel.lengthscales[0];
    assert!((0.6..=2.0).contains(&lb) && (lb - 0.6).abs() < 1e-9, "{lb}");
    assert!((0.5..=0.8).contains(&b.kernel.signal_variance));
    assert!((b.noise_variance - 0.05).abs() < 1e-15);
}

#[test]
fn push_built_equals_refit_at_two_thousand_points() {
    // The benchmark's setting: n = 2000 in d = 9, the last 50 points pushed.
    let (n, d) = (2000, 9);
    let mut rng = ChaCha8Rng::seed_from_u64(5);
    let x: Vec<f64> = (0..n * d).map(|_| rng.random_range(0.0..1.0)).collect();
    let y: Vec<f64> = (0..n)
        .map(|i| x[i * d] + rng.random_range(-0.5..0.5))
        .collect();
    let p = GpParams::default();
    let m = n - 50;
    let mut gp = Gp::fit(d, p.clone(), &x[..m * d], &y[..m]).unwrap();
    for i in m..n {
        gp.push(&x[i * d..(i + 1) * d], y[i]).unwrap();
    }
    let refit = Gp::fit(d, p, &x, &y).unwrap();
    for j in 0..20 {
        let q: Vec<f64> = (0..d).map(|_| rng.random_range(0.0..1.0)).collect();
        let _ = j;
        assert_close(pred(&gp, &q), pred(&refit, &q), 1e-8, "push vs refit");
    }
}
