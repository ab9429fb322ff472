//! The figures of `strider navigate` for the first site and seed: the aerial image with the
//! final paths, the true fields, each model's final mean and σ with its visited cells, and the
//! experienced cost per run.

use std::path::Path;

use anyhow::Result;
use strider_core::{Cell, Point2, Rgb8};
use strider_explore::navigate::ModelKind;
use strider_plan::grid::lcb::Rectifier;

use super::metrics::costs;
use super::site::{Site, task_points, true_field};
use super::{Config, Group};
use crate::render::{Canvas, line_chart, palette, rgb_canvas, scalar_canvas};

/// Colours of the configurations in figures.
fn config_color(c: &Config) -> [u8; 3] {
    match (c.model, c.rectifier) {
        (ModelKind::SingleGp, _) => [230, 85, 13],
        (ModelKind::GpMixture, _) => [117, 107, 177],
        (ModelKind::GpMixtureAerial, Rectifier::Softplus) => [0, 200, 255],
        (ModelKind::GpMixtureAerial, Rectifier::Relu) => [255, 0, 200],
    }
}

const SHORTEST: [u8; 3] = [255, 40, 40];
const LEAST: [u8; 3] = [255, 255, 255];

fn file_stem(g: &Group, c: &Config) -> String {
    format!(
        "{}_{}_{}{}",
        g.task.name(),
        g.objective.name(),
        c.model.name(),
        if c.rectifier == Rectifier::Relu {
            "_relu"
        } else {
            ""
        }
    )
}

/// Figures of the first site and seed: the aerial image with the final paths, the true fields,
/// each model's final mean and σ with its visited cells, and experienced cost per run.
pub(crate) fn write_figures(site: &Site, groups: &[Group], out: &Path) -> Result<()> {
    let map = &site.map;
    let (rect, d) = (map.rect(), map.cell_size());
    let scale = Canvas::auto_scale(rect, 900);
    let Some(g0) = groups.first() else {
        return Ok(());
    };
    let colors: Vec<Option<Rgb8>> = map
        .aerial()
        .map(|a| a.iter().map(|&c| Some(c)).collect())
        .unwrap_or_else(|| vec![None; rect.len()]);
    let line = (scale as i64 / 3).max(1);
    let mut terrain = Canvas::new(rect, d, scale);
    terrain.fill(|k| Some(palette(site.scenario.world.terrain[k] as usize)));
    terrain.save(&out.join("terrain.png"))?;
    for g in groups
        .iter()
        .filter(|g| g.site == g0.site && g.seed == g0.seed)
    {
        let stem = format!("{}_{}", g.task.name(), g.objective.name());
        let truth = true_field(&site.scenario, g.objective);
        let t32: Vec<f32> = truth.iter().map(|&v| v as f32).collect();
        let (tc, range) = scalar_canvas(rect, d, scale, &t32, None);
        tc.save(&out.join(format!("truth_{}.png", g.objective.name())))?;
        let mut paths = rgb_canvas(rect, d, scale, &colors);
        let to_pts =
            |p: &[Vec<Cell>]| -> Vec<Point2> { p.iter().flatten().map(|c| c.center(d)).collect() };
        paths.polyline(&to_pts(&g.shortest.2), SHORTEST, line);
        paths.polyline(&to_pts(&g.least_cost.2), LEAST, line);
        for (c, log, _) in &g.configs {
            if let Some(r) = log.runs.last() {
                paths.polyline(&to_pts(&r.planned), config_color(c), line);
            }
            // Final model: mean (the truth's colour range), σ, visited cells.
            if let Some(f) = log.fields.last() {
                let (mc, _) = scalar_canvas(rect, d, scale, &f.mean, Some(range));
                mc.save(&out.join(format!("{}_mean.png", file_stem(g, c))))?;
                let (mut sc, _) = scalar_canvas(rect, d, scale, &f.std, None);
                for &(k, _) in &log.visited {
                    sc.marker(rect.cell(k).center(d), [255, 255, 255], 0);
                }
                sc.save(&out.join(format!("{}_std.png", file_stem(g, c))))?;
            }
        }
        for p in task_points(site, g.task) {
            paths.marker(*p, [255, 255, 0], (scale as i64).max(3));
        }
        paths.save(&out.join(format!("{stem}_paths.png")))?;
        cost_chart(g)?.save(&out.join(format!("{stem}_cost_per_run.png")))?;
    }
    Ok(())
}

/// Experienced cost per run for every configuration (coloured as in the path figure), with the
/// shortest (red) and least-cost (dark grey) drives as horizontal lines; y from 0.
fn cost_chart(g: &Group) -> Result<Canvas> {
    let series: Vec<(Vec<f64>, [u8; 3])> = g
        .configs
        .iter()
        .map(|(cfg, log, _)| (costs(log), config_color(cfg)))
        .collect();
    let hlines = [
        (g.shortest.1.experienced_cost, SHORTEST),
        (g.least_cost.1.experienced_cost, [40, 40, 40]),
    ];
    Ok(line_chart(&series, &hlines, "RUN", ""))
}
