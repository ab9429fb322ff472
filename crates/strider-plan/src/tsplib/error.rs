//! The reader's error type.

use thiserror::Error;

use crate::memory::MemoryError;

/// Errors of the TSPLIB reader. Line numbers are 1-based; vertex and set
/// numbers are the file's (1-based) numbers.
#[derive(Debug, Error)]
pub enum TsplibError {
    /// The file could not be read.
    #[error("cannot read {}: {source}", strider_core::text::one_line(.path))]
    Io {
        /// The path.
        path: String,
        /// The I/O error.
        source: std::io::Error,
    },
    /// The file is larger than [`super::MAX_FILE_BYTES`].
    #[error(
        "{} is {bytes} bytes, more than the reader's limit of {limit} bytes (MAX_FILE_BYTES)",
        strider_core::text::one_line(.path)
    )]
    FileTooLarge {
        /// The path.
        path: String,
        /// Its size.
        bytes: u64,
        /// [`super::MAX_FILE_BYTES`].
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
    /// Malformed line or value.
    #[error("line {line}: {}", strider_core::text::one_line(.msg))]
    Syntax {
        /// Line number.
        line: usize,
        /// What is wrong.
        msg: String,
    },
    /// A section ended (end of file or next keyword) before all its values.
    #[error(
        "line {line}: {} is truncated: expected {expected} {unit}, found {found}",
        strider_core::text::one_line(.section)
    )]
    Truncated {
        /// Line where the data stopped.
        line: usize,
        /// The section.
        section: String,
        /// Number of values (or sets) expected.
        expected: usize,
        /// Number found.
        found: usize,
        /// What is counted: "values" or "sets".
        unit: &'static str,
    },
    /// A value after a section that already has all the values its header announced.
    #[error(
        "line {line}: extra value '{}' after the {expected} {unit} of {} ({})",
        strider_core::text::one_line(.value),
        strider_core::text::one_line(.section),
        strider_core::text::one_line(.because)
    )]
    ExtraValues {
        /// Line of the extra value.
        line: usize,
        /// The value.
        value: String,
        /// The section it follows.
        section: String,
        /// Number of values (or sets) the section holds.
        expected: usize,
        /// What is counted: "values" or "sets".
        unit: &'static str,
        /// Where that number comes from, e.g. "DIMENSION 10: 3 values per node".
        because: String,
    },
    /// `DIMENSION` or `GTSP_SETS` missing, zero, or inconsistent.
    #[error("line {line}: bad dimension: {}", strider_core::text::one_line(.msg))]
    BadDimension {
        /// Line number.
        line: usize,
        /// What is wrong.
        msg: String,
    },
    /// The declared size needs more memory than the reader may allocate.
    #[error("line {line}: {source}")]
    TooLarge {
        /// Line of the size (`DIMENSION`).
        line: usize,
        /// The refused allocation.
        source: MemoryError,
    },
    /// Costs so large that a tour's cost could overflow.
    #[error(
        "{}; with {n} vertices a tour could cost {n} times that, more than the limit \
         {limit} (MAX_TOUR_COST): scale the costs down",
        strider_core::text::one_line(.what)
    )]
    CostTooLarge {
        /// The largest cost and where it is, e.g. "arc 1 -> 2 costs 9000000000000000".
        what: String,
        /// Number of vertices.
        n: usize,
        /// [`crate::MAX_TOUR_COST`].
        limit: i64,
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
    #[error("line {line}: unsupported {}", strider_core::text::one_line(.what))]
    Unsupported {
        /// Line number.
        line: usize,
        /// What is unsupported.
        what: String,
    },
    /// A required header or section is missing.
    #[error("line {line}: missing {}", strider_core::text::one_line(.what))]
    Missing {
        /// Line number (end of file).
        line: usize,
        /// What is missing.
        what: String,
    },
}
