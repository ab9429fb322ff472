//! The report `strider run` writes for a mission, built from a soak mission, and its checks:
//! it serialises to JSON and parses back to the same value, every number in it is finite, and
//! its counts agree with each other.
//!
//! The reports are those of `strider run` without the benchmark tours (the soak does not drive
//! them) and, for `escape` and `rigid`, without the times at which sections were first
//! explored (`explored_at_s` is the end of the mission for a section explored by then).

use std::path::Path;
use std::time::Instant;

use serde::Serialize;
use strider_explore::escape::EscapeMission;
use strider_explore::kernel::TrajectorySample;
use strider_explore::rbcm_greedy::RbcmGreedy;
use strider_explore::registry::{Configured, EscapeTable, RbcmTable, typed};
use strider_explore::{Mission, TourExplorer};
use strider_scenario::Scenario;

use super::finite::NonFinite;
use super::plan::Task;
use super::violation::{Findings, Kind};
use crate::pragr19::{self, report::RbcmReport};
use crate::pragr22::report::RunReport;
use crate::pragr23::trial::{
    SECTION_EXPLORED_FRACTION, SectionResult, section_fractions, sections,
};
use crate::pragr23::{EscapeReport, escape_report};
use crate::run::{Explored, MissionId, RunRequest};

/// What a report's counts are checked against.
pub struct Bounds {
    /// The mission's time limit, s.
    pub limit_s: f64,
    /// One control step, s.
    pub step_s: f64,
    /// Map cells covering the world (with a cell of margin on each side).
    pub map_cells: usize,
}

impl Bounds {
    /// The bounds of a mission of `limit_s` with control step `step_s` on `sc`'s world.
    pub fn of(sc: &Scenario, limit_s: f64, step_s: f64) -> Self {
        let e = sc.world.extent();
        let cs = sc.map.cell_size;
        let side = |len: f64| ((len / cs).ceil().max(0.0) as usize).saturating_add(2);
        Self {
            limit_s,
            step_s,
            map_cells: side(e.max.x - e.min.x).saturating_mul(side(e.max.y - e.min.y)),
        }
    }
}

/// The soak judges whole missions: nothing cancels one midway.
static NEVER_CANCELLED: std::sync::LazyLock<crate::cancel::Cancel> =
    std::sync::LazyLock::new(crate::cancel::Cancel::new);

/// The request `strider run` would have had for `task`.
fn request(task: &Task) -> RunRequest<'_> {
    RunRequest {
        scenario: task.scenario,
        world_seed: task.world_seed,
        strategy: task.strategy,
        sets: &[],
        seed: task.seed,
        time_limit: Some(task.time_limit_s),
        out: Path::new(""),
        mcap: None,
        live: None,
        rate: None,
        cancel: &NEVER_CANCELLED,
    }
}

/// The report of a Prágr22 mission: `strider run`'s own, without tours.
pub fn tour(
    sc: &Scenario,
    task: &Task,
    configured: &Configured,
    mission: &Mission<TourExplorer>,
    wall: Instant,
) -> RunReport {
    let log = mission.strategy().log();
    crate::pragr22::mission_report(sc, &request(task), configured, (mission, log), &[], wall)
}

/// The counts of a Prágr22 report that must agree.
pub fn tour_counts(r: &RunReport, f: &mut Findings) {
    for m in &r.models {
        // The table lists the classes represented on the map, `classes` counts the IGNG's.
        if m.class_table.len() > m.classes {
            f.add(Kind::Report, || {
                format!(
                    "model {}: {} classes but {} rows in the class table",
                    m.gait,
                    m.classes,
                    m.class_table.len()
                )
            });
        }
        if m.measured_cells > r.explored.observed_cells {
            f.add(Kind::Report, || {
                format!(
                    "model {}: {} measured cells of {} observed",
                    m.gait, m.measured_cells, r.explored.observed_cells
                )
            });
        }
        if let Some(c) = m.class_table.iter().find(|c| c.learning_cells > c.cells) {
            f.add(Kind::Report, || {
                format!(
                    "model {} class {}: {} learning cells of {} cells",
                    m.gait, c.id, c.learning_cells, c.cells
                )
            });
        }
    }
}

/// The report of a Prágr19 mission (`pragr19::run`'s).
pub fn rbcm(
    sc: &Scenario,
    task: &Task,
    table: &RbcmTable,
    mission: &Mission<RbcmGreedy>,
    wall: Instant,
) -> RbcmReport {
    let (terrains, learned) = pragr19::terrain_check(sc, mission.strategy());
    let mut r = pragr19::report::report(sc, &request(task), mission, terrains, learned, wall);
    r.parameters = typed::to_table(table);
    r
}

