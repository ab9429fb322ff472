//! Tests of the IGNG terrain classes (Prágr22 Alg. 11, decision 17).

use proptest::prelude::*;
use rand::rngs::ChaCha8Rng;
use rand::{RngExt, SeedableRng};
use strider_learn::igng::{AdaptOutcome, ClassId, Igng, IgngError, IgngParams, InsertionRule};

const CENTRES: [[f32; 5]; 3] = [
    [0.0, 0.0, 1.0, 0.0, 0.0],
    [0.0, 0.0, 1.0, 3.0, 0.0],
    [0.5, 0.2, 0.3, 0.0, -3.0],
];

/// `per` points around each centre, uniform in ±`spread` per coordinate, clusters interleaved.
fn clusters(per: usize, spread: f32, seed: u64) -> Vec<f32> {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let mut out = Vec::new();
    for _ in 0..per {
        for c in CENTRES {
            for v in c {
                out.push(v + rng.random_range(-spread..=spread));
            }
        }
    }
    out
}

fn pairwise_min(g: &Igng) -> f64 {
    let protos: Vec<Vec<f64>> = g.prototypes().map(|(_, w)| w.to_vec()).collect();
    let mut best = f64::INFINITY;
    for i in 0..protos.len() {
        for j in i + 1..protos.len() {
            let d = protos[i]
                .iter()
                .zip(&protos[j])
                .map(|(a, b)| (a - b) * (a - b))
                .sum::<f64>()
                .sqrt();
            best = best.min(d);
        }
    }
    best
}

fn small_batches(sigma: f64) -> IgngParams {
    let mut p = IgngParams::with_sigma(sigma);
    p.batch = 500;
    p
}

#[test]
fn defaults_are_table_3() {
    let p = IgngParams::from_lengthscale(0.4);
    assert_eq!(p.sigma, 0.8);
    assert_eq!(p.eps_winner, 1e-3);
    assert_eq!(p.eps_neighbour, 1e-5);
    assert_eq!(p.age_mature, 100);
    assert_eq!(p.age_max, 50);
    assert_eq!(p.batch, 5000);
    assert_eq!(p.insertion, InsertionRule::Separated);
}

#[test]
fn three_separated_clusters_give_three_classes() {
    let data = clusters(400, 0.2, 7);
    let mut g = Igng::new(5, IgngParams::from_lengthscale(0.4), 11).unwrap();
    let rep = g.train(&data, 3).unwrap();
    assert_eq!(rep.rows, 1200);
    assert_eq!(rep.steps, 3600);
    assert_eq!(g.len(), 3);
    // Every point of a cluster gets the same class, and the three classes differ.
    let mut class_of = Vec::new();
    for (k, row) in data.chunks(5).enumerate() {
        let c = g.classify(row).unwrap();
        if k < 3 {
            class_of.push(c);
        } else {
            assert_eq!(c, class_of[k % 3]);
        }
    }
    class_of.sort();
    class_of.dedup();
    assert_eq!(class_of.len(), 3);
    assert!(pairwise_min(&g) >= 0.8);
}

#[test]
fn literal_alg11_splits_each_cluster_into_a_connected_pair() {
    // Alg. 11 verbatim inserts the second sample of a cluster as a second neuron: three tight
    // clusters give six neurons in three connected components.
    let data = clusters(300, 0.05, 3);
    let mut p = IgngParams::from_lengthscale(0.4);
    p.insertion = InsertionRule::Alg11;
    let mut g = Igng::new(5, p, 5).unwrap();
    g.train(&data, 2).unwrap();
    assert_eq!(g.len(), 6);
    let comps = g.components();
    assert_eq!(comps.len(), 3);
    assert!(comps.iter().all(|c| c.len() == 2));
    assert!(pairwise_min(&g) < 0.8);
}

#[test]
fn same_seed_same_structure_different_seed_may_differ() {
    let mut rng = ChaCha8Rng::seed_from_u64(99);
    let data: Vec<f64> = (0..2 * 2000).map(|_| rng.random_range(0.0..10.0)).collect();
    let run = |seed: u64| {
        let mut g = Igng::new(2, small_batches(1.0), seed).unwrap();
        g.train(&data, 4).unwrap();
        let protos: Vec<(ClassId, Vec<f64>)> =
            g.prototypes().map(|(c, w)| (c, w.to_vec())).collect();
        let edges: Vec<_> = g.edges().collect();
        (protos, edges)
    };
    let a = run(1);
    assert_eq!(a, run(1));
    assert!(!a.0.is_empty());
    assert!((2..8).any(|s| run(s).0 != a.0));
}

