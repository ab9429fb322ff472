//! `strider run --strategy rbcm-greedy`: the Prágr19 explorer (Alg. 1) on a scenario whose
//! robot feels roll (`lab-track` with `hexapod-rss`), and its report.
//!
//! The explorer's parameters come from the scenario's `[strategy.rbcm-greedy]` section (see
//! `strider strategies`). Experts use the exponential kernel (Prágr19 §V-A's best) and are
//! refitted within bounds relative to the initial values: lengthscale ×[0.1, 10], σ_s²
//! ×[0.01, 25], σ_n² from σ_n²/100 up to σ_s², ≤ 200 iterations.
//!
//! Evaluation only (never seen by the explorer): the final Mcost is compared with the
//! scenario's terrain layer: per terrain, the mean predicted μ and σ over the traversable Mcost
//! cells on it, next to the terrain table's roll variance for the gait; the terrains are
//! *learned* when every easy terrain (flat, grass, carpet) is predicted cheaper than every hard
//! one (cubes, stairs), as Prágr19 §V-B checks.

use std::fmt;
use std::path::Path;
use std::time::Instant;

use anyhow::Result;
use strider_explore::Mission;
use strider_explore::rbcm_greedy::{RbcmGreedy, RbcmGreedyLog};
use strider_explore::registry::RbcmTable;
use strider_scenario::Scenario;

use super::report::{RbcmReport, TerrainRow, report};
use crate::io::write_json;
use crate::progress::Progress;
use crate::render::{Canvas, line_chart, palette, scalar_canvas};
use crate::run::{MissionRun, Recorded, RunRequest, learning_message, start};
use crate::stats::{max, min};
use crate::trial::{robot_spec, run_strategy};

/// Terrains Prágr19 §V-B expects to be learned as easy and as hard.
const EASY: [&str; 3] = ["flat", "grass", "carpet"];
const HARD: [&str; 2] = ["cubes", "stairs"];

/// A finished `strider run --strategy rbcm-greedy`.
pub type RbcmRun = MissionRun<RbcmReport>;

/// Per-terrain predictions of the final Mcost against the terrain table (module docs), and
/// whether the easy terrains are all predicted cheaper than the hard ones.
pub fn terrain_check(sc: &Scenario, ex: &RbcmGreedy) -> (Vec<TerrainRow>, bool) {
    let cm = ex.cost_map();
    let gait_name = &sc.robot.gaits[ex.params().gait.0 as usize].name;
    // Per terrain: sum of μ, sum of σ, cells.
    let mut acc: Vec<(f64, f64, usize)> = vec![(0.0, 0.0, 0); sc.world.terrains.len()];
    for k in 0..cm.rect.len() {
        if !cm.traversable[k] {
            continue;
        }
        let p = cm.rect.cell(k).center(cm.cell_size);
        let Some(w) = sc.world.index_at(p) else {
            continue;
        };
        if let Some(a) = acc.get_mut(sc.world.terrain[w] as usize)
            && cm.mean[k].is_finite()
        {
            a.0 += cm.mean[k];
            a.1 += cm.std[k];
            a.2 += 1;
        }
    }
    let rows: Vec<TerrainRow> = sc
        .world
        .terrains
        .iter()
        .zip(acc)
        .filter_map(|(tt, (sm, ss, n))| {
            let truth = tt.gaits.get(gait_name).map(|r| r.roll_variance);
            (n > 0 || truth.is_some()).then(|| TerrainRow {
                terrain: tt.name.clone(),
                cells: n,
                predicted_mean: (n > 0).then(|| sm / n as f64),
                predicted_std: (n > 0).then(|| ss / n as f64),
                roll_variance_truth: truth,
            })
        })
        .collect();
    let mean_of = |names: &[&str]| -> Vec<f64> {
        rows.iter()
            .filter(|r| names.contains(&r.terrain.as_str()))
            .filter_map(|r| r.predicted_mean)
            .collect()
    };
    let (easy, hard) = (mean_of(&EASY), mean_of(&HARD));
    let easy_max = max(&easy).unwrap_or(f64::NEG_INFINITY);
    let hard_min = min(&hard).unwrap_or(f64::INFINITY);
    let learned = easy.len() + hard.len() == EASY.len() + HARD.len() && easy_max < hard_min;
    (rows, learned)
}

/// The world, not the strategy, is at fault when no terrain makes the robot roll: run, and say
/// so.
fn warnings(sc: &Scenario) -> Vec<String> {
    let rolls = sc
        .world
        .terrains
        .iter()
        .any(|t| t.gaits.values().any(|r| r.roll_variance > 0.0));
    if rolls {
        return Vec::new();
    }
    vec![format!(
        "scenario {}: no terrain makes the robot roll, so the roll-variance cost is the same everywhere",
        sc.name
    )]
}

