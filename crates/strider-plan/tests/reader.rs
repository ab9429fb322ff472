//! TSPLIB / GTSPLIB reader tests on small hand-made files.

use strider_plan::tsplib::{TsplibError, parse_instance, parse_tour, tsplib_distance};

fn matrix(inst: &strider_plan::Instance) -> Vec<Vec<i64>> {
    (0..inst.n)
        .map(|i| (0..inst.n).map(|j| inst.dist.get(i, j)).collect())
        .collect()
}

const POINTS: &str = "1 0 0\n2 3 4\n3 1 1\n4 0 2.5\n";

fn coord_file(kind: &str) -> String {
    format!(
        "NAME : t\nTYPE : TSP\nDIMENSION : 4\nEDGE_WEIGHT_TYPE : {kind}\nNODE_COORD_SECTION\n{POINTS}EOF\n"
    )
}

#[test]
fn euc_2d_rounds_to_nearest() {
    let inst = parse_instance(&coord_file("EUC_2D")).unwrap();
    // 5, nint(1.414)=1, nint(2.5)=3, nint(3.606)=4, nint(3.354)=3, nint(1.803)=2
    assert_eq!(
        matrix(&inst),
        vec![
            vec![0, 5, 1, 3],
            vec![5, 0, 4, 3],
            vec![1, 4, 0, 2],
            vec![3, 3, 2, 0]
        ]
    );
    assert!(inst.symmetric);
    assert_eq!(inst.sets, vec![vec![0], vec![1], vec![2], vec![3]]);
    assert_eq!(inst.name, "t");
}

#[test]
fn ceil_2d_rounds_up() {
    let inst = parse_instance(&coord_file("CEIL_2D")).unwrap();
    assert_eq!(
        matrix(&inst),
        vec![
            vec![0, 5, 2, 3],
            vec![5, 0, 4, 4],
            vec![2, 4, 0, 2],
            vec![3, 4, 2, 0]
        ]
    );
}

#[test]
fn att_pseudo_euclidean() {
    let text = "NAME: a\nTYPE: TSP\nDIMENSION: 4\nEDGE_WEIGHT_TYPE: ATT\nNODE_COORD_SECTION\n\
                1 0 0\n2 10 0\n3 0 30\n4 10 30\nEOF\n";
    let inst = parse_instance(text).unwrap();
    // r = sqrt(10) = 3.16 -> 4; r = sqrt(90) = 9.49 -> t = 9 < r -> 10; r = 10 -> 10.
    assert_eq!(
        matrix(&inst),
        vec![
            vec![0, 4, 10, 10],
            vec![4, 0, 10, 10],
            vec![10, 10, 0, 4],
            vec![10, 10, 4, 0]
        ]
    );
}

#[test]
fn geo_uses_deg_min_and_truncation() {
    // 0.30 is 0 degrees 30 minutes = 0.5 degrees; -1.30 is -1.5 degrees.
    let text = "NAME : g\nTYPE : TSP\nDIMENSION : 5\nEDGE_WEIGHT_TYPE : GEO\nEDGE_WEIGHT_FORMAT : FUNCTION\n\
                NODE_COORD_SECTION\n1 0.0 0.0\n2 0.0 1.0\n3 0.30 0.0\n4 -1.30 0.0\n5 45.30 10.45\nEOF\n";
    let inst = parse_instance(text).unwrap();
    // R * 1 deg = 111.32 -> (int)(111.32 + 1) = 112; R * 0.5 deg = 55.66 -> 56;
    // R * 1.5 deg = 166.99 -> 167.
    assert_eq!(
        matrix(&inst),
        vec![
            vec![0, 112, 56, 167, 5175],
            vec![112, 0, 125, 201, 5156],
            vec![56, 125, 0, 223, 5120],
            vec![167, 201, 223, 0, 5339],
            vec![5175, 5156, 5120, 5339, 0],
        ]
    );
    assert_eq!(tsplib_distance("GEO", (0.0, 0.0), (0.0, 1.0)), Some(112));
    assert_eq!(tsplib_distance("EUC_2D", (0.0, 0.0), (3.0, 4.0)), Some(5));
    assert_eq!(tsplib_distance("XRAY1", (0.0, 0.0), (3.0, 4.0)), None);
}

/// The symmetric 4x4 matrix used by the explicit-format tests.
fn sym4() -> Vec<Vec<i64>> {
    vec![
        vec![0, 1, 2, 3],
        vec![1, 0, 4, 5],
        vec![2, 4, 0, 6],
        vec![3, 5, 6, 0],
    ]
}

