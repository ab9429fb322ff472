//! The strategy registry: every exploration method on the mission kernel, with its paper, its
//! typed parameters and what it needs of the robot. A strategy is chosen by name, configured
//! from a scenario's `[strategy.<name>]` table and `key=value` overrides, checked against the
//! robot it is to drive, and built into a [`Mission`].

pub mod escape;
pub mod rbcm;
pub mod tour;
pub mod typed;

use crate::escape::{EscapeMission, EscapeMode};
use crate::kernel::{BodyParams, FromParams, Mission, MissionError, Strategy};
use crate::params::Strategy as Planner;
use crate::rbcm_greedy::RbcmGreedy;
use crate::tour_explorer::TourExplorer;
use strider_core::GaitSpec;
use strider_map::MapParams;
use strider_map::rect::WorldRect;
use typed::{ParamDoc, ParamError, StrategyParams};

pub use escape::EscapeTable;
pub use rbcm::RbcmTable;
pub use tour::TourParams;

/// What a strategy needs to know about the robot and the task (a scenario's robot profile,
/// map parameters, bounds and time limit, or a real robot's configuration).
#[derive(Clone, Debug, PartialEq)]
pub struct RobotSpec {
    /// The robot's name, for messages.
    pub name: String,
    /// Its gaits.
    pub gaits: Vec<GaitSpec>,
    /// Horizontal field of view of each range sensor, degrees (360: omnidirectional).
    pub sensor_hfov_deg: Vec<f64>,
    /// Map parameters.
    pub map: MapParams,
    /// Exploration bounds.
    pub bounds: Option<WorldRect>,
    /// Mission time limit, s.
    pub time_limit_s: f64,
    /// It has a haptic bumper.
    pub bumper: bool,
    /// Rate of its proprioception (roll, bumper, power), Hz.
    pub proprio_rate_hz: f64,
    /// Rate of its pose stream, Hz.
    pub pose_rate_hz: f64,
}

/// The strategies of the registry.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum StrategyId {
    /// Prágr22 Alg. 1: spatial and cost-model goals in an open GTSP tour.
    Gtsp,
    /// The same goals, cheapest next.
    Greedy,
    /// Spatial goals only, reactive gait.
    SpatialOnly,
    /// Prágr19 Alg. 1: RBCM of GP experts, variance-driven greedy goals.
    RbcmGreedy,
    /// Prágr23 Alg. 2: learning the force to push through apparent obstacles.
    Escape,
    /// C4's baseline: every apparent obstacle is rigid.
    Rigid,
}

/// One strategy of the registry.
#[derive(Clone, Copy, Debug)]
pub struct StrategyInfo {
    /// Which.
    pub id: StrategyId,
    /// Its name (`--strategy`, `[strategy.<name>]`).
    pub name: &'static str,
    /// The paper it comes from, cited in full.
    pub paper: &'static str,
    /// The paper's short key, as the parameter docs cite it.
    pub key: &'static str,
    /// One line on what it does.
    pub summary: &'static str,
    /// It needs a haptic bumper.
    pub needs_bumper: bool,
}

const PRAGR_2022: &str = "M. Prágr, J. Bayer, J. Faigl: Autonomous robotic exploration with simultaneous environment and traversability models learning. Frontiers in Robotics and AI 9, 2022. doi:10.3389/frobt.2022.910113";
const PRAGR_2019: &str = "M. Prágr et al.: Online incremental learning of the terrain traversal cost in autonomous exploration. Robotics: Science and Systems (RSS), 2019. doi:10.15607/RSS.2019.XV.040";
const PRAGR_2023: &str = "M. Prágr et al.: Autonomous exploration with online learning of traversable yet visually rigid obstacles. Autonomous Robots 47, 161-180, 2023. doi:10.1007/s10514-022-10075-4";

