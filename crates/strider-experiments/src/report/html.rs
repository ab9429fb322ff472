//! `report.html`: the summary, the tour and model tables, and the figures of Prágr22 Fig. 5/7
//! with captions, all read from the `report.json` written beside it.

use std::fmt::Write as _;

use serde_json::Value;
use strider_core::color::COLOR_PROTOTYPES;
use strider_explore::evaluate::{NavigationMode, TourResult};

use super::MapFigure;
use super::figure::escape as esc;

/// Reads fields of the report.
struct Fields<'a>(&'a Value);

impl Fields<'_> {
    /// A number (NaN when missing).
    fn num(&self, k: &str) -> f64 {
        self.0.get(k).and_then(|v| v.as_f64()).unwrap_or(f64::NAN)
    }

    /// A field as text (strings without quotes; empty when missing).
    fn text(&self, k: &str) -> String {
        self.0
            .get(k)
            .map(|v| v.as_str().map_or(v.to_string(), str::to_string))
            .unwrap_or_default()
    }

    /// A number at a path of keys (NaN when missing).
    fn at(&self, path: &[&str]) -> f64 {
        path.iter()
            .try_fold(self.0, |v, k| v.get(k))
            .and_then(|v| v.as_f64())
            .unwrap_or(f64::NAN)
    }
}

/// The page for the report `r` of a mission with `gaits` that drove `tours`.
pub fn report_html(r: &Value, figs: &[MapFigure], tours: &[(String, Vec<TourResult>)]) -> String {
    let mut h = head(&Fields(r));
    if !tours.is_empty() {
        tour_tables(&mut h, tours);
    }
    models(&mut h, r);
    figures(&mut h, figs);
    h.push_str(
        "<p>Costs are the dimensionless inverse-velocity cost of Prágr22 Eq. 19–20: 1 is ideal \
         terrain at the gait's full speed, c_max a robot that barely moves. Cells never observed \
         are dark grey. Raw numbers: <a href=\"report.json\">report.json</a>.</p></body></html>\n",
    );
    h
}

const STYLE: &str = "<style>body{font-family:sans-serif;max-width:1200px;margin:2em auto;color:#222}\
table{border-collapse:collapse;margin:1em 0}td,th{border:1px solid #ccc;padding:3px 8px;text-align:right}\
th{background:#f3f3f3}td:first-child,th:first-child{text-align:left}\
figure{display:inline-block;margin:6px;vertical-align:top;width:480px}figure svg{width:100%;height:auto}\
figcaption{font-size:90%}</style>";

/// The document head and the summary: of the exploration, or of a replayed log.
fn head(f: &Fields) -> String {
    let mut h = String::new();
    let _ = write!(
        h,
        "<!doctype html><html><head><meta charset=\"utf-8\"><title>Strider: {}</title>{STYLE}</head><body>",
        esc(&title(f))
    );
    match f.0.get("source_log").and_then(|v| v.as_str()) {
        Some(log) => replay_summary(&mut h, f, log),
        None => mission_summary(&mut h, f),
    }
    h
}

/// The page title: the explored scenario and strategy, or the replayed log.
fn title(f: &Fields) -> String {
    match f.0.get("source_log").and_then(|v| v.as_str()) {
        Some(log) => format!("replay of {log}"),
        None => format!("{} on {}", f.text("strategy"), f.text("scenario")),
    }
}

fn mission_summary(h: &mut String, f: &Fields) {
    let _ = write!(
        h,
        "<h1>Exploration of <code>{sc}</code> with <code>{strat}</code></h1>\
<p>World seed {ws}, mission seed {seed}. The robot explored for <b>{expl:.0} s</b> of simulated time \
({term}), drove {driven:.1} m and mapped {cells} cells; it then drove every benchmark tour once per \
navigation mode on the frozen map and models. The mission ran {speed:.0}× faster than real time \
({mw:.1} s wall; whole command {wall:.1} s).</p>\
<p>Replanning (planning view, all-pairs site costs, GTSP, path): {rn} replans, median {rmed:.1} ms, \
max {rmax:.1} ms. Spatial goal identification (passability, reachability, Eq. 11, Alg. 3): median \
{smed:.1} ms, max {smax:.1} ms. Learning updates (descriptors and every gait's model): median \
{lmed:.1} ms, max {lmax:.1} ms. From new data to a new tour (each replan plus the goal \
identifications run since the previous one): median {gmed:.1} ms, max {gmax:.1} ms.</p>",
        sc = esc(&f.text("scenario")),
        strat = esc(&f.text("strategy")),
        ws = f.text("world_seed"),
        seed = f.text("seed"),
        expl = f.num("exploration_time_s"),
        term = esc(&f.text("termination")),
        driven = f.num("driven_m"),
        cells = f.text("observed_cells"),
        speed = f.num("speedup"),
        mw = f.num("mission_wall_s"),
        wall = f.num("wall_time_s"),
        rn = f.text("replans"),
        rmed = f.at(&["replan_latency_ms", "median"]),
        rmax = f.at(&["replan_latency_ms", "max"]),
        gmed = f.at(&["goals_to_tour_ms", "median"]),
        gmax = f.at(&["goals_to_tour_ms", "max"]),
        smed = f.at(&["goal_identification_ms", "spatial", "median"]),
        smax = f.at(&["goal_identification_ms", "spatial", "max"]),
        lmed = f.at(&["goal_identification_ms", "learning", "median"]),
        lmax = f.at(&["goal_identification_ms", "learning", "max"]),
    );
}

