//! `strider run --strategy escape|rigid`: the Prágr23 escape mission (Alg. 2) or the
//! rigid-obstacle baseline on a scenario in the simulator, and its report: sections explored,
//! the explored area and the apparent-obstacle cell states over time (Prágr23 Figs. 11–12),
//! bumper contacts, goals, and PNG figures.

use std::fmt;
use std::time::Instant;

use anyhow::Result;
use serde::Serialize;
use strider_explore::Mission;
use strider_explore::escape::force_predictor::describe;
use strider_explore::escape::{
    ContactEvent, EscapeLog, EscapeMission, EscapeMode, GoalEvent, TimelineSample,
};
use strider_explore::kernel::TrajectorySample;
use strider_explore::registry::EscapeTable;
use strider_scenario::Scenario;

use super::figures::write_figures;
use super::trial::{EscapeTrial, SECTION_EXPLORED_FRACTION, SectionResult, run_escape};
use crate::io::write_json;
use crate::progress::Progress;
use crate::run::{Explored, MissionId, MissionRun, Recorded, RunRequest, start};
use crate::trial::robot_spec;

/// The apparent-obstacle cell states at one time (Prágr23 Fig. 11).
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct CellStateSample {
    /// Mission time, s.
    pub t: f64,
    /// Explored area, m².
    pub explored_m2: f64,
    /// Certain and traversable.
    pub certain_traversable: usize,
    /// Uncertain and traversable.
    pub uncertain_traversable: usize,
    /// Uncertain and untraversable.
    pub uncertain_untraversable: usize,
    /// Certain and untraversable.
    pub certain_untraversable: usize,
    /// Cells with a haptic measurement.
    pub haptic_cells: usize,
}

impl From<&TimelineSample> for CellStateSample {
    fn from(s: &TimelineSample) -> Self {
        Self {
            t: s.t,
            explored_m2: s.explored_m2,
            certain_traversable: s.states.certain_traversable,
            uncertain_traversable: s.states.uncertain_traversable,
            uncertain_untraversable: s.states.uncertain_untraversable,
            certain_untraversable: s.states.certain_untraversable,
            haptic_cells: s.haptic_cells,
        }
    }
}

/// A cell the bumper measured.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct HapticReport {
    /// Cell centre, m.
    pub x: f64,
    /// Cell centre, m.
    pub y: f64,
    /// Fused force to push through, N.
    pub force: f64,
    /// Its variance, N².
    pub variance: f64,
    /// Measurements fused.
    pub count: u32,
    /// The force predictor's descriptor of the cell.
    pub descriptor: Option<Vec<f64>>,
}

/// `report.json` of `strider run --strategy escape|rigid`.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct EscapeReport {
    /// Which mission (strategy `escape` or `rigid`).
    #[serde(flatten)]
    pub id: MissionId,
    /// The strategy's parameters.
    pub parameters: toml::Table,
    /// How the exploration ended.
    #[serde(flatten)]
    pub explored: Explored,
    /// Sections explored.
    pub sections_explored: usize,
    /// The fraction of a section that must be mapped.
    pub section_explored_fraction: f64,
    /// Every section.
    pub sections: Vec<SectionResult>,
    /// (t, explored m²).
    pub explored_area_over_time: Vec<[f64; 2]>,
    /// The cell states over time.
    pub cell_states_over_time: Vec<CellStateSample>,
    /// Bumper contacts.
    pub contacts: Vec<ContactEvent>,
    /// Goals.
    pub goals: Vec<GoalEvent>,
    /// Pushes.
    pub pushes: usize,
    /// Sampling manoeuvres.
    pub samplings: usize,
    /// Predictor relearns.
    pub relearns: usize,
    /// Cells with a haptic measurement.
    pub haptic_cells: usize,
    /// Those cells.
    pub haptic: Vec<HapticReport>,
    /// Training set of the force predictor.
    pub predictor_training_set: usize,
    /// Wall time of the mission, s.
    pub mission_wall_s: f64,
    /// Wall time of the command, s.
    pub wall_time_s: f64,
    /// The trajectory.
    pub trajectory: Vec<TrajectorySample>,
}

/// A finished `strider run --strategy escape|rigid`.
pub type EscapeRun = MissionRun<EscapeReport>;