#[test]
fn pruned_class_is_blacklisted_and_ids_are_stable() {
    let data = clusters(300, 0.2, 1);
    let mut g = Igng::new(5, small_batches(0.8), 2).unwrap();
    g.train(&data, 2).unwrap();
    assert_eq!(g.len(), 3);
    let before: Vec<(ClassId, Vec<f64>)> = g.prototypes().map(|(c, w)| (c, w.to_vec())).collect();
    let victim = g.classify(&CENTRES[1]).unwrap();
    let victim_proto = g.prototype(victim).unwrap().to_vec();
    g.prune(victim).unwrap();
    assert_eq!(g.prune(victim), Err(IgngError::UnknownClass(victim)));
    assert_eq!(g.blacklist().count(), 1);
    assert_eq!(g.len(), 2);

    let rep = g.train(&data, 3).unwrap();
    assert_eq!(rep.created, 0);
    assert!(rep.blacklisted > 0);
    assert_eq!(g.len(), 2);
    // No class within σ of the pruned prototype; the survivors kept their ids.
    for (c, w) in g.prototypes() {
        let d = w
            .iter()
            .zip(&victim_proto)
            .map(|(a, b)| (a - b) * (a - b))
            .sum::<f64>()
            .sqrt();
        assert!(d > 0.8, "{c} re-created near the pruned class");
        assert!(before.iter().any(|(b, _)| *b == c));
    }
    // Cells of the pruned terrain fall to the nearest surviving class (Alg. 7 line 8).
    let c = g.classify(&CENTRES[1]).unwrap();
    assert_ne!(c, victim);
    // A new terrain elsewhere gets a fresh id.
    let out = g.adapt(&[9.0f32, 9.0, 9.0, 9.0, 9.0]).unwrap();
    assert_eq!(out, AdaptOutcome::Created(ClassId(3)));
}

#[test]
fn non_finite_inputs_are_rejected_and_counted() {
    let mut data = clusters(100, 0.2, 4);
    for r in [3usize, 50, 77, 120] {
        data[r * 5 + 2] = f32::NAN;
    }
    data[200 * 5] = f32::INFINITY;
    let mut g = Igng::new(5, small_batches(0.8), 0).unwrap();
    let rep = g.train(&data, 2).unwrap();
    assert_eq!(rep.rejected_rows, 5);
    assert_eq!(g.rejected(), 5);
    assert_eq!(rep.steps, 2 * 295);
    assert!(g.prototypes().all(|(_, w)| w.iter().all(|v| v.is_finite())));
    assert_eq!(
        g.adapt(&[f64::NAN, 0.0, 0.0, 0.0, 0.0]),
        Err(IgngError::NonFinite)
    );
    assert_eq!(g.rejected(), 6);
    assert_eq!(g.classify(&[f64::NAN, 0.0, 0.0, 0.0, 0.0]), None);
    // All-invalid input trains nothing.
    let rep = g.train(&[f32::NAN; 10], 3).unwrap();
    assert_eq!((rep.rejected_rows, rep.steps), (2, 0));
}

#[test]
fn bad_shapes_and_parameters_are_errors() {
    assert_eq!(
        Igng::new(0, IgngParams::with_sigma(1.0), 0).err(),
        Some(IgngError::ZeroDimension)
    );
    assert!(matches!(
        Igng::new(2, IgngParams::with_sigma(f64::NAN), 0),
        Err(IgngError::InvalidParameter { name: "sigma", .. })
    ));
    assert!(Igng::new(2, IgngParams::with_sigma(-1.0), 0).is_err());
    let mut p = IgngParams::with_sigma(1.0);
    p.eps_winner = 2.0;
    assert!(Igng::new(2, p, 0).is_err());
    let mut g = Igng::new(2, IgngParams::with_sigma(1.0), 0).unwrap();
    assert_eq!(
        g.train(&[1.0f32, 2.0, 3.0], 1).err(),
        Some(IgngError::DimensionMismatch { dim: 2, len: 3 })
    );
    assert!(g.adapt(&[1.0f64]).is_err());
    assert_eq!(g.classify(&[0.0f64, 0.0]), None); // no class yet
    assert_eq!(g.classify(&[0.0f64]), None); // wrong length
}

#[test]
fn nearest_reports_distance_beyond_sigma() {
    let mut g = Igng::new(2, IgngParams::with_sigma(1.0), 0).unwrap();
    g.adapt(&[0.0f64, 0.0]).unwrap();
    let (c, d) = g.nearest(&[3.0f64, 4.0]).unwrap();
    assert_eq!(c, ClassId(0));
    assert!((d - 5.0).abs() < 1e-12);
    assert_eq!(g.classify(&[3.0f64, 4.0]), Some(ClassId(0)));
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(48))]

    /// Under the default insertion rule the live prototypes stay pairwise ≥ σ apart, whatever
    /// the data, the seed and any pruning.
    #[test]
    fn classes_stay_sigma_apart(
        points in prop::collection::vec(prop::array::uniform3(-3.0f64..3.0), 1..300),
        sigma in 0.2f64..2.0,
        seed in any::<u64>(),
        prune_first in any::<bool>(),
    ) {
        let data: Vec<f64> = points.iter().flatten().copied().collect();
        let mut p = IgngParams::with_sigma(sigma);
        p.batch = 200;
        // Fast warps stress the separation guard.
        p.eps_winner = 0.3;
        p.eps_neighbour = 0.05;
        p.age_mature = 5;
        p.age_max = 4;
        let mut g = Igng::new(3, p, seed).unwrap();
        g.train(&data, 3).unwrap();
        let first = g.prototypes().next().map(|(c, _)| c);
        if prune_first && let Some(c) = first {
            g.prune(c).unwrap();
            g.train(&data, 2).unwrap();
        }
        prop_assert!(!g.is_empty() || prune_first);
        prop_assert!(pairwise_min(&g) >= sigma * (1.0 - 1e-12));
        for row in data.chunks(3) {
            prop_assert!(g.is_empty() || g.classify(row).is_some());
        }
    }
}
