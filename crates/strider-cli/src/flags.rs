//! The allowed range of every numeric flag, checked where the flag is parsed (clap value
//! parsers): a value out of range is a one-line error naming the flag, the value and the range,
//! before anything runs or allocates. The limits themselves live with the code they protect
//! (`strider_experiments`), each with the reason for its value.
//!
//! | flag | allowed |
//! |---|---|
//! | `--time-limit` (run, map build, bench) | finite, > 0 and ≤ 10⁶ simulated s |
//! | `--trials` (bench) | 1 ..= 10 000 |
//! | `--large-trials` (bench table5) | 0 (no large-world rows) ..= 10 000 |
//! | `--world-seeds` (bench) | 1 ..= 10⁶ |
//! | `--jobs` | 1 ..= 256; more than the CPUs run one thread per CPU |
//! | `--seeds` (tours) | 1 ..= 1000 |
//! | `--world-seeds` (tours) | 1 ..= 1000 (and at most 10 000 runs) |
//! | `--tours` | 1 ..= 10 000 |
//! | `--seeds` (navigate) | 1 ..= 1000 |
//! | `--runs` (navigate) | 1 ..= 1000 |
//! | `--lambda` (navigate) | finite, 0 ..= 100 |
//! | `--lane-spacing` (map build) | finite, > 0 and ≤ 1000 m |
//! | `--reps`, `--streams` (learn bench) | 1 ..= 1000 |
//! | `--pairs` (learn bench) | 2 ..= 2000 |
//! | `--c1-runs` (learn bench) | 1 ..= 1000 |
//! | `--c1-pairs` (learn bench) | 0 (the whole lane) ..= 100 000 |
//! | `--seed`, `--world-seed` | any integer 0 ..= 2⁶⁴ − 1 |
//! | `--rate` (run, replay) | finite, 0.01 ..= 10⁴ × real time |
//! | `--live` (run, replay) | an address IP:PORT (port 0: any free port) |

use std::fmt::Display;
use std::net::SocketAddr;
use std::str::FromStr;

use strider_experiments::live::DEFAULT_ADDR;
use strider_experiments::pace::Rate;
use strider_experiments::parallel::MAX_JOBS;
use strider_experiments::trial::{MAX_TIME_LIMIT_S, MAX_TRIALS};
use strider_experiments::{map_build, martin_corke, nardi19, pragr18, pragr19};

/// The most world seeds a bench cycles through (`--world-seeds`): more worlds than trials are
/// never used, so this only bounds the number.
pub const MAX_WORLD_SEEDS: u64 = 1_000_000;

/// An integer from `lo` to `hi`.
fn int_in<T>(s: &str, lo: T, hi: T) -> Result<T, String>
where
    T: FromStr + PartialOrd + Display + Copy,
{
    match s.trim().parse::<T>() {
        Ok(v) if lo <= v && v <= hi => Ok(v),
        _ => Err(format!("must be an integer from {lo} to {hi}")),
    }
}

/// A finite number > 0 and ≤ `hi`, in `unit`.
fn positive_up_to(s: &str, hi: f64, unit: &str) -> Result<f64, String> {
    match s.trim().parse::<f64>() {
        Ok(v) if v.is_finite() && v > 0.0 && v <= hi => Ok(v),
        _ => Err(format!(
            "must be a finite number of {unit} > 0 and ≤ {hi:e}"
        )),
    }
}

/// `--seed`, `--world-seed`: any 64-bit unsigned integer.
pub fn seed(s: &str) -> Result<u64, String> {
    int_in(s, 0, u64::MAX)
}

/// `--time-limit`: simulated seconds.
pub fn time_limit(s: &str) -> Result<f64, String> {
    positive_up_to(s, MAX_TIME_LIMIT_S, "simulated seconds")
}

/// `--trials` of a bench.
pub fn trials(s: &str) -> Result<usize, String> {
    int_in(s, 1, MAX_TRIALS)
}

/// `--large-trials` of table5 (0 leaves out the large world).
pub fn large_trials(s: &str) -> Result<usize, String> {
    int_in(s, 0, MAX_TRIALS)
}

/// `--world-seeds` of a bench.
pub fn world_seeds(s: &str) -> Result<u64, String> {
    int_in(s, 1, MAX_WORLD_SEEDS)
}

/// `--jobs`.
pub fn jobs(s: &str) -> Result<usize, String> {
    int_in(s, 1, MAX_JOBS)
}

/// `--seeds` of `strider tours`.
pub fn tour_seeds(s: &str) -> Result<u64, String> {
    int_in(s, 1, martin_corke::MAX_SEEDS)
}

/// `--world-seeds` of `strider tours`.
pub fn tour_worlds(s: &str) -> Result<u64, String> {
    int_in(s, 1, martin_corke::MAX_WORLDS)
}

