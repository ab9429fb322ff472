//! The IGMN regressor (Prágr18 parameters): statistics of a single component, the component
//! cap, pruning, finite predictions on degenerate data, determinism.

use proptest::prelude::*;
use rand::rngs::ChaCha8Rng;
use rand::{RngExt, SeedableRng};
use strider_learn::igmn::{Igmn, IgmnError, IgmnParams};

/// A standard normal draw (Box–Muller).
fn normal(rng: &mut ChaCha8Rng) -> f64 {
    let u: f64 = rng.random_range(f64::EPSILON..1.0);
    let v: f64 = rng.random_range(0.0..1.0);
    (-2.0 * u.ln()).sqrt() * (std::f64::consts::TAU * v).cos()
}

#[test]
fn a_single_gaussian_recovers_mean_and_covariance() {
    // y = 2 x + noise with x ~ N(1, 0.5²): joint mean (1, 2), covariance
    // [[0.25, 0.5], [0.5, 1 + 0.01]]. A huge δ keeps everything in one component; its initial
    // covariance then weighs 1/n in the running estimate, so δ is kept moderate (4 σ) and the
    // stream long.
    let mut rng = ChaCha8Rng::seed_from_u64(7);
    let params = IgmnParams {
        delta: 4.0,
        max_components: 1,
        ..IgmnParams::default()
    };
    let mut g = Igmn::new(1, params, &[0.5, 1.0]).unwrap();
    let n = 20_000;
    let (mut xs, mut ys) = (Vec::new(), Vec::new());
    for _ in 0..n {
        let x = 1.0 + 0.5 * normal(&mut rng);
        let y = 2.0 * x + 0.1 * normal(&mut rng);
        g.learn(&[x], y).unwrap();
        xs.push(x);
        ys.push(y);
    }
    assert_eq!(g.components(), 1);
    let mx = xs.iter().sum::<f64>() / n as f64;
    let my = ys.iter().sum::<f64>() / n as f64;
    let m = g.component_mean(0);
    assert!(
        (m[0] - mx).abs() < 1e-9 && (m[1] - my).abs() < 1e-9,
        "{m:?}"
    );
    let c = g.component_covariance(0);
    for (got, want) in c.iter().zip([0.25, 0.5, 0.5, 1.01]) {
        assert!((got - want).abs() < 0.03, "{c:?}");
    }
    // The recall is the regression line.
    for x in [0.0, 1.0, 2.0] {
        let p = g.predict(&[x]).unwrap();
        assert!((p - 2.0 * x).abs() < 0.05, "{x}: {p}");
    }
}

#[test]
fn two_separate_clusters_get_two_components_and_the_right_recall() {
    let mut rng = ChaCha8Rng::seed_from_u64(3);
    let mut g = Igmn::new(2, IgmnParams::default(), &[0.1, 0.1, 1.0]).unwrap();
    for i in 0..400 {
        let c = (i % 2) as f64;
        let x = [
            c + rng.random_range(-0.02..0.02),
            rng.random_range(-0.02..0.02),
        ];
        let y = 10.0 * c + rng.random_range(-0.1..0.1);
        g.learn(&x, y).unwrap();
    }
    assert!(g.components() >= 2 && g.components() <= 10);
    assert!((g.predict(&[0.0, 0.0]).unwrap()).abs() < 0.5);
    assert!((g.predict(&[1.0, 0.0]).unwrap() - 10.0).abs() < 0.5);
}

#[test]
fn pruning_removes_stale_components_after_the_grace_period() {
    // One outlier creates a component that never gains support: after v_min = 100 more points
    // with sp < 3 it is removed.
    let mut g = Igmn::new(1, IgmnParams::default(), &[0.01, 0.01]).unwrap();
    g.learn(&[5.0], 5.0).unwrap();
    let mut rng = ChaCha8Rng::seed_from_u64(1);
    for _ in 0..150 {
        g.learn(&[rng.random_range(0.0..0.01)], 0.0).unwrap();
    }
    let (created, pruned) = g.created_pruned();
    assert!(created >= 2 && pruned >= 1, "{created} {pruned}");
    assert!(g.predict(&[0.005]).unwrap().abs() < 0.1);
}

#[test]
fn degenerate_and_bad_input() {
    // Constant descriptors (decision 7: flat λ3 = 0 gives (0, 0, 1); missing colour gives a
    // constant) and constant costs: finite predictions, no panic.
    let mut g = Igmn::new(3, IgmnParams::default(), &[0.0, 0.0, 0.0, 0.0]).unwrap();
    for _ in 0..50 {
        g.learn(&[0.0, 0.0, 1.0], 0.005).unwrap();
    }
    let p = g.predict(&[0.0, 0.0, 1.0]).unwrap();
    assert!((p - 0.005).abs() < 1e-9, "{p}");
    assert!(g.predict(&[1e6, -1e6, 3.0]).unwrap().is_finite());
    assert!(g.predict(&[f64::NAN, 0.0, 0.0]).unwrap().is_finite());
    // Non-finite pairs and wrong dimensions are refused and change nothing.
    let before = g.len();
    assert!(matches!(
        g.learn(&[f64::NAN, 0.0, 1.0], 1.0),
        Err(IgmnError::NonFinite(_))
    ));
    assert!(matches!(
        g.learn(&[0.0, 0.0, 1.0], f64::INFINITY),
        Err(IgmnError::NonFinite(_))
    ));
    assert!(matches!(
        g.learn(&[0.0], 1.0),
        Err(IgmnError::BadDimension { .. })
    ));
    assert_eq!(g.len(), before);
    // Empty network: no prediction; bad parameters: errors.
    let e = Igmn::new(2, IgmnParams::default(), &[1.0; 3]).unwrap();
    assert_eq!(e.predict(&[0.0, 0.0]), None);
    assert!(Igmn::new(0, IgmnParams::default(), &[1.0]).is_err());
    assert!(
        Igmn::new(
            1,
            IgmnParams {
                max_components: 0,
                ..IgmnParams::default()
            },
            &[1.0; 2]
        )
        .is_err()
    );
    assert!(
        Igmn::new(
            1,
            IgmnParams {
                beta: 1.0,
                ..IgmnParams::default()
            },
            &[1.0; 2]
        )
        .is_err()
    );
    assert!(Igmn::new(1, IgmnParams::default(), &[1.0]).is_err());
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(32))]

    /// Predictions stay finite and the component cap holds for arbitrary streams; the same
    /// stream gives the same model.
    #[test]
    fn finite_capped_and_deterministic(
        pts in prop::collection::vec((-5.0f64..5.0, -5.0f64..5.0, -100.0f64..100.0), 1..120),
        cap in 1usize..6,
    ) {
        let params = IgmnParams { max_components: cap, v_min: 20, ..IgmnParams::default() };
        let mut a = Igmn::new(2, params.clone(), &[1.0, 1.0, 10.0]).unwrap();
        let mut b = Igmn::new(2, params, &[1.0, 1.0, 10.0]).unwrap();
        for &(x0, x1, y) in &pts {
            a.learn(&[x0, x1], y).unwrap();
            b.learn(&[x0, x1], y).unwrap();
            prop_assert!(a.components() <= cap);
        }
        for &(x0, x1, _) in &pts {
            let p = a.predict(&[x0, x1]).unwrap();
            prop_assert!(p.is_finite());
            prop_assert_eq!(p.to_bits(), b.predict(&[x0, x1]).unwrap().to_bits());
        }
    }
}
