//! Terrain classes by an Incremental Growing Neural Gas (IGNG; Prágr22 §4.3 Alg. 7 and appendix
//! Alg. 11, after Prudent and Ennaji 2005; decision 17).
//!
//! The gas is a graph of neurons (prototypes in descriptor space, each with an age) and edges
//! (each with an age). A neuron is an *embryo* while its age is below `a_mature` and *mature*
//! from then on; per decision 17 **every** neuron, embryo or mature, is a terrain class. A class
//! keeps its [`ClassId`] for as long as its neuron lives; ids are never reused.
//!
//! [`Igng::adapt`] is one step of Alg. 11 for a measurement x, with ω₁, ω₂ the nearest and second
//! nearest neurons and σ = σ^IGNG (= 2l, Prágr22 §4.3; [`IgngParams::from_lengthscale`]):
//!
//! 1. no neuron, or ‖x − ω₁‖ > σ: insert an embryo neuron at x with age 1 (lines 4–5);
//! 2. else if there is one neuron only or ‖x − ω₂‖ > σ: insert a neuron at x with age 1 and an edge
//!    (x, ω₁) of age 0 (lines 7–9) — **only under [`InsertionRule::Alg11`]**, see below;
//! 3. else: warp ω₁ by ε₁ (x − ω₁), warp each neighbour of ω₁ by ε_nb (x − ω_nb) and age its edge to
//!    ω₁ by one (lines 11–14); reset the edge (ω₁, ω₂) to age 0 or create it (lines 15–18); age
//!    every neighbour of ω₁ by one (lines 19–20);
//!
//! then remove edges older than a_max (lines 21–22) and mature neurons left without an edge
//! (lines 23–25; [`InsertionRule::Alg11`] only, see below). As Alg. 11 is indented, the pruning belongs to the adaptation branch; the
//! insertion branches change no age, so for a_mature ≥ 2 pruning after every step (as the text
//! puts it) would change nothing.
//!
//! ## The separation conflict and [`InsertionRule`]
//!
//! The paper's text (§4.3) says "new classes are inserted into the neural gas when the distance
//! from all prototypes exceeds σ^IGNG", but Alg. 11 step 2 inserts a neuron at x although ω₁ lies
//! within σ of it: taken literally, a tight cluster of descriptors always produces at least two
//! neurons (the second sample of a cluster lands in step 2), so with "every neuron is a class"
//! (decision 17) one terrain splits into several classes whose cells interleave and are then
//! eroded away (Eq. 25). Both readings are implemented:
//!
//! * [`InsertionRule::Separated`] (**default**): classes are created only farther than σ from every
//!   live class. Step 2 becomes an adaptation without the ω₂ edge (lines 11–14 and 19–20; lines
//!   15–18 need an ω₂ within σ). Warps that would bring a neuron within σ of another live neuron
//!   are not applied. Invariant: live prototypes are pairwise ≥ σ apart.
//!   Mature neurons without an edge are **kept** (Alg. 11 lines 23–25 do not apply): with
//!   classes ≥ σ apart, an edge needs a descriptor within σ of two of them, so a well-separated
//!   terrain's neuron is isolated by design. Removing it once mature made every class die and be
//!   re-created under a new id every few updates (one courtyard-small mission went through
//!   class ids 10 to 1895), and an update could end with a terrain's class missing, its cells
//!   assigned to the nearest other class (fast-gait brown turf planned as pavement).
//! * [`InsertionRule::Alg11`]: Alg. 11 verbatim. Prototypes may be closer than σ; the graph's
//!   connected components ([`Igng::components`]) are then the natural clusters.
//!
//! ## Training, classification and pruning
//!
//! [`Igng::train`] is Alg. 7 lines 5–6: for each batch it draws min(n^IGNG, rows) distinct rows
//! uniformly at random (a seeded ChaCha8 stream, so a seed and a call sequence fix the result) and
//! adapts to each in turn. [`Igng::classify`] is Alg. 7 line 8: the nearest live prototype,
//! whatever its distance (the paper assigns every described cell); [`Igng::nearest`] also returns
//! the distance for callers that want to gate on σ. [`Igng::prune`] removes a class (Alg. 9 prunes
//! classes whose information gain is exhausted) and blacklists its prototype (decision 17): no
//! neuron is ever created within σ of a blacklisted prototype; a measurement that would create one
//! is skipped and counted.
//!
//! Rows or measurements with a non-finite component are rejected and counted, never adapted to.
//!
//! Defaults (Prágr22 Table 3): ε₁ = 1e-3, ε_nb = 1e-5, a_mature = 100, a_max = 50, n^IGNG = 5000.
//! σ has no default: it is 2l for the model's GP lengthscale l (0.4 → σ = 0.8).

