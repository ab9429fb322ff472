//! The inputs of Nardi19 Alg. 1: the grid map 𝓜 (where the robot may be) and the aerial image
//! 𝓘, and the gating features drawn from them.

use super::params::{ModelKind, NavigateError};
use strider_core::{Cell, CellRect, Point2, Rgb8};

/// The inputs of Alg. 1: the grid map 𝓜 and, for the aerial model, the aerial image 𝓘, both
/// row-major over one rectangle of the cell lattice.
#[derive(Clone, Debug)]
pub struct NavigationMap {
    pub(super) rect: CellRect,
    pub(super) cell_size: f64,
    pub(super) admissible: Vec<bool>,
    aerial: Option<Vec<Rgb8>>,
}

impl NavigationMap {
    /// Checks that the mask and the image (if any) hold one value per cell of `rect`.
    pub fn new(
        rect: CellRect,
        cell_size: f64,
        admissible: Vec<bool>,
        aerial: Option<Vec<Rgb8>>,
    ) -> Result<NavigationMap, NavigateError> {
        if !(cell_size.is_finite() && cell_size > 0.0) {
            return Err(NavigateError::BadInput(format!(
                "cell size {cell_size} is not a positive number"
            )));
        }
        if rect.is_empty() {
            return Err(NavigateError::BadInput("the grid map has no cells".into()));
        }
        if admissible.len() != rect.len() {
            return Err(NavigateError::BadInput(format!(
                "the grid map has {} cells but its rectangle {}×{} has {}",
                admissible.len(),
                rect.width,
                rect.height,
                rect.len()
            )));
        }
        if let Some(a) = &aerial
            && a.len() != rect.len()
        {
            return Err(NavigateError::BadInput(format!(
                "the aerial image has {} pixels but the grid map is {}×{} = {} cells",
                a.len(),
                rect.width,
                rect.height,
                rect.len()
            )));
        }
        Ok(NavigationMap {
            rect,
            cell_size,
            admissible,
            aerial,
        })
    }

    /// The rectangle of the grid.
    pub fn rect(&self) -> CellRect {
        self.rect
    }

    /// Cell size, metres.
    pub fn cell_size(&self) -> f64 {
        self.cell_size
    }

    /// Where the robot may be, row-major.
    pub fn admissible(&self) -> &[bool] {
        &self.admissible
    }

    /// The aerial image, row-major, if given.
    pub fn aerial(&self) -> Option<&[Rgb8]> {
        self.aerial.as_deref()
    }

    /// Row-major index of the cell containing `p`, if inside.
    pub fn index_of(&self, p: Point2) -> Option<usize> {
        Cell::containing(p.x, p.y, self.cell_size).and_then(|c| self.rect.index(c))
    }

    /// The gating features of every cell for `kind`, standardised per feature over the whole
    /// grid (mean 0, standard deviation 1; the image statistics, no labels), row-major, and
    /// the feature count: (x, y), or (x, y, r, g, b) for the aerial model.
    pub fn gate_features(&self, kind: ModelKind) -> Result<(Vec<f64>, usize), NavigateError> {
        let aerial = match kind {
            ModelKind::GpMixtureAerial => Some(self.aerial.as_deref().ok_or_else(|| {
                NavigateError::BadInput("the gp-mixture-aerial model needs an aerial image".into())
            })?),
            _ => None,
        };
        let dim = if aerial.is_some() { 5 } else { 2 };
        let n = self.rect.len();
        let mut f = vec![0.0; n * dim];
        for (k, row) in f.chunks_exact_mut(dim).enumerate() {
            let c = self.rect.cell(k).center(self.cell_size);
            row[0] = c.x;
            row[1] = c.y;
            if let Some(a) = aerial {
                for ch in 0..3 {
                    row[2 + ch] = a[k].0[ch] as f64 / 255.0;
                }
            }
        }
        for j in 0..dim {
            let mean = f.iter().skip(j).step_by(dim).sum::<f64>() / n as f64;
            let var = f
                .iter()
                .skip(j)
                .step_by(dim)
                .map(|v| (v - mean) * (v - mean))
                .sum::<f64>()
                / n as f64;
            // A constant feature (a one-colour image) carries nothing: leave it at 0.
            let inv = if var > 0.0 { 1.0 / var.sqrt() } else { 0.0 };
            for v in f.iter_mut().skip(j).step_by(dim) {
                *v = (*v - mean) * inv;
            }
        }
        Ok((f, dim))
    }
}
