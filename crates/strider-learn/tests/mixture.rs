//! The Nardi19 GP mixture against the plain GP and against what it is for: a one-component
//! mixture is exactly the single GP; Eq. 4's noise multipliers behave like removing a point in
//! the limit; the aerial gating predicts unvisited terrain from its colour; bad input is an
//! error, never a panic or a NaN.

use proptest::prelude::*;
use strider_learn::gp::{Gp, GpParams, Kernel, KernelKind};
use strider_learn::mixture::{
    FieldPrediction, MixtureError, MixtureModel, MixtureParams, TrainingSet,
};

fn se(l: f64, s2: f64, n2: f64, m: f64) -> GpParams {
    GpParams {
        kernel: Kernel {
            kind: KernelKind::SquaredExponential,
            lengthscales: vec![l],
            signal_variance: s2,
        },
        noise_variance: n2,
        prior_mean: m,
    }
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 12, .. ProptestConfig::default() })]

    /// A mixture limited to one component is the single GP of Nardi19 §III: same fitted
    /// hyperparameters, prior mean the mean of y, Ψ = I, and Eq. 3 reduces to Eq. 2.
    #[test]
    fn one_component_mixture_equals_the_single_gp(
        pts in prop::collection::vec((0.0f64..20.0, 0.0f64..10.0, 0.0f64..5.0), 4..40),
        queries in prop::collection::vec((-5.0f64..25.0, -5.0f64..15.0), 1..20),
    ) {
        let pos: Vec<f64> = pts.iter().flat_map(|p| [p.0, p.1]).collect();
        let y: Vec<f64> = pts.iter().map(|p| p.2).collect();
        let train = TrainingSet { positions: &pos, y: &y, gate_features: &pos, gate_dim: 2 };
        let params = MixtureParams { max_components: 1, ..MixtureParams::default() };
        let model = MixtureModel::fit(&train, &params, None).unwrap();
        prop_assert_eq!(model.components().len(), 1);
        prop_assert!(model.gates().is_empty());
        let fitted = model.components()[0].gp.params().clone();
        let mean_y = y.iter().sum::<f64>() / y.len() as f64;
        prop_assert!((fitted.prior_mean - mean_y).abs() < 1e-12);
        let single = Gp::fit(2, fitted, &pos, &y).unwrap();
        let q: Vec<f64> = queries.iter().flat_map(|p| [p.0, p.1]).collect();
        let mut out = FieldPrediction::default();
        model.predict(&q, &q, &mut out).unwrap();
        for (k, qp) in q.chunks_exact(2).enumerate() {
            let p = single.predict(qp);
            prop_assert!((out.mean[k] - p.mean).abs() <= 1e-9 * (1.0 + p.mean.abs()));
            prop_assert!(
                (out.variance[k] - p.latent_variance).abs()
                    <= 1e-9 * (1.0 + p.latent_variance)
            );
            prop_assert_eq!(out.gates[k], 1.0);
        }
    }
}

#[test]
fn unit_noise_multipliers_are_the_homoscedastic_gp() {
    let x: Vec<f64> = (0..30).map(|i| (i as f64 * 0.7).sin() * 3.0).collect();
    let y: Vec<f64> = x.iter().map(|v| v.cos()).collect();
    let p = se(0.8, 1.3, 0.05, 0.2);
    let a = Gp::fit(1, p.clone(), &x, &y).unwrap();
    let b = Gp::fit_heteroscedastic(1, p, &x, &y, &[1.0; 30]).unwrap();
    for t in [-4.0, -1.1, 0.0, 0.3, 2.9] {
        assert_eq!(a.predict(&[t]), b.predict(&[t]));
    }
    assert_eq!(b.noise_scale(3), 1.0);
}