use std::collections::BTreeMap;

use rustc_hash::FxHashMap as HashMap;
use std::fmt;

use rand::rngs::ChaCha8Rng;
use rand::{RngExt, SeedableRng};
use thiserror::Error;

/// Identifier of a terrain class (one IGNG neuron). Stable while the class lives; never reused.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct ClassId(pub u32);

impl fmt::Display for ClassId {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "T{}", self.0)
    }
}

/// Errors of the IGNG.
#[derive(Clone, Debug, Error, PartialEq)]
pub enum IgngError {
    /// A parameter is non-finite or out of range.
    #[error("invalid IGNG parameter {name} = {value}: {reason}")]
    InvalidParameter {
        /// The parameter's name.
        name: &'static str,
        /// The offending value.
        value: f64,
        /// What was expected.
        reason: &'static str,
    },
    /// The descriptor dimension is zero.
    #[error("descriptor dimension must be at least 1")]
    ZeroDimension,
    /// A measurement or the descriptor buffer does not match the dimension.
    #[error("length {len} is not a multiple of (or equal to) the dimension {dim}")]
    DimensionMismatch {
        /// The gas's dimension.
        dim: usize,
        /// The length received.
        len: usize,
    },
    /// A measurement has a non-finite component.
    #[error("measurement has a non-finite component")]
    NonFinite,
    /// The class does not exist (never did, or was removed).
    #[error("unknown class {0}")]
    UnknownClass(ClassId),
}

/// Which reading of Alg. 11's second insertion branch to use (see the module documentation).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum InsertionRule {
    /// Classes only farther than σ from every live class; prototypes stay pairwise ≥ σ apart.
    #[default]
    Separated,
    /// Alg. 11 verbatim: a neuron is also inserted when ω₁ is within σ but ω₂ is not.
    Alg11,
}

/// IGNG parameters (Prágr22 Table 3 names in brackets).
#[derive(Clone, Debug, PartialEq)]
pub struct IgngParams {
    /// Adaptation threshold σ^IGNG = 2l (l the GP lengthscale), descriptor units.
    pub sigma: f64,
    /// Winner warp rate ε₁^IGNG (`igng_eps_winner`, 1e-3).
    pub eps_winner: f64,
    /// Neighbour warp rate ε_nb^IGNG (`igng_eps_neighbour`, 1e-5).
    pub eps_neighbour: f64,
    /// Neuron mature age a_mature^IGNG (`igng_age_mature`, 100).
    pub age_mature: u32,
    /// Edge maximum age a_max^IGNG (`igng_age_max`, 50).
    pub age_max: u32,
    /// Batch size n^IGNG (`igng_batch`, 5000).
    pub batch: usize,
    /// Insertion rule (default [`InsertionRule::Separated`]).
    pub insertion: InsertionRule,
}

impl IgngParams {
    /// The paper's defaults with σ^IGNG = 2 · `lengthscale` (Prágr22 §4.3).
    pub fn from_lengthscale(lengthscale: f64) -> Self {
        Self::with_sigma(2.0 * lengthscale)
    }

    /// The paper's defaults with the given σ^IGNG.
    pub fn with_sigma(sigma: f64) -> Self {
        Self {
            sigma,
            eps_winner: 1e-3,
            eps_neighbour: 1e-5,
            age_mature: 100,
            age_max: 50,
            batch: 5000,
            insertion: InsertionRule::default(),
        }
    }

