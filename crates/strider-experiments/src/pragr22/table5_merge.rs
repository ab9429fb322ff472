//! Table 5 split into shards and merged back: `strider bench table5 --shard K/N` runs every
//! N-th trial (from the K-th) and writes the table of its trials; `strider bench merge DIR…`
//! checks that the shards are the N parts of one table and writes the table the unsharded
//! bench gives (every trial is a pure function of its world and seeds, so only wall times and
//! latencies differ).

use std::collections::BTreeSet;
use std::path::{Path, PathBuf};

use anyhow::{Context, Result, bail};
use serde::Deserialize;

use super::table5_report::Table5Report;
use super::table5_trials::{Table5Options, TrialResult, sort, tasks};
use crate::cancel::{Cancel, Completion};
use crate::compare::Shard;

/// The part of a shard's `table5.json` the merge reads.
#[derive(Deserialize)]
struct ShardFile {
    complete: bool,
    trials: usize,
    large_trials: usize,
    world_seeds: u64,
    jobs: usize,
    time_limit_s: Option<f64>,
    shard: Option<Shard>,
    #[serde(default, rename = "set")]
    sets: Vec<(String, String)>,
    wall_s: f64,
    trial_results: Vec<TrialResult>,
}

fn read(dir: &Path) -> Result<(ShardFile, Shard)> {
    let path = dir.join("table5.json");
    let text = std::fs::read_to_string(&path)
        .with_context(|| format!("cannot read {}", path.display()))?;
    let f: ShardFile = serde_json::from_str(&text)
        .with_context(|| format!("{}: not a Table 5 bench's table5.json", path.display()))?;
    let Some(shard) = f.shard else {
        bail!(
            "{}: not a shard (it was written without --shard)",
            path.display()
        );
    };
    if !f.complete {
        bail!(
            "{}: shard {}/{} was interrupted; run it again with --resume",
            path.display(),
            shard.k,
            shard.n
        );
    }
    Ok((f, shard))
}

/// The options all shards share, or an error naming the shard that differs.
fn same_table(first: (&ShardFile, Shard), other: (&ShardFile, Shard), dir: &Path) -> Result<()> {
    let ((a, sa), (b, sb)) = (first, other);
    let same = sa.n == sb.n
        && a.trials == b.trials
        && a.large_trials == b.large_trials
        && a.world_seeds == b.world_seeds
        && a.time_limit_s == b.time_limit_s
        && a.sets == b.sets;
    if !same {
        bail!(
            "{}: shard of another table (trials, large trials, world seeds, time limit, --set or shard count differ)",
            dir.display()
        );
    }
    Ok(())
}

/// Merges the Table 5 shards in `dirs` into the table the unsharded bench gives.
pub fn merge_table5(dirs: &[PathBuf]) -> Result<Table5Report> {
    let Some(first) = dirs.first() else {
        bail!("give the folders of the shards to merge");
    };
    let (f0, s0) = read(first)?;
    let (mut seen, mut trials, mut wall_s) = (BTreeSet::new(), Vec::new(), 0.0f64);
    for dir in dirs {
        let (f, s) = read(dir)?;
        same_table((&f0, s0), (&f, s), dir)?;
        if !seen.insert(s.k) {
            bail!("{}: shard {}/{} is given twice", dir.display(), s.k, s.n);
        }
        // Shards run side by side: the table took as long as the longest.
        wall_s = wall_s.max(f.wall_s);
        trials.extend(f.trial_results);
    }
    if seen.len() != s0.n {
        let missing: Vec<String> = (1..=s0.n)
            .filter(|k| !seen.contains(k))
            .take(10)
            .map(|k| format!("{k}/{}", s0.n))
            .collect();
        bail!("shards missing: {}", missing.join(", "));
    }
    let o = Table5Options {
        trials: f0.trials,
        large_trials: f0.large_trials,
        world_seeds: f0.world_seeds,
        jobs: f0.jobs,
        time_limit: f0.time_limit_s,
        mcap_dir: None,
        resume: false,
        cancel: Cancel::new(),
        shard: None,
        sets: f0.sets.clone(),
    };
    let expected = tasks(&o).len();
    let keys: BTreeSet<_> = trials
        .iter()
        .map(|t| (&t.trial.scenario, &t.trial.strategy, t.trial.seed))
        .collect();
    if trials.len() != expected || keys.len() != expected {
        bail!(
            "the shards hold {} trials ({} distinct), the table has {expected}",
            trials.len(),
            keys.len()
        );
    }
    sort(&mut trials);
    Ok(Table5Report::new(&o, trials, wall_s, Completion::of(false)))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn merging_needs_the_shards_of_one_table() {
        let e = merge_table5(&[]).unwrap_err().to_string();
        assert!(e.contains("give the folders"), "{e}");
        let dir = std::env::temp_dir().join(format!("strider-t5merge-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let e = merge_table5(std::slice::from_ref(&dir))
            .unwrap_err()
            .to_string();
        assert!(
            e.contains("cannot read") && e.contains("table5.json"),
            "{e}"
        );
        // A whole table is not a shard.
        let whole = r#"{"complete": true, "interrupted": false, "trials": 1, "large_trials": 0,
            "world_seeds": 1, "jobs": 1, "time_limit_s": 10.0, "wall_s": 1.0,
            "trial_results": []}"#;
        std::fs::write(dir.join("table5.json"), whole).unwrap();
        let e = merge_table5(std::slice::from_ref(&dir))
            .unwrap_err()
            .to_string();
        assert!(e.contains("not a shard"), "{e}");
        // Shard 1 of 2 alone: the other is missing.
        let shard = whole.replace(
            "\"trial_results\"",
            "\"shard\": {\"k\": 1, \"n\": 2}, \"trial_results\"",
        );
        std::fs::write(dir.join("table5.json"), shard).unwrap();
        let e = merge_table5(std::slice::from_ref(&dir))
            .unwrap_err()
            .to_string();
        assert!(e.contains("shards missing: 2/2"), "{e}");
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