#[test]
fn a_huge_noise_multiplier_removes_the_point() {
    // Eq. 4 with φ → 0: the point's noise grows without bound and it stops mattering.
    let x = [0.0, 1.0, 2.0, 3.0];
    let y = [0.0, 5.0, 1.0, 2.0];
    let p = se(1.0, 2.0, 0.1, 0.0);
    let w = Gp::fit_heteroscedastic(1, p.clone(), &x, &y, &[1.0, 1e12, 1.0, 1.0]).unwrap();
    let without = Gp::fit(1, p.clone(), &[0.0, 2.0, 3.0], &[0.0, 1.0, 2.0]).unwrap();
    let with = Gp::fit(1, p, &x, &y).unwrap();
    let (a, b, c) = (
        w.predict(&[1.0]),
        without.predict(&[1.0]),
        with.predict(&[1.0]),
    );
    assert!((a.mean - b.mean).abs() < 1e-9, "{a:?} vs {b:?}");
    assert!((a.latent_variance - b.latent_variance).abs() < 1e-9);
    // The point does matter when its multiplier is 1.
    assert!((c.mean - b.mean).abs() > 1.0);
    // Removal and insertion keep the other points' multipliers.
    let mut w2 = w.clone();
    w2.remove(0).unwrap();
    assert_eq!(w2.noise_scale(0), 1e12);
    w2.push(&[4.0], 1.0).unwrap();
    assert_eq!(w2.noise_scale(3), 1.0);
}

#[test]
fn noise_multipliers_are_validated() {
    let p = se(1.0, 1.0, 0.1, 0.0);
    assert!(Gp::fit_heteroscedastic(1, p.clone(), &[0.0, 1.0], &[0.0, 1.0], &[1.0]).is_err());
    assert!(Gp::fit_heteroscedastic(1, p.clone(), &[0.0, 1.0], &[0.0, 1.0], &[1.0, 0.0]).is_err());
    assert!(Gp::fit_heteroscedastic(1, p, &[0.0, 1.0], &[0.0, 1.0], &[f64::NAN, 1.0]).is_err());
}

#[test]
fn mean_only_prediction_equals_the_full_prediction() {
    let x: Vec<f64> = (0..50)
        .flat_map(|i| [(i as f64 * 0.37).sin() * 4.0, (i as f64 * 0.11).cos()])
        .collect();
    let y: Vec<f64> = (0..50).map(|i| (i as f64 * 0.5).sin()).collect();
    let mut p = se(0.9, 1.0, 0.05, 0.3);
    p.kernel.lengthscales = vec![0.9, 2.0];
    let gp = Gp::fit(2, p, &x, &y).unwrap();
    let q: Vec<f64> = (0..300).map(|k| (k as f64 * 0.013).sin() * 5.0).collect();
    let (mut m1, mut v1, mut m2) = (vec![0.0; 150], vec![0.0; 150], vec![0.0; 150]);
    gp.predict_batch(&q, &mut m1, &mut v1).unwrap();
    gp.predict_mean_batch(&q, &mut m2).unwrap();
    for (a, b) in m1.iter().zip(&m2) {
        assert!((a - b).abs() < 1e-9, "{a} vs {b}");
    }
    assert!(gp.predict_mean_batch(&q[..3], &mut m2).is_err());
    let mut bad = q.clone();
    bad[7] = f64::NAN;
    assert!(gp.predict_mean_batch(&bad, &mut m2).is_err());
}

/// A 40 × 10 strip of cells whose left and right thirds are "paved" (0.5) and "gravel" (4.0)
/// with a pale and a dark colour; the middle third, never visited, is paved in its upper half
/// and gravel in its lower half. Returns positions, values, colours for every cell.
fn strip() -> (Vec<f64>, Vec<f64>, Vec<f64>, Vec<bool>) {
    let (mut pos, mut y, mut col, mut visited) = (vec![], vec![], vec![], vec![]);
    for j in 0..10 {
        for i in 0..40 {
            let middle = (13..27).contains(&i);
            let paved = if middle { j >= 5 } else { (i + j) % 2 == 0 };
            let noise = ((i * 7 + j * 13) % 11) as f64 * 0.002;
            pos.extend([i as f64, j as f64]);
            y.push(if paved { 0.5 } else { 4.0 } + noise);
            col.push(if paved { 0.9 } else { 0.1 } + noise);
            visited.push(!middle);
        }
    }
    (pos, y, col, visited)
}

