//! Tests of `strider_experiments::stats` against hand-computed and SciPy reference values, plus
//! property tests of the Mann–Whitney invariants.
//!
//! Reference values marked "SciPy" were computed with SciPy 1.17.1 / NumPy 2.4.6 as
//! `scipy.stats.mannwhitneyu(a, b, alternative=ALT, method=METHOD, use_continuity=True)` for
//! ALT in {'two-sided', 'less', 'greater'} (the printed `statistic` is U_a), and summaries with
//! `np.mean(x)`, `np.std(x, ddof=1)`, `np.median(x)`.

use approx::assert_relative_eq;
use proptest::prelude::*;
use strider_experiments::stats::{
    EXACT_MAX_N, MannWhitney, Method, StatsError, Summary, mann_whitney_u, mann_whitney_u_with,
    paired_win_fraction,
};

/// Relative tolerance for agreement with SciPy's p-values (both are double precision; the
/// exact p-values here sum integer counts, SciPy's use floating-point cumulative sums).
const REL: f64 = 1e-12;

/// Asserts `(two_sided, less, greater)` p-values.
fn assert_p(r: &MannWhitney, want: (f64, f64, f64)) {
    assert_relative_eq!(r.p_two_sided, want.0, max_relative = REL);
    assert_relative_eq!(r.p_less, want.1, max_relative = REL);
    assert_relative_eq!(r.p_greater, want.2, max_relative = REL);
}

const SMALL_A: [f64; 4] = [1.1, 2.3, 3.0, 4.2];
const SMALL_B: [f64; 5] = [5.1, 6.2, 7.3, 8.4, 9.5];

const INTERLEAVED_A: [f64; 6] = [3.2, 1.5, 4.8, 2.2, 6.1, 5.5];
const INTERLEAVED_B: [f64; 7] = [4.1, 7.3, 5.9, 8.8, 3.9, 6.6, 9.2];

const TIED_A: [f64; 7] = [1.0, 2.0, 2.0, 3.0, 4.0, 4.0, 5.0];
const TIED_B: [f64; 8] = [2.0, 3.0, 4.0, 4.0, 6.0, 7.0, 7.0, 8.0];

// Generated once with `np.round(np.random.default_rng(20240501).normal(300, 40, 30), 1)` and the
// next draw `normal(330, 45, 30)`; contains two cross-sample ties (285.1 and 367.5).
const A30: [f64; 30] = [
    286.9, 261.0, 319.8, 317.0, 282.4, 296.0, 227.9, 264.7, 308.7, 323.8, 299.6, 267.1, 285.8,
    321.0, 245.3, 348.2, 290.9, 267.8, 258.4, 254.8, 330.5, 245.8, 266.3, 304.1, 251.5, 253.8,
    367.5, 294.2, 285.1, 386.0,
];
const B30: [f64; 30] = [
    374.8, 355.9, 369.0, 355.5, 335.9, 224.8, 359.3, 323.7, 398.5, 374.9, 391.1, 311.9, 350.5,
    389.1, 285.1, 323.9, 305.6, 338.9, 326.3, 314.3, 367.5, 353.3, 367.2, 359.6, 270.8, 337.9,
    298.4, 400.4, 326.5, 380.3,
];

// Generated once with `np.round(np.random.default_rng(7).normal(50, 10, 20), 2)` and the next
// draw `normal(57, 10, 18)`; no ties. Sizes at the exact-method limit.
const A20: [f64; 20] = [
    50.01, 52.99, 47.26, 41.09, 45.45, 40.08, 50.60, 63.40, 45.08, 43.80, 54.90, 53.57, 51.05,
    40.70, 49.71, 56.95, 36.56, 45.42, 30.99, 37.10,
];
const B18: [f64; 18] = [
    38.58, 54.65, 44.33, 59.71, 58.57, 55.13, 31.83, 51.61, 56.51, 58.13, 41.70, 52.22, 47.21,
    48.91, 67.61, 48.92, 56.67, 65.84,
];

