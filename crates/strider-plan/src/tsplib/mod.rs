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
//! Files: `lexer` (the line and token cursor), `header` (header lines and their values),
//! `sections` (coordinates, edge weights, sets), `distance` (TSPLIB's distance functions). The
//! instance they produce is the solver's [`Instance`], re-exported here.

mod distance;
mod header;
mod lexer;
mod sections;

use std::path::Path;

use thiserror::Error;

pub use crate::gtsp::{CostMatrix, Instance, InstanceError};
pub use distance::tsplib_distance;

use header::{WeightFormat, WeightType, check_type, positive_count, split_header};
use lexer::Lexer;

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
    let mut file = InstanceFile::default();
    while let Some((l, line)) = lx.line() {
        let (key, value) = split_header(l);
        match key {
            "EOF" => break,
            "NAME" => file.name = value.to_string(),
            "COMMENT" | "NODE_COORD_TYPE" | "DISPLAY_DATA_TYPE" | "CAPACITY" => {}
            "TYPE" => check_type(value, line)?,
            "DIMENSION" | "N" => {
                let d = positive_count(value, line, "DIMENSION")?;
                if key == "N" {
                    file.compact = true;
                }
                file.dim = Some((d, line));
            }
            "GTSP_SETS" | "M" => {
                let m = positive_count(value, line, "GTSP_SETS")?;
                file.num_sets = Some((m, line));
                if file.compact {
                    let n = file.need_dim(line)?;
                    let (sets, matrix) = sections::read_compact(&mut lx, n, m, line)?;
                    file.sets = Some((sets, line));
                    file.matrix = Some(matrix);
                }
            }
            "EDGE_WEIGHT_TYPE" => file.wtype = Some(WeightType::parse(value, line)?),
            "EDGE_WEIGHT_FORMAT" => file.wformat = Some(WeightFormat::parse(value, line)?),
            "NODE_COORD_SECTION" | "DISPLAY_DATA_SECTION" => {
                let n = file.need_dim(line)?;
                if let Some(c) = sections::read_coordinates(&mut lx, n, key)? {
                    file.coords = Some(c);
                }
            }
            "EDGE_WEIGHT_SECTION" => {
                let n = file.need_dim(line)?;
                let fmt = file.wformat.unwrap_or(WeightFormat::Full);
                file.matrix = Some(sections::read_edge_weights(&mut lx, n, fmt, line)?);
            }
            "GTSP_SET_SECTION" => {
                let n = file.need_dim(line)?;
                let sets = sections::read_gtsp_sets(&mut lx, n, file.num_sets)?;
                file.sets = Some((sets, line));
            }
            _ => {
                return Err(TsplibError::Syntax {
                    line,
                    msg: format!("unknown keyword '{key}'"),
                });
            }
        }
    }
    file.into_instance(lx.last_line())
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
}

impl InstanceFile {
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
    /// from the coordinates, with a zero diagonal; singleton sets for a plain TSP.
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
                distance::coordinate_matrix(kind, &c, n)
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
        Ok(Instance {
            name: self.name,
            n,
            sets,
            dist,
            symmetric,
        })
    }
}

/// Parses a TSPLIB tour file (`TOUR_SECTION`, 1-based vertices, ended by
/// `-1` or `EOF`) and returns 0-based vertices.
pub fn parse_tour(text: &str) -> Result<Vec<usize>, TsplibError> {
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
    let path = path.as_ref();
    let text = std::fs::read_to_string(path).map_err(|source| TsplibError::Io {
        path: path.display().to_string(),
        source,
    })?;
    parse_tour(&text)
}
