//! A built-in world's terrain table: per terrain type its gait responses (simulator truth) and
//! its look (how the generator colours and textures its cells), declared together in one row.

use std::collections::BTreeMap;

use strider_core::Rgb8;

use crate::model::{GaitResponse, TerrainType};

/// How a terrain looks: colour bases (one picked per cell), colour noise and elevation texture.
#[derive(Clone, Debug)]
pub(crate) struct Look {
    pub bases: Vec<Rgb8>,
    /// Standard deviation of the per-cell colour noise (0–255 scale).
    pub sigma: f64,
    /// Elevation texture: uniform noise amplitude, metres.
    pub texture: f32,
}

impl Look {
    /// One colour base.
    pub fn new(base: Rgb8, sigma: f64, texture: f32) -> Self {
        Self::mixed(&[base], sigma, texture)
    }

    /// Several colour bases, one drawn per cell.
    pub fn mixed(bases: &[Rgb8], sigma: f64, texture: f32) -> Self {
        Self {
            bases: bases.to_vec(),
            sigma,
            texture,
        }
    }

    /// The white, untextured walls and fences of the indoor worlds.
    pub fn white_wall() -> Self {
        Self::new(Rgb8::new(240, 240, 240), 4.0, 0.0)
    }
}

/// The terrain types of a world in layer-index order, each with its look.
#[derive(Clone, Debug, Default)]
pub(crate) struct TerrainTable {
    rows: Vec<(TerrainType, Look)>,
}

impl TerrainTable {
    pub fn new() -> Self {
        Self::default()
    }

    /// Adds terrain `t` drawn with `look`.
    pub fn row(mut self, t: TerrainType, look: Look) -> Self {
        self.rows.push((t, look));
        self
    }

    /// Adds terrain `index` called `name` with the given per-gait responses.
    pub fn add(self, index: u8, name: &str, gaits: &[(&str, GaitResponse)], look: Look) -> Self {
        self.row(terrain(index, name, gaits), look)
    }

    /// Adds a rigid obstacle: no gait crosses it, nothing pushes through it.
    pub fn obstacle(self, index: u8, name: &str, look: Look) -> Self {
        self.add(index, name, &[], look)
    }

    /// The terrain types, in the order they were added.
    pub fn types(&self) -> Vec<TerrainType> {
        self.rows.iter().map(|(t, _)| t.clone()).collect()
    }

    /// The look of terrain `index`.
    pub fn look(&self, index: u8) -> Option<&Look> {
        self.rows
            .iter()
            .find(|(t, _)| t.index == index)
            .map(|(_, l)| l)
    }
}

/// A terrain type with per-gait responses and the defaults of everything else (no vibration,
/// unit energy per metre, rigid).
pub(crate) fn terrain(index: u8, name: &str, gaits: &[(&str, GaitResponse)]) -> TerrainType {
    TerrainType {
        index,
        name: name.to_string(),
        gaits: gaits
            .iter()
            .map(|(g, r)| (g.to_string(), r.clone()))
            .collect::<BTreeMap<_, _>>(),
        vibration: 0.0,
        energy_per_m: 1.0,
        push_force_n: None,
    }
}

/// A gait response reaching `speed_factor` of the gait's top speed, with nothing else to note.
pub(crate) fn speed(speed_factor: f64) -> GaitResponse {
    GaitResponse {
        speed_factor,
        ..GaitResponse::default()
    }
}

/// A gait response in which the robot gets stuck at `speed_factor`.
pub(crate) fn stuck(speed_factor: f64) -> GaitResponse {
    GaitResponse {
        stuck: true,
        ..speed(speed_factor)
    }
}

/// A gait response drawing `power_w` watts at `speed_factor`.
pub(crate) fn powered(speed_factor: f64, power_w: f64) -> GaitResponse {
    GaitResponse {
        power_w,
        ..speed(speed_factor)
    }
}
