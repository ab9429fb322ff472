//! Prágr23 §5.3 (Table 5): the force predictor on outdoor terrains with the 8-bin histogram
//! descriptor, presented one terrain at a time in three orders.
//!
//! Prágr23 §5.3 is an offline evaluation of the predictor, not a mission: bumper measurements were
//! collected on four terrains (sparse grass, dense grass with hay, a tree trunk, rocks), split into
//! training and testing sets, and the predictor was presented with the training sets one terrain
//! after the other; after each presentation the prediction entropy on every terrain's testing set
//! is reported. So this bench builds no world for the simulator: it lays the four terrains out as
//! patches of a coloured elevation map (per-cell colours drawn, seeded, from each terrain's colour
//! mixture), measures each training cell with the simulated bumper (push force through the Table 4
//! torque calibration with servo noise, a few spikes and dropped packets), fuses the readings with
//! the haptic model (median filter and Kalman, Eq. 9) and learns the GP force predictor on the
//! 8-bin histograms (l = 0.4, Table 3). Test cells are the other half of each patch (a checkerboard
//! split).

use std::path::Path;

use rand::rngs::ChaCha8Rng;
use rand::{RngExt, SeedableRng};
use rand_distr::StandardNormal;
use strider_core::{Cell, Rgb8};
use strider_explore::escape::force_predictor::{
    ForcePrediction, ForcePredictor, PredictorParams, describe,
};
use strider_explore::escape::haptic::{BumperFilter, HapticModel, HapticParams};
use strider_map::{ElevationMap, MapParams};
use strider_sim::BumperCalibration;

use crate::io::{create_dir, write_json, write_text};
use crate::stats::mean;

/// One terrain of Prágr23 §5.3.
#[derive(Clone, Debug)]
pub struct VegetationTerrain {
    /// Name.
    pub name: &'static str,
    /// Colour mixture: (colour, weight).
    pub colors: Vec<(Rgb8, f64)>,
    /// Force to push through, N (`None`: rigid, the bumper reads the robot's maximum).
    pub push_force_n: Option<f64>,
}

/// The four terrains of Prágr23 Fig. 14 (forces: the curtains' range for sparse grass, near F_trav
/// for dense grass with hay; trunk and rocks rigid).
pub fn terrains() -> Vec<VegetationTerrain> {
    let c = Rgb8::new;
    vec![
        VegetationTerrain {
            name: "sparse grass",
            colors: vec![(c(50, 150, 50), 0.5), (c(130, 90, 50), 0.5)],
            push_force_n: Some(0.6),
        },
        VegetationTerrain {
            name: "dense grass with hay",
            colors: vec![(c(50, 150, 50), 0.6), (c(220, 200, 50), 0.4)],
            push_force_n: Some(1.5),
        },
        VegetationTerrain {
            name: "tree trunk",
            colors: vec![(c(130, 90, 50), 0.7), (c(20, 20, 20), 0.3)],
            push_force_n: None,
        },
        VegetationTerrain {
            name: "rocks",
            colors: vec![(c(128, 128, 128), 0.7), (c(240, 240, 240), 0.3)],
            push_force_n: None,
        },
    ]
}

/// Parameters of the bench.
#[derive(Clone, Debug)]
pub struct VegetationParams {
    /// Patch side, cells.
    pub patch_cells: i32,
    /// Per-channel colour noise, standard deviation (sRGB units).
    pub color_noise: f64,
    /// Bumper readings per training cell.
    pub readings_per_cell: usize,
    /// The robot's maximum push force (what a rigid terrain reads), N.
    pub max_push_n: f64,
    /// Servo torque noise (fraction).
    pub torque_noise: f64,
    /// Probability of a spike (servo reads its limit) per reading.
    pub spike_probability: f64,
    /// Probability of a NaN reading.
    pub nan_probability: f64,
    /// Seed.
    pub seed: u64,
}

impl Default for VegetationParams {
    fn default() -> Self {
        Self {
            patch_cells: 16,
            color_noise: 8.0,
            readings_per_cell: 10,
            max_push_n: 3.0,
            torque_noise: 0.05,
            spike_probability: 0.02,
            nan_probability: 0.02,
            seed: 1,
        }
    }
}

