//! The depth-5 CART regression tree: depth limit, exact fit of piecewise-constant data, equality
//! with a brute-force greedy CART on tiny sets, bad input.

use proptest::prelude::*;
use strider_learn::regression_tree::{Node, RegressionTree, TreeError, TreeParams};

fn sse(y: &[f64]) -> f64 {
    if y.is_empty() {
        return 0.0;
    }
    let m = y.iter().sum::<f64>() / y.len() as f64;
    y.iter().map(|v| (v - m).powi(2)).sum()
}

/// Naive greedy CART: at each node try every feature and every midpoint between distinct sorted
/// values, computing both sides' SSE directly; returns the predictions at `queries`.
fn brute(x: &[Vec<f64>], y: &[f64], depth: usize, max_depth: usize, q: &[f64]) -> f64 {
    let mean = y.iter().sum::<f64>() / y.len() as f64;
    let parent = sse(y);
    if depth >= max_depth || y.len() < 2 || parent <= 1e-24 * y.iter().map(|v| v * v).sum::<f64>() {
        return mean;
    }
    let d = x[0].len();
    let mut best: Option<(f64, usize, f64)> = None;
    for f in 0..d {
        let mut vals: Vec<f64> = x.iter().map(|r| r[f]).collect();
        vals.sort_by(f64::total_cmp);
        vals.dedup();
        for w in vals.windows(2) {
            let t = w[0] + 0.5 * (w[1] - w[0]);
            let (l, r): (Vec<f64>, Vec<f64>) = {
                let mut l = Vec::new();
                let mut r = Vec::new();
                for (row, &v) in x.iter().zip(y) {
                    if row[f] <= t { l.push(v) } else { r.push(v) }
                }
                (l, r)
            };
            let s = sse(&l) + sse(&r);
            if best.is_none_or(|(b, _, _)| s < b - 1e-9) {
                best = Some((s, f, t));
            }
        }
    }
    let Some((s, f, t)) = best else { return mean };
    if s >= parent - 1e-12 {
        return mean;
    }
    let (mut xl, mut yl, mut xr, mut yr) = (Vec::new(), Vec::new(), Vec::new(), Vec::new());
    for (row, &v) in x.iter().zip(y) {
        if row[f] <= t {
            xl.push(row.clone());
            yl.push(v);
        } else {
            xr.push(row.clone());
            yr.push(v);
        }
    }
    if q[f] <= t {
        brute(&xl, &yl, depth + 1, max_depth, q)
    } else {
        brute(&xr, &yr, depth + 1, max_depth, q)
    }
}

#[test]
fn exact_fit_on_piecewise_constant_data_within_depth_five() {
    // y depends on a 4 × 4 grid of cells of (x0, x1) plus an irrelevant x2: 16 pieces need depth
    // 4, well within 5; every training and fresh point inside a piece is predicted exactly.
    let f = |a: f64, b: f64| ((a * 4.0).floor() * 10.0 + (b * 4.0).floor()) * 1.5 - 7.0;
    let (mut x, mut y) = (Vec::new(), Vec::new());
    for i in 0..24 {
        for j in 0..24 {
            let (a, b) = ((i as f64 + 0.5) / 24.0, (j as f64 + 0.5) / 24.0);
            x.extend_from_slice(&[a, b, ((i * 7 + j * 3) % 5) as f64]);
            y.push(f(a, b));
        }
    }
    let t = RegressionTree::fit(3, &x, &y, &TreeParams::default()).unwrap();
    assert!(t.depth() <= 5);
    for (row, &v) in x.chunks_exact(3).zip(&y) {
        assert_eq!(t.predict(row), v);
    }
    for (a, b) in [(0.1, 0.1), (0.3, 0.9), (0.6, 0.4), (0.95, 0.55)] {
        assert_eq!(t.predict(&[a, b, 2.0]), f(a, b));
    }
    // Every split uses a relevant feature.
    for n in t.nodes() {
        if let Node::Split { feature, .. } = n {
            assert!(*feature < 2);
        }
    }
}

