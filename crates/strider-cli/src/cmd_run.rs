//! `strider run`: an exploration mission (`001` Alg. 1) on a scenario in the simulator, the
//! benchmark tours in every navigation mode, and the report (JSON, PNG figures).

use std::fs;
use std::path::Path;
use std::time::Instant;

use anyhow::{Context, Result, bail};
use serde_json::json;
use strider_core::Point2;
use strider_explore::evaluate::{NavigationMode, TourResult};
use strider_explore::planner::{CostMode, PlanningView};
use strider_explore::registry::Configured;
use strider_explore::{Mission, MissionLog, TourExplorer};
use strider_scenario::Scenario;

use crate::cmd_scenario::load;
use crate::render::{Canvas, palette, rgb_canvas, scalar_canvas};
pub(crate) use crate::run_support::median_max;
use crate::run_support::{RunRequest, checked_time_limit, start_run};
use strider_cli::trial::{
    configure, on_worker, robot_spec, run_mission, run_mission_recorded, run_tours,
};
use strider_core::color::COLOR_PROTOTYPES;

/// Runs `strider run` (on a pool thread, see [`on_worker`]).
pub fn run(req: &RunRequest) -> Result<()> {
    on_worker(|| run_on_worker(req))
}

fn run_on_worker(req: &RunRequest) -> Result<()> {
    let sc = load(req.scenario, req.world_seed)?;
    let (_, configured) = configure(&sc, req.strategy, req.sets)?;
    match &configured {
        Configured::Tour(..) => run_tour(&sc, req, &configured),
        Configured::Rbcm(table) => crate::cmd_run_rbcm::run(&sc, req, table),
        Configured::Escape(mode, table) => crate::cmd_run_escape::run(&sc, req, *mode, table),
    }
}

