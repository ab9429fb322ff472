//! `strider bench table5`: the mission-level reproduction of Prágr22 Table 5.
//!
//! Every block of the table is rebuilt from independent trials in the simulator:
//!
//! * small tours 1 and 2 with the three navigation modes, after a `gtsp` exploration of
//!   `courtyard-small` (one exploration per trial, the three modes on its map and models);
//! * small exploration time, `gtsp` against `greedy`;
//! * the large tour in the `learned` mode after a `gtsp` exploration ("proposed") against the
//!   same after a `spatial-only` exploration, and the two exploration times, on
//!   `courtyard-large`.
//!
//! Trial i (0-based) of a row runs on world seed 1 + (i mod K) with mission seed 1 + i, so the
//! trials of a row cover K random worlds and the rows that are compared (gtsp/greedy, and the
//! modes of one exploration) are paired by trial. Trials run in parallel on a pool of `--jobs`
//! threads; each trial is deterministic, so the table does not depend on the job count.
//! Statistics: mean ± std, paired win fractions and two-sided and one-sided Mann–Whitney U
//! ([`crate::stats`]).

use std::path::{Path, PathBuf};
use std::time::Instant;

use anyhow::{Result, bail};

use super::table5_report::{Table5Report, markdown};
use super::table5_trials::{
    Table5Options, TrialResult, kept, run_task, run_trials, setting, sort, tasks,
};
use crate::cancel::Completion;
use crate::io::{create_dir, write_json, write_text};
use crate::journal::Journal;
use crate::progress::Progress;
use crate::trial::{MAX_TRIALS, checked_time_limit};

/// The table written: `table5.json`, `table5.md` (also returned, for the terminal).
pub struct Table5 {
    /// The markdown table.
    pub markdown: String,
    /// `table5.json`.
    pub json: PathBuf,
    /// `table5.md`.
    pub md: PathBuf,
    /// Trials in the table, of `total`; fewer when interrupted (the files then hold the table
    /// of the finished trials, marked `"complete": false`, and none are written when no trial
    /// finished).
    pub finished: usize,
    /// Trials the table needs.
    pub total: usize,
    /// Where every finished trial is kept (`OUT/trials`), for `--resume`.
    pub trials_dir: PathBuf,
}

impl Table5 {
    /// Whether every trial finished.
    pub fn complete(&self) -> bool {
        self.finished == self.total
    }
}

/// Runs `strider bench table5` into `out`: the trials (those kept by an earlier run too, with
/// `o.resume`), each kept in `out/trials` as it finishes, then the table.
pub fn table5(o: &Table5Options, out: &Path, progress: &dyn Progress) -> Result<Table5> {
    check(o)?;
    let journal = Journal::open(out, setting(o), o.resume)?;
    if let Some(dir) = &o.mcap_dir {
        create_dir(dir)?;
    }
    let wall = Instant::now();
    let tasks = tasks(o);
    let (mut trials, todo) = kept(o, &tasks, &journal, progress)?;
    progress.start(todo.len() as u64);
    trials.extend(run_trials(o, &todo, &journal, progress)?);
    sort(&mut trials);
    let (finished, total) = (trials.len(), tasks.len());
    let json = out.join("table5.json");
    let md = out.join("table5.md");
    let wall_s = wall.elapsed().as_secs_f64();
    let report = Table5Report::new(o, trials, wall_s, Completion::of(finished < total));
    let markdown = markdown(&report);
    if finished > 0 {
        write(out, &report, &markdown)?;
    }
    Ok(Table5 {
        markdown,
        json,
        md,
        finished,
        total,
        trials_dir: journal.dir().to_path_buf(),
    })
}

/// The number of trials the table needs (its shard's, with `o.shard`): the pieces below let a
/// distributed sweep run the table's trials as tasks of its own.
pub fn trial_count(o: &Table5Options) -> Result<usize> {
    check(o)?;
    Ok(tasks(o).len())
}

/// Trial `index` (of [`trial_count`]) of the table's order, run on the calling thread.
pub fn run_trial(o: &Table5Options, index: usize) -> Result<TrialResult> {
    check(o)?;
    let all = tasks(o);
    let Some(task) = all.get(index) else {
        bail!("trial {index}: the table has {} trials", all.len());
    };
    run_task(task, o)?.ok_or_else(|| anyhow::anyhow!("trial {index} was interrupted"))
}

/// The table of `trials` (every trial of [`trial_count`], in any order).
pub fn assemble(o: &Table5Options, mut trials: Vec<TrialResult>, wall_s: f64) -> Table5Report {
    sort(&mut trials);
    Table5Report::new(o, trials, wall_s, Completion::of(false))
}

/// Writes `table5.json` and `table5.md` into `out`.
pub fn write(out: &Path, report: &Table5Report, markdown: &str) -> Result<()> {
    create_dir(out)?;
    write_json(&out.join("table5.json"), report)?;
    write_text(&out.join("table5.md"), markdown)
}

fn check(o: &Table5Options) -> Result<()> {
    if o.trials == 0 || o.world_seeds == 0 || o.jobs == 0 {
        bail!("--trials, --world-seeds and --jobs must be at least 1");
    }
    for (flag, n) in [("--trials", o.trials), ("--large-trials", o.large_trials)] {
        if n > MAX_TRIALS {
            bail!("{flag} {n}: must be an integer from 1 to {MAX_TRIALS}");
        }
    }
    if let Some(t) = o.time_limit {
        checked_time_limit(t)?;
    }
    Ok(())
}
