//! The statistics of every experiment, one definition of each: mean, median, sample standard
//! deviation, population variance, minimum and maximum, the [`Summary`] of a sample, column-wise
//! means over repetitions, and the Mann–Whitney U test with the paired win fraction.
//!
//! # Conventions
//!
//! * **Input.** Every function takes plain `&[f64]` samples. The plain functions ([`mean`],
//!   [`median`], …) return `None` for an empty sample; [`Summary::of`] and the tests reject empty
//!   samples and non-finite values (NaN, ±∞) with a [`StatsError`] that names the offending
//!   sample and index. No function panics on bad input.
//! * **Median.** The middle value of the sorted sample; for an even count the mean of the two
//!   middle values (NumPy's `np.median`).
//! * **Standard deviation.** The *sample* standard deviation (divisor `n − 1`, like NumPy's
//!   `ddof=1`), defined as `0` for a single observation. [`mean_population_variance`] divides by `n`.
//! * **[`mann_whitney_u`].** Follows `scipy.stats.mannwhitneyu` (SciPy ≥ 1.7) exactly:
//!   - ranks are computed on the pooled sample, ties get midranks (average ranks);
//!   - `U_a = R_a − n_a(n_a + 1)/2` where `R_a` is the rank sum of the first sample, so `U_a`
//!     counts the pairs `(i, j)` with `a[i] > b[j]` (ties counting ½), and `U_b = n_a·n_b − U_a`.
//!     SciPy's reported statistic is `U_a`;
//!   - `p_less` tests the alternative "the distribution underlying `a` is stochastically *less*
//!     than that of `b`" (`a` tends to be smaller, e.g. shorter tour times); `p_greater` the
//!     opposite; `p_two_sided` either direction;
//!   - [`Method::Exact`] uses the exact null distribution of `U` (all `C(n_a + n_b, n_a)`
//!     rank assignments equally likely, no ties), `p_greater = P(U ≥ U_a)`,
//!     `p_less = P(U ≥ U_b)`, `p_two_sided = min(1, 2·P(U ≥ max(U_a, U_b)))` — SciPy's
//!     `method='exact'`;
//!   - [`Method::Normal`] is the normal approximation with the tie-corrected variance
//!     `σ² = n_a n_b / 12 · ((n + 1) − Σ(t³ − t) / (n(n − 1)))` (`t` = tie-group sizes) and a
//!     continuity correction of `−0.5` applied to `U − n_a n_b / 2` before dividing by `σ`, the
//!     p-value being the upper normal tail of the relevant `U` (`U_a`, `U_b` or `max(U_a, U_b)`
//!     doubled), exactly SciPy's `method='asymptotic', use_continuity=True`. When every value is
//!     tied (`σ = 0`) all p-values are `1`, as in SciPy.
//!   - [`mann_whitney_u`] picks the method automatically: **exact when both samples have at most
//!     [`EXACT_MAX_N`] = 20 observations and there are no ties, normal otherwise.** (SciPy's own
//!     `method='auto'` uses a different threshold, 8; pass the method explicitly to
//!     [`mann_whitney_u_with`] to reproduce a specific SciPy call.)
//!   - the effect size is the common-language effect size `U_a / (n_a n_b)`, i.e.
//!     `P(A > B) + ½ P(A = B)` for random draws `A` from `a` and `B` from `b`: values below ½
//!     mean `a` tends to be smaller.
//! * **[`paired_win_fraction`].** Fraction of indices `i` with `a[i] < b[i]` (strictly; ties are
//!   not wins), e.g. how often method `a` finished faster than method `b` on the same trial.

mod erfc;
mod mann_whitney;

pub use mann_whitney::{
    EXACT_MAX_N, MannWhitney, Method, mann_whitney_u, mann_whitney_u_with, paired_win_fraction,
};

use std::fmt;

/// Errors returned by the functions of this module. Nothing here panics on bad input.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum StatsError {
    /// A sample had no observations.
    #[error("sample `{sample}` is empty")]
    Empty {
        /// Name of the offending sample (`"x"` for [`Summary::of`], `"a"` or `"b"` otherwise).
        sample: &'static str,
    },
    /// A sample contained NaN or an infinity.
    #[error("sample `{sample}` has a non-finite value {value} at index {index}")]
    NonFinite {
        /// Name of the offending sample.
        sample: &'static str,
        /// Index of the first non-finite value.
        index: usize,
        /// The value itself (NaN, `inf` or `-inf`).
        value: f64,
    },
    /// Index-paired samples had different lengths.
    #[error("paired samples have different lengths: a has {len_a}, b has {len_b}")]
    LengthMismatch {
        /// Length of `a`.
        len_a: usize,
        /// Length of `b`.
        len_b: usize,
    },
    /// [`Method::Exact`] was requested but cannot be used.
    #[error("exact Mann–Whitney distribution unavailable: {reason}")]
    ExactUnavailable {
        /// Why: ties in the data, or a sample too large for exact counting.
        reason: &'static str,
    },
}

