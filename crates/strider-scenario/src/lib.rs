//! # strider-scenario
//!
//! Scenarios: what the simulator simulates and what a mission is asked to do. A [`Scenario`] is
//! a world (co-registered colour, elevation and terrain-type layers on the global cell lattice,
//! plus a terrain table giving each terrain's per-gait response), a robot profile (gaits,
//! sensors, footprint), the map, simulator and strategy parameters, a start pose, exploration
//! bounds and benchmark tours.
//!
//! * [`model`]: the in-memory data model.
//! * [`format`](mod@format): the file format (TOML naming PNG layers), [`Scenario::load`],
//!   [`Scenario::from_toml_str`] and [`Scenario::save`].
//! * [`profiles`]: the built-in robot profiles.
//! * [`builtin`]: the procedurally generated built-in worlds (and `cot-track`, Prágr18)
//!   and their registry.
//! * [`layers`]: where the PNG layers come from (files or memory).
//! * [`validate`](mod@validate): the checks of every part of a scenario and the documented
//!   limits they enforce.
//! * [`ground_truth`]: flood fill and nearest-cell queries over ground-truth admissibility
//!   ([`World::gt_admissible`] applies `strider_map`'s passability rule to the true elevation).
//!
//! Everything here is simulator truth: the autonomy stack sees the world only through the
//! simulated sensors.

pub mod builtin;
pub mod error;
pub mod format;
pub mod ground_truth;
pub mod layers;
pub mod model;
mod png_io;
pub mod profiles;
pub mod validate;

pub use error::ScenarioError;
pub use layers::{LayerDir, LayerSource};
pub use model::*;

impl Scenario {
    /// A built-in scenario by name (generated with `world_seed`), or else a scenario file or
    /// directory at path `arg` (the seed is then ignored).
    pub fn from_name_or_file(arg: &str, world_seed: u64) -> Result<Scenario, ScenarioError> {
        if builtin::describe(arg).is_some() {
            return builtin::generate(arg, world_seed);
        }
        let path = std::path::Path::new(arg);
        if path.exists() {
            return Scenario::load(path);
        }
        Err(builtin::unknown(arg, " (not a built-in, and no such file)"))
    }
}
