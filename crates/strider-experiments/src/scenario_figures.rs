//! A scenario's world drawn for people: colour, elevation, terrain, ground-truth passability
//! and the tours, with `render.json` as the legend.

use std::path::Path;

use anyhow::Result;
use serde_json::json;
use strider_map::Passability;
use strider_scenario::Scenario;

use crate::io::{create_dir, write_json};
use crate::render::{Canvas, palette, rgb_canvas, scalar_canvas};
use crate::trial::load;

/// Colours of tours in overlays.
const TOUR_COLORS: [[u8; 3]; 4] = [[0, 160, 255], [255, 120, 0], [255, 0, 200], [0, 220, 120]];

/// Writes color, elevation, terrain, ground-truth passability and tour PNGs plus `render.json`
/// into `out`; returns the scenario.
pub fn render(arg: &str, world_seed: u64, out: &Path) -> Result<Scenario> {
    let sc = load(arg, world_seed)?;
    create_dir(out)?;
    let w = &sc.world;
    let (rect, res) = (w.rect, w.resolution);
    let scale = Canvas::auto_scale(rect, 900);

    let colors: Vec<_> = w.color.iter().map(|&c| Some(c)).collect();
    rgb_canvas(rect, res, scale, &colors).save(&out.join("color.png"))?;
    let (elev, elev_range) = scalar_canvas(rect, res, scale, &w.elevation, None);
    elev.save(&out.join("elevation.png"))?;

    let mut terrain = Canvas::new(rect, res, scale);
    terrain.fill(|k| Some(palette(w.terrain[k] as usize)));
    terrain.save(&out.join("terrain.png"))?;

    let pass = w.gt_passability(sc.map.rho_obstacle);
    let adm = w.gt_admissible(sc.map.rho_obstacle, sc.map.r_robot);
    let mut pc = Canvas::new(rect, res, scale);
    pc.fill(|k| {
        Some(match (pass[k], adm[k]) {
            (Passability::Impassable, _) => [20, 20, 20],
            (_, true) => [230, 230, 230],
            (Passability::Passable, false) => [150, 150, 150],
            _ => [90, 60, 60],
        })
    });
    pc.save(&out.join("passability.png"))?;

    let mut tours = rgb_canvas(rect, res, scale, &colors);
    for (t, tour) in sc.tours.iter().enumerate() {
        let c = TOUR_COLORS[t % TOUR_COLORS.len()];
        let mut pts = tour.waypoints.clone();
        if tour.closed && !pts.is_empty() {
            pts.push(pts[0]);
        }
        tours.polyline(&pts, c, (scale as i64 / 3).max(1));
        for p in &tour.waypoints {
            tours.marker(*p, c, (scale as i64).max(3));
        }
    }
    tours.marker(sc.start.position(), [255, 255, 255], (scale as i64).max(4));
    tours.save(&out.join("tours.png"))?;

    let legend = json!({
        "scenario": sc.name,
        "world_seed": sc.world_seed,
        "resolution_m": res,
        "size_cells": [rect.width, rect.height],
        "elevation_range_m": [elev_range.0, elev_range.1],
        "terrains": w.terrains.iter().map(|t| json!({
            "index": t.index, "name": t.name, "palette_rgb": palette(t.index as usize)
        })).collect::<Vec<_>>(),
        "passability_png": "black: impassable (step > rho_obstacle); light: admissible for the robot centre; mid gray: passable but within r_robot of an obstacle",
        "tours": sc.tours.iter().map(|t| json!({"name": t.name, "waypoints": t.waypoints.len()})).collect::<Vec<_>>(),
    });
    write_json(&out.join("render.json"), &legend)?;
    Ok(sc)
}
