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
//!
//! Bad input of any kind (sizes beyond [`crate::MEMORY_LIMIT_BYTES`], costs whose tour sums
//! could pass [`crate::MAX_TOUR_COST`], negative off-diagonal weights, stray values, bytes that
//! are not UTF-8) is a [`TsplibError`] naming the line; the readers never panic.
//!
//! Files: `error` (the error type), `lexer` (the line and token cursor), `header` (header lines
//! and their values),
//! `sections` (coordinates, edge weights, sets), `distance` (TSPLIB's distance functions). The
//! instance they produce is the solver's [`Instance`], re-exported here.

mod distance;
mod error;
mod header;
mod lexer;
mod sections;

use std::io::Read;
use std::path::Path;

pub use crate::gtsp::{CostMatrix, Instance, InstanceError};
pub use distance::tsplib_distance;
pub use error::TsplibError;

use header::{
    WeightFormat, WeightType, check_matrix_size, check_type, positive_count, split_header,
};
use lexer::{Lexer, looks_numeric};

/// Largest instance or tour file the reader reads: 2 GiB. The reader holds the whole text
/// and the matrix at once; the largest explicit matrix the solver takes (about 12 000
/// vertices, see [`crate::MEMORY_LIMIT_BYTES`]) is about 1 GB of text.
pub const MAX_FILE_BYTES: u64 = 2 << 30;

/// Reads a file of at most [`MAX_FILE_BYTES`].
fn read_bytes(path: &Path) -> Result<Vec<u8>, TsplibError> {
    let io = |source| TsplibError::Io {
        path: path.display().to_string(),
        source,
    };
    let file = std::fs::File::open(path).map_err(io)?;
    let mut bytes = Vec::new();
    file.take(MAX_FILE_BYTES + 1)
        .read_to_end(&mut bytes)
        .map_err(io)?;
    if bytes.len() as u64 > MAX_FILE_BYTES {
        let size = std::fs::metadata(path).map_or(MAX_FILE_BYTES + 1, |m| m.len());
        return Err(TsplibError::FileTooLarge {
            path: path.display().to_string(),
            bytes: size,
            limit: MAX_FILE_BYTES,
        });
    }
    Ok(bytes)
}

/// The text of `bytes`, or the line and column of the first byte that is not UTF-8.
fn utf8(bytes: &[u8]) -> Result<&str, TsplibError> {
    std::str::from_utf8(bytes).map_err(|e| {
        let good = &bytes[..e.valid_up_to()];
        let line = good.iter().filter(|&&b| b == b'\n').count() + 1;
        let column = good.len() - good.iter().rposition(|&b| b == b'\n').map_or(0, |p| p + 1) + 1;
        TsplibError::NotUtf8 { line, column }
    })
}

/// Reads an instance file from disk. The instance name defaults to the file
/// stem when the file has no `NAME`.
pub fn read_instance_file(path: impl AsRef<Path>) -> Result<Instance, TsplibError> {
    let path = path.as_ref();
    let mut inst = parse_bytes(&read_bytes(path)?)?;
    if inst.name.is_empty() {
        inst.name = path
            .file_stem()
            .map(|s| s.to_string_lossy().into_owned())
            .unwrap_or_default();
    }
    Ok(inst)
}

/// Parses an instance from raw bytes (which must be UTF-8). Never panics; every bad input is a
/// [`TsplibError`].
pub fn parse_bytes(bytes: &[u8]) -> Result<Instance, TsplibError> {
    parse_instance(utf8(bytes)?)
}