/// `--tours` of `strider tours`.
pub fn tours(s: &str) -> Result<usize, String> {
    int_in(s, 1, martin_corke::MAX_TOURS)
}

/// `--seeds` of `strider navigate`.
pub fn navigate_seeds(s: &str) -> Result<u64, String> {
    int_in(s, 1, nardi19::MAX_SEEDS)
}

/// `--runs` of `strider navigate`.
pub fn runs(s: &str) -> Result<usize, String> {
    int_in(s, 1, nardi19::MAX_RUNS)
}

/// `--lambda` of `strider navigate`.
pub fn lambda(s: &str) -> Result<f64, String> {
    match s.trim().parse::<f64>() {
        Ok(v) if v.is_finite() && (0.0..=nardi19::MAX_LAMBDA).contains(&v) => Ok(v),
        _ => Err(format!(
            "must be a finite number from 0 to {}",
            nardi19::MAX_LAMBDA
        )),
    }
}

/// `--lane-spacing` of `strider map build`, m.
pub fn lane_spacing(s: &str) -> Result<f64, String> {
    positive_up_to(s, map_build::MAX_LANE_SPACING_M, "metres")
}

/// `--reps` of `strider learn bench`.
pub fn reps(s: &str) -> Result<usize, String> {
    int_in(s, 1, pragr19::MAX_REPS)
}

/// `--streams` of `strider learn bench`.
pub fn streams(s: &str) -> Result<usize, String> {
    int_in(s, 1, pragr19::MAX_STREAMS)
}

/// `--pairs` of `strider learn bench`.
pub fn pairs(s: &str) -> Result<usize, String> {
    int_in(s, 2, pragr19::MAX_PAIRS)
}

/// `--c1-runs` of `strider learn bench`.
pub fn c1_runs(s: &str) -> Result<usize, String> {
    int_in(s, 1, pragr18::MAX_C1_RUNS)
}

/// `--c1-pairs` of `strider learn bench` (0: the whole lane).
pub fn c1_pairs(s: &str) -> Result<usize, String> {
    int_in(s, 0, pragr18::MAX_C1_PAIRS)
}

/// `--rate` of `strider run` and `strider replay`: a multiple of real time.
pub fn rate(s: &str) -> Result<Rate, String> {
    let v = s.trim().parse::<f64>().unwrap_or(f64::NAN);
    Rate::new(v).map_err(|e| e.to_string())
}

/// `--live ADDR` of `strider run` and `strider replay`. A value that is no address is most
/// likely the positional argument after a bare `--live`, hence the hint.
pub fn live_addr(s: &str) -> Result<SocketAddr, String> {
    s.trim().parse::<SocketAddr>().map_err(|_| {
        format!(
            "not an address IP:PORT such as {DEFAULT_ADDR} (a bare --live goes after the other arguments, or write --live=ADDR)"
        )
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn values_in_range_are_read_and_others_name_the_range() {
        assert_eq!(time_limit("20"), Ok(20.0));
        assert_eq!(time_limit("1e6"), Ok(1e6));
        for bad in ["-1", "0", "NaN", "inf", "1e7", "x", ""] {
            let e = time_limit(bad).unwrap_err();
            assert!(e.contains("> 0 and ≤ 1e6"), "{bad}: {e}");
        }
        assert_eq!(trials("25"), Ok(25));
        for bad in ["0", "-1", "18446744073709551615", "1e3", "10001"] {
            assert_eq!(
                trials(bad),
                Err("must be an integer from 1 to 10000".into())
            );
        }
        assert_eq!(large_trials("0"), Ok(0));
        assert_eq!(jobs("256"), Ok(256));
        assert!(jobs("2000").is_err() && jobs("0").is_err());
        assert_eq!(
            tour_seeds("18446744073709551615"),
            Err("must be an integer from 1 to 1000".into())
        );
        assert_eq!(
            lane_spacing("1e9"),
            Err("must be a finite number of metres > 0 and ≤ 1e3".into())
        );
        assert_eq!(lambda("0"), Ok(0.0));
        assert!(lambda("-0.5").is_err() && lambda("NaN").is_err());
        assert_eq!(c1_pairs("0"), Ok(0));
        assert!(pairs("1").is_err());
        assert_eq!(rate("1").map(Rate::get), Ok(1.0));
        for bad in ["0", "-1", "NaN", "1e5", "x"] {
            let e = rate(bad).unwrap_err();
            assert!(e.contains("from 0.01 to 1e4"), "{bad}: {e}");
        }
        assert_eq!(live_addr("127.0.0.1:0"), Ok("127.0.0.1:0".parse().unwrap()));
        assert!(live_addr("log.mcap").unwrap_err().contains("--live=ADDR"));
    }
}