/// `strider run` of a `001` strategy: the mission, the benchmark tours in every navigation
/// mode, the report and the figures.
fn run_tour(sc: &Scenario, req: &RunRequest, configured: &Configured) -> Result<()> {
    let RunRequest {
        world_seed,
        seed,
        time_limit,
        out,
        mcap,
        ..
    } = *req;
    let wall = Instant::now();
    let Some(mut params) = configured.tour_mission(&robot_spec(sc), seed) else {
        bail!("{} is not a 001 strategy", configured.name());
    };
    if let Some(t) = time_limit {
        params.time_limit_s = checked_time_limit(t)?;
    }
    let bar = start_run(out, params.time_limit_s)?;
    let progress = |p: &strider_explore::MissionProgress| {
        bar.set_position(p.time_s as u64);
        bar.set_message(format!(
            "{} cells mapped, {} spatial + {} cost goals, {} learning pairs",
            p.observed_cells, p.spatial_goals, p.cost_goals, p.learning_set
        ));
    };
    let (mission, log) = match mcap {
        None => run_mission(sc, params, seed, progress)?,
        Some(file) => {
            let (m, l, written) = run_mission_recorded(sc, params, seed, progress, file)?;
            bar.suspend(|| println!("{} messages -> {}", written.total(), file.display()));
            (m, l)
        }
    };
    bar.finish_and_clear();
    let spin = indicatif::ProgressBar::new_spinner();
    spin.enable_steady_tick(std::time::Duration::from_millis(200));
    let tours = run_tours(sc, &mission, seed, &NavigationMode::ALL, |tour, mode| {
        spin.set_message(format!("tour {tour} with {} navigation", mode.name()));
    })?;
    spin.finish_and_clear();
    let tours_json: Vec<_> = tours
        .iter()
        .map(|(name, modes)| {
            json!({
                "name": name,
                "modes": modes.iter().map(|r| json!({
                    "mode": r.mode.name(),
                    "total_s": r.total_s,
                    "completed": r.completed,
                    "segments": r.segments,
                    "trajectory": r.trajectory,
                })).collect::<Vec<_>>(),
            })
        })
        .collect();

    write_figures(&mission, &tours, out)?;

    let (rep_med, rep_max) = median_max(&log.replan_ms);
    let (g2t_med, g2t_max) = median_max(&log.goals_to_tour_ms);
    let part = |f: fn(&strider_explore::tour_explorer::ReplanParts) -> f64| {
        let v: Vec<f64> = log.replan_parts.iter().map(f).collect();
        let (median, max) = median_max(&v);
        json!({"median": median, "max": max})
    };
    let (sp_med, sp_max) = median_max(&log.spatial_goal_ms);
    let (le_med, le_max) = median_max(&log.learning_ms);
    let models = models_json(&mission, &log);
    let wall_s = wall.elapsed().as_secs_f64();
    let report = json!({
        "scenario": sc.name,
        "world_seed": world_seed,
        "seed": seed,
        "strategy": configured.name(),
        "parameters": configured.table(),
        "termination": format!("{:?}", mission.record().termination),
        "exploration_time_s": mission.record().exploration_time_s,
        "driven_m": mission.record().driven_m,
        "observed_cells": mission.body().map().observed_count(),
        "scans_fused": mission.body().map().scan_count(),
        "phase_wall_s": log.phase_wall_s,
        "models": models,
        "tours": tours_json,
        "stuck_events": log.stuck_events,
        "turn_skipped_cost_samples": log.turn_skipped,
        "information_gain_evaluations": {"fresh": log.gain_evaluated, "incremental": log.gain_updated},
        "replans": log.replan_ms.len(),
        "replan_latency_ms": {"median": rep_med, "max": rep_max},
        "goals_to_tour_ms": {"median": g2t_med, "max": g2t_max},
        "replan_parts_ms": {
            "view": part(|p| p.view_ms),
            "all_pairs": part(|p| p.all_pairs_ms),
            "gtsp": part(|p| p.gtsp_ms),
            "vertices": part(|p| p.vertices as f64),
        },
        "goal_identification_ms": {
            "spatial": {"median": sp_med, "max": sp_max},
            "learning": {"median": le_med, "max": le_max},
        },
        "mission_wall_s": mission.record().wall_s,
        "speedup": mission.record().exploration_time_s / mission.record().wall_s.max(1e-9),
        "wall_time_s": wall_s,
        "trajectory": mission.record().trajectory,
    });
    let path = write_reports(out, &report, &mission, &tours)?;
    println!(
        "{} ({}): {:?} after {:.0} s simulated, {:.1} m driven, {} replans (median {:.1} ms, max {:.1} ms), {:.0}x real time, {:.1} s wall -> {}",
        sc.name,
        configured.name(),
        mission.record().termination,
        mission.record().exploration_time_s,
        mission.record().driven_m,
        log.replan_ms.len(),
        rep_med,
        rep_max,
        mission.record().exploration_time_s / mission.record().wall_s.max(1e-9),
        wall_s,
        path.display()
    );
    println!(
        "  new data to new tour (goal identification + replan): median {g2t_med:.1} ms, max {g2t_max:.1} ms"
    );
    for (name, modes) in &tours {
        let parts: Vec<String> = modes
            .iter()
            .map(|r| {
                format!(
                    "{} {:.0} s{}",
                    r.mode.name(),
                    r.total_s,
                    if r.completed { "" } else { " (incomplete)" }
                )
            })
            .collect();
        println!("  tour {name}: {}", parts.join(", "));
    }
    Ok(())
}

/// Writes `report.json` and `report.html` (for `mission`'s gaits and the driven `tours`) into
/// `out`; returns the JSON's path.
pub(crate) fn write_reports(
    out: &Path,
    report: &serde_json::Value,
    mission: &Mission<TourExplorer>,
    tours: &[(String, Vec<TourResult>)],
) -> Result<std::path::PathBuf> {
    let path = out.join("report.json");
    fs::write(&path, serde_json::to_string_pretty(report)?)
        .with_context(|| format!("{}: cannot write", path.display()))?;
    let gait_names: Vec<String> = mission
        .strategy()
        .params()
        .gaits
        .iter()
        .map(|g| g.name.clone())
        .collect();
    let html = out.join("report.html");
    fs::write(&html, report_html(report, &gait_names, tours))
        .with_context(|| format!("{}: cannot write", html.display()))?;
    Ok(path)
}

