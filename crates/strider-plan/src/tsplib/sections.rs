//! The data sections: node coordinates, explicit edge weights, GTSP sets (and the set lines and
//! matrix of GLNS's compact format).

use super::TsplibError;
use super::header::WeightFormat;
use super::lexer::{Lexer, is_keyword};

/// `NODE_COORD_SECTION` or `DISPLAY_DATA_SECTION` (`key`): n lines `id x y`. The coordinates by
/// vertex for the former; the latter is read and dropped (`None`).
pub(super) fn read_coordinates(
    lx: &mut Lexer<'_>,
    n: usize,
    key: &str,
    line: usize,
) -> Result<Option<Vec<(f64, f64)>>, TsplibError> {
    let Some(expected) = n.checked_mul(3) else {
        return Err(TsplibError::BadDimension {
            line,
            msg: format!("{key} of {n} nodes has more values than this machine can count"),
        });
    };
    let keep = key == "NODE_COORD_SECTION";
    // `n` passed the matrix-size check, so this is small next to the matrix to come.
    let mut c = vec![(f64::NAN, f64::NAN); if keep { n } else { 0 }];
    for k in 0..n {
        let (id, l) = lx.number(key, expected, 3 * k)?;
        let (x, _) = lx.number(key, expected, 3 * k + 1)?;
        let (y, _) = lx.number(key, expected, 3 * k + 2)?;
        if id.fract() != 0.0 || id < 1.0 || id > n as f64 {
            // Scientific notation keeps a huge id on one short line.
            let shown = if id.abs() < 1e15 {
                id.to_string()
            } else {
                format!("{id:e}")
            };
            return Err(TsplibError::Syntax {
                line: l,
                msg: format!("node id {shown} not in 1..={n}"),
            });
        }
        if !keep {
            continue;
        }
        let i = id as usize - 1;
        if !c[i].0.is_nan() {
            return Err(TsplibError::Syntax {
                line: l,
                msg: format!("node {id} listed twice"),
            });
        }
        c[i] = (x, y);
    }
    lx.end_tokens()?;
    Ok(keep.then_some(c))
}

/// Number of values `EDGE_WEIGHT_SECTION` lists for an n-vertex matrix in format `fmt`.
pub(super) fn weight_count(n: usize, fmt: WeightFormat) -> Option<usize> {
    let tri = |k: usize| n.checked_mul(k).map(|c| c / 2);
    match fmt {
        WeightFormat::Full => n.checked_mul(n),
        WeightFormat::UpperRow | WeightFormat::LowerRow => tri(n.saturating_sub(1)),
        WeightFormat::UpperDiagRow | WeightFormat::LowerDiagRow => tri(n.checked_add(1)?),
        WeightFormat::Function => None,
    }
}

/// `EDGE_WEIGHT_SECTION` (at `line`) of an n-vertex matrix listed in format `fmt`: the full
/// matrix, row-major (a triangle is mirrored). Off-diagonal weights must be ≥ 0; the diagonal
/// (a sentinel in some GTSPLIB files) is kept as listed.
pub(super) fn read_edge_weights(
    lx: &mut Lexer<'_>,
    n: usize,
    fmt: WeightFormat,
    line: usize,
) -> Result<Vec<i64>, TsplibError> {
    if fmt == WeightFormat::Function {
        return Err(TsplibError::Syntax {
            line,
            msg: "EDGE_WEIGHT_SECTION with EDGE_WEIGHT_FORMAT FUNCTION".into(),
        });
    }
    let Some(count) = weight_count(n, fmt) else {
        return Err(TsplibError::BadDimension {
            line,
            msg: format!("the weights of {n} vertices are more than this machine can count"),
        });
    };
    let section = "EDGE_WEIGHT_SECTION";
    let mut vals = Vec::with_capacity(lx.capacity(count));
    for (k, (i, j)) in listed_cells(n, fmt).enumerate() {
        vals.push(weight(lx, section, count, k, i != j)?);
    }
    lx.end_tokens()?;
    if fmt == WeightFormat::Full {
        return Ok(vals);
    }
    let mut m = vec![0i64; n * n];
    for ((i, j), v) in listed_cells(n, fmt).zip(vals) {
        m[i * n + j] = v;
        m[j * n + i] = v;
    }
    Ok(m)
}

