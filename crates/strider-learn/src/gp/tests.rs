//! Unit tests of the factor internals and the kernels.

use super::factor::Factor;
use super::*;

#[test]
fn kernel_values_at_zero_and_at_a_hand_computed_r() {
    // l = 2, σ_s² = 3, a − b = (1, 1): r = √2 / 2 = 0.7071067811865476.
    let r = 0.5f64.sqrt();
    let expect = [
        (KernelKind::SquaredExponential, 3.0 * (-0.25f64).exp()),
        (KernelKind::Exponential, 3.0 * (-r).exp()),
        (
            KernelKind::Matern32,
            3.0 * (1.0 + 3f64.sqrt() * r) * (-(3f64.sqrt()) * r).exp(),
        ),
        (
            KernelKind::Matern52,
            3.0 * (1.0 + 5f64.sqrt() * r + 5.0 / 3.0 * 0.5) * (-(5f64.sqrt()) * r).exp(),
        ),
    ];
    // Numbers (python): SE 2.3364023492142145, Exp 1.4792060741857194,
    // M32 1.9611080826363372, M52 2.10748728046141.
    let numbers = [
        2.3364023492142145,
        1.4792060741857194,
        1.9611080826363372,
        2.10748728046141,
    ];
    for ((kind, v), num) in expect.into_iter().zip(numbers) {
        let k = Kernel {
            kind,
            lengthscales: vec![2.0],
            signal_variance: 3.0,
        };
        assert_eq!(k.eval(&[0.5, -1.0], &[0.5, -1.0]), 3.0);
        assert!(
            (k.eval(&[0.0, 0.0], &[1.0, 1.0]) - v).abs() < 1e-14,
            "{kind:?}"
        );
        assert!((v - num).abs() < 1e-12, "{kind:?}: {v}");
        assert_eq!(k.prior_variance(), 3.0);
    }
}

#[test]
fn factor_remove_equals_factor_of_the_reduced_matrix() {
    // A = M Mᵀ + I for a fixed M; remove row/col 2 of 6.
    let n = 6;
    let m: Vec<f64> = (0..n * n)
        .map(|k| ((k * 37 % 11) as f64 - 5.0) / 7.0)
        .collect();
    let a = |i: usize, j: usize| -> f64 {
        (0..n).map(|k| m[i * n + k] * m[j * n + k]).sum::<f64>() + if i == j { 1.0 } else { 0.0 }
    };
    let build = |idx: &[usize]| {
        let mut f = Factor::with_capacity(idx.len());
        f.n = idx.len();
        for (r, &i) in idx.iter().enumerate() {
            for (c, &j) in idx.iter().enumerate().take(r + 1) {
                f.data[c * f.ld + r] = a(i, j);
            }
        }
        assert!(f.factorize(0.0, faer::Par::Seq));
        f
    };
    let mut full = build(&[0, 1, 2, 3, 4, 5]);
    for i in 0..n {
        for j in 0..=i {
            let v: f64 = (0..=j).map(|k| full.at(i, k) * full.at(j, k)).sum();
            assert!(
                (v - a(i, j)).abs() < 1e-12,
                "LLt {i} {j}: {v} vs {}",
                a(i, j)
            );
        }
    }
    full.remove(2);
    let reduced = build(&[0, 1, 3, 4, 5]);
    for i in 0..5 {
        for j in 0..=i {
            assert!((full.at(i, j) - reduced.at(i, j)).abs() < 1e-12, "{i} {j}");
        }
    }
}

#[test]
fn differential_entropy_of_unit_variance() {
    // ½ ln(2πe) = 1.4189385332046727
    assert!((differential_entropy(1.0) - 1.4189385332046727).abs() < 1e-15);
    let p = Prediction {
        mean: 0.0,
        latent_variance: 1.0,
    };
    assert_eq!(p.entropy(), differential_entropy(1.0));
    assert_eq!(p.noisy_variance(0.25), 1.25);
}

/// A fuzzer found a fit on a target of 1.8e308 whose predictions were NaN (inf − inf in the
/// solve); such targets are refused at every entry, and the largest allowed ones predict finitely.
#[test]
fn targets_beyond_the_deviation_limit_are_refused_and_those_within_predict_finitely() {
    let x = [-1.0, 0.0, 1.0, 2.0, 3.0];
    let params = GpParams::default();
    let mut y = [0.3, 1e6, f64::MAX, 1e-3, -25.0];
    let err = Gp::fit(1, params.clone(), &x, &y).unwrap_err();
    assert!(
        matches!(err, GpError::TargetTooLarge { point: 2, .. }),
        "{err}"
    );
    assert!(err.to_string().contains("rescale"), "{err}");
    y[2] = MAX_TARGET_DEVIATION;
    y[4] = -MAX_TARGET_DEVIATION;
    let mut gp = Gp::fit(1, params, &x, &y).unwrap();
    let mut mean = [0.0; 5];
    let mut var = [0.0; 5];
    gp.predict_batch(&x, &mut mean, &mut var).unwrap();
    assert!(
        mean.iter().chain(&var).all(|v| v.is_finite()),
        "{mean:?} {var:?}"
    );
    assert!(matches!(
        gp.push(&[4.0], -f64::MAX),
        Err(GpError::TargetTooLarge { point: 5, .. })
    ));
    assert!(matches!(
        gp.set_y(0, 2e100),
        Err(GpError::TargetTooLarge { point: 0, .. })
    ));
    assert_eq!(gp.len(), 5);
}
