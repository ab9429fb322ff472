//! A comparison split into shards and merged back: `strider bench compare --shard K/N` runs
//! every N-th trial (from the K-th) and writes its trials with what the merge needs;
//! `strider bench merge DIR…` checks that the shards are the N parts of one comparison and
//! assembles the table the unsharded comparison gives (every trial is a pure function of
//! scenario, strategy and seeds, so only the wall times differ).

use std::collections::BTreeSet;
use std::path::{Path, PathBuf};

use anyhow::{Context, Result, bail};
use serde::{Deserialize, Serialize};

use super::{CompareOptions, CompareTrial, Comparison, Skipped, assemble, command_line};
use crate::cancel::{Cancel, Completion};

/// The most shards a comparison is split into.
pub const MAX_SHARDS: usize = 100_000;

/// Shard `k` of `n` (1-based): the trials whose index i in the comparison's order has
/// i mod n = k − 1.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub struct Shard {
    /// This shard, 1..=n.
    pub k: usize,
    /// The number of shards.
    pub n: usize,
}

impl Shard {
    /// Reads `K/N` (1 ≤ K ≤ N ≤ [`MAX_SHARDS`]).
    pub fn parse(s: &str) -> Result<Self> {
        let bad = || format!("--shard {s:?}: expected K/N with 1 ≤ K ≤ N ≤ {MAX_SHARDS}, e.g. 2/8");
        let (k, n) = s.split_once('/').with_context(bad)?;
        let (k, n): (usize, usize) = (
            k.trim().parse().ok().with_context(bad)?,
            n.trim().parse().ok().with_context(bad)?,
        );
        if !(1 <= k && k <= n && n <= MAX_SHARDS) {
            bail!(bad());
        }
        Ok(Self { k, n })
    }

    /// Whether the trial at `index` of the comparison's order is this shard's.
    pub fn owns(&self, index: usize) -> bool {
        index % self.n == self.k - 1
    }
}

/// What a shard's `compare.json` records for the merge: the shard and the comparison's
/// options.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct ShardInfo {
    /// Which shard.
    #[serde(flatten)]
    pub shard: Shard,
    /// The comparison's scenarios, in order.
    pub scenarios: Vec<String>,
    /// Its strategies, in order.
    pub strategies: Vec<String>,
    /// Its time-limit override.
    pub time_limit: Option<f64>,
}

/// A cell's skip reason as a shard file has it.
#[derive(Deserialize)]
struct CellSkip {
    scenario: String,
    strategy: String,
    skipped: Option<String>,
}

/// The part of a shard's `compare.json` the merge reads.
#[derive(Deserialize)]
struct ShardFile {
    complete: bool,
    trials_per_cell: usize,
    world_seeds: u64,
    cells: Vec<CellSkip>,
    shard: Option<ShardInfo>,
    trials: Vec<CompareTrial>,
}

fn read(dir: &Path) -> Result<(ShardFile, ShardInfo)> {
    let path = dir.join("compare.json");
    let text = std::fs::read_to_string(&path)
        .with_context(|| format!("cannot read {}", path.display()))?;
    let f: ShardFile = serde_json::from_str(&text)
        .with_context(|| format!("{}: not a comparison's compare.json", path.display()))?;
    let Some(info) = f.shard.clone() else {
        bail!(
            "{}: not a shard (it was written without --shard)",
            path.display()
        );
    };
    if !f.complete {
        bail!(
            "{}: shard {}/{} was interrupted; run it again",
            path.display(),
            info.shard.k,
            info.shard.n
        );
    }
    Ok((f, info))
}

/// Merges the shards in `dirs` into the comparison the unsharded command gives, with that
/// command's line.
pub fn merge(dirs: &[PathBuf]) -> Result<(Comparison, String)> {
    let Some(first) = dirs.first() else {
        bail!("give the folders of the shards to merge");
    };
    let (f0, i0) = read(first)?;
    let mut seen = BTreeSet::new();
    let mut trials = Vec::new();
    let mut skipped = Skipped::new();
    for c in &f0.cells {
        if let Some(why) = &c.skipped {
            skipped.insert((c.scenario.clone(), c.strategy.clone()), why.clone());
        }
    }
    for dir in dirs {
        let (f, info) = read(dir)?;
        let same = info.shard.n == i0.shard.n
            && info.scenarios == i0.scenarios
            && info.strategies == i0.strategies
            && info.time_limit == i0.time_limit
            && f.trials_per_cell == f0.trials_per_cell
            && f.world_seeds == f0.world_seeds;
        if !same {
            bail!(
                "{}: shard of another comparison than {} (scenarios, strategies, trials, world seeds, time limit or shard count differ)",
                dir.display(),
                first.display()
            );
        }
        if !seen.insert(info.shard.k) {
            bail!(
                "{}: shard {}/{} is given twice",
                dir.display(),
                info.shard.k,
                info.shard.n
            );
        }
        trials.extend(f.trials);
    }
    if seen.len() != i0.shard.n {
        let missing: Vec<String> = (1..=i0.shard.n)
            .filter(|k| !seen.contains(k))
            .take(10)
            .map(|k| format!("{k}/{}", i0.shard.n))
            .collect();
        bail!("shards missing: {}", missing.join(", "));
    }
    let o = CompareOptions {
        scenarios: i0.scenarios.clone(),
        trials: f0.trials_per_cell,
        world_seeds: f0.world_seeds,
        jobs: 1,
        time_limit: i0.time_limit,
        cancel: Cancel::new(),
        shard: None,
    };
    let expected = i0.scenarios.len() * i0.strategies.len() * o.trials - skipped.len() * o.trials;
    if trials.len() != expected {
        bail!(
            "the shards hold {} trials, the comparison has {expected}",
            trials.len()
        );
    }
    let c = assemble(&o, &i0.strategies, &skipped, trials, Completion::of(false));
    Ok((c, command_line(&o, &i0.strategies)))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn shards_parse_and_split_the_trials_into_disjoint_parts() {
        let s = Shard::parse("2/3").unwrap();
        assert_eq!(s, Shard { k: 2, n: 3 });
        for bad in ["0/3", "4/3", "3", "a/b", "1/0", "1/100001", "-1/2"] {
            let e = Shard::parse(bad).unwrap_err().to_string();
            assert!(
                e.starts_with(&format!("--shard {bad:?}: expected K/N")),
                "{e}"
            );
        }
        let shards: Vec<Shard> = (1..=3).map(|k| Shard { k, n: 3 }).collect();
        for i in 0..10 {
            assert_eq!(shards.iter().filter(|s| s.owns(i)).count(), 1);
        }
    }

    #[test]
    fn merging_needs_shard_folders() {
        assert!(
            merge(&[])
                .unwrap_err()
                .to_string()
                .contains("give the folders")
        );
        let dir = std::env::temp_dir().join(format!("strider-merge-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let e = format!("{:#}", merge(std::slice::from_ref(&dir)).unwrap_err());
        assert!(
            e.contains("cannot read") && e.contains("compare.json"),
            "{e}"
        );
        let _ = std::fs::remove_dir_all(dir);
    }
}
