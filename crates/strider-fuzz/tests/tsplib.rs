//! Fuzz target: the TSPLIB/GTSPLIB reader and, on every accepted instance, a short solve whose
//! tour must be feasible and priced exactly (no silent overflow).

use std::time::Duration;

use strider_fuzz::{CappedAlloc, Outcome, Text, config, fuzz};
use strider_plan::gtsp::{Instance, SolverParams, solve};
use strider_plan::tsplib::parse_instance;

#[global_allocator]
static ALLOC: CappedAlloc = CappedAlloc::new();

const DICTIONARY: &[&str] = &[
    "NAME",
    "TYPE",
    "COMMENT",
    "DIMENSION",
    "GTSP_SETS",
    "EDGE_WEIGHT_TYPE",
    "EDGE_WEIGHT_FORMAT",
    "NODE_COORD_SECTION",
    "EDGE_WEIGHT_SECTION",
    "GTSP_SET_SECTION",
    "DISPLAY_DATA_SECTION",
    "EOF",
    "TSP",
    "GTSP",
    "ATSP",
    "AGTSP",
    "EUC_2D",
    "CEIL_2D",
    "ATT",
    "GEO",
    "EXPLICIT",
    "FULL_MATRIX",
    "UPPER_ROW",
    "LOWER_ROW",
    "UPPER_DIAG_ROW",
    "LOWER_DIAG_ROW",
    "FUNCTION",
    "NODE_COORD_TYPE",
    "TWOD_COORDS",
];

const COORD_GTSP: &str = "NAME : four\nTYPE : GTSP\nDIMENSION : 6\nGTSP_SETS : 3\n\
EDGE_WEIGHT_TYPE : EUC_2D\nNODE_COORD_SECTION\n1 0 0\n2 10 0\n3 10 10\n4 0 10\n5 5 5\n6 20 3\n\
GTSP_SET_SECTION\n1 1 5 -1\n2 2 6 -1\n3 3 4 -1\nEOF\n";

const ATT_TSP: &str = "NAME: att5\nTYPE: TSP\nDIMENSION: 5\nEDGE_WEIGHT_TYPE: ATT\n\
NODE_COORD_SECTION\n1 6734 1453\n2 2233 10\n3 5530 1424\n4 401 841\n5 3082 1644\nEOF\n";

const CEIL_TSP: &str = "NAME: ceil4\nTYPE: TSP\nDIMENSION: 4\nEDGE_WEIGHT_TYPE: CEIL_2D\n\
NODE_COORD_SECTION\n1 0.5 0.5\n2 3.2 0.1\n3 3.3 4.4\n4 0.2 4.9\nEOF\n";

const GEO_TSP: &str = "NAME: geo4\nTYPE: TSP\nDIMENSION: 4\nEDGE_WEIGHT_TYPE: GEO\n\
NODE_COORD_SECTION\n1 16.47 96.10\n2 16.47 94.44\n3 20.09 92.54\n4 22.39 93.37\nEOF\n";

const FULL_GTSP: &str = "NAME: full4\nTYPE: AGTSP\nDIMENSION: 4\nGTSP_SETS: 2\n\
EDGE_WEIGHT_TYPE: EXPLICIT\nEDGE_WEIGHT_FORMAT: FULL_MATRIX\nEDGE_WEIGHT_SECTION\n\
0 3 4 5\n3 0 6 2\n4 7 0 1\n5 2 1 0\nGTSP_SET_SECTION:\n1 1 2 -1\n2 3 4 -1\nEOF\n";

const UPPER_ROW_TSP: &str = "NAME: up5\nTYPE: TSP\nDIMENSION: 5\nEDGE_WEIGHT_TYPE: EXPLICIT\n\
EDGE_WEIGHT_FORMAT: UPPER_ROW\nEDGE_WEIGHT_SECTION\n1 2 3 4\n5 6 7\n8 9\n10\nEOF\n";

const LOWER_DIAG_TSP: &str = "NAME: lo4\nTYPE: TSP\nDIMENSION: 4\nEDGE_WEIGHT_TYPE: EXPLICIT\n\
EDGE_WEIGHT_FORMAT: LOWER_DIAG_ROW\nEDGE_WEIGHT_SECTION\n0\n7 0\n3 4 0\n9 2 8 0\nEOF\n";

const UPPER_DIAG_GTSP: &str = "NAME: ud4\nTYPE: GTSP\nDIMENSION: 4\nGTSP_SETS: 3\n\
EDGE_WEIGHT_TYPE: EXPLICIT\nEDGE_WEIGHT_FORMAT: UPPER_DIAG_ROW\nEDGE_WEIGHT_SECTION\n\
0 1 2 3\n0 4 5\n0 6\n0\nGTSP_SET_SECTION\n1 1 -1\n2 2 3 -1\n3 4 -1\nEOF\n";

/// Parses; on success the instance must be consistent and a 5 ms solve must return a feasible
/// tour whose reported cost is the exact (unbounded-precision) sum of its edges.
fn check(input: &Text) -> Result<Outcome, String> {
    let Ok(text) = std::str::from_utf8(&input.0) else {
        return Ok(Outcome::Rejected("not UTF-8".into()));
    };
    let inst = match parse_instance(text) {
        Ok(inst) => inst,
        Err(e) => return Ok(Outcome::Rejected(e.to_string())),
    };
    consistent(&inst)?;
    let params = SolverParams {
        time_limit_s: 0.005,
        ..SolverParams::default()
    };
    let sol = match solve(&inst, &params) {
        Ok(sol) => sol,
        Err(e) => return Ok(Outcome::Rejected(e.to_string())),
    };
    inst.check_tour(&sol.tour).map_err(|e| e.to_string())?;
    let exact: i128 = closed_tour_edges(&sol.tour)
        .map(|(a, b)| i128::from(inst.dist.get(a, b)))
        .sum();
    if exact != i128::from(sol.cost) {
        return Err(format!(
            "tour cost {} but its edges sum to {exact}",
            sol.cost
        ));
    }
    Ok(Outcome::Accepted)
}

fn consistent(inst: &Instance) -> Result<(), String> {
    if inst.sets.is_empty() || inst.sets.iter().any(Vec::is_empty) {
        return Err("an accepted instance has an empty set or no sets".into());
    }
    if let Some(v) = inst.sets.iter().flatten().find(|&&v| v >= inst.n) {
        return Err(format!("set member {v} out of range (n = {})", inst.n));
    }
    Ok(())
}

fn closed_tour_edges(tour: &[usize]) -> impl Iterator<Item = (usize, usize)> + '_ {
    let n = tour.len();
    (0..if n < 2 { 0 } else { n }).map(move |k| (tour[k], tour[(k + 1) % n]))
}

#[test]
fn fuzz_tsplib_reader_and_solver() {
    let seeds = [
        COORD_GTSP,
        ATT_TSP,
        CEIL_TSP,
        GEO_TSP,
        FULL_GTSP,
        UPPER_ROW_TSP,
        LOWER_DIAG_TSP,
        UPPER_DIAG_GTSP,
    ]
    .iter()
    .map(|s| Text(s.as_bytes().to_vec()))
    .collect();
    let mut cfg = config!("tsplib", 3000);
    cfg.case_limit = cfg.case_limit.max(Duration::from_secs(5));
    fuzz(cfg, &ALLOC, seeds, DICTIONARY, check);
}