// ---------------------------------------------------------------------------------------------
// Summary

#[test]
fn summary_hand_computed() {
    // mean 12, deviations 0.5, -2, 2, -0.5 → ss = 8.5, var = 8.5/3.
    let s = Summary::of(&[12.5, 10.0, 14.0, 11.5]).unwrap();
    assert_eq!(s.n, 4);
    assert_relative_eq!(s.mean, 12.0);
    assert_relative_eq!(s.std, (8.5f64 / 3.0).sqrt(), max_relative = 1e-15);
    assert_relative_eq!(s.std, 1.683_250_823_060_346_5, max_relative = 1e-15); // NumPy ddof=1
    assert_eq!(s.min, 10.0);
    assert_eq!(s.max, 14.0);
    assert_eq!(s.median, 12.0); // (11.5 + 12.5) / 2

    let odd = Summary::of(&[3.0, 1.0, 2.0]).unwrap();
    assert_eq!(odd.median, 2.0);
    assert_relative_eq!(odd.std, 1.0);
}

#[test]
fn summary_single_value_has_zero_std() {
    let s = Summary::of(&[42.0]).unwrap();
    assert_eq!(
        s,
        Summary {
            n: 1,
            mean: 42.0,
            std: 0.0,
            min: 42.0,
            max: 42.0,
            median: 42.0
        }
    );
}

#[test]
fn summary_matches_numpy() {
    // NumPy 2.4.6: np.mean, np.std(ddof=1), np.median.
    let a = Summary::of(&A30).unwrap();
    assert_relative_eq!(a.mean, 290.396_666_666_666_65, max_relative = 1e-14);
    assert_relative_eq!(a.std, 37.447_936_118_566_396, max_relative = 1e-13);
    assert_relative_eq!(a.median, 286.35, max_relative = 1e-15);
    assert_eq!((a.min, a.max), (227.9, 386.0));
    let b = Summary::of(&B30).unwrap();
    assert_relative_eq!(b.mean, 342.363_333_333_333_34, max_relative = 1e-14);
    assert_relative_eq!(b.std, 39.916_693_278_612_776, max_relative = 1e-13);
    assert_relative_eq!(b.median, 351.9, max_relative = 1e-15);
    assert_eq!((b.min, b.max), (224.8, 400.4));
}

#[test]
fn summary_display_is_mean_pm_std() {
    let s = Summary::of(&[12.5, 10.0, 14.0, 11.5]).unwrap();
    assert_eq!(format!("{s:.2}"), "12.00 ± 1.68");
    assert_eq!(format!("{:.0}", Summary::of(&[1.0]).unwrap()), "1 ± 0");
}

#[test]
fn summary_rejects_bad_input() {
    assert_eq!(Summary::of(&[]), Err(StatsError::Empty { sample: "x" }));
    match Summary::of(&[1.0, f64::NAN, 3.0]) {
        Err(StatsError::NonFinite {
            sample: "x",
            index: 1,
            value,
        }) => assert!(value.is_nan()),
        other => panic!("expected NonFinite, got {other:?}"),
    }
    assert!(matches!(
        Summary::of(&[1.0, 2.0, f64::NEG_INFINITY]),
        Err(StatsError::NonFinite { index: 2, .. })
    ));
    let msg = Summary::of(&[f64::INFINITY]).unwrap_err().to_string();
    assert!(
        msg.contains("non-finite") && msg.contains("index 0"),
        "{msg}"
    );
}

// ---------------------------------------------------------------------------------------------
// Mann–Whitney: reference values

