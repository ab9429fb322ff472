//! The built-in scenarios (docs/guide.md, "Scenarios and your own world"), generated procedurally from a world seed.
//!
//! Each world is a function of `world_seed: u64`: seed 1 is "the" world of the paper, other seeds
//! give a random family with the same terrain types and rules, so strategies can be compared over
//! many worlds. Generation is deterministic (ChaCha8 seeded with the world seed). Every generator
//! checks its own invariants (start and waypoints admissible on the ground truth, connectivity
//! where promised) and re-draws the layout when a draw violates them.
//!
//! To get an editable copy: [`generate`] then [`crate::Scenario::save`].
//!
//! Each world's module describes what is special about it; `builder` holds what they share
//! (the attempt loop and the scenario around a layout), `canvas` the painter, `terrains`
//! the terrain table with its looks, `placement` the ground-truth checks of a layout,
//! `draw` shared random draws and `strategy` the `[strategy]` sections.

mod bonn_paths;
mod builder;
mod campus;
mod canvas;
mod cot_track;
mod courtyard;
mod courtyard_large;
pub mod courtyard_small;
mod draw;
mod energy_arena;
mod escape_arena;
mod lab_track;
mod placement;
mod strategy;
mod terrains;

use crate::error::ScenarioError;
use crate::model::Scenario;

/// One built-in scenario: name, description, generator.
struct Entry {
    name: &'static str,
    description: &'static str,
    generate: fn(u64) -> Result<Scenario, ScenarioError>,
}

const ENTRIES: [Entry; 9] = [
    Entry {
        name: "courtyard-small",
        description: courtyard_small::DESCRIPTION,
        generate: courtyard_small::generate,
    },
    Entry {
        name: "courtyard-large",
        description: courtyard_large::DESCRIPTION,
        generate: courtyard_large::generate,
    },
    Entry {
        name: "lab-track",
        description: lab_track::DESCRIPTION,
        generate: lab_track::generate,
    },
    Entry {
        name: "lab-track-large",
        description: lab_track::DESCRIPTION_LARGE,
        generate: lab_track::generate_large,
    },
    Entry {
        name: "escape-arena",
        description: escape_arena::DESCRIPTION,
        generate: escape_arena::generate,
    },
    Entry {
        name: "energy-arena",
        description: energy_arena::DESCRIPTION,
        generate: energy_arena::generate,
    },
    Entry {
        name: "bonn-paths",
        description: bonn_paths::DESCRIPTION,
        generate: bonn_paths::generate,
    },
    Entry {
        name: "cot-track",
        description: cot_track::DESCRIPTION,
        generate: cot_track::generate,
    },
    Entry {
        name: "campus",
        description: campus::DESCRIPTION,
        generate: campus::generate,
    },
];

const NAMES: [&str; 9] = [
    ENTRIES[0].name,
    ENTRIES[1].name,
    ENTRIES[2].name,
    ENTRIES[3].name,
    ENTRIES[4].name,
    ENTRIES[5].name,
    ENTRIES[6].name,
    ENTRIES[7].name,
    ENTRIES[8].name,
];

/// Names of the built-in scenarios.
pub fn names() -> &'static [&'static str] {
    &NAMES
}

/// One-paragraph description of built-in scenario `name`, if it exists.
pub fn describe(name: &str) -> Option<&'static str> {
    ENTRIES
        .iter()
        .find(|e| e.name == name)
        .map(|e| e.description)
}

/// Generates built-in scenario `name` for `world_seed`. Unknown names give an error listing the
/// valid ones.
pub fn generate(name: &str, world_seed: u64) -> Result<Scenario, ScenarioError> {
    let entry = ENTRIES
        .iter()
        .find(|e| e.name == name)
        .ok_or_else(|| unknown(name, ""))?;
    (entry.generate)(world_seed)
}

pub(crate) fn unknown(name: &str, note: &str) -> ScenarioError {
    ScenarioError::UnknownBuiltin {
        name: name.to_string(),
        note: note.to_string(),
        valid: NAMES.join(", "),
    }
}