/// Every strategy, in the order `strider strategies` lists them.
pub const STRATEGIES: &[StrategyInfo] = &[
    StrategyInfo {
        id: StrategyId::Gtsp,
        name: "gtsp",
        paper: PRAGR_2022,
        key: "Prágr22",
        summary: "per-gait GP cost models with IGNG classes; spatial and cost-model goals ordered by an open GTSP tour; gait selection",
        needs_bumper: false,
    },
    StrategyInfo {
        id: StrategyId::Greedy,
        name: "greedy",
        paper: PRAGR_2022,
        key: "Prágr22",
        summary: "the gtsp explorer's goals and models, cheapest goal next (the paper's myopic baseline)",
        needs_bumper: false,
    },
    StrategyInfo {
        id: StrategyId::SpatialOnly,
        name: "spatial-only",
        paper: PRAGR_2022,
        key: "Prágr22",
        summary: "spatial goals only, flat planning costs and the fastest gait; learns incidentally (the paper's baseline)",
        needs_bumper: false,
    },
    StrategyInfo {
        id: StrategyId::RbcmGreedy,
        name: "rbcm-greedy",
        paper: PRAGR_2019,
        key: "Prágr19",
        summary: "robust Bayesian committee of GP experts on a shape + Lab descriptor, roll-variance cost, variance-driven greedy goals",
        needs_bumper: false,
    },
    StrategyInfo {
        id: StrategyId::Escape,
        name: "escape",
        paper: PRAGR_2023,
        key: "Prágr23",
        summary: "learns from a haptic bumper the force to push through apparent obstacles and explores past the pushable ones",
        needs_bumper: true,
    },
    StrategyInfo {
        id: StrategyId::Rigid,
        name: "rigid",
        paper: PRAGR_2023,
        key: "Prágr23",
        summary: "every apparent obstacle is rigid; spatial goals only (the paper's baseline)",
        needs_bumper: false,
    },
];

/// What can go wrong choosing, configuring or building a strategy; one line each.
#[derive(Debug, thiserror::Error)]
pub enum RegistryError {
    /// No strategy of that name.
    #[error("unknown strategy {name:?}; the strategies are {}", names().join(", "))]
    Unknown {
        /// The name asked for.
        name: String,
    },
    /// A parameter is wrong.
    #[error("strategy {strategy}: {source}")]
    Param {
        /// The strategy.
        strategy: &'static str,
        /// Which parameter and why.
        source: ParamError,
    },
    /// The robot cannot carry the strategy.
    #[error("strategy {strategy} cannot run on robot {robot}: {why}")]
    DoesNotFit {
        /// The strategy.
        strategy: &'static str,
        /// The robot.
        robot: String,
        /// Why.
        why: String,
    },
    /// The mission could not be built.
    #[error(transparent)]
    Mission(#[from] MissionError),
}

/// The names of every strategy.
pub fn names() -> Vec<&'static str> {
    STRATEGIES.iter().map(|s| s.name).collect()
}

/// The strategy called `name`.
pub fn find(name: &str) -> Result<&'static StrategyInfo, RegistryError> {
    STRATEGIES
        .iter()
        .find(|s| s.name == name)
        .ok_or_else(|| RegistryError::Unknown {
            name: name.to_string(),
        })
}

/// A strategy with its typed parameters.
#[derive(Clone, Debug, PartialEq)]
pub enum Configured {
    /// `gtsp`, `greedy` or `spatial-only`.
    Tour(Planner, TourParams),
    /// `rbcm-greedy`.
    Rbcm(RbcmTable),
    /// `escape` or `rigid`.
    Escape(EscapeMode, EscapeTable),
}

/// Every parameter of a strategy with its default, as TOML text.
pub type ParamRows = Vec<(ParamDoc, String)>;

impl StrategyInfo {
    /// The parameters with their defaults.
    pub fn params(&self) -> ParamRows {
        match self.id {
            StrategyId::Gtsp | StrategyId::Greedy | StrategyId::SpatialOnly => {
                typed::defaults::<TourParams>()
            }
            StrategyId::RbcmGreedy => typed::defaults::<RbcmTable>(),
            StrategyId::Escape | StrategyId::Rigid => typed::defaults::<EscapeTable>(),
        }
    }

    /// The strategy configured from `table` (a scenario's `[strategy.<name>]`, or none) and
    /// then the overrides `sets` (key, value) in order.
    pub fn configure(
        &self,
        table: Option<&toml::Table>,
        sets: &[(String, String)],
    ) -> Result<Configured, RegistryError> {
        let empty = toml::Table::new();
        let table = table.unwrap_or(&empty);
        let param = |source| RegistryError::Param {
            strategy: self.name,
            source,
        };
        Ok(match self.id {
            StrategyId::Gtsp => Configured::Tour(Planner::Gtsp, apply(table, sets).map_err(param)?),
            StrategyId::Greedy => {
                Configured::Tour(Planner::Greedy, apply(table, sets).map_err(param)?)
            }
            StrategyId::SpatialOnly => {
                Configured::Tour(Planner::SpatialOnly, apply(table, sets).map_err(param)?)
            }
            StrategyId::RbcmGreedy => Configured::Rbcm(apply(table, sets).map_err(param)?),
            StrategyId::Escape => {
                Configured::Escape(EscapeMode::Escape, apply(table, sets).map_err(param)?)
            }
            StrategyId::Rigid => {
                Configured::Escape(EscapeMode::Rigid, apply(table, sets).map_err(param)?)
            }
        })
    }

