//! Structure-aware generated input for the TSPLIB / GTSPLIB reader: valid instances of every
//! supported layout, mutated by replacing numbers with extremes, deleting, duplicating and
//! swapping lines, truncating, and inserting random bytes. The reader must never panic; what
//! it accepts must be a consistent instance on which a short solve returns a feasible tour
//! whose reported cost is the sum of its arcs.
//!
//! `PROPTEST_CASES=100000 cargo test -p strider-plan --test mutated_instances` runs a long
//! mode.

use proptest::prelude::*;
use strider_plan::tsplib::parse_bytes;
use strider_plan::{Instance, MAX_TOUR_COST, SolverParams, solve};

/// Valid instances covering the reader's layouts.
const SEEDS: &[&str] = &[
    "NAME: e\nTYPE: TSP\nDIMENSION: 5\nEDGE_WEIGHT_TYPE: EUC_2D\nNODE_COORD_SECTION\n\
     1 0 0\n2 3 4\n3 1 1\n4 0 2.5\n5 7 1\nEOF\n",
    "NAME: a\nTYPE: TSP\nDIMENSION: 4\nEDGE_WEIGHT_TYPE: ATT\nNODE_COORD_SECTION\n\
     1 0 0\n2 10 0\n3 0 30\n4 10 30\nEOF\n",
    "NAME: c\nTYPE: TSP\nDIMENSION: 4\nEDGE_WEIGHT_TYPE: CEIL_2D\nNODE_COORD_SECTION\n\
     1 0 0\n2 3 4\n3 1 1\n4 0 2.5\nEOF\n",
    "NAME : g\nTYPE : TSP\nDIMENSION : 4\nEDGE_WEIGHT_TYPE : GEO\nNODE_COORD_SECTION\n\
     1 0.0 0.0\n2 0.0 1.0\n3 0.30 0.0\n4 45.30 10.45\nEOF\n",
    "NAME: q\nTYPE: AGTSP\nDIMENSION: 4\nGTSP_SETS: 2\nEDGE_WEIGHT_TYPE: EXPLICIT\n\
     EDGE_WEIGHT_FORMAT: FULL_MATRIX\nEDGE_WEIGHT_SECTION\n9999 1 2 3\n4 9999 5 6\n\
     7 8 9999 9\n10 11 12 9999\nGTSP_SET_SECTION:\n2 2 4 -1\n1 1 3 -1\nEOF\n",
    "NAME: u\nTYPE: TSP\nDIMENSION: 4\nEDGE_WEIGHT_TYPE: EXPLICIT\nEDGE_WEIGHT_FORMAT: UPPER_ROW\n\
     EDGE_WEIGHT_SECTION\n1 2 3\n4 5\n6\nEOF\n",
    "NAME: l\nTYPE: TSP\nDIMENSION: 4\nEDGE_WEIGHT_TYPE: EXPLICIT\n\
     EDGE_WEIGHT_FORMAT: LOWER_DIAG_ROW\nEDGE_WEIGHT_SECTION\n0\n1 0\n2 4 0\n3 5 6 0\nEOF\n",
    "NAME: s\nTYPE: GTSP\nDIMENSION: 6\nGTSP_SETS: 3\nEDGE_WEIGHT_TYPE: EUC_2D\n\
     NODE_COORD_SECTION\n1 0 0\n2 3 4\n3 1 1\n4 0 2.5\n5 6 6\n6 2 9\n\
     GTSP_SET_SECTION\n1 1 2 -1\n2 3 4 -1\n3 5 6 -1\nEOF\n",
    // Beyond the exact solver's 12 sets: the large-neighbourhood search runs.
    "NAME: big\nTYPE: TSP\nDIMENSION: 16\nEDGE_WEIGHT_TYPE: EUC_2D\nNODE_COORD_SECTION\n\
     1 0 0\n2 10 3\n3 20 1\n4 30 7\n5 31 18\n6 22 25\n7 12 21\n8 2 28\n9 5 40\n10 17 44\n\
     11 29 39\n12 40 47\n13 44 30\n14 48 12\n15 41 2\n16 36 21\nEOF\n",
    "NAME: bg\nTYPE: GTSP\nDIMENSION: 16\nGTSP_SETS: 14\nEDGE_WEIGHT_TYPE: ATT\n\
     NODE_COORD_SECTION\n1 0 0\n2 10 3\n3 20 1\n4 30 7\n5 31 18\n6 22 25\n7 12 21\n8 2 28\n\
     9 5 40\n10 17 44\n11 29 39\n12 40 47\n13 44 30\n14 48 12\n15 41 2\n16 36 21\n\
     GTSP_SET_SECTION\n1 1 2 -1\n2 3 -1\n3 4 -1\n4 5 -1\n5 6 -1\n6 7 -1\n7 8 -1\n8 9 -1\n\
     9 10 -1\n10 11 12 -1\n11 13 -1\n12 14 -1\n13 15 -1\n14 16 -1\nEOF\n",
    "N: 6\nM: 3\n1 1 2\n2 3 4\n3 5 6\n9999 3 4 7 8 2\n3 9999 6 5 3 9\n4 6 9999 4 2 6\n\
     7 5 4 9999 1 7\n8 3 2 1 9999 4\n2 9 6 7 4 9999\n",
];

/// The extremes a number is replaced with.
const EXTREMES: &[&str] = &[
    "0",
    "-1",
    "2147483648",
    "4294967296",
    "9223372036854775807",
    "-9223372036854775808",
    "18446744073709551615",
    "1e18",
    "1e308",
    "-1e308",
    "NaN",
    "inf",
    "-inf",
    "1.5",
    "99999999999999999999999",
];