#[test]
fn mwu_small_exact_hand_and_scipy() {
    let r = mann_whitney_u(&SMALL_A, &SMALL_B).unwrap();
    assert_eq!(r.method, Method::Exact);
    assert!(!r.has_ties);
    assert_eq!((r.n_a, r.n_b), (4, 5));
    // Every a is below every b: U_a = 0, U_b = 20.
    assert_eq!((r.u_a, r.u_b), (0.0, 20.0));
    assert_eq!(r.effect_size, 0.0);
    // Hand: only 1 of the C(9, 4) = 126 equally likely rank assignments has U_a ≤ 0.
    assert_relative_eq!(r.p_less, 1.0 / 126.0, max_relative = 1e-15);
    assert_relative_eq!(r.p_two_sided, 2.0 / 126.0, max_relative = 1e-15);
    assert_eq!(r.p_greater, 1.0);
    // SciPy, method='exact'.
    assert_p(&r, (0.015873015873015872, 0.007936507936507936, 1.0));

    // SciPy, method='asymptotic'.
    let n = mann_whitney_u_with(&SMALL_A, &SMALL_B, Method::Normal).unwrap();
    assert_eq!(n.method, Method::Normal);
    assert_eq!(n.u_a, 0.0);
    assert_p(
        &n,
        (
            0.019964453305216043,
            0.009982226652608022,
            0.9949438330393333,
        ),
    );
}

#[test]
fn mwu_interleaved_scipy() {
    let r = mann_whitney_u(&INTERLEAVED_A, &INTERLEAVED_B).unwrap();
    assert_eq!(r.method, Method::Exact);
    assert_eq!((r.u_a, r.u_b), (7.0, 35.0));
    assert_relative_eq!(r.effect_size, 7.0 / 42.0);
    // SciPy, method='exact'.
    assert_p(
        &r,
        (0.05128205128205128, 0.02564102564102564, 0.9825174825174825),
    );
    // SciPy, method='asymptotic'.
    let n = mann_whitney_u_with(&INTERLEAVED_A, &INTERLEAVED_B, Method::Normal).unwrap();
    assert_p(
        &n,
        (0.05378408886239828, 0.02689204443119914, 0.9808406184252932),
    );
}

#[test]
fn mwu_tied_scipy() {
    let r = mann_whitney_u(&TIED_A, &TIED_B).unwrap();
    // Ties force the normal approximation.
    assert_eq!(r.method, Method::Normal);
    assert!(r.has_ties);
    // Hand: pairs a > b count 1, ties ½ → U_a = 12.5.
    assert_eq!((r.u_a, r.u_b), (12.5, 43.5));
    // SciPy, method='asymptotic' (tie-corrected variance).
    assert_p(
        &r,
        (0.07819511429228164, 0.03909755714614082, 0.9698554130046989),
    );
    // The exact distribution is not offered for tied data.
    assert!(matches!(
        mann_whitney_u_with(&TIED_A, &TIED_B, Method::Exact),
        Err(StatsError::ExactUnavailable { .. })
    ));
}

#[test]
fn mwu_n30_scipy() {
    let r = mann_whitney_u(&A30, &B30).unwrap();
    assert_eq!(r.method, Method::Normal);
    assert!(r.has_ties);
    assert_eq!((r.u_a, r.u_b), (146.0, 754.0));
    // SciPy, method='asymptotic' (also what SciPy's method='auto' picks here).
    assert_p(
        &r,
        (
            7.2166070525183175e-06,
            3.6083035262591587e-06,
            0.9999966338757794,
        ),
    );
    // NumPy: np.mean(A30 < B30) = 26/30.
    assert_relative_eq!(paired_win_fraction(&A30, &B30).unwrap(), 26.0 / 30.0);
}

#[test]
fn mwu_exact_at_size_limit_scipy() {
    let r = mann_whitney_u(&A20, &B18).unwrap();
    assert_eq!(r.method, Method::Exact);
    assert_eq!(r.u_a, 113.0);
    // SciPy, method='exact'.
    assert_p(
        &r,
        (0.05110335912880311, 0.025551679564401554, 0.976199787257077),
    );
    // SciPy, method='asymptotic' (what SciPy's method='auto' would pick for these sizes).
    let n = mann_whitney_u_with(&A20, &B18, Method::Normal).unwrap();
    assert_p(
        &n,
        (0.05187793473220298, 0.02593896736610149, 0.9757738886811081),
    );
}

