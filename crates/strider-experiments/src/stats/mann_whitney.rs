//! The Mann–Whitney U test (SciPy's `mannwhitneyu`, see the conventions of [`super`]) and the
//! paired win fraction.

use super::erfc::normal_sf;
use super::{StatsError, validate};

/// Largest per-sample size for which [`mann_whitney_u`] uses the exact null distribution (when
/// there are also no ties). Above this, the normal approximation is used.
pub const EXACT_MAX_N: usize = 20;

/// How the p-values of a Mann–Whitney test were computed.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Method {
    /// Exact null distribution of `U` (no ties); SciPy's `method='exact'`.
    Exact,
    /// Normal approximation with tie correction and continuity correction; SciPy's
    /// `method='asymptotic', use_continuity=True`.
    Normal,
}

/// Result of a two-sample Mann–Whitney U test (see the module docs for the conventions).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MannWhitney {
    /// Size of the first sample `a`.
    pub n_a: usize,
    /// Size of the second sample `b`.
    pub n_b: usize,
    /// `U` of the first sample: `R_a − n_a(n_a + 1)/2` = number of pairs with `a[i] > b[j]`,
    /// ties counting ½. This is the statistic SciPy reports.
    pub u_a: f64,
    /// `U` of the second sample, `n_a·n_b − u_a`.
    pub u_b: f64,
    /// p-value for the two-sided alternative (the distributions differ).
    pub p_two_sided: f64,
    /// p-value for the alternative "`a` is stochastically less than `b`" (`a` tends to be
    /// smaller); SciPy's `alternative='less'`.
    pub p_less: f64,
    /// p-value for the alternative "`a` is stochastically greater than `b`"; SciPy's
    /// `alternative='greater'`.
    pub p_greater: f64,
    /// How the p-values were computed.
    pub method: Method,
    /// Whether the pooled sample contains tied values.
    pub has_ties: bool,
    /// Common-language effect size `u_a / (n_a·n_b)` = `P(A > B) + ½ P(A = B)`; below ½ means
    /// `a` tends to be smaller than `b`.
    pub effect_size: f64,
}

/// Mann–Whitney U test of `a` against `b`, choosing the method automatically: [`Method::Exact`]
/// when both samples have at most [`EXACT_MAX_N`] observations and there are no ties,
/// [`Method::Normal`] otherwise.
///
/// # Errors
/// [`StatsError::Empty`] / [`StatsError::NonFinite`] (sample `"a"` or `"b"`) on bad input.
pub fn mann_whitney_u(a: &[f64], b: &[f64]) -> Result<MannWhitney, StatsError> {
    mann_whitney_impl(a, b, None)
}

/// Mann–Whitney U test of `a` against `b` with an explicitly chosen method, to reproduce a
/// specific `scipy.stats.mannwhitneyu(a, b, method=..., use_continuity=True)` call.
///
/// # Errors
/// As [`mann_whitney_u`], plus [`StatsError::ExactUnavailable`] when [`Method::Exact`] is asked
/// for data with ties (the exact distribution here assumes none) or for samples so large that
/// the number of rank assignments overflows 128-bit counting.
pub fn mann_whitney_u_with(
    a: &[f64],
    b: &[f64],
    method: Method,
) -> Result<MannWhitney, StatsError> {
    mann_whitney_impl(a, b, Some(method))
}

