//! The soak's tables: per strategy × world, missions, violations by kind, median exploration
//! time and wall time; the violations with the commands that rerun them; the summary line.

use std::collections::BTreeMap;
use std::fmt::Write;

use serde::Serialize;

use super::Soak;
use super::mission::MissionResult;
use super::plan::Coverage;
use super::violation::Kind;
use crate::stats::median;

/// One strategy × world of a soak.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct CellSummary {
    /// Strategy.
    pub strategy: String,
    /// Built-in world.
    pub scenario: String,
    /// Missions.
    pub missions: usize,
    /// Missions that broke each invariant, by kind.
    pub violations: BTreeMap<&'static str, usize>,
    /// Median exploration time of the missions that ran to their end, simulated s.
    pub median_exploration_time_s: Option<f64>,
    /// Median distance driven by them, m.
    pub median_driven_m: Option<f64>,
    /// True poses judged.
    pub poses_judged: u64,
    /// Of them, with the centre within the footprint radius of a true obstacle (counted only).
    pub poses_near_obstacles: u64,
    /// Goal sites outside the exploration bounds over the snapshots judged (counted only).
    pub goal_sites_outside_bounds: u64,
    /// Median wall time of a mission, s.
    pub median_wall_s: Option<f64>,
    /// Wall time of all its missions, s.
    pub wall_s: f64,
}

/// The cells of every strategy × world that ran, in coverage order.
pub fn cells(coverage: &[Coverage], results: &[MissionResult]) -> Vec<CellSummary> {
    let mut out = Vec::new();
    for c in coverage {
        for &w in &c.worlds {
            let mine: Vec<&MissionResult> = results
                .iter()
                .filter(|r| r.task.strategy == c.strategy && r.task.scenario == w)
                .collect();
            if mine.is_empty() {
                continue;
            }
            let violations = Kind::ALL
                .iter()
                .map(|&k| {
                    let n = mine
                        .iter()
                        .filter(|r| r.violations.iter().any(|v| v.kind == k))
                        .count();
                    (k.name(), n)
                })
                .collect();
            let times: Vec<f64> = mine
                .iter()
                .filter_map(|r| r.explored.as_ref().map(|e| e.exploration_time_s))
                .collect();
            let driven: Vec<f64> = mine
                .iter()
                .filter_map(|r| r.explored.as_ref().map(|e| e.driven_m))
                .collect();
            let walls: Vec<f64> = mine.iter().map(|r| r.wall_s).collect();
            out.push(CellSummary {
                strategy: c.strategy.to_string(),
                scenario: w.to_string(),
                missions: mine.len(),
                violations,
                median_exploration_time_s: median(&times),
                median_driven_m: median(&driven),
                poses_judged: mine.iter().map(|r| r.poses_judged).sum(),
                poses_near_obstacles: mine.iter().map(|r| r.poses_near_obstacles).sum(),
                goal_sites_outside_bounds: mine.iter().map(|r| r.goal_sites_outside_bounds).sum(),
                median_wall_s: median(&walls),
                wall_s: walls.iter().sum(),
            });
        }
    }
    out
}

fn opt(v: Option<f64>, digits: usize) -> String {
    v.map_or_else(|| "–".into(), |v| format!("{v:.digits$}"))
}

/// The soak as Markdown: the table, the worlds skipped, the violations, the summary line.
pub fn markdown(s: &Soak) -> String {
    let mut m = String::new();
    let _ = writeln!(m, "# Soak: invariants at scale\n\n`{}`\n", s.command);
    let kinds: Vec<&str> = Kind::ALL.iter().map(|k| k.name()).collect();
    let _ = writeln!(
        m,
        "| strategy | world | missions | {} | median exploration (s) | median driven (m) | poses judged | near obstacles | median wall (s) | wall (s) |",
        kinds.join(" | ")
    );
    let _ = writeln!(
        m,
        "|---|---|---:|{}---:|---:|---:|---:|---:|",
        "---:|".repeat(kinds.len())
    );
    for c in &s.cells {
        let v: Vec<String> = kinds.iter().map(|k| c.violations[k].to_string()).collect();
        let _ = writeln!(
            m,
            "| {} | {} | {} | {} | {} | {} | {} | {} | {} | {:.0} |",
            c.strategy,
            c.scenario,
            c.missions,
            v.join(" | "),
            opt(c.median_exploration_time_s, 1),
            opt(c.median_driven_m, 2),
            c.poses_judged,
            c.poses_near_obstacles,
            opt(c.median_wall_s, 2),
            c.wall_s
        );
    }
    let outside: u64 = s.cells.iter().map(|c| c.goal_sites_outside_bounds).sum();
    let _ = writeln!(
        m,
        "\nViolation columns count missions. *Near obstacles*: poses whose centre lies within the footprint radius of a true obstacle (the map's admissibility on the true elevation); the simulator allows it, so it is counted, not a violation. Goal sites listed outside the exploration bounds (counted, not a violation; a tour site there is one): {outside} over all snapshots.\n"
    );
    let _ = writeln!(m, "Worlds a strategy cannot run on:\n");
    for c in &s.coverage {
        for (w, why) in &c.skipped {
            let _ = writeln!(m, "- {} on {w}: {why}", c.strategy);
        }
    }
    let _ = writeln!(m, "\n## Violations\n");
    let mut any = false;
    for r in s.failures() {
        any = true;
        let _ = writeln!(m, "- {}", r.task);
        for v in &r.violations {
            let _ = writeln!(
                m,
                "  - {} ×{}: {}",
                v.kind.name(),
                v.count,
                v.examples.join("; ")
            );
        }
        let _ = writeln!(
            m,
            "  - rerun: `{}` (the same mission without the judge: `{}`)",
            r.task.rerun(),
            r.task.run_command()
        );
    }
    if !any {
        let _ = writeln!(m, "None.");
    }
    let _ = writeln!(m, "\n**{}** ({:.0} s wall)", s.summary, s.wall_s);
    m
}