fn explicit(format: &str, data: &str) -> String {
    format!(
        "NAME : e\nTYPE : TSP\nDIMENSION : 4\nEDGE_WEIGHT_TYPE : EXPLICIT\nEDGE_WEIGHT_FORMAT : {format}\n\
         EDGE_WEIGHT_SECTION\n{data}\nEOF\n"
    )
}

#[test]
fn explicit_formats() {
    let cases = [
        ("FULL_MATRIX", "0 1 2 3\n1 0 4 5\n2 4 0 6\n3 5 6 0"),
        ("UPPER_ROW", "1 2 3\n4 5\n6"),
        ("UPPER_DIAG_ROW", "0 1 2 3 0 4 5\n0 6 0"),
        ("LOWER_DIAG_ROW", "0\n1 0\n2 4 0\n3 5 6 0"),
        ("LOWER_ROW", "1 2 4 3 5 6"),
    ];
    for (fmt, data) in cases {
        let inst = parse_instance(&explicit(fmt, data)).unwrap_or_else(|e| panic!("{fmt}: {e}"));
        assert_eq!(matrix(&inst), sym4(), "{fmt}");
        assert!(inst.symmetric);
    }
}

#[test]
fn asymmetric_gtsp_with_header_quirks() {
    // No-colon TYPE, double blanks, trailing blanks, sentinel diagonal, CRLF,
    // trailing colon on the set section, sets listed out of order.
    let text = "NAME:  q\r\nTYPE  AGTSP\r\nCOMMENT : quirky\nDIMENSION :  4 \nGTSP_SETS: 2\n\
                EDGE_WEIGHT_TYPE:  EXPLICIT\nEDGE_WEIGHT_FORMAT : FULL_MATRIX \nEDGE_WEIGHT_SECTION\n\
                9999 1 2 3\r\n4 9999 5 6\n7 8 9999 9\n10 11 12 9999\nGTSP_SET_SECTION:\n2 2 4 -1\n1 1\n3 -1\n";
    let inst = parse_instance(text).unwrap();
    assert_eq!(inst.name, "q");
    assert!(!inst.symmetric);
    assert_eq!(inst.sets, vec![vec![0, 2], vec![1, 3]]);
    assert_eq!(inst.dist.get(0, 0), 0, "diagonal is zeroed");
    assert_eq!(inst.dist.get(2, 3), 9);
    assert_eq!(inst.dist.get(3, 2), 12);
    assert_eq!(inst.tour_cost(&[0, 1]), 1 + 4);
    assert!(inst.check_tour(&[2, 3]).is_ok());
    assert!(inst.check_tour(&[0, 2]).is_err());
    assert!(inst.check_tour(&[0]).is_err());
}

#[test]
fn gtsp_with_coordinates_and_hofmeister_type() {
    let text = "NAME : 2x\nTYPE : GTSP (M.~Hofmeister)\nDIMENSION : 4\nGTSP_SETS : 2\n\
                EDGE_WEIGHT_TYPE : EUC_2D\nNODE_COORD_SECTION\n1 0 0\n2 3 4\n3 1 1\n4 0 2.5\n\
                GTSP_SET_SECTION\n1 1 2 -1\n2 3 4 -1\n";
    let inst = parse_instance(text).unwrap();
    assert_eq!(inst.sets, vec![vec![0, 1], vec![2, 3]]);
    assert_eq!(inst.tour_cost(&[0, 2]), 2);
}

#[test]
fn glns_compact_format() {
    let text = "N: 6\nM: 3\n1 1 2\n2 3 4\n3 5 6\n\
                9999 3 4 7 8 2\n3 9999 6 5 3 9\n4 6 9999 4 2 6\n7 5 4 9999 1 7\n8 3 2 1 9999 4\n2 9 6 7 4 9999\n";
    let inst = parse_instance(text).unwrap();
    assert_eq!(inst.sets, vec![vec![0, 1], vec![2, 3], vec![4, 5]]);
    // The README's exhaustive optimum: 2 -> 4 -> 5 costs 3 + 5... evaluated here.
    let sol = strider_plan::solve(&inst, &Default::default()).unwrap();
    assert_eq!(sol.cost, 9);
}

fn err(text: &str) -> TsplibError {
    parse_instance(text).expect_err("should fail")
}

