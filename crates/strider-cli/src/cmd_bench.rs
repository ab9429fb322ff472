//! The papers' benchmarks: `strider bench table5`, `strider bench compare`, `strider tours`
//! and `strider navigate`.

use anyhow::{Context, Result, bail};
use strider_experiments::compare::{self, CompareOptions, Entrant};
use strider_experiments::martin_corke::{self, ToursOptions};
use strider_experiments::nardi19::{self, NavigateOptions};
use strider_experiments::parallel::{available_jobs, threads};
use strider_experiments::pragr22::{self, Table5Options, table5 as run_table5};
use strider_experiments::progress::Progress;
use strider_explore::navigate::Objective;

use strider_experiments::cancel::Interrupted;

use crate::args::{CompareArgs, MergeArgs, NavigateArgs, Table5Args, ToursArgs};
use crate::interrupt;
use crate::progress::Bar;

/// `strider bench table5`: Prágr22 Table 5.
pub fn table5(a: &Table5Args) -> Result<()> {
    let o = Table5Options {
        trials: a.trials,
        large_trials: a.large_trials.unwrap_or(a.trials),
        world_seeds: a.world_seeds,
        jobs: threads(a.jobs.unwrap_or_else(available_jobs)),
        time_limit: a.time_limit,
        mcap_dir: a.mcap_dir.clone(),
        resume: a.resume,
        cancel: interrupt::winds_down().clone(),
        shard: a.shard.as_deref().map(compare::Shard::parse).transpose()?,
        sets: crate::cmd_run::parse_sets(&a.sets, None)?,
    };
    let bar = Bar::new("{spinner} table 5: {pos}/{len} trials ({elapsed}, eta {eta})");
    let t = run_table5(&o, &a.out, &bar)?;
    drop(bar);
    if !t.complete() {
        let table = if t.finished > 0 {
            format!(
                " and their table {} (\"complete\": false)",
                t.json.display()
            )
        } else {
            String::new()
        };
        return Err(Interrupted::new(format!(
            "kept {} of {} trials in {}{table}; continue with `{}`",
            t.finished,
            t.total,
            t.trials_dir.display(),
            table5_resume_command(a, &o)
        ))
        .into());
    }
    print!("{}", t.markdown);
    println!("-> {} and {}", t.json.display(), t.md.display());
    Ok(())
}

/// The command that continues an interrupted `strider bench table5`.
fn table5_resume_command(a: &Table5Args, o: &Table5Options) -> String {
    let mut c = format!(
        "strider bench table5 --trials {} --large-trials {} --world-seeds {}",
        o.trials, o.large_trials, o.world_seeds
    );
    if let Some(t) = o.time_limit {
        c.push_str(&format!(" --time-limit {t}"));
    }
    if let Some(d) = &o.mcap_dir {
        c.push_str(&format!(" --mcap-dir {}", d.display()));
    }
    if let Some(s) = o.shard {
        c.push_str(&format!(" --shard {}/{}", s.k, s.n));
    }
    c.push_str(&format!(" --out {} --resume", a.out.display()));
    c
}

/// `strider bench compare`: the registry's strategies on the same worlds.
pub fn compare(a: &CompareArgs) -> Result<()> {
    let o = CompareOptions {
        scenarios: a.scenarios.clone(),
        trials: a.trials,
        world_seeds: a.world_seeds,
        jobs: threads(a.jobs.unwrap_or_else(available_jobs)),
        time_limit: a.time_limit,
        cancel: interrupt::winds_down().clone(),
        shard: a.shard.as_deref().map(compare::Shard::parse).transpose()?,
    };
    let entrants = a
        .strategies
        .iter()
        .map(|n| Entrant::registered(n))
        .collect::<Result<Vec<_>>>()?;
    let bar = Bar::new("{spinner} compare: {pos}/{len} trials ({elapsed}, eta {eta})");
    let all = o.scenarios.len() * entrants.len() * o.trials;
    // A shard runs about one N-th of the trials.
    bar.start(o.shard.map_or(all, |s| all.div_ceil(s.n)) as u64);
    let wall = std::time::Instant::now();
    let result = compare::run(&o, &entrants, || bar.inc())?;
    drop(bar);
    let command = compare::command_line(&o, &a.strategies);
    if result.completion.interrupted {
        if result.trials.is_empty() {
            return Err(Interrupted::new(
                "no trial had finished, nothing was kept; run the command again",
            )
            .into());
        }
        compare::write(&a.out, &result, &command)?;
        return Err(Interrupted::new(format!(
            "kept the comparison of the {} trials finished, {} (\"complete\": false); `bench compare` cannot resume: run `{command}` again for all of them",
            result.trials.len(),
            a.out.join("compare.json").display()
        ))
        .into());
    }
    compare::write(&a.out, &result, &command)?;
    print!("{}", compare::markdown(&result, &command));
    println!(
        "{} trials in {:.0} s wall -> {}",
        result.trials.len(),
        wall.elapsed().as_secs_f64(),
        a.out.join("compare.md").display()
    );
    Ok(())
}

