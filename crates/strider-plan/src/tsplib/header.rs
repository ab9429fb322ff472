//! Header lines: `KEY : value` in its variants, and the values of `TYPE`, `DIMENSION`,
//! `GTSP_SETS`, `EDGE_WEIGHT_TYPE` and `EDGE_WEIGHT_FORMAT`.

use super::TsplibError;
use crate::memory;

/// `EDGE_WEIGHT_TYPE`: a distance computed from coordinates, or explicit weights.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum WeightType {
    Euc2d,
    Ceil2d,
    Geo,
    Att,
    Explicit,
}

impl WeightType {
    /// The type of a TSPLIB name; `None` for names this reader does not support.
    pub(super) fn from_name(name: &str) -> Option<WeightType> {
        Some(match name {
            "EUC_2D" => WeightType::Euc2d,
            "CEIL_2D" => WeightType::Ceil2d,
            "GEO" => WeightType::Geo,
            "ATT" => WeightType::Att,
            "EXPLICIT" => WeightType::Explicit,
            _ => return None,
        })
    }

    /// The TSPLIB name.
    pub(super) fn name(self) -> &'static str {
        match self {
            WeightType::Euc2d => "EUC_2D",
            WeightType::Ceil2d => "CEIL_2D",
            WeightType::Geo => "GEO",
            WeightType::Att => "ATT",
            WeightType::Explicit => "EXPLICIT",
        }
    }

    /// The value of an `EDGE_WEIGHT_TYPE` line.
    pub(super) fn parse(value: &str, line: usize) -> Result<WeightType, TsplibError> {
        WeightType::from_name(value).ok_or_else(|| TsplibError::Unsupported {
            line,
            what: format!("EDGE_WEIGHT_TYPE '{value}'"),
        })
    }
}

/// `EDGE_WEIGHT_FORMAT`: how `EDGE_WEIGHT_SECTION` lists the matrix. A `*_COL` format lists the
/// same numbers as the `*_ROW` format of the other triangle.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum WeightFormat {
    Function,
    Full,
    UpperRow,
    LowerRow,
    UpperDiagRow,
    LowerDiagRow,
}

impl WeightFormat {
    /// The TSPLIB name (of the `*_ROW` variant).
    pub(super) fn name(self) -> &'static str {
        match self {
            WeightFormat::Function => "FUNCTION",
            WeightFormat::Full => "FULL_MATRIX",
            WeightFormat::UpperRow => "UPPER_ROW",
            WeightFormat::LowerRow => "LOWER_ROW",
            WeightFormat::UpperDiagRow => "UPPER_DIAG_ROW",
            WeightFormat::LowerDiagRow => "LOWER_DIAG_ROW",
        }
    }

    /// The value of an `EDGE_WEIGHT_FORMAT` line.
    pub(super) fn parse(value: &str, line: usize) -> Result<WeightFormat, TsplibError> {
        Ok(match value {
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
}

/// Splits a header line into its key and value, accepting `KEY : v`,
/// `KEY: v`, `KEY  v` and `KEY:` forms.
pub(super) fn split_header(line: &str) -> (&str, &str) {
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
    tok.parse::<usize>().map_err(|e| TsplibError::BadDimension {
        line,
        msg: match e.kind() {
            std::num::IntErrorKind::PosOverflow => {
                format!("{what} {tok} is too large (at most {})", usize::MAX)
            }
            _ => format!("{what} '{value}' is not a non-negative integer"),
        },
    })
}

/// Checks, when `DIMENSION` is read, that the n × n cost matrix every instance becomes fits
/// the memory budget, so that no section allocates for a size the reader would refuse.
pub(super) fn check_matrix_size(n: usize, line: usize) -> Result<(), TsplibError> {
    let bytes = (n as u64)
        .checked_mul(n as u64)
        .and_then(|c| memory::bytes_of(c, 8));
    let max_n = (memory::MEMORY_LIMIT_BYTES / 8).isqrt();
    memory::check(
        bytes,
        &format!("DIMENSION {n}: a {n} × {n} cost matrix"),
        &format!(
            "cost matrices are dense: use an instance of at most {max_n} vertices (the solver \
             takes at most {})",
            crate::gtsp::max_solver_vertices()
        ),
    )
    .map_err(|source| TsplibError::TooLarge { line, source })
}

/// A positive count (`DIMENSION`, `GTSP_SETS`; `what` names it in errors).
pub(super) fn positive_count(value: &str, line: usize, what: &str) -> Result<usize, TsplibError> {
    let count = parse_usize(value, line, what)?;
    if count == 0 {
        return Err(TsplibError::BadDimension {
            line,
            msg: format!("{what} is 0"),
        });
    }
    Ok(count)
}

/// Checks a `TYPE` value: `TSP`, `ATSP`, `GTSP` or `AGTSP`, trailing text ignored.
pub(super) fn check_type(value: &str, line: usize) -> Result<(), TsplibError> {
    match value.split_whitespace().next().unwrap_or("") {
        "TSP" | "ATSP" | "GTSP" | "AGTSP" => Ok(()),
        _ => Err(TsplibError::Unsupported {
            line,
            what: format!("TYPE '{value}'"),
        }),
    }
}
