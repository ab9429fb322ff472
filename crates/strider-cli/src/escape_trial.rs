//! One trial of the thesis C4 escape experiment: a scenario's world in the simulator, the
//! `escape` or `rigid` mission on it, and the evaluation of which arena sections were explored.
//!
//! The mission never sees the scenario's world; the evaluation does: a *section* is the set of
//! cells of the rigid-obstacle configuration space (ground-truth admissible cells with every
//! apparent obstacle rigid) connected to one waypoint of the scenario's `sections` tour, and it
//! counts as explored when at least [`SECTION_EXPLORED_FRACTION`] of its cells are observed in the
//! mission's map.

use crate::trial::num;
use anyhow::{Context, Result, bail};
use strider_core::Cell;
use strider_explore::escape::force_predictor::{DescriptorKind, PredictorParams};
use strider_explore::escape::{EscapeLog, EscapeMission, EscapeMode, EscapeParams};
use strider_map::ElevationMap;
use strider_map::rect::WorldRect;
use strider_scenario::Scenario;
use strider_scenario::ground_truth::flood_fill;
use strider_sim::Simulator;

/// Fraction of a section's cells that must be mapped for it to count as explored.
pub const SECTION_EXPLORED_FRACTION: f64 = 0.5;

/// Escape-mission parameters from a scenario: the robot profile, the map and the `[strategy]`
/// table (C4 Table 3 names: `f_trav`, `sigma_sensor_sq`, `sigma_0_sq`, `gp_noise_variance`,
/// `gp_signal_variance`, `gp_lengthscale`, `learn_hz`, `i_thr_predict`, `r_hist`, and
/// `descriptor` = `lab` or `hist8`).
pub fn escape_params(sc: &Scenario, mode: EscapeMode) -> Result<EscapeParams> {
    let Some(gait) = sc.robot.gaits.first() else {
        bail!(
            "scenario {}: robot profile {} has no gait",
            sc.name,
            sc.robot.name
        );
    };
    let hfov = crate::trial::sensor_hfovs(&sc.robot);
    let b = &sc.bounds;
    let mut p = EscapeParams::new(
        mode,
        sc.map.clone(),
        gait.max_speed,
        hfov,
        Some(WorldRect::new(b.min, b.max)),
    );
    p.time_limit_s = sc.time_limit_s;
    let t = &sc.strategy;
    let descriptor = match t.get("descriptor").and_then(|v| v.as_str()) {
        None => DescriptorKind::LabAb,
        Some(s) => DescriptorKind::parse(s)
            .with_context(|| format!("strategy.descriptor {s:?}: expected lab or hist8"))?,
    };
    let base = match descriptor {
        DescriptorKind::LabAb => PredictorParams::lab(),
        DescriptorKind::Histogram8 => PredictorParams::histogram(),
    };
    p.predictor = PredictorParams {
        noise_variance: num(t, "gp_noise_variance", base.noise_variance),
        signal_variance: num(t, "gp_signal_variance", base.signal_variance),
        lengthscale: num(t, "gp_lengthscale", base.lengthscale),
        learn_hz: num(t, "learn_hz", base.learn_hz),
        entropy_threshold: num(t, "i_thr_predict", base.entropy_threshold),
        r_hist: num(t, "r_hist", base.r_hist),
        ..base
    };
    p.haptic.f_trav = num(t, "f_trav", p.haptic.f_trav);
    p.haptic.sigma_sensor2 = num(t, "sigma_sensor_sq", p.haptic.sigma_sensor2);
    p.haptic.sigma0_2 = num(t, "sigma_0_sq", p.haptic.sigma0_2);
    Ok(p)
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
    pub mission: EscapeMission,
    /// Its log.
    pub log: EscapeLog,
    /// The sections.
    pub sections: Vec<SectionResult>,
}

impl EscapeTrial {
    /// Number of sections explored.
    pub fn sections_explored(&self) -> usize {
        self.sections.iter().filter(|s| s.explored).count()
    }
}

/// Runs `params` on the scenario's world (simulator seeded with `seed`); `progress` gets the
/// mission about once per simulated second.
pub fn run_escape(
    sc: &Scenario,
    params: EscapeParams,
    seed: u64,
    mut progress: impl FnMut(&EscapeMission),
) -> Result<EscapeTrial> {
    let mut sim = Simulator::new(sc, seed)?;
    let secs = sections(sc);
    let mut at: Vec<Option<f64>> = vec![None; secs.len()];
    let mut mission = EscapeMission::new(params)?;
    let t0 = 0.0;
    let mut tick = 0u64;
    let log = mission
        .run(&mut sim, |m| {
            // Section times every 5 simulated seconds: the check walks every section cell.
            tick += 1;
            if tick.is_multiple_of(5) {
                let t = m.log().run.trajectory.last().map_or(t0, |s| s.t);
                for (k, f) in section_fractions(m.map(), &secs).into_iter().enumerate() {
                    if at[k].is_none() && f >= SECTION_EXPLORED_FRACTION {
                        at[k] = Some(t);
                    }
                }
            }
            progress(m);
        })?
        .clone();
    let fractions = section_fractions(mission.map(), &secs);
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
                explored_at_s: at[k].or(explored.then_some(log.run.exploration_time_s)),
            }
        })
        .collect();
    Ok(EscapeTrial {
        mission,
        log,
        sections,
    })
}
