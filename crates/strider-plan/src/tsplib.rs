//! Reader for TSPLIB and GTSPLIB instance files, and for TSPLIB tour files.
//!
//! Supported (see Reinelt, "TSPLIB — A Traveling Salesman Problem Library",
//! ORSA J. Computing 3(4), 1991, and the GTSPLIB format of Fischetti,
//! Salazar González & Toth, Oper. Res. 45(3), 1997):
//!
//! * header keys `NAME`, `TYPE` (`TSP`, `ATSP`, `GTSP`, `AGTSP`; trailing text
//!   such as `GTSP (M.~Hofmeister)` is ignored), `COMMENT`, `DIMENSION`,
//!   `GTSP_SETS`, `EDGE_WEIGHT_TYPE` (`EUC_2D`, `CEIL_2D`, `GEO`, `ATT`,
//!   `EXPLICIT`), `EDGE_WEIGHT_FORMAT` (`FULL_MATRIX`, `UPPER_ROW`,
//!   `LOWER_ROW`, `UPPER_DIAG_ROW`, `LOWER_DIAG_ROW`, the `*_COL` variants,
//!   and `FUNCTION`, which means "computed from the coordinates"),
//!   `NODE_COORD_TYPE`, `DISPLAY_DATA_TYPE`;
//! * sections `NODE_COORD_SECTION`, `EDGE_WEIGHT_SECTION`,
//!   `DISPLAY_DATA_SECTION` (skipped), `GTSP_SET_SECTION` (lines
//!   `setid v1 v2 ... -1`, 1-based, values may wrap over lines), `EOF`;
//! * header quirks seen in GTSPLIB: `KEY : value`, `KEY: value`, `KEY  value`
//!   (no colon), `KEY:  value`, trailing blanks, trailing colon on a section
//!   keyword (`GTSP_SET_SECTION:`), CRLF/LF mixes, a missing `EOF`;
//! * GLNS.jl's compact format (`N: 6`, `M: 3`, one line per set
//!   `id v1 v2 ...`, then the full matrix).
//!
//! Distances follow TSPLIB exactly: `EUC_2D` = `nint(sqrt(dx²+dy²))`,
//! `CEIL_2D` = `ceil(...)`, `ATT` pseudo-Euclidean, `GEO` with
//! `PI = 3.141592`, the `deg.min` conversion with truncation of the degrees,
//! radius 6378.388 and `(int)(R·acos(..) + 1)`. The diagonal of every matrix
//! is set to 0 (GTSPLIB's asymmetric files store a large sentinel there; a
//! g-tour never uses it).

use std::fmt;
use std::path::Path;

use thiserror::Error;

/// Dense row-major integer cost matrix: `get(i, j)` is the cost of going
/// from vertex `i` to vertex `j`.
#[derive(Clone, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
pub struct CostMatrix {
    n: usize,
    data: Vec<i64>,
}

impl fmt::Debug for CostMatrix {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "CostMatrix({}x{})", self.n, self.n)
    }
}

impl CostMatrix {
    /// Builds a matrix from row-major data of length `n * n`.
    ///
    /// # Panics
    /// If `data.len() != n * n`.
    pub fn new(n: usize, data: Vec<i64>) -> Self {
        assert_eq!(data.len(), n * n, "cost matrix must have n*n entries");
        Self { n, data }
    }

    /// Builds a matrix by evaluating `f(i, j)` for every pair.
    pub fn from_fn(n: usize, mut f: impl FnMut(usize, usize) -> i64) -> Self {
        let mut data = Vec::with_capacity(n * n);
        for i in 0..n {
            for j in 0..n {
                data.push(f(i, j));
            }
        }
        Self { n, data }
    }

    /// Number of vertices.
    pub fn n(&self) -> usize {
        self.n
    }

    /// Cost of the arc `i -> j`.
    #[inline]
    pub fn get(&self, i: usize, j: usize) -> i64 {
        self.data[i * self.n + j]
    }

    /// Sets the cost of the arc `i -> j`.
    pub fn set(&mut self, i: usize, j: usize, c: i64) {
        self.data[i * self.n + j] = c;
    }

