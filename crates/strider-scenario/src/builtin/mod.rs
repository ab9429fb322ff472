//! The built-in scenarios (SCENARIOS.md "Worlds"), generated procedurally from a world seed.
//!
//! Each world is a function of `world_seed: u64`: seed 1 is "the" world of the paper, other seeds
//! give a random family with the same terrain types and rules, so strategies can be compared over
//! many worlds. Generation is deterministic (ChaCha8 seeded with the world seed). Every generator
//! checks its own invariants (start and waypoints admissible on the ground truth, connectivity
//! where promised) and re-draws the layout when a draw violates them.
//!
//! To get an editable copy: [`generate`] then [`crate::Scenario::save`].

mod bonn_paths;
mod canvas;
mod cot_track;
mod courtyard_large;
mod courtyard_small;
mod energy_arena;
mod escape_arena;
mod lab_track;

use rand::{RngExt, rngs::ChaCha8Rng};
use strider_core::Point2;

use crate::error::ScenarioError;
use crate::ground_truth::nearest_in_mask;
use crate::model::{Scenario, World};

/// One built-in scenario: name, description, generator.
struct Entry {
    name: &'static str,
    description: &'static str,
    generate: fn(u64) -> Result<Scenario, ScenarioError>,
}

const ENTRIES: [Entry; 8] = [
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
];

const NAMES: [&str; 8] = [
    ENTRIES[0].name,
    ENTRIES[1].name,
    ENTRIES[2].name,
    ENTRIES[3].name,
    ENTRIES[4].name,
    ENTRIES[5].name,
    ENTRIES[6].name,
    ENTRIES[7].name,
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

/// Layouts a generator may draw before giving up.
const MAX_ATTEMPTS: usize = 200;

fn gen_error(name: &str, seed: u64, message: impl Into<String>) -> ScenarioError {
    ScenarioError::Generate {
        name: name.to_string(),
        seed,
        message: message.into(),
    }
}

/// Uniform sample in `[lo, hi)`.
fn uni(rng: &mut ChaCha8Rng, lo: f64, hi: f64) -> f64 {
    if hi > lo {
        rng.random_range(lo..hi)
    } else {
        lo
    }
}

/// The centre of the `mask` cell nearest to `p`.
fn snap(world: &World, mask: &[bool], p: Point2) -> Option<Point2> {
    nearest_in_mask(world, mask, p).map(|k| world.cell_center(k))
}

/// `n` distinct centres of `mask` cells drawn uniformly, each at least `min_sep` from the
/// previous one.
fn sample_cells(
    world: &World,
    mask: &[bool],
    n: usize,
    min_sep: f64,
    rng: &mut ChaCha8Rng,
) -> Vec<Point2> {
    let cells: Vec<usize> = (0..mask.len()).filter(|&k| mask[k]).collect();
    let mut out: Vec<Point2> = Vec::with_capacity(n);
    if cells.is_empty() {
        return out;
    }
    let mut tries = 0;
    while out.len() < n && tries < 100 * n {
        tries += 1;
        let p = world.cell_center(cells[rng.random_range(0..cells.len())]);
        if out.iter().any(|q| q.dist(p) < 1e-9) || out.last().is_some_and(|q| q.dist(p) < min_sep) {
            continue;
        }
        out.push(p);
    }
    out
}
