//! Numeric CSV tables for exact GP regression from files (`strider gp predict`): a header line,
//! then rows of finite numbers with as many fields as the header.
//!
//! The reader never panics: every bad input (text that is not UTF-8, an empty file, a header
//! without rows, ragged rows, fields that are not finite numbers, more rows or bytes than the
//! limits below) is a [`CsvError`] naming the line and field.

use std::io::Read;
use std::path::Path;

use thiserror::Error;

/// Largest CSV file read: 512 MiB. Ten million rows of a few features (the row limit) are
/// about 200 MB of text; the parsed values take at most four times the text.
pub const MAX_CSV_BYTES: u64 = 512 << 20;

/// Most data rows of one file: ten million. A prediction keeps a mean, a variance and an
/// output line per query row (about 70 bytes), so this bounds that memory at under 1 GB.
pub const MAX_ROWS: usize = 10_000_000;

/// Most training rows of an exact GP fit: 10 000. The fit stores an n × n Cholesky factor
/// (with growth room, about 1 GB at this size) and takes O(n³) time (about 3·10¹¹ operations,
/// tens of seconds); beyond it, subsample the training data.
pub const MAX_TRAIN_ROWS: usize = 10_000;

/// A numeric CSV: the column count of its header and the values, row-major.
#[derive(Clone, Debug, PartialEq)]
pub struct Table {
    /// Number of columns (fields of the header line).
    pub cols: usize,
    /// Number of data rows.
    pub rows: usize,
    /// `rows × cols` values, row-major.
    pub values: Vec<f64>,
}

/// Errors of the CSV reader. Lines and fields are 1-based.
#[derive(Debug, Error)]
pub enum CsvError {
    /// The file could not be read.
    #[error("cannot read {path}: {source}")]
    Io {
        /// The path.
        path: String,
        /// The I/O error.
        source: std::io::Error,
    },
    /// The file is larger than [`MAX_CSV_BYTES`].
    #[error("{path} is {bytes} bytes, more than the limit of {limit} bytes (MAX_CSV_BYTES)")]
    FileTooLarge {
        /// The path.
        path: String,
        /// Its size.
        bytes: u64,
        /// [`MAX_CSV_BYTES`].
        limit: u64,
    },
    /// The text is not UTF-8.
    #[error("line {line}: not UTF-8 text (invalid byte at column {column})")]
    NotUtf8 {
        /// Line of the first invalid byte.
        line: usize,
        /// Its 1-based byte column.
        column: usize,
    },
    /// No header line.
    #[error("empty file (a header line is expected)")]
    Empty,
    /// A header and no data row.
    #[error("no data rows after the header")]
    NoRows,
    /// A field that is not a number.
    #[error("line {line}: field {field} {text:?} is not a number")]
    NotANumber {
        /// Line.
        line: usize,
        /// Field.
        field: usize,
        /// Its text.
        text: String,
    },
    /// A field that is NaN or infinite.
    #[error("line {line}: field {field} is {text} (finite numbers only)")]
    NonFinite {
        /// Line.
        line: usize,
        /// Field.
        field: usize,
        /// Its text.
        text: String,
    },
    /// A row with another number of fields than the header.
    #[error("line {line}: {found} columns, the header has {expected}")]
    Columns {
        /// Line.
        line: usize,
        /// Fields of the row.
        found: usize,
        /// Fields of the header.
        expected: usize,
    },
    /// More data rows than [`MAX_ROWS`].
    #[error("line {line}: more than {limit} data rows (MAX_ROWS): split or subsample the file")]
    TooManyRows {
        /// Line of the first row beyond the limit.
        line: usize,
        /// [`MAX_ROWS`].
        limit: usize,
    },
}

/// Parses a CSV from text. Blank lines are skipped, fields are trimmed, a leading UTF-8
/// byte-order mark is skipped.
pub fn parse(text: &str) -> Result<Table, CsvError> {
    let text = text.strip_prefix('\u{feff}').unwrap_or(text);
    let mut lines = text
        .lines()
        .enumerate()
        .filter(|(_, l)| !l.trim().is_empty());
    let Some((_, header)) = lines.next() else {
        return Err(CsvError::Empty);
    };
    let cols = header.split(',').count();
    let mut values = Vec::new();
    let mut rows = 0;
    for (ln, line) in lines {
        let line_no = ln + 1;
        if rows == MAX_ROWS {
            return Err(CsvError::TooManyRows {
                line: line_no,
                limit: MAX_ROWS,
            });
        }
        let mut found = 0;
        for field in line.split(',') {
            found += 1;
            if found <= cols {
                values.push(number(field.trim(), line_no, found)?);
            }
        }
        if found != cols {
            return Err(CsvError::Columns {
                line: line_no,
                found,
                expected: cols,
            });
        }
        rows += 1;
    }
    if rows == 0 {
        return Err(CsvError::NoRows);
    }
    Ok(Table { cols, rows, values })
}

