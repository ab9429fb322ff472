//! `strider run --strategy escape|rigid`: the thesis C4 escape mission (Alg. 2) or the
//! rigid-obstacle baseline on a scenario in the simulator, and its report: sections explored,
//! the explored area and the apparent-obstacle cell states over time (C4 Figs. 11–12), bumper
//! contacts, goals, and PNG figures.

use std::fs;
use std::path::Path;
use std::time::Instant;

use anyhow::{Context, Result};
use serde_json::json;
use strider_explore::Mission;
use strider_explore::escape::force_predictor::describe;
use strider_explore::escape::view::ObstacleState;
use strider_explore::escape::{EscapeLog, EscapeMission, EscapeMode};

use crate::render::{compose, label, line_chart, rgb_canvas};
use crate::run_support::{RunRequest, checked_time_limit, start_run};
use strider_cli::escape_trial::{SECTION_EXPLORED_FRACTION, run_escape};
use strider_explore::registry::EscapeTable;
use strider_scenario::Scenario;

/// Runs `strider run` for the `escape` and `rigid` strategies.
pub fn run(sc: &Scenario, req: &RunRequest, mode: EscapeMode, table: &EscapeTable) -> Result<()> {
    let RunRequest {
        world_seed,
        seed,
        time_limit,
        out,
        mcap,
        ..
    } = *req;
    let wall = Instant::now();
    let mut params = table
        .escape_params(&strider_cli::trial::robot_spec(sc), mode)
        .map_err(|e| anyhow::anyhow!("strategy {}: {e}", mode.name()))?;
    if let Some(t) = time_limit {
        params.time_limit_s = checked_time_limit(t)?;
    }
    let bar = start_run(out, params.time_limit_s)?;
    let trial = run_escape(sc, params, seed, mcap, |m: &Mission<EscapeMission>| {
        let l = m.strategy().log();
        bar.set_position(l.timeline.last().map_or(0.0, |s| s.t) as u64);
        bar.set_message(format!(
            "{} cells mapped, {} haptic cells, {} contacts",
            m.body().map().observed_count(),
            m.strategy().haptic().len(),
            l.contacts.len()
        ));
    })?;
    let run = trial.mission.record();
    let esc = trial.mission.strategy();
    let map = trial.mission.body().map();
    bar.finish_and_clear();
    if let (Some(w), Some(file)) = (&trial.written, mcap) {
        println!("{} messages -> {}", w.total(), file.display());
    }
    let log = &trial.log;
    write_figures(&trial.mission, log, out)?;
    let wall_s = wall.elapsed().as_secs_f64();
    let timeline: Vec<_> = log
        .timeline
        .iter()
        .map(|s| {
            json!({
                "t": s.t,
                "explored_m2": s.explored_m2,
                "certain_traversable": s.states.certain_traversable,
                "uncertain_traversable": s.states.uncertain_traversable,
                "uncertain_untraversable": s.states.uncertain_untraversable,
                "certain_untraversable": s.states.certain_untraversable,
                "haptic_cells": s.haptic_cells,
            })
        })
        .collect();
    let report = json!({
        "scenario": sc.name,
        "world_seed": world_seed,
        "seed": seed,
        "strategy": mode.name(),
        "parameters": strider_explore::registry::typed::to_table(table),
        "termination": format!("{:?}", run.termination),
        "exploration_time_s": run.exploration_time_s,
        "driven_m": run.driven_m,
        "observed_cells": map.observed_count(),
        "sections_explored": trial.sections_explored(),
        "section_explored_fraction": SECTION_EXPLORED_FRACTION,
        "sections": trial.sections,
        "explored_area_over_time": log.timeline.iter().map(|s| [s.t, s.explored_m2]).collect::<Vec<_>>(),
        "cell_states_over_time": timeline,
        "contacts": log.contacts,
        "goals": log.goals,
        "pushes": log.pushes,
        "samplings": log.samplings,
        "relearns": log.relearns,
        "haptic_cells": esc.haptic().len(),
        "haptic": esc.haptic().cells().iter().map(|(c, h)| {
            let p = c.center(map.cell_size());
            json!({
                "x": p.x, "y": p.y, "force": h.force, "variance": h.variance, "count": h.count,
                "descriptor": describe(map, *c, &esc.params().predictor),
            })
        }).collect::<Vec<_>>(),
        "predictor_training_set": esc.predictor().len(),
        "mission_wall_s": run.wall_s,
        "wall_time_s": wall_s,
        "trajectory": run.trajectory,
    });
    let path = out.join("report.json");
    fs::write(&path, serde_json::to_string_pretty(&report)?)
        .with_context(|| format!("{}: cannot write", path.display()))?;
    println!(
        "{} ({}): {:?} after {:.0} s simulated, {:.1} m driven, {}/{} sections explored, {} contacts ({} corrected), {:.1} s wall -> {}",
        sc.name,
        mode.name(),
        run.termination,
        run.exploration_time_s,
        run.driven_m,
        trial.sections_explored(),
        trial.sections.len(),
        log.contacts.len(),
        log.contacts.iter().filter(|c| c.corrected).count(),
        wall_s,
        path.display()
    );
    Ok(())
}

/// `explored_area.png` (m² over time), `cell_states.png` (C4 Fig. 11: certain/uncertain ×
/// traversable/untraversable apparent-obstacle cells over time) and `map.png` (the map's colours
/// beside the Eq. 4 classification with the trajectory).
fn write_figures(m: &Mission<EscapeMission>, log: &EscapeLog, out: &Path) -> Result<()> {
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
        let scale = crate::render::Canvas::auto_scale(view.rect, 700);
        let colors = map.color_raster(view.rect);
        let mut a = rgb_canvas(view.rect, view.cell_size, scale, &colors);
        let mut b = crate::render::Canvas::new(view.rect, view.cell_size, scale);
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

/// `strider learn c4-vegetation`: the C4 §5.3 presentation-order table.
pub fn vegetation(out: &Path) -> Result<()> {
    use strider_cli::c4_vegetation::{VegetationParams, markdown, run};
    let rows = run(&VegetationParams::default())?;
    let thr =
        strider_explore::escape::force_predictor::PredictorParams::histogram().entropy_threshold;
    let md = format!(
        "Test-set prediction entropy H (mean predicted force F) per terrain after each \
         presentation; * marks H < {thr} nat (terrain known).\n\n{}",
        markdown(&rows, thr)
    );
    fs::create_dir_all(out)
        .with_context(|| format!("{}: cannot create directory", out.display()))?;
    fs::write(out.join("c4_vegetation.md"), &md)
        .with_context(|| format!("{}: cannot write", out.display()))?;
    fs::write(
        out.join("c4_vegetation.json"),
        serde_json::to_string_pretty(&rows)?,
    )
    .with_context(|| format!("{}: cannot write", out.display()))?;
    println!("{md}");
    Ok(())
}