    /// Row `i`: costs of the arcs leaving `i`.
    pub fn row(&self, i: usize) -> &[i64] {
        &self.data[i * self.n..(i + 1) * self.n]
    }

    /// True if `get(i, j) == get(j, i)` for all pairs.
    pub fn is_symmetric(&self) -> bool {
        (0..self.n).all(|i| (0..i).all(|j| self.get(i, j) == self.get(j, i)))
    }
}

/// A (G)TSP instance: `n` vertices, a partition (or sub-partition) of them
/// into `sets`, and a dense cost matrix.
#[derive(Clone, Debug, serde::Serialize, serde::Deserialize)]
pub struct Instance {
    /// Instance name (`NAME` of the file).
    pub name: String,
    /// Number of vertices; vertices are `0..n`.
    pub n: usize,
    /// The vertex sets (clusters). A g-tour visits exactly one vertex of each.
    pub sets: Vec<Vec<usize>>,
    /// Arc costs.
    pub dist: CostMatrix,
    /// True if `dist` is symmetric.
    pub symmetric: bool,
}

/// Errors of [`Instance::new`] and of tour checks.
#[derive(Debug, Error, PartialEq, Eq)]
pub enum InstanceError {
    /// The matrix dimension differs from `n`.
    #[error("cost matrix is {got}x{got}, expected {expected}x{expected}")]
    MatrixSize {
        /// Expected dimension.
        expected: usize,
        /// Actual dimension.
        got: usize,
    },
    /// A set has no vertex.
    #[error("set {set} has no vertex")]
    EmptySet {
        /// 0-based set index.
        set: usize,
    },
    /// A vertex index is `>= n`.
    #[error("vertex {vertex} out of range (n = {n})")]
    VertexOutOfRange {
        /// The vertex.
        vertex: usize,
        /// Number of vertices.
        n: usize,
    },
    /// A vertex belongs to two sets.
    #[error("vertex {vertex} is in sets {first} and {second}")]
    VertexInTwoSets {
        /// The vertex.
        vertex: usize,
        /// First set.
        first: usize,
        /// Second set.
        second: usize,
    },
    /// A vertex belongs to no set.
    #[error("vertex {vertex} is in no set")]
    VertexInNoSet {
        /// The vertex.
        vertex: usize,
    },
    /// A tour visits a set twice or misses one.
    #[error("tour is infeasible: {0}")]
    InfeasibleTour(String),
}

impl Instance {
    /// Builds an instance. Every set must be non-empty and no vertex may be
    /// in two sets; vertices in no set are allowed (the solver ignores them).
    pub fn new(
        name: impl Into<String>,
        sets: Vec<Vec<usize>>,
        dist: CostMatrix,
    ) -> Result<Self, InstanceError> {
        let n = dist.n();
        let mut owner = vec![usize::MAX; n];
        for (s, set) in sets.iter().enumerate() {
            if set.is_empty() {
                return Err(InstanceError::EmptySet { set: s });
            }
            for &v in set {
                if v >= n {
                    return Err(InstanceError::VertexOutOfRange { vertex: v, n });
                }
                if owner[v] != usize::MAX {
                    return Err(InstanceError::VertexInTwoSets {
                        vertex: v,
                        first: owner[v],
                        second: s,
                    });
                }
                owner[v] = s;
            }
        }
        let symmetric = dist.is_symmetric();
        Ok(Self {
            name: name.into(),
            n,
            sets,
            dist,
            symmetric,
        })
    }

    /// A plain TSP: every vertex is its own set.
    pub fn tsp(name: impl Into<String>, dist: CostMatrix) -> Self {
        let sets = (0..dist.n()).map(|v| vec![v]).collect();
        Self::new(name, sets, dist).expect("singleton sets are valid")
    }

    /// Number of sets.
    pub fn num_sets(&self) -> usize {
        self.sets.len()
    }

