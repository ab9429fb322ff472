//! The report of a mapping-and-learning run (`strider run` with a Prágr22 strategy, `strider
//! replay`): `report.json` and the page `report.html` that shows it with its figures.

mod figure;
mod html;

use std::path::{Path, PathBuf};

use anyhow::Result;
use serde::Serialize;
use strider_explore::evaluate::TourResult;

use crate::io::{write_json, write_text};
pub use figure::{Extent, Key, MapFigure};
pub use html::report_html;

/// Writes `report.json` and `report.html` (with the `figures` written beside them and the
/// driven `tours`) into `out`; returns the JSON's path.
pub fn write_reports(
    out: &Path,
    report: &impl Serialize,
    figures: &[MapFigure],
    tours: &[(String, Vec<TourResult>)],
) -> Result<PathBuf> {
    let path = out.join("report.json");
    write_json(&path, report)?;
    let value = serde_json::to_value(report)?;
    write_text(
        &out.join("report.html"),
        &report_html(&value, figures, tours),
    )?;
    Ok(path)
}