/// A finite number of field `field` on line `line`.
fn number(text: &str, line: usize, field: usize) -> Result<f64, CsvError> {
    match text.parse::<f64>() {
        Ok(v) if v.is_finite() => Ok(v),
        Ok(_) => Err(CsvError::NonFinite {
            line,
            field,
            text: text.to_string(),
        }),
        Err(_) => Err(CsvError::NotANumber {
            line,
            field,
            text: text.chars().take(40).collect(),
        }),
    }
}

/// Parses a CSV from bytes, which must be UTF-8.
pub fn parse_bytes(bytes: &[u8]) -> Result<Table, CsvError> {
    let text = std::str::from_utf8(bytes).map_err(|e| {
        let good = &bytes[..e.valid_up_to()];
        let line = good.iter().filter(|&&b| b == b'\n').count() + 1;
        let start = good.iter().rposition(|&b| b == b'\n').map_or(0, |p| p + 1);
        CsvError::NotUtf8 {
            line,
            column: good.len() - start + 1,
        }
    })?;
    parse(text)
}

/// Reads and parses a CSV file of at most [`MAX_CSV_BYTES`].
pub fn read(path: &Path) -> Result<Table, CsvError> {
    let io = |source| CsvError::Io {
        path: path.display().to_string(),
        source,
    };
    let file = std::fs::File::open(path).map_err(io)?;
    let mut bytes = Vec::new();
    file.take(MAX_CSV_BYTES + 1)
        .read_to_end(&mut bytes)
        .map_err(io)?;
    if bytes.len() as u64 > MAX_CSV_BYTES {
        return Err(CsvError::FileTooLarge {
            path: path.display().to_string(),
            bytes: std::fs::metadata(path).map_or(MAX_CSV_BYTES + 1, |m| m.len()),
            limit: MAX_CSV_BYTES,
        });
    }
    parse_bytes(&bytes)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn err(text: &str) -> String {
        parse(text).unwrap_err().to_string()
    }

    #[test]
    fn reads_header_and_rows() {
        let t = parse("\u{feff}x,y\n\n 1, 2\r\n3,4e-1\n").unwrap();
        assert_eq!(
            t,
            Table {
                cols: 2,
                rows: 2,
                values: vec![1.0, 2.0, 3.0, 0.4]
            }
        );
    }

    #[test]
    fn bad_tables_are_one_line_errors() {
        assert_eq!(err(""), "empty file (a header line is expected)");
        assert_eq!(err("\n  \n"), "empty file (a header line is expected)");
        assert_eq!(err("x,y\n"), "no data rows after the header");
        assert_eq!(err("x,y\n0,1\n1\n"), "line 3: 1 columns, the header has 2");
        assert_eq!(
            err("x,y\n0,1\n1,2,3\n"),
            "line 3: 3 columns, the header has 2"
        );
        assert_eq!(
            err("x,y\n0,nan\n"),
            "line 2: field 2 is nan (finite numbers only)"
        );
        assert_eq!(
            err("x,y\n-inf,1\n"),
            "line 2: field 1 is -inf (finite numbers only)"
        );
        assert_eq!(
            err("x,y\n1e999,1\n"),
            "line 2: field 1 is 1e999 (finite numbers only)"
        );
        assert_eq!(
            err("x,y\n1,two\n"),
            "line 2: field 2 \"two\" is not a number"
        );
        assert_eq!(err("x,y\n1,\n"), "line 2: field 2 \"\" is not a number");
        let e = parse_bytes(b"x,y\n0,1\n\xff,2\n").unwrap_err().to_string();
        assert_eq!(e, "line 3: not UTF-8 text (invalid byte at column 1)");
    }

    proptest::proptest! {
        /// Any bytes: no panic; an accepted table is rectangular and finite.
        #[test]
        fn any_bytes_give_a_table_or_an_error(
            bytes in proptest::collection::vec(
                proptest::prop_oneof![
                    proptest::sample::select(b"0123456789,.-+eE\n naif\r".to_vec()),
                    proptest::prelude::any::<u8>(),
                ],
                0..200,
            )
        ) {
            if let Ok(t) = parse_bytes(&bytes) {
                proptest::prop_assert!(t.rows >= 1 && t.cols >= 1);
                proptest::prop_assert_eq!(t.values.len(), t.rows * t.cols);
                proptest::prop_assert!(t.values.iter().all(|v| v.is_finite()));
            }
        }
    }

    #[test]
    fn rows_beyond_the_limit_are_refused() {
        // One column, so every data line is two bytes: MAX_ROWS + 1 rows is ~20 MB of text.
        let mut text = String::with_capacity(2 * MAX_ROWS + 16);
        text.push_str("y\n");
        for _ in 0..=MAX_ROWS {
            text.push_str("1\n");
        }
        match parse(&text) {
            Err(CsvError::TooManyRows { line, limit }) => {
                assert_eq!((line, limit), (MAX_ROWS + 2, MAX_ROWS));
            }
            other => panic!("unexpected {other:?}"),
        }
    }
}