    /// `set_of()[v]` is the set containing `v`, if any.
    pub fn set_of(&self) -> Vec<Option<usize>> {
        let mut owner = vec![None; self.n];
        for (s, set) in self.sets.iter().enumerate() {
            for &v in set {
                owner[v] = Some(s);
            }
        }
        owner
    }

    /// Cost of the closed tour `tour[0] -> tour[1] -> ... -> tour[0]`
    /// (0 for fewer than two vertices).
    pub fn tour_cost(&self, tour: &[usize]) -> i64 {
        if tour.len() < 2 {
            return 0;
        }
        self.path_cost(tour) + self.dist.get(tour[tour.len() - 1], tour[0])
    }

    /// Cost of the open path `tour[0] -> ... -> tour[last]`.
    pub fn path_cost(&self, tour: &[usize]) -> i64 {
        tour.windows(2).map(|w| self.dist.get(w[0], w[1])).sum()
    }

    /// Checks that `tour` visits exactly one vertex of every set.
    pub fn check_tour(&self, tour: &[usize]) -> Result<(), InstanceError> {
        let owner = self.set_of();
        let mut seen = vec![false; self.sets.len()];
        for &v in tour {
            if v >= self.n {
                return Err(InstanceError::VertexOutOfRange {
                    vertex: v,
                    n: self.n,
                });
            }
            let Some(s) = owner[v] else {
                return Err(InstanceError::InfeasibleTour(format!(
                    "vertex {v} is in no set"
                )));
            };
            if seen[s] {
                return Err(InstanceError::InfeasibleTour(format!(
                    "set {s} visited twice"
                )));
            }
            seen[s] = true;
        }
        if let Some(s) = seen.iter().position(|&b| !b) {
            return Err(InstanceError::InfeasibleTour(format!(
                "set {s} not visited"
            )));
        }
        Ok(())
    }
}

/// Errors of the TSPLIB reader. Line numbers are 1-based; vertex and set
/// numbers are the file's (1-based) numbers.
#[derive(Debug, Error)]
pub enum TsplibError {
    /// The file could not be read.
    #[error("cannot read {path}: {source}")]
    Io {
        /// The path.
        path: String,
        /// The I/O error.
        source: std::io::Error,
    },
    /// Malformed line or value.
    #[error("line {line}: {msg}")]
    Syntax {
        /// Line number.
        line: usize,
        /// What is wrong.
        msg: String,
    },
    /// A section ended (end of file or next keyword) before all its values.
    #[error("line {line}: {section} is truncated: expected {expected} values, found {found}")]
    Truncated {
        /// Line where the data stopped.
        line: usize,
        /// The section.
        section: String,
        /// Number of values expected.
        expected: usize,
        /// Number of values found.
        found: usize,
    },
    /// `DIMENSION` or `GTSP_SETS` missing, zero, or inconsistent.
    #[error("line {line}: bad dimension: {msg}")]
    BadDimension {
        /// Line number.
        line: usize,
        /// What is wrong.
        msg: String,
    },
    /// A set of `GTSP_SET_SECTION` has no vertex.
    #[error("line {line}: set {set} has no vertex")]
    EmptySet {
        /// Line number.
        line: usize,
        /// 1-based set id.
        set: usize,
    },
    /// A vertex is listed in two sets.
    #[error("line {line}: vertex {vertex} is in set {first} and in set {second}")]
    VertexInTwoSets {
        /// Line number of the second occurrence.
        line: usize,
        /// 1-based vertex.
        vertex: usize,
        /// 1-based first set.
        first: usize,
        /// 1-based second set.
        second: usize,
    },
    /// A vertex is in no set.
    #[error("line {line}: vertex {vertex} is in no set")]
    VertexInNoSet {
        /// Line of the `GTSP_SET_SECTION` keyword.
        line: usize,
        /// 1-based vertex.
        vertex: usize,
    },
    /// A keyword value this reader does not support.
    #[error("line {line}: unsupported {what}")]
    Unsupported {
        /// Line number.
        line: usize,
        /// What is unsupported.
        what: String,
    },
    /// A required header or section is missing.
    #[error("line {line}: missing {what}")]
    Missing {
        /// Line number (end of file).
        line: usize,
        /// What is missing.
        what: String,
    },
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum WeightType {
    Euc2d,
    Ceil2d,
    Geo,
    Att,
    Explicit,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum WeightFormat {
    Function,
    Full,
    UpperRow,
    LowerRow,
    UpperDiagRow,
    LowerDiagRow,
}

/// Line-and-token cursor over the file text.
struct Lexer<'a> {
    lines: Vec<&'a str>,
    /// Index of the next line to read.
    next: usize,
    /// Tokens left on the line last loaded by `token()`, with its number.
    pending: Vec<&'a str>,
    pending_line: usize,
}

impl<'a> Lexer<'a> {
    fn new(text: &'a str) -> Self {
        Self {
            lines: text.lines().collect(),
            next: 0,
            pending: Vec::new(),
            pending_line: 0,
        }
    }

