//! Range-checking value parsers for command-line flags (clap `value_parser`s) and the same
//! checks for values that arrive already parsed. Each error is one line naming the allowed
//! range; clap prefixes the flag and the value.
//!
//! A flag whose value may start with `-` (so that `--time-limit -1` or `-inf` is refused by
//! the range, not taken for an unknown flag) also needs `allow_hyphen_values = true`, e.g.
//! `#[arg(long, default_value_t = 60.0, allow_hyphen_values = true,
//! value_parser = ranges::time_limit_s)]`.
#![cfg_attr(
    not(test),
    expect(dead_code, reason = "value parsers for the flag attributes of args.rs")
)]

/// Longest wall-clock limit a command accepts: one week. Longer limits are typing mistakes
/// (e.g. milliseconds for seconds), and the solver's iteration limits end it sooner anyway.
pub const MAX_TIME_LIMIT_S: f64 = 604_800.0;

/// Most runs (seeds) per instance of `strider gtsp bench`: 1000. Enough for any statistic;
/// beyond it a run count is a typing mistake that would keep the benchmark busy for days.
pub const MAX_RUNS: usize = 1000;

/// A number as an error shows it: scientific notation for very large or small magnitudes, so
/// that `1e300` is not printed as 301 digits.
pub fn show(v: f64) -> String {
    let a = v.abs();
    if a != 0.0 && a.is_finite() && !(1e-4..1e15).contains(&a) {
        format!("{v:e}")
    } else {
        v.to_string()
    }
}

/// Parses a number (accepting `nan`, `inf` and negatives, which the checks then refuse).
fn number(s: &str) -> Result<f64, String> {
    s.trim()
        .parse::<f64>()
        .map_err(|_| format!("'{s}' is not a number"))
}

/// Checks a wall-clock limit: a finite number of seconds in (0, [`MAX_TIME_LIMIT_S`]].
pub fn check_time_limit(v: f64) -> Result<f64, String> {
    if v.is_finite() && v > 0.0 && v <= MAX_TIME_LIMIT_S {
        Ok(v)
    } else {
        Err(format!(
            "must be a finite number of seconds > 0 and ≤ {MAX_TIME_LIMIT_S} (one week)"
        ))
    }
}

/// `value_parser` of a wall-clock limit in seconds; see [`check_time_limit`].
pub fn time_limit_s(s: &str) -> Result<f64, String> {
    check_time_limit(number(s)?)
}

/// Checks a value that must be finite and > 0 (a lengthscale, a signal variance).
pub fn check_positive(v: f64) -> Result<f64, String> {
    if v.is_finite() && v > 0.0 {
        Ok(v)
    } else {
        Err("must be a finite number > 0".into())
    }
}

/// `value_parser` of a finite positive number; see [`check_positive`].
pub fn positive(s: &str) -> Result<f64, String> {
    check_positive(number(s)?)
}

/// Checks a value that must be finite and ≥ 0 (a noise variance).
pub fn check_non_negative(v: f64) -> Result<f64, String> {
    if v.is_finite() && v >= 0.0 {
        Ok(v)
    } else {
        Err("must be a finite number ≥ 0".into())
    }
}

/// `value_parser` of a finite non-negative number; see [`check_non_negative`].
pub fn non_negative(s: &str) -> Result<f64, String> {
    check_non_negative(number(s)?)
}

/// `value_parser` of any finite number (a prior mean).
pub fn finite(s: &str) -> Result<f64, String> {
    let v = number(s)?;
    if v.is_finite() {
        Ok(v)
    } else {
        Err("must be a finite number".into())
    }
}

/// Checks a count in `lo..=hi`.
pub fn check_count(v: usize, lo: usize, hi: usize) -> Result<usize, String> {
    if (lo..=hi).contains(&v) {
        Ok(v)
    } else {
        Err(format!("must be an integer from {lo} to {hi}"))
    }
}