fn mann_whitney_impl(
    a: &[f64],
    b: &[f64],
    method: Option<Method>,
) -> Result<MannWhitney, StatsError> {
    validate("a", a)?;
    validate("b", b)?;
    let (n1, n2) = (a.len(), b.len());
    let pooled: Vec<f64> = a.iter().chain(b).copied().collect();
    let (ranks, tie_sizes) = midranks(&pooled);
    let has_ties = !tie_sizes.is_empty();

    let r1: f64 = ranks[..n1].iter().sum();
    let (n1f, n2f) = (n1 as f64, n2 as f64);
    let u_a = r1 - n1f * (n1f + 1.0) / 2.0;
    let u_b = n1f * n2f - u_a;

    let method = method.unwrap_or(if n1 <= EXACT_MAX_N && n2 <= EXACT_MAX_N && !has_ties {
        Method::Exact
    } else {
        Method::Normal
    });

    let (p_greater, p_less, p_max) = match method {
        Method::Exact => {
            if has_ties {
                return Err(StatsError::ExactUnavailable {
                    reason: "the samples contain ties",
                });
            }
            let dist = ExactU::new(n1, n2).ok_or(StatsError::ExactUnavailable {
                reason: "too many rank assignments to count exactly",
            })?;
            // Without ties U is an integer; rounding only removes float noise.
            let (ua, ub) = (u_a.round() as usize, u_b.round() as usize);
            (dist.sf(ua), dist.sf(ub), dist.sf(ua.max(ub)))
        }
        Method::Normal => {
            let n = n1f + n2f;
            let tie_term: f64 = tie_sizes
                .iter()
                .map(|&t| {
                    let t = t as f64;
                    t * t * t - t
                })
                .sum();
            let sigma = (n1f * n2f / 12.0 * ((n + 1.0) - tie_term / (n * (n - 1.0)))).sqrt();
            let mu = n1f * n2f / 2.0;
            let sf = |u: f64| {
                if sigma > 0.0 && sigma.is_finite() {
                    normal_sf((u - mu - 0.5) / sigma)
                } else {
                    // All values tied: SciPy gets z = −∞, i.e. p = 1.
                    1.0
                }
            };
            (sf(u_a), sf(u_b), sf(u_a.max(u_b)))
        }
    };

    Ok(MannWhitney {
        n_a: n1,
        n_b: n2,
        u_a,
        u_b,
        p_two_sided: (2.0 * p_max).clamp(0.0, 1.0),
        p_less: p_less.clamp(0.0, 1.0),
        p_greater: p_greater.clamp(0.0, 1.0),
        method,
        has_ties,
        effect_size: u_a / (n1f * n2f),
    })
}

/// Fraction of index-paired trials in which `a` beat `b`, i.e. `a[i] < b[i]` strictly (ties are
/// not wins). Typical use: `a` and `b` are the times of two methods on the same trial seeds.
///
/// # Errors
/// [`StatsError::LengthMismatch`] if the lengths differ, [`StatsError::Empty`] if both are empty,
/// [`StatsError::NonFinite`] on NaN or infinite values.
pub fn paired_win_fraction(a: &[f64], b: &[f64]) -> Result<f64, StatsError> {
    if a.len() != b.len() {
        return Err(StatsError::LengthMismatch {
            len_a: a.len(),
            len_b: b.len(),
        });
    }
    validate("a", a)?;
    validate("b", b)?;
    let wins = a.iter().zip(b).filter(|(x, y)| x < y).count();
    Ok(wins as f64 / a.len() as f64)
}

/// Midranks (1-based average ranks) of `xs` and the sizes of its tie groups (only groups of
/// size ≥ 2). `xs` must be finite.
fn midranks(xs: &[f64]) -> (Vec<f64>, Vec<usize>) {
    let mut order: Vec<usize> = (0..xs.len()).collect();
    order.sort_by(|&i, &j| xs[i].total_cmp(&xs[j]));
    let mut ranks = vec![0.0; xs.len()];
    let mut ties = Vec::new();
    let mut start = 0;
    while start < order.len() {
        let mut end = start + 1;
        // `==` (not total order) so that -0.0 and 0.0 tie; they are adjacent after sorting.
        while end < order.len() && xs[order[end]] == xs[order[start]] {
            end += 1;
        }
        // Positions start..end (0-based) hold ranks start+1..=end; their mean:
        let rank = (start + 1 + end) as f64 / 2.0;
        for &i in &order[start..end] {
            ranks[i] = rank;
        }
        if end - start > 1 {
            ties.push(end - start);
        }
        start = end;
    }
    (ranks, ties)
}

/// Exact null distribution of the Mann–Whitney `U` for sample sizes `(n1, n2)` without ties.
struct ExactU {
    /// `counts[k]` = number of the `C(n1 + n2, n1)` rank assignments with `U = k`.
    counts: Vec<u128>,
    total: u128,
}

