//! Prágr23 (thesis C4) §4.2: the haptic model, and the cell traversability fusion of C4 Eq. 4.
//!
//! * [`BumperFilter`]: the bumper stream is cleaned before fusion. Non-finite and negative
//!   readings are dropped, readings are clamped to `f_max`, and the median of the last `window`
//!   valid readings is what gets fused. C4 §5.1 samples each obstacle for 2 s "to ensure that the
//!   observed value is not an outlier caused by bumper motion"; a running median is how we honour
//!   that per reading: an isolated spike (fewer than half of the window) cannot move it outside
//!   the range of the good readings around it.
//! * [`HapticModel`]: per-cell 1-D Kalman fusion of the force to pass through, C4 Eq. 9:
//!   F_k = (σ²_sensor F_{k−1} + σ²_{k−1} z_k) / (σ²_sensor + σ²_{k−1}),
//!   σ²_k = σ²_sensor σ²_{k−1} / (σ²_sensor + σ²_{k−1}), F_0 = the first measurement,
//!   σ²_0 = 1 (the first measurement is F_0 itself; the update starts at the second).
//!   p_haptic(ν) = [F(ν) ≤ F_trav] (C4 Eq. 2).
//! * [`fuse_traversability`]: C4 Eq. 4, p(ν) = p_haptic(ν) when known, else p_geom(ν) = 1 for
//!   geometrically traversable cells, else p_predict(ν) for apparent obstacles, and 1 for
//!   unobserved cells.

use std::collections::{HashMap, VecDeque};
use strider_core::Cell;

/// Parameters of the haptic model (C4 Table 3).
#[derive(Clone, Debug, PartialEq)]
pub struct HapticParams {
    /// Bumper measurement variance σ²_sensor of the Kalman fuser, N² (C4: 0.01).
    pub sigma_sensor2: f64,
    /// Initial filter variance σ²_0, N² (C4: 1).
    pub sigma0_2: f64,
    /// The robot's maximum force to push through an obstacle F_trav, N (C4: 2 N).
    pub f_trav: f64,
    /// Readings at or below this are "no contact" and not fused, N: a bumper at rest reads
    /// about zero, which says nothing about what lies ahead.
    pub f_contact: f64,
    /// Readings are clamped to this before fusion, N (the bumper's useful range).
    pub f_max: f64,
    /// Length of the running median over valid readings.
    pub median_window: usize,
}

impl Default for HapticParams {
    fn default() -> Self {
        Self {
            sigma_sensor2: 0.01,
            sigma0_2: 1.0,
            f_trav: 2.0,
            f_contact: 0.2,
            f_max: 10.0,
            median_window: 5,
        }
    }
}

/// Running median of the valid bumper readings (see the module docs).
#[derive(Clone, Debug, Default)]
pub struct BumperFilter {
    window: VecDeque<f64>,
    scratch: Vec<f64>,
}

impl BumperFilter {
    /// Forgets the readings (a new contact starts).
    pub fn reset(&mut self) {
        self.window.clear();
    }

    /// Takes one reading; returns the filtered value to fuse, or `None` when the reading is
    /// invalid (NaN, ±∞, negative) or shows no contact, or the window is not yet half full.
    pub fn push(&mut self, reading: f64, p: &HapticParams) -> Option<f64> {
        if !reading.is_finite() || reading < 0.0 {
            return None;
        }
        if reading <= p.f_contact {
            // Contact lost: the next contact starts a fresh window.
            self.window.clear();
            return None;
        }
        let n = p.median_window.max(1);
        self.window.push_back(reading.min(p.f_max));
        while self.window.len() > n {
            self.window.pop_front();
        }
        if self.window.len() < n.div_ceil(2) {
            return None;
        }
        self.scratch.clear();
        self.scratch.extend(self.window.iter().copied());
        self.scratch.sort_by(f64::total_cmp);
        Some(self.scratch[self.scratch.len() / 2])
    }
}

/// The fused force estimate of one cell.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct HapticCell {
    /// F_k, N.
    pub force: f64,
    /// σ²_k, N².
    pub variance: f64,
    /// Measurements fused, k.
    pub count: u32,
}