    /// `Ok` when `robot` can carry the strategy, else one line why not.
    pub fn fits(&self, robot: &RobotSpec) -> Result<(), RegistryError> {
        let why = if robot.gaits.is_empty() {
            Some("it has no gait".to_string())
        } else if robot.sensor_hfov_deg.is_empty() {
            Some("it has no range sensor to map with".to_string())
        } else if self.needs_bumper && !robot.bumper {
            Some("it has no haptic bumper, which the strategy learns from".to_string())
        } else if self.id == StrategyId::RbcmGreedy
            && (robot.proprio_rate_hz.is_nan() || robot.proprio_rate_hz <= 0.0)
        {
            Some("it reports no proprioception (body roll), which the strategy learns from".into())
        } else {
            None
        };
        match why {
            None => Ok(()),
            Some(why) => Err(RegistryError::DoesNotFit {
                strategy: self.name,
                robot: robot.name.clone(),
                why,
            }),
        }
    }
}

fn apply<P: StrategyParams>(
    table: &toml::Table,
    sets: &[(String, String)],
) -> Result<P, ParamError> {
    let mut p: P = typed::from_table(table)?;
    for (k, v) in sets {
        p = typed::with_set(&p, k, v)?;
    }
    Ok(p)
}

/// A mission of any registered strategy.
pub type AnyMission = Mission<Box<dyn Strategy + Send>>;

impl Configured {
    /// The parameters as a TOML table, for reports.
    pub fn table(&self) -> toml::Table {
        match self {
            Configured::Tour(_, p) => typed::to_table(p),
            Configured::Rbcm(p) => typed::to_table(p),
            Configured::Escape(_, p) => typed::to_table(p),
        }
    }

    /// The Prágr22 explorer's mission parameters (only for `gtsp`, `greedy`, `spatial-only`).
    pub fn tour_mission(
        &self,
        robot: &RobotSpec,
        seed: u64,
    ) -> Option<crate::params::MissionParams> {
        match self {
            Configured::Tour(planner, p) => Some(p.mission_params(robot, *planner, seed)),
            _ => None,
        }
    }

    /// A mission of the strategy on `robot` (the seed is the strategy's own).
    pub fn build(&self, robot: &RobotSpec, seed: u64) -> Result<AnyMission, RegistryError> {
        let (body, strategy) = self.parts(robot, seed)?;
        Ok(Mission::new(body, strategy)?)
    }

    /// The body parameters and the strategy of [`Configured::build`], to compose them (e.g.
    /// with a [`crate::shadow::Shadowed`] learner) before the mission is made.
    pub fn parts(
        &self,
        robot: &RobotSpec,
        seed: u64,
    ) -> Result<(BodyParams, Box<dyn Strategy + Send>), RegistryError> {
        let name = self.name();
        let param = |source| RegistryError::Param {
            strategy: name,
            source,
        };
        match self {
            Configured::Tour(planner, p) => {
                parts::<TourExplorer>(p.mission_params(robot, *planner, seed))
            }
            Configured::Rbcm(p) => parts::<RbcmGreedy>(p.explorer_params(robot).map_err(param)?),
            Configured::Escape(mode, p) => {
                parts::<EscapeMission>(p.escape_params(robot, *mode).map_err(param)?)
            }
        }
    }

    /// The strategy's registry name.
    pub fn name(&self) -> &'static str {
        match self {
            Configured::Tour(p, _) => p.name(),
            Configured::Rbcm(_) => "rbcm-greedy",
            Configured::Escape(m, _) => m.name(),
        }
    }
}