/// Parses a TSPLIB / GTSPLIB (or GLNS compact) instance from text. A leading UTF-8 byte-order
/// mark is skipped. Never panics; every bad input is a [`TsplibError`].
pub fn parse_instance(text: &str) -> Result<Instance, TsplibError> {
    let text = text.strip_prefix('\u{feff}').unwrap_or(text);
    let mut lx = Lexer::new(text);
    let mut file = InstanceFile::default();
    while let Some((l, line)) = lx.line() {
        let (key, value) = split_header(l);
        let after = file.section_end.take();
        match key {
            "EOF" => break,
            "NAME" => file.name = value.to_string(),
            "COMMENT" | "NODE_COORD_TYPE" | "DISPLAY_DATA_TYPE" | "CAPACITY" => {}
            "TYPE" => check_type(value, line)?,
            "DIMENSION" | "N" => file.set_dim(key, value, line)?,
            "GTSP_SETS" | "M" => {
                let m = positive_count(value, line, "GTSP_SETS")?;
                file.num_sets = Some((m, line));
                if file.compact {
                    let n = file.need_dim(line)?;
                    let (sets, matrix) = sections::read_compact(&mut lx, n, m, line)?;
                    file.sets = Some((sets, line));
                    file.matrix = Some(matrix);
                    file.ended(
                        "matrix",
                        n * n,
                        "values",
                        format!("N {n}: a {n} × {n} matrix"),
                    );
                }
            }
            "EDGE_WEIGHT_TYPE" => file.wtype = Some(WeightType::parse(value, line)?),
            "EDGE_WEIGHT_FORMAT" => file.wformat = Some(WeightFormat::parse(value, line)?),
            "NODE_COORD_SECTION" | "DISPLAY_DATA_SECTION" => {
                let n = file.need_dim(line)?;
                if let Some(c) = sections::read_coordinates(&mut lx, n, key, line)? {
                    file.coords = Some(c);
                }
                let because = format!("DIMENSION {n}: 3 values per node");
                file.ended(key, n.saturating_mul(3), "values", because);
            }
            "EDGE_WEIGHT_SECTION" => {
                let n = file.need_dim(line)?;
                let fmt = file.wformat.unwrap_or(WeightFormat::Full);
                file.matrix = Some(sections::read_edge_weights(&mut lx, n, fmt, line)?);
                let count = sections::weight_count(n, fmt).unwrap_or(usize::MAX);
                file.ended(
                    key,
                    count,
                    "values",
                    format!("DIMENSION {n} in {}", fmt.name()),
                );
            }
            "GTSP_SET_SECTION" => {
                let n = file.need_dim(line)?;
                let sets = sections::read_gtsp_sets(&mut lx, n, file.num_sets)?;
                let because = format!("GTSP_SETS {}", sets.len());
                file.ended(key, sets.len(), "sets", because);
                file.sets = Some((sets, line));
            }
            _ => return Err(unexpected_line(l, key, line, after)),
        }
    }
    file.into_instance(lx.last_line())
}

/// Where the last data section ended: what a stray value after it is reported against.
struct SectionEnd {
    section: String,
    expected: usize,
    unit: &'static str,
    because: String,
}

/// The error of a line that is not a known keyword: an extra value when it follows a data
/// section, else an unknown keyword or stray text.
fn unexpected_line(l: &str, key: &str, line: usize, after: Option<SectionEnd>) -> TsplibError {
    let first = l.split_whitespace().next().unwrap_or("");
    if looks_numeric(l) {
        return match after {
            Some(e) => TsplibError::ExtraValues {
                line,
                value: first.to_string(),
                section: e.section,
                expected: e.expected,
                unit: e.unit,
                because: e.because,
            },
            None => TsplibError::Syntax {
                line,
                msg: format!("value '{first}' outside any section"),
            },
        };
    }
    let msg = if key.is_empty() {
        let shown: String = l.chars().take(40).collect();
        format!("unexpected text '{shown}' (not a TSPLIB keyword)")
    } else {
        format!("unknown keyword '{key}'")
    };
    TsplibError::Syntax { line, msg }
}

/// What an instance file has said so far; the lines of values are kept for errors.
#[derive(Default)]
struct InstanceFile {
    name: String,
    /// `DIMENSION` and its line.
    dim: Option<(usize, usize)>,
    /// `GTSP_SETS` and its line.
    num_sets: Option<(usize, usize)>,
    wtype: Option<WeightType>,
    wformat: Option<WeightFormat>,
    coords: Option<Vec<(f64, f64)>>,
    matrix: Option<Vec<i64>>,
    /// The sets and the line of their section.
    sets: Option<(Vec<Vec<usize>>, usize)>,
    /// GLNS's compact format (`N:` instead of `DIMENSION`).
    compact: bool,
    /// The data section just read, if the last line was one.
    section_end: Option<SectionEnd>,
}