    fn validate(&self) -> Result<(), IgngError> {
        let bad = |name, value, reason| {
            Err(IgngError::InvalidParameter {
                name,
                value,
                reason,
            })
        };
        if !(self.sigma.is_finite() && self.sigma > 0.0) {
            return bad("sigma", self.sigma, "must be finite and > 0");
        }
        for (name, v) in [
            ("eps_winner", self.eps_winner),
            ("eps_neighbour", self.eps_neighbour),
        ] {
            if !(v.is_finite() && (0.0..=1.0).contains(&v)) {
                return bad(name, v, "must lie in [0, 1]");
            }
        }
        if self.batch == 0 {
            return bad("batch", 0.0, "must be at least 1");
        }
        Ok(())
    }
}

/// What one adaptation step did.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum AdaptOutcome {
    /// A neuron (class) was created at the measurement (Alg. 11 lines 5 or 8–9).
    Created(ClassId),
    /// The nearest neuron (and its neighbours) were warped (lines 11–20).
    Adapted(ClassId),
    /// A class would have been created within σ of a blacklisted prototype; nothing was done.
    Blacklisted,
}

/// Counts of one [`Igng::train`] call.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct TrainReport {
    /// Rows in the descriptor buffer.
    pub rows: usize,
    /// Rows rejected for a non-finite component (not drawn).
    pub rejected_rows: usize,
    /// Adaptation steps performed.
    pub steps: usize,
    /// Classes created.
    pub created: usize,
    /// Steps skipped because of the blacklist.
    pub blacklisted: usize,
    /// Classes removed by the graph pruning (Alg. 11 lines 23–25).
    pub removed: usize,
}

/// A neuron as seen from outside.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct NeuronView<'a> {
    /// Its class id.
    pub id: ClassId,
    /// Its prototype ta(T) in descriptor space.
    pub prototype: &'a [f64],
    /// Its age a(ω).
    pub age: u32,
    /// True when mature (age ≥ a_mature); embryo otherwise.
    pub mature: bool,
}

#[derive(Clone, Debug, PartialEq)]
struct Neuron {
    id: ClassId,
    w: Box<[f64]>,
    age: u32,
}

/// The incremental growing neural gas of terrain classes. See the module documentation.
#[derive(Debug)]
pub struct Igng {
    dim: usize,
    params: IgngParams,
    neurons: Vec<Neuron>,
    /// Edges keyed by (smaller id, larger id), value = age.
    edges: BTreeMap<(ClassId, ClassId), u32>,
    blacklist: Vec<Box<[f64]>>,
    next_id: u32,
    rng: ChaCha8Rng,
    rejected: u64,
    removed: usize,
    /// Reused buffers of one adaptation step (a batch is thousands of steps): the moved
    /// prototype of [`Self::warp`] and the winner's neighbours.
    scratch_w: Vec<f64>,
    scratch_ids: Vec<ClassId>,
}

fn edge_key(a: ClassId, b: ClassId) -> (ClassId, ClassId) {
    if a <= b { (a, b) } else { (b, a) }
}

fn dist2(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).map(|(x, y)| (x - y) * (x - y)).sum()
}

impl Igng {
    /// An empty gas for `dim`-dimensional descriptors; `seed` fixes the batch draws.
    pub fn new(dim: usize, params: IgngParams, seed: u64) -> Result<Self, IgngError> {
        if dim == 0 {
            return Err(IgngError::ZeroDimension);
        }
        params.validate()?;
        Ok(Self {
            dim,
            params,
            neurons: Vec::new(),
            edges: BTreeMap::new(),
            blacklist: Vec::new(),
            next_id: 0,
            rng: ChaCha8Rng::seed_from_u64(seed),
            rejected: 0,
            removed: 0,
            scratch_w: Vec::with_capacity(dim),
            scratch_ids: Vec::new(),
        })
    }

    /// Descriptor dimension.
    pub fn dim(&self) -> usize {
        self.dim
    }

    /// The parameters.
    pub fn params(&self) -> &IgngParams {
        &self.params
    }

    /// Number of live classes (neurons).
    pub fn len(&self) -> usize {
        self.neurons.len()
    }

    /// True when there is no class.
    pub fn is_empty(&self) -> bool {
        self.neurons.is_empty()
    }

    /// Measurements and rows rejected so far for non-finite components.
    pub fn rejected(&self) -> u64 {
        self.rejected
    }