#[test]
fn constant_targets_and_single_points_are_one_leaf() {
    let t = RegressionTree::fit(
        2,
        &[0.0, 1.0, 2.0, 3.0],
        &[4.0, 4.0],
        &TreeParams::default(),
    )
    .unwrap();
    assert_eq!((t.depth(), t.leaves()), (0, 1));
    assert_eq!(t.predict(&[9.0, 9.0]), 4.0);
    // Identical inputs with different targets cannot be split: one leaf with their mean.
    let t = RegressionTree::fit(1, &[1.0, 1.0], &[0.0, 2.0], &TreeParams::default()).unwrap();
    assert_eq!(t.leaves(), 1);
    assert_eq!(t.predict(&[1.0]), 1.0);
    // A NaN query takes the right branch: a number, not a panic.
    let t = RegressionTree::fit(1, &[0.0, 1.0], &[0.0, 2.0], &TreeParams::default()).unwrap();
    assert_eq!(t.predict(&[f64::NAN]), 2.0);
}

#[test]
fn bad_input_is_an_error() {
    let p = TreeParams::default();
    assert_eq!(RegressionTree::fit(2, &[], &[], &p), Err(TreeError::Empty));
    assert!(matches!(
        RegressionTree::fit(2, &[1.0], &[1.0], &p),
        Err(TreeError::BadDimension(_))
    ));
    assert!(matches!(
        RegressionTree::fit(0, &[], &[], &p),
        Err(TreeError::BadDimension(_))
    ));
    assert!(matches!(
        RegressionTree::fit(1, &[f64::NAN], &[1.0], &p),
        Err(TreeError::NonFinite(_))
    ));
    assert!(matches!(
        RegressionTree::fit(1, &[1.0], &[f64::INFINITY], &p),
        Err(TreeError::NonFinite(_))
    ));
    let bad = TreeParams {
        min_samples_leaf: 0,
        ..TreeParams::default()
    };
    assert!(matches!(
        RegressionTree::fit(1, &[1.0], &[1.0], &bad),
        Err(TreeError::BadParameter(_))
    ));
}

#[test]
fn a_stump_is_the_best_single_split() {
    let x = [0.3, 0.1, 0.9, 0.5, 0.7, 0.2];
    let y = [1.0, 0.0, 5.0, 1.2, 4.0, 0.4];
    let p = TreeParams {
        max_depth: 1,
        ..TreeParams::default()
    };
    let t = RegressionTree::fit(1, &x, &y, &p).unwrap();
    let pred_sse: f64 = x
        .iter()
        .zip(&y)
        .map(|(a, b)| (t.predict(&[*a]) - b).powi(2))
        .sum();
    // Brute force over all thresholds.
    let mut best = f64::INFINITY;
    for &thr in &x {
        let l: Vec<f64> = x
            .iter()
            .zip(&y)
            .filter(|(a, _)| **a <= thr)
            .map(|p| *p.1)
            .collect();
        let r: Vec<f64> = x
            .iter()
            .zip(&y)
            .filter(|(a, _)| **a > thr)
            .map(|p| *p.1)
            .collect();
        best = best.min(sse(&l) + sse(&r));
    }
    assert!((pred_sse - best).abs() < 1e-12, "{pred_sse} vs {best}");
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(48))]

    /// On tiny random sets the tree equals a naive greedy CART at training points and fresh
    /// queries, never exceeds the depth limit, and fitting twice gives the same tree.
    #[test]
    fn equals_brute_force_on_tiny_sets(
        rows in prop::collection::vec((0u8..6, 0u8..6, -50i32..50), 1..14),
        qs in prop::collection::vec((0u8..6, 0u8..6), 1..6),
        max_depth in 0usize..4,
    ) {
        let x: Vec<f64> = rows.iter().flat_map(|r| [r.0 as f64, r.1 as f64]).collect();
        let y: Vec<f64> = rows.iter().map(|r| r.2 as f64 / 4.0).collect();
        let p = TreeParams { max_depth, ..TreeParams::default() };
        let t = RegressionTree::fit(2, &x, &y, &p).unwrap();
        prop_assert!(t.depth() <= max_depth);
        prop_assert_eq!(&t, &RegressionTree::fit(2, &x, &y, &p).unwrap());
        let xr: Vec<Vec<f64>> = x.chunks_exact(2).map(|c| c.to_vec()).collect();
        let queries: Vec<[f64; 2]> = rows.iter().map(|r| [r.0 as f64, r.1 as f64])
            .chain(qs.iter().map(|q| [q.0 as f64 + 0.25, q.1 as f64 - 0.25])).collect();
        for q in queries {
            let a = t.predict(&q);
            let b = brute(&xr, &y, 0, max_depth, &q);
            prop_assert!((a - b).abs() < 1e-9, "{:?}: {} vs {}", q, a, b);
        }
    }
}
