//! The judge of the comparison: each learned model's error against the terrain table of the
//! simulator's world, in the model's own quantity.

use strider_core::snapshot::{Quantity, Snapshot};
use strider_core::{Cell, GaitId};
use strider_learn::signals::tanh_bound;
use strider_scenario::Scenario;

use super::ModelError;

/// The RMSE of each model layer of `snap` against the terrain table (module docs).
pub fn cost_errors(sc: &Scenario, snap: &Snapshot) -> Vec<ModelError> {
    let Some(layers) = &snap.layers else {
        return Vec::new();
    };
    let w = &sc.world;
    let admissible = w.gt_admissible(sc.map.rho_obstacle, sc.map.r_robot);
    let d = snap.cell_size;
    layers
        .models
        .iter()
        .map(|m| {
            let (mut sum, mut n) = (0.0, 0usize);
            for (k, c) in layers.rect.cells().enumerate() {
                let learned = m.cost[k] as f64;
                if !(layers.observed[k] && learned.is_finite()) {
                    continue;
                }
                let Some(truth) = truth_at(sc, &admissible, c, d, m.quantity, m.gait) else {
                    continue;
                };
                sum += (learned - truth).powi(2);
                n += 1;
            }
            ModelError {
                model: m.name.clone(),
                quantity: m.quantity,
                rmse: if n > 0 {
                    (sum / n as f64).sqrt()
                } else {
                    f64::NAN
                },
                cells: n,
            }
        })
        .collect()
}

/// The terrain table's value of `quantity` at map cell `c` for `gait`; `None` where the world
/// has no such cell, it is not traversable in truth (push force: not pushable), or the
/// quantity needs a gait the model does not name.
fn truth_at(
    sc: &Scenario,
    admissible: &[bool],
    c: Cell,
    cell_size: f64,
    quantity: Quantity,
    gait: Option<GaitId>,
) -> Option<f64> {
    let w = &sc.world;
    let k = w.index_at(c.center(cell_size))?;
    let terrain = w.terrain_type(w.terrain[k])?;
    let response = |g: GaitId| {
        let name = &sc.robot.gaits.get(g.0 as usize)?.name;
        Some((
            terrain.gaits.get(name).cloned().unwrap_or_default(),
            sc.robot.gaits[g.0 as usize].max_speed,
        ))
    };
    match quantity {
        Quantity::PushForce => terrain.push_force_n,
        Quantity::RollVariance => {
            let (r, _) = response(gait?)?;
            admissible[k].then_some(r.roll_variance)
        }
        Quantity::InverseVelocity { v_max, c_high } => {
            let (r, top) = response(gait?)?;
            // On stuck terrain the simulator's nominal speed is its stuck fraction of the gait's.
            let factor = if r.stuck {
                strider_sim::MotionParams::default().stuck_speed_fraction
            } else {
                r.speed_factor
            };
            let v = factor * top;
            admissible[k].then(|| tanh_bound(v_max / v, c_high))
        }
    }
}