    /// The live classes and their prototypes, in creation order.
    pub fn prototypes(&self) -> impl Iterator<Item = (ClassId, &[f64])> + '_ {
        self.neurons.iter().map(|n| (n.id, &n.w[..]))
    }

    /// The prototype of `class`, if it lives.
    pub fn prototype(&self, class: ClassId) -> Option<&[f64]> {
        self.index_of(class).map(|i| &self.neurons[i].w[..])
    }

    /// The live neurons with their ages and maturity, in creation order.
    pub fn neurons(&self) -> impl Iterator<Item = NeuronView<'_>> + '_ {
        let mature_age = self.params.age_mature;
        self.neurons.iter().map(move |n| NeuronView {
            id: n.id,
            prototype: &n.w,
            age: n.age,
            mature: n.age >= mature_age,
        })
    }

    /// The edges as (a, b, age) with a < b, in id order.
    pub fn edges(&self) -> impl Iterator<Item = (ClassId, ClassId, u32)> + '_ {
        self.edges.iter().map(|(&(a, b), &age)| (a, b, age))
    }

    /// The blacklisted prototypes of pruned classes, in pruning order.
    pub fn blacklist(&self) -> impl Iterator<Item = &[f64]> + '_ {
        self.blacklist.iter().map(|w| &w[..])
    }

    /// The connected components of the graph, each sorted by id, ordered by their smallest id.
    /// Under [`InsertionRule::Alg11`] these are the natural clusters.
    pub fn components(&self) -> Vec<Vec<ClassId>> {
        let n = self.neurons.len();
        let mut parent: Vec<usize> = (0..n).collect();
        fn find(p: &mut [usize], mut i: usize) -> usize {
            while p[i] != i {
                p[i] = p[p[i]];
                i = p[i];
            }
            i
        }
        for &(a, b) in self.edges.keys() {
            if let (Some(i), Some(j)) = (self.index_of(a), self.index_of(b)) {
                let (ri, rj) = (find(&mut parent, i), find(&mut parent, j));
                if ri != rj {
                    parent[ri.max(rj)] = ri.min(rj);
                }
            }
        }
        let mut groups: BTreeMap<usize, Vec<ClassId>> = BTreeMap::new();
        for i in 0..n {
            let r = find(&mut parent, i);
            groups.entry(r).or_default().push(self.neurons[i].id);
        }
        let mut out: Vec<Vec<ClassId>> = groups
            .into_values()
            .map(|mut g| {
                g.sort();
                g
            })
            .collect();
        out.sort();
        out
    }

    /// The nearest live class to `x` and the Euclidean distance to its prototype; `None` when
    /// there is no class or `x` is invalid (wrong length or non-finite).
    pub fn nearest<D: Copy + Into<f64>>(&self, x: &[D]) -> Option<(ClassId, f64)> {
        if x.len() != self.dim || !x.iter().all(|&v| v.into().is_finite()) {
            return None;
        }
        let mut best: Option<(usize, f64)> = None;
        for (i, n) in self.neurons.iter().enumerate() {
            let d =
                n.w.iter()
                    .zip(x)
                    .map(|(a, &b)| {
                        let e = a - b.into();
                        e * e
                    })
                    .sum::<f64>();
            if best.is_none_or(|(_, bd)| d < bd) {
                best = Some((i, d));
            }
        }
        best.map(|(i, d)| (self.neurons[i].id, d.sqrt()))
    }

    /// [`classify`](Self::classify)'s class of `x` with the distances to its prototype and to
    /// the nearest other prototype (`+∞` when there is none): a prototype that moves by δ
    /// changes a distance by at most δ, so the class stands as long as no prototype moved by
    /// half the difference. `None` when there is no class or `x` is invalid.
    pub fn nearest_two(&self, x: &[f64]) -> Option<(ClassId, f64, f64)> {
        if x.len() != self.dim || !x.iter().all(|v| v.is_finite()) {
            return None;
        }
        let mut best: Option<(usize, f64)> = None;
        let mut second = f64::INFINITY;
        for (i, n) in self.neurons.iter().enumerate() {
            let d = dist2(&n.w, x);
            // The same comparison as `nearest`, so the same class on ties.
            match best {
                Some((_, bd)) if d >= bd => second = second.min(d),
                _ => {
                    if let Some((_, bd)) = best {
                        second = second.min(bd);
                    }
                    best = Some((i, d));
                }
            }
        }
        best.map(|(i, d)| (self.neurons[i].id, d.sqrt(), second.sqrt()))
    }

    /// The class of descriptor `x` (Alg. 7 line 8): the nearest live prototype, whatever the
    /// distance. `None` when there is no class or `x` is invalid.
    pub fn classify<D: Copy + Into<f64>>(&self, x: &[D]) -> Option<ClassId> {
        self.nearest(x).map(|(c, _)| c)
    }

    /// Removes `class` and its edges and blacklists its prototype (decision 17).
    pub fn prune(&mut self, class: ClassId) -> Result<(), IgngError> {
        let i = self.index_of(class).ok_or(IgngError::UnknownClass(class))?;
        let n = self.neurons.remove(i);
        self.edges.retain(|&(a, b), _| a != class && b != class);
        self.blacklist.push(n.w);
        Ok(())
    }

    /// Alg. 7 lines 5–6: `batches` rounds, each adapting to min(n^IGNG, valid rows) distinct rows
    /// drawn uniformly from `descriptors` (row-major, `dim` values per row). Rows with a
    /// non-finite value are rejected and counted (once per call).
    pub fn train<D: Copy + Into<f64>>(
        &mut self,
        descriptors: &[D],
        batches: usize,
    ) -> Result<TrainReport, IgngError> {
        if !descriptors.len().is_multiple_of(self.dim) {
            return Err(IgngError::DimensionMismatch {
                dim: self.dim,
                len: descriptors.len(),
            });
        }
        let dim = self.dim;
        let rows = descriptors.len() / dim;
        Ok(self.train_rows(rows, |r| &descriptors[r * dim..(r + 1) * dim], batches))
    }

    /// [`train`](Self::train) on `rows` descriptors read through `row` (each of `dim`
    /// values), so that a caller whose descriptors are not one contiguous slice need not copy
    /// them: the same rows in the same order give the same network.
    pub fn train_rows<'a, D: Copy + Into<f64> + 'a>(
        &mut self,
        rows: usize,
        row: impl Fn(usize) -> &'a [D],
        batches: usize,
    ) -> TrainReport {
        let valid: Vec<usize> = (0..rows)
            .filter(|&r| {
                let x = row(r);
                x.len() == self.dim && x.iter().all(|&v| v.into().is_finite())
            })
            .collect();
        let rejected = rows - valid.len();
        self.rejected += rejected as u64;
        let mut report = self.train_drawn(valid.len(), |k| row(valid[k]), batches);
        report.rows = rows;
        report.rejected_rows += rejected;
        report
    }

    /// [`train_rows`](Self::train_rows) for rows the caller has already validated (each of
    /// `dim` finite values, as a [`crate::descriptor_field::DescriptorField`] stores them): the
    /// draws no longer visit every row, so a batch costs O(n^IGNG) whatever the row count. The
    /// random subset is the same as `train_rows` draws when every row is valid, so the network
    /// is the same. A drawn row that is not valid after all is skipped and counted as rejected.
    pub fn train_valid_rows<'a, D: Copy + Into<f64> + 'a>(
        &mut self,
        rows: usize,
        row: impl Fn(usize) -> &'a [D],
        batches: usize,
    ) -> TrainReport {
        self.train_drawn(rows, row, batches)
    }

    /// `batches` rounds, each adapting to min(n^IGNG, `rows`) distinct rows drawn uniformly
    /// (by a partial Fisher–Yates shuffle that keeps only the positions it has moved, so a
    /// batch costs O(n^IGNG) whatever the row count). A drawn row that is not valid is skipped
    /// and counted as rejected.
    fn train_drawn<'a, D: Copy + Into<f64> + 'a>(
        &mut self,
        rows: usize,
        row: impl Fn(usize) -> &'a [D],
        batches: usize,
    ) -> TrainReport {
        let mut report = TrainReport {
            rows,
            ..TrainReport::default()
        };
        if rows == 0 {
            return report;
        }
        let removed_before = self.removed;
        let take = self.params.batch.min(rows);
        // Position → row for the positions the shuffle moved; the others hold their own index.
        let mut moved: HashMap<usize, usize> = HashMap::default();
        let at = |moved: &HashMap<usize, usize>, k: usize| moved.get(&k).copied().unwrap_or(k);
        let mut x = vec![0.0; self.dim];
        for _ in 0..batches {
            for k in 0..take {
                let j = self.rng.random_range(k..rows);
                let (rk, rj) = (at(&moved, k), at(&moved, j));
                moved.insert(k, rj);
                moved.insert(j, rk);
            }
            for k in 0..take {
                let r = at(&moved, k);
                let v = row(r);
                if v.len() != self.dim || !v.iter().all(|&v| v.into().is_finite()) {
                    report.rejected_rows += 1;
                    continue;
                }
                for (xi, &v) in x.iter_mut().zip(v) {
                    *xi = v.into();
                }
                self.counted_step(&x, &mut report);
            }
        }
        self.rejected += report.rejected_rows as u64;
        report.removed = self.removed - removed_before;
        report
    }

    /// One training step on a validated row, counted in `report`.
    fn counted_step(&mut self, x: &[f64], report: &mut TrainReport) {
        match self.adapt_valid(x) {
            AdaptOutcome::Created(_) => report.created += 1,
            AdaptOutcome::Blacklisted => report.blacklisted += 1,
            AdaptOutcome::Adapted(_) => {}
        }
        report.steps += 1;
    }

    /// One step of Alg. 11 for measurement `x`. Errors (and counts) non-finite measurements.
    pub fn adapt<D: Copy + Into<f64>>(&mut self, x: &[D]) -> Result<AdaptOutcome, IgngError> {
        if x.len() != self.dim {
            return Err(IgngError::DimensionMismatch {
                dim: self.dim,
                len: x.len(),
            });
        }
        let x: Vec<f64> = x.iter().map(|&v| v.into()).collect();
        if !x.iter().all(|v| v.is_finite()) {
            self.rejected += 1;
            return Err(IgngError::NonFinite);
        }
        Ok(self.adapt_valid(&x))
    }

    fn index_of(&self, class: ClassId) -> Option<usize> {
        self.neurons.iter().position(|n| n.id == class)
    }

    fn near_blacklist(&self, x: &[f64]) -> bool {
        let s2 = self.params.sigma * self.params.sigma;
        self.blacklist.iter().any(|b| dist2(b, x) <= s2)
    }

    fn insert(&mut self, x: &[f64]) -> ClassId {
        let id = ClassId(self.next_id);
        self.next_id += 1;
        self.neurons.push(Neuron {
            id,
            w: x.into(),
            age: 1,
        });
        id
    }

    /// Alg. 11 on a validated measurement.
    fn adapt_valid(&mut self, x: &[f64]) -> AdaptOutcome {
        let sigma2 = self.params.sigma * self.params.sigma;
        // Lines 2–3: nearest and second nearest (ties: the earlier-created neuron).
        let mut first: Option<(usize, f64)> = None;
        let mut second: Option<(usize, f64)> = None;
        for (i, n) in self.neurons.iter().enumerate() {
            let d = dist2(&n.w, x);
            if first.is_none_or(|(_, fd)| d < fd) {
                second = first;
                first = Some((i, d));
            } else if second.is_none_or(|(_, sd)| d < sd) {
                second = Some((i, d));
            }
        }
        // Lines 4–5.
        let Some((i1, _)) = first.filter(|&(_, d1)| d1 <= sigma2) else {
            if self.near_blacklist(x) {
                return AdaptOutcome::Blacklisted;
            }
            return AdaptOutcome::Created(self.insert(x));
        };
        let id1 = self.neurons[i1].id;
        let second_close = second.filter(|&(_, d2)| d2 <= sigma2);
        if second_close.is_none() && self.params.insertion == InsertionRule::Alg11 {
            // Lines 7–9.
            if self.near_blacklist(x) {
                return AdaptOutcome::Blacklisted;
            }
            let id = self.insert(x);
            self.edges.insert(edge_key(id, id1), 0);
            return AdaptOutcome::Created(id);
        }
        // Lines 11–14.
        self.warp(i1, x, self.params.eps_winner);
        let mut nbs = std::mem::take(&mut self.scratch_ids);
        nbs.clear();
        nbs.extend(self.neighbours(id1));
        for &nb in &nbs {
            if let Some(j) = self.index_of(nb) {
                self.warp(j, x, self.params.eps_neighbour);
            }
            if let Some(age) = self.edges.get_mut(&edge_key(id1, nb)) {
                *age = age.saturating_add(1);
            }
        }
        // Lines 15–18 (need an ω₂ within σ).
        if let Some((i2, _)) = second_close {
            let id2 = self.neurons[i2].id;
            self.edges.insert(edge_key(id1, id2), 0);
            // The neighbours now: those of lines 11–14 (no edge was removed since) and ω₂.
            if !nbs.contains(&id2) {
                nbs.push(id2);
            }
        }
        // Lines 19–20.
        for &nb in &nbs {
            if let Some(j) = self.index_of(nb) {
                self.neurons[j].age = self.neurons[j].age.saturating_add(1);
            }
        }
        self.scratch_ids = nbs;
        // Lines 21–25.
        let age_max = self.params.age_max;
        self.edges.retain(|_, &mut age| age <= age_max);
        if self.params.insertion == InsertionRule::Alg11 {
            // Under `Separated` a class is isolated by design (see the module docs).
            let age_mature = self.params.age_mature;
            let edges = &self.edges;
            let before = self.neurons.len();
            self.neurons.retain(|n| {
                n.age < age_mature || edges.keys().any(|&(a, b)| a == n.id || b == n.id)
            });
            self.removed += before - self.neurons.len();
        }
        AdaptOutcome::Adapted(id1)
    }

    fn neighbours(&self, id: ClassId) -> impl Iterator<Item = ClassId> + '_ {
        self.edges.keys().filter_map(move |&(a, b)| {
            if a == id {
                Some(b)
            } else if b == id {
                Some(a)
            } else {
                None
            }
        })
    }

    /// ω ← ω + ε (x − ω); under [`InsertionRule::Separated`] not applied when it would bring the
    /// neuron within σ of another live neuron.
    fn warp(&mut self, i: usize, x: &[f64], eps: f64) {
        if eps == 0.0 {
            return;
        }
        let mut moved = std::mem::take(&mut self.scratch_w);
        moved.clear();
        moved.extend(
            self.neurons[i]
                .w
                .iter()
                .zip(x)
                .map(|(w, xv)| w + eps * (xv - w)),
        );
        let clash = self.params.insertion == InsertionRule::Separated && {
            let s2 = self.params.sigma * self.params.sigma;
            self.neurons
                .iter()
                .enumerate()
                .any(|(j, n)| j != i && dist2(&n.w, &moved) < s2)
        };
        if !clash {
            self.neurons[i].w.copy_from_slice(&moved);
        }
        self.scratch_w = moved;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn alg11_second_sample_creates_connected_neuron() {
        let mut p = IgngParams::with_sigma(1.0);
        p.insertion = InsertionRule::Alg11;
        let mut g = Igng::new(1, p, 0).unwrap();
        assert_eq!(g.adapt(&[0.0]).unwrap(), AdaptOutcome::Created(ClassId(0)));
        assert_eq!(g.adapt(&[0.1]).unwrap(), AdaptOutcome::Created(ClassId(1)));
        assert_eq!(
            g.edges().collect::<Vec<_>>(),
            vec![(ClassId(0), ClassId(1), 0)]
        );
        // Both within σ now: adapt, reset the edge, age the neighbour.
        assert_eq!(g.adapt(&[0.05]).unwrap(), AdaptOutcome::Adapted(ClassId(0)));
        let ages: Vec<u32> = g.neurons().map(|n| n.age).collect();
        assert_eq!(ages, vec![1, 2]);
        assert_eq!(g.edges().next().unwrap().2, 0);
    }

    #[test]
    fn separated_second_sample_adapts() {
        let mut g = Igng::new(1, IgngParams::with_sigma(1.0), 0).unwrap();
        g.adapt(&[0.0]).unwrap();
        assert_eq!(g.adapt(&[0.5]).unwrap(), AdaptOutcome::Adapted(ClassId(0)));
        assert_eq!(g.len(), 1);
        let w = g.prototype(ClassId(0)).unwrap()[0];
        assert!((w - 0.5e-3).abs() < 1e-15);
    }

    #[test]
    fn separated_classes_survive_maturity_without_edges() {
        // Two terrains 2σ apart: under `Separated` no descriptor is within σ of both, so
        // neither neuron ever gets an edge; both stay the same classes however long they adapt.
        let mut p = IgngParams::with_sigma(1.0);
        p.age_mature = 1;
        p.age_max = 1;
        let mut g = Igng::new(1, p, 0).unwrap();
        assert_eq!(g.adapt(&[0.0]).unwrap(), AdaptOutcome::Created(ClassId(0)));
        assert_eq!(g.adapt(&[2.0]).unwrap(), AdaptOutcome::Created(ClassId(1)));
        for k in 0..500 {
            let x = if k % 2 == 0 { 0.1 } else { 1.9 };
            let want = ClassId((k % 2) as u32);
            assert_eq!(g.adapt(&[x]).unwrap(), AdaptOutcome::Adapted(want));
        }
        assert_eq!(g.len(), 2);
        assert_eq!(g.classify(&[0.0]), Some(ClassId(0)));
        assert_eq!(g.classify(&[2.0]), Some(ClassId(1)));
    }

    #[test]
    fn old_edges_and_isolated_mature_neurons_are_removed() {
        // a_max = 1: an edge aged twice without reset is dropped; a_mature = 1 makes every
        // neuron mature, so the isolated one disappears.
        let mut p = IgngParams::with_sigma(1.0);
        p.insertion = InsertionRule::Alg11;
        p.age_max = 1;
        p.age_mature = 1;
        let mut g = Igng::new(1, p, 0).unwrap();
        g.adapt(&[0.0]).unwrap(); // ω0
        g.adapt(&[0.9]).unwrap(); // ω1, edge (0,1)
        g.adapt(&[-0.9]).unwrap(); // ω1 farther than σ from -0.9: ω2 at -0.9, edge (0,2)
        assert_eq!(g.len(), 3);
        // x with ω0 nearest and ω2 second: edges (0,1) and (0,2) age, (0,2) is reset.
        for _ in 0..2 {
            assert_eq!(g.adapt(&[-0.4]).unwrap(), AdaptOutcome::Adapted(ClassId(0)));
        }
        // Edge (0,1) exceeded a_max and went; ω1 (mature, isolated) was removed.
        assert!(g.prototype(ClassId(1)).is_none());
        assert!(g.prototype(ClassId(0)).is_some());
    }

    proptest::proptest! {
        /// `train_rows` skips invalid rows and draws from the rest: the same network as
        /// drawing from the valid rows alone, batch after batch.
        #[test]
        fn invalid_rows_are_dropped_before_the_draws(
            values in proptest::collection::vec(-1.0f64..1.0, 2..240),
            invalid in proptest::collection::vec(proptest::bool::weighted(0.2), 120),
            batch in 1usize..40,
            batches in 1usize..4,
            seed in 0u64..1000,
        ) {
            let dim = 2;
            let rows: Vec<[f64; 2]> = values
                .chunks_exact(dim)
                .zip(&invalid)
                .map(|(r, &bad)| if bad { [f64::NAN, r[1]] } else { [r[0], r[1]] })
                .collect();
            let valid: Vec<[f64; 2]> =
                rows.iter().copied().filter(|r| r[0].is_finite()).collect();
            let mut p = IgngParams::with_sigma(0.3);
            p.batch = batch;
            p.age_mature = 5;
            p.age_max = 4;
            let mut a = Igng::new(dim, p.clone(), seed).unwrap();
            let mut b = Igng::new(dim, p, seed).unwrap();
            let ra = a.train_rows(rows.len(), |r| &rows[r][..], batches);
            let rb = b.train_valid_rows(valid.len(), |r| &valid[r][..], batches);
            proptest::prop_assert_eq!(ra.rejected_rows, rows.len() - valid.len());
            proptest::prop_assert_eq!((ra.steps, ra.created, ra.removed), (rb.steps, rb.created, rb.removed));
            let pa: Vec<_> = a.prototypes().map(|(c, w)| (c, w.to_vec())).collect();
            let pb: Vec<_> = b.prototypes().map(|(c, w)| (c, w.to_vec())).collect();
            proptest::prop_assert_eq!(pa, pb);
        }
    }
}