#[test]
fn aerial_gating_predicts_unvisited_terrain_by_colour() {
    let (pos, y, col, visited) = strip();
    let n = y.len();
    let pick = |k: usize| visited[k];
    let tr_pos: Vec<f64> = (0..n)
        .filter(|&k| pick(k))
        .flat_map(|k| [pos[2 * k], pos[2 * k + 1]])
        .collect();
    let tr_y: Vec<f64> = (0..n).filter(|&k| pick(k)).map(|k| y[k]).collect();
    // Gating features: standardised-ish position (and colour for the aerial model).
    let feat = |k: usize, aerial: bool| -> Vec<f64> {
        let mut f = vec![pos[2 * k] / 12.0, pos[2 * k + 1] / 3.0];
        if aerial {
            f.push(col[k] / 0.4);
        }
        f
    };
    let rmse_middle = |aerial: bool| -> (f64, usize) {
        let dim = if aerial { 3 } else { 2 };
        let g_tr: Vec<f64> = (0..n)
            .filter(|&k| pick(k))
            .flat_map(|k| feat(k, aerial))
            .collect();
        let g_all: Vec<f64> = (0..n).flat_map(|k| feat(k, aerial)).collect();
        let train = TrainingSet {
            positions: &tr_pos,
            y: &tr_y,
            gate_features: &g_tr,
            gate_dim: dim,
        };
        let model = MixtureModel::fit(&train, &MixtureParams::default(), None).unwrap();
        let mut out = FieldPrediction::default();
        model.predict(&pos, &g_all, &mut out).unwrap();
        assert!(out.mean.iter().chain(&out.variance).all(|v| v.is_finite()));
        let mid: Vec<usize> = (0..n).filter(|&k| !visited[k]).collect();
        let se: f64 = mid.iter().map(|&k| (out.mean[k] - y[k]).powi(2)).sum();
        ((se / mid.len() as f64).sqrt(), model.components().len())
    };
    let (plain, m_plain) = rmse_middle(false);
    let (aerial, m_aerial) = rmse_middle(true);
    assert_eq!((m_plain, m_aerial), (2, 2));
    // Without colour the middle is a guess (about half the gap of 3.5); with it, near exact.
    assert!(plain > 1.0, "position-only RMSE {plain}");
    assert!(
        aerial < 0.25 * plain,
        "aerial {aerial} vs position-only {plain}"
    );
}

#[test]
fn bad_training_sets_are_errors() {
    let p = MixtureParams::default();
    let empty = TrainingSet {
        positions: &[],
        y: &[],
        gate_features: &[],
        gate_dim: 2,
    };
    assert_eq!(
        MixtureModel::fit(&empty, &p, None).unwrap_err(),
        MixtureError::Empty
    );
    let pos = [0.0, 0.0, 1.0, 1.0];
    let short = TrainingSet {
        positions: &pos[..3],
        y: &[1.0, 2.0],
        gate_features: &pos,
        gate_dim: 2,
    };
    assert!(matches!(
        MixtureModel::fit(&short, &p, None),
        Err(MixtureError::BadDimension(_))
    ));
    let nan = TrainingSet {
        positions: &pos,
        y: &[1.0, f64::NAN],
        gate_features: &pos,
        gate_dim: 2,
    };
    assert!(matches!(
        MixtureModel::fit(&nan, &p, None),
        Err(MixtureError::NonFinite(_))
    ));
    let ok = TrainingSet {
        positions: &pos,
        y: &[1.0, 2.0],
        gate_features: &pos,
        gate_dim: 2,
    };
    let bad = MixtureParams {
        max_components: 0,
        ..p.clone()
    };
    assert!(matches!(
        MixtureModel::fit(&ok, &bad, None),
        Err(MixtureError::BadParameter(_))
    ));
    let bad = MixtureParams {
        bandwidth: Some(-1.0),
        ..p.clone()
    };
    assert!(MixtureModel::fit(&ok, &bad, None).is_err());
    // Prediction inputs of the wrong shape or not finite.
    let model = MixtureModel::fit(&ok, &p, None).unwrap();
    let mut out = FieldPrediction::default();
    assert!(
        model
            .predict(&[0.0, 0.0, 1.0], &[0.0; 3], &mut out)
            .is_err()
    );
    assert!(
        model
            .predict(&[0.0, f64::NAN], &[0.0; 2], &mut out)
            .is_err()
    );
    let pr = model.predict_one([0.5, 0.5], &[0.5, 0.5]).unwrap();
    assert!(pr.mean.is_finite() && pr.latent_variance >= 0.0);
}