#[test]
fn truncated_section_reports_line() {
    let text = explicit("UPPER_ROW", "1 2 3\n4 5");
    match err(&text) {
        TsplibError::Truncated {
            line,
            expected,
            found,
            ..
        } => {
            assert_eq!(line, 9, "the EOF line stops the section");
            assert_eq!((expected, found), (6, 5));
        }
        e => panic!("unexpected {e}"),
    }
    let text =
        "NAME: t\nDIMENSION: 3\nEDGE_WEIGHT_TYPE: EUC_2D\nNODE_COORD_SECTION\n1 0 0\n2 1 1\n";
    assert!(matches!(err(text), TsplibError::Truncated { line: 6, .. }));
}

#[test]
fn malformed_values_report_line() {
    let text = explicit("UPPER_ROW", "1 2 x\n4 5 6");
    assert!(
        matches!(err(&text), TsplibError::Syntax { line: 7, .. }),
        "{}",
        err(&text)
    );
    let text = "NAME: t\nDIMENSION: 2\nBOGUS_KEY: 3\n";
    assert!(matches!(err(text), TsplibError::Syntax { line: 3, .. }));
    let text = explicit("UPPER_ROW", "1 2 3 4 5 6 7");
    assert!(
        matches!(err(&text), TsplibError::Syntax { line: 7, .. }),
        "extra value"
    );
}

#[test]
fn bad_dimension() {
    assert!(matches!(
        err("NAME: x\nDIMENSION: zero\n"),
        TsplibError::BadDimension { line: 2, .. }
    ));
    assert!(matches!(
        err("NAME: x\nDIMENSION: 0\n"),
        TsplibError::BadDimension { line: 2, .. }
    ));
    assert!(matches!(
        err("NAME: x\nEDGE_WEIGHT_TYPE: EXPLICIT\nEDGE_WEIGHT_SECTION\n1 2\n"),
        TsplibError::BadDimension { line: 3, .. }
    ));
    assert!(matches!(
        err("NAME: x\nTYPE: TSP\n"),
        TsplibError::Missing { .. }
    ));
}

fn gtsp_sets(sets: &str, m: usize) -> String {
    format!(
        "NAME : s\nTYPE : GTSP\nDIMENSION : 4\nGTSP_SETS : {m}\nEDGE_WEIGHT_TYPE : EUC_2D\n\
         NODE_COORD_SECTION\n{POINTS}GTSP_SET_SECTION\n{sets}EOF\n"
    )
}

#[test]
fn set_errors() {
    assert!(
        gtsp_sets("1 1 2 -1\n2 3 4 -1\n", 2)
            .parse::<String>()
            .is_ok()
    );
    match err(&gtsp_sets("1 1 2 -1\n2 -1\n3 3 4 -1\n", 3)) {
        TsplibError::EmptySet { line, set } => assert_eq!((line, set), (13, 2)),
        e => panic!("unexpected {e}"),
    }
    match err(&gtsp_sets("1 1 2 -1\n2 2 3 4 -1\n", 2)) {
        TsplibError::VertexInTwoSets {
            line,
            vertex,
            first,
            second,
        } => assert_eq!((line, vertex, first, second), (13, 2, 1, 2)),
        e => panic!("unexpected {e}"),
    }
    match err(&gtsp_sets("1 1 2 -1\n2 3 -1\n", 2)) {
        TsplibError::VertexInNoSet { vertex, .. } => assert_eq!(vertex, 4),
        e => panic!("unexpected {e}"),
    }
    assert!(matches!(
        err(&gtsp_sets("1 1 2 -1\n2 3 4 -1\n", 3)),
        TsplibError::Truncated { line: 14, .. }
    ));
    assert!(matches!(
        err(&gtsp_sets("1 1 2 -1\n2 3 9 -1\n", 2)),
        TsplibError::Syntax { line: 13, .. }
    ));
}

#[test]
fn tour_files() {
    let t =
        parse_tour("NAME : x.tour\nTYPE : TOUR\nDIMENSION : 3\nTOUR_SECTION\n3\n1\n2\n-1\nEOF\n")
            .unwrap();
    assert_eq!(t, vec![2, 0, 1]);
    assert!(parse_tour("NAME : x\n").is_err());
    assert!(matches!(
        parse_tour("TOUR_SECTION\n1\nzz\n"),
        Err(TsplibError::Syntax { line: 3, .. })
    ));
}