/// Runs `strider run` for the `escape` and `rigid` strategies.
pub fn run(
    sc: &Scenario,
    req: &RunRequest,
    mode: EscapeMode,
    table: &EscapeTable,
    progress: &dyn Progress,
) -> Result<EscapeRun> {
    let wall = Instant::now();
    let mut params = table
        .escape_params(&robot_spec(sc), mode)
        .map_err(|e| anyhow::anyhow!("strategy {}: {e}", mode.name()))?;
    start(req, &mut params.time_limit_s, progress)?;
    let trial = run_escape(
        sc,
        params,
        req.seed,
        req.watch(),
        |m: &Mission<EscapeMission>| {
            let l = m.strategy().log();
            progress.at(
                l.timeline.last().map_or(0.0, |s| s.t) as u64,
                &format!(
                    "{} cells mapped, {} haptic cells, {} contacts",
                    m.body().map().observed_count(),
                    m.strategy().haptic().len(),
                    l.contacts.len()
                ),
            );
        },
    )?;
    write_figures(&trial.mission, &trial.log, req.out)?;
    let report = report(sc, req, (mode, table), &trial, wall);
    let path = req.out.join("report.json");
    write_json(&path, &report)?;
    Ok(MissionRun {
        report,
        path,
        recorded: Recorded::of(trial.written.as_ref(), req.mcap),
        last: trial.mission.snapshot(true),
    })
}

fn report(
    sc: &Scenario,
    req: &RunRequest,
    (mode, table): (EscapeMode, &EscapeTable),
    trial: &EscapeTrial,
    wall: Instant,
) -> EscapeReport {
    escape_report(
        MissionId::of(sc, req, mode.name()),
        table,
        (&trial.mission, &trial.log),
        trial.sections.clone(),
        wall,
    )
}

/// The report of a finished escape mission whose `log` and judged `sections` are given (a
/// trial's, or the soak's judged at the end).
pub(crate) fn escape_report(
    id: MissionId,
    table: &EscapeTable,
    (mission, log): (&Mission<EscapeMission>, &EscapeLog),
    sections: Vec<SectionResult>,
    wall: Instant,
) -> EscapeReport {
    let (run, esc) = (mission.record(), mission.strategy());
    let map = mission.body().map();
    EscapeReport {
        id,
        parameters: strider_explore::registry::typed::to_table(table),
        explored: Explored::of(mission),
        sections_explored: sections.iter().filter(|s| s.explored).count(),
        section_explored_fraction: SECTION_EXPLORED_FRACTION,
        sections,
        explored_area_over_time: log.timeline.iter().map(|s| [s.t, s.explored_m2]).collect(),
        cell_states_over_time: log.timeline.iter().map(CellStateSample::from).collect(),
        contacts: log.contacts.clone(),
        goals: log.goals.clone(),
        pushes: log.pushes,
        samplings: log.samplings,
        relearns: log.relearns,
        haptic_cells: esc.haptic().len(),
        haptic: esc
            .haptic()
            .cells()
            .iter()
            .map(|(c, h)| {
                let p = c.center(map.cell_size());
                HapticReport {
                    x: p.x,
                    y: p.y,
                    force: h.force,
                    variance: h.variance,
                    count: h.count,
                    descriptor: describe(map, *c, &esc.params().predictor),
                }
            })
            .collect(),
        predictor_training_set: esc.predictor().len(),
        mission_wall_s: run.wall_s,
        wall_time_s: wall.elapsed().as_secs_f64(),
        trajectory: run.trajectory.clone(),
    }
}

impl fmt::Display for EscapeRun {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let r = &self.report;
        let (id, ex) = (&r.id, &r.explored);
        if let Some(rec) = &self.recorded {
            writeln!(f, "{rec}")?;
        }
        write!(
            f,
            "{} ({}): {} after {:.0} s simulated, {:.1} m driven, {}/{} sections explored, {} contacts ({} corrected), {:.1} s wall -> {}",
            id.scenario,
            id.strategy,
            ex.termination,
            ex.exploration_time_s,
            ex.driven_m,
            r.sections_explored,
            r.sections.len(),
            r.contacts.len(),
            r.contacts.iter().filter(|c| c.corrected).count(),
            r.wall_time_s,
            self.path.display()
        )
    }
}