/// `strider bench merge`: the shards of a comparison or of Table 5 joined into the whole.
pub fn merge(a: &MergeArgs) -> Result<()> {
    if a.dirs
        .first()
        .is_some_and(|d| d.join("table5.json").is_file())
    {
        return merge_table5(a);
    }
    let (result, command) = compare::merge(&a.dirs)?;
    compare::write(&a.out, &result, &command)?;
    print!("{}", compare::markdown(&result, &command));
    println!(
        "{} trials from {} shards -> {}",
        result.trials.len(),
        a.dirs.len(),
        a.out.join("compare.md").display()
    );
    Ok(())
}

/// `strider bench merge` of Table 5 shards.
fn merge_table5(a: &MergeArgs) -> Result<()> {
    let report = pragr22::merge_table5(&a.dirs)?;
    let md = pragr22::markdown(&report);
    pragr22::write_table5(&a.out, &report, &md)?;
    print!("{md}");
    println!(
        "{} trials from {} shards -> {}",
        report.trial_results.len(),
        a.dirs.len(),
        a.out.join("table5.md").display()
    );
    Ok(())
}

/// `strider tours`: MartinCorke's repeated tours.
pub fn tours(a: &ToursArgs) -> Result<()> {
    let lines = martin_corke::tours(&ToursOptions {
        scenario: a.scenario.clone(),
        world_seed: a.world_seed,
        world_seeds: a.world_seeds,
        seed: a.seed,
        seeds: a.seeds,
        tours: a.tours,
        out: a.out.clone(),
    })?;
    for line in lines {
        println!("{line}");
    }
    Ok(())
}

/// `strider navigate`: Nardi19's repeated navigation.
pub fn navigate(a: &NavigateArgs) -> Result<()> {
    let o = NavigateOptions {
        scenario: a.scenario.clone(),
        seed: a.seed,
        out: a.out.clone(),
        sites: parse_list(&a.sites, "--sites", |s| s.parse::<u64>().ok())?,
        seeds: a.seeds,
        runs: a.runs,
        objectives: parse_list(&a.objectives, "--objectives", Objective::parse)?,
        lambda: a.lambda,
        aerial: a.aerial.clone(),
        jobs: threads(a.jobs.unwrap_or_else(available_jobs)),
    };
    let bar = Bar::new("{bar:30} {pos}/{len} runs ({elapsed}) {msg}");
    if let Some(list) = &a.lambdas {
        let lambdas = parse_list(list, "--lambdas", |s| s.parse::<f64>().ok())?;
        let done = nardi19::sweep_lambdas(&o, &lambdas, &bar)?;
        drop(bar);
        for d in done {
            println!("{d}");
        }
        println!("wrote {}", a.out.join("lambdas.md").display());
        return Ok(());
    }
    let done = nardi19::run(&o, &bar)?;
    drop(bar);
    println!("{done}");
    Ok(())
}

/// A comma-separated list of `flag`, each item read by `parse`.
fn parse_list<T>(s: &str, flag: &str, parse: impl Fn(&str) -> Option<T>) -> Result<Vec<T>> {
    let v: Vec<T> = s
        .split(',')
        .map(str::trim)
        .filter(|t| !t.is_empty())
        .map(|t| parse(t).with_context(|| format!("{flag}: cannot read {t:?}")))
        .collect::<Result<_>>()?;
    if v.is_empty() {
        bail!("{flag} lists nothing");
    }
    Ok(v)
}

/// `strider bench soak`: invariants at scale; fails when any invariant broke.
pub fn soak(a: &crate::args::SoakArgs) -> Result<()> {
    use strider_experiments::soak::{self, SoakOptions};
    let o = SoakOptions {
        missions: a.missions,
        seed: a.seed,
        jobs: a.jobs.unwrap_or_else(available_jobs),
        time_limit: a.time_limit,
        rerun: a.rerun.clone(),
    };
    let bar = Bar::new("{spinner} soak: {pos}/{len} missions ({elapsed}, eta {eta})");
    let s = soak::run(&o, &bar)?;
    drop(bar);
    soak::write(&a.out, &s)?;
    print!("{}", soak::markdown(&s));
    println!("-> {}", a.out.join("soak.md").display());
    if s.violations > 0 {
        bail!(
            "{}: see {} for what broke and how to rerun each",
            s.summary,
            a.out.join("soak.md").display()
        );
    }
    Ok(())
}

/// `strider bench scale`: one exploration of a large world, sampled over time.
pub fn scale(a: &crate::args::ScaleArgs) -> Result<()> {
    use strider_experiments::scale::{self, ScaleOptions};
    let o = ScaleOptions {
        scenario: a.scenario.clone(),
        world_seed: a.world_seed,
        seed: a.seed,
        strategy: a.strategy.clone(),
        time_limit: a.time_limit,
        window_s: a.window,
        cancel: interrupt::winds_down().clone(),
    };
    let bar = Bar::new("{spinner} scale: {pos}/{len} simulated s ({elapsed}) {msg}");
    let r = scale::scale(&o, &a.out, &bar)?;
    drop(bar);
    print!("{}", scale::markdown(&r));
    println!("-> {}", a.out.join("scale.md").display());
    Ok(())
}
