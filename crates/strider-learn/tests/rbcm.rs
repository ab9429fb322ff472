//! The committee against a single GP.

use rand::rngs::ChaCha8Rng;
use rand::{RngExt, SeedableRng};
use strider_learn::gp::{Gp, GpParams};
use strider_learn::rbcm::{Rbcm, RbcmParams, RbcmVariant};

fn data(n: usize, seed: u64) -> (Vec<f64>, Vec<f64>) {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let x: Vec<f64> = (0..2 * n).map(|_| rng.random_range(0.0..1.0)).collect();
    let y = (0..n)
        .map(|i| (4.0 * x[2 * i]).sin() + x[2 * i + 1] + rng.random_range(-0.2..0.2))
        .collect();
    (x, y)
}

/// A committee over every point of (`x`, `y`), pushed in order.
fn committee(p: GpParams, rbcm: RbcmParams, x: &[f64], y: &[f64]) -> Rbcm {
    let mut r = Rbcm::new(2, p, rbcm).unwrap();
    for (xi, &yi) in x.chunks_exact(2).zip(y) {
        r.push(xi, yi).unwrap();
    }
    r
}

#[test]
fn one_bcm_expert_is_the_gp() {
    let (x, y) = data(40, 1);
    let p = GpParams {
        prior_mean: 0.5,
        ..GpParams::default()
    };
    let gp = Gp::fit(2, p.clone(), &x, &y).unwrap();
    let bcm = RbcmParams {
        m_max: 100,
        m_min: 1,
        variant: RbcmVariant::Bcm,
    };
    let r = committee(p, bcm, &x, &y);
    assert_eq!(r.experts().len(), 1);
    for q in [[0.1, 0.9], [0.5, 0.5], [3.0, -2.0]] {
        let (a, b) = (r.predict(&q), gp.predict(&q));
        assert!(
            (a.mean - b.mean).abs() < 1e-10
                && (a.latent_variance - b.latent_variance).abs() < 1e-10
        );
    }
}

#[test]
fn robust_committee_tracks_the_gp_on_dense_data() {
    let (x, y) = data(300, 2);
    let p = GpParams::default();
    let gp = Gp::fit(2, p.clone(), &x, &y).unwrap();
    let robust = RbcmParams {
        m_max: 50,
        m_min: 25,
        variant: RbcmVariant::Robust,
    };
    let r = committee(p, robust, &x, &y);
    assert_eq!(r.experts().len(), 6);
    assert_eq!(r.len(), 300);
    let mut worst: f64 = 0.0;
    for i in 0..10 {
        let q = [0.05 + 0.09 * i as f64, 0.5];
        let (a, b) = (r.predict(&q), gp.predict(&q));
        worst = worst.max((a.mean - b.mean).abs());
        assert!(a.latent_variance > 0.0 && a.latent_variance < 1.0);
    }
    assert!(worst < 0.15, "worst mean gap {worst}");
}