/// Per-cell Kalman fusion of the force to pass through (C4 Eq. 9).
#[derive(Clone, Debug, Default)]
pub struct HapticModel {
    params: HapticParams,
    cells: HashMap<Cell, HapticCell>,
    measurements: u64,
}

impl HapticModel {
    /// An empty model.
    pub fn new(params: HapticParams) -> Self {
        Self {
            params,
            cells: HashMap::new(),
            measurements: 0,
        }
    }

    /// The parameters.
    pub fn params(&self) -> &HapticParams {
        &self.params
    }

    /// Fuses the measurement `z` (N) into `cell`. Non-finite or negative values are ignored;
    /// values above `f_max` are clamped. Returns whether it was fused.
    pub fn fuse(&mut self, cell: Cell, z: f64) -> bool {
        if !z.is_finite() || z < 0.0 {
            return false;
        }
        let z = z.min(self.params.f_max);
        let s2 = self.params.sigma_sensor2;
        self.measurements += 1;
        match self.cells.get_mut(&cell) {
            None => {
                self.cells.insert(
                    cell,
                    HapticCell {
                        force: z,
                        variance: self.params.sigma0_2,
                        count: 1,
                    },
                );
            }
            Some(c) => {
                let d = s2 + c.variance;
                c.force = (s2 * c.force + c.variance * z) / d;
                c.variance = s2 * c.variance / d;
                c.count += 1;
            }
        }
        true
    }

    /// The estimate of `cell`, `None` when the bumper never touched it.
    pub fn get(&self, cell: Cell) -> Option<&HapticCell> {
        self.cells.get(&cell)
    }

    /// p_haptic(ν): `Some(F ≤ F_trav)` when the cell has a measurement.
    pub fn traversable(&self, cell: Cell) -> Option<bool> {
        self.get(cell).map(|c| c.force <= self.params.f_trav)
    }

    /// Cells with a measurement, in a fixed (sorted) order.
    pub fn cells(&self) -> Vec<(Cell, HapticCell)> {
        let mut v: Vec<(Cell, HapticCell)> = self.cells.iter().map(|(&c, &h)| (c, h)).collect();
        v.sort_by_key(|&(c, _)| (c.j, c.i));
        v
    }

    /// Number of cells with a measurement.
    pub fn len(&self) -> usize {
        self.cells.len()
    }

    /// True when no cell has a measurement.
    pub fn is_empty(&self) -> bool {
        self.cells.is_empty()
    }

    /// Measurements fused so far (over all cells).
    pub fn measurements(&self) -> u64 {
        self.measurements
    }
}

/// The geometric view of a cell (C4 Eq. 5) that Eq. 4 starts from.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Geometry {
    /// Not observed (or no known neighbour to judge a step against).
    Unobserved,
    /// p_geom = 1.
    Traversable,
    /// p_geom = 0: an apparent obstacle.
    Obstacle,
}

