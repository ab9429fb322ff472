//! The report of a mapping-and-learning run (`strider run` with a Prágr22 strategy, `strider
//! replay`): `report.json` and the page `report.html` that shows it with its figures.

mod html;

use std::path::{Path, PathBuf};

use anyhow::Result;
use serde::Serialize;
use strider_explore::evaluate::TourResult;
use strider_explore::{Mission, TourExplorer};

use crate::io::{write_json, write_text};
pub use html::report_html;

/// Writes `report.json` and `report.html` (for `mission`'s gaits and the driven `tours`) into
/// `out`; returns the JSON's path.
pub fn write_reports(
    out: &Path,
    report: &impl Serialize,
    mission: &Mission<TourExplorer>,
    tours: &[(String, Vec<TourResult>)],
) -> Result<PathBuf> {
    let path = out.join("report.json");
    write_json(&path, report)?;
    let gait_names: Vec<String> = mission
        .strategy()
        .params()
        .gaits
        .iter()
        .map(|g| g.name.clone())
        .collect();
    let value = serde_json::to_value(report)?;
    write_text(
        &out.join("report.html"),
        &report_html(&value, &gait_names, tours),
    )?;
    Ok(path)
}