/// The (row, column) of every value `EDGE_WEIGHT_SECTION` lists in format `fmt`, in listing
/// order.
fn listed_cells(n: usize, fmt: WeightFormat) -> Box<dyn Iterator<Item = (usize, usize)>> {
    match fmt {
        WeightFormat::Full => Box::new((0..n).flat_map(move |i| (0..n).map(move |j| (i, j)))),
        WeightFormat::UpperRow => {
            Box::new((0..n).flat_map(move |i| (i + 1..n).map(move |j| (i, j))))
        }
        WeightFormat::LowerRow => Box::new((0..n).flat_map(|i| (0..i).map(move |j| (i, j)))),
        WeightFormat::UpperDiagRow => {
            Box::new((0..n).flat_map(move |i| (i..n).map(move |j| (i, j))))
        }
        WeightFormat::LowerDiagRow => Box::new((0..n).flat_map(|i| (0..=i).map(move |j| (i, j)))),
        WeightFormat::Function => Box::new(std::iter::empty()),
    }
}

/// The next weight (`k` of `count`), refused when negative off the diagonal.
fn weight(
    lx: &mut Lexer<'_>,
    section: &str,
    count: usize,
    k: usize,
    off_diagonal: bool,
) -> Result<i64, TsplibError> {
    let (v, line) = lx.integer(section, count, k)?;
    if off_diagonal && v < 0 {
        return Err(TsplibError::Syntax {
            line,
            msg: format!("negative weight {v} in {section} (weights must be ≥ 0)"),
        });
    }
    Ok(v)
}

/// GLNS's compact format after `M: m` at `line`: m lines `id v1 v2 ...`, then the full n × n
/// matrix. The validated 0-based sets and the matrix.
pub(super) fn read_compact(
    lx: &mut Lexer<'_>,
    n: usize,
    m: usize,
    line: usize,
) -> Result<(Vec<Vec<usize>>, Vec<i64>), TsplibError> {
    if m > n {
        return Err(TsplibError::BadDimension {
            line,
            msg: format!("{m} sets for {n} vertices"),
        });
    }
    let mut groups = Vec::with_capacity(m);
    for _ in 0..m {
        let Some((sl, sline)) = lx.line() else {
            return Err(TsplibError::Truncated {
                line: lx.last_line(),
                section: "set list".into(),
                expected: m,
                found: groups.len(),
                unit: "sets",
            });
        };
        let mut toks = sl.split_whitespace();
        toks.next(); // set id
        let mut g = Vec::new();
        for t in toks {
            let v = t.parse::<usize>().map_err(|_| TsplibError::Syntax {
                line: sline,
                msg: format!("'{t}' is not a vertex number"),
            })?;
            g.push((v, sline));
        }
        groups.push((g, sline));
    }
    let sets = check_sets(groups, n, m)?;
    let count = n * n;
    let mut matrix = Vec::with_capacity(lx.capacity(count));
    for k in 0..count {
        matrix.push(weight(lx, "matrix", count, k, k % (n + 1) != 0)?);
    }
    lx.end_tokens()?;
    Ok((sets, matrix))
}

/// `GTSP_SET_SECTION` of an n-vertex instance whose header declared `declared` (count, line)
/// sets: the validated 0-based sets, ordered by set id.
pub(super) fn read_gtsp_sets(
    lx: &mut Lexer<'_>,
    n: usize,
    declared: Option<(usize, usize)>,
) -> Result<Vec<Vec<usize>>, TsplibError> {
    if let Some((m, line)) = declared
        && m > n
    {
        return Err(TsplibError::BadDimension {
            line,
            msg: format!("GTSP_SETS {m} is more than DIMENSION {n} (every set needs a vertex)"),
        });
    }
    let groups = read_set_section(lx, declared.map(|x| x.0))?;
    lx.end_tokens()?;
    let m = groups.len();
    if let Some((declared, dl)) = declared
        && declared != m
    {
        return Err(TsplibError::BadDimension {
            line: dl,
            msg: format!("GTSP_SETS is {declared} but {m} sets are listed"),
        });
    }
    check_sets(groups, n, m)
}

/// One listed set: its (vertex, line) entries and the line of its id.
type Group = (Vec<(usize, usize)>, usize);
type Groups = Vec<Group>;

