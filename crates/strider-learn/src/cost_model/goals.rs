//! Goals of one gait's cost model (Alg. 9): sampling sites on a lattice of spacing d_S, one goal
//! per informative class, and the bootstrap goal of decision 16 before the regressor exists.

use strider_core::{Cell, CellRect, Point2};

use super::classes::ClassInfo;
use super::{GaitCostModel, ModelUpdate};
use crate::descriptor_field::DescriptorField;
use crate::gp::differential_entropy;
use crate::igng::ClassId;
use crate::morphology::TerrainCell;

/// A cost-model goal γ_C(T): sampling sites of one terrain class (Alg. 9).
#[derive(Clone, Debug, PartialEq)]
pub struct CostGoal {
    /// The class to sample; `None` for the bootstrap goal of decision 16.
    pub class: Option<ClassId>,
    /// I_C of the class (for the bootstrap goal: the prior's entropy).
    pub information_gain: f64,
    /// Sampling sites, in lattice order.
    pub sites: Vec<Cell>,
}

impl GaitCostModel {
    /// Decision 16: before the regressor exists every described cell is one eroded class, and
    /// one bootstrap goal holds the lattice sites over admissible cells with no measured cost.
    pub(super) fn bootstrap_update(
        &mut self,
        desc: &DescriptorField,
        admissible: &[bool],
    ) -> ModelUpdate {
        for k in 0..self.rect.len() {
            if desc.get_index(k).is_some() {
                self.learn_class[k] = TerrainCell::Eroded;
                self.plan_class[k] = TerrainCell::Eroded;
            }
        }
        let sites = lattice_sites(desc.rect(), self.cell_size, self.params.d_s, |k| {
            admissible[k] && !self.costs.contains_key(&self.rect.cell(k))
        });
        let goals = if sites.is_empty() {
            Vec::new()
        } else {
            vec![CostGoal {
                class: None,
                information_gain: differential_entropy(self.params.gp.kernel.prior_variance()),
                sites,
            }]
        };
        ModelUpdate {
            goals,
            ..ModelUpdate::default()
        }
    }

    /// Alg. 9 lines 3–9: the lattice sites over admissible unmeasured cells of informative
    /// classes, grouped into one goal per informative class; the informative classes left
    /// without a site are returned to be pruned.
    pub(super) fn class_goals(
        &self,
        desc: &DescriptorField,
        admissible: &[bool],
        classes: &[ClassInfo],
    ) -> (Vec<CostGoal>, Vec<ClassId>) {
        let sites = lattice_sites(desc.rect(), self.cell_size, self.params.d_s, |k| {
            admissible[k]
                && !self.costs.contains_key(&self.rect.cell(k))
                && match self.learn_class[k] {
                    TerrainCell::Class(t) => self.class_gain.get(&t).copied().unwrap_or(0.0) > 0.0,
                    _ => false,
                }
        });
        let mut goals: Vec<CostGoal> = Vec::new();
        for c in classes {
            if c.information_gain > 0.0 {
                goals.push(CostGoal {
                    class: Some(c.id),
                    information_gain: c.information_gain,
                    sites: Vec::new(),
                });
            }
        }
        for s in sites {
            if let Some(TerrainCell::Class(t)) = self.rect.index(s).map(|k| self.learn_class[k])
                && let Some(g) = goals.iter_mut().find(|g| g.class == Some(t))
            {
                g.sites.push(s);
            }
        }
        let mut pruned = Vec::new();
        goals.retain(|g| {
            if g.sites.is_empty() {
                pruned.extend(g.class);
                false
            } else {
                true
            }
        });
        (goals, pruned)
    }
}

/// Alg. 9 lines 4–7: for each point p_S of the global lattice of spacing d_S inside the
/// rectangle `rect` of cells of size `d`, the closest cell within √2/2·d_S of p_S whose
/// row-major index satisfies `ok`.
/// Lattice order (rows, then columns); ties go to the lower row-major index.
fn lattice_sites(rect: CellRect, d: f64, ds: f64, ok: impl Fn(usize) -> bool) -> Vec<Cell> {
    if rect.is_empty() {
        return Vec::new();
    }
    let r = std::f64::consts::FRAC_1_SQRT_2 * ds;
    let lo = rect.min.center(d);
    let hi = Cell::new(
        rect.min.i + rect.width as i32 - 1,
        rect.min.j + rect.height as i32 - 1,
    )
    .center(d);
    let (a0, a1) = ((lo.x / ds).ceil() as i64, (hi.x / ds).floor() as i64);
    let (b0, b1) = ((lo.y / ds).ceil() as i64, (hi.y / ds).floor() as i64);
    let reach = (r / d).ceil() as i32 + 1;
    let mut out = Vec::new();
    for b in b0..=b1 {
        for a in a0..=a1 {
            let p = Point2::new(a as f64 * ds, b as f64 * ds);
            let Some(pc) = Cell::containing(p.x, p.y, d) else {
                continue;
            };
            let mut best: Option<(f64, usize)> = None;
            for dj in -reach..=reach {
                for di in -reach..=reach {
                    let c = Cell::new(pc.i + di, pc.j + dj);
                    let Some(k) = rect.index(c) else { continue };
                    let cc = c.center(d);
                    let dist = ((cc.x - p.x).powi(2) + (cc.y - p.y).powi(2)).sqrt();
                    if dist >= r || !ok(k) {
                        continue;
                    }
                    if best.is_none_or(|(bd, bk)| dist < bd || (dist == bd && k < bk)) {
                        best = Some((dist, k));
                    }
                }
            }
            if let Some((_, k)) = best {
                let c = rect.cell(k);
                if out.last() != Some(&c) {
                    out.push(c);
                }
            }
        }
    }
    out
}