/// Runs `strider run --strategy rbcm-greedy`.
pub fn run(
    sc: &Scenario,
    req: &RunRequest,
    table: &RbcmTable,
    progress: &dyn Progress,
) -> Result<RbcmRun> {
    let wall = Instant::now();
    let warnings = warnings(sc);
    let mut params = table
        .explorer_params(&robot_spec(sc))
        .map_err(|e| anyhow::anyhow!("strategy rbcm-greedy: {e}"))?;
    start(req, &mut params.time_limit_s, progress)?;
    for w in &warnings {
        progress.warn(w);
    }
    let (mission, written) = run_strategy::<RbcmGreedy>(sc, params, req.seed, req.watch(), |p| {
        progress.at(p.time_s as u64, &learning_message(p));
    })?;
    let ex = mission.strategy();
    let (terrains, learned) = terrain_check(sc, ex);
    let mut report = report(sc, req, &mission, terrains, learned, wall);
    report.parameters = strider_explore::registry::typed::to_table(table);
    report.warnings = warnings;
    write_figures(&mission, ex.log(), req.out)?;
    let path = req.out.join("report.json");
    write_json(&path, &report)?;
    Ok(MissionRun {
        report,
        path,
        recorded: Recorded::of(written.as_ref(), req.mcap),
        last: mission.snapshot(true),
    })
}

impl fmt::Display for RbcmRun {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let r = &self.report;
        let (id, ex, p) = (&r.id, &r.explored, &r.planning_ms);
        if let Some(rec) = &self.recorded {
            writeln!(f, "{rec}")?;
        }
        let large = if p.large_map.cycles > 0 {
            format!(
                "median {:.2} ms over {} cycles",
                p.large_map.ms.median, p.large_map.cycles
            )
        } else {
            format!("none (largest map {} cells)", p.max_traversable_cells)
        };
        writeln!(
            f,
            "{}: rbcm-greedy ({} gait, λ_score {}) {} after {:.0} s simulated ({:.1} s wall), {:.1} m, {} pairs in {} experts; terrains learned: {}; planning median {:.2} ms (max {:.2}) over {} cycles, at ≥ {} cells: {large}",
            id.scenario,
            r.gait,
            r.lambda_score,
            ex.termination,
            ex.exploration_time_s,
            r.wall_s,
            ex.driven_m,
            r.learning_pairs,
            r.experts.len(),
            if r.terrains_learned { "yes" } else { "no" },
            p.all.ms.median,
            p.all.ms.max,
            p.all.cycles,
            p.large_map_min_cells,
        )?;
        let opt = |v: Option<f64>| v.map_or("-".into(), |x| format!("{x:.5}"));
        for t in &r.terrains {
            writeln!(
                f,
                "  {:<8} μ {:>9} σ {:>9} truth {:>7} ({} cells)",
                t.terrain,
                opt(t.predicted_mean),
                opt(t.predicted_std),
                opt(t.roll_variance_truth),
                t.cells
            )?;
        }
        write!(f, "report: {}", self.path.display())
    }
}

/// `mcost_mean.png`, `mcost_std.png` (final Mcost with the trajectory), `rbcm_planning.png`
/// (planning time and traversable cells per cycle).
fn write_figures(mission: &Mission<RbcmGreedy>, log: &RbcmGreedyLog, out: &Path) -> Result<()> {
    let cm = mission.strategy().cost_map();
    if cm.rect.is_empty() {
        return Ok(());
    }
    let scale = Canvas::auto_scale(cm.rect, 800);
    let traj: Vec<_> = mission
        .record()
        .trajectory
        .iter()
        .map(|s| strider_core::Point2::new(s.x, s.y))
        .collect();
    for (name, values) in [("mcost_mean.png", &cm.mean), ("mcost_std.png", &cm.std)] {
        let v: Vec<f32> = values.iter().map(|&x| x as f32).collect();
        let (mut c, _) = scalar_canvas(cm.rect, cm.cell_size, scale, &v, None);
        c.polyline(&traj, [255, 255, 255], 1);
        c.save(&out.join(name))?;
    }
    let total: Vec<f64> = log.plans.iter().map(|p| p.total_ms).collect();
    let cells: Vec<f64> = log
        .plans
        .iter()
        .map(|p| p.traversable_cells as f64 / 100.0)
        .collect();
    line_chart(
        &[(total, palette(0)), (cells, palette(1))],
        &[(20.0, palette(3))],
        "PLANNING CYCLE",
        "MS / CELLS/100",
    )
    .save(&out.join("rbcm_planning.png"))
}
