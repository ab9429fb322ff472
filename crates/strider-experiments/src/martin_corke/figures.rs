//! The figures of `strider tours`: energy per tour, cumulative energy and its difference, and
//! the learnt energy maps beside the true one.

use std::path::Path;

use anyhow::Result;
use strider_explore::energy_tours::{EnergyMap, PlannedTour, TourRecord};

use super::{SeedFigures, SeedRun};
use crate::render::{Canvas, line_chart, scalar_canvas};

/// Tours whose learnt maps are drawn (plus the convergence tour).
const MAP_TOURS: [usize; 4] = [1, 5, 10, 25];

const WHITE: [u8; 3] = [255, 255, 255];
const BLUE: [u8; 3] = [31, 119, 180];
const ORANGE: [u8; 3] = [255, 127, 14];
const GREEN: [u8; 3] = [44, 160, 44];
const MAGENTA: [u8; 3] = [255, 0, 255];

/// Writes the figures of one seed into `dir`.
pub(crate) fn write(r: &SeedRun, s: &SeedFigures, dir: &Path) -> Result<()> {
    let e = |v: &[TourRecord]| -> Vec<f64> { v.iter().map(|x| x.measured.energy_j).collect() };
    let chart = |series: &[(Vec<f64>, [u8; 3])], name: &str| {
        line_chart(series, &[], "TOUR", "J").save(&dir.join(name))
    };
    chart(
        &[
            (e(&r.outcome.tours), BLUE),
            (e(&r.shortest), ORANGE),
            (e(&r.known), GREEN),
        ],
        "energy_per_tour.png",
    )?;
    chart(
        &[
            (s.cumulative.iter().map(|c| c.0).collect(), BLUE),
            (s.cumulative.iter().map(|c| c.1).collect(), ORANGE),
        ],
        "cumulative_energy.png",
    )?;
    // The same as one curve: below zero, exploring has cost less in total so far.
    chart(
        &[(s.cumulative.iter().map(|c| c.0 - c.1).collect(), BLUE)],
        "cumulative_difference.png",
    )?;
    // One colour scale for the truth and every learnt map.
    let hi = r
        .truth
        .mean
        .iter()
        .chain(r.outcome.maps.iter().flat_map(|(_, m)| m.mean.iter()))
        .filter(|v| v.is_finite() && **v < 1e3)
        .fold(1.0f32, |a, &b| a.max(b));
    let range = (0.0, hi);
    let tours = &r.outcome.tours;
    let draw = |map: &EnergyMap,
                planned: Option<&PlannedTour>,
                driven: Option<&TourRecord>,
                path: &Path|
     -> Result<()> {
        let scale = Canvas::auto_scale(map.rect, 640);
        let (mut c, _) = scalar_canvas(map.rect, map.cell_size, scale, &map.mean, Some(range));
        if let Some(t) = driven {
            c.polyline(&t.measured.trajectory, MAGENTA, 1);
        }
        if let Some(pl) = planned {
            c.polyline(&pl.path, WHITE, 2);
        }
        if let Some(t) = tours.first() {
            for w in &t.plan.path {
                c.marker(*w, WHITE, 3);
            }
        }
        c.save(path)
    };
    draw(
        &r.truth,
        Some(&r.known_plan),
        None,
        &dir.join("map_truth.png"),
    )?;
    // The map after tour k is the last one learnt at or before k (learning stops at
    // convergence).
    let map_after = |k: usize| r.outcome.maps.iter().rev().find(|(t, _)| *t <= k);
    let plan_after = |k: usize| {
        tours
            .get(k)
            .map(|x| &x.plan)
            .or(tours.last().map(|x| &x.plan))
    };
    for k in MAP_TOURS {
        if k > tours.len() {
            continue;
        }
        if let Some((_, m)) = map_after(k) {
            draw(
                m,
                plan_after(k),
                tours.get(k - 1),
                &dir.join(format!("map_after_tour_{k:02}.png")),
            )?;
        }
    }
    if let Some(k) = r.outcome.convergence_tour
        && let Some((_, m)) = map_after(k)
    {
        draw(
            m,
            plan_after(k),
            tours.get(k - 1),
            &dir.join("map_convergence.png"),
        )?;
    }
    Ok(())
}
