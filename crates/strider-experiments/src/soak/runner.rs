//! Missions side by side under a watchdog: a mission that does not return within its bound is
//! a violation, and the soak goes on without it.
//!
//! Each mission runs on a thread of its own inside a one-thread rayon pool, so its parallel
//! parts run on that thread and no other mission can be started inside its waits (rayon lets a
//! waiting pool thread take up any queued job, which would make one mission's wall time
//! include another's). At most `jobs` missions run at once. One that does not return within
//! its hard bound is recorded as not returning and its thread is left behind (a thread cannot
//! be killed; the process ends it); a new mission takes its place. After
//! [`MAX_ABANDONED_PER_JOB`] × `jobs` such missions, the soak starts no new mission (the
//! abandoned threads may still be burning the cores) and records the rest as not run.

use std::sync::Arc;
use std::sync::mpsc;
use std::time::{Duration, Instant};

use super::mission::MissionResult;
use super::plan::Task;
use super::violation::Kind;

/// Abandoned missions per job after which the soak starts no new mission.
pub const MAX_ABANDONED_PER_JOB: usize = 4;

/// How long a mission may run past its own cooperative bound before the watchdog gives up on
/// it, s (the mission checks its bound between control ticks; one tick may take a while).
pub const GRACE_S: f64 = 30.0;

/// How often the watchdog looks at the running missions.
const POLL: Duration = Duration::from_millis(200);

/// A mission's work: the task and its cooperative wall-clock bound.
pub type Work = dyn Fn(&Task, Duration) -> MissionResult + Send + Sync;

/// Runs every task (at most `jobs` at once), each with the bound `bound(task)` (the watchdog
/// allows `grace` more, [`GRACE_S`] in a soak); `done` is called with each result as it
/// arrives. Results come back in task order.
pub fn run_all(
    tasks: &[Task],
    (jobs, grace): (usize, Duration),
    bound: impl Fn(&Task) -> Duration,
    work: Arc<Work>,
    mut done: impl FnMut(&MissionResult),
) -> Vec<MissionResult> {
    let jobs = jobs.max(1);
    let (tx, rx) = mpsc::channel::<(usize, MissionResult)>();
    let mut results: Vec<Option<MissionResult>> = vec![None; tasks.len()];
    // (task index, started, hard bound)
    let mut running: Vec<(usize, Instant, Duration)> = Vec::new();
    let mut next = 0;
    let mut abandoned = 0;
    let mut record = |i: usize, r: MissionResult, results: &mut Vec<Option<MissionResult>>| {
        if results[i].is_none() {
            done(&r);
            results[i] = Some(r);
        }
    };
    loop {
        while running.len() < jobs && next < tasks.len() && abandoned < MAX_ABANDONED_PER_JOB * jobs
        {
            let b = bound(&tasks[next]);
            match start(next, &tasks[next], b, work.clone(), tx.clone()) {
                Ok(()) => running.push((next, Instant::now(), b + grace)),
                Err(e) => {
                    let r = MissionResult::failed(&tasks[next], Kind::Crash, e, 0.0);
                    record(next, r, &mut results);
                }
            }
            next += 1;
        }
        if running.is_empty() {
            break;
        }
        match rx.recv_timeout(POLL) {
            Ok((i, r)) => {
                running.retain(|(j, ..)| *j != i);
                record(i, r, &mut results);
            }
            Err(_) => {
                let now = Instant::now();
                for &(i, t0, hard) in running.iter().filter(|(_, t0, hard)| now - *t0 > *hard) {
                    abandoned += 1;
                    let what = format!(
                        "did not return within {:.0} s of wall time (abandoned)",
                        hard.as_secs_f64()
                    );
                    let wall = (now - t0).as_secs_f64();
                    record(
                        i,
                        MissionResult::failed(&tasks[i], Kind::Termination, what, wall),
                        &mut results,
                    );
                }
                running.retain(|(_, t0, hard)| now - *t0 <= *hard);
            }
        }
    }
    for (i, t) in tasks.iter().enumerate().skip(next) {
        let what =
            format!("not run: {abandoned} missions did not return, so the soak started no more");
        record(
            i,
            MissionResult::failed(t, Kind::Crash, what, 0.0),
            &mut results,
        );
    }
    results.into_iter().flatten().collect()
}

/// Starts task `i` on its own thread (see the module docs).
fn start(
    i: usize,
    task: &Task,
    bound: Duration,
    work: Arc<Work>,
    tx: mpsc::Sender<(usize, MissionResult)>,
) -> Result<(), String> {
    let task = task.clone();
    std::thread::Builder::new()
        .name(format!("soak-{i}"))
        .spawn(move || {
            let r = match rayon::ThreadPoolBuilder::new().num_threads(1).build() {
                Ok(pool) => pool.install(|| work(&task, bound)),
                Err(e) => {
                    MissionResult::failed(&task, Kind::Crash, format!("no thread pool: {e}"), 0.0)
                }
            };
            // The soak may have given up on this mission and stopped listening.
            let _ = tx.send((i, r));
        })
        .map(|_| ())
        .map_err(|e| format!("cannot start a thread: {e}"))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn task(seed: u64) -> Task {
        Task {
            strategy: "gtsp",
            scenario: "courtyard-small",
            world_seed: 1,
            seed,
            time_limit_s: 1.0,
        }
    }

    /// Seed 0 never returns; the others return at once.
    fn work() -> Arc<Work> {
        Arc::new(|t: &Task, _| {
            if t.seed == 0 {
                std::thread::sleep(Duration::from_secs(3600));
            }
            MissionResult::failed(t, Kind::Report, format!("seed {}", t.seed), 0.0)
        })
    }

    fn kinds(r: &[MissionResult]) -> Vec<(u64, Kind)> {
        r.iter()
            .map(|r| (r.task.seed, r.violations[0].kind))
            .collect()
    }

    #[test]
    fn a_mission_that_does_not_return_is_a_violation_and_the_rest_run() {
        let tasks: Vec<Task> = [1, 0, 2, 3].into_iter().map(task).collect();
        let mut seen = 0;
        let r = run_all(
            &tasks,
            (2, Duration::ZERO),
            |_| Duration::ZERO,
            work(),
            |_| seen += 1,
        );
        assert_eq!(seen, 4);
        assert_eq!(
            kinds(&r),
            [
                (1, Kind::Report),
                (0, Kind::Termination),
                (2, Kind::Report),
                (3, Kind::Report)
            ]
        );
        assert!(r[1].violations[0].examples[0].contains("did not return"));
    }

    #[test]
    fn after_too_many_abandoned_missions_no_more_start() {
        let mut tasks: Vec<Task> = (0..MAX_ABANDONED_PER_JOB).map(|_| task(0)).collect();
        tasks.push(task(5));
        let r = run_all(
            &tasks,
            (1, Duration::ZERO),
            |_| Duration::ZERO,
            work(),
            |_| {},
        );
        assert_eq!(r.len(), tasks.len());
        assert_eq!(r[MAX_ABANDONED_PER_JOB].violations[0].kind, Kind::Crash);
        assert!(r[MAX_ABANDONED_PER_JOB].violations[0].examples[0].contains("not run"));
    }
}