/// The body parameters and the boxed strategy of `params`.
fn parts<S: FromParams + Send + 'static>(
    params: S::Params,
) -> Result<(BodyParams, Box<dyn Strategy + Send>), RegistryError> {
    let body = S::body_params(&params);
    Ok((body, Box::new(S::from_params(params)?)))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn keys<P: StrategyParams>() -> Vec<String> {
        let mut t: Vec<String> = typed::to_table(&P::default()).keys().cloned().collect();
        t.sort();
        t
    }

    fn doc_keys<P: StrategyParams>(optional: &[&str]) -> Vec<String> {
        let mut d: Vec<String> = P::DOCS
            .iter()
            .map(|d| d.key.to_string())
            .filter(|k| !optional.contains(&k.as_str()))
            .collect();
        d.sort();
        d
    }

    #[test]
    fn every_parameter_is_documented_once() {
        assert_eq!(
            keys::<TourParams>(),
            doc_keys::<TourParams>(&[
                "info_gain_spacing_m",
                "max_learning_pairs",
                "max_tour_sites"
            ])
        );
        assert_eq!(
            keys::<RbcmTable>(),
            doc_keys::<RbcmTable>(&["gait", "sample_period_s", "r_spatial"])
        );
        assert_eq!(
            keys::<EscapeTable>(),
            doc_keys::<EscapeTable>(&[
                "gp_noise_variance",
                "gp_signal_variance",
                "gp_lengthscale",
                "info_gain_spacing_m"
            ])
        );
        for p in STRATEGIES {
            assert!(p.params().len() >= 10, "{}", p.name);
            assert_eq!(find(p.name).unwrap().id, p.id);
        }
    }

    #[test]
    fn defaults_validate_and_bad_values_name_their_key() {
        let s = find("gtsp").unwrap();
        assert!(s.configure(None, &[]).is_ok());
        for (k, v, want) in [
            ("n_min", "-3", "n_min"),
            ("n_min", "0", "n_min"),
            ("lenghtscale", "1", "lenghtscale"),
            ("lengthscale", "\"a\"", "lengthscale"),
            ("lengthscale", "nan", "lengthscale"),
            ("look_around", "1", "look_around"),
        ] {
            let e = s
                .configure(None, &[(k.into(), v.into())])
                .unwrap_err()
                .to_string();
            assert!(e.contains(want) && !e.contains('\n'), "{k}={v}: {e}");
        }
        let mut t = toml::Table::new();
        t.insert("n_min".into(), toml::Value::Integer(-3));
        let e = s.configure(Some(&t), &[]).unwrap_err().to_string();
        assert!(e.contains("n_min"), "{e}");
        let e = find("escape")
            .unwrap()
            .configure(None, &[("descriptor".into(), "hsv".into())])
            .unwrap_err()
            .to_string();
        assert!(e.contains("descriptor") || e.contains("hsv"), "{e}");
        assert!(find("frontier").unwrap_err().to_string().contains("gtsp"));
    }

    /// Every numeric parameter of `P`: NaN, infinity, a negative value, a fraction where a
    /// whole number is wanted, a value above its cap and one of the wrong type are refused
    /// with one line naming the key, the value and the range; the defaults pass.
    fn every_range_is_enforced<P: StrategyParams + std::fmt::Debug>(strategy: &str) {
        let s = find(strategy).unwrap();
        P::default().validate().unwrap();
        for d in P::DOCS {
            let bad: Vec<String> = match d.range {
                typed::Range::Above(lo, hi) | typed::Range::Within(lo, hi) => vec![
                    "nan".into(),
                    "inf".into(),
                    format!("{}", lo - 1.0),
                    format!("{:e}", hi * 2.0),
                    "\"x\"".into(),
                ],
                typed::Range::Count(_, hi) => {
                    vec!["-3".into(), "0.5".into(), format!("{}", hi + 1)]
                }
                typed::Range::Flag => vec!["1".into()],
                typed::Range::OneOf(_) => vec!["hsv".into()],
                typed::Range::EachWithin(..) => vec!["{ fast = -1 }".into()],
                typed::Range::Name | typed::Range::Any => vec!["1".into()],
            };
            for v in bad {
                let e = s
                    .configure(None, &[(d.key.into(), v.clone())])
                    .unwrap_err()
                    .to_string();
                assert!(
                    e.contains(&format!("`{}`", d.key)) && !e.contains('\n'),
                    "{strategy} {}={v}: {e}",
                    d.key
                );
                // A range check names the value and what is allowed.
                if d.range != typed::Range::Any && d.range != typed::Range::Name {
                    assert!(e.contains("must be"), "{strategy} {}={v}: {e}", d.key);
                }
            }
        }
    }

    #[test]
    fn every_strategy_refuses_values_out_of_range() {
        every_range_is_enforced::<TourParams>("gtsp");
        every_range_is_enforced::<RbcmTable>("rbcm-greedy");
        every_range_is_enforced::<EscapeTable>("escape");
    }

    #[test]
    fn errors_name_key_value_range_and_unit() {
        let e = |strategy: &str, k: &str, v: &str| {
            let mut t = toml::Table::new();
            t.insert(
                k.into(),
                toml::from_str::<toml::Table>(&format!("v = {v}")).unwrap()["v"].clone(),
            );
            find(strategy)
                .unwrap()
                .configure(Some(&t), &[])
                .unwrap_err()
                .to_string()
        };
        assert_eq!(
            e("gtsp", "n_min", "-3"),
            "strategy gtsp: `n_min` = -3: must be a whole number of cells ≥ 1 and ≤ 1000000"
        );
        assert_eq!(
            e("escape", "r_hist", "-0.1"),
            "strategy escape: `r_hist` = -0.1: must be a finite number > 0 m and ≤ 2 m"
        );
        assert_eq!(
            e("rbcm-greedy", "plan_hz", "nan"),
            "strategy rbcm-greedy: `plan_hz` = nan: must be a finite number > 0 Hz and ≤ 1000 Hz"
        );
        assert!(e("gtsp", "lenghtscale", "1").contains("did you mean `lengthscale`?"));
        assert!(e("gtsp", "zzz", "1").contains("the parameters are lengthscale, sigma_s"));
        let m = e("rbcm-greedy", "m_min", "60");
        assert!(
            m.contains("`m_min` = 60") && m.contains("m_max = 50"),
            "{m}"
        );
        // A whole number where a number is wanted is fine.
        let mut t = toml::Table::new();
        t.insert("c_loss".into(), toml::Value::Integer(7));
        assert!(find("gtsp").unwrap().configure(Some(&t), &[]).is_ok());
    }

    #[test]
    fn design_choices_reach_the_mission_parameters() {
        let robot = RobotSpec {
            name: "r".into(),
            gaits: vec![GaitSpec {
                name: "fast".into(),
                v_max: 0.05,
            }],
            sensor_hfov_deg: vec![87.0],
            map: MapParams::default(),
            bounds: None,
            time_limit_s: 100.0,
            bumper: false,
            proprio_rate_hz: 20.0,
            pose_rate_hz: 20.0,
        };
        let sets: Vec<(String, String)> = [
            ("look_around", "true"),
            ("commit_to_goal", "false"),
            ("stuck_windows_as_samples", "false"),
            ("gtsp_max_trials", "3"),
            ("info_gain_spacing_m", "0.5"),
        ]
        .iter()
        .map(|(k, v)| (k.to_string(), v.to_string()))
        .collect();
        let c = find("gtsp").unwrap().configure(None, &sets).unwrap();
        let p = c.tour_mission(&robot, 7).unwrap();
        assert!(p.look_around && !p.commit_to_goal && !p.stuck_samples);
        assert_eq!(p.solver.max_trials, 3);
        assert_eq!(p.info_gain_spacing_m, Some(0.5));
        assert_eq!(p.seed, 7);
        let d = find("gtsp").unwrap().configure(None, &[]).unwrap();
        let q = d.tour_mission(&robot, 7).unwrap();
        // The defaults: no look-around (as Prágr22's Alg. 1), commitment and stuck samples on.
        assert!(!q.look_around && q.commit_to_goal && q.stuck_samples);
        assert!(find("escape").unwrap().fits(&robot).is_err());
        assert!(find("rbcm-greedy").unwrap().fits(&robot).is_ok());
    }

    #[test]
    fn a_set_value_reaches_the_mission() {
        let s = find("greedy").unwrap();
        let c = s
            .configure(
                None,
                &[
                    ("c_loss".into(), "7.5".into()),
                    ("n_min".into(), "30".into()),
                ],
            )
            .unwrap();
        let t = c.table();
        assert_eq!(t["c_loss"].as_float(), Some(7.5));
        assert_eq!(t["n_min"].as_integer(), Some(30));
    }
}
