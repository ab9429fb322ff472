//! `strider learn bench` (the learner benchmarks of Prágr19 and Prágr18) and `strider learn
//! c4-vegetation` (Prágr23 §5.3).

use std::time::Instant;

use anyhow::{Result, bail};
use strider_experiments::io::create_dir;
use strider_experiments::parallel::{available_jobs, pool, threads};
use strider_experiments::pragr18::{C1Options, c1_bench};
use strider_experiments::pragr19::{StreamOptions, stream_bench};
use strider_experiments::pragr23::vegetation;

use crate::args::{LearnBenchArgs, VegetationArgs};

/// `strider learn bench`: the stream protocol, the C1 protocol or both.
pub fn bench(a: &LearnBenchArgs) -> Result<()> {
    let wall = Instant::now();
    let (stream, c1) = match a.protocol.as_str() {
        "stream" => (true, false),
        "c1" => (false, true),
        "all" => (true, true),
        p => bail!("--protocol must be stream, c1 or all, got {p:?}"),
    };
    let stream_options = StreamOptions {
        reps: a.reps,
        streams: a.streams,
        pairs: a.pairs,
        seed: a.seed,
        out: a.out.clone(),
    };
    let c1_options = C1Options {
        runs: a.c1_runs,
        pairs: a.c1_pairs,
        seed: a.seed,
        out: a.out.clone(),
    };
    if stream {
        stream_options.check()?;
    }
    if c1 {
        c1_options.check()?;
    }
    create_dir(&a.out)?;
    let pool = pool(threads(a.jobs.unwrap_or_else(available_jobs)))?;
    let mut summary = Vec::new();
    if stream {
        let t = Instant::now();
        let s = pool.install(|| stream_bench(&stream_options))?;
        summary.push(format!("{s} ({:.0} s)", t.elapsed().as_secs_f64()));
    }
    if c1 {
        let t = Instant::now();
        let s = pool.install(|| c1_bench(&c1_options))?;
        summary.push(format!("{s} ({:.0} s)", t.elapsed().as_secs_f64()));
    }
    println!(
        "learn bench: {}; {:.1} s wall -> {}",
        summary.join("; "),
        wall.elapsed().as_secs_f64(),
        a.out.display()
    );
    Ok(())
}

/// `strider learn c4-vegetation`: the force predictor in three presentation orders.
pub fn vegetation(a: &VegetationArgs) -> Result<()> {
    println!("{}", vegetation::bench(&a.out)?);
    Ok(())
}
