//! The regression tree of the Prágr18 learner benchmark: CART with recursive partitioning to
//! depth d = 5 (Prágr18 §III-B.2; Breiman et al. 1984).
//!
//! # Algorithm
//! Greedy top-down induction on squared error. At a node holding the samples S, every feature f
//! and every threshold t halfway between two consecutive distinct values of f in S is a candidate
//! split S_L = {x_f ≤ t}, S_R = {x_f > t}; the one with the least Σ_L (y − ȳ_L)² + Σ_R (y − ȳ_R)²
//! wins (ties: the lower feature index, then the lower threshold), provided both sides keep at
//! least `min_samples_leaf` samples. Equivalently it maximises s_L²/n_L + s_R²/n_R with s the
//! sums of y, computed from prefix sums over the samples sorted by f: O(d n log n) per node. A
//! node becomes a leaf at `max_depth`, below `min_samples_split` samples, when it is pure, or when
//! no split lowers the error. A leaf predicts the mean of its samples.
//!
//! # Why our own
//! `linfa-trees` has decision-tree *classifiers* only; `smartcore`'s `DecisionTreeRegressor`
//! brings a whole ML framework with its own matrix abstractions for ~150 lines of CART, and
//! neither is in the project's dependency set (DEPENDENCIES.md). The tree is a batch learner:
//! the incremental benchmark refits it after every new pair (its "learning time").

use thiserror::Error;

use crate::training_data::first_non_finite;

/// Errors of tree induction.
#[derive(Clone, Debug, Error, PartialEq)]
pub enum TreeError {
    /// No training samples.
    #[error("no training samples")]
    Empty,
    /// A zero input dimension or inputs and targets of inconsistent lengths.
    #[error("bad dimension: {0}")]
    BadDimension(String),
    /// A non-finite input or target.
    #[error("{0} is not finite")]
    NonFinite(String),
    /// A parameter out of its domain.
    #[error("bad tree parameter: {0}")]
    BadParameter(String),
}

/// Tree-induction parameters.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct TreeParams {
    /// The deepest level a node may sit at (the root is depth 0; Prágr18: 5).
    pub max_depth: usize,
    /// Nodes with fewer samples become leaves (≥ 2).
    pub min_samples_split: usize,
    /// Every leaf keeps at least this many samples (≥ 1).
    pub min_samples_leaf: usize,
}

impl Default for TreeParams {
    /// Depth 5 (Prágr18), split nodes of ≥ 2 samples, leaves of ≥ 1.
    fn default() -> Self {
        TreeParams {
            max_depth: 5,
            min_samples_split: 2,
            min_samples_leaf: 1,
        }
    }
}

/// A node of the tree.
#[derive(Clone, Debug, PartialEq)]
pub enum Node {
    /// A leaf: the mean of its samples, their count and (population) variance.
    Leaf {
        /// The prediction.
        value: f64,
        /// Training samples in the leaf.
        n: usize,
        /// Population variance of their targets.
        variance: f64,
    },
    /// An internal node: go left when x\[feature\] ≤ threshold.
    Split {
        /// The feature tested.
        feature: usize,
        /// The threshold.
        threshold: f64,
        /// Index of the left child in [`RegressionTree::nodes`].
        left: usize,
        /// Index of the right child.
        right: usize,
    },
}

/// A fitted CART regression tree.
#[derive(Clone, Debug, PartialEq)]
pub struct RegressionTree {
    dim: usize,
    nodes: Vec<Node>,
}

impl RegressionTree {
    /// Fits a tree to n samples: `x` is n × `dim` row-major, `y` has n targets.
    pub fn fit(
        dim: usize,
        x: &[f64],
        y: &[f64],
        params: &TreeParams,
    ) -> Result<RegressionTree, TreeError> {
        if dim == 0 {
            return Err(TreeError::BadDimension(
                "input dimension must be ≥ 1".into(),
            ));
        }
        if x.len() != y.len() * dim {
            return Err(TreeError::BadDimension(format!(
                "{} input values for {} targets of dimension {dim}",
                x.len(),
                y.len()
            )));
        }
        if params.min_samples_leaf == 0 || params.min_samples_split < 2 {
            return Err(TreeError::BadParameter(
                "min_samples_leaf must be ≥ 1 and min_samples_split ≥ 2".into(),
            ));
        }
        if y.is_empty() {
            return Err(TreeError::Empty);
        }
        if let Some(what) = first_non_finite(dim, x, y, "sample") {
            return Err(TreeError::NonFinite(what));
        }
        let mut t = RegressionTree {
            dim,
            nodes: Vec::new(),
        };
        let idx: Vec<usize> = (0..y.len()).collect();
        t.grow(x, y, idx, 0, params);
        Ok(t)
    }

    /// The input dimension.
    pub fn dim(&self) -> usize {
        self.dim
    }

    /// The nodes; the root is node 0.
    pub fn nodes(&self) -> &[Node] {
        &self.nodes
    }

