//! The figures of a Prágr23 mission: the explored area and the apparent-obstacle cell states
//! over time (Figs. 11–12), and the map beside its Eq. 4 classification.

use std::path::Path;

use anyhow::Result;
use strider_explore::Mission;
use strider_explore::escape::view::ObstacleState;
use strider_explore::escape::{EscapeLog, EscapeMission};

use crate::render::{Canvas, compose, label, line_chart, rgb_canvas};

/// `explored_area.png` (m² over time), `cell_states.png` (Prágr23 Fig. 11: certain/uncertain ×
/// traversable/untraversable apparent-obstacle cells over time) and `map.png` (the map's colours
/// beside the Eq. 4 classification with the trajectory).
pub(crate) fn write_figures(m: &Mission<EscapeMission>, log: &EscapeLog, out: &Path) -> Result<()> {
    let (map, run, mission) = (m.body().map(), m.record(), m.strategy());
    let tl = &log.timeline;
    let area: Vec<f64> = tl.iter().map(|s| s.explored_m2).collect();
    let x_label = format!(
        "sample ({:.0} s)",
        1.0 / mission.params().record_hz.max(1e-9)
    );
    line_chart(&[(area, [30, 90, 200])], &[], &x_label, "explored m2")
        .save(&out.join("explored_area.png"))?;
    let series = |f: fn(&strider_explore::escape::TimelineSample) -> usize| -> Vec<f64> {
        tl.iter().map(|s| f(s) as f64).collect()
    };
    let mut chart = line_chart(
        &[
            (series(|s| s.states.certain_traversable), CERTAIN_TRAV),
            (series(|s| s.states.uncertain_traversable), UNCERTAIN_TRAV),
            (
                series(|s| s.states.uncertain_untraversable),
                UNCERTAIN_UNTRAV,
            ),
            (series(|s| s.states.certain_untraversable), CERTAIN_UNTRAV),
        ],
        &[],
        &x_label,
        "cells",
    );
    label(&mut chart, 80.0, 400.0, "CERTAIN TRAV", CERTAIN_TRAV);
    label(&mut chart, 220.0, 400.0, "UNCERTAIN TRAV", UNCERTAIN_TRAV);
    label(
        &mut chart,
        380.0,
        400.0,
        "UNCERTAIN UNTRAV",
        UNCERTAIN_UNTRAV,
    );
    label(&mut chart, 560.0, 400.0, "CERTAIN UNTRAV", CERTAIN_UNTRAV);
    chart.save(&out.join("cell_states.png"))?;
    if let Some(view) = mission.view() {
        let scale = Canvas::auto_scale(view.rect, 700);
        let colors = map.color_raster(view.rect);
        let mut a = rgb_canvas(view.rect, view.cell_size, scale, &colors);
        let mut b = Canvas::new(view.rect, view.cell_size, scale);
        let thr = mission.params().predictor.entropy_threshold;
        let f_trav = mission.params().haptic.f_trav;
        b.fill(|k| {
            if !view.observed[k] {
                return None;
            }
            Some(match view.obstacle[k] {
                Some(ObstacleState::Haptic { traversable, .. }) => {
                    if traversable {
                        HAPTIC_TRAV
                    } else {
                        HAPTIC_UNTRAV
                    }
                }
                Some(ObstacleState::Predicted(fp)) => match (fp.entropy < thr, fp.mean <= f_trav) {
                    (true, true) => CERTAIN_TRAV,
                    (false, true) => UNCERTAIN_TRAV,
                    (false, false) => UNCERTAIN_UNTRAV,
                    (true, false) => CERTAIN_UNTRAV,
                },
                Some(ObstacleState::Unpredicted) => UNCERTAIN_UNTRAV,
                None if view.traversable[k] => [200, 200, 200],
                None => [120, 60, 60],
            })
        });
        let pts: Vec<strider_core::Point2> = run
            .trajectory
            .iter()
            .map(|s| strider_core::Point2::new(s.x, s.y))
            .collect();
        a.polyline(&pts, [255, 255, 0], 1);
        b.polyline(&pts, [0, 0, 0], 1);
        compose(&[a, b], 2).save(&out.join("map.png"))?;
    }
    Ok(())
}

const CERTAIN_TRAV: [u8; 3] = [30, 160, 60];
const UNCERTAIN_TRAV: [u8; 3] = [150, 220, 120];
const UNCERTAIN_UNTRAV: [u8; 3] = [240, 170, 60];
const CERTAIN_UNTRAV: [u8; 3] = [200, 40, 40];
const HAPTIC_TRAV: [u8; 3] = [40, 90, 230];
const HAPTIC_UNTRAV: [u8; 3] = [120, 20, 120];
