//! Learning from the roll: each roll-variance window spent walking becomes, once per sample
//! period, a (descriptor, cost) pair of the committee's newest expert.

use super::RbcmGreedy;
use super::log::CostRecord;
use crate::kernel::Body;
use crate::timing::ms_since;
use std::time::Instant;
use strider_core::Proprioception;
use strider_map::descriptors::shape_lab_descriptor;

impl RbcmGreedy {
    /// A proprioceptive reading into the roll signal; a finished window spent walking is
    /// paired with its cell's descriptor and learned, one pair per sample period.
    pub(super) fn feel_roll(&mut self, body: &Body, p: &Proprioception) {
        let Some(s) = self.roll.push(p) else { return };
        // Only windows spent walking, one pair per sample period.
        let window_start = p.stamp - self.params.window_s;
        if !self.walking_since.is_some_and(|w| w <= window_start)
            || p.stamp - self.last_sample_t < self.params.sample_period_s
            || !s.cost.is_finite()
        {
            return;
        }
        self.last_sample_t = p.stamp;
        let map = body.map();
        let desc = map
            .cell_at(s.position.x, s.position.y)
            .and_then(|c| shape_lab_descriptor(map, c, self.params.delta_desc));
        let Some(d) = desc else {
            self.log.undescribed_samples += 1;
            return;
        };
        let x = d.map(f64::from);
        self.learn(&x, s.cost);
        self.log.samples.push(CostRecord {
            t: s.stamp,
            x: s.position.x,
            y: s.position.y,
            cost: s.cost,
        });
    }

    /// Stores a (descriptor, cost) pair in the committee.
    fn learn(&mut self, x: &[f64; 5], cost: f64) {
        let w = Instant::now();
        let ok = match &self.params.fit {
            Some(bounds) => self.rbcm.push_fitted(x, cost, bounds),
            None => self.rbcm.push(x, cost),
        };
        self.log.learning_ms.push(ms_since(w));
        if ok.is_ok() {
            self.min_cost = self.min_cost.min(cost);
        }
    }
}