/// One row of the table: after presenting `presented`, the mean test entropy and predicted
/// force per terrain.
#[derive(Clone, Debug, serde::Serialize)]
pub struct VegetationRow {
    /// Presentation order (terrain indices).
    pub order: Vec<usize>,
    /// Step (1-based).
    pub step: usize,
    /// The terrain presented at this step.
    pub presented: String,
    /// Mean test entropy per terrain, nat.
    pub entropy: Vec<f64>,
    /// Mean predicted force per terrain, N.
    pub force: Vec<f64>,
}

/// The three presentation orders reported.
pub const ORDERS: [[usize; 4]; 3] = [[0, 1, 2, 3], [3, 2, 1, 0], [2, 0, 3, 1]];

/// Runs the bench: one row per (order, step).
pub fn run(p: &VegetationParams) -> anyhow::Result<Vec<VegetationRow>> {
    let ts = terrains();
    let mut rng = ChaCha8Rng::seed_from_u64(p.seed);
    let mut map = ElevationMap::new(MapParams::default());
    let pred_params = PredictorParams::histogram();
    // Patches side by side, one patch gap, flat ground.
    let n = p.patch_cells;
    let mut patches: Vec<Vec<Cell>> = Vec::new();
    for (k, t) in ts.iter().enumerate() {
        let x0 = k as i32 * (n + 4);
        let mut cells = Vec::new();
        for j in 0..n {
            for i in 0..n {
                let c = Cell::new(x0 + i, j);
                let u: f64 = rng.random();
                let mut acc = 0.0;
                let mut col = t.colors[0].0;
                for &(rgb, w) in &t.colors {
                    acc += w;
                    if u <= acc {
                        col = rgb;
                        break;
                    }
                }
                let mut ch = |v: u8| {
                    let e: f64 = rng.sample(StandardNormal);
                    (v as f64 + p.color_noise * e).round().clamp(0.0, 255.0) as u8
                };
                map.set_cell(
                    c,
                    0.0,
                    1e-4,
                    Rgb8::new(ch(col.0[0]), ch(col.0[1]), ch(col.0[2])),
                );
                cells.push(c);
            }
        }
        patches.push(cells);
    }
    // Interior cells only (the histogram disc must lie inside the patch), split by parity.
    let margin = (pred_params.r_hist / map.cell_size()).ceil() as i32;
    let inside = |c: &Cell, k: usize| {
        let x0 = k as i32 * (n + 4);
        c.i - x0 >= margin && c.i - x0 < n - margin && c.j >= margin && c.j < n - margin
    };
    let cal = BumperCalibration::c4_table4();
    let hp = HapticParams::default();
    let mut haptic = HapticModel::new(hp.clone());
    let mut train: Vec<Vec<Cell>> = Vec::new();
    let mut test: Vec<Vec<Cell>> = Vec::new();
    for (k, cells) in patches.iter().enumerate() {
        let f = ts[k].push_force_n.unwrap_or(p.max_push_n);
        let (mut tr, mut te) = (Vec::new(), Vec::new());
        for c in cells.iter().filter(|c| inside(c, k)) {
            if (c.i + c.j).rem_euclid(2) == 0 {
                // The bumper pressed on this cell: readings through the servo calibration.
                let mut filter = BumperFilter::default();
                for _ in 0..p.readings_per_cell {
                    let e: f64 = rng.sample(StandardNormal);
                    let mut reading =
                        cal.force((cal.torque(f) * (1.0 + p.torque_noise * e)).max(0.0));
                    if rng.random_bool(p.spike_probability) {
                        reading = cal.force(cal.max_torque());
                    }
                    if rng.random_bool(p.nan_probability) {
                        reading = f64::NAN;
                    }
                    if let Some(z) = filter.push(reading, &hp) {
                        haptic.fuse(*c, z);
                    }
                }
                tr.push(*c);
            } else {
                te.push(*c);
            }
        }
        train.push(tr);
        test.push(te);
    }
    let mut rows = Vec::new();
    for order in ORDERS {
        let mut samples: Vec<(Vec<f64>, f64)> = Vec::new();
        let mut pred = ForcePredictor::new(pred_params.clone());
        for (step, &k) in order.iter().enumerate() {
            for c in &train[k] {
                if let (Some(d), Some(h)) = (describe(&map, *c, &pred_params), haptic.get(*c)) {
                    samples.push((d, h.force));
                }
            }
            pred.learn(&samples)?;
            let mut entropy = Vec::new();
            let mut force = Vec::new();
            for cells in &test {
                let ps: Vec<_> = cells
                    .iter()
                    .filter_map(|c| describe(&map, *c, &pred_params))
                    .filter_map(|d| pred.predict(&d))
                    .collect();
                let mean_of = |f: fn(&ForcePrediction) -> f64| {
                    mean(&ps.iter().map(f).collect::<Vec<f64>>()).unwrap_or(0.0)
                };
                entropy.push(mean_of(|p| p.entropy));
                force.push(mean_of(|p| p.mean));
            }
            rows.push(VegetationRow {
                order: order.to_vec(),
                step: step + 1,
                presented: ts[k].name.to_string(),
                entropy,
                force,
            });
        }
    }
    Ok(rows)
}