#[test]
fn mwu_method_selection_boundary() {
    let a: Vec<f64> = (0..EXACT_MAX_N).map(|i| i as f64).collect();
    let b: Vec<f64> = (0..EXACT_MAX_N).map(|i| i as f64 + 0.5).collect();
    assert_eq!(mann_whitney_u(&a, &b).unwrap().method, Method::Exact);
    let b21: Vec<f64> = (0..=EXACT_MAX_N).map(|i| i as f64 + 0.5).collect();
    assert_eq!(mann_whitney_u(&a, &b21).unwrap().method, Method::Normal);
    assert_eq!(mann_whitney_u(&b21, &a).unwrap().method, Method::Normal);
    // Exact can still be forced for larger untied samples.
    let forced = mann_whitney_u_with(&a, &b21, Method::Exact).unwrap();
    assert_eq!(forced.method, Method::Exact);
}

#[test]
fn mwu_all_tied_gives_p_one() {
    let r = mann_whitney_u(&[3.0, 3.0], &[3.0, 3.0, 3.0]).unwrap();
    assert_eq!(r.method, Method::Normal);
    assert_eq!((r.u_a, r.u_b), (3.0, 3.0));
    assert_eq!((r.p_two_sided, r.p_less, r.p_greater), (1.0, 1.0, 1.0));
    assert_eq!(r.effect_size, 0.5);
}

#[test]
fn mwu_single_observations() {
    // n1 = n2 = 1: two equally likely orders.
    let r = mann_whitney_u(&[1.0], &[2.0]).unwrap();
    assert_eq!(r.method, Method::Exact);
    assert_eq!((r.p_less, r.p_greater, r.p_two_sided), (0.5, 1.0, 1.0));
}

#[test]
fn mwu_rejects_bad_input() {
    assert_eq!(
        mann_whitney_u(&[], &[1.0]).unwrap_err(),
        StatsError::Empty { sample: "a" }
    );
    assert_eq!(
        mann_whitney_u(&[1.0], &[]).unwrap_err(),
        StatsError::Empty { sample: "b" }
    );
    assert!(matches!(
        mann_whitney_u(&[1.0, 2.0], &[3.0, f64::NAN]),
        Err(StatsError::NonFinite {
            sample: "b",
            index: 1,
            ..
        })
    ));
    assert!(matches!(
        mann_whitney_u_with(&[f64::INFINITY], &[3.0], Method::Exact),
        Err(StatsError::NonFinite {
            sample: "a",
            index: 0,
            ..
        })
    ));
    let msg = mann_whitney_u(&[], &[1.0]).unwrap_err().to_string();
    assert!(msg.contains("`a`") && msg.contains("empty"), "{msg}");
}

// ---------------------------------------------------------------------------------------------
// paired_win_fraction

#[test]
fn paired_win_fraction_hand_computed() {
    // wins at 0 and 2; index 1 is a tie (not a win); index 3 a loss.
    let f = paired_win_fraction(&[1.0, 2.0, 3.0, 9.0], &[2.0, 2.0, 4.0, 1.0]).unwrap();
    assert_eq!(f, 0.5);
    assert_eq!(
        paired_win_fraction(&[1.0, 2.0], &[1.0]).unwrap_err(),
        StatsError::LengthMismatch { len_a: 2, len_b: 1 }
    );
    assert_eq!(
        paired_win_fraction(&[], &[]).unwrap_err(),
        StatsError::Empty { sample: "a" }
    );
    assert!(matches!(
        paired_win_fraction(&[1.0], &[f64::NAN]),
        Err(StatsError::NonFinite { sample: "b", .. })
    ));
}

// ---------------------------------------------------------------------------------------------
// Properties

