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
) -> Result<Option<Vec<(f64, f64)>>, TsplibError> {
    let vals = lx.numbers(3 * n, key)?;
    lx.end_tokens()?;
    if key != "NODE_COORD_SECTION" {
        return Ok(None);
    }
    let mut c = vec![(f64::NAN, f64::NAN); n];
    for k in 0..n {
        let (id, l) = vals[3 * k];
        if id.fract() != 0.0 || id < 1.0 || id > n as f64 {
            return Err(TsplibError::Syntax {
                line: l,
                msg: format!("node id {id} not in 1..={n}"),
            });
        }
        let i = id as usize - 1;
        if !c[i].0.is_nan() {
            return Err(TsplibError::Syntax {
                line: l,
                msg: format!("node {id} listed twice"),
            });
        }
        c[i] = (vals[3 * k + 1].0, vals[3 * k + 2].0);
    }
    Ok(Some(c))
}

/// `EDGE_WEIGHT_SECTION` (at `line`) of an n-vertex matrix listed in format `fmt`: the full
/// matrix, row-major (a triangle is mirrored).
pub(super) fn read_edge_weights(
    lx: &mut Lexer<'_>,
    n: usize,
    fmt: WeightFormat,
    line: usize,
) -> Result<Vec<i64>, TsplibError> {
    let count = match fmt {
        WeightFormat::Full => n * n,
        WeightFormat::UpperRow | WeightFormat::LowerRow => n * (n - 1) / 2,
        WeightFormat::UpperDiagRow | WeightFormat::LowerDiagRow => n * (n + 1) / 2,
        WeightFormat::Function => {
            return Err(TsplibError::Syntax {
                line,
                msg: "EDGE_WEIGHT_SECTION with EDGE_WEIGHT_FORMAT FUNCTION".into(),
            });
        }
    };
    let vals = read_integers(lx, count, "EDGE_WEIGHT_SECTION")?;
    let mut m = vec![0i64; n * n];
    let mut it = vals.into_iter();
    let mut put = |i: usize, j: usize, v: i64| {
        m[i * n + j] = v;
        m[j * n + i] = v;
    };
    match fmt {
        WeightFormat::Full => {
            for (k, v) in it.enumerate() {
                m[k] = v;
            }
        }
        WeightFormat::UpperRow => {
            for i in 0..n {
                for j in i + 1..n {
                    put(i, j, it.next().unwrap());
                }
            }
        }
        WeightFormat::LowerRow => {
            for i in 0..n {
                for j in 0..i {
                    put(i, j, it.next().unwrap());
                }
            }
        }
        WeightFormat::UpperDiagRow => {
            for i in 0..n {
                for j in i..n {
                    put(i, j, it.next().unwrap());
                }
            }
        }
        WeightFormat::LowerDiagRow => {
            for i in 0..n {
                for j in 0..=i {
                    put(i, j, it.next().unwrap());
                }
            }
        }
        WeightFormat::Function => unreachable!(),
    }
    Ok(m)
}

/// `count` integer values of `section`, ending its last line.
fn read_integers(lx: &mut Lexer<'_>, count: usize, section: &str) -> Result<Vec<i64>, TsplibError> {
    let vals = lx.numbers(count, section)?;
    lx.end_tokens()?;
    vals.iter().map(|&(x, l)| to_int(x, l)).collect()
}

fn to_int(x: f64, line: usize) -> Result<i64, TsplibError> {
    if x.abs() > 9.0e15 {
        return Err(TsplibError::Syntax {
            line,
            msg: format!("value {x} out of range"),
        });
    }
    Ok(x.round() as i64)
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
    let matrix = read_integers(lx, n * n, "matrix")?;
    Ok((sets, matrix))
}

/// `GTSP_SET_SECTION` of an n-vertex instance whose header declared `declared` (count, line)
/// sets: the validated 0-based sets, ordered by set id.
pub(super) fn read_gtsp_sets(
    lx: &mut Lexer<'_>,
    n: usize,
    declared: Option<(usize, usize)>,
) -> Result<Vec<Vec<usize>>, TsplibError> {
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