impl ExactU {
    /// Counts the rank assignments reaching each `U` by dynamic programming over the Gaussian
    /// binomial `[n1 + n2 choose m]_q = Π_{i=1..m} (1 − q^{M+i}) / (1 − q^i)` with
    /// `m = min(n1, n2)`, `M = max(n1, n2)`: after step `i` the coefficient of `q^k` is the number
    /// of ways an `i`-sample and an `M`-sample interleave with `U = k`. Each step multiplies by
    /// `1 − q^{M+i}` and then divides exactly by `1 − q^i` (a running sum). Returns `None` if the
    /// counts overflow (never for samples of at most [`EXACT_MAX_N`]; `C(40, 20) ≈ 1.4·10¹¹`).
    fn new(n1: usize, n2: usize) -> Option<ExactU> {
        let (m, big) = (n1.min(n2), n1.max(n2));
        let max_u = m.checked_mul(big)?;
        let mut c = vec![0i128; max_u + 1];
        c[0] = 1;
        for i in 1..=m {
            let deg = (i - 1) * big; // current degree of the polynomial
            let shift = big + i;
            // Multiply by (1 − q^shift), in place from the top so sources are still unmodified.
            for k in (shift..=(deg + shift).min(max_u)).rev() {
                c[k] = c[k].checked_sub(c[k - shift])?;
            }
            // Divide by (1 − q^i): c[k] += c[k − i] in increasing k.
            for k in i..=(i * big) {
                c[k] = c[k].checked_add(c[k - i])?;
            }
            // The quotient has degree i·big: clear what the product left above it.
            for v in c.iter_mut().skip(i * big + 1) {
                *v = 0;
            }
        }
        let mut counts = Vec::with_capacity(c.len());
        let mut total: u128 = 0;
        for v in c {
            let v = u128::try_from(v).ok()?; // exact division leaves no negatives
            total = total.checked_add(v)?;
            counts.push(v);
        }
        Some(ExactU { counts, total })
    }

    /// `P(U ≥ u)` under the null hypothesis.
    fn sf(&self, u: usize) -> f64 {
        let tail: u128 = self.counts.iter().skip(u).sum();
        tail as f64 / self.total as f64
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// All `n1`-subsets of `0..n1+n2` (positions in the pooled order), by brute force.
    fn brute_force_counts(n1: usize, n2: usize) -> Vec<u128> {
        let n = n1 + n2;
        let mut counts = vec![0u128; n1 * n2 + 1];
        for mask in 0u32..(1 << n) {
            if mask.count_ones() as usize != n1 {
                continue;
            }
            // U1 = Σ over a-elements of the number of b-elements below them.
            let mut u = 0;
            let mut bs_below = 0;
            for pos in 0..n {
                if mask & (1 << pos) != 0 {
                    u += bs_below;
                } else {
                    bs_below += 1;
                }
            }
            counts[u] += 1;
        }
        counts
    }

    #[test]
    fn exact_counts_match_brute_force() {
        for n1 in 1..=7 {
            for n2 in 1..=7 {
                let d = ExactU::new(n1, n2).unwrap();
                assert_eq!(d.counts, brute_force_counts(n1, n2), "n1={n1} n2={n2}");
            }
        }
    }

    #[test]
    fn exact_total_is_binomial_at_max_size() {
        let d = ExactU::new(EXACT_MAX_N, EXACT_MAX_N).unwrap();
        assert_eq!(d.total, 137_846_528_820); // C(40, 20)
        // Symmetric around n1 n2 / 2.
        let k = d.counts.len();
        for i in 0..k {
            assert_eq!(d.counts[i], d.counts[k - 1 - i]);
        }
        assert_eq!(d.sf(0), 1.0);
    }

    #[test]
    fn exact_overflow_is_reported() {
        assert!(ExactU::new(200, 200).is_none());
    }

    #[test]
    fn midranks_with_ties() {
        let (r, t) = midranks(&[3.0, 1.0, 3.0, 2.0, 3.0, -0.0, 0.0]);
        assert_eq!(r, vec![6.0, 3.0, 6.0, 4.0, 6.0, 1.5, 1.5]);
        assert_eq!(t, vec![2, 3]);
    }
}