/// Samples mixing small integers (to force ties) and continuous values.
fn sample(max_len: usize) -> impl Strategy<Value = Vec<f64>> {
    prop::collection::vec(
        prop_oneof![(0i32..12).prop_map(f64::from), -1.0e3f64..1.0e3],
        1..max_len,
    )
}

/// Untied, integer-valued sample pairs (distinct values shuffled between the two samples).
fn untied_pair(max_len: usize) -> impl Strategy<Value = (Vec<f64>, Vec<f64>)> {
    (1..max_len, 1..max_len).prop_flat_map(|(n1, n2)| {
        Just((0..(n1 + n2)).map(|i| i as f64).collect::<Vec<f64>>())
            .prop_shuffle()
            .prop_map(move |v| (v[..n1].to_vec(), v[n1..].to_vec()))
    })
}

fn check_invariants(r: &MannWhitney) -> Result<(), TestCaseError> {
    let nn = (r.n_a * r.n_b) as f64;
    for p in [r.p_two_sided, r.p_less, r.p_greater] {
        prop_assert!((0.0..=1.0).contains(&p), "p = {p}");
    }
    prop_assert_eq!(r.u_a + r.u_b, nn);
    prop_assert!(r.u_a >= 0.0 && r.u_b >= 0.0);
    prop_assert!((0.0..=1.0).contains(&r.effect_size));
    // One-sided tails overlap at the observed U (exact: 1 + P(U = u); normal with continuity
    // correction: Φ((d + ½)/σ) + 1 − Φ((d − ½)/σ)), so they never sum to less than 1.
    prop_assert!(r.p_less + r.p_greater >= 1.0 - 1e-12);
    // The two-sided p-value doubles the smaller one-sided tail.
    let two = (2.0 * r.p_less.min(r.p_greater)).min(1.0);
    prop_assert!((r.p_two_sided - two).abs() <= 1e-12 * two.max(1e-300));
    Ok(())
}

