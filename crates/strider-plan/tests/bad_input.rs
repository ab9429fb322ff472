//! Bad TSPLIB / GTSPLIB input: every case ends in a one-line error naming what is wrong (or in
//! a correct instance), never in a panic, an allocation failure or a silently wrong tour cost.

use strider_plan::tsplib::{TsplibError, parse_bytes, parse_instance};
use strider_plan::{CostMatrix, Instance, MAX_TOUR_COST, SolveError, SolverParams, solve};

fn err(text: &str) -> String {
    parse_instance(text).expect_err("should fail").to_string()
}

fn explicit(n: &str, format: &str, data: &str) -> String {
    format!(
        "NAME: x\nTYPE: TSP\nDIMENSION: {n}\nEDGE_WEIGHT_TYPE: EXPLICIT\n\
         EDGE_WEIGHT_FORMAT: {format}\nEDGE_WEIGHT_SECTION\n{data}\nEOF\n"
    )
}

fn coords(kind: &str, points: &str) -> String {
    let n = points.lines().count();
    format!(
        "NAME: c\nTYPE: TSP\nDIMENSION: {n}\nEDGE_WEIGHT_TYPE: {kind}\nNODE_COORD_SECTION\n\
         {points}EOF\n"
    )
}

/// A 10-vertex, 2-set GTSP with coordinates; `extra` is inserted after the coordinates.
fn gtsp10(sets_line: &str, extra: &str, sets: &str) -> String {
    let mut s = format!(
        "NAME: g\nTYPE: GTSP\nDIMENSION: 10\n{sets_line}\nEDGE_WEIGHT_TYPE: EUC_2D\n\
         NODE_COORD_SECTION\n"
    );
    for i in 1..=10 {
        s.push_str(&format!("{i} {} {}\n", i * 3, i * i % 7));
    }
    s.push_str(extra);
    s.push_str(sets);
    s
}

const SETS: &str = "GTSP_SET_SECTION\n1 1 2 3 4 5 -1\n2 6 7 8 9 10 -1\nEOF\n";

#[test]
fn dimensions_whose_matrix_overflows_or_is_too_big_are_refused_at_the_dimension_line() {
    let limit = "but the limit is 4.0 GiB (MEMORY_LIMIT_BYTES); cost matrices are dense: use an \
                 instance of at most 23170 vertices (the solver takes at most 12385)";
    for (n, fmt, size) in [
        ("4294967296", "FULL_MATRIX", "more than 16 EiB"),
        ("18446744073709551615", "FULL_MATRIX", "more than 16 EiB"),
        ("5000000000", "FULL_MATRIX", "more than 16 EiB"),
        ("5000000000", "UPPER_ROW", "more than 16 EiB"),
        ("1000000000", "FULL_MATRIX", "6.9 EiB"),
        ("100000", "FULL_MATRIX", "74.5 GiB"),
    ] {
        let e = err(&explicit(n, fmt, "0 1 1 0"));
        assert_eq!(
            e,
            format!("line 3: DIMENSION {n}: a {n} × {n} cost matrix needs {size} {limit}"),
            "{n} {fmt}"
        );
    }
}

#[test]
fn a_valid_100k_node_coordinate_tsp_is_refused_before_reading_its_coordinates() {
    let points: String = (1..=100_000)
        .map(|i| format!("{i} {} {}\n", i % 997, i % 991))
        .collect();
    let e = err(&coords("EUC_2D", &points));
    assert!(
        e.starts_with("line 3: DIMENSION 100000: a 100000 × 100000 cost matrix needs 74.5 GiB"),
        "{e}"
    );
    // A header that claims 10⁹ nodes and lists two is refused just as early.
    let text = "NAME: b\nTYPE: TSP\nDIMENSION: 1000000000\nEDGE_WEIGHT_TYPE: EUC_2D\n\
                NODE_COORD_SECTION\n1 0 0\n2 1 1\nEOF\n";
    assert!(
        err(text).starts_with("line 3: DIMENSION 1000000000:"),
        "{}",
        err(text)
    );
}

#[test]
fn coordinates_whose_tours_could_overflow_are_refused() {
    let far = "1 0 0\n2 1e18 0\n3 1e18 1e18\n4 0 1e18\n";
    for (kind, reach) in [
        ("EUC_2D", "1.414e18"),
        ("CEIL_2D", "1.414e18"),
        ("ATT", "4.472e17"),
    ] {
        assert_eq!(
            err(&coords(kind, far)),
            format!(
                "{kind} distances between these coordinates reach {reach} (across their \
                 bounding box); with 4 vertices a tour could cost 4 times that, more than the \
                 limit 1152921504606846975 (MAX_TOUR_COST): scale the costs down"
            )
        );
    }
    // Coordinates whose difference is not even a finite f64.
    let e = err(&coords("EUC_2D", "1 0 0\n2 1e308 0\n3 -1e308 1\n"));
    assert!(
        e.starts_with("EUC_2D distances between these coordinates reach inf"),
        "{e}"
    );
    // Far-apart coordinates that still fit are read.
    let inst = parse_instance(&coords("EUC_2D", "1 0 0\n2 1e14 0\n3 0 1e14\n")).unwrap();
    assert_eq!(inst.dist.get(0, 1), 100_000_000_000_000);
}