/// Reads `setid v1 ... -1` groups. With `expected = None`, reads groups until
/// a non-numeric token.
fn read_set_section(lx: &mut Lexer<'_>, expected: Option<usize>) -> Result<Groups, TsplibError> {
    let mut groups: Groups = Vec::new();
    let mut ids = Vec::new();
    loop {
        if let Some(m) = expected
            && groups.len() == m
        {
            break;
        }
        let Some((t, line)) = lx.peek() else {
            if expected.is_none() {
                break;
            }
            return Err(TsplibError::Truncated {
                line: lx.last_line(),
                section: "GTSP_SET_SECTION".into(),
                expected: expected.unwrap_or(0),
                found: groups.len(),
                unit: "sets",
            });
        };
        let Ok(id) = t.parse::<usize>() else {
            if expected.is_none() && is_keyword(t) {
                break;
            }
            return Err(if is_keyword(t) {
                TsplibError::Truncated {
                    line,
                    section: "GTSP_SET_SECTION".into(),
                    expected: expected.unwrap_or(0),
                    found: groups.len(),
                    unit: "sets",
                }
            } else {
                TsplibError::Syntax {
                    line,
                    msg: format!("'{t}' is not a set id"),
                }
            });
        };
        lx.token();
        ids.push((id, line));
        let mut g = Vec::new();
        loop {
            let Some((t, l)) = lx.token() else {
                return Err(TsplibError::Truncated {
                    line: lx.last_line(),
                    section: "GTSP_SET_SECTION".into(),
                    expected: expected.unwrap_or(groups.len() + 1),
                    found: groups.len(),
                    unit: "sets",
                });
            };
            if t == "-1" {
                break;
            }
            match t.parse::<usize>() {
                Ok(v) => g.push((v, l)),
                Err(_) => {
                    return Err(if is_keyword(t) {
                        TsplibError::Truncated {
                            line: l,
                            section: "GTSP_SET_SECTION".into(),
                            expected: expected.unwrap_or(groups.len() + 1),
                            found: groups.len(),
                            unit: "sets",
                        }
                    } else {
                        TsplibError::Syntax {
                            line: l,
                            msg: format!("'{t}' is not a vertex number"),
                        }
                    });
                }
            }
        }
        groups.push((g, line));
    }
    // Order the groups by set id when the ids are a permutation of 1..=m.
    let m = groups.len();
    let mut order: Vec<usize> = (0..m).collect();
    let mut idseen = vec![false; m + 1];
    let perm = ids.iter().all(|&(id, _)| {
        let ok = id >= 1 && id <= m && !idseen[id];
        if ok {
            idseen[id] = true;
        }
        ok
    });
    if perm {
        order.sort_by_key(|&k| ids[k].0);
        let mut sorted = Vec::with_capacity(m);
        let mut taken: Vec<Option<Group>> = groups.into_iter().map(Some).collect();
        for k in order {
            sorted.push(taken[k].take().unwrap());
        }
        groups = sorted;
    } else if let Some(&(id, line)) = ids.iter().find(|&&(id, _)| id < 1 || id > m) {
        return Err(TsplibError::Syntax {
            line,
            msg: format!("set id {id} not in 1..={m}"),
        });
    } else if let Some(&(id, line)) = ids
        .iter()
        .enumerate()
        .find(|(k, (id, _))| ids[..*k].iter().any(|(o, _)| o == id))
        .map(|(_, x)| x)
    {
        return Err(TsplibError::Syntax {
            line,
            msg: format!("set id {id} listed twice"),
        });
    }
    Ok(groups)
}

/// Validates 1-based groups and converts them to 0-based sets.
fn check_sets(groups: Groups, n: usize, m: usize) -> Result<Vec<Vec<usize>>, TsplibError> {
    let mut owner = vec![usize::MAX; n];
    let mut out = Vec::with_capacity(m);
    let first_line = groups.first().map(|g| g.1).unwrap_or(0);
    for (s, (g, line)) in groups.into_iter().enumerate() {
        if g.is_empty() {
            return Err(TsplibError::EmptySet { line, set: s + 1 });
        }
        let mut set = Vec::with_capacity(g.len());
        for (v, l) in g {
            if v < 1 || v > n {
                return Err(TsplibError::Syntax {
                    line: l,
                    msg: format!("vertex {v} not in 1..={n}"),
                });
            }
            let v0 = v - 1;
            if owner[v0] != usize::MAX {
                return Err(TsplibError::VertexInTwoSets {
                    line: l,
                    vertex: v,
                    first: owner[v0] + 1,
                    second: s + 1,
                });
            }
            owner[v0] = s;
            set.push(v0);
        }
        out.push(set);
    }
    if let Some(v) = owner.iter().position(|&o| o == usize::MAX) {
        return Err(TsplibError::VertexInNoSet {
            line: first_line,
            vertex: v + 1,
        });
    }
    Ok(out)
}