    /// Number of the last line (for end-of-file errors).
    fn last_line(&self) -> usize {
        self.lines.len().max(1)
    }

    /// Next non-blank line, trimmed, with its 1-based number.
    fn line(&mut self) -> Option<(&'a str, usize)> {
        debug_assert!(self.pending.is_empty());
        while self.next < self.lines.len() {
            let l = self.lines[self.next].trim();
            self.next += 1;
            if !l.is_empty() {
                return Some((l, self.next));
            }
        }
        None
    }

    /// Peeks the next token (possibly on a later line) without consuming it.
    fn peek(&mut self) -> Option<(&'a str, usize)> {
        while self.pending.is_empty() {
            if self.next >= self.lines.len() {
                return None;
            }
            let l = self.lines[self.next];
            self.next += 1;
            self.pending = l.split_whitespace().rev().collect();
            self.pending_line = self.next;
        }
        self.pending.last().map(|t| (*t, self.pending_line))
    }

    fn token(&mut self) -> Option<(&'a str, usize)> {
        let t = self.peek()?;
        self.pending.pop();
        Some(t)
    }

    /// Ends token mode: the rest of the current line must be empty.
    fn end_tokens(&mut self) -> Result<(), TsplibError> {
        if let Some(t) = self.pending.last() {
            return Err(TsplibError::Syntax {
                line: self.pending_line,
                msg: format!("unexpected extra value '{t}'"),
            });
        }
        Ok(())
    }