/// A `value_parser` of an integer count in `lo..=hi`, e.g. `count_in(1, MAX_RUNS)`.
pub fn count_in(lo: usize, hi: usize) -> impl Fn(&str) -> Result<usize, String> + Clone {
    move |s: &str| {
        let v = s
            .trim()
            .parse::<usize>()
            .map_err(|_| format!("'{s}' is not an integer from {lo} to {hi}"))?;
        check_count(v, lo, hi)
    }
}

/// `value_parser` of a seed: any integer in 0..=2⁶⁴−1 (a negative seed gets this range in its
/// error instead of clap's "invalid digit").
pub fn seed(s: &str) -> Result<u64, String> {
    s.trim()
        .parse::<u64>()
        .map_err(|_| format!("'{s}' is not an integer from 0 to {}", u64::MAX))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn time_limits() {
        assert_eq!(time_limit_s("0.5"), Ok(0.5));
        assert_eq!(time_limit_s("604800"), Ok(604_800.0));
        for bad in ["-1", "0", "nan", "NaN", "inf", "-inf", "1e300", "604801"] {
            let e = time_limit_s(bad).unwrap_err();
            assert!(
                e.contains("must be a finite number of seconds > 0"),
                "{bad}: {e}"
            );
        }
        assert_eq!(time_limit_s("soon").unwrap_err(), "'soon' is not a number");
    }

    #[test]
    fn counts_and_seeds() {
        let runs = count_in(1, MAX_RUNS);
        assert_eq!(runs("3"), Ok(3));
        assert_eq!(runs("0").unwrap_err(), "must be an integer from 1 to 1000");
        assert_eq!(
            runs("18446744073709551615").unwrap_err(),
            "must be an integer from 1 to 1000"
        );
        assert!(
            runs("-1")
                .unwrap_err()
                .contains("not an integer from 1 to 1000")
        );
        assert_eq!(seed("18446744073709551615"), Ok(u64::MAX));
        assert!(
            seed("-1")
                .unwrap_err()
                .contains("0 to 18446744073709551615")
        );
    }

    /// The parsers as clap uses them: the error names the flag, the value and the range.
    #[test]
    fn clap_reports_flag_value_and_range() {
        use clap::{Arg, Command};
        let cmd = Command::new("t")
            .arg(
                Arg::new("time-limit")
                    .long("time-limit")
                    .allow_hyphen_values(true)
                    .value_parser(time_limit_s),
            )
            .arg(
                Arg::new("runs")
                    .long("runs")
                    .allow_hyphen_values(true)
                    .value_parser(count_in(1, MAX_RUNS)),
            );
        for v in ["-1", "-inf", "nan", "0"] {
            let e = cmd
                .clone()
                .try_get_matches_from(["t", "--time-limit", v])
                .unwrap_err()
                .to_string();
            let want = format!(
                "invalid value '{v}' for '--time-limit <time-limit>': must be a finite number \
                 of seconds > 0 and ≤ 604800 (one week)"
            );
            assert!(e.contains(&want), "{e}");
        }
        let e = cmd
            .clone()
            .try_get_matches_from(["t", "--runs", "18446744073709551615"])
            .unwrap_err()
            .to_string();
        assert!(
            e.contains("invalid value '18446744073709551615' for '--runs <runs>'"),
            "{e}"
        );
        let m = cmd
            .try_get_matches_from(["t", "--time-limit", "2.5"])
            .unwrap();
        assert_eq!(m.get_one::<f64>("time-limit"), Some(&2.5));
    }

    #[test]
    fn numbers_show_compactly() {
        assert_eq!(show(1e300), "1e300");
        assert_eq!(show(2.5), "2.5");
        assert_eq!(show(1e-300), "1e-300");
        assert_eq!(show(f64::NAN), "NaN");
        assert_eq!(show(-1.0), "-1");
    }

    #[test]
    fn gp_hyperparameters() {
        assert_eq!(positive("0.4"), Ok(0.4));
        for bad in ["0", "-1", "nan", "inf"] {
            assert!(positive(bad).is_err(), "{bad}");
        }
        assert_eq!(non_negative("0"), Ok(0.0));
        assert!(non_negative("-0.1").is_err());
        assert_eq!(finite("-3"), Ok(-3.0));
        assert!(finite("nan").is_err());
    }
}