/// The counts of a Prágr19 report that must agree.
pub fn rbcm_counts(r: &RbcmReport, f: &mut Findings) {
    let points: usize = r.experts.iter().map(|e| e.points).sum();
    if points != r.learning_pairs {
        f.add(Kind::Report, || {
            format!(
                "{} learning pairs but {points} points in the experts",
                r.learning_pairs
            )
        });
    }
}

/// The report of a Prágr23 mission (`pragr23::run`'s, sections judged at the end).
pub fn escape(
    sc: &Scenario,
    task: &Task,
    table: &EscapeTable,
    mission: &Mission<EscapeMission>,
    wall: Instant,
) -> EscapeReport {
    let (run, esc) = (mission.record(), mission.strategy());
    let log = esc.log();
    let map = mission.body().map();
    let secs = sections(sc);
    let sections: Vec<SectionResult> = secs
        .iter()
        .zip(section_fractions(map, &secs))
        .map(|(s, f)| {
            let explored = f >= SECTION_EXPLORED_FRACTION;
            SectionResult {
                cells: s.len(),
                observed_fraction: f,
                explored,
                explored_at_s: explored.then_some(run.exploration_time_s),
            }
        })
        .collect();
    escape_report(
        MissionId::of(sc, &request(task), esc.params().mode.name()),
        table,
        (mission, log),
        sections,
        wall,
    )
}

/// The counts of a Prágr23 report that must agree.
pub fn escape_counts(r: &EscapeReport, f: &mut Findings) {
    if r.haptic_cells != r.haptic.len() {
        f.add(Kind::Report, || {
            format!(
                "{} haptic cells but {} listed",
                r.haptic_cells,
                r.haptic.len()
            )
        });
    }
    if let Some(s) = r
        .sections
        .iter()
        .find(|s| !(0.0..=1.0).contains(&s.observed_fraction))
    {
        f.add(Kind::Report, || {
            format!(
                "a section observed to a fraction of {}",
                s.observed_fraction
            )
        });
    }
}

/// Checks `report` (with its `explored` part and `trajectory`): the JSON round trip, finite
/// numbers, and the counts every mission report has.
pub fn check<R: Serialize>(
    report: &R,
    explored: &Explored,
    trajectory: &[TrajectorySample],
    b: &Bounds,
    f: &mut Findings,
) {
    f.check(Kind::Report, round_trip(report));
    match NonFinite::of(report) {
        Ok(n) if n.count > 0 => f.add(Kind::Report, || n.to_string()),
        Ok(_) => {}
        Err(e) => f.add(Kind::Report, || format!("cannot walk the report: {e}")),
    }
    let t = explored.exploration_time_s;
    if !(t >= 0.0 && t <= b.limit_s + b.step_s + 1e-6) {
        f.add(Kind::Report, || {
            format!(
                "exploration time {t} s outside 0..{} s (time limit + one control step)",
                b.limit_s + b.step_s
            )
        });
    }
    if explored.observed_cells > b.map_cells {
        f.add(Kind::Report, || {
            format!(
                "{} observed cells, more than the {} map cells covering the world",
                explored.observed_cells, b.map_cells
            )
        });
    }
    if explored.driven_m.is_nan() || explored.driven_m < 0.0 {
        f.add(Kind::Report, || format!("{} m driven", explored.driven_m));
    }
    let late = t + b.step_s + 1e-6;
    if let Some(w) = trajectory
        .windows(2)
        .find(|w| w[1].t.is_nan() || w[1].t < w[0].t || w[1].t > late)
    {
        f.add(Kind::Report, || {
            format!(
                "trajectory sample at {} s after one at {} s (exploration time {t} s)",
                w[1].t, w[0].t
            )
        });
    }
}

/// `Err` unless `report` serialises to JSON text that parses back to the value it was
/// written from. Numbers compare as the same `f32` or within two `f64` ulps: an `f32` is
/// written as its shortest decimal, which parses back to a different `f64` than the `f32`'s
/// own, and `serde_json`'s parser without its `float_roundtrip` feature may land one ulp off.
fn round_trip<R: Serialize>(report: &R) -> Result<(), String> {
    let value = serde_json::to_value(report).map_err(|e| format!("to JSON: {e}"))?;
    let text = serde_json::to_string(report).map_err(|e| format!("to JSON text: {e}"))?;
    let back: serde_json::Value =
        serde_json::from_str(&text).map_err(|e| format!("the JSON does not parse back: {e}"))?;
    same(&value, &back, &mut String::new())
}

