//! The learnt map of motive energy per metre: samples binned into square cells, and the
//! zero-mean GP of MartinCorke Eq. 1 on the bins.
//!
//! Binning (MartinCorke §3.1, after Plonski et al.) bounds the GP by the number of bins rather than
//! the run time: a bin holds the mean of every sample attributed to it over all tours so far.
//! The GP is fitted to (bin centre, bin mean) with the squared exponential kernel of Eq. 1 and
//! a zero prior mean (decision 12: unseen ground is assumed free to drive on, which draws the
//! robot into exploring it); σ_f², l and the noise variance are refitted after every tour by
//! type-II maximum likelihood within [`EnergyTourParams::hyper_bounds`], warm-started from the
//! previous fit (deterministic: one start, a fixed bin order).

use std::collections::BTreeMap;

use serde::Serialize;
use strider_core::{Cell, CellRect, Point2};
use strider_learn::gp::{Gp, GpParams, HyperBounds, fit_hyperparameters};

use super::{EnergyTourParams, TourError};

/// One bin of the learning set.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct BinValue {
    /// Bin centre.
    pub centre: Point2,
    /// Mean motive energy per metre of its samples, J/m.
    pub mean_j_per_m: f64,
    /// Number of samples.
    pub count: usize,
}

/// The model's view of the planning area at one moment.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct EnergyMap {
    /// The planning cells.
    pub rect: CellRect,
    /// Cell size, metres.
    pub cell_size: f64,
    /// GP mean of the motive energy per metre at each cell centre, J/m (row-major).
    pub mean: Vec<f32>,
    /// GP latent variance there, (J/m)².
    pub variance: Vec<f32>,
    /// The bins the GP was fitted to.
    pub bins: Vec<BinValue>,
}

/// The result of one refit.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct FitSummary {
    /// Bins in the learning set.
    pub bins: usize,
    /// Samples binned so far.
    pub samples: usize,
    /// Fitted lengthscale l, metres.
    pub lengthscale: f64,
    /// Fitted signal variance σ_f², (J/m)².
    pub signal_variance: f64,
    /// Fitted noise variance σ_n², (J/m)².
    pub noise_variance: f64,
    /// Log marginal likelihood at the fit (`None` before any sample: nothing was fitted).
    pub log_marginal_likelihood: Option<f64>,
}

/// Binned samples and the GP fitted to them.
#[derive(Clone, Debug)]
pub struct EnergyModel {
    bin_size: f64,
    bins: BTreeMap<Cell, (f64, usize)>,
    samples: usize,
    params: GpParams,
    bounds: HyperBounds,
    fitted: bool,
    gp: Option<Gp>,
}

impl EnergyModel {
    /// An empty model: it predicts the zero prior mean everywhere.
    pub fn new(params: &EnergyTourParams) -> Self {
        Self {
            bin_size: params.bin_size_m,
            bins: BTreeMap::new(),
            samples: 0,
            params: params.initial_gp(),
            bounds: params.hyper_bounds.clone(),
            fitted: false,
            gp: None,
        }
    }

    /// Bins samples (position, motive energy per metre); non-finite ones are skipped.
    pub fn add_samples(&mut self, samples: &[(Point2, f64)]) {
        for &(p, e) in samples {
            if !e.is_finite() {
                continue;
            }
            let Some(c) = Cell::containing(p.x, p.y, self.bin_size) else {
                continue;
            };
            let b = self.bins.entry(c).or_insert((0.0, 0));
            b.0 += e;
            b.1 += 1;
            self.samples += 1;
        }
    }

    /// The bins, in a fixed order.
    pub fn bins(&self) -> Vec<BinValue> {
        self.bins
            .iter()
            .map(|(c, &(sum, n))| BinValue {
                centre: c.center(self.bin_size),
                mean_j_per_m: sum / n as f64,
                count: n,
            })
            .collect()
    }

    /// Refits the hyperparameters and the GP to the current bins.
    pub fn refit(&mut self) -> Result<FitSummary, TourError> {
        let bins = self.bins();
        if bins.is_empty() {
            return Ok(self.summary(0, None));
        }
        let x: Vec<f64> = bins.iter().flat_map(|b| [b.centre.x, b.centre.y]).collect();
        let y: Vec<f64> = bins.iter().map(|b| b.mean_j_per_m).collect();
        let mut init = self.params.clone();
        if !self.fitted {
            // First fit: signal variance at the data's second moment about the zero mean, noise
            // a hundredth of it, both inside the bounds.
            let m2 = y.iter().map(|v| v * v).sum::<f64>() / y.len() as f64;
            let clamp = |v: f64, (lo, hi): (f64, f64)| v.clamp(lo, hi);
            init.kernel.signal_variance = clamp(m2, self.bounds.signal_variance);
            init.noise_variance = clamp(0.01 * m2, self.bounds.noise_variance);
        }
        for l in &mut init.kernel.lengthscales {
            *l = l.clamp(self.bounds.lengthscale.0, self.bounds.lengthscale.1);
        }
        let fitted = fit_hyperparameters(2, &x, &y, init, &self.bounds)?;
        let gp = Gp::fit(2, fitted.clone(), &x, &y)?;
        let lml = gp.log_marginal_likelihood();
        self.params = fitted;
        self.fitted = true;
        self.gp = Some(gp);
        Ok(self.summary(bins.len(), Some(lml)))
    }

