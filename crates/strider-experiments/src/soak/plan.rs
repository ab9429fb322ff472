//! Which missions a soak runs: every registered strategy on every built-in world it can run
//! on, with world and mission seeds drawn from the soak's seed, and a time limit per world.

use std::fmt;

use anyhow::{Context, Result, bail};
use serde::Serialize;
use strider_explore::registry::STRATEGIES;
use strider_scenario::builtin;

use crate::trial::{configure, load, robot_spec};

/// Simulated time limit of a mission per built-in world, s: long enough for the robot to look
/// around, drive a few metres and replan 5–20 times (hexapods walk 0.05–0.1 m/s), short
/// enough that 500 missions take about a quarter of an hour on two cores (measured on a loaded
/// machine: 1–10 s of wall time a mission, 1.2 s of CPU time on average). courtyard-large
/// costs most per simulated second (a 10 m omnidirectional sensor; `rigid` runs there at
/// about real time) and gets least, as does `campus` (the same robot on 4 M cells).
const WORLD_LIMITS_S: [(&str, f64); 9] = [
    ("courtyard-small", 90.0),
    ("courtyard-large", 30.0),
    ("lab-track", 90.0),
    ("lab-track-large", 90.0),
    ("escape-arena", 60.0),
    ("energy-arena", 60.0),
    ("bonn-paths", 45.0),
    ("cot-track", 90.0),
    ("campus", 30.0),
];

/// Limit of a world not in [`WORLD_LIMITS_S`], s.
const DEFAULT_LIMIT_S: f64 = 60.0;

/// World seeds are drawn from 1..=this (seed 1 is the paper's world, the others its random
/// family).
const WORLD_SEEDS: u64 = 1000;

/// Mission seeds are drawn from 1..=this.
const MISSION_SEEDS: u64 = 1_000_000;

/// The soak's time limit of a mission on built-in world `scenario`, s.
pub fn world_limit_s(scenario: &str) -> f64 {
    WORLD_LIMITS_S
        .iter()
        .find(|(n, _)| *n == scenario)
        .map_or(DEFAULT_LIMIT_S, |(_, t)| *t)
}

/// One mission: enough to run it again alone.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Task {
    /// Strategy.
    pub strategy: &'static str,
    /// Built-in scenario.
    pub scenario: &'static str,
    /// World seed.
    pub world_seed: u64,
    /// Mission and simulator seed.
    pub seed: u64,
    /// Simulated time limit, s.
    pub time_limit_s: f64,
}

impl Task {
    /// `STRATEGY@SCENARIO:WORLD_SEED:SEED`, what `--rerun` reads.
    pub fn key(&self) -> String {
        format!(
            "{}@{}:{}:{}",
            self.strategy, self.scenario, self.world_seed, self.seed
        )
    }

    /// The command that runs this mission alone under the soak's judge.
    pub fn rerun(&self) -> String {
        format!(
            "strider bench soak --rerun {} --time-limit {}",
            self.key(),
            self.time_limit_s
        )
    }

    /// The same mission as `strider run` (without the judge).
    pub fn run_command(&self) -> String {
        format!(
            "strider run -s {} --world-seed {} --strategy {} --seed {} --time-limit {}",
            self.scenario, self.world_seed, self.strategy, self.seed, self.time_limit_s
        )
    }

    /// Reads `STRATEGY@SCENARIO:WORLD_SEED:SEED` with time limit `limit_s` (the world's when
    /// `None`).
    pub fn parse(key: &str, limit_s: Option<f64>) -> Result<Self> {
        let bad = || {
            format!(
                "--rerun {key:?}: expected STRATEGY@SCENARIO:WORLD_SEED:SEED, e.g. gtsp@courtyard-small:17:4242"
            )
        };
        let (strategy, rest) = key.split_once('@').with_context(bad)?;
        let mut parts = rest.split(':');
        let (Some(scenario), Some(ws), Some(s), None) =
            (parts.next(), parts.next(), parts.next(), parts.next())
        else {
            bail!(bad());
        };
        let info = strider_explore::registry::find(strategy)?;
        let Some(&scenario) = builtin::names().iter().find(|n| **n == scenario) else {
            bail!(
                "--rerun: {scenario:?} is not a built-in scenario ({})",
                builtin::names().join(", ")
            );
        };
        Ok(Self {
            strategy: info.name,
            scenario,
            world_seed: ws.parse().with_context(bad)?,
            seed: s.parse().with_context(bad)?,
            time_limit_s: limit_s.unwrap_or_else(|| world_limit_s(scenario)),
        })
    }
}

impl fmt::Display for Task {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "{} on {} (world seed {}, mission seed {}, {} s)",
            self.strategy, self.scenario, self.world_seed, self.seed, self.time_limit_s
        )
    }
}

