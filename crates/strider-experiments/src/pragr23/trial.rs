//! One trial of the Prágr23 escape experiment: a scenario's world in the simulator, the
//! `escape` or `rigid` mission on it, and the evaluation of which arena sections were explored.
//!
//! The mission never sees the scenario's world; the evaluation does: a *section* is the set of
//! cells of the rigid-obstacle configuration space (ground-truth admissible cells with every
//! apparent obstacle rigid) connected to one waypoint of the scenario's `sections` tour, and it
//! counts as explored when at least [`SECTION_EXPLORED_FRACTION`] of its cells are observed in the
//! mission's map.

use anyhow::{Result, bail};
use strider_core::Cell;
use strider_explore::FromParams;
use strider_explore::Mission;
use strider_explore::escape::{EscapeLog, EscapeMission, EscapeMode, EscapeParams};
use strider_explore::registry::Configured;
use strider_map::ElevationMap;
use strider_scenario::Scenario;
use strider_scenario::ground_truth::flood_fill;

use crate::trial::{configure, drive, robot_spec};

/// Fraction of a section's cells that must be mapped for it to count as explored.
pub const SECTION_EXPLORED_FRACTION: f64 = 0.5;

/// Escape-mission parameters from a scenario: the robot profile, the map and the strategy's
/// `[strategy.escape]` (or `[strategy.rigid]`) section, with `sets` overriding it.
pub fn escape_params(
    sc: &Scenario,
    mode: EscapeMode,
    sets: &[(String, String)],
) -> Result<EscapeParams> {
    let (_, configured) = configure(sc, mode.name(), sets)?;
    let Configured::Escape(mode, table) = configured else {
        bail!("{} is not a Prágr23 strategy", mode.name());
    };
    Ok(table.escape_params(&robot_spec(sc), mode)?)
}

/// One evaluated arena section.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct SectionResult {
    /// Cells of the section.
    pub cells: usize,
    /// Fraction observed at the end.
    pub observed_fraction: f64,
    /// Whether it counts as explored.
    pub explored: bool,
    /// Mission time at which it first counted as explored, s.
    pub explored_at_s: Option<f64>,
}

/// The sections of a scenario (see the module docs); empty when it has no `sections` tour.
pub fn sections(sc: &Scenario) -> Vec<Vec<Cell>> {
    let Some(tour) = sc.tours.iter().find(|t| t.name == "sections") else {
        return Vec::new();
    };
    let w = &sc.world;
    let adm = w.gt_admissible(sc.map.rho_obstacle, sc.map.r_robot);
    tour.waypoints
        .iter()
        .filter_map(|&p| w.index_at(p))
        .map(|k| {
            let fill = flood_fill(&adm, w.width(), w.height(), k);
            (0..fill.len())
                .filter(|&k| fill[k])
                .map(|k| w.rect.cell(k))
                .collect()
        })
        .collect()
}

/// Observed fraction of each section in `map`.
pub fn section_fractions(map: &ElevationMap, sections: &[Vec<Cell>]) -> Vec<f64> {
    sections
        .iter()
        .map(|s| {
            let seen = s.iter().filter(|&&c| map.is_observed(c)).count();
            seen as f64 / s.len().max(1) as f64
        })
        .collect()
}

/// A finished escape trial.
pub struct EscapeTrial {
    /// The mission (map, haptic model, predictor, final view).
    pub mission: Mission<EscapeMission>,
    /// Its log.
    pub log: EscapeLog,
    /// The sections.
    pub sections: Vec<SectionResult>,
    /// What was recorded, if the trial was.
    pub written: Option<strider_log::writer::WriteSummary>,
}

impl EscapeTrial {
    /// Number of sections explored.
    pub fn sections_explored(&self) -> usize {
        self.sections.iter().filter(|s| s.explored).count()
    }
}

/// Runs `params` on the scenario's world (simulator seeded with `seed`) until it ends or the
/// cancellation flag of `watch` is requested, recording to its MCAP file if any (see
/// [`drive`]); `progress` gets the mission about once per simulated second.
pub fn run_escape<'a>(
    sc: &Scenario,
    params: EscapeParams,
    seed: u64,
    watch: impl Into<crate::live::Watch<'a>>,
    mut progress: impl FnMut(&Mission<EscapeMission>),
) -> Result<EscapeTrial> {
    let secs = sections(sc);
    let mut at: Vec<Option<f64>> = vec![None; secs.len()];
    let mut mission = EscapeMission::mission(params)?;
    let t0 = 0.0;
    let mut tick = 0u64;
    let written = drive(sc, seed, &mut mission, watch, |m, _| {
        // Section times every 5 simulated seconds: the check walks every section cell.
        tick += 1;
        if tick.is_multiple_of(5) {
            let t = m.record().trajectory.last().map_or(t0, |s| s.t);
            for (k, f) in section_fractions(m.body().map(), &secs)
                .into_iter()
                .enumerate()
            {
                if at[k].is_none() && f >= SECTION_EXPLORED_FRACTION {
                    at[k] = Some(t);
                }
            }
        }
        progress(m);
    })?;
    let log = mission.strategy().log().clone();
    let fractions = section_fractions(mission.body().map(), &secs);
    let sections = secs
        .iter()
        .zip(fractions)
        .enumerate()
        .map(|(k, (s, f))| {
            let explored = f >= SECTION_EXPLORED_FRACTION;
            SectionResult {
                cells: s.len(),
                observed_fraction: f,
                explored,
                explored_at_s: at[k].or(explored.then_some(mission.record().exploration_time_s)),
            }
        })
        .collect();
    Ok(EscapeTrial {
        mission,
        log,
        sections,
        written,
    })
}