/// Per-gait model summaries of the report: classes with dominant colour, cost and variance,
/// sample counts, H^GT.
pub(crate) fn models_json(
    mission: &Mission<TourExplorer>,
    log: &MissionLog,
) -> Vec<serde_json::Value> {
    mission
        .strategy()
        .models()
        .iter()
        .enumerate()
        .map(|(g, m)| {
            json!({
                "gait": mission.strategy().params().gaits[g].name,
                "regressor": m.has_regressor(),
                "learning_set": m.learning_set_len(),
                "measured_cells": m.measured_cells().len(),
                "classes": m.igng().len(),
                "cost_samples": log.cost_samples[g],
                "h_gt": mission.strategy().model_updates()[g].h_gt,
                "class_table": mission.strategy().model_updates()[g].classes.iter().map(|c| json!({
                    "id": c.id.0,
                    // Of the descriptor the class is predicted at (its cells' median).
                    "dominant_colour_bin": c.median.iter().enumerate()
                        .max_by(|a, b| a.1.total_cmp(b.1)).map(|(k, _)| k),
                    "cells": c.cells,
                    "learning_cells": c.learning_cells,
                    "cost": c.cost,
                    "variance": c.variance,
                    "information_gain": c.information_gain,
                })).collect::<Vec<_>>(),
                "samplings": log.samplings[g],
            })
        })
        .collect()
}

/// The figures of `001` Fig. 7 over the map's known area: map colour, merged planning cost and
/// selected gait (Eq. 13), per gait the learned cell costs, the classes (dilated, Alg. 10) and
/// the planning cost, the exploration path, and the tour paths of each navigation mode.
pub(crate) fn write_figures(
    mission: &Mission<TourExplorer>,
    tours: &[(String, Vec<TourResult>)],
    out: &Path,
) -> Result<()> {
    let map = mission.body().map();
    let Some(rect) = map.known_bounds() else {
        return Ok(());
    };
    let d = map.cell_size();
    let scale = Canvas::auto_scale(rect, 900);
    let colors = map.color_raster(rect);
    rgb_canvas(rect, d, scale, &colors).save(&out.join("color.png"))?;
    // Fig. 5E: the dominant colour prototype of each cell's descriptor ta(ν).
    let desc = mission.strategy().descriptors();
    let dominant: Vec<_> = rect
        .cells()
        .map(|c| {
            desc.get(c).and_then(|h| {
                h.iter()
                    .enumerate()
                    .max_by(|a, b| a.1.total_cmp(b.1))
                    .map(|(k, _)| COLOR_PROTOTYPES[k].1)
            })
        })
        .collect();
    rgb_canvas(rect, d, scale, &dominant).save(&out.join("dominant_colour.png"))?;
    let c_max = mission.strategy().params().cost_model.c_max as f32;
    if let Some(view) = PlanningView::build(
        map,
        mission.strategy().models(),
        CostMode::Learned,
        mission.strategy().params().c_loss,
        mission.strategy().params().bounds.as_ref(),
    ) {
        // The view covers the known area grown by the footprint; crop it to the known area.
        let vr = view.rect();
        let crop = |k: usize| vr.index(rect.cell(k));
        let merged: Vec<f32> = (0..rect.len())
            .map(|k| crop(k).map_or(f32::NAN, |i| view.grid.costs()[i]))
            .collect();
        scalar_canvas(rect, d, scale, &merged, Some((1.0, c_max)))
            .0
            .save(&out.join("merged_cost.png"))?;
        let mut g = Canvas::new(rect, d, scale);
        let obs = map.observed_raster(rect);
        g.fill(|k| {
            obs[k]
                .then(|| crop(k).and_then(|i| view.best_gait[i]))
                .flatten()
                .map(|x| palette(x as usize))
        });
        g.save(&out.join("gait.png"))?;
    }
    for (gi, m) in mission.strategy().models().iter().enumerate() {
        let name = &mission.strategy().params().gaits[gi].name;
        let costs: Vec<f32> = rect
            .cells()
            .map(|c| m.cell_cost(c).map_or(f32::NAN, |k| k.cost as f32))
            .collect();
        scalar_canvas(rect, d, scale, &costs, Some((1.0, c_max)))
            .0
            .save(&out.join(format!("measured_cost_{name}.png")))?;
        let mut cl = Canvas::new(rect, d, scale);
        let cells: Vec<_> = rect.cells().map(|c| m.planning_class(c)).collect();
        cl.fill(|k| cells[k].map(|t| palette(t.0 as usize)));
        cl.save(&out.join(format!("classes_{name}.png")))?;
        scalar_canvas(rect, d, scale, &m.planning_costs(rect), Some((1.0, c_max)))
            .0
            .save(&out.join(format!("planning_cost_{name}.png")))?;
        // Fig. 5G–H: the raw GP prediction and its (latent) variance at the described cells:
        // every cell when there are few, else on a lattice of about 16384 cells with each
        // lattice cell's value shown over its block (a prediction costs O(n²), `001` fn. 2).
        let stride = ((rect.len() as f64 / 16384.0).sqrt().ceil() as i32).max(1);
        let anchor = |c: strider_core::Cell| {
            strider_core::Cell::new(
                c.i - (c.i - rect.min.i).rem_euclid(stride),
                c.j - (c.j - rect.min.j).rem_euclid(stride),
            )
        };
        let lattice: Vec<strider_core::Cell> = rect
            .cells()
            .filter(|&c| anchor(c) == c && desc.get(c).is_some())
            .collect();
        let xs: Vec<f64> = lattice
            .iter()
            .flat_map(|&c| desc.get(c).unwrap_or(&[]).iter().copied())
            .collect();
        let at: std::collections::HashMap<strider_core::Cell, (f64, f64)> =
            lattice.iter().copied().zip(m.predict_many(&xs)).collect();
        let pred: Vec<(f32, f32)> = rect
            .cells()
            .map(|c| match (desc.get(c), at.get(&anchor(c))) {
                (Some(_), Some(&(mu, var))) => (mu as f32, var as f32),
                _ => (f32::NAN, f32::NAN),
            })
            .collect();
        let mu: Vec<f32> = pred.iter().map(|p| p.0).collect();
        let var: Vec<f32> = pred.iter().map(|p| p.1).collect();
        scalar_canvas(rect, d, scale, &mu, Some((1.0, c_max)))
            .0
            .save(&out.join(format!("prediction_{name}.png")))?;
        scalar_canvas(rect, d, scale, &var, None)
            .0
            .save(&out.join(format!("variance_{name}.png")))?;
    }
    let mut path = rgb_canvas(rect, d, scale, &colors);
    let pts: Vec<Point2> = mission
        .record()
        .trajectory
        .iter()
        .map(|s| Point2::new(s.x, s.y))
        .collect();
    path.polyline(&pts, [255, 0, 255], 2);
    path.save(&out.join("exploration_path.png"))?;
    for (name, modes) in tours {
        for r in modes {
            let mut c = rgb_canvas(rect, d, scale, &colors);
            for w in r.trajectory.windows(2) {
                let col = palette(w[0].gait as usize);
                c.polyline(
                    &[Point2::new(w[0].x, w[0].y), Point2::new(w[1].x, w[1].y)],
                    col,
                    2,
                );
            }
            c.save(&out.join(format!("tour_{name}_{}.png", r.mode.name())))?;
        }
    }
    Ok(())
}