    /// Reads `count` numbers of a section.
    fn numbers(&mut self, count: usize, section: &str) -> Result<Vec<(f64, usize)>, TsplibError> {
        let mut out = Vec::with_capacity(count);
        while out.len() < count {
            let Some((t, line)) = self.peek() else {
                return Err(TsplibError::Truncated {
                    line: self.last_line(),
                    section: section.to_string(),
                    expected: count,
                    found: out.len(),
                });
            };
            match t.parse::<f64>() {
                Ok(x) if x.is_finite() => {
                    self.pending.pop();
                    out.push((x, line));
                }
                _ => {
                    if is_keyword(t) {
                        return Err(TsplibError::Truncated {
                            line,
                            section: section.to_string(),
                            expected: count,
                            found: out.len(),
                        });
                    }
                    return Err(TsplibError::Syntax {
                        line,
                        msg: format!("'{t}' is not a number in {section}"),
                    });
                }
            }
        }
        Ok(out)
    }
}

/// True for a TSPLIB keyword such as `EOF` or `GTSP_SET_SECTION:` (used to
/// tell a truncated section from a malformed value).
fn is_keyword(t: &str) -> bool {
    let t = t.trim_end_matches(':');
    t.len() > 1
        && t.chars()
            .all(|c| c.is_ascii_uppercase() || c == '_' || c.is_ascii_digit())
        && t.starts_with(|c: char| c.is_ascii_uppercase())
}

/// Splits a header line into its key and value, accepting `KEY : v`,
/// `KEY: v`, `KEY  v` and `KEY:` forms.
fn split_header(line: &str) -> (&str, &str) {
    let key_end = line
        .find(|c: char| !(c.is_ascii_alphanumeric() || c == '_'))
        .unwrap_or(line.len());
    let key = &line[..key_end];
    let rest = line[key_end..].trim_start();
    let rest = rest.strip_prefix(':').unwrap_or(rest).trim();
    (key, rest)
}

fn parse_usize(value: &str, line: usize, what: &str) -> Result<usize, TsplibError> {
    let tok = value.split_whitespace().next().unwrap_or("");
    tok.parse::<usize>().map_err(|_| TsplibError::BadDimension {
        line,
        msg: format!("{what} '{value}' is not a non-negative integer"),
    })
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

/// TSPLIB `nint`.
fn nint(x: f64) -> i64 {
    (x + 0.5).floor() as i64
}

/// Geographic latitude/longitude in radians from TSPLIB's `DDD.MM` format.
fn geo_radians(x: f64) -> f64 {
    // TSPLIB's truncated value, not std::f64::consts::PI.
    #[allow(clippy::approx_constant)]
    const PI: f64 = 3.141592;
    let deg = x.trunc();
    let min = x - deg;
    PI * (deg + 5.0 * min / 3.0) / 180.0
}

fn coord_distance(kind: WeightType, a: (f64, f64), b: (f64, f64)) -> i64 {
    let dx = a.0 - b.0;
    let dy = a.1 - b.1;
    match kind {
        WeightType::Euc2d => nint((dx * dx + dy * dy).sqrt()),
        WeightType::Ceil2d => (dx * dx + dy * dy).sqrt().ceil() as i64,
        WeightType::Att => {
            let r = ((dx * dx + dy * dy) / 10.0).sqrt();
            let t = nint(r);
            if (t as f64) < r { t + 1 } else { t }
        }
        WeightType::Geo => {
            const RRR: f64 = 6378.388;
            let (lat_i, lon_i) = (geo_radians(a.0), geo_radians(a.1));
            let (lat_j, lon_j) = (geo_radians(b.0), geo_radians(b.1));
            let q1 = (lon_i - lon_j).cos();
            let q2 = (lat_i - lat_j).cos();
            let q3 = (lat_i + lat_j).cos();
            (RRR * (0.5 * ((1.0 + q1) * q2 - (1.0 - q1) * q3)).acos() + 1.0) as i64
        }
        WeightType::Explicit => unreachable!("explicit weights have no coordinates"),
    }
}

/// TSPLIB distance between two points for `EDGE_WEIGHT_TYPE` `kind`
/// (`"EUC_2D"`, `"CEIL_2D"`, `"ATT"`, `"GEO"`). Returns `None` for other kinds.
pub fn tsplib_distance(kind: &str, a: (f64, f64), b: (f64, f64)) -> Option<i64> {
    let k = match kind {
        "EUC_2D" => WeightType::Euc2d,
        "CEIL_2D" => WeightType::Ceil2d,
        "ATT" => WeightType::Att,
        "GEO" => WeightType::Geo,
        _ => return None,
    };
    Some(coord_distance(k, a, b))
}

/// Reads an instance file from disk. The instance name defaults to the file
/// stem when the file has no `NAME`.
pub fn read_instance_file(path: impl AsRef<Path>) -> Result<Instance, TsplibError> {
    let path = path.as_ref();
    let text = std::fs::read_to_string(path).map_err(|source| TsplibError::Io {
        path: path.display().to_string(),
        source,
    })?;
    let mut inst = parse_instance(&text)?;
    if inst.name.is_empty() {
        inst.name = path
            .file_stem()
            .map(|s| s.to_string_lossy().into_owned())
            .unwrap_or_default();
    }
    Ok(inst)
}

/// Parses a TSPLIB / GTSPLIB (or GLNS compact) instance from text.
pub fn parse_instance(text: &str) -> Result<Instance, TsplibError> {
    let mut lx = Lexer::new(text);
    let mut name = String::new();
    let mut dim: Option<(usize, usize)> = None; // (value, line)
    let mut num_sets: Option<(usize, usize)> = None;
    let mut wtype: Option<WeightType> = None;
    let mut wformat: Option<WeightFormat> = None;
    let mut coords: Option<Vec<(f64, f64)>> = None;
    let mut matrix: Option<Vec<i64>> = None;
    let mut sets: Option<(Vec<Vec<usize>>, usize)> = None;
    let mut compact = false;

    let need_dim = |dim: Option<(usize, usize)>, line: usize| -> Result<usize, TsplibError> {
        match dim {
            Some((d, _)) => Ok(d),
            None => Err(TsplibError::BadDimension {
                line,
                msg: "section before DIMENSION".into(),
            }),
        }
    };

    while let Some((l, line)) = lx.line() {
        let (key, value) = split_header(l);
        match key {
            "EOF" => break,
            "NAME" => name = value.to_string(),
            "COMMENT" | "NODE_COORD_TYPE" | "DISPLAY_DATA_TYPE" | "CAPACITY" => {}
            "TYPE" => {
                let t = value.split_whitespace().next().unwrap_or("");
                match t {
                    "TSP" | "ATSP" | "GTSP" | "AGTSP" => {}
                    _ => {
                        return Err(TsplibError::Unsupported {
                            line,
                            what: format!("TYPE '{value}'"),
                        });
                    }
                }
            }
            "DIMENSION" | "N" => {
                let d = parse_usize(value, line, "DIMENSION")?;
                if d == 0 {
                    return Err(TsplibError::BadDimension {
                        line,
                        msg: "DIMENSION is 0".into(),
                    });
                }
                if key == "N" {
                    compact = true;
                }
                dim = Some((d, line));
            }
            "GTSP_SETS" | "M" => {
                let m = parse_usize(value, line, "GTSP_SETS")?;
                if m == 0 {
                    return Err(TsplibError::BadDimension {
                        line,
                        msg: "GTSP_SETS is 0".into(),
                    });
                }
                num_sets = Some((m, line));
                if compact {
                    // GLNS compact format: m set lines, then the full matrix.
                    let n = need_dim(dim, line)?;
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
                    sets = Some((check_sets(groups, n, m)?, line));
                    let vals = lx.numbers(n * n, "matrix")?;
                    lx.end_tokens()?;
                    matrix = Some(
                        vals.iter()
                            .map(|&(x, l)| to_int(x, l))
                            .collect::<Result<_, _>>()?,
                    );
                }
            }
            "EDGE_WEIGHT_TYPE" => {
                wtype = Some(match value {
                    "EUC_2D" => WeightType::Euc2d,
                    "CEIL_2D" => WeightType::Ceil2d,
                    "GEO" => WeightType::Geo,
                    "ATT" => WeightType::Att,
                    "EXPLICIT" => WeightType::Explicit,
                    _ => {
                        return Err(TsplibError::Unsupported {
                            line,
                            what: format!("EDGE_WEIGHT_TYPE '{value}'"),
                        });
                    }
                })
            }
            "EDGE_WEIGHT_FORMAT" => {
                wformat = Some(match value {
                    "FUNCTION" => WeightFormat::Function,
                    "FULL_MATRIX" => WeightFormat::Full,
                    "UPPER_ROW" | "LOWER_COL" => WeightFormat::UpperRow,
                    "LOWER_ROW" | "UPPER_COL" => WeightFormat::LowerRow,
                    "UPPER_DIAG_ROW" | "LOWER_DIAG_COL" => WeightFormat::UpperDiagRow,
                    "LOWER_DIAG_ROW" | "UPPER_DIAG_COL" => WeightFormat::LowerDiagRow,
                    _ => {
                        return Err(TsplibError::Unsupported {
                            line,
                            what: format!("EDGE_WEIGHT_FORMAT '{value}'"),
                        });
                    }
                })
            }
            "NODE_COORD_SECTION" | "DISPLAY_DATA_SECTION" => {
                let n = need_dim(dim, line)?;
                let vals = lx.numbers(3 * n, key)?;
                lx.end_tokens()?;
                if key == "NODE_COORD_SECTION" {
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
                    coords = Some(c);
                }
            }
            "EDGE_WEIGHT_SECTION" => {
                let n = need_dim(dim, line)?;
                let fmt = wformat.unwrap_or(WeightFormat::Full);
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
                let vals = lx.numbers(count, key)?;
                lx.end_tokens()?;
                let vals: Vec<i64> = vals
                    .iter()
                    .map(|&(x, l)| to_int(x, l))
                    .collect::<Result<_, _>>()?;
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
                matrix = Some(m);
            }
            "GTSP_SET_SECTION" => {
                let n = need_dim(dim, line)?;
                let groups = read_set_section(&mut lx, num_sets.map(|x| x.0))?;
                lx.end_tokens()?;
                let m = groups.len();
                if let Some((declared, dl)) = num_sets
                    && declared != m
                {
                    return Err(TsplibError::BadDimension {
                        line: dl,
                        msg: format!("GTSP_SETS is {declared} but {m} sets are listed"),
                    });
                }
                sets = Some((check_sets(groups, n, m)?, line));
            }
            _ => {
                return Err(TsplibError::Syntax {
                    line,
                    msg: format!("unknown keyword '{key}'"),
                });
            }
        }
    }

    let end = lx.last_line();
    let Some((n, _)) = dim else {
        return Err(TsplibError::Missing {
            line: end,
            what: "DIMENSION".into(),
        });
    };
    let data = match (wtype, matrix) {
        (_, Some(m)) => m,
        (Some(WeightType::Explicit), None) | (None, None) => {
            return Err(TsplibError::Missing {
                line: end,
                what: "EDGE_WEIGHT_SECTION".into(),
            });
        }
        (Some(kind), None) => {
            let Some(c) = coords else {
                return Err(TsplibError::Missing {
                    line: end,
                    what: "NODE_COORD_SECTION".into(),
                });
            };
            let mut m = vec![0i64; n * n];
            for i in 0..n {
                for j in 0..n {
                    if i != j {
                        m[i * n + j] = coord_distance(kind, c[i], c[j]);
                    }
                }
            }
            m
        }
    };
    let mut dist = CostMatrix::new(n, data);
    for i in 0..n {
        dist.set(i, i, 0);
    }
    let sets = match sets {
        Some((s, _)) => s,
        None => {
            if let Some((_, l)) = num_sets {
                return Err(TsplibError::Missing {
                    line: l,
                    what: "GTSP_SET_SECTION".into(),
                });
            }
            (0..n).map(|v| vec![v]).collect()
        }
    };
    let symmetric = dist.is_symmetric();
    Ok(Instance {
        name,
        n,
        sets,
        dist,
        symmetric,
    })
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

/// Parses a TSPLIB tour file (`TOUR_SECTION`, 1-based vertices, ended by
/// `-1` or `EOF`) and returns 0-based vertices.
pub fn parse_tour(text: &str) -> Result<Vec<usize>, TsplibError> {
    let mut lx = Lexer::new(text);
    while let Some((l, line)) = lx.line() {
        let (key, _) = split_header(l);
        if key == "TOUR_SECTION" {
            let mut tour = Vec::new();
            while let Some((t, l)) = lx.token() {
                if t == "-1" || t == "EOF" {
                    return Ok(tour);
                }
                let v = t.parse::<usize>().map_err(|_| TsplibError::Syntax {
                    line: l,
                    msg: format!("'{t}' is not a vertex number"),
                })?;
                if v == 0 {
                    return Err(TsplibError::Syntax {
                        line: l,
                        msg: "vertex 0 in a 1-based tour".into(),
                    });
                }
                tour.push(v - 1);
            }
            return Ok(tour);
        }
        if key == "EOF" {
            break;
        }
        let _ = line;
    }
    Err(TsplibError::Missing {
        line: lx.last_line(),
        what: "TOUR_SECTION".into(),
    })
}

/// Reads a tour file from disk; see [`parse_tour`].
pub fn read_tour_file(path: impl AsRef<Path>) -> Result<Vec<usize>, TsplibError> {
    let path = path.as_ref();
    let text = std::fs::read_to_string(path).map_err(|source| TsplibError::Io {
        path: path.display().to_string(),
        source,
    })?;
    parse_tour(&text)
}