    /// The number of leaves.
    pub fn leaves(&self) -> usize {
        self.nodes
            .iter()
            .filter(|n| matches!(n, Node::Leaf { .. }))
            .count()
    }

    /// The depth: the most splits on a root-to-leaf path.
    pub fn depth(&self) -> usize {
        fn d(nodes: &[Node], k: usize) -> usize {
            match nodes[k] {
                Node::Leaf { .. } => 0,
                Node::Split { left, right, .. } => 1 + d(nodes, left).max(d(nodes, right)),
            }
        }
        d(&self.nodes, 0)
    }

    /// The leaf reached by `x`.
    ///
    /// # Panics
    /// If `x.len() != dim()`.
    pub fn leaf(&self, x: &[f64]) -> &Node {
        assert_eq!(x.len(), self.dim, "query of the wrong dimension");
        let mut k = 0;
        loop {
            match &self.nodes[k] {
                Node::Split {
                    feature,
                    threshold,
                    left,
                    right,
                } => {
                    // NaN goes right (not ≤ anything): a defined answer, not a panic.
                    k = if x[*feature] <= *threshold {
                        *left
                    } else {
                        *right
                    };
                }
                leaf => return leaf,
            }
        }
    }

    /// The prediction at `x`: the mean of its leaf.
    ///
    /// # Panics
    /// If `x.len() != dim()`.
    pub fn predict(&self, x: &[f64]) -> f64 {
        match self.leaf(x) {
            Node::Leaf { value, .. } => *value,
            Node::Split { .. } => unreachable!("leaf() returns leaves"),
        }
    }

    /// Grows the subtree of the samples `idx` at `depth`; returns its node index.
    fn grow(
        &mut self,
        x: &[f64],
        y: &[f64],
        idx: Vec<usize>,
        depth: usize,
        p: &TreeParams,
    ) -> usize {
        let n = idx.len();
        let mean = idx.iter().map(|&i| y[i]).sum::<f64>() / n as f64;
        let sse: f64 = idx.iter().map(|&i| (y[i] - mean).powi(2)).sum();
        let me = self.nodes.len();
        self.nodes.push(Node::Leaf {
            value: mean,
            n,
            variance: sse / n as f64,
        });
        // Pure (relative to the targets' magnitude) or too small or too deep: a leaf.
        let scale = idx
            .iter()
            .map(|&i| y[i] * y[i])
            .sum::<f64>()
            .max(f64::MIN_POSITIVE);
        if depth >= p.max_depth || n < p.min_samples_split || sse <= 1e-24 * scale {
            return me;
        }
        let Some((feature, threshold)) = self.best_split(x, y, &idx, sse, p) else {
            return me;
        };
        let (li, ri): (Vec<usize>, Vec<usize>) = idx
            .into_iter()
            .partition(|&i| x[i * self.dim + feature] <= threshold);
        let left = self.grow(x, y, li, depth + 1, p);
        let right = self.grow(x, y, ri, depth + 1, p);
        self.nodes[me] = Node::Split {
            feature,
            threshold,
            left,
            right,
        };
        me
    }

    /// The best (feature, threshold) for the samples `idx`, if one lowers the error.
    fn best_split(
        &self,
        x: &[f64],
        y: &[f64],
        idx: &[usize],
        sse: f64,
        p: &TreeParams,
    ) -> Option<(usize, f64)> {
        let n = idx.len();
        let d = self.dim;
        let total: f64 = idx.iter().map(|&i| y[i]).sum();
        // Maximise s_L²/n_L + s_R²/n_R; the parent's term is total²/n.
        let parent = total * total / n as f64;
        let mut best: Option<(f64, usize, f64)> = None;
        let mut order: Vec<usize> = idx.to_vec();
        for f in 0..d {
            order.sort_by(|&a, &b| x[a * d + f].total_cmp(&x[b * d + f]).then(a.cmp(&b)));
            let mut sl = 0.0;
            for k in 0..n - 1 {
                sl += y[order[k]];
                let (nl, nr) = (k + 1, n - k - 1);
                let (va, vb) = (x[order[k] * d + f], x[order[k + 1] * d + f]);
                if va == vb || nl < p.min_samples_leaf || nr < p.min_samples_leaf {
                    continue;
                }
                let sr = total - sl;
                let score = sl * sl / nl as f64 + sr * sr / nr as f64;
                // The midpoint, unless rounding lands it on vb (adjacent floats).
                let mid = va + 0.5 * (vb - va);
                let threshold = if mid < vb { mid } else { va };
                // Strictly better by more than rounding noise (deterministic tie-breaking: the
                // first feature, then the lowest threshold).
                let better = match best {
                    None => true,
                    Some((s, _, _)) => score > s + 1e-12 * s.abs().max(1e-300),
                };
                if better {
                    best = Some((score, f, threshold));
                }
            }
        }
        let (score, f, t) = best?;
        // The split must lower the squared error (score − parent is the reduction).
        let gain = score - parent;
        (gain > 1e-12 * sse.max(f64::MIN_POSITIVE) && gain > 0.0).then_some((f, t))
    }
}