proptest! {
    #[test]
    fn mwu_invariants(a in sample(40), b in sample(40)) {
        let r = mann_whitney_u(&a, &b).unwrap();
        check_invariants(&r)?;
        let expect_exact = a.len() <= EXACT_MAX_N && b.len() <= EXACT_MAX_N && !r.has_ties;
        prop_assert_eq!(r.method == Method::Exact, expect_exact);
        let n = mann_whitney_u_with(&a, &b, Method::Normal).unwrap();
        check_invariants(&n)?;
    }

    #[test]
    fn mwu_exact_invariants((a, b) in untied_pair(25)) {
        let r = mann_whitney_u_with(&a, &b, Method::Exact).unwrap();
        check_invariants(&r)?;
        prop_assert!(!r.has_ties);
        // Exact p-values are multiples of 1 / C(n1 + n2, n1) and the tails overlap strictly.
        prop_assert!(r.p_less + r.p_greater > 1.0);
    }

    #[test]
    fn mwu_swap_swaps_tails(a in sample(30), b in sample(30)) {
        let ab = mann_whitney_u(&a, &b).unwrap();
        let ba = mann_whitney_u(&b, &a).unwrap();
        prop_assert_eq!(ab.method, ba.method);
        prop_assert_eq!(ab.u_a, ba.u_b);
        prop_assert_eq!(ab.u_b, ba.u_a);
        prop_assert!((ab.p_less - ba.p_greater).abs() <= 1e-14);
        prop_assert!((ab.p_greater - ba.p_less).abs() <= 1e-14);
        prop_assert!((ab.p_two_sided - ba.p_two_sided).abs() <= 1e-14);
        prop_assert!((ab.effect_size + ba.effect_size - 1.0).abs() <= 1e-12);
    }

    #[test]
    fn mwu_invariant_under_increasing_maps(
        a in prop::collection::vec(-50i32..50, 1..30),
        b in prop::collection::vec(-50i32..50, 1..30),
    ) {
        let f = |v: &[i32], g: fn(i32) -> f64| v.iter().map(|&x| g(x)).collect::<Vec<f64>>();
        let r1 = mann_whitney_u(&f(&a, f64::from), &f(&b, f64::from)).unwrap();
        let r2 = mann_whitney_u(
            &f(&a, |x| 4.0 * f64::from(x) + 1000.0),
            &f(&b, |x| 4.0 * f64::from(x) + 1000.0),
        )
        .unwrap();
        prop_assert_eq!(r1, r2);
    }

    #[test]
    fn mwu_separated_samples_are_extreme(n1 in 1usize..=EXACT_MAX_N, n2 in 1usize..=EXACT_MAX_N) {
        // a entirely below b: p_less = 1 / C(n1 + n2, n1).
        let a: Vec<f64> = (0..n1).map(|i| i as f64).collect();
        let b: Vec<f64> = (0..n2).map(|i| (n1 + i) as f64).collect();
        let r = mann_whitney_u(&a, &b).unwrap();
        let k = n1.min(n2) as u128;
        let n = (n1 + n2) as u128;
        let binom = (0..k).fold(1u128, |acc, i| acc * (n - i) / (i + 1));
        prop_assert_eq!(r.u_a, 0.0);
        prop_assert!((r.p_less * binom as f64 - 1.0).abs() < 1e-12);
        prop_assert_eq!(r.p_greater, 1.0);
    }

    #[test]
    fn bad_values_are_errors_not_panics(
        mut a in prop::collection::vec(-1.0e3f64..1.0e3, 1..20),
        b in prop::collection::vec(-1.0e3f64..1.0e3, 1..20),
        idx in any::<prop::sample::Index>(),
        bad in prop_oneof![Just(f64::NAN), Just(f64::INFINITY), Just(f64::NEG_INFINITY)],
    ) {
        let i = idx.index(a.len());
        a[i] = bad;
        // `Some((sample, index))` of a NonFinite error.
        fn bad_at<T>(r: Result<T, StatsError>) -> Option<(&'static str, usize)> {
            match r {
                Err(StatsError::NonFinite { sample, index, .. }) => Some((sample, index)),
                _ => None,
            }
        }
        prop_assert_eq!(bad_at(mann_whitney_u(&a, &b)), Some(("a", i)));
        prop_assert_eq!(bad_at(mann_whitney_u(&b, &a)), Some(("b", i)));
        prop_assert_eq!(bad_at(Summary::of(&a)), Some(("x", i)));
        let b_same: Vec<f64> = b.iter().cycle().take(a.len()).copied().collect();
        prop_assert_eq!(bad_at(paired_win_fraction(&a, &b_same)), Some(("a", i)));
    }

    #[test]
    fn summary_bounds(x in sample(50)) {
        let s = Summary::of(&x).unwrap();
        prop_assert_eq!(s.n, x.len());
        prop_assert!(s.min <= s.median && s.median <= s.max);
        let slack = 1e-9 * s.max.abs().max(s.min.abs()).max(1.0);
        prop_assert!(s.min - slack <= s.mean && s.mean <= s.max + slack);
        prop_assert!(s.std >= 0.0);
        prop_assert!(s.std <= (s.max - s.min) + slack);
    }

    #[test]
    fn paired_fractions_partition(
        pairs in prop::collection::vec((0i32..5, 0i32..5), 1..40)
    ) {
        let a: Vec<f64> = pairs.iter().map(|p| f64::from(p.0)).collect();
        let b: Vec<f64> = pairs.iter().map(|p| f64::from(p.1)).collect();
        let wins = paired_win_fraction(&a, &b).unwrap();
        let losses = paired_win_fraction(&b, &a).unwrap();
        let ties = pairs.iter().filter(|p| p.0 == p.1).count() as f64 / pairs.len() as f64;
        prop_assert!((wins + losses + ties - 1.0).abs() < 1e-12);
    }
}