#[test]
fn non_finite_coordinates_are_refused() {
    for bad in ["nan", "NaN", "inf", "-inf", "1e999"] {
        let e = err(&coords("EUC_2D", &format!("1 0 0\n2 {bad} 0\n3 1 1\n")));
        assert_eq!(
            e,
            format!("line 7: '{bad}' is not a finite number in NODE_COORD_SECTION")
        );
    }
}

#[test]
fn explicit_weights_whose_tour_sum_overflows_are_refused() {
    // Each weight fits i64, but four of them do not.
    let big = "0 4000000000000000000 1 4000000000000000000\n\
               4000000000000000000 0 4000000000000000000 1\n\
               1 4000000000000000000 0 4000000000000000000\n\
               4000000000000000000 1 4000000000000000000 0";
    assert_eq!(
        err(&explicit("4", "FULL_MATRIX", big)),
        "arc 1 -> 2 costs 4000000000000000000; with 4 vertices a tour could cost 4 times that, \
         more than the limit 1152921504606846975 (MAX_TOUR_COST): scale the costs down"
    );
    // 200 vertices of 9·10¹⁵ each: every weight is small, their tour sum is not.
    let row = vec!["9000000000000000"; 200 * 199 / 2].join(" ");
    let e = err(&explicit("200", "UPPER_ROW", &row));
    assert!(
        e.starts_with("arc 1 -> 2 costs 9000000000000000; with 200 vertices"),
        "{e}"
    );
    // A weight beyond i64 and a fractional one beyond 2^53.
    let e = err(&explicit("2", "UPPER_ROW", "9223372036854775808"));
    assert!(
        e.starts_with("line 7: value 9.223372036854776e18 in EDGE_WEIGHT_SECTION is out of range"),
        "{e}"
    );
}

#[test]
fn negative_weights_are_refused_except_on_the_diagonal() {
    assert_eq!(
        err(&explicit("3", "FULL_MATRIX", "0 -5 1\n1 0 1\n1 1 0")),
        "line 7: negative weight -5 in EDGE_WEIGHT_SECTION (weights must be ≥ 0)"
    );
    let inst = parse_instance(&explicit("3", "FULL_MATRIX", "-1 5 1\n1 -1 1\n1 1 -1")).unwrap();
    assert_eq!(
        inst.dist.get(0, 0),
        0,
        "the diagonal is never used and is zeroed"
    );
}

#[test]
fn values_beyond_a_section_name_the_section_and_its_count() {
    let e = err(&gtsp10("GTSP_SETS: 2", "11 5 5\n", SETS));
    assert_eq!(
        e,
        "line 17: extra value '11' after the 30 values of NODE_COORD_SECTION (DIMENSION 10: 3 \
         values per node)"
    );
    let e = err(&explicit("3", "UPPER_ROW", "1 2 3\n4"));
    assert_eq!(
        e,
        "line 8: extra value '4' after the 3 values of EDGE_WEIGHT_SECTION (DIMENSION 3 in \
         UPPER_ROW)"
    );
    let sets = "GTSP_SET_SECTION\n1 1 2 3 4 5 6 7 8 9 10 -1\n2 1 -1\nEOF\n";
    let e = err(&gtsp10("GTSP_SETS: 1", "", sets));
    assert_eq!(
        e,
        "line 19: extra value '2' after the 1 sets of GTSP_SET_SECTION (GTSP_SETS 1)"
    );
}

#[test]
fn a_byte_order_mark_is_skipped() {
    let plain = parse_instance(&gtsp10("GTSP_SETS: 2", "", SETS)).unwrap();
    let bom = parse_instance(&format!("\u{feff}{}", gtsp10("GTSP_SETS: 2", "", SETS))).unwrap();
    assert_eq!(
        (bom.n, &bom.sets, bom.dist),
        (plain.n, &plain.sets, plain.dist)
    );
    // Other stray text is named as such.
    assert_eq!(
        err("NAME: x\n§ DIMENSION: 3\n"),
        "line 2: unexpected text '§ DIMENSION: 3' (not a TSPLIB keyword)"
    );
}