/// A replayed log (`strider replay`): no exploration, no tours.
fn replay_summary(h: &mut String, f: &Fields, log: &str) {
    let _ = write!(
        h,
        "<h1>Replay of <code>{}</code></h1><p>{:.0} s of recorded time mapped and learned in \
         {:.1} s wall ({:.0}× real time): {} cells mapped from {} scans. Learning updates: \
         median {:.1} ms, max {:.1} ms.</p>",
        esc(log),
        f.num("exploration_time_s"),
        f.num("mission_wall_s"),
        f.num("speedup"),
        f.text("observed_cells"),
        f.text("scans_fused"),
        f.at(&["goal_identification_ms", "learning", "median"]),
        f.at(&["goal_identification_ms", "learning", "max"]),
    );
}

/// The tour totals per navigation mode, then each tour's segments.
fn tour_tables(h: &mut String, tours: &[(String, Vec<TourResult>)]) {
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
        segments(h, name, modes);
    }
}

fn segments(h: &mut String, name: &str, modes: &[TourResult]) {
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

/// A field as its JSON text (empty when missing).
fn raw(v: &Value, k: &str) -> String {
    v.get(k).map_or(String::new(), |v| v.to_string())
}

/// Per gait: the sample counts and the class table.
fn models(h: &mut String, r: &Value) {
    h.push_str("<h2>Learned models</h2>");
    let Some(models) = r.get("models").and_then(|m| m.as_array()) else {
        return;
    };
    for m in models {
        let g = m.get("gait").and_then(|v| v.as_str()).unwrap_or("?");
        let _ = write!(
            h,
            "<h3>gait {}</h3><p>{} cost samples, learning set {}, {} terrain classes{}.</p>\
             <table><tr><th>class</th><th>dominant colour</th>\
             <th>cells</th><th>learning cells</th><th>cost</th><th>variance</th></tr>",
            esc(g),
            raw(m, "cost_samples"),
            raw(m, "learning_set"),
            raw(m, "classes"),
            // Without a ground truth (a replayed log) there is no H^GT to show.
            m.get("h_gt")
                .and_then(Value::as_f64)
                .map_or(String::new(), |x| format!(", H<sup>GT</sup> = {x:.3}")),
        );
        for c in m
            .get("class_table")
            .and_then(|v| v.as_array())
            .into_iter()
            .flatten()
        {
            class_row(h, c);
        }
        h.push_str("</table>");
    }
}

fn class_row(h: &mut String, c: &Value) {
    let num = |k: &str| c.get(k).and_then(|v| v.as_f64()).unwrap_or(f64::NAN);
    let colour = c
        .get("dominant_colour_bin")
        .and_then(|v| v.as_u64())
        .and_then(|b| COLOR_PROTOTYPES.get(b as usize))
        .map_or("–".to_string(), |p| p.0.to_string());
    let _ = write!(
        h,
        "<tr><td>{}</td><td>{}</td><td>{}</td><td>{}</td><td>{:.3}</td><td>{:.4}</td></tr>",
        raw(c, "id"),
        colour,
        raw(c, "cells"),
        raw(c, "learning_cells"),
        num("cost"),
        num("variance"),
    );
}

/// The figures, each with its axes in metres, its colour bar or legend, and its caption.
fn figures(h: &mut String, figures: &[MapFigure]) {
    if figures.is_empty() {
        return;
    }
    h.push_str("<h2>Figures</h2>");
    for (id, fig) in figures.iter().enumerate() {
        h.push_str(&fig.to_html(id));
    }
}