/// Checks that `xs` is non-empty and all-finite.
pub(crate) fn validate(sample: &'static str, xs: &[f64]) -> Result<(), StatsError> {
    if xs.is_empty() {
        return Err(StatsError::Empty { sample });
    }
    match xs.iter().position(|v| !v.is_finite()) {
        Some(index) => Err(StatsError::NonFinite {
            sample,
            index,
            value: xs[index],
        }),
        None => Ok(()),
    }
}

/// Descriptive statistics of one sample (e.g. the exploration times of one method over trials).
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct Summary {
    /// Number of observations (≥ 1).
    pub n: usize,
    /// Arithmetic mean.
    pub mean: f64,
    /// Sample standard deviation (divisor `n − 1`); `0` when `n = 1`.
    pub std: f64,
    /// Smallest observation.
    pub min: f64,
    /// Largest observation.
    pub max: f64,
    /// Median (mean of the two middle observations when `n` is even).
    pub median: f64,
}

impl Summary {
    /// Summarises a sample.
    ///
    /// # Errors
    /// [`StatsError::Empty`] for an empty slice, [`StatsError::NonFinite`] if any value is NaN or
    /// infinite (the error carries the sample name `"x"`).
    pub fn of(xs: &[f64]) -> Result<Summary, StatsError> {
        validate("x", xs)?;
        let n = xs.len();
        let mean = mean_of_nonempty(xs);
        let sorted = sorted(xs);
        Ok(Summary {
            n,
            mean,
            std: std_about(xs, mean),
            min: sorted[0],
            max: sorted[n - 1],
            median: median_of_sorted(&sorted),
        })
    }
}

impl fmt::Display for Summary {
    /// Formats as `mean ± std`; a precision applies to both numbers (`format!("{s:.1}")` gives
    /// e.g. `"123.4 ± 5.6"`).
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match f.precision() {
            Some(p) => write!(f, "{:.p$} ± {:.p$}", self.mean, self.std),
            None => write!(f, "{} ± {}", self.mean, self.std),
        }
    }
}

/// A mean and a sample standard deviation (a published figure, or ours over seeds).
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct MeanStd {
    /// Mean.
    pub mean: f64,
    /// Sample standard deviation.
    pub std: f64,
}

impl MeanStd {
    /// Of the finite values of `xs` (NaN, NaN when there are none).
    pub fn of_finite(xs: &[f64]) -> Self {
        let (mean, std) = mean_std_finite(xs);
        Self { mean, std }
    }
}

/// Arithmetic mean; `None` for an empty sample.
pub fn mean(xs: &[f64]) -> Option<f64> {
    (!xs.is_empty()).then(|| mean_of_nonempty(xs))
}

/// Median (the module's convention: the mean of the two middle values for an even count);
/// `None` for an empty sample.
pub fn median(xs: &[f64]) -> Option<f64> {
    (!xs.is_empty()).then(|| median_of_sorted(&sorted(xs)))
}

/// Sample standard deviation (divisor `n − 1`, `0` for one value); `None` for an empty sample.
pub fn sample_std(xs: &[f64]) -> Option<f64> {
    mean(xs).map(|m| std_about(xs, m))
}

/// Mean and population variance (divisor `n`); `None` for an empty sample.
pub fn mean_population_variance(xs: &[f64]) -> Option<(f64, f64)> {
    let m = mean(xs)?;
    Some((m, sum_squared_deviations(xs, m) / xs.len() as f64))
}

/// Largest value (NaNs ignored); `None` for an empty sample.
pub fn max(xs: &[f64]) -> Option<f64> {
    xs.iter().copied().reduce(f64::max)
}

/// Smallest value (NaNs ignored); `None` for an empty sample.
pub fn min(xs: &[f64]) -> Option<f64> {
    xs.iter().copied().reduce(f64::min)
}