    fn summary(&self, bins: usize, lml: Option<f64>) -> FitSummary {
        FitSummary {
            bins,
            samples: self.samples,
            lengthscale: self.params.kernel.lengthscales[0],
            signal_variance: self.params.kernel.signal_variance,
            noise_variance: self.params.noise_variance,
            log_marginal_likelihood: lml,
        }
    }

    /// The GP mean and latent variance at the centres of `rect`'s cells (the prior before the
    /// first fit: zero mean, the initial signal variance).
    pub fn map(&self, rect: CellRect, cell_size: f64) -> Result<EnergyMap, TourError> {
        let n = rect.len();
        let (mut mean, mut var) = (vec![0.0; n], vec![self.params.kernel.signal_variance; n]);
        if let Some(gp) = &self.gp {
            let xs: Vec<f64> = rect
                .cells()
                .flat_map(|c| {
                    let p = c.center(cell_size);
                    [p.x, p.y]
                })
                .collect();
            gp.predict_batch(&xs, &mut mean, &mut var)?;
        }
        Ok(EnergyMap {
            rect,
            cell_size,
            mean: mean.into_iter().map(|v| v as f32).collect(),
            variance: var.into_iter().map(|v| v as f32).collect(),
            bins: self.bins(),
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn params() -> EnergyTourParams {
        crate::energy_tours::test_params(vec![Point2::new(0.2, 0.2), Point2::new(1.0, 0.2)])
    }

    #[test]
    fn bins_average_their_samples() {
        let mut m = EnergyModel::new(&params());
        m.add_samples(&[
            (Point2::new(0.01, 0.01), 4.0),
            (Point2::new(0.09, 0.02), 6.0),
            (Point2::new(0.15, 0.05), 10.0),
            (Point2::new(0.15, 0.05), f64::NAN),
        ]);
        let b = m.bins();
        assert_eq!(b.len(), 2);
        assert_eq!((b[0].mean_j_per_m, b[0].count), (5.0, 2));
        assert_eq!((b[1].mean_j_per_m, b[1].count), (10.0, 1));
        assert_eq!(m.samples, 3);
    }

    /// Before any data the map is the zero prior; after a fit on a cheap left half and a dear
    /// right half the mean follows the data, and far from the data it falls back towards zero.
    #[test]
    fn fit_follows_the_data_and_reverts_to_zero_far_away() {
        let p = params();
        let mut m = EnergyModel::new(&p);
        let rect = CellRect::new(Cell::new(0, 0), 40, 20);
        let empty = m.map(rect, 0.05).unwrap();
        assert!(empty.mean.iter().all(|&v| v == 0.0));
        let none = m.refit().unwrap();
        assert_eq!((none.bins, none.log_marginal_likelihood), (0, None));
        let mut s = Vec::new();
        for k in 0..20 {
            let x = 0.05 + 0.05 * k as f64;
            let e = if x < 0.5 { 6.0 } else { 12.0 };
            s.push((Point2::new(x, 0.1), e));
            s.push((Point2::new(x, 0.12), e + 0.1));
        }
        m.add_samples(&s);
        let fit = m.refit().unwrap();
        assert!(fit.bins >= 10);
        assert!(fit.log_marginal_likelihood.is_some_and(f64::is_finite));
        let (lo, hi) = p.hyper_bounds.lengthscale;
        assert!(fit.lengthscale >= lo && fit.lengthscale <= hi);
        let map = m.map(rect, 0.05).unwrap();
        let at = |x: f64, y: f64| {
            map.mean[rect
                .index(Cell::new((x / 0.05) as i32, (y / 0.05) as i32))
                .unwrap()]
        };
        assert!((at(0.2, 0.1) - 6.0).abs() < 1.0, "{}", at(0.2, 0.1));
        assert!((at(0.8, 0.1) - 12.0).abs() < 1.5, "{}", at(0.8, 0.1));
        assert!(at(1.9, 0.95).abs() < 1.0, "{}", at(1.9, 0.95));
    }
}