impl InstanceFile {
    /// `DIMENSION` (or `N`, `key`) at `line`: once per file, and small enough for its matrix.
    fn set_dim(&mut self, key: &str, value: &str, line: usize) -> Result<(), TsplibError> {
        let d = positive_count(value, line, "DIMENSION")?;
        if let Some((_, first)) = self.dim {
            return Err(TsplibError::BadDimension {
                line,
                msg: format!("DIMENSION given twice (first on line {first})"),
            });
        }
        check_matrix_size(d, line)?;
        if key == "N" {
            self.compact = true;
        }
        self.dim = Some((d, line));
        Ok(())
    }

    /// Records that data section `section` of `expected` `unit` just ended.
    fn ended(&mut self, section: &str, expected: usize, unit: &'static str, because: String) {
        self.section_end = Some(SectionEnd {
            section: section.to_string(),
            expected,
            unit,
            because,
        });
    }

    /// The dimension, needed by a section at `line`.
    fn need_dim(&self, line: usize) -> Result<usize, TsplibError> {
        match self.dim {
            Some((d, _)) => Ok(d),
            None => Err(TsplibError::BadDimension {
                line,
                msg: "section before DIMENSION".into(),
            }),
        }
    }

    /// The instance, once the file (of `end` lines) is read: the matrix as listed or computed
    /// from the coordinates, with a zero diagonal; singleton sets for a plain TSP. Refused when
    /// a tour's cost could overflow.
    fn into_instance(self, end: usize) -> Result<Instance, TsplibError> {
        let Some((n, _)) = self.dim else {
            return Err(TsplibError::Missing {
                line: end,
                what: "DIMENSION".into(),
            });
        };
        let data = match (self.wtype, self.matrix) {
            (_, Some(m)) => m,
            (Some(WeightType::Explicit), None) | (None, None) => {
                return Err(TsplibError::Missing {
                    line: end,
                    what: "EDGE_WEIGHT_SECTION".into(),
                });
            }
            (Some(kind), None) => {
                let Some(c) = self.coords else {
                    return Err(TsplibError::Missing {
                        line: end,
                        what: "NODE_COORD_SECTION".into(),
                    });
                };
                distance::coordinate_matrix(kind, &c, n)?
            }
        };
        let mut dist = CostMatrix::new(n, data);
        for i in 0..n {
            dist.set(i, i, 0);
        }
        let sets = match self.sets {
            Some((s, _)) => s,
            None => {
                if let Some((_, l)) = self.num_sets {
                    return Err(TsplibError::Missing {
                        line: l,
                        what: "GTSP_SET_SECTION".into(),
                    });
                }
                (0..n).map(|v| vec![v]).collect()
            }
        };
        let symmetric = dist.is_symmetric();
        let inst = Instance {
            name: self.name,
            n,
            sets,
            dist,
            symmetric,
        };
        match inst.check_costs() {
            Err(InstanceError::CostTooLarge {
                from,
                to,
                cost,
                n,
                limit,
            }) => Err(TsplibError::CostTooLarge {
                what: format!("arc {} -> {} costs {cost}", from + 1, to + 1),
                n,
                limit,
            }),
            Err(e) => Err(TsplibError::Syntax {
                line: end,
                msg: e.to_string(),
            }),
            Ok(()) => Ok(inst),
        }
    }
}

/// Parses a TSPLIB tour file (`TOUR_SECTION`, 1-based vertices, ended by
/// `-1` or `EOF`) and returns 0-based vertices.
pub fn parse_tour(text: &str) -> Result<Vec<usize>, TsplibError> {
    let text = text.strip_prefix('\u{feff}').unwrap_or(text);
    let mut lx = Lexer::new(text);
    while let Some((l, _)) = lx.line() {
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
    }
    Err(TsplibError::Missing {
        line: lx.last_line(),
        what: "TOUR_SECTION".into(),
    })
}

/// Reads a tour file from disk; see [`parse_tour`].
pub fn read_tour_file(path: impl AsRef<Path>) -> Result<Vec<usize>, TsplibError> {
    let bytes = read_bytes(path.as_ref())?;
    parse_tour(utf8(&bytes)?)
}