/// The table as markdown: per order and step, the test entropy (and predicted force) of every
/// terrain; entropies below `threshold` (known terrain) are marked with `*`.
pub fn markdown(rows: &[VegetationRow], threshold: f64) -> String {
    let ts = terrains();
    let mut s = String::from("| order | step | presented |");
    for t in &ts {
        s.push_str(&format!(" {} H [nat] (F [N]) |", t.name));
    }
    s.push_str("\n|---|---|---|");
    s.push_str(&"---|".repeat(ts.len()));
    s.push('\n');
    for r in rows {
        let order: Vec<String> = r.order.iter().map(|k| (k + 1).to_string()).collect();
        s.push_str(&format!(
            "| {} | {} | {} |",
            order.join("-"),
            r.step,
            r.presented
        ));
        for (h, f) in r.entropy.iter().zip(&r.force) {
            let mark = if *h < threshold { "*" } else { "" };
            s.push_str(&format!(" {h:.2}{mark} ({f:.2}) |"));
        }
        s.push('\n');
    }
    s
}

/// `strider learn c4-vegetation`: runs the bench with the default parameters and writes
/// `c4_vegetation.md` and `c4_vegetation.json` into `out`; returns the markdown.
pub fn bench(out: &Path) -> anyhow::Result<String> {
    let rows = run(&VegetationParams::default())?;
    let thr = PredictorParams::histogram().entropy_threshold;
    let md = format!(
        "Produced by `strider learn c4-vegetation`. Test-set prediction entropy H (mean predicted force F) per terrain after each \
         presentation; * marks H < {thr} nat (terrain known).\n\n{}",
        markdown(&rows, thr)
    );
    create_dir(out)?;
    write_text(&out.join("c4_vegetation.md"), &md)?;
    write_json(&out.join("c4_vegetation.json"), &rows)?;
    Ok(md)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Prágr23 §5.3: after each terrain is presented its test entropy is below the threshold, in
    /// every order; a terrain not yet presented and unlike every presented one stays above.
    #[test]
    fn presented_terrains_become_known_in_every_order() {
        let rows = run(&VegetationParams::default()).unwrap();
        let thr = PredictorParams::histogram().entropy_threshold;
        assert_eq!(rows.len(), 12);
        for order in ORDERS {
            let rs: Vec<&VegetationRow> = rows.iter().filter(|r| r.order == order).collect();
            for (step, r) in rs.iter().enumerate() {
                for &k in &order[..=step] {
                    assert!(
                        r.entropy[k] < thr,
                        "order {order:?} step {}: {r:?}",
                        step + 1
                    );
                }
            }
            // Before any rigid terrain is presented the first one is uncertain.
            let first = rs[0];
            let unseen = order[1..]
                .iter()
                .filter(|&&k| first.entropy[k] > thr)
                .count();
            assert!(unseen >= 1, "{first:?}");
        }
        // Rigid terrains end above F_trav, the traversable ones below.
        let last = rows.last().unwrap();
        assert!(last.force[0] < 2.0 && last.force[1] < 2.0);
        assert!(last.force[2] > 2.0 && last.force[3] > 2.0);
    }
}