#[derive(Clone, Debug)]
enum Mutation {
    /// Replace the k-th number (mod their count) with an extreme.
    Number(usize, usize),
    DeleteLine(usize),
    DuplicateLine(usize),
    SwapLines(usize, usize),
    /// Keep the first k bytes (mod the length + 1).
    Truncate(usize),
    /// Insert bytes at a position (mod the length + 1).
    Insert(usize, Vec<u8>),
}

fn mutation() -> impl Strategy<Value = Mutation> {
    prop_oneof![
        4 => (any::<usize>(), 0..EXTREMES.len()).prop_map(|(k, e)| Mutation::Number(k, e)),
        1 => any::<usize>().prop_map(Mutation::DeleteLine),
        1 => any::<usize>().prop_map(Mutation::DuplicateLine),
        1 => (any::<usize>(), any::<usize>()).prop_map(|(a, b)| Mutation::SwapLines(a, b)),
        1 => any::<usize>().prop_map(Mutation::Truncate),
        1 => (any::<usize>(), prop::collection::vec(any::<u8>(), 1..8))
            .prop_map(|(k, b)| Mutation::Insert(k, b)),
    ]
}

/// Lines of `bytes`, each with its newline.
fn lines(bytes: &[u8]) -> Vec<Vec<u8>> {
    bytes
        .split_inclusive(|&b| b == b'\n')
        .map(<[u8]>::to_vec)
        .collect()
}

fn apply(bytes: Vec<u8>, m: &Mutation) -> Vec<u8> {
    let mut ls = lines(&bytes);
    match m {
        Mutation::Number(k, e) => return replace_number(&bytes, *k, EXTREMES[*e]),
        Mutation::DeleteLine(k) if !ls.is_empty() => {
            let k = k % ls.len();
            ls.remove(k);
        }
        Mutation::DuplicateLine(k) if !ls.is_empty() => {
            let k = k % ls.len();
            let l = ls[k].clone();
            ls.insert(k, l);
        }
        Mutation::SwapLines(a, b) if !ls.is_empty() => {
            let n = ls.len();
            ls.swap(a % n, b % n);
        }
        Mutation::Truncate(k) => return bytes[..k % (bytes.len() + 1)].to_vec(),
        Mutation::Insert(k, ins) => {
            let k = k % (bytes.len() + 1);
            let mut out = bytes[..k].to_vec();
            out.extend_from_slice(ins);
            out.extend_from_slice(&bytes[k..]);
            return out;
        }
        _ => {}
    }
    ls.concat()
}

/// Replaces the k-th (mod their count) whitespace-separated token that parses as a number.
fn replace_number(bytes: &[u8], k: usize, with: &str) -> Vec<u8> {
    let Ok(text) = std::str::from_utf8(bytes) else {
        return bytes.to_vec();
    };
    let mut spans = Vec::new();
    let mut start = None;
    for (i, c) in text.char_indices().chain([(text.len(), ' ')]) {
        match (c.is_whitespace(), start) {
            (false, None) => start = Some(i),
            (true, Some(s)) => {
                if text[s..i].parse::<f64>().is_ok() {
                    spans.push((s, i));
                }
                start = None;
            }
            _ => {}
        }
    }
    if spans.is_empty() {
        return bytes.to_vec();
    }
    let (s, e) = spans[k % spans.len()];
    format!("{}{with}{}", &text[..s], &text[e..]).into_bytes()
}

/// An accepted instance must be consistent, and a short solve must give a feasible tour whose
/// cost is the sum of its arcs.
fn check_accepted(inst: &Instance) -> Result<(), TestCaseError> {
    prop_assert_eq!(inst.dist.n(), inst.n);
    let mut seen = vec![false; inst.n];
    for set in &inst.sets {
        prop_assert!(!set.is_empty());
        for &v in set {
            prop_assert!(v < inst.n);
            prop_assert!(!seen[v], "vertex {} in two sets", v);
            seen[v] = true;
        }
    }
    prop_assert!(inst.check_costs().is_ok());
    let params = SolverParams {
        time_limit_s: 0.01,
        ..SolverParams::default()
    };
    let sol = solve(inst, &params).map_err(|e| TestCaseError::fail(e.to_string()))?;
    prop_assert!(inst.check_tour(&sol.tour).is_ok());
    let t = &sol.tour;
    let sum: i128 = (0..t.len())
        .map(|i| i128::from(inst.dist.get(t[i], t[(i + 1) % t.len()])))
        .sum();
    prop_assert_eq!(i128::from(sol.cost), sum);
    prop_assert!(sol.cost.unsigned_abs() <= MAX_TOUR_COST as u64);
    Ok(())
}

/// 512 cases, or `PROPTEST_CASES`.
fn config() -> ProptestConfig {
    let cases = std::env::var("PROPTEST_CASES")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(512);
    ProptestConfig::with_cases(cases)
}

proptest! {
    #![proptest_config(config())]

    #[test]
    fn mutated_instances_never_panic_and_accepted_ones_solve_exactly(
        seed in 0..SEEDS.len(),
        mutations in prop::collection::vec(mutation(), 1..4),
    ) {
        let mut bytes = SEEDS[seed].as_bytes().to_vec();
        for m in &mutations {
            bytes = apply(bytes, m);
        }
        if let Ok(inst) = parse_bytes(&bytes) {
            check_accepted(&inst)?;
        }
    }

    #[test]
    fn random_bytes_never_panic(bytes in prop::collection::vec(any::<u8>(), 0..400)) {
        let _ = parse_bytes(&bytes);
    }
}

#[test]
fn every_seed_is_valid() {
    for (k, s) in SEEDS.iter().enumerate() {
        let inst = parse_bytes(s.as_bytes()).unwrap_or_else(|e| panic!("seed {k}: {e}"));
        assert!(inst.n >= 4, "seed {k}");
    }
}