#[test]
fn gtsp_set_errors() {
    let g = |sets_line: &str, sets: &str| err(&gtsp10(sets_line, "", sets));
    assert_eq!(
        g("GTSP_SETS: 3", SETS),
        "line 20: GTSP_SET_SECTION is truncated: expected 3 sets, found 2"
    );
    assert_eq!(
        g("GTSP_SETS: 18446744073709551615", SETS),
        "line 4: bad dimension: GTSP_SETS 18446744073709551615 is more than DIMENSION 10 (every \
         set needs a vertex)"
    );
    assert_eq!(
        g("GTSP_SETS: 99999999999999999999999", SETS),
        "line 4: bad dimension: GTSP_SETS 99999999999999999999999 is too large (at most \
         18446744073709551615)"
    );
    let empty = "GTSP_SET_SECTION\n1 1 2 3 4 5 6 7 8 9 10 -1\n2 -1\nEOF\n";
    assert_eq!(g("GTSP_SETS: 2", empty), "line 19: set 2 has no vertex");
    let out = "GTSP_SET_SECTION\n1 1 2 3 4 5 -1\n2 6 7 8 9 11 -1\nEOF\n";
    assert_eq!(g("GTSP_SETS: 2", out), "line 19: vertex 11 not in 1..=10");
    let zero = "GTSP_SET_SECTION\n1 0 2 3 4 5 -1\n2 6 7 8 9 10 1 -1\nEOF\n";
    assert_eq!(g("GTSP_SETS: 2", zero), "line 18: vertex 0 not in 1..=10");
    let dup = "GTSP_SET_SECTION\n1 1 2 3 4 5 -1\n2 5 6 7 8 9 10 -1\nEOF\n";
    assert_eq!(
        g("GTSP_SETS: 2", dup),
        "line 19: vertex 5 is in set 1 and in set 2"
    );
    let id = "GTSP_SET_SECTION\n1 1 2 3 4 5 -1\n7 6 7 8 9 10 -1\nEOF\n";
    assert_eq!(g("GTSP_SETS: 2", id), "line 19: set id 7 not in 1..=2");
}

#[test]
fn a_second_dimension_is_refused() {
    // The coordinates were read for 4 nodes; a matrix for 8 would index past them.
    let text = "NAME: d\nTYPE: TSP\nDIMENSION: 4\nEDGE_WEIGHT_TYPE: EUC_2D\nNODE_COORD_SECTION\n\
                1 0 0\n2 1 0\n3 1 1\n4 0 1\nDIMENSION: 8\nEOF\n";
    assert_eq!(
        err(text),
        "line 10: bad dimension: DIMENSION given twice (first on line 3)"
    );
}

#[test]
fn bytes_that_are_not_utf8_name_their_line_and_column() {
    let text = gtsp10("GTSP_SETS: 2", "", SETS).replace("EUC_2D", "EUC\u{1}2D");
    let bytes: Vec<u8> = text
        .bytes()
        .map(|b| if b == 1 { 0xff } else { b })
        .collect();
    match parse_bytes(&bytes) {
        Err(e @ TsplibError::NotUtf8 { .. }) => {
            assert_eq!(
                e.to_string(),
                "line 5: not UTF-8 text (invalid byte at column 22)"
            )
        }
        other => panic!("unexpected {other:?}"),
    }
}

#[test]
fn every_truncation_of_a_valid_file_is_an_instance_or_an_error() {
    let text = gtsp10("GTSP_SETS: 2", "", SETS);
    for end in 0..text.len() {
        if let Ok(inst) = parse_instance(&text[..end]) {
            // Only cuts inside the last line or its EOF can leave a complete instance.
            assert_eq!((inst.n, inst.sets.len()), (10, 2), "cut at {end}");
        }
    }
}

#[test]
fn the_solver_refuses_costs_whose_tours_could_overflow() {
    let big = i64::MAX / 2;
    let dist = CostMatrix::from_fn(4, |i, j| if i == j { 0 } else { big });
    let inst = Instance::tsp("big", dist);
    match solve(&inst, &SolverParams::default()) {
        Err(SolveError::Costs(e)) => assert_eq!(
            e.to_string(),
            format!(
                "arc 0 -> 1 costs {big}; with 4 vertices a tour could cost up to 4 × {big}, more \
                 than the limit {MAX_TOUR_COST} (MAX_TOUR_COST): scale the costs down"
            )
        ),
        other => panic!("unexpected {other:?}"),
    }
    // Just below the limit every tour sum is exact.
    let edge = MAX_TOUR_COST / 4;
    let dist = CostMatrix::from_fn(4, |i, j| if i == j { 0 } else { edge });
    let sol = solve(&Instance::tsp("edge", dist), &SolverParams::default()).unwrap();
    assert_eq!(sol.cost, 4 * edge);
}

#[test]
fn the_solver_refuses_a_time_limit_that_is_not_a_positive_number() {
    let inst = Instance::tsp("t", CostMatrix::from_fn(3, |i, j| (i + j) as i64));
    for t in [f64::NAN, 0.0, -1.0, f64::NEG_INFINITY] {
        let p = SolverParams {
            time_limit_s: t,
            ..SolverParams::default()
        };
        match solve(&inst, &p) {
            Err(SolveError::BadParameter(m)) => {
                assert!(m.contains("must be a number of seconds > 0"), "{m}")
            }
            other => panic!("{t}: unexpected {other:?}"),
        }
    }
    // An infinite limit leaves the iteration limits in charge.
    let p = SolverParams {
        time_limit_s: f64::INFINITY,
        ..SolverParams::default()
    };
    assert!(solve(&inst, &p).is_ok());
}
