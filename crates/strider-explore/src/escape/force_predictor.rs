//! Prágr23 (thesis C4) §4.3–4.4: the force predictor P, a GP from a cell's appearance A(ν) to the force
//! needed to pass through it (C4 Eq. 11–12, 17–19), and its information gain, the differential
//! entropy of the prediction (C4 Eq. 13).
//!
//! * Appearance: A^ab(ν) = (a, b) of the cell's colour in CIELAB (C4 Eq. 10), divided by
//!   [`PredictorParams::lab_scale`] (128: a, b to about [−1, 1], the scale decision 7 uses for the
//!   same features; with raw Lab values and l = 1 no two colours would ever correlate), or the
//!   8-bin colour-prototype histogram A^hist within r_hist (C4 §5.3).
//! * GP: exponential kernel σ²_exp exp(−‖x − x'‖ / l_exp) (C4 Eq. 19), σ²_n = 0.1, σ²_exp = 1,
//!   l_exp = 1 (Lab) or 0.4 (histogram), fixed hyper-parameters (C4 §5.1), zero prior mean (C4
//!   Eq. 18), relearned from all haptic cells at a fixed rate (0.03 Hz, C4 §4.4).
//! * I_predict(ν) = ½ ln(2πe σ²_F(ν)) with σ²_F the latent predictive variance (C4 Eq. 13): with
//!   the noisy variance the entropy could never fall below ½ ln(2πe · 0.1) = 0.27 nat, above the
//!   C4 threshold of 0.26 nat that marks a terrain as known.

use strider_core::Cell;
use strider_core::color::rgb_to_lab;
use strider_learn::gp::{Gp, GpError, GpParams, Kernel, KernelKind, differential_entropy};
use strider_map::ElevationMap;
use strider_map::descriptors::{C4_BINS, c4_histogram};

/// The appearance descriptor of the predictor.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize)]
pub enum DescriptorKind {
    /// Lab (a, b) of the cell (C4 indoor, Eq. 10).
    LabAb,
    /// 8-bin colour-prototype histogram within r_hist (C4 outdoor, §5.3).
    Histogram8,
}

impl DescriptorKind {
    /// Input dimension.
    pub fn dim(self) -> usize {
        match self {
            Self::LabAb => 2,
            Self::Histogram8 => C4_BINS,
        }
    }

    /// Parses `lab` or `hist8`.
    pub fn parse(s: &str) -> Option<Self> {
        match s {
            "lab" => Some(Self::LabAb),
            "hist8" => Some(Self::Histogram8),
            _ => None,
        }
    }
}

/// Parameters of the force predictor (C4 Table 3).
#[derive(Clone, Debug, PartialEq)]
pub struct PredictorParams {
    /// The descriptor.
    pub descriptor: DescriptorKind,
    /// GP noise variance σ²_n (C4: 0.1).
    pub noise_variance: f64,
    /// Exponential kernel output variance σ²_exp (C4: 1).
    pub signal_variance: f64,
    /// Exponential kernel lengthscale l_exp (C4: 1 for Lab, 0.4 for histograms).
    pub lengthscale: f64,
    /// Relearning rate, Hz (C4: 0.03).
    pub learn_hz: f64,
    /// Minimum information gain I^thr_predict of a predictor goal, nat (C4: 0.26).
    pub entropy_threshold: f64,
    /// Histogram radius r_hist, m (C4: 0.15, half the bumper width).
    pub r_hist: f64,
    /// Lab a, b are divided by this.
    pub lab_scale: f64,
}

impl PredictorParams {
    /// The C4 indoor setting (Lab, l = 1).
    pub fn lab() -> Self {
        Self {
            descriptor: DescriptorKind::LabAb,
            noise_variance: 0.1,
            signal_variance: 1.0,
            lengthscale: 1.0,
            learn_hz: 0.03,
            entropy_threshold: 0.26,
            r_hist: 0.15,
            lab_scale: 128.0,
        }
    }

    /// The C4 outdoor setting (8-bin histogram, l = 0.4).
    pub fn histogram() -> Self {
        Self {
            descriptor: DescriptorKind::Histogram8,
            lengthscale: 0.4,
            ..Self::lab()
        }
    }

    fn gp(&self) -> GpParams {
        GpParams {
            kernel: Kernel {
                kind: KernelKind::Exponential,
                lengthscales: vec![self.lengthscale],
                signal_variance: self.signal_variance,
            },
            noise_variance: self.noise_variance,
            prior_mean: 0.0,
        }
    }
}

/// A force prediction N(μ_F, σ²_F) and its entropy.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct ForcePrediction {
    /// μ_F, N.
    pub mean: f64,
    /// σ²_F (latent), N².
    pub variance: f64,
    /// I_predict = ½ ln(2πe σ²_F), nat.
    pub entropy: f64,
}

