//! `strider run` of a Prágr22 strategy: the mission (Alg. 1), the benchmark tours in every
//! navigation mode on the frozen map and models, the report and the figures.

use std::fmt;
use std::time::Instant;

use anyhow::{Result, bail};
use strider_explore::evaluate::{NavigationMode, TourResult};
use strider_explore::registry::Configured;
use strider_explore::{Mission, MissionLog, MissionProgress, TourExplorer};
use strider_scenario::Scenario;

use super::figures::write_figures;
use super::report::{
    GainEvaluations, GoalIdentificationMs, MedianMax, RunReport, models, replan_parts, tour_reports,
};
use crate::progress::Progress;
use crate::report::write_reports;
use crate::run::{Explored, MissionId, MissionRun, Recorded, RunRequest, start};
use crate::trial::{robot_spec, run_mission, run_tours};

/// A finished Prágr22 `strider run`.
pub type TourRun = MissionRun<RunReport>;

/// Runs the mission, the tours, and writes the report and figures into `req.out`.
pub fn run_tour(
    sc: &Scenario,
    req: &RunRequest,
    configured: &Configured,
    progress: &dyn Progress,
) -> Result<TourRun> {
    let wall = Instant::now();
    let Some(mut params) = configured.tour_mission(&robot_spec(sc), req.seed) else {
        bail!("{} is not a Prágr22 strategy", configured.name());
    };
    start(req, &mut params.time_limit_s, progress)?;
    let (mission, log, written) = run_mission(sc, params, req.seed, req.watch(), |p| {
        progress.at(p.time_s as u64, &goals_message(p));
    })?;
    // An interrupted mission's report is written at once, without the tours.
    let tours = if mission.interrupted() {
        Vec::new()
    } else {
        run_tours(
            sc,
            &mission,
            req.seed,
            &NavigationMode::ALL,
            |tour, mode| {
                progress.phase(&format!("tour {tour} with {} navigation", mode.name()));
            },
        )?
    };
    let figures = write_figures(&mission, &tours, req.out)?;
    let report = report(sc, req, configured, (&mission, &log), &tours, wall);
    let path = write_reports(req.out, &report, &figures, &tours)?;
    Ok(MissionRun {
        report,
        path,
        recorded: Recorded::of(written.as_ref(), req.mcap),
        last: mission.snapshot(true),
    })
}

/// The progress line of a Prágr22 mission.
fn goals_message(p: &MissionProgress) -> String {
    format!(
        "{} cells mapped, {} spatial + {} cost goals, {} learning pairs",
        p.observed_cells, p.spatial_goals, p.cost_goals, p.learning_set
    )
}

/// The report of a finished Prágr22 mission and its benchmark tours (none for the soak).
pub(crate) fn report(
    sc: &Scenario,
    req: &RunRequest,
    configured: &Configured,
    (mission, log): (&Mission<TourExplorer>, &MissionLog),
    tours: &[(String, Vec<TourResult>)],
    wall: Instant,
) -> RunReport {
    let record = mission.record();
    RunReport {
        id: MissionId::of(sc, req, configured.name()),
        parameters: configured.table(),
        explored: Explored::of(mission),
        scans_fused: mission.body().map().scan_count(),
        phase_wall_s: log.phase_wall_s,
        activity_s: log.activity_s,
        models: models(mission, log),
        tours: tour_reports(tours),
        stuck_events: log.stuck_events,
        turn_skipped_cost_samples: log.turn_skipped,
        information_gain_evaluations: GainEvaluations {
            fresh: log.gain_evaluated,
            incremental: log.gain_updated,
        },
        replans: log.replan_ms.len(),
        replan_latency_ms: MedianMax::of(&log.replan_ms),
        goals_to_tour_ms: MedianMax::of(&log.goals_to_tour_ms),
        replan_parts_ms: replan_parts(log),
        goal_identification_ms: GoalIdentificationMs {
            spatial: MedianMax::of(&log.spatial_goal_ms),
            learning: MedianMax::of(&log.learning_ms),
        },
        mission_wall_s: record.wall_s,
        speedup: record.exploration_time_s / record.wall_s.max(1e-9),
        wall_time_s: wall.elapsed().as_secs_f64(),
        trajectory: record.trajectory.clone(),
    }
}

impl fmt::Display for TourRun {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let r = &self.report;
        let (id, ex) = (&r.id, &r.explored);
        if let Some(rec) = &self.recorded {
            writeln!(f, "{rec}")?;
        }
        writeln!(
            f,
            "{} ({}): {} after {:.0} s simulated, {:.1} m driven, {} replans (median {:.1} ms, max {:.1} ms), {:.0}x real time, {:.1} s wall -> {}",
            id.scenario,
            id.strategy,
            ex.termination,
            ex.exploration_time_s,
            ex.driven_m,
            r.replans,
            r.replan_latency_ms.median,
            r.replan_latency_ms.max,
            r.speedup,
            r.wall_time_s,
            self.path.display()
        )?;
        write!(
            f,
            "  new data to new tour (goal identification + replan): median {:.1} ms, max {:.1} ms",
            r.goals_to_tour_ms.median, r.goals_to_tour_ms.max
        )?;
        for t in &r.tours {
            let parts: Vec<String> = t
                .modes
                .iter()
                .map(|m| {
                    format!(
                        "{} {:.0} s{}",
                        m.mode,
                        m.total_s,
                        if m.completed { "" } else { " (incomplete)" }
                    )
                })
                .collect();
            write!(f, "\n  tour {}: {}", t.name, parts.join(", "))?;
        }
        Ok(())
    }
}
