//! The figures of `strider map build` over the world rectangle: colour, elevation, variance,
//! elevation error, passability, admissibility and the driven path.

use std::path::Path;

use anyhow::Result;
use strider_core::Point2;
use strider_map::{ElevationMap, Passability};
use strider_scenario::Scenario;

use super::score::Score;
use crate::render::{Canvas, rgb_canvas, scalar_canvas};

/// Writes the figures into `out`.
pub(crate) fn write(
    sc: &Scenario,
    map: &ElevationMap,
    score: &Score,
    trajectory: &[Point2],
    out: &Path,
) -> Result<()> {
    let w = &sc.world;
    let (rect, res) = (w.rect, w.resolution);
    let scale = Canvas::auto_scale(rect, 900);
    let scalar = |values: &[f32], range: Option<(f32, f32)>, file: &str| {
        scalar_canvas(rect, res, scale, values, range)
            .0
            .save(&out.join(file))
    };
    let colors = map.color_raster(rect);
    rgb_canvas(rect, res, scale, &colors).save(&out.join("color.png"))?;
    let gt_range = w
        .elevation
        .iter()
        .fold((f32::INFINITY, f32::NEG_INFINITY), |(a, b), &z| {
            (a.min(z), b.max(z))
        });
    scalar(&map.elevation_raster(rect), Some(gt_range), "elevation.png")?;
    let var: Vec<f32> = map
        .variance_raster(rect)
        .iter()
        .map(|v| v.max(1e-12).log10())
        .collect();
    scalar(&var, None, "variance.png")?;
    scalar(
        &score.error_raster,
        Some((0.0, 0.05)),
        "elevation_error.png",
    )?;
    let pass = map.passability_raster(rect);
    let adm = map.admissible_raster(rect);
    let mut pc = Canvas::new(rect, res, scale);
    pc.fill(|k| match pass[k] {
        Passability::Unknown => None,
        Passability::Impassable => Some([20, 20, 20]),
        Passability::Passable if adm[k] => Some([230, 230, 230]),
        Passability::Passable => Some([150, 150, 150]),
    });
    pc.save(&out.join("passability.png"))?;
    let obs = map.observed_raster(rect);
    let mut ac = Canvas::new(rect, res, scale);
    ac.fill(|k| {
        obs[k].then_some(if adm[k] {
            [230, 230, 230]
        } else {
            [60, 20, 20]
        })
    });
    ac.save(&out.join("admissible.png"))?;
    let mut pathc = rgb_canvas(rect, res, scale, &colors);
    pathc.polyline(trajectory, [255, 60, 0], (scale as i64 / 3).max(1));
    pathc.marker(sc.start.position(), [255, 255, 255], (scale as i64).max(3));
    pathc.save(&out.join("path.png"))
}