/// The appearance descriptor A(ν) of a cell, `None` when the map cannot describe it.
pub fn describe(map: &ElevationMap, c: Cell, p: &PredictorParams) -> Option<Vec<f64>> {
    match p.descriptor {
        DescriptorKind::LabAb => {
            let lab = rgb_to_lab(map.color(c)?);
            let s = p.lab_scale.max(f64::MIN_POSITIVE);
            Some(vec![lab.a as f64 / s, lab.b as f64 / s])
        }
        DescriptorKind::Histogram8 => {
            c4_histogram(map, c, p.r_hist).map(|h| h.iter().map(|&v| v as f64).collect())
        }
    }
}

/// The predictor P: absent until first learned (C4 Alg. 2 line 2).
#[derive(Clone, Debug)]
pub struct ForcePredictor {
    params: PredictorParams,
    gp: Option<Gp>,
}

impl ForcePredictor {
    /// No predictor yet.
    pub fn new(params: PredictorParams) -> Self {
        Self { params, gp: None }
    }

    /// The parameters.
    pub fn params(&self) -> &PredictorParams {
        &self.params
    }

    /// Whether P has been learned (from at least one sample).
    pub fn is_learned(&self) -> bool {
        self.gp.as_ref().is_some_and(|g| !g.is_empty())
    }

    /// Training-set size.
    pub fn len(&self) -> usize {
        self.gp.as_ref().map_or(0, |g| g.len())
    }

    /// True when not learned.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// C4 Eq. 11: relearns P from (descriptor, force) pairs. Pairs with a descriptor of the
    /// wrong dimension or non-finite values are skipped; with no pair left P stays as it was.
    /// Returns the number of pairs used.
    pub fn learn(&mut self, samples: &[(Vec<f64>, f64)]) -> Result<usize, GpError> {
        let dim = self.params.descriptor.dim();
        let mut x = Vec::with_capacity(samples.len() * dim);
        let mut y = Vec::with_capacity(samples.len());
        for (d, f) in samples {
            if d.len() == dim && d.iter().all(|v| v.is_finite()) && f.is_finite() {
                x.extend_from_slice(d);
                y.push(*f);
            }
        }
        if y.is_empty() {
            return Ok(0);
        }
        self.gp = Some(Gp::fit(dim, self.params.gp(), &x, &y)?);
        Ok(y.len())
    }

    /// C4 Eq. 12–13 at descriptor `x`; `None` while P is not learned or for a bad descriptor.
    pub fn predict(&self, x: &[f64]) -> Option<ForcePrediction> {
        let gp = self.gp.as_ref()?;
        if x.len() != self.params.descriptor.dim() || !x.iter().all(|v| v.is_finite()) {
            return None;
        }
        let p = gp.predict(x);
        Some(ForcePrediction {
            mean: p.mean,
            variance: p.latent_variance,
            entropy: differential_entropy(p.latent_variance),
        })
    }

    /// Whether a prediction is certain: I_predict below the threshold.
    pub fn is_certain(&self, p: &ForcePrediction) -> bool {
        p.entropy < self.params.entropy_threshold
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn lab(rgb: [u8; 3]) -> Vec<f64> {
        let l = rgb_to_lab(strider_core::Rgb8::new(rgb[0], rgb[1], rgb[2]));
        vec![l.a as f64 / 128.0, l.b as f64 / 128.0]
    }

    #[test]
    fn unlearned_predictor_predicts_nothing() {
        let p = ForcePredictor::new(PredictorParams::lab());
        assert!(!p.is_learned());
        assert!(p.predict(&[0.0, 0.0]).is_none());
    }

    #[test]
    fn a_sampled_colour_becomes_certain_and_a_distant_one_stays_uncertain() {
        let mut p = ForcePredictor::new(PredictorParams::lab());
        let white = lab([240, 240, 240]);
        let purple = lab([170, 60, 170]);
        assert_eq!(p.learn(&[(white.clone(), 3.0)]).unwrap(), 1);
        let w = p.predict(&white).unwrap();
        assert!(p.is_certain(&w), "sampled terrain: {w:?}");
        assert!(w.mean > 2.0);
        let c = p.predict(&purple).unwrap();
        assert!(!p.is_certain(&c), "curtain after the wall only: {c:?}");
        // Curtain sampled too: both certain, on the right sides of F_trav.
        p.learn(&[(white.clone(), 3.0), (purple.clone(), 0.7)])
            .unwrap();
        let c = p.predict(&purple).unwrap();
        assert!(p.is_certain(&c) && c.mean < 2.0, "{c:?}");
    }

    #[test]
    fn bad_samples_are_skipped() {
        let mut p = ForcePredictor::new(PredictorParams::lab());
        assert_eq!(
            p.learn(&[(vec![f64::NAN, 0.0], 1.0), (vec![0.0], 1.0)])
                .unwrap(),
            0
        );
        assert!(!p.is_learned());
        assert_eq!(p.learn(&[(vec![0.0, 0.0], f64::NAN)]).unwrap(), 0);
        assert!(p.predict(&[0.0, f64::INFINITY]).is_none());
    }
}