/// A strategy and the built-in worlds it runs on.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Coverage {
    /// Strategy.
    pub strategy: &'static str,
    /// The worlds it runs on.
    pub worlds: Vec<&'static str>,
    /// The worlds it cannot run on, and why.
    pub skipped: Vec<(&'static str, String)>,
}

/// Which strategy runs on which built-in world (each world's reference seed decides: a world
/// family keeps its robot).
pub fn coverage() -> Result<Vec<Coverage>> {
    let worlds = builtin::names()
        .iter()
        .map(|&n| Ok((n, load(n, 1).with_context(|| format!("scenario {n}"))?)))
        .collect::<Result<Vec<_>>>()?;
    Ok(STRATEGIES
        .iter()
        .map(|info| {
            let mut c = Coverage {
                strategy: info.name,
                worlds: Vec::new(),
                skipped: Vec::new(),
            };
            for (name, sc) in &worlds {
                let fits = configure(sc, info.name, &[])
                    .and_then(|(_, cfg)| Ok(cfg.parts(&robot_spec(sc), 1).map(|_| ())?));
                match fits {
                    Ok(()) => c.worlds.push(name),
                    Err(e) => c.skipped.push((name, format!("{e:#}"))),
                }
            }
            c
        })
        .collect())
}

/// SplitMix64: a well-mixed u64 of `x`.
fn mix(mut x: u64) -> u64 {
    x = x.wrapping_add(0x9E37_79B9_7F4A_7C15);
    x = (x ^ (x >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    x = (x ^ (x >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    x ^ (x >> 31)
}

/// `n` missions of soak seed `seed`: strategies in turn (every strategy within the first few
/// missions), each cycling through its worlds; world and mission seeds drawn from `(seed, i)`;
/// the world's limit unless `limit_s` overrides it.
pub fn tasks(cov: &[Coverage], n: usize, seed: u64, limit_s: Option<f64>) -> Vec<Task> {
    let able: Vec<&Coverage> = cov.iter().filter(|c| !c.worlds.is_empty()).collect();
    if able.is_empty() {
        return Vec::new();
    }
    (0..n)
        .map(|i| {
            let c = able[i % able.len()];
            let scenario = c.worlds[(i / able.len()) % c.worlds.len()];
            let base = mix(seed ^ mix(i as u64));
            Task {
                strategy: c.strategy,
                scenario,
                world_seed: 1 + mix(base ^ 1) % WORLD_SEEDS,
                seed: 1 + mix(base ^ 2) % MISSION_SEEDS,
                time_limit_s: limit_s.unwrap_or_else(|| world_limit_s(scenario)),
            }
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn cov() -> Vec<Coverage> {
        vec![
            Coverage {
                strategy: "gtsp",
                worlds: vec!["courtyard-small", "lab-track"],
                skipped: vec![],
            },
            Coverage {
                strategy: "escape",
                worlds: vec!["escape-arena"],
                skipped: vec![("lab-track", "no bumper".into())],
            },
            Coverage {
                strategy: "none",
                worlds: vec![],
                skipped: vec![],
            },
        ]
    }

    #[test]
    fn tasks_take_strategies_in_turn_and_depend_on_the_seed_only() {
        let t = tasks(&cov(), 6, 7, None);
        let who: Vec<_> = t.iter().map(|t| (t.strategy, t.scenario)).collect();
        assert_eq!(
            who,
            [
                ("gtsp", "courtyard-small"),
                ("escape", "escape-arena"),
                ("gtsp", "lab-track"),
                ("escape", "escape-arena"),
                ("gtsp", "courtyard-small"),
                ("escape", "escape-arena"),
            ]
        );
        assert_eq!(t, tasks(&cov(), 6, 7, None));
        assert_ne!(t, tasks(&cov(), 6, 8, None));
        assert!(t.iter().all(|t| (1..=WORLD_SEEDS).contains(&t.world_seed)));
        assert_eq!(t[0].time_limit_s, 90.0);
        assert_eq!(tasks(&cov(), 2, 7, Some(5.0))[1].time_limit_s, 5.0);
    }

    #[test]
    fn a_rerun_key_reads_back() {
        let t = &tasks(&cov(), 3, 1, None)[2];
        assert_eq!(&Task::parse(&t.key(), None).unwrap(), t);
        for bad in [
            "gtsp",
            "gtsp@courtyard-small:1",
            "gtsp@courtyard-small:1:x",
            "gtsp@nowhere:1:2",
            "frontier@lab-track:1:2",
            "gtsp@lab-track:1:2:3",
        ] {
            assert!(Task::parse(bad, None).is_err(), "{bad}");
        }
    }
}