/// C4 Eq. 4: the reported traversability of a cell from its haptic ground truth (if any), its
/// geometry, and the predictor's verdict (`None` while no predictor exists: apparent obstacles
/// are then untraversable, C4 §4.3).
pub fn fuse_traversability(
    haptic: Option<bool>,
    geometry: Geometry,
    predicted: Option<bool>,
) -> bool {
    match (haptic, geometry) {
        (Some(h), _) => h,
        (None, Geometry::Traversable) => true,
        (None, Geometry::Obstacle) => predicted.unwrap_or(false),
        (None, Geometry::Unobserved) => true,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    #[test]
    fn kalman_follows_eq9() {
        let mut m = HapticModel::new(HapticParams::default());
        let c = Cell::new(3, 4);
        assert!(m.fuse(c, 1.0));
        assert_eq!(m.get(c).unwrap().force, 1.0);
        assert_eq!(m.get(c).unwrap().variance, 1.0);
        assert!(m.fuse(c, 2.0));
        let h = *m.get(c).unwrap();
        // (0.01·1 + 1·2) / 1.01 and 0.01·1 / 1.01.
        assert!((h.force - 2.01 / 1.01).abs() < 1e-12);
        assert!((h.variance - 0.01 / 1.01).abs() < 1e-12);
        assert_eq!(m.traversable(c), Some(true));
        assert_eq!(m.traversable(Cell::new(0, 0)), None);
        assert!(m.fuse(c, 50.0));
        assert!(m.get(c).unwrap().force <= 10.0, "clamped to f_max");
        assert_eq!(m.traversable(c), Some(false));
    }

    #[test]
    fn invalid_measurements_are_not_fused() {
        let mut m = HapticModel::new(HapticParams::default());
        let c = Cell::new(0, 0);
        for z in [f64::NAN, f64::INFINITY, f64::NEG_INFINITY, -1.0] {
            assert!(!m.fuse(c, z));
        }
        assert!(m.is_empty());
        assert_eq!(m.measurements(), 0);
    }

    #[test]
    fn eq4_precedence() {
        use Geometry::*;
        // Haptic overrides everything.
        assert!(!fuse_traversability(Some(false), Traversable, Some(true)));
        assert!(fuse_traversability(Some(true), Obstacle, Some(false)));
        // Geometry overrides the prediction.
        assert!(fuse_traversability(None, Traversable, Some(false)));
        // The prediction decides apparent obstacles; without a predictor they are obstacles.
        assert!(fuse_traversability(None, Obstacle, Some(true)));
        assert!(!fuse_traversability(None, Obstacle, Some(false)));
        assert!(!fuse_traversability(None, Obstacle, None));
        // Unobserved cells are traversable.
        assert!(fuse_traversability(None, Unobserved, None));
    }

    #[test]
    fn filter_waits_for_half_a_window_and_resets_on_release() {
        let p = HapticParams::default();
        let mut f = BumperFilter::default();
        assert_eq!(f.push(1.0, &p), None);
        assert_eq!(f.push(1.0, &p), None);
        assert_eq!(f.push(1.0, &p), Some(1.0));
        assert_eq!(f.push(0.0, &p), None, "released");
        assert_eq!(f.push(3.0, &p), None, "fresh window");
    }

    /// A reading sequence: the true force `f` in [lo, hi] with noise, NaNs anywhere and at most
    /// one spike in any `window` consecutive valid readings.
    fn stream() -> impl Strategy<Value = (f64, Vec<(f64, u8)>)> {
        (
            0.3f64..6.0,
            prop::collection::vec((-0.05f64..0.05, 0u8..10), 10..80),
        )
    }

    proptest! {
        /// Bounded influence: NaN readings are ignored and isolated spikes never reach the
        /// estimate, which stays within the range of the good readings.
        #[test]
        fn spikes_and_nans_do_not_corrupt_the_estimate(
            (f, noise) in stream(),
            spike in prop_oneof![Just(1e6f64), Just(100.0), Just(f64::INFINITY), 0.0f64..1e3],
        ) {
            let p = HapticParams::default();
            let mut filt = BumperFilter::default();
            let mut m = HapticModel::new(p.clone());
            let c = Cell::new(1, 1);
            let mut since_spike = p.median_window;
            let (mut lo, mut hi) = (f64::INFINITY, f64::NEG_INFINITY);
            for (e, kind) in noise {
                let good = f * (1.0 + e);
                let reading = match kind {
                    0 => f64::NAN,
                    1 if since_spike >= p.median_window => {
                        since_spike = 0;
                        spike
                    }
                    _ => {
                        since_spike += 1;
                        lo = lo.min(good);
                        hi = hi.max(good);
                        good
                    }
                };
                if let Some(z) = filt.push(reading, &p) {
                    m.fuse(c, z);
                }
            }
            if let Some(h) = m.get(c) {
                prop_assert!(h.force.is_finite());
                prop_assert!(h.force >= lo - 1e-9 && h.force <= hi + 1e-9,
                    "estimate {} outside the good readings [{lo}, {hi}]", h.force);
                prop_assert!(h.variance > 0.0 && h.variance <= p.sigma0_2);
            }
        }
    }
}