/// Mean and sample standard deviation of the finite values (NaN, NaN when there are none).
pub fn mean_std_finite(xs: &[f64]) -> (f64, f64) {
    let finite: Vec<f64> = xs.iter().copied().filter(|x| x.is_finite()).collect();
    Summary::of(&finite).map_or((f64::NAN, f64::NAN), |s| (s.mean, s.std))
}

/// (median, max) of a series of latencies; (0, 0) when there are none.
pub fn median_max(xs: &[f64]) -> (f64, f64) {
    let s = sorted(xs);
    match s.last() {
        Some(&last) => (median_of_sorted(&s), last),
        None => (0.0, 0.0),
    }
}

/// Per position, the mean over `rows` (positions up to the shortest row).
pub fn column_means(rows: &[Vec<f64>]) -> Vec<f64> {
    columns(rows)
        .iter()
        .map(|c| mean(c).unwrap_or(f64::NAN))
        .collect()
}

/// Per position, the sample standard deviation over `rows` (0 for one row).
pub fn column_stds(rows: &[Vec<f64>]) -> Vec<f64> {
    columns(rows)
        .iter()
        .map(|c| sample_std(c).unwrap_or(f64::NAN))
        .collect()
}

/// The columns of `rows`, up to the shortest row.
fn columns(rows: &[Vec<f64>]) -> Vec<Vec<f64>> {
    let n = rows.iter().map(Vec::len).min().unwrap_or(0);
    (0..n)
        .map(|k| rows.iter().map(|r| r[k]).collect())
        .collect()
}

fn mean_of_nonempty(xs: &[f64]) -> f64 {
    xs.iter().sum::<f64>() / xs.len() as f64
}

fn sorted(xs: &[f64]) -> Vec<f64> {
    let mut s = xs.to_vec();
    s.sort_by(f64::total_cmp);
    s
}

/// The median of a sorted, non-empty sample.
fn median_of_sorted(s: &[f64]) -> f64 {
    let n = s.len();
    if n % 2 == 1 {
        s[n / 2]
    } else {
        0.5 * (s[n / 2 - 1] + s[n / 2])
    }
}

fn sum_squared_deviations(xs: &[f64], mean: f64) -> f64 {
    xs.iter().map(|&x| (x - mean) * (x - mean)).sum()
}

/// Sample standard deviation about `mean` (two-pass: numerically stable enough for trial
/// times); `0` for one value.
fn std_about(xs: &[f64], mean: f64) -> f64 {
    if xs.len() > 1 {
        (sum_squared_deviations(xs, mean) / (xs.len() as f64 - 1.0)).sqrt()
    } else {
        0.0
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn median_is_the_mean_of_the_two_middle_values_everywhere() {
        let v = [4.0, 1.0, 3.0, 2.0];
        assert_eq!(median(&v), Some(2.5));
        assert_eq!(median_max(&v), (2.5, 4.0));
        assert_eq!(Summary::of(&v).unwrap().median, 2.5);
        assert_eq!(median(&[3.0, 1.0, 2.0]), Some(2.0));
        assert_eq!(median(&[]), None);
        assert_eq!(median_max(&[]), (0.0, 0.0));
    }

    #[test]
    fn plain_statistics() {
        let v = [1.0, 2.0, 3.0, 6.0];
        assert_eq!(mean(&v), Some(3.0));
        assert_eq!(mean(&[]), None);
        assert_eq!(sample_std(&[5.0]), Some(0.0));
        assert!((sample_std(&v).unwrap() - (14.0f64 / 3.0).sqrt()).abs() < 1e-12);
        assert_eq!(mean_population_variance(&v), Some((3.0, 3.5)));
        assert_eq!((min(&v), max(&v)), (Some(1.0), Some(6.0)));
        assert_eq!(mean_std_finite(&[f64::NAN, 2.0, 4.0]).0, 3.0);
        assert!(mean_std_finite(&[f64::NAN]).0.is_nan());
    }

    #[test]
    fn column_statistics_stop_at_the_shortest_row() {
        let rows = vec![vec![1.0, 2.0, 9.0], vec![3.0, 6.0]];
        assert_eq!(column_means(&rows), vec![2.0, 4.0]);
        let s = column_stds(&rows);
        assert!((s[0] - 2f64.sqrt()).abs() < 1e-12 && (s[1] - 8f64.sqrt()).abs() < 1e-12);
        assert_eq!(column_stds(&rows[..1]), vec![0.0, 0.0, 0.0]);
    }
}