/// `Err` naming the first place where `a` and `b` differ (see [`round_trip`]).
fn same(a: &serde_json::Value, b: &serde_json::Value, path: &mut String) -> Result<(), String> {
    use serde_json::Value as V;
    let differ = |path: &str| {
        Err(format!(
            "the JSON parsed back differs at {}: {a} became {b}",
            if path.is_empty() { "." } else { path }
        ))
    };
    match (a, b) {
        (V::Number(x), V::Number(y)) => {
            let (x, y) = (x.as_f64(), y.as_f64());
            let ok = x == y
                || x.zip(y)
                    .is_some_and(|(x, y)| x as f32 == y as f32 || within_ulps(x, y, 2));
            if ok { Ok(()) } else { differ(path) }
        }
        (V::Array(x), V::Array(y)) if x.len() == y.len() => {
            for (i, (x, y)) in x.iter().zip(y).enumerate() {
                let n = path.len();
                path.push_str(&format!("[{i}]"));
                same(x, y, path)?;
                path.truncate(n);
            }
            Ok(())
        }
        (V::Object(x), V::Object(y)) if x.len() == y.len() => {
            for ((k, x), (l, y)) in x.iter().zip(y) {
                if k != l {
                    return differ(path);
                }
                let n = path.len();
                path.push('.');
                path.push_str(k);
                same(x, y, path)?;
                path.truncate(n);
            }
            Ok(())
        }
        _ if a == b => Ok(()),
        _ => differ(path),
    }
}

/// Whether finite `x` and `y` are at most `n` representable `f64`s apart.
fn within_ulps(x: f64, y: f64, n: u32) -> bool {
    let mut z = x.min(y);
    for _ in 0..n {
        z = z.next_up();
    }
    x.is_finite() && y.is_finite() && x.max(y) <= z
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::run::Explored;

    fn explored(t: f64, cells: usize) -> Explored {
        Explored {
            termination: "TimeLimit".into(),
            exploration_time_s: t,
            driven_m: 1.0,
            observed_cells: cells,
            completion: crate::cancel::Completion::of(false),
        }
    }

    fn kinds(f: Findings) -> Vec<(Kind, u64)> {
        f.into_sorted().iter().map(|v| (v.kind, v.count)).collect()
    }

    #[test]
    fn a_report_with_a_nan_or_contradicting_counts_is_a_violation() {
        let b = Bounds {
            limit_s: 60.0,
            step_s: 0.05,
            map_cells: 100,
        };
        let traj = [
            TrajectorySample {
                t: 0.0,
                x: 0.0,
                y: 0.0,
                gait: 0,
            },
            TrajectorySample {
                t: 0.5,
                x: 0.0,
                y: 0.0,
                gait: 0,
            },
        ];
        let good = explored(60.05, 100);
        let mut f = Findings::default();
        check(&good, &good, &traj, &b, &mut f);
        assert!(f.is_empty(), "{f:?}");

        let mut nan = explored(60.0, 10);
        nan.driven_m = f64::NAN;
        let mut f = Findings::default();
        check(&nan, &nan, &traj, &b, &mut f);
        let v = f.clone().into_sorted();
        assert!(
            v[0].examples.iter().any(|e| e.contains("driven_m (NaN)")),
            "{v:?}"
        );
        assert_eq!(kinds(f), [(Kind::Report, 2)]);

        let mut f = Findings::default();
        let late = explored(61.0, 101);
        check(&late, &late, &traj, &b, &mut f);
        assert_eq!(kinds(f), [(Kind::Report, 2)]);
    }

    #[test]
    fn a_round_trip_tolerates_f32_and_last_ulp_but_not_more() {
        #[derive(serde::Serialize)]
        struct R {
            a: f32,
            b: f64,
        }
        assert_eq!(
            round_trip(&R {
                a: 0.1,
                b: 123.74120400000001
            }),
            Ok(())
        );
        use serde_json::json;
        assert!(
            same(
                &json!({"x": [1.0, 2.0]}),
                &json!({"x": [1.0, 2.0]}),
                &mut String::new()
            )
            .is_ok()
        );
        let e = same(
            &json!({"x": [1.0, 2.0]}),
            &json!({"x": [1.0, 2.001]}),
            &mut String::new(),
        );
        assert!(e.unwrap_err().contains(".x[1]"));
        assert!(same(&json!({"x": 1}), &json!({"y": 1}), &mut String::new()).is_err());
        assert!(same(&json!(null), &json!(0.0), &mut String::new()).is_err());
        assert!(within_ulps(1.0, 1.0f64.next_up().next_up(), 2));
        assert!(!within_ulps(1.0, 1.0f64.next_up().next_up().next_up(), 2));
    }
}
