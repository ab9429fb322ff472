//! A dense field of terrain descriptors over a rectangle of the map lattice.
//!
//! The learners are generic over the descriptor: the 9-bin colour histogram ta(ν) of Prágr22
//! §4.2, the 5-D shape + Lab descriptor of Prágr19 Eq. 10, or anything else with a fixed
//! dimension. The map crate computes them as `Raster<Option<[f32; N]>>`; this type flattens them
//! into one `f64` buffer (what the GP works on) and a "described" mask, and refuses non-finite
//! values so nothing downstream ever sees a NaN.

use strider_core::{Cell, CellRect};
use strider_map::descriptors::Raster;

/// Descriptors over `rect`: `dim` values per cell, row-major like [`CellRect::index`].
#[derive(Clone, Debug, PartialEq)]
pub struct DescriptorField {
    rect: CellRect,
    dim: usize,
    values: Vec<f64>,
    described: Vec<bool>,
    rejected: usize,
}

impl DescriptorField {
    /// An empty field (no cell described) of dimension `dim` over `rect`.
    pub fn empty(rect: CellRect, dim: usize) -> Self {
        Self {
            rect,
            dim,
            values: vec![0.0; rect.len() * dim],
            described: vec![false; rect.len()],
            rejected: 0,
        }
    }

    /// Flattens a map-crate descriptor raster. Descriptors with a non-finite component are
    /// treated as absent and counted in [`DescriptorField::rejected`].
    pub fn from_raster<const N: usize>(r: &Raster<Option<[f32; N]>>) -> Self {
        let mut f = Self::empty(r.rect, N);
        for (k, v) in r.values.iter().enumerate() {
            if let Some(d) = v {
                let row: [f64; N] = d.map(f64::from);
                f.set_index(k, &row);
            }
        }
        f
    }

    /// Sets the descriptor of the `k`-th cell of the rectangle; a non-finite one is rejected,
    /// counted, and leaves the cell undescribed.
    fn set_index(&mut self, k: usize, d: &[f64]) {
        if d.len() != self.dim || d.iter().any(|x| !x.is_finite()) {
            self.rejected += 1;
            self.described[k] = false;
            return;
        }
        self.values[k * self.dim..(k + 1) * self.dim].copy_from_slice(d);
        self.described[k] = true;
    }

    /// Sets the descriptor of cell `c`. Returns `false` (and counts a rejection) when `c` is
    /// outside the rectangle, `d` has the wrong length or a non-finite component.
    pub fn set(&mut self, c: Cell, d: &[f64]) -> bool {
        match self.rect.index(c) {
            Some(k) => {
                self.set_index(k, d);
                self.described[k]
            }
            None => {
                self.rejected += 1;
                false
            }
        }
    }

    /// The rectangle covered.
    pub fn rect(&self) -> CellRect {
        self.rect
    }

    /// Descriptor dimension.
    pub fn dim(&self) -> usize {
        self.dim
    }

    /// The descriptor of `c`, `None` when outside the rectangle or not described.
    pub fn get(&self, c: Cell) -> Option<&[f64]> {
        let k = self.rect.index(c)?;
        self.get_index(k)
    }

    /// The descriptor of the `k`-th cell of the rectangle, if described.
    pub fn get_index(&self, k: usize) -> Option<&[f64]> {
        if self.described[k] {
            Some(&self.values[k * self.dim..(k + 1) * self.dim])
        } else {
            None
        }
    }

    /// Number of described cells.
    pub fn described_count(&self) -> usize {
        self.described.iter().filter(|&&d| d).count()
    }

    /// Descriptors refused because of a non-finite component, wrong length or position.
    pub fn rejected(&self) -> usize {
        self.rejected
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn from_raster_skips_absent_and_non_finite() {
        let rect = CellRect::new(Cell::new(-1, -1), 2, 2);
        let r = Raster {
            rect,
            values: vec![
                Some([1.0, 2.0]),
                None,
                Some([f32::NAN, 0.0]),
                Some([0.5, 0.5]),
            ],
        };
        let f = DescriptorField::from_raster(&r);
        assert_eq!(f.dim(), 2);
        assert_eq!(f.get(Cell::new(-1, -1)), Some(&[1.0, 2.0][..]));
        assert_eq!(f.get(Cell::new(0, -1)), None);
        assert_eq!(f.get(Cell::new(-1, 0)), None);
        assert_eq!(f.get(Cell::new(0, 0)), Some(&[0.5, 0.5][..]));
        assert_eq!(f.described_count(), 2);
        assert_eq!(f.rejected(), 1);
        assert_eq!(f.get(Cell::new(5, 5)), None);
    }
}
