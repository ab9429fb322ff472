//! Adaptive operator selection (Ropke & Pisinger 2006, as used by GLNS).
//!
//! Every operator has a weight; an operator is drawn with probability
//! proportional to its weight. Each use earns a score (new best, improved
//! the current tour, accepted, rejected); at the end of every segment of
//! iterations the weight moves towards the operator's mean score:
//! `w ← (1 − r)·w + r·score/uses`, floored so no operator dies out.

use rand::RngExt;
use rand::rngs::ChaCha8Rng;

/// Outcome of an iteration, for scoring.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Outcome {
    NewBest,
    Improved,
    Accepted,
    Rejected,
}

impl Outcome {
    fn score(self) -> f64 {
        match self {
            Outcome::NewBest => 3.0,
            Outcome::Improved => 1.0,
            Outcome::Accepted => 0.3,
            Outcome::Rejected => 0.0,
        }
    }
}

/// Weights of one family of operators.
#[derive(Clone, Debug)]
pub(crate) struct Adaptive {
    weights: Vec<f64>,
    scores: Vec<f64>,
    uses: Vec<u32>,
    reaction: f64,
    floor: f64,
}

impl Adaptive {
    pub fn new(n: usize) -> Self {
        Self {
            weights: vec![1.0; n],
            scores: vec![0.0; n],
            uses: vec![0; n],
            reaction: 0.2,
            floor: 0.05,
        }
    }

    /// Draws an operator index.
    pub fn pick(&self, rng: &mut ChaCha8Rng) -> usize {
        let total: f64 = self.weights.iter().sum();
        let mut u = rng.random::<f64>() * total;
        for (i, w) in self.weights.iter().enumerate() {
            if u < *w {
                return i;
            }
            u -= w;
        }
        self.weights.len() - 1
    }

    /// Records the outcome of a use of operator `i`.
    pub fn record(&mut self, i: usize, o: Outcome) {
        self.scores[i] += o.score();
        self.uses[i] += 1;
    }

    /// Ends a segment: updates the weights from the collected scores.
    pub fn update(&mut self) {
        let max_mean = self
            .scores
            .iter()
            .zip(&self.uses)
            .map(|(s, &u)| if u > 0 { s / u as f64 } else { 0.0 })
            .fold(0.0f64, f64::max);
        for i in 0..self.weights.len() {
            if self.uses[i] > 0 {
                let mean = self.scores[i] / self.uses[i] as f64;
                let rel = if max_mean > 0.0 { mean / max_mean } else { 1.0 };
                self.weights[i] =
                    ((1.0 - self.reaction) * self.weights[i] + self.reaction * rel).max(self.floor);
            }
            self.scores[i] = 0.0;
            self.uses[i] = 0;
        }
    }
}
