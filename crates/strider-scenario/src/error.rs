//! Errors of scenario loading, saving and generation: each names the file and says what is wrong
//! in one line.

use std::path::PathBuf;

/// Why a scenario could not be loaded, saved or generated.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum ScenarioError {
    /// A file could not be read.
    #[error("{}: cannot read: {source}", path.display())]
    Read {
        /// The file.
        path: PathBuf,
        /// The I/O error.
        source: std::io::Error,
    },
    /// A file could not be written.
    #[error("{}: cannot write: {source}", path.display())]
    Write {
        /// The file.
        path: PathBuf,
        /// The I/O error.
        source: std::io::Error,
    },
    /// A file named by the scenario does not exist.
    #[error("{}: file not found ({what})", path.display())]
    MissingFile {
        /// The missing file.
        path: PathBuf,
        /// Which role the file plays (e.g. "elevation layer named in \[world\]").
        what: String,
    },
    /// The scenario TOML is malformed or has wrong/unknown keys.
    #[error("{}:{line}:{column}: {message}", path.display())]
    Toml {
        /// The TOML file.
        path: PathBuf,
        /// 1-based line of the problem.
        line: usize,
        /// 1-based column (in characters) of the problem.
        column: usize,
        /// What the parser says.
        message: String,
    },
    /// A PNG layer has the wrong bit depth or colour type.
    #[error("{}: expected {expected}, found {found}", path.display())]
    PngFormat {
        /// The PNG file.
        path: PathBuf,
        /// What the layer must be (e.g. "16-bit grayscale").
        expected: String,
        /// What the file is (e.g. "8-bit RGB").
        found: String,
    },
    /// A PNG layer could not be decoded or encoded.
    #[error("{}: invalid PNG: {message}", path.display())]
    Png {
        /// The PNG file.
        path: PathBuf,
        /// What the PNG codec says.
        message: String,
    },
    /// Two layers differ in size.
    #[error(
        "{}: size {width}×{height} differs from {} ({ref_width}×{ref_height})",
        path.display(),
        reference.display()
    )]
    SizeMismatch {
        /// The offending layer.
        path: PathBuf,
        /// Its width.
        width: u32,
        /// Its height.
        height: u32,
        /// The layer it was compared with (the colour layer).
        reference: PathBuf,
        /// The reference width.
        ref_width: u32,
        /// The reference height.
        ref_height: u32,
    },
    /// The terrain layer uses an index that the terrain table does not define.
    #[error(
        "{}: terrain index {index} is not in the [[terrain]] table (first at pixel column {x}, row {y} from the top; {count} pixels)",
        path.display()
    )]
    UnknownTerrainIndex {
        /// The terrain layer.
        path: PathBuf,
        /// The undefined index.
        index: u8,
        /// Pixel column of its first occurrence.
        x: u32,
        /// Pixel row (from the top of the image) of its first occurrence.
        y: u32,
        /// How many pixels carry it.
        count: usize,
    },
    /// A parameter is outside its allowed range (or a layer is larger than the limits allow).
    #[error("{}: {source}", path.display())]
    Param {
        /// The scenario file (or the layer file, or `<name>` for a generated scenario).
        path: PathBuf,
        /// Which key, its value and what is allowed.
        source: strider_map::ParamError,
    },
    /// A value of the scenario is invalid (out of range, inconsistent, unknown name).
    #[error("{}: {message}", path.display())]
    Invalid {
        /// The scenario file (or `<name>` for a generated scenario).
        path: PathBuf,
        /// What is wrong, naming the key.
        message: String,
    },
    /// A name is neither a built-in scenario nor (for [`crate::Scenario::from_name_or_file`]) an
    /// existing file.
    #[error("unknown scenario '{name}'{note}; built-in scenarios: {valid}")]
    UnknownBuiltin {
        /// The name asked for.
        name: String,
        /// Extra explanation (e.g. ", and no such file").
        note: String,
        /// The valid names, comma-separated.
        valid: String,
    },
    /// A procedural generator failed to produce a valid layout (a bug, not an input error).
    #[error("generator '{name}' (world seed {seed}): {message}")]
    Generate {
        /// The built-in scenario.
        name: String,
        /// The world seed.
        seed: u64,
        /// What failed.
        message: String,
    },
}

impl ScenarioError {
    /// An [`ScenarioError::Invalid`] for `path`.
    pub(crate) fn invalid(path: impl Into<PathBuf>, message: impl Into<String>) -> Self {
        Self::Invalid {
            path: path.into(),
            message: message.into(),
        }
    }
}