/// Escapes text for HTML.
fn esc(s: &str) -> String {
    s.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
}

/// `report.html`: the summary, the tour and model tables, and the figures of `001` Fig. 5/7
/// with captions, all read from the report written beside it.
fn report_html(
    r: &serde_json::Value,
    gaits: &[String],
    tours: &[(String, Vec<TourResult>)],
) -> String {
    use std::fmt::Write as _;
    let f = |k: &str| r.get(k).and_then(|v| v.as_f64()).unwrap_or(f64::NAN);
    let st = |k: &str| {
        r.get(k)
            .map(|v| v.as_str().map_or(v.to_string(), str::to_string))
            .unwrap_or_default()
    };
    let lat = |k: &str, q: &str| {
        r.get(k)
            .and_then(|v| v.get(q))
            .and_then(|v| v.as_f64())
            .unwrap_or(f64::NAN)
    };
    let lat2 = |part: &str, q: &str| {
        r.get("goal_identification_ms")
            .and_then(|v| v.get(part))
            .and_then(|v| v.get(q))
            .and_then(|v| v.as_f64())
            .unwrap_or(f64::NAN)
    };
    let mut h = String::new();
    let _ = write!(
        h,
        "<!doctype html><html><head><meta charset=\"utf-8\"><title>Strider: {sc}</title>\
<style>body{{font-family:sans-serif;max-width:1200px;margin:2em auto;color:#222}}\
table{{border-collapse:collapse;margin:1em 0}}td,th{{border:1px solid #ccc;padding:3px 8px;text-align:right}}\
th{{background:#f3f3f3}}td:first-child,th:first-child{{text-align:left}}\
figure{{display:inline-block;margin:6px;vertical-align:top;width:380px}}img{{width:100%;image-rendering:pixelated;border:1px solid #ddd}}\
figcaption{{font-size:90%}}</style></head><body>\
<h1>Exploration of <code>{sc}</code> with <code>{strat}</code></h1>\
<p>World seed {ws}, mission seed {seed}. The robot explored for <b>{expl:.0} s</b> of simulated time \
({term}), drove {driven:.1} m and mapped {cells} cells; it then drove every benchmark tour once per \
navigation mode on the frozen map and models. The mission ran {speed:.0}× faster than real time \
({mw:.1} s wall; whole command {wall:.1} s).</p>\
<p>Replanning (planning view, all-pairs site costs, GTSP, path): {rn} replans, median {rmed:.1} ms, \
max {rmax:.1} ms. Spatial goal identification (passability, reachability, Eq. 11, Alg. 3): median \
{smed:.1} ms, max {smax:.1} ms. Learning updates (descriptors and every gait's model): median \
{lmed:.1} ms, max {lmax:.1} ms. From new data to a new tour (each replan plus the goal \
identifications run since the previous one): median {gmed:.1} ms, max {gmax:.1} ms.</p>",
        sc = esc(&st("scenario")),
        strat = esc(&st("strategy")),
        ws = st("world_seed"),
        seed = st("seed"),
        expl = f("exploration_time_s"),
        term = esc(&st("termination")),
        driven = f("driven_m"),
        cells = st("observed_cells"),
        speed = f("speedup"),
        mw = f("mission_wall_s"),
        wall = f("wall_time_s"),
        rn = st("replans"),
        rmed = lat("replan_latency_ms", "median"),
        rmax = lat("replan_latency_ms", "max"),
        gmed = lat("goals_to_tour_ms", "median"),
        gmax = lat("goals_to_tour_ms", "max"),
        smed = lat2("spatial", "median"),
        smax = lat2("spatial", "max"),
        lmed = lat2("learning", "median"),
        lmax = lat2("learning", "max"),
    );
    if let Some(log) = r.get("source_log").and_then(|v| v.as_str()) {
        // A replayed log (`strider replay`): no exploration, no tours.
        let start = h.find("<h1>").unwrap_or(h.len());
        h.truncate(start);
        let _ = write!(
            h,
            "<h1>Replay of <code>{}</code></h1><p>{:.0} s of recorded time mapped and learned in \
             {:.1} s wall ({:.0}× real time): {} cells mapped from {} scans. Learning updates: \
             median {:.1} ms, max {:.1} ms.</p>",
            esc(log),
            f("exploration_time_s"),
            f("mission_wall_s"),
            f("speedup"),
            st("observed_cells"),
            st("scans_fused"),
            lat2("learning", "median"),
            lat2("learning", "max"),
        );
    }
    // Tours: total per mode, then segments.
    h.push_str("<h2>Benchmark tours</h2><table><tr><th>tour</th>");
    for m in NavigationMode::ALL {
        let _ = write!(h, "<th>{} (s)</th>", m.name());
    }
    h.push_str("</tr>");
    for (name, modes) in tours {
        let _ = write!(h, "<tr><td>{}</td>", esc(name));
        for r in modes {
            let _ = write!(
                h,
                "<td>{:.1}{}</td>",
                r.total_s,
                if r.completed { "" } else { " (incomplete)" }
            );
        }
        h.push_str("</tr>");
    }
    h.push_str("</table>");
    for (name, modes) in tours {
        let n = modes.first().map_or(0, |r| r.segments.len());
        let _ = write!(
            h,
            "<details><summary>Segments of {}</summary><table><tr><th>segment</th>",
            esc(name)
        );
        for r in modes {
            let _ = write!(h, "<th>{} (s)</th>", r.mode.name());
        }
        h.push_str("</tr>");
        for k in 0..n {
            let _ = write!(h, "<tr><td>{} → {}</td>", k, k + 1);
            for r in modes {
                match r.segments.get(k) {
                    Some(s) => {
                        let _ = write!(
                            h,
                            "<td>{:.1}{}</td>",
                            s.time_s,
                            if s.reached { "" } else { " ✗" }
                        );
                    }
                    None => h.push_str("<td>–</td>"),
                }
            }
            h.push_str("</tr>");
        }
        h.push_str("</table></details>");
    }
    if tours.is_empty()
        && let Some(k) = h.find("<h2>Benchmark tours</h2>")
    {
        h.truncate(k);
    }
    // Models.
    h.push_str("<h2>Learned models</h2>");
    if let Some(models) = r.get("models").and_then(|m| m.as_array()) {
        for m in models {
            let g = m.get("gait").and_then(|v| v.as_str()).unwrap_or("?");
            let _ = write!(
                h,
                "<h3>gait {}</h3><p>{} cost samples, learning set {}, {} terrain classes, \
                 H<sup>GT</sup> = {}.</p><table><tr><th>class</th><th>dominant colour</th>\
                 <th>cells</th><th>learning cells</th><th>cost</th><th>variance</th></tr>",
                esc(g),
                m.get("cost_samples")
                    .map_or(String::new(), |v| v.to_string()),
                m.get("learning_set")
                    .map_or(String::new(), |v| v.to_string()),
                m.get("classes").map_or(String::new(), |v| v.to_string()),
                m.get("h_gt").map_or(String::new(), |v| match v.as_f64() {
                    Some(x) => format!("{x:.3}"),
                    None => v.to_string(),
                }),
            );
            for c in m
                .get("class_table")
                .and_then(|v| v.as_array())
                .into_iter()
                .flatten()
            {
                let num = |k: &str| c.get(k).and_then(|v| v.as_f64()).unwrap_or(f64::NAN);
                let bin = c
                    .get("dominant_colour_bin")
                    .and_then(|v| v.as_u64())
                    .map(|b| b as usize);
                let colour = bin
                    .and_then(|b| COLOR_PROTOTYPES.get(b))
                    .map_or("–".to_string(), |p| p.0.to_string());
                let _ = write!(
                    h,
                    "<tr><td>{}</td><td>{}</td><td>{}</td><td>{}</td><td>{:.3}</td><td>{:.4}</td></tr>",
                    c.get("id").map_or(String::new(), |v| v.to_string()),
                    colour,
                    c.get("cells").map_or(String::new(), |v| v.to_string()),
                    c.get("learning_cells")
                        .map_or(String::new(), |v| v.to_string()),
                    num("cost"),
                    num("variance"),
                );
            }
            h.push_str("</table>");
        }
    }
    // Figures.
    let mut figs: Vec<(String, String)> = vec![
        ("color.png".into(), "Map colour (mean cell colour).".into()),
        (
            "dominant_colour.png".into(),
            "Dominant colour prototype of each cell's 9-bin descriptor ta(ν) (Fig. 5E).".into(),
        ),
        (
            "merged_cost.png".into(),
            "Planning cost: the minimum over gaits after the distance transform (Fig. 5C).".into(),
        ),
        (
            "gait.png".into(),
            "Cheapest gait per cell (Fig. 5D; palette order = gait order).".into(),
        ),
    ];
    for g in gaits {
        figs.push((
            format!("measured_cost_{g}.png"),
            format!("Gait {g}: measured costs (tanh-bounded) where it walked (Fig. 5F)."),
        ));
        figs.push((
            format!("prediction_{g}.png"),
            format!("Gait {g}: raw GP cost prediction (Fig. 5G)."),
        ));
        figs.push((
            format!("variance_{g}.png"),
            format!("Gait {g}: GP prediction variance (Fig. 5H)."),
        ));
        figs.push((
            format!("classes_{g}.png"),
            format!("Gait {g}: IGNG terrain classes after erosion and dilation (Fig. 5I)."),
        ));
        figs.push((
            format!("planning_cost_{g}.png"),
            format!("Gait {g}: class costs used in planning (Fig. 5K)."),
        ));
    }
    figs.push((
        "exploration_path.png".into(),
        "The exploration path (Fig. 7).".into(),
    ));
    for (name, modes) in tours {
        for r in modes {
            figs.push((
                format!("tour_{name}_{}.png", r.mode.name()),
                format!(
                    "Tour {name}, {} navigation: {:.0} s (colour = gait).",
                    r.mode.name(),
                    r.total_s
                ),
            ));
        }
    }
    h.push_str("<h2>Figures</h2>");
    for (file, caption) in figs {
        let _ = write!(
            h,
            "<figure><img src=\"{f}\" alt=\"{c}\"><figcaption>{c}</figcaption></figure>",
            f = esc(&file),
            c = esc(&caption)
        );
    }
    h.push_str(
        "<p>Cost images use viridis from purple (cost 1) to yellow (c_max); the variance images \
         span their own range. Unobserved cells are blank. Raw numbers: \
         <a href=\"report.json\">report.json</a>.</p></body></html>\n",
    );
    h
}
