//! Measured costs: the Kalman filter of a cell (Eq. 22) and the novelty test that decides whether
//! a measurement is stored (§4.3.2).

use strider_core::Cell;

use super::{CostModelError, GaitCostModel};
use crate::descriptor_field::DescriptorField;

/// The Kalman cost estimate of one cell (Eq. 22).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CellCost {
    /// c(ν).
    pub cost: f64,
    /// Its variance σ_k².
    pub variance: f64,
    /// Measurements fused.
    pub count: u32,
}

impl CellCost {
    /// A cell's first measurement `z`, with the initial variance σ_0².
    fn first(z: f64, sigma0_2: f64) -> Self {
        CellCost {
            cost: z,
            variance: sigma0_2,
            count: 1,
        }
    }

    /// Fuses a measurement `z` of variance σ_sense² into the estimate (Eq. 22).
    fn fuse(&mut self, z: f64, sigma_sense2: f64) {
        let sum = sigma_sense2 + self.variance;
        self.cost = (sigma_sense2 * self.cost + self.variance * z) / sum;
        self.variance = sigma_sense2 * self.variance / sum;
        self.count += 1;
    }
}

/// What [`GaitCostModel::insert_measurement`] did.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Insertion {
    /// The measurement was novel and updated the cell and its neighbours.
    Stored,
    /// The model already predicts it well and the cell's class is certain.
    NotNovel,
}

impl GaitCostModel {
    /// Alg. 5 line 3, `insertIfNovel`: fuses a cost measurement `z` experienced with this
    /// model's gait at cell `c` into `c` and its 8 neighbours (Eq. 22, decision 11) when it is
    /// novel; the learning set follows at the next [`update`](GaitCostModel::update). `desc`
    /// supplies ta(ν) for the novelty test. Non-finite costs are refused (error, counted,
    /// nothing stored).
    pub fn insert_measurement(
        &mut self,
        c: Cell,
        z: f64,
        desc: &DescriptorField,
    ) -> Result<Insertion, CostModelError> {
        if !z.is_finite() {
            self.rejected_costs += 1;
            return Err(CostModelError::NonFiniteCost {
                value: z,
                i: c.i,
                j: c.j,
            });
        }
        self.check_dim(desc)?;
        if !self.is_novel(c, z, desc) {
            return Ok(Insertion::NotNovel);
        }
        let (s2, s0) = (self.params.sigma_sense2, self.params.sigma0_2);
        for cell in std::iter::once(c).chain(c.neighbours8()) {
            match self.costs.get_mut(&cell) {
                Some(k) => k.fuse(z, s2),
                None => {
                    self.costs.insert(cell, CellCost::first(z, s0));
                    self.measured.push(cell);
                }
            }
        }
        // The learning set follows at the next update (Alg. 5 relearns the regressor at the
        // learning rate; the novelty test uses the latest learned one).
        Ok(Insertion::Stored)
    }

    /// Novelty (§4.3.2): no regressor yet, or outside the 2σ predictive interval, or the cell's
    /// class can still give information.
    ///
    /// The regressor changes only at updates, so its prediction at a cell is cached until the
    /// next update (keyed by the cell and checked against its descriptor): the robot measures
    /// the same cells many times at 20 Hz, and a prediction costs O(n²).
    fn is_novel(&mut self, c: Cell, z: f64, desc: &DescriptorField) -> bool {
        if !self.has_regressor() || self.cell_information_gain(c) > 0.0 {
            return true;
        }
        let Some(x) = desc.get(c) else {
            // Without a descriptor the prediction is unknown: keep the measurement, it joins
            // the learning set once the cell is described.
            return true;
        };
        let (mean, latent) = match self.novelty_cache.get(&c) {
            Some((xc, m, v)) if xc[..] == x[..] => (*m, *v),
            _ => {
                let alpha = match &self.alpha {
                    Some(a) => a,
                    None => self.alpha.insert(self.gp.alpha()),
                };
                let mean = self.gp.mean_with_alpha(alpha, x, &mut self.query_scratch);
                self.novelty_cache.insert(c, (x.to_vec(), mean, f64::NAN));
                (mean, f64::NAN)
            }
        };
        // The latent variance lies in [0, σ_f²]: outside the band those bounds leave open the
        // test is decided by the O(n·dim) mean alone, and only inside it is the O(n²)
        // variance computed (then cached too).
        let sn2 = self.params.gp.noise_variance;
        let deviation = (mean - z).abs();
        if deviation > 2.0 * (self.gp.params().kernel.prior_variance() + sn2).sqrt() {
            return true;
        }
        if deviation <= 2.0 * sn2.sqrt() {
            return false;
        }
        let latent = if latent.is_nan() {
            let v = self.gp.predict(x).latent_variance;
            self.novelty_cache.insert(c, (x.to_vec(), mean, v));
            v
        } else {
            latent
        };
        deviation > 2.0 * (latent.max(0.0) + sn2).sqrt()
    }
}
